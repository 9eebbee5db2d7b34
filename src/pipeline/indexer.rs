//! The fast indexers: [`index_vbo_tbn_hashed`] and [`index_vbo_hashed`] give the meshes of the tutorial's
//! `indexVBO_TBN` and `indexVBO` ([`crate::common::vboindexer`]) to the bit, in expected linear time.
//!
//! [`index_vbo_tbn_hashed`] works in two passes. First the corners are numbered by their exact bits, as
//! [`index_vbo_hashed`] (and meshoptimizer's remap) does (`weld.rs`): a corner equal to an earlier one to the
//! bit gets that corner's vertex, which the search would find again. Then, corner by corner in the
//! tutorial's order, the search (once per distinct corner), the index and the tangent sums. The
//! search keeps output vertices in a hash grid keyed on their position (`grid.rs`: each registered in
//! the cells its ±0.01 neighbourhood touches); a corner looks only in its own cell, taking the lowest
//! matching index, as the tutorial's linear search would.
//!
//! The two hash tables are written here rather than taken from a crate because their speed comes
//! from what a general map does not offer: a slot is loaded a few corners before it is needed
//! (with a prefetch), and a small table of recent keys answers most corners of a mesh from the
//! core's cache. Both are measured against meshoptimizer in `benches/first_frame.rs`.

mod grid;
mod weld;

use crate::common::objloader::TriangleSoup;
use crate::common::tangentspace::TangentBasis;
use crate::common::vboindexer::{
    check_lengths, corner, Builder, IndexOptions, IndexedMesh, Indices,
};
use grid::{cell_side, Grid};
use weld::weld;

/// The exact numbering by bits, for MikkTSpace's weld ([`crate::pipeline::mikktspace`]).
pub(crate) use weld::weld as weld_exact;

