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

use glam::{Vec2, Vec3};
use rustc_hash::FxHashMap;

use crate::common::objloader::TriangleSoup;
use crate::pipeline::indexer::weld_exact;
use crate::pipeline::on_threads;
use crate::{Error, Result};

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
    let threads = threads.max(1);
    let clock = crate::clock::Instant::now();
    let mut lap = {
        let mut last = clock;
        move |stage: &str| {
            let now = crate::clock::Instant::now();
            log::trace!(
                "MikkTSpace {stage}: {:.1} ms",
                (now - last).as_secs_f64() * 1e3
            );
            last = now;
        }
    };
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
    // Good corners in the soup's order, then degenerate triangles' corners copied from the first
    // good corner of their vertex (the reference searches its good triangles in order). With no
    // degenerate triangle the frames are already in the soup's order.
    let out = if good.len() == corners / 3 {
        frames
    } else {
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
    };
    lap("output");
    log::debug!(
        "MikkTSpace: {} triangles on {threads} threads in {:.1} ms",
        corners / 3,
        clock.elapsed().as_secs_f64() * 1e3
    );
    Ok((out, exact.unwrap_or(vertices.of_corner)))
}

// -------------------------------------------------------------------------------------------------
// The float operations the reference's result depends on, spelled out in its order.

fn dot(a: Vec3, b: Vec3) -> f32 {
    a.x * b.x + a.y * b.y + a.z * b.z
}

/// The reference's "not zero": above the smallest normal f32.
fn not_zero(x: f32) -> bool {
    x.abs() > f32::MIN_POSITIVE
}

fn any_not_zero(v: Vec3) -> bool {
    not_zero(v.x) || not_zero(v.y) || not_zero(v.z)
}

/// `v` scaled by the reciprocal of its length (not divided: the reference multiplies).
fn normalize(v: Vec3) -> Vec3 {
    let scale = 1.0 / dot(v, v).sqrt();
    Vec3::new(scale * v.x, scale * v.y, scale * v.z)
}

/// `v` normalized unless it is (nearly) zero.
fn normalize_if_not_zero(v: Vec3) -> Vec3 {
    if any_not_zero(v) {
        normalize(v)
    } else {
        v
    }
}

/// `v` with its component along the unit normal `n` taken away, then normalized unless zero.
fn on_plane(v: Vec3, n: Vec3) -> Vec3 {
    let along = dot(n, v);
    normalize_if_not_zero(Vec3::new(
        v.x - along * n.x,
        v.y - along * n.y,
        v.z - along * n.z,
    ))
}

// -------------------------------------------------------------------------------------------------
// 1. Vertices

/// The welded vertices: each corner's, and each vertex's floats.
struct Vertices {
    of_corner: Vec<u32>,
    positions: Vec<Vec3>,
    normals: Vec<Vec3>,
    uvs: Vec<Vec2>,
}

/// A corner's eight floats in the order the weld compares them.
fn floats(soup: &TriangleSoup, c: usize) -> [f32; 8] {
    let (p, n, uv) = (soup.vertices[c], soup.normals[c], soup.uvs[c]);
    [p.x, p.y, p.z, n.x, n.y, n.z, uv.x, uv.y]
}

impl Vertices {
    /// Corners equal under `==`. First by their bits (the indexers' fast table); then, only if
    /// some float is −0, the bit patterns that differ only in zeros' signs are merged. A vertex
    /// whose corners differ so reads the floats of the corner the reference's weld keeps; any
    /// other, those of its first corner (the same bits). Also gives the numbering by bits where
    /// it differs from the vertices' (only if some zero is negative).
    fn weld(
        soup: &TriangleSoup,
        corners: usize,
        threads: usize,
    ) -> (Self, Numbering, Option<Vec<u32>>) {
        let (numbers, first) = weld_exact(soup, false);
        let has_negative_zero = |c: u32| {
            floats(soup, c as usize)
                .iter()
                .any(|x| x.to_bits() == 0x8000_0000)
        };
        let (of_corner, mut reps, mixed, exact) = if first.iter().any(|&c| has_negative_zero(c)) {
            let (of_corner, reps, mixed) = merge_signed_zeros(soup, &numbers, &first);
            (of_corner, reps, mixed, Some(numbers))
        } else {
            (numbers, first, Vec::new(), None)
        };
        debug_assert_eq!(of_corner.len(), corners);
        let mut numbering = Numbering::new(soup, &of_corner, &reps, threads);
        for class in mixed {
            reps[class as usize] = numbering.representative(soup, &of_corner, class);
        }
        let pick = |c: &u32| *c as usize;
        let vertices = Vertices {
            positions: reps.iter().map(|c| soup.vertices[pick(c)]).collect(),
            normals: reps.iter().map(|c| soup.normals[pick(c)]).collect(),
            uvs: reps.iter().map(|c| soup.uvs[pick(c)]).collect(),
            of_corner,
        };
        (vertices, numbering, exact)
    }
}

