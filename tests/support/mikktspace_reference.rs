//! The `mikktspace` crate (the port of Mikkelsen's reference code), which the program's own
//! MikkTSpace (`pipeline::mikktspace`) must equal to the bit. Included with `#[path]` by tests/all,
//! fuzz/main.rs and benches/pipeline.rs: a dev-dependency of tutorial13 and a dependency of the
//! fuzz and bench packages, never in the program.

#![allow(dead_code)] // each including crate uses a different part

use tutorial13::common::objloader::TriangleSoup;

/// The soup as the crate reads it: faces of three corners, a tangent written back per corner.
struct Reference<'a> {
    soup: &'a TriangleSoup,
    tangents: Vec<[f32; 4]>,
}

impl mikktspace::Geometry for Reference<'_> {
    fn num_faces(&self) -> usize {
        self.soup.triangle_count()
    }
    fn num_vertices_of_face(&self, _face: usize) -> usize {
        3
    }
    fn position(&self, face: usize, vert: usize) -> [f32; 3] {
        self.soup.vertices[3 * face + vert].to_array()
    }
    fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
        self.soup.normals[3 * face + vert].to_array()
    }
    fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
        self.soup.uvs[3 * face + vert].to_array()
    }
    fn set_tangent_encoded(&mut self, tangent: [f32; 4], face: usize, vert: usize) {
        self.tangents[3 * face + vert] = tangent;
    }
}

/// The crate's tangent per corner, or `None` where it refuses the mesh.
///
/// Only for meshes the crate can take: finite numbers, and at least one triangle without two
/// equal positions (with none, its prologue underflows a `usize` and reads past its array).
pub fn reference_tangents(soup: &TriangleSoup) -> Option<Vec<[f32; 4]>> {
    let mut geometry = Reference {
        soup,
        tangents: vec![[0.0; 4]; soup.vertices.len()],
    };
    mikktspace::generate_tangents(&mut geometry).then_some(geometry.tangents)
}

/// Whether the crate can take `soup` (see [`reference_tangents`]).
pub fn reference_can_take(soup: &TriangleSoup) -> bool {
    let p = &soup.vertices;
    let finite = p.iter().all(|v| v.is_finite())
        && soup.normals.iter().all(|v| v.is_finite())
        && soup.uvs.iter().all(|v| v.is_finite());
    let good = (0..soup.triangle_count()).any(|f| {
        !(p[3 * f] == p[3 * f + 1] || p[3 * f] == p[3 * f + 2] || p[3 * f + 1] == p[3 * f + 2])
    });
    finite && good
}

/// The first corner whose tangent differs in any bit from the crate's, named with both values
/// (NaNs of any payload count as equal: which operand's payload an operation keeps is the
/// compiler's choice).
pub fn first_difference(ours: &[[f32; 4]], reference: &[[f32; 4]]) -> Option<String> {
    if ours.len() != reference.len() {
        return Some(format!(
            "{} tangents, the crate {}",
            ours.len(),
            reference.len()
        ));
    }
    let same = |a: f32, b: f32| a.to_bits() == b.to_bits() || a.is_nan() && b.is_nan();
    (0..ours.len())
        .find(|&i| !(0..4).all(|k| same(ours[i][k], reference[i][k])))
        .map(|i| {
            format!(
                "corner {i}: ours {:?}, the crate {:?}",
                ours[i], reference[i]
            )
        })
}
