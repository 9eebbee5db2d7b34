//! MikkTSpace tangents, computed here: the `mikktspace` crate's results (the port of Morten
//! Mikkelsen's reference code) to the bit, for a triangle soup, in a fraction of its time and spread
//! over the cores. The crate stays as the reference the tests and the fuzz target compare with.
//!
//! The algorithm, as the reference runs it on triangles (its quads never come from a soup):
//!
//! 1. Corners whose position, normal and UV compare equal (`==`: −0 equals +0) are one vertex; each
//!    vertex reads the floats of one of its corners (which one only shows in the sign of a zero).
//! 2. A triangle with two equal positions is degenerate: it takes no part, and its corners copy
//!    the frame of the first good corner of the same vertex.
//! 3. Per good triangle: the directions of increasing u and v (dP/du, dP/dv) from its positions
//!    and UVs, unit length, pointing along the UV area's sign; whether the UV area is positive (the
//!    orientation); and whether the triangle has no usable UV area (it then joins any group).
//! 4. Neighbours across shared edges (same two vertices, opposite directions), first come first
//!    paired, as the reference's sorted edge list pairs them.
//! 5. Groups: around each vertex, the fan of triangles reached across edges with the same
//!    orientation; a triangle without UV area takes the orientation of the first group that
//!    reaches it. Groups are made in the order of their first corner, which decides that.
//! 6. Per group: each member's dP/du and dP/dv projected on the vertex normal's plane; the members
//!    whose projections are not opposite (cosines above −1, the reference's 180° threshold) form a
//!    corner's sub-group; its tangent is the sum of the members' projected dP/du weighted by their
//!    angle at the vertex, in triangle order, normalized. The sign is the group's orientation.
//!
//! Where the order of float operations shows in the result (sums, projections, the angle through
//! `f64::acos`), it is the reference's; everything else is free: vertices are numbered by a hash
//! of their bits, edges are paired through buckets per vertex, and triangles and groups are worked
//! through in runs, one per core.

//!
//! The steps' files: weld.rs and numbering.rs (1: the vertices, and the numbers the reference's
//! weld gives them), triangles.rs (2 and 3), neighbours.rs (4), groups.rs (5), frames.rs (6), and
//! ops.rs, the float operations they share; this file runs them and puts the frames in the soup's
//! order.

mod frames;
mod groups;
mod neighbours;
mod numbering;
mod ops;
mod triangles;
mod weld;

use crate::common::objloader::TriangleSoup;
use crate::pipeline::on_threads;
use crate::{Error, Result};
use frames::group_frames;
use groups::Groups;
use neighbours::{neighbours, Numbers};
use triangles::{good_triangles, Triangles};
use weld::Vertices;

/// No neighbour, no group.
const NONE: u32 = u32::MAX;

/// The frame of a corner MikkTSpace could give none (no group reached it): the reference's
/// starting value, x with the bitangent's sign negative.
const FALLBACK: [f32; 4] = [1.0, 0.0, 0.0, -1.0];

/// MikkTSpace's tangent per corner (xyz unit, or the fallback (1, 0, 0); w = ±1, the bitangent's
/// sign), on every core.
pub fn mikktspace_tangents(soup: &TriangleSoup) -> Result<Vec<[f32; 4]>> {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    mikktspace_tangents_on(soup, cores)
}

/// [`mikktspace_tangents`] on `threads` threads (the result is the same for any number).
pub fn mikktspace_tangents_on(soup: &TriangleSoup, threads: usize) -> Result<Vec<[f32; 4]>> {
    Ok(mikktspace_numbered(soup, threads)?.0)
}

