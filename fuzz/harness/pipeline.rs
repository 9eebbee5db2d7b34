//! The `pipeline` target: OBJ text through tangents and indexing under every switch setting.

use std::path::Path;

use tutorial13::common::objloader::TriangleSoup;
use tutorial13::common::tangentspace::{compute_tangent_basis, TangentOptions};
use tutorial13::common::vboindexer::{self, IndexOptions, IndexedMesh};
use tutorial13::mesh::MeshOptions;
use tutorial13::pipeline::indexer::index_vbo_tbn_hashed;
use tutorial13::pipeline::obj_parse::load_obj_bytes_threaded;

use super::obj::check_soup;
use super::{rejected, Outcome};

/// Meshes up to this many corners are also indexed by the quadratic reference.
const LINEAR_REFERENCE_MAX_CORNERS: usize = 3000;

/// The `pipeline` target's check (see [`Target::Pipeline`](super::Target::Pipeline)).
pub(super) fn check(input: &[u8], path: &Path) -> Result<Outcome, String> {
    match load_obj_bytes_threaded(input, path) {
        Err(e) => rejected(path, e),
        Ok(soup) => {
            check_soup(&soup)?;
            check_pipeline(&soup)?;
            Ok(Outcome::Loaded)
        }
    }
}

/// Tangents and indexing under every switch setting.
fn check_pipeline(soup: &TriangleSoup) -> Result<(), String> {
    let corners = soup.vertices.len();
    for bits in 0..8u8 {
        let options = MeshOptions {
            tangents: TangentOptions {
                gram_schmidt: bits & 1 == 0,
                handedness: bits & 2 == 0,
            },
            indexing: IndexOptions {
                normalize_before_sum: bits & 4 != 0,
            },
            code: None,
        };
        let basis = compute_tangent_basis(soup, options.tangents);
        if basis.tangents.len() != corners || basis.bitangents.len() != corners {
            return Err(format!("{options:?}: tangent basis of the wrong length"));
        }
        if let Some(i) = (0..corners)
            .find(|&i| !(basis.tangents[i].is_finite() && basis.bitangents[i].is_finite()))
        {
            return Err(format!(
                "{options:?}: corner {i} has tangent {} bitangent {}",
                basis.tangents[i], basis.bitangents[i]
            ));
        }
        if options.tangents.gram_schmidt {
            // Gram-Schmidt ends in a normalize: a unit tangent or the (unit) fallback frame. (Within
            // 1 %: f32's normalize of a vector with subnormal squares is off by 1e-4.)
            if let Some(i) = (0..corners).find(|&i| (basis.tangents[i].length() - 1.0).abs() > 0.01)
            {
                return Err(format!(
                    "{options:?}: corner {i} tangent {} is not unit length",
                    basis.tangents[i]
                ));
            }
        }
        let mesh = index_vbo_tbn_hashed(soup, &basis, options.indexing);
        check_indexed(&mesh, corners).map_err(|e| format!("{options:?}: {e}"))?;
        if corners <= LINEAR_REFERENCE_MAX_CORNERS {
            let reference = vboindexer::index_vbo_tbn(soup, &basis, options.indexing);
            if mesh != reference {
                return Err(format!(
                    "{options:?}: grid indexer differs from the linear reference"
                ));
            }
        }
    }
    Ok(())
}

fn check_indexed(mesh: &IndexedMesh, corners: usize) -> Result<(), String> {
    let n = mesh.vertices.len();
    if mesh.uvs.len() != n
        || mesh.normals.len() != n
        || mesh.tangents.len() != n
        || mesh.bitangents.len() != n
    {
        return Err("vertex arrays of different lengths".into());
    }
    if mesh.indices.len() != corners {
        return Err(format!(
            "{} indices for {corners} corners",
            mesh.indices.len()
        ));
    }
    if let Some(i) = (0..corners).find(|&i| mesh.indices.get(i) as usize >= n) {
        return Err(format!(
            "index {} out of range ({n} vertices)",
            mesh.indices.get(i)
        ));
    }
    if let Some(j) = (0..n).find(|&j| {
        !(mesh.vertices[j].is_finite()
            && mesh.uvs[j].is_finite()
            && mesh.normals[j].is_finite()
            && mesh.tangents[j].is_finite()
            && mesh.bitangents[j].is_finite())
    }) {
        return Err(format!(
            "vertex {j} not finite: tangent {} bitangent {}",
            mesh.tangents[j], mesh.bitangents[j]
        ));
    }
    // Usable by the shader: sums stay at most 2^40 per component (the indexer's limit).
    let limit = (1u64 << 40) as f32;
    if let Some(j) = (0..n).find(|&j| {
        mesh.tangents[j].abs().max_element() > limit
            || mesh.bitangents[j].abs().max_element() > limit
    }) {
        return Err(format!(
            "vertex {j} beyond 2^40: tangent {} bitangent {}",
            mesh.tangents[j], mesh.bitangents[j]
        ));
    }
    Ok(())
}
