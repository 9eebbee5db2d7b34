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
//!   are; for the primitives that supply none, MikkTSpace over their triangles, as the
//!   specification says a viewer computes.
//!
//! Where the UVs are mirrored (the tutorial's cylinder, seen through the loader's negated V, is
//! mirrored everywhere), the tutorial's handedness fix flips the tangent, while MikkTSpace keeps
//! T = dP/du and flips the bitangent instead (w = −1): the two frames agree on B and are opposite on
//! T, so a map's red channel lights the other way. The per-pixel frame follows the UVs as MikkTSpace
//! does.
//!
//! This module chooses among the sources; the computations are elsewhere: the port of
//! `tangentspace.cpp` in [`crate::common::tangentspace`], MikkTSpace in [`crate::pipeline::mikktspace`].

use std::borrow::Cow;
use std::ops::Range;

use glam::{DMat3, DVec3, Vec3};

use crate::common::objloader::TriangleSoup;
use crate::common::vboindexer::{IndexedMesh, Indices};
use crate::mesh::{build_mesh, MeshOptions};
use crate::pipeline::indexer::{index_vbo_hashed, weld_exact};
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
    /// Whether the mesh carries a tangent per vertex (every source but the per-pixel frame, which
    /// solves one in the fragment shader): what the TBN lines and the per-vertex programs need.
    pub fn has_vertex_tangents(self) -> bool {
        self != TangentSource::Derivative
    }

    /// The indexed mesh this source draws: with summed tangents (tutorial), MikkTSpace's
    /// (mikktspace, and file for a soup without a file's tangents), or none (derivative).
    /// `options` are the tutorial pipeline's switches.
    pub fn mesh(self, soup: &TriangleSoup, options: MeshOptions) -> Result<IndexedMesh> {
        self.mesh_with(soup, None, options)
    }

    /// [`TangentSource::mesh`], with the file's tangents for `file`.
    pub fn mesh_with(
        self,
        soup: &TriangleSoup,
        file_tangents: Option<&FileTangents>,
        options: MeshOptions,
    ) -> Result<IndexedMesh> {
        match (self, file_tangents) {
            (Self::Tutorial, _) => Ok(build_mesh(soup, options)),
            (Self::File, Some(file)) => Ok(welded_mesh(soup, &file.complete(soup)?)),
            (Self::MikkTSpace | Self::File, _) => mikktspace_mesh(soup),
            (Self::Derivative, _) => Ok(index_vbo_hashed(soup)),
        }
    }
}

/// A model file's own tangents (glTF's `TANGENT`), where some of its primitives supply them.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FileTangents {
    /// One per corner (xyz unit, w = ±1: the bitangent is `w × cross(N, T)`); the corners of
    /// `missing` hold zeros until [`FileTangents::complete`] computes theirs.
    pub per_corner: Vec<[f32; 4]>,
    /// Runs of triangles, in the soup's order, whose primitive supplies none.
    pub missing: Vec<Range<usize>>,
}

impl FileTangents {
    /// Every corner's tangent: the file's, and for the triangles of `missing`, MikkTSpace's over
    /// those triangles alone (the specification asks a viewer to compute them for each primitive
    /// that has none; the file's own take no part).
    pub fn complete(&self, soup: &TriangleSoup) -> Result<Cow<'_, [[f32; 4]]>> {
        if self.missing.is_empty() {
            return Ok(Cow::Borrowed(&self.per_corner));
        }
        let corners = |r: &Range<usize>| 3 * r.start..3 * r.end;
        let mut lacking = TriangleSoup::default();
        for r in &self.missing {
            lacking.vertices.extend(&soup.vertices[corners(r)]);
            lacking.uvs.extend(&soup.uvs[corners(r)]);
            lacking.normals.extend(&soup.normals[corners(r)]);
        }
        let computed = mikktspace_tangents(&lacking)?;
        let mut all = self.per_corner.clone();
        let mut from = 0;
        for r in &self.missing {
            let to = from + 3 * r.len();
            all[corners(r)].copy_from_slice(&computed[from..to]);
            from = to;
        }
        Ok(Cow::Owned(all))
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
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let (tangents, numbers) = crate::pipeline::mikktspace::mikktspace_numbered(soup, threads)?;
    let clock = crate::clock::Instant::now();
    let mesh = weld_numbered(soup, &tangents, &numbers);
    log::trace!(
        "weld of MikkTSpace's output: {:.1} ms",
        clock.elapsed().as_secs_f64() * 1e3
    );
    Ok(mesh)
}

/// The soup indexed with a tangent per corner (xyz, w the bitangent's sign), welded as
/// [`mikktspace_mesh`] welds.
pub fn welded_mesh(soup: &TriangleSoup, tangents: &[[f32; 4]]) -> IndexedMesh {
    weld_numbered(soup, tangents, &weld_exact(soup, false).0)
}