/// Asks the CPU to start loading `x`'s cache line, so that a lookup a few corners later does not
/// wait for memory. Changes no result.
#[inline(always)]
fn prefetch<T>(x: &T) {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: a prefetch only warms the cache; the pointer comes from a live reference.
    unsafe {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        _mm_prefetch::<_MM_HINT_T0>((x as *const T).cast());
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = x;
}

/// `indexVBO_TBN` with the tutorial's exact semantics, in expected linear time (see the module docs).
pub fn index_vbo_tbn_hashed(
    soup: &TriangleSoup,
    basis: &TangentBasis,
    options: IndexOptions,
) -> IndexedMesh {
    index_with_grid(soup, basis, options).0
}

/// How many numbers ahead [`index_with_grid`] starts loading the cells of their first corners.
const GRID_AHEAD: usize = 8;

/// [`index_vbo_tbn_hashed`], also giving how many candidate vertices the searches looked at in all.
///
/// In two passes over the corners, each with a small working set: number them by their exact bits
/// ([`weld`]); then, corner by corner, search the grid at each number's first corner (a corner
/// equal to an earlier one to the bit gets that corner's vertex: any near vertex with a lower index
/// existed back then, and would have been found), write the index and sum the tangents, as the
/// tutorial does.
fn index_with_grid(
    soup: &TriangleSoup,
    basis: &TangentBasis,
    options: IndexOptions,
) -> (IndexedMesh, u64) {
    check_lengths(soup, basis);
    let (mut numbers, mut first) = weld(soup, true);
    // At most one vertex per number; the index buffer will be `numbers`.
    let mut out = Builder::with_capacity(first.len(), 0, options);
    let mut grid = Grid::new(cell_side(soup), first.len());
    let mut steps = 0u64;
    // Numbers below `searched` have their vertex, which replaces their first corner in `first`.
    let mut searched = 0;
    for (i, index) in numbers.iter_mut().enumerate() {
        let number = *index as usize;
        // Numbers come in the order of their first corners: this is number `searched`'s.
        if number == searched {
            if let Some(&next) = first.get(number + GRID_AHEAD) {
                grid.prefetch(soup.vertices[next as usize]);
            }
            let corner = corner(soup, i);
            // A non-finite component is never near anything (NaN and inf - inf compare false), so
            // such a corner is always new and never found again: [`weld`] numbered it alone.
            let finite = corner.0.is_finite() && corner.1.is_finite() && corner.2.is_finite();
            first[number] = if finite {
                let found = grid.find(corner, &out.mesh);
                steps += found.steps as u64;
                if let Some(key) = found.split {
                    grid.split(key, &out.mesh);
                }
                match found.vertex {
                    Some(j) => j,
                    None => {
                        let j = out.add_vertex(corner);
                        grid.insert(j, &out.mesh);
                        j
                    }
                }
            } else {
                out.add_vertex(corner)
            };
            searched += 1;
        }
        let j = first[number];
        let (t, b) = (basis.tangents[i], basis.bitangents[i]);
        // Vertices are numbered in the order of the corners that made them.
        if j as usize == out.mesh.tangents.len() {
            out.start_sums(j, t, b);
        } else {
            out.add_sums(j, t, b);
        }
        // The corner's number becomes its vertex: the index buffer, in place.
        *index = j;
    }
    out.indices = numbers;
    (out.finish(), steps)
}

/// The plain `indexVBO`: corners merge only when position, UV and normal are bit-for-bit equal (the
/// original compares `PackedVertex` with `memcmp` in a `std::map`). No tangents.
pub fn index_vbo_hashed(soup: &TriangleSoup) -> IndexedMesh {
    let n = soup.vertices.len();
    assert!(soup.uvs.len() == n && soup.normals.len() == n);
    let (numbers, first) = weld(soup, false);
    // The vertices are the distinct corners, in the order they first came.
    IndexedMesh {
        indices: Indices::from_u32(numbers, first.len()),
        vertices: first.iter().map(|&i| soup.vertices[i as usize]).collect(),
        uvs: first.iter().map(|&i| soup.uvs[i as usize]).collect(),
        normals: first.iter().map(|&i| soup.normals[i as usize]).collect(),
        tangents: Vec::new(),
        bitangents: Vec::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::grid::cell_side;
    use super::*;
    use crate::common::vboindexer::{self, IndexOptions, Indices};
    use glam::{Vec2, Vec3};

    fn soup_of(positions: &[Vec3]) -> (TriangleSoup, TangentBasis) {
        let n = positions.len();
        let soup = TriangleSoup {
            vertices: positions.to_vec(),
            uvs: vec![Vec2::ZERO; n],
            normals: vec![Vec3::Z; n],
        };
        let basis = TangentBasis {
            tangents: (0..n).map(|i| Vec3::new(i as f32, 1.0, 0.0)).collect(),
            bitangents: vec![Vec3::Y; n],
        };
        (soup, basis)
    }

    // Fails if "near" is not strict per-component < 0.01, or if a merged vertex keeps its own
    // tangent instead of the sum.
    #[test]
    fn near_corners_merge_and_sum() {
        let (soup, basis) = soup_of(&[
            Vec3::ZERO,
            Vec3::new(0.009, 0.0, 0.0), // near the first
            Vec3::new(0.011, 0.0, 0.0), // not near the first, near the second: new vertex
        ]);
        for mesh in [
            index_vbo_tbn_hashed(&soup, &basis, IndexOptions::default()),
            vboindexer::index_vbo_tbn(&soup, &basis, IndexOptions::default()),
        ] {
            assert_eq!(mesh.indices, Indices::U16(vec![0, 0, 1]));
            assert_eq!(mesh.vertices, vec![Vec3::ZERO, Vec3::new(0.011, 0.0, 0.0)]);
            assert_eq!(mesh.tangents[0], Vec3::new(1.0, 2.0, 0.0));
            assert_eq!(mesh.bitangents[0], Vec3::new(0.0, 2.0, 0.0));
        }
    }

    // Fails if the fast indexer takes any near vertex rather than the first, as the linear search does.
    #[test]
    fn first_near_vertex_wins_across_cells() {
        // Vertices 0 and 1 are 0.015 apart (both kept); the corner at 0.0075 is near both and
        // straddles a cell boundary: it must pick vertex 0.
        let base = 0.025 * 7.0 - 0.0075;
        let (soup, basis) = soup_of(&[
            Vec3::new(base + 0.015, 0.0, 0.0),
            Vec3::new(base, 0.0, 0.0),
            Vec3::new(base + 0.0075, 0.0, 0.0),
        ]);
        let fast = index_vbo_tbn_hashed(&soup, &basis, IndexOptions::default());
        assert_eq!(fast.indices.to_u32(), vec![0, 1, 0]);
        assert_eq!(
            fast,
            vboindexer::index_vbo_tbn(&soup, &basis, IndexOptions::default())
        );
    }

    // Fails if NaN corners are merged with each other or anything else (the original never does).
    #[test]
    fn non_finite_corners_never_merge() {
        let (soup, basis) = soup_of(&[
            Vec3::NAN,
            Vec3::NAN,
            Vec3::ZERO,
            Vec3::INFINITY,
            Vec3::INFINITY,
            Vec3::ZERO,
        ]);
        let fast = index_vbo_tbn_hashed(&soup, &basis, IndexOptions::default());
        assert_eq!(fast.indices.to_u32(), vec![0, 1, 2, 3, 4, 2]);
    }

    // Fails if the exercise switch does not normalize each corner before summing.
    #[test]
    fn normalize_before_sum() {
        let (soup, basis) = soup_of(&[Vec3::ZERO, Vec3::ZERO, Vec3::ZERO]);
        let options = IndexOptions {
            normalize_before_sum: true,
        };
        let mesh = index_vbo_tbn_hashed(&soup, &basis, options);
        let expected =
            Vec3::Y + Vec3::new(1.0, 1.0, 0.0).normalize() + Vec3::new(2.0, 1.0, 0.0).normalize();
        assert!((mesh.tangents[0] - expected).length() < 1e-6);
        assert_eq!(mesh.bitangents[0], Vec3::new(0.0, 3.0, 0.0));
    }

    // Fails if the plain indexer merges anything but bit-identical corners.
    #[test]
    fn index_vbo_merges_exact_duplicates_only() {
        let (soup, _) = soup_of(&[Vec3::ZERO, Vec3::new(0.001, 0.0, 0.0), Vec3::ZERO]);
        let mesh = index_vbo_hashed(&soup);
        assert_eq!(mesh.indices.to_u32(), vec![0, 1, 0]);
        assert!(mesh.tangents.is_empty());
    }

    // Fails if thousands of vertices sharing one position (distinct UVs) stay in one list that
    // every corner walks: the search would be quadratic. After the split, lists stay short.
    #[test]
    fn one_position_cell_is_split() {
        for position in [Vec3::ZERO, Vec3::splat(0.025)] {
            let n = 3000;
            let (mut soup, basis) = soup_of(&vec![position; n]);
            soup.uvs = (0..n)
                .map(|i| Vec2::new(0.02 * (i % 50) as f32, 0.02 * (i / 50) as f32))
                .collect();
            let (mesh, steps) = index_with_grid(&soup, &basis, IndexOptions::default());
            assert_eq!(mesh.vertices.len(), n);
            // Unsplit, every corner walks every earlier vertex: n²/2 = 4.5 million steps.
            assert!(steps < 20 * n as u64, "{position}: {steps} steps");
        }
    }

    // Fails if the position cells are not sized to the mesh: twice the typical edge, rounded to
    // 0.05 × 2^k, at least 0.05 (also for a soup of one point, or of edges too long for f32).
    #[test]
    fn cell_side_follows_the_edges() {
        // Right triangles along x, legs `edge` long (so the median edge is `edge`).
        let strip = |edge: f32| {
            let positions: Vec<Vec3> = (0..300)
                .map(|i| {
                    let corner = [Vec3::ZERO, Vec3::X, Vec3::Y][i % 3];
                    (corner + Vec3::X * (i / 3) as f32) * edge
                })
                .collect();
            soup_of(&positions).0
        };
        assert_eq!(cell_side(&strip(0.06)), 0.1);
        assert_eq!(cell_side(&strip(0.02)), 0.05);
        assert_eq!(cell_side(&strip(0.5)), 0.8);
        assert_eq!(cell_side(&soup_of(&[Vec3::ONE; 30]).0), 0.05);
        assert_eq!(cell_side(&strip(3e38)), 0.05);
        assert_eq!(cell_side(&soup_of(&[]).0), 0.05);
    }
}
