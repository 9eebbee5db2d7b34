//! Where a mesh's tangent frame comes from. Tutorial 13 teaches one way; the field uses three, and
//! the cylinder scene can switch between them on the same mesh:
//!
//! * `tutorial`: `computeTangentBasis` per triangle, Gram-Schmidt, the handedness fix, and
//!   `indexVBO_TBN` summing the tangents of merged corners (the default, the tutorial's frames);
//! * `mikktspace`: MikkTSpace (the convention of most tools and engines), computed by
//!   [`crate::pipeline::mikktspace`] (the `mikktspace` crate's results to the bit, on every core): a
//!   unit tangent per corner with the bitangent's sign in w, corners welded only where
//!   everything matches exactly, so that each keeps its own frame; the bitangent is
//!   `w × cross(N, T)`, as MikkTSpace's readers rebuild it;
//! * `derivative`: no precomputed tangents at all; the fragment shader builds a cotangent frame per
//!   pixel from screen-space derivatives (article 002), so the mesh goes up without tangent arrays;
//! * `file`: a glTF model's own `TANGENT`s (the specification's default), indexed as MikkTSpace's
//!   are; where the file supplies none, MikkTSpace, as the specification says a viewer computes.
//!
//! Where the UVs are mirrored (the tutorial's cylinder, seen through the loader's negated V, is
//! mirrored everywhere), the tutorial's handedness fix flips the tangent, while MikkTSpace keeps
//! T = dP/du and flips the bitangent instead (w = −1): the two frames agree on B and are opposite on
//! T, so a map's red channel lights the other way. The per-pixel frame follows the UVs as MikkTSpace
//! does.

use glam::Vec3;
use rustc_hash::FxHashMap;

use crate::common::objloader::TriangleSoup;
use crate::common::vboindexer::{IndexedMesh, Indices};
use crate::mesh::{build_mesh, MeshOptions};
use crate::pipeline::indexer::index_vbo;
use crate::Result;

/// The three sources, in the order the key steps through them.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash, clap::ValueEnum)]
pub enum TangentSource {
    #[default]
    Tutorial,
    #[value(name = "mikktspace")]
    MikkTSpace,
    Derivative,
    /// Listed (key F) only for a glTF model, whose file can supply tangents.
    File,
}

impl TangentSource {
    /// The next source, wrapping around (key F).
    pub fn next(self) -> Self {
        crate::choices::next(&self)
    }

    /// The indexed mesh this source draws: with summed tangents (tutorial), MikkTSpace's
    /// (mikktspace, and file for a soup without a file's tangents), or none (derivative).
    /// `options` are the tutorial pipeline's switches.
    pub fn mesh(self, soup: &TriangleSoup, options: MeshOptions) -> Result<IndexedMesh> {
        self.mesh_with(soup, None, options)
    }

    /// [`TangentSource::mesh`], with the file's tangents (one per corner) for `file`.
    pub fn mesh_with(
        self,
        soup: &TriangleSoup,
        file_tangents: Option<&[[f32; 4]]>,
        options: MeshOptions,
    ) -> Result<IndexedMesh> {
        match (self, file_tangents) {
            (Self::Tutorial, _) => Ok(build_mesh(soup, options)),
            (Self::File, Some(tangents)) => Ok(welded_mesh(soup, tangents)),
            (Self::MikkTSpace | Self::File, _) => mikktspace_mesh(soup),
            (Self::Derivative, _) => Ok(index_vbo(soup)),
        }
    }
}

impl std::fmt::Display for TangentSource {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&crate::choices::name(self))
    }
}

/// MikkTSpace's tangent per corner (xyz unit, w = ±1, the bitangent's sign): the program's own
/// implementation ([`crate::pipeline::mikktspace`]), the `mikktspace` crate's results to the bit.
pub fn mikktspace_tangents(soup: &TriangleSoup) -> Result<Vec<[f32; 4]>> {
    crate::pipeline::mikktspace::mikktspace_tangents(soup)
}

/// The soup indexed with MikkTSpace's frames: two corners become one vertex only when position,
/// UV, normal and tangent (with its sign) are bit for bit the same, so no frame is averaged.
pub fn mikktspace_mesh(soup: &TriangleSoup) -> Result<IndexedMesh> {
    Ok(welded_mesh(soup, &mikktspace_tangents(soup)?))
}

/// The soup indexed with a tangent per corner (xyz, w the bitangent's sign), welded as
/// [`mikktspace_mesh`] welds.
pub fn welded_mesh(soup: &TriangleSoup, tangents: &[[f32; 4]]) -> IndexedMesh {
    let (mut vertices, mut uvs, mut normals) = (Vec::new(), Vec::new(), Vec::new());
    let (mut tangents_out, mut bitangents) = (Vec::new(), Vec::new());
    let mut indices = Vec::with_capacity(tangents.len());
    let mut seen: FxHashMap<[u32; 12], u32> = FxHashMap::default();
    for (i, &[tx, ty, tz, w]) in tangents.iter().enumerate() {
        let (p, uv, n) = (soup.vertices[i], soup.uvs[i], soup.normals[i]);
        let t = Vec3::new(tx, ty, tz);
        let floats = [p.x, p.y, p.z, uv.x, uv.y, n.x, n.y, n.z, tx, ty, tz, w];
        let key = floats.map(f32::to_bits);
        let index = *seen.entry(key).or_insert_with(|| {
            vertices.push(p);
            uvs.push(uv);
            normals.push(n);
            tangents_out.push(t);
            // MikkTSpace's readers rebuild the bitangent from the normal, the tangent and the sign.
            bitangents.push(w * n.cross(t));
            (vertices.len() - 1) as u32
        });
        indices.push(index);
    }
    IndexedMesh {
        indices: Indices::from_u32(indices, vertices.len()),
        vertices,
        uvs,
        normals,
        tangents: tangents_out,
        bitangents,
    }
}
