//! The reference's number for each vertex (the corner its weld grid keeps), worked out only for
//! the cells whose vertices are asked.

use glam::Vec3;

use super::{on_runs, NONE};
use crate::common::objloader::TriangleSoup;
use crate::pipeline::on_threads;

/// Cells of the reference's weld grid, along the bounding box's longest axis.
const CELLS: usize = 2048;

/// The reference's grid cell of coordinate `x` between `min` and `max`.
fn grid_cell(min: f32, max: f32, x: f32) -> usize {
    let at = (CELLS as f32 * ((x - min) / (max - min))) as isize;
    at.clamp(0, CELLS as isize - 1) as usize
}

/// The reference's number for each vertex: the corner its weld keeps, as `face << 2 | corner`.
/// Numbers order the edges, and so decide the few neighbours the reference's sort leaves
/// unsorted ([`last_run`](super::neighbours::last_run)); a vertex whose corners differ in zeros' signs reads that corner's
/// floats.
///
/// The corner kept is the first of the vertex in the order the weld leaves the corners: a grid
/// along the longest axis, then each cell split at midpoints until the corners of a part are one
/// point or cannot be split. Redoing that for every cell costs more than all the rest, so it is
/// done only for the cells of the vertices whose number is asked; the others are known only
/// between their lowest and highest corner, which most comparisons need no more than. A mesh
/// whose rows cross the whole axis (a cylinder's rings) asks for nearly every cell: after
/// [`CELLS_ONE_BY_ONE`] the rest are redone at once, on every core.
pub(super) struct Numbering {
    axis: usize,
    min: f32,
    max: f32,
    /// The corners of each cell, in the soup's order (as the reference lists them).
    cell_start: Vec<u32>,
    cell_corners: Vec<u32>,
    /// Per vertex: its lowest and highest corner's number; the kept corner, once known (or NONE).
    pub(super) bounds: Vec<(u32, u32)>,
    pub(super) kept: Vec<u32>,
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
    /// The grid of the soup's corners and each vertex's bounds, no cell redone yet.
    pub(super) fn new(
        soup: &TriangleSoup,
        of_corner: &[u32],
        some_corner: &[u32],
        threads: usize,
    ) -> Self {
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
    pub(super) fn representative(
        &mut self,
        soup: &TriangleSoup,
        of_corner: &[u32],
        class: u32,
    ) -> u32 {
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
    pub(super) fn number(&mut self, soup: &TriangleSoup, of_corner: &[u32], class: u32) -> u32 {
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

#[cfg(test)]
mod tests {
    use glam::Vec2;

    use super::super::weld::Vertices;
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