/// Merges the bit-exact numbering (`numbers`, with each number's first corner) into `==` classes:
/// gives each corner's class, each class's first corner, and the classes merged from several.
fn merge_signed_zeros(
    soup: &TriangleSoup,
    numbers: &[u32],
    first: &[u32],
) -> (Vec<u32>, Vec<u32>, Vec<u32>) {
    // Only numbers with a zero somewhere can equal another number: key those by their floats
    // with −0 made +0 (adding +0 does just that).
    let mut by_key: FxHashMap<[u32; 8], u32> = FxHashMap::default();
    let mut class_of = Vec::with_capacity(first.len());
    let (mut class_first, mut merged) = (Vec::new(), Vec::new());
    for &c in first {
        let f = floats(soup, c as usize);
        let new = class_first.len() as u32;
        let class = if f.contains(&0.0) {
            *by_key.entry(f.map(|x| (x + 0.0).to_bits())).or_insert(new)
        } else {
            new
        };
        if class == new {
            class_first.push(c);
            merged.push(false);
        } else {
            merged[class as usize] = true;
        }
        class_of.push(class);
    }
    let of_corner = numbers.iter().map(|&n| class_of[n as usize]).collect();
    let mixed = (0..merged.len() as u32)
        .filter(|&k| merged[k as usize])
        .collect();
    (of_corner, class_first, mixed)
}

/// Cells of the reference's weld grid, along the bounding box's longest axis.
const CELLS: usize = 2048;

/// The reference's grid cell of coordinate `x` between `min` and `max`.
fn grid_cell(min: f32, max: f32, x: f32) -> usize {
    let at = (CELLS as f32 * ((x - min) / (max - min))) as isize;
    at.clamp(0, CELLS as isize - 1) as usize
}

/// The reference's number for each vertex: the corner its weld keeps, as `face << 2 | corner`.
/// Numbers order the edges, and so decide the few neighbours the reference's sort leaves
/// unsorted ([`last_run`]); a vertex whose corners differ in zeros' signs reads that corner's
/// floats.
///
/// The corner kept is the first of the vertex in the order the weld leaves the corners: a grid
/// along the longest axis, then each cell split at midpoints until the corners of a part are one
/// point or cannot be split. Redoing that for every cell costs more than all the rest, so it is
/// done only for the cells of the vertices whose number is asked; the others are known only
/// between their lowest and highest corner, which most comparisons need no more than. A mesh
/// whose rows cross the whole axis (a cylinder's rings) asks for nearly every cell: after
/// [`CELLS_ONE_BY_ONE`] the rest are redone at once, on every core.
struct Numbering {
    axis: usize,
    min: f32,
    max: f32,
    /// The corners of each cell, in the soup's order (as the reference lists them).
    cell_start: Vec<u32>,
    cell_corners: Vec<u32>,
    /// Per vertex: its lowest and highest corner's number; the kept corner, once known (or NONE).
    bounds: Vec<(u32, u32)>,
    kept: Vec<u32>,
    /// A corner of each vertex, to find its cell.
    some_corner: Vec<u32>,
    /// Cells redone so far (all of them once the rest were redone at once), how many are redone
    /// one by one ([`CELLS_ONE_BY_ONE`]), and the threads.
    cells_redone: usize,
    one_by_one: usize,
    threads: usize,
}

