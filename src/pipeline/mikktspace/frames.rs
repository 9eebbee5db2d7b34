//! Step 6, the frames: per group, its members' projected dP/du summed by sub-group and weighted by
//! angle, the groups worked through in runs, one per core.

use glam::Vec3;

use super::groups::Groups;
use super::ops::{dot, normalize_if_not_zero, on_plane};
use super::triangles::Triangles;
use super::weld::Vertices;
use super::{FALLBACK, NONE};
use crate::pipeline::on_threads;

/// The frame of every good triangle's corner (3 t + i): per group, over the cores.
pub(super) fn group_frames(
    vertices: &Vertices,
    triangles: &Triangles,
    groups: &Groups,
    threads: usize,
) -> Vec<[f32; 4]> {
    // Each group's corners, in triangle order (corners are listed in order, one per triangle).
    let group_count = groups.vertex.len();
    let mut start = vec![0u32; group_count + 1];
    for &g in &groups.of_corner {
        if g != NONE {
            start[g as usize + 1] += 1;
        }
    }
    for g in 0..group_count {
        start[g + 1] += start[g];
    }
    let mut fill = start.clone();
    let mut members = vec![0u32; start[group_count] as usize];
    for (c, &g) in groups.of_corner.iter().enumerate() {
        if g != NONE {
            members[fill[g as usize] as usize] = c as u32;
            fill[g as usize] += 1;
        }
    }
    // Frames in `members`' order, cut into runs at group boundaries.
    let mut frames = vec![FALLBACK; members.len()];
    let runs = group_runs(&start, threads);
    let mut pieces = Vec::new();
    let mut rest = frames.as_mut_slice();
    for w in runs.windows(2) {
        let (piece, tail) = rest.split_at_mut((start[w[1]] - start[w[0]]) as usize);
        pieces.push((w[0]..w[1], piece));
        rest = tail;
    }
    let work = |(groups_run, out): (std::ops::Range<usize>, &mut [[f32; 4]])| {
        let base = start[groups_run.start] as usize;
        let mut scratch = Scratch::default();
        for g in groups_run {
            let range = start[g] as usize..start[g + 1] as usize;
            let frame_out = &mut out[range.start - base..range.end - base];
            group_frame(
                vertices,
                triangles,
                groups,
                g,
                &members[range],
                frame_out,
                &mut scratch,
            );
        }
    };
    on_threads(pieces, work);
    let mut out = vec![FALLBACK; groups.of_corner.len()];
    for (&c, frame) in members.iter().zip(&frames) {
        out[c as usize] = *frame;
    }
    out
}

/// Group indices cutting the groups into about `threads` runs of equal corner counts.
fn group_runs(start: &[u32], threads: usize) -> Vec<usize> {
    let groups = start.len() - 1;
    let total = start[groups] as usize;
    let mut cuts = vec![0];
    for k in 1..threads {
        let target = (total * k / threads) as u32;
        let g = start.partition_point(|&s| s < target).min(groups);
        if g > *cuts.last().unwrap() {
            cuts.push(g);
        }
    }
    if *cuts.last().unwrap() != groups {
        cuts.push(groups);
    }
    cuts
}

/// Buffers reused from group to group.
#[derive(Default)]
struct Scratch {
    du: Vec<Vec3>,
    dv: Vec<Vec3>,
    subgroups: Vec<(Vec<u32>, Vec3)>,
    members: Vec<u32>,
}

/// The frames of one group's corners (`corners`: 3 t + i, in triangle order).
fn group_frame(
    vertices: &Vertices,
    triangles: &Triangles,
    groups: &Groups,
    g: usize,
    corners: &[u32],
    out: &mut [[f32; 4]],
    scratch: &mut Scratch,
) {
    let v = groups.vertex[g];
    let n = vertices.normals[v as usize];
    let w = if groups.orientation[g] { 1.0 } else { -1.0 };
    let info = |c: u32| &groups.info[c as usize / 3];
    scratch.du.clear();
    scratch.dv.clear();
    for &c in corners {
        scratch.du.push(on_plane(info(c).du, n));
        scratch.dv.push(on_plane(info(c).dv, n));
    }
    // A member joins a corner's sub-group unless both are UV-bearing and one of their projected
    // directions point exactly opposite (not above the threshold's cosine).
    let threshold = threshold_cosine();
    let (du, dv) = (&scratch.du, &scratch.dv);
    let joins = |a: usize, b: usize| {
        a == b
            || info(corners[a]).flat
            || info(corners[b]).flat
            || dot(du[a], du[b]) > threshold && dot(dv[a], dv[b]) > threshold
    };
    let all_join = (0..corners.len()).all(|a| (a + 1..corners.len()).all(|b| joins(a, b)));
    if all_join {
        let t = subgroup_tangent(
            vertices,
            triangles,
            groups,
            v,
            n,
            corners,
            du,
            0..corners.len(),
        );
        out.fill([t.x, t.y, t.z, w]);
        return;
    }
    // Rare: sub-groups differ from corner to corner; equal ones share one sum.
    scratch.subgroups.clear();
    for (a, frame) in out.iter_mut().enumerate() {
        scratch.members.clear();
        scratch.members.extend(
            (0..corners.len())
                .filter(|&b| joins(a, b))
                .map(|b| b as u32),
        );
        let known = scratch
            .subgroups
            .iter()
            .find(|(m, _)| *m == scratch.members);
        let t = match known {
            Some(&(_, t)) => t,
            None => {
                let members = scratch.members.iter().map(|&b| b as usize);
                let t = subgroup_tangent(vertices, triangles, groups, v, n, corners, du, members);
                scratch.subgroups.push((scratch.members.clone(), t));
                t
            }
        };
        *frame = [t.x, t.y, t.z, w];
    }
}

/// The reference's threshold, the cosine of 180° as it computes it (−1).
fn threshold_cosine() -> f32 {
    ((180.0f32 * std::f64::consts::PI as f32 / 180.0) as f64).cos() as f32
}

/// The sum of the members' projected dP/du weighted by their angle at vertex `v`, in triangle order,
/// normalized.
#[allow(clippy::too_many_arguments)]
fn subgroup_tangent(
    vertices: &Vertices,
    triangles: &Triangles,
    groups: &Groups,
    v: u32,
    n: Vec3,
    corners: &[u32],
    du: &[Vec3],
    members: impl Iterator<Item = usize>,
) -> Vec3 {
    let mut sum = Vec3::ZERO;
    for k in members {
        let t = corners[k] as usize / 3;
        if groups.info[t].flat {
            continue;
        }
        let tri = triangles.corners[t];
        let i = tri.iter().position(|&w| w == v).unwrap_or(0);
        let p = |j: usize| vertices.positions[tri[j] as usize];
        let (p0, p1, p2) = (p((i + 2) % 3), p(i), p((i + 1) % 3));
        let (e1, e2) = (on_plane(p0 - p1, n), on_plane(p2 - p1, n));
        let cos = dot(e1, e2);
        // (A NaN stays NaN, as through the reference's comparisons.)
        let cos = cos.clamp(-1.0, 1.0);
        let angle = (cos as f64).acos() as f32;
        let d = du[k];
        sum = Vec3::new(
            sum.x + angle * d.x,
            sum.y + angle * d.y,
            sum.z + angle * d.z,
        );
    }
    normalize_if_not_zero(sum)
}
