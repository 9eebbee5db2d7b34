//! Steps 2 and 3, the triangles: the good ones (no two equal positions), and per good triangle its
//! unit dP/du and dP/dv, its orientation and whether it has a usable UV area.

use glam::Vec3;

use super::on_runs;
use super::ops::{dot, not_zero};
use super::weld::Vertices;

/// The soup's triangles with no two equal positions, in order.
pub(super) fn good_triangles(vertices: &Vertices, triangles: usize) -> Vec<u32> {
    let p = |c: usize| vertices.positions[vertices.of_corner[c] as usize];
    (0..triangles)
        .filter(|&f| {
            let (a, b, c) = (p(3 * f), p(3 * f + 1), p(3 * f + 2));
            !(a == b || a == c || b == c)
        })
        .map(|f| f as u32)
        .collect()
}

/// Per good triangle: its vertices and what its UVs say.
pub(super) struct Triangles {
    pub(super) corners: Vec<[u32; 3]>,
    pub(super) info: Vec<TriangleInfo>,
}

/// What a triangle's UVs say.
#[derive(Clone, Copy, Default)]
pub(super) struct TriangleInfo {
    /// Unit dP/du and dP/dv, each times the orientation's sign (zero where undefined).
    pub(super) du: Vec3,
    pub(super) dv: Vec3,
    /// Positive UV area. Changed for a triangle without UV area by the first group that takes it.
    pub(super) orientation: bool,
    /// No UV area or a zero magnitude: takes no part in sums, joins any sub-group.
    pub(super) flat: bool,
}

impl Triangles {
    /// The good triangles' vertices, and what their UVs say (over the cores).
    pub(super) fn new(vertices: &Vertices, good: &[u32], threads: usize) -> Self {
        let corners: Vec<[u32; 3]> = good
            .iter()
            .map(|&f| {
                let c = |i: usize| vertices.of_corner[3 * f as usize + i];
                [c(0), c(1), c(2)]
            })
            .collect();
        let mut info = vec![TriangleInfo::default(); good.len()];
        on_runs(&mut info, threads, |start, run| {
            for (t, slot) in run.iter_mut().enumerate() {
                *slot = triangle_info(vertices, corners[start + t]);
            }
        });
        Triangles { corners, info }
    }
}

/// What the UVs of the triangle of vertices `a`, `b`, `c` say.
fn triangle_info(vertices: &Vertices, [a, b, c]: [u32; 3]) -> TriangleInfo {
    let (p1, p2, p3) = (
        vertices.positions[a as usize],
        vertices.positions[b as usize],
        vertices.positions[c as usize],
    );
    let (t1, t2, t3) = (
        vertices.uvs[a as usize],
        vertices.uvs[b as usize],
        vertices.uvs[c as usize],
    );
    let (t21x, t21y) = (t2.x - t1.x, t2.y - t1.y);
    let (t31x, t31y) = (t3.x - t1.x, t3.y - t1.y);
    let (d1, d2) = (p2 - p1, p3 - p1);
    let area = t21x * t31y - t21y * t31x;
    let du = Vec3::new(
        t31y * d1.x - t21y * d2.x,
        t31y * d1.y - t21y * d2.y,
        t31y * d1.z - t21y * d2.z,
    );
    let dv = Vec3::new(
        -t31x * d1.x + t21x * d2.x,
        -t31x * d1.y + t21x * d2.y,
        -t31x * d1.z + t21x * d2.z,
    );
    let mut info = TriangleInfo {
        orientation: area > 0.0,
        flat: true,
        ..Default::default()
    };
    if not_zero(area) {
        let (len_u, len_v) = (dot(du, du).sqrt(), dot(dv, dv).sqrt());
        let sign = if info.orientation { 1.0 } else { -1.0 };
        if not_zero(len_u) {
            info.du = (sign / len_u) * du;
        }
        if not_zero(len_v) {
            info.dv = (sign / len_v) * dv;
        }
        // The magnitudes (length over UV area) matter only as "not zero".
        let abs_area = area.abs();
        info.flat = !(not_zero(len_u / abs_area) && not_zero(len_v / abs_area));
    }
    info
}