/// Cells redone one at a time, when asked, before all the others are redone together.
const CELLS_ONE_BY_ONE: usize = 64;

/// A corner's number in the reference: `face << 2 | corner`.
fn corner_number(c: u32) -> u32 {
    ((c / 3) << 2) | (c % 3)
}

impl Numbering {
    fn new(soup: &TriangleSoup, of_corner: &[u32], some_corner: &[u32], threads: usize) -> Self {
        let p = &soup.vertices[..of_corner.len()];
        let (lo, hi) = reference_box(p[0], p[1..].iter().copied());
        let axis = longest_axis(lo, hi);
        let (min, max) = (lo[axis], hi[axis]);
        let mut cell = vec![0u16; p.len()];
        on_runs(&mut cell, threads, |start, run| {
            for (k, c) in run.iter_mut().enumerate() {
                *c = grid_cell(min, max, p[start + k][axis]) as u16;
            }
        });
        let mut cell_start = vec![0u32; CELLS + 1];
        for &k in &cell {
            cell_start[k as usize + 1] += 1;
        }
        for k in 0..CELLS {
            cell_start[k + 1] += cell_start[k];
        }
        let mut fill = cell_start.clone();
        let mut cell_corners = vec![0u32; p.len()];
        let mut bounds = vec![(u32::MAX, 0); some_corner.len()];
        for (c, &k) in cell.iter().enumerate() {
            cell_corners[fill[k as usize] as usize] = c as u32;
            fill[k as usize] += 1;
            let number = corner_number(c as u32);
            let b = &mut bounds[of_corner[c] as usize];
            *b = (b.0.min(number), b.1.max(number));
        }
        Numbering {
            axis,
            min,
            max,
            cell_start,
            cell_corners,
            bounds,
            kept: vec![NONE; some_corner.len()],
            some_corner: some_corner.to_vec(),
            cells_redone: 0,
            one_by_one: CELLS_ONE_BY_ONE,
            threads,
        }
    }

    /// The corner the reference keeps for vertex `class`: its cell redone if not yet.
    fn representative(&mut self, soup: &TriangleSoup, of_corner: &[u32], class: u32) -> u32 {
        if self.kept[class as usize] == NONE {
            if self.cells_redone < self.one_by_one {
                let corner = self.some_corner[class as usize] as usize;
                let k = grid_cell(self.min, self.max, soup.vertices[corner][self.axis]);
                let order = self.redo_cell(soup, k);
                self.keep_first(of_corner, order);
                self.cells_redone += 1;
            } else {
                self.redo_all_cells(soup, of_corner);
            }
        }
        self.kept[class as usize]
    }

    /// Cell `k`'s corners in the order the reference's split leaves them.
    fn redo_cell(&self, soup: &TriangleSoup, k: usize) -> Vec<u32> {
        let range = self.cell_start[k] as usize..self.cell_start[k + 1] as usize;
        let mut list: Vec<(Vec3, u32)> = self.cell_corners[range]
            .iter()
            .map(|&c| (soup.vertices[c as usize], c))
            .collect();
        split_like_the_reference(&mut list);
        list.into_iter().map(|(_, c)| c).collect()
    }

    /// Keeps each vertex's first corner in `order`.
    fn keep_first(&mut self, of_corner: &[u32], order: impl IntoIterator<Item = u32>) {
        for c in order {
            let kept = &mut self.kept[of_corner[c as usize] as usize];
            if *kept == NONE {
                *kept = c;
            }
        }
    }