/// [`mikktspace_tangents_on`], also giving each corner's number by the exact bits of its
/// position, UV and normal (the indexers' weld, first come first numbered), which MikkTSpace's
/// weld starts from: the mesh's final weld then needs only compare tangents.
pub(crate) fn mikktspace_numbered(
    soup: &TriangleSoup,
    threads: usize,
) -> Result<(Vec<[f32; 4]>, Vec<u32>)> {
    let corners = soup.triangle_count() * 3;
    check_input(soup, corners)?;
    let threads = threads.max(1);
    let clock = crate::clock::Instant::now();
    let mut lap = stage_timer(clock);
    let (vertices, numbering, exact) = Vertices::weld(soup, corners, threads);
    lap("weld");
    let good = good_triangles(&vertices, corners / 3);
    let triangles = Triangles::new(&vertices, &good, threads);
    lap("triangles");
    let numbers = Numbers {
        numbering,
        soup,
        of_corner: &vertices.of_corner,
    };
    let neighbours = neighbours(&triangles.corners, numbers);
    lap("neighbours");
    let groups = Groups::build(&triangles, &neighbours);
    lap("groups");
    let frames = group_frames(&vertices, &triangles, &groups, threads);
    lap("frames");
    let out = in_soup_order(frames, &vertices, &triangles, &good, corners);
    lap("output");
    log::debug!(
        "MikkTSpace: {} triangles on {threads} threads in {:.1} ms",
        corners / 3,
        clock.elapsed().as_secs_f64() * 1e3
    );
    Ok((out, exact.unwrap_or(vertices.of_corner)))
}

/// An error unless the soup has a triangle and all its floats are finite.
fn check_input(soup: &TriangleSoup, corners: usize) -> Result<()> {
    if corners == 0 {
        return Err(Error::Mesh(
            "MikkTSpace could not compute tangents for this mesh: it has no triangle".into(),
        ));
    }
    let finite = |i: usize| {
        soup.vertices[i].is_finite() && soup.normals[i].is_finite() && soup.uvs[i].is_finite()
    };
    // The reference's weld splits space at midpoints, which a NaN or an infinity never passes.
    if let Some(i) = (0..corners).find(|&i| !finite(i)) {
        return Err(Error::Mesh(format!(
            "MikkTSpace needs finite positions, normals and UVs: corner {i} has a NaN or an infinity"
        )));
    }
    Ok(())
}

/// Logs (at trace level) each stage's time since the last one, the first since `start`.
fn stage_timer(start: crate::clock::Instant) -> impl FnMut(&str) {
    let mut last = start;
    move |stage: &str| {
        let now = crate::clock::Instant::now();
        log::trace!(
            "MikkTSpace {stage}: {:.1} ms",
            (now - last).as_secs_f64() * 1e3
        );
        last = now;
    }
}

/// The frames of the good triangles' corners (`frames`, 3 t + i) put per corner of the soup.
fn in_soup_order(
    frames: Vec<[f32; 4]>,
    vertices: &Vertices,
    triangles: &Triangles,
    good: &[u32],
    corners: usize,
) -> Vec<[f32; 4]> {
    // Good corners in the soup's order, then degenerate triangles' corners copied from the first
    // good corner of their vertex (the reference searches its good triangles in order). With no
    // degenerate triangle the frames are already in the soup's order.
    if good.len() == corners / 3 {
        return frames;
    }
    let mut out = vec![FALLBACK; corners];
    let mut first_good = vec![NONE; vertices.positions.len()];
    let mut is_good = vec![false; corners / 3];
    for (t, &f) in good.iter().enumerate() {
        is_good[f as usize] = true;
        for i in 0..3 {
            out[3 * f as usize + i] = frames[3 * t + i];
            let v = triangles.corners[t][i] as usize;
            if first_good[v] == NONE {
                first_good[v] = 3 * f + i as u32;
            }
        }
    }
    for c in (0..corners).filter(|c| !is_good[c / 3]) {
        let source = first_good[vertices.of_corner[c] as usize];
        if source != NONE {
            out[c] = out[source as usize];
        }
    }
    out
}

/// `f` on `items` cut into `threads` runs (given each run's first index), each on a thread of its
/// own but the first, which runs here. One run: no thread (the browser has none).
fn on_runs<T: Send>(items: &mut [T], threads: usize, f: impl Fn(usize, &mut [T]) + Sync) {
    let size = items.len().div_ceil(threads.max(1)).max(1);
    let runs: Vec<(usize, &mut [T])> = items
        .chunks_mut(size)
        .enumerate()
        .map(|(k, run)| (k * size, run))
        .collect();
    on_threads(runs, |(start, run)| f(start, run));
}
