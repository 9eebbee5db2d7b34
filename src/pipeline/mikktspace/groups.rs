//! Step 5, the groups: around each vertex, the fan of triangles of one orientation reached across
//! edges, made in the order of their first corner.

use super::triangles::{TriangleInfo, Triangles};
use super::NONE;

/// The groups: each good corner's, and each group's vertex and orientation.
pub(super) struct Groups {
    /// Per good triangle's corner (3 t + i): its group, or [`NONE`].
    pub(super) of_corner: Vec<u32>,
    pub(super) vertex: Vec<u32>,
    pub(super) orientation: Vec<bool>,
    /// Triangles' orientations after the groups took the flat ones.
    pub(super) info: Vec<TriangleInfo>,
}

impl Groups {
    /// One at a time, in the order of their first corner: a flat triangle's orientation is the
    /// first group's to reach it, which the later ones then see.
    pub(super) fn build(triangles: &Triangles, across: &[u32]) -> Self {
        let mut info = triangles.info.clone();
        let mut of_corner = vec![NONE; triangles.corners.len() * 3];
        let (mut vertex, mut orientation) = (Vec::new(), Vec::new());
        let mut stack = Vec::new();
        for t in 0..triangles.corners.len() {
            for i in 0..3 {
                if info[t].flat || of_corner[3 * t + i] != NONE {
                    continue;
                }
                let group = vertex.len() as u32;
                let v = triangles.corners[t][i];
                let orient = info[t].orientation;
                vertex.push(v);
                orientation.push(orient);
                of_corner[3 * t + i] = group;
                // The fan goes on across the two edges that meet at the vertex.
                stack.extend([across[3 * t + i], across[3 * t + (i + 2) % 3]]);
                while let Some(u) = stack.pop() {
                    if u == NONE {
                        continue;
                    }
                    let u = u as usize;
                    let Some(j) = triangles.corners[u].iter().position(|&w| w == v) else {
                        continue;
                    };
                    if of_corner[3 * u + j] != NONE {
                        continue;
                    }
                    if info[u].flat && of_corner[3 * u..3 * u + 3].iter().all(|&g| g == NONE) {
                        info[u].orientation = orient;
                    }
                    if info[u].orientation != orient {
                        continue;
                    }
                    of_corner[3 * u + j] = group;
                    stack.extend([across[3 * u + j], across[3 * u + (j + 2) % 3]]);
                }
            }
        }
        Groups {
            of_corner,
            vertex,
            orientation,
            info,
        }
    }
}