    /// Every cell not yet redone, redone in runs of about equal corners, one run per core. A
    /// cell's vertices are its own (equal positions share a cell), so the runs never meet.
    fn redo_all_cells(&mut self, soup: &TriangleSoup, of_corner: &[u32]) {
        let todo: Vec<usize> = (0..CELLS)
            .filter(|&k| self.cell_start[k] < self.cell_start[k + 1])
            .filter(|&k| {
                let first = self.cell_corners[self.cell_start[k] as usize];
                self.kept[of_corner[first as usize] as usize] == NONE
            })
            .collect();
        let share = (self.cell_start[CELLS] as usize).div_ceil(self.threads.max(1));
        let mut runs: Vec<Vec<usize>> = vec![Vec::new()];
        let mut filled = 0;
        for k in todo {
            if filled >= share {
                runs.push(Vec::new());
                filled = 0;
            }
            filled += (self.cell_start[k + 1] - self.cell_start[k]) as usize;
            runs.last_mut().expect("a run").push(k);
        }
        let this = &*self;
        let orders = on_threads(runs, |cells| {
            cells
                .into_iter()
                .flat_map(|k| this.redo_cell(soup, k))
                .collect::<Vec<_>>()
        });
        self.keep_first(of_corner, orders.into_iter().flatten());
        self.cells_redone = CELLS;
    }

    /// Vertex `class`'s number.
    fn number(&mut self, soup: &TriangleSoup, of_corner: &[u32], class: u32) -> u32 {
        corner_number(self.representative(soup, of_corner, class))
    }
}