/// [`welded_mesh`], given each corner's number by the exact bits of its position, UV and normal
/// (numbered in the order they first come): corners of one number are one vertex per distinct
/// tangent, and vertices come in the order of their first corner, as a hash of all twelve floats
/// would give them, for a fraction of its cost (a number has one tangent, or a few).
fn weld_numbered(soup: &TriangleSoup, tangents: &[[f32; 4]], numbers: &[u32]) -> IndexedMesh {
    const NONE: u32 = u32::MAX;
    debug_assert_eq!(numbers.len(), tangents.len());
    let expected = numbers.iter().max().map_or(0, |&n| n as usize + 1);
    // Per number, its latest vertex; per vertex, the one before it of the same number.
    let mut latest = vec![NONE; expected];
    let mut before: Vec<u32> = Vec::with_capacity(expected);
    let mut keys: Vec<[u32; 4]> = Vec::with_capacity(expected);
    let (mut vertices, mut uvs, mut normals) = (
        Vec::with_capacity(expected),
        Vec::with_capacity(expected),
        Vec::with_capacity(expected),
    );
    let (mut tangents_out, mut bitangents) =
        (Vec::with_capacity(expected), Vec::with_capacity(expected));
    let mut indices = Vec::with_capacity(tangents.len());
    for (i, (&t, &number)) in tangents.iter().zip(numbers).enumerate() {
        let key = t.map(f32::to_bits);
        let mut v = latest[number as usize];
        while v != NONE && keys[v as usize] != key {
            v = before[v as usize];
        }
        if v == NONE {
            v = vertices.len() as u32;
            before.push(latest[number as usize]);
            latest[number as usize] = v;
            keys.push(key);
            let (p, uv, n) = (soup.vertices[i], soup.uvs[i], soup.normals[i]);
            let [tx, ty, tz, w] = t;
            let t = Vec3::new(tx, ty, tz);
            vertices.push(p);
            uvs.push(uv);
            normals.push(n);
            tangents_out.push(t);
            // MikkTSpace's readers rebuild the bitangent from the normal, the tangent and the sign.
            bitangents.push(w * n.cross(t));
        }
        indices.push(v);
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

/// σmax/σmin of the matrix whose columns are `t`, `b` and `n`: how far a frame is from one at right
/// angles with equal lengths (1), which the tutorial's shader needs to light right.
pub fn frame_stretch(t: Vec3, b: Vec3, n: Vec3) -> f64 {
    stretch(&[t.as_dvec3(), b.as_dvec3(), n.as_dvec3()])
}

/// σmax/σmin of the frame's matrix (the square roots of its Gram matrix's extreme eigenvalues); a
/// frame with no inverse is infinitely stretched.
pub fn stretch(frame: &[DVec3; 3]) -> f64 {
    let m = DMat3::from_cols(frame[0], frame[1], frame[2]);
    let gram = m.transpose() * m;
    let (smallest, largest) = symmetric_eigen_extremes(&gram);
    if smallest <= 0.0 || !smallest.is_finite() {
        return f64::INFINITY;
    }
    (largest / smallest).sqrt()
}

/// The smallest and largest eigenvalues of a symmetric 3 × 3 matrix (the trigonometric solution of
/// its characteristic cubic).
fn symmetric_eigen_extremes(a: &DMat3) -> (f64, f64) {
    let (a00, a11, a22) = (a.x_axis.x, a.y_axis.y, a.z_axis.z);
    let (a01, a02, a12) = (a.y_axis.x, a.z_axis.x, a.z_axis.y);
    let off = a01 * a01 + a02 * a02 + a12 * a12;
    let q = (a00 + a11 + a22) / 3.0;
    if off <= 1e-30 * q * q {
        let d = [a00, a11, a22];
        return (
            d.iter().copied().fold(f64::INFINITY, f64::min),
            d.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        );
    }
    let p2 = (a00 - q).powi(2) + (a11 - q).powi(2) + (a22 - q).powi(2) + 2.0 * off;
    let p = (p2 / 6.0).sqrt();
    let b = (*a - DMat3::from_diagonal(DVec3::splat(q))) * (1.0 / p);
    let r = (b.determinant() / 2.0).clamp(-1.0, 1.0);
    let phi = r.acos() / 3.0;
    let largest = q + 2.0 * p * phi.cos();
    let smallest = q + 2.0 * p * (phi + 2.0 * std::f64::consts::PI / 3.0).cos();
    (smallest, largest)
}

#[cfg(test)]
mod stretch_tests {
    use super::*;

    /// Fails if the eigenvalue solution is wrong for a rotated spectrum, or for a diagonal one.
    #[test]
    fn the_stretch_of_a_frame_is_its_singular_values_ratio() {
        let rotation = DMat3::from_euler(glam::EulerRot::XYZ, 0.3, -0.7, 1.1);
        let scaled = rotation * DMat3::from_diagonal(DVec3::new(2.0, 0.5, 1.0));
        let frame = [scaled.x_axis, scaled.y_axis, scaled.z_axis];
        assert!((stretch(&frame) - 4.0).abs() < 1e-9, "{}", stretch(&frame));
        let identity = [DVec3::X, DVec3::Y, DVec3::Z];
        assert!((stretch(&identity) - 1.0).abs() < 1e-12);
        let scaled = [DVec3::X * 3.0, DVec3::Y * 3.0, DVec3::Z * 3.0];
        assert!((stretch(&scaled) - 1.0).abs() < 1e-12);
        let flat = [DVec3::X, DVec3::Y, DVec3::X + DVec3::Y];
        assert!(stretch(&flat) > 1e6);
    }
}
