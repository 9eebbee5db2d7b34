//! Step 1, the weld: corners equal under `==` made one vertex, each vertex reading the floats of
//! the corner the reference keeps.

use glam::{Vec2, Vec3};
use rustc_hash::FxHashMap;

use super::numbering::Numbering;
use crate::common::objloader::TriangleSoup;
use crate::pipeline::indexer::weld_exact;

/// The welded vertices: each corner's, and each vertex's floats.
pub(super) struct Vertices {
    pub(super) of_corner: Vec<u32>,
    pub(super) positions: Vec<Vec3>,
    pub(super) normals: Vec<Vec3>,
    pub(super) uvs: Vec<Vec2>,
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
    pub(super) fn weld(
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