/// The reference's choice of axis: y if strictly the longest, else z if longer than x, else x.
fn longest_axis(lo: [f32; 3], hi: [f32; 3]) -> usize {
    let (dx, dy, dz) = (hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
    if dy > dx && dy > dz {
        1
    } else if dz > dx {
        2
    } else {
        0
    }
}

/// The reference's box around `first` and `rest`: its min and max as it computes them (a value is
/// compared with the max only when it is not below the min, which matters to no finite number but
/// is kept so that the box is the reference's to the bit).
fn reference_box(first: Vec3, rest: impl Iterator<Item = Vec3>) -> ([f32; 3], [f32; 3]) {
    let (mut lo, mut hi) = (first.to_array(), first.to_array());
    for v in rest {
        for k in 0..3 {
            if lo[k] > v[k] {
                lo[k] = v[k];
            } else if hi[k] < v[k] {
                hi[k] = v[k];
            }
        }
    }
    (lo, hi)
}

/// Reorders a cell's corners as the reference's recursive split does (the parts are disjoint,
/// so the order they are worked in does not matter: a stack instead of recursion).
fn split_like_the_reference(list: &mut [(Vec3, u32)]) {
    let mut parts = vec![(0isize, list.len() as isize - 1)];
    while let Some((left, right)) = parts.pop() {
        let (l, r) = (left as usize, right as usize);
        let (lo, hi) = reference_box(list[l].0, list[l + 1..=r].iter().map(|(v, _)| *v));
        let axis = longest_axis(lo, hi);
        let sep = 0.5 * (hi[axis] + lo[axis]);
        if sep >= hi[axis] || sep <= lo[axis] {
            continue; // one point, or no float between: the reference merges here
        }
        let below = |list: &[(Vec3, u32)], i: isize| list[i as usize].0[axis] < sep;
        let (mut il, mut ir) = (left, right);
        while il < ir {
            let (mut left_ready, mut right_ready) = (false, false);
            while !left_ready && il < ir {
                left_ready = !below(list, il);
                if !left_ready {
                    il += 1;
                }
            }
            while !right_ready && il < ir {
                right_ready = below(list, ir);
                if !right_ready {
                    ir -= 1;
                }
            }
            if left_ready && right_ready {
                list.swap(il as usize, ir as usize);
                il += 1;
                ir -= 1;
            }
        }
        if il == ir {
            if below(list, ir) {
                il += 1;
            } else {
                ir -= 1;
            }
        }
        if left < ir {
            parts.push((left, ir));
        }
        if il < right {
            parts.push((il, right));
        }
    }
}

// -------------------------------------------------------------------------------------------------
// 2 and 3. Triangles

/// The soup's triangles with no two equal positions, in order.
fn good_triangles(vertices: &Vertices, triangles: usize) -> Vec<u32> {
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
struct Triangles {
    corners: Vec<[u32; 3]>,
    info: Vec<TriangleInfo>,
}

#[derive(Clone, Copy, Default)]
struct TriangleInfo {
    /// Unit dP/du and dP/dv, each times the orientation's sign (zero where undefined).
    du: Vec3,
    dv: Vec3,
    /// Positive UV area. Changed for a triangle without UV area by the first group that takes it.
    orientation: bool,
    /// No UV area or a zero magnitude: takes no part in sums, joins any sub-group.
    flat: bool,
}

impl Triangles {
    fn new(vertices: &Vertices, good: &[u32], threads: usize) -> Self {
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

// -------------------------------------------------------------------------------------------------
// 4. Neighbours

/// Per good triangle and edge (corner i to i + 1), the triangle across it, or [`NONE`].
///
/// The reference sorts the edges by their lower vertex number, then by the higher, then by
/// triangle, and pairs each unpaired edge with the first later unpaired one going the other way
/// among the equal edges that follow it. Its sorts skip the last run of each pass: the edges of
/// the highest lower vertex stay in the order its quicksort left them ([`last_run`]), pairing only
/// with equal edges next to them. All the others are bucketed here by their lower vertex, then
/// by the other (a stable sort keeps the triangle order).
fn neighbours(corners: &[[u32; 3]], mut numbers: Numbers) -> Vec<u32> {
    let ends = |edge: u32| {
        let (t, e) = ((edge / 3) as usize, (edge % 3) as usize);
        (corners[t][e], corners[t][(e + 1) % 3])
    };
    let low = |edge: u32| {
        let (a, b) = ends(edge);
        a.min(b)
    };
    let high = |edge: u32| {
        let (a, b) = ends(edge);
        a.max(b)
    };
    let edge_count = corners.len() * 3;
    let mut across = vec![NONE; edge_count];
    let pair = |run: &[u32], across: &mut [u32]| {
        for (i, &a) in run.iter().enumerate() {
            if across[a as usize] != NONE {
                continue;
            }
            let (a0, a1) = ends(a);
            let partner = run[i + 1..]
                .iter()
                .find(|&&b| across[b as usize] == NONE && ends(b) == (a1, a0));
            if let Some(&b) = partner {
                across[a as usize] = b / 3;
                across[b as usize] = a / 3;
            }
        }
    };
    let last = last_run(corners, &mut numbers);
    let mut in_last = vec![false; edge_count];
    for &edge in &last {
        in_last[edge as usize] = true;
    }
    // The last run: stretches of equal edges as they lie, each but the final one by triangle.
    let upper: Vec<u32> = last
        .iter()
        .map(|&edge| {
            let (a, b) = ends(edge);
            numbers.number(a).max(numbers.number(b))
        })
        .collect();
    let mut stretches = Vec::new();
    let mut from = 0;
    for k in 1..=last.len() {
        if k == last.len() || upper[k] != upper[from] {
            stretches.push(&last[from..k]);
            from = k;
        }
    }
    let final_stretch = stretches.pop();
    for stretch in stretches {
        let mut sorted = stretch.to_vec();
        sorted.sort_unstable();
        pair(&sorted, &mut across);
    }
    if let Some(stretch) = final_stretch {
        pair(stretch, &mut across);
    }

    let vertex_count = numbers.numbering.kept.len();
    let mut start = vec![0u32; vertex_count + 1];
    for edge in 0..edge_count as u32 {
        start[low(edge) as usize + 1] += 1;
    }
    for v in 0..vertex_count {
        start[v + 1] += start[v];
    }
    let mut fill = start.clone();
    let mut edges = vec![0u32; edge_count];
    for edge in 0..edge_count as u32 {
        let slot = &mut fill[low(edge) as usize];
        edges[*slot as usize] = edge;
        *slot += 1;
    }
    for v in 0..vertex_count {
        let bucket = &mut edges[start[v] as usize..start[v + 1] as usize];
        if bucket.len() < 2 {
            continue;
        }
        bucket.sort_by_key(|&edge| high(edge));
        for run in bucket.chunk_by(|&a, &b| high(a) == high(b)) {
            if !in_last[run[0] as usize] {
                pair(run, &mut across);
            }
        }
    }
    across
}

/// [`Numbering`] with what it reads.
struct Numbers<'a> {
    numbering: Numbering,
    soup: &'a TriangleSoup,
    of_corner: &'a [u32],
}

impl Numbers<'_> {
    fn number(&mut self, class: u32) -> u32 {
        self.numbering.number(self.soup, self.of_corner, class)
    }
}

/// The edges whose lower vertex number is the highest of all, in the order the reference's
/// quicksort on that number leaves them (in edge order where no order could pair them otherwise).
///
/// The quicksort is the reference's (its pivot from a seeded rotation), run only on the parts
/// that hold those edges: a part whose pivot is below the highest number leaves them all to its
/// right. An edge's number is kept as bounds until a comparison needs it exactly.
fn last_run(corners: &[[u32; 3]], numbers: &mut Numbers) -> Vec<u32> {
    let ends = |edge: u32| {
        let (t, e) = ((edge / 3) as usize, (edge % 3) as usize);
        (corners[t][e], corners[t][(e + 1) % 3])
    };
    let exact = |numbers: &mut Numbers, edge: u32| {
        let (a, b) = ends(edge);
        numbers.number(a).min(numbers.number(b))
    };
    let bounds = std::mem::take(&mut numbers.numbering.bounds);
    let bound = |edge: u32| {
        let (a, b) = ends(edge);
        let ((la, ha), (lb, hb)) = (bounds[a as usize], bounds[b as usize]);
        (la.min(lb), ha.min(hb))
    };
    let edge_count = corners.len() as u32 * 3;
    let Some(floor) = (0..edge_count).map(|e| bound(e).0).max() else {
        return Vec::new();
    };
    let candidates: Vec<(u32, u32)> = (0..edge_count)
        .filter(|&e| bound(e).1 >= floor)
        .map(|e| (e, exact(numbers, e)))
        .collect();
    let top = candidates.iter().map(|&(_, n)| n).max().unwrap_or(0);
    // Their order only decides which of them are paired when some two join the same two vertices
    // (a stretch) beside a third: with at most two, or no two alike, every order pairs them the
    // same, and the quicksort (most of a first frame's neighbour step) need not be run.
    let last: Vec<u32> = candidates
        .iter()
        .filter(|&&(_, n)| n == top)
        .map(|&(e, _)| e)
        .collect();
    let count = last.len();
    if count <= 2 {
        return last;
    }
    // All share their lower vertex (numbered `top`): two alike share the upper one too.
    let mut uppers: Vec<u32> = last
        .iter()
        .map(|&e| {
            let (a, b) = ends(e);
            numbers.number(a).max(numbers.number(b))
        })
        .collect();
    uppers.sort_unstable();
    uppers.dedup();
    if uppers.len() == count {
        return last;
    }
    let mut keys: Vec<(u32, u32, u32)> = (0..edge_count)
        .map(|e| {
            let (lo, hi) = bound(e);
            (lo, hi, e)
        })
        .collect();
    // The key of entry `i`, exactly (and from then on without bounds).
    let mut resolve = |keys: &mut [(u32, u32, u32)], i: isize| {
        let entry = &mut keys[i as usize];
        if entry.0 != entry.1 {
            let n = exact(numbers, entry.2);
            *entry = (n, n, entry.2);
        }
        entry.0
    };
    let mut parts = vec![(0isize, keys.len() as isize - 1, 39_871_946u32)];
    while let Some((left, right, seed)) = parts.pop() {
        let size = right - left + 1;
        if size < 2 {
            continue;
        }
        if size == 2 {
            if resolve(&mut keys, left) > resolve(&mut keys, right) {
                keys.swap(left as usize, right as usize);
            }
            continue;
        }
        let turn = seed & 31;
        let seed = seed
            .wrapping_add(seed.rotate_left(turn) | seed.rotate_right(32u32.wrapping_sub(turn)))
            .wrapping_add(3);
        let pivot = resolve(&mut keys, left + (seed % size as u32) as isize);
        let (mut il, mut ir) = (left, right);
        loop {
            // Below the pivot: certain from the bounds, else worked out.
            while keys[il as usize].1 < pivot
                || keys[il as usize].0 < pivot && resolve(&mut keys, il) < pivot
            {
                il += 1;
            }
            while keys[ir as usize].0 > pivot
                || keys[ir as usize].1 > pivot && resolve(&mut keys, ir) > pivot
            {
                ir -= 1;
            }
            if il <= ir {
                keys.swap(il as usize, ir as usize);
                il += 1;
                ir -= 1;
            }
            if il > ir {
                break;
            }
        }
        if left < ir && pivot == top {
            parts.push((left, ir, seed));
        }
        if il < right {
            parts.push((il, right, seed));
        }
    }
    keys[keys.len() - count..]
        .iter()
        .map(|&(_, _, e)| e)
        .collect()
}

// -------------------------------------------------------------------------------------------------
// 5. Groups

struct Groups {
    /// Per good triangle's corner (3 t + i): its group, or [`NONE`].
    of_corner: Vec<u32>,
    vertex: Vec<u32>,
    orientation: Vec<bool>,
    /// Triangles' orientations after the groups took the flat ones.
    info: Vec<TriangleInfo>,
}

impl Groups {
    /// One at a time, in the order of their first corner: a flat triangle's orientation is the
    /// first group's to reach it, which the later ones then see.
    fn build(triangles: &Triangles, across: &[u32]) -> Self {
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

// -------------------------------------------------------------------------------------------------
// 6. Frames

/// The frame of every good triangle's corner (3 t + i): per group, over the cores.
fn group_frames(
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

// -------------------------------------------------------------------------------------------------
// Threads

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

#[cfg(test)]
mod tests {
    use super::*;

    /// A cylinder's rings of `segments` quads, `rings` high, with seams of duplicated corners: its
    /// rows cross the weld grid's whole axis, as a 1M-triangle model's do.
    fn rings(segments: usize, rings: usize) -> TriangleSoup {
        let mut soup = TriangleSoup::default();
        let point = |i: usize, j: usize| {
            let a = std::f32::consts::TAU * i as f32 / segments as f32;
            let p = Vec3::new(a.cos(), j as f32 / rings as f32, a.sin());
            (
                p,
                Vec2::new(i as f32 / segments as f32, j as f32),
                Vec3::new(p.x, 0.0, p.z),
            )
        };
        for j in 0..rings {
            for i in 0..segments {
                for (di, dj) in [(0, 0), (0, 1), (1, 0), (1, 0), (0, 1), (1, 1)] {
                    let (p, uv, n) = point(i + di, j + dj);
                    soup.vertices.push(p);
                    soup.uvs.push(uv);
                    soup.normals.push(n);
                }
            }
        }
        soup
    }

    /// The kept corners of every vertex: one cell at a time as asked, or the cells left after
    /// `one_by_one` of them redone together. Fails if the batch reorders a cell differently or
    /// misses one (a cell's first vertex already kept is taken as the cell done).
    fn kept(soup: &TriangleSoup, one_by_one: usize, threads: usize) -> Vec<u32> {
        let (vertices, mut numbering, _) = Vertices::weld(soup, soup.vertices.len(), threads);
        let classes = numbering.kept.len() as u32;
        // Asked in an order that visits the cells out of turn.
        let order = (0..classes).map(|k| (k * 7919) % classes);
        let mut out = vec![NONE; classes as usize];
        numbering.one_by_one = one_by_one;
        for class in order {
            out[class as usize] = numbering.representative(soup, &vertices.of_corner, class);
        }
        out
    }

    fn numbering_of(soup: &TriangleSoup) -> Numbering {
        Vertices::weld(soup, soup.vertices.len(), 1).1
    }

    #[test]
    fn cells_redone_together_keep_the_corners_redone_one_by_one() {
        let soup = rings(300, 20);
        assert_eq!(300 * 20 * 6, soup.vertices.len());
        let lazy = kept(&soup, usize::MAX, 1);
        assert!(lazy.iter().all(|&c| c != NONE));
        let start = numbering_of(&soup).cell_start;
        let cells = (0..CELLS).filter(|&k| start[k] < start[k + 1]).count();
        assert!(cells > CELLS_ONE_BY_ONE, "{cells} cells");
        for (one_by_one, threads) in [(0, 1), (0, 3), (5, 2), (CELLS_ONE_BY_ONE, 2)] {
            assert_eq!(
                lazy,
                kept(&soup, one_by_one, threads),
                "{one_by_one} cells one by one, then the rest on {threads} threads"
            );
        }
    }
}
