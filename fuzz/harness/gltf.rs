//! The `gltf` target: glTF models (JSON or binary), and their own tangents.

use std::path::Path;

use tutorial13::model::{load_model_bytes, load_shape_bytes, MapOverrides, Model};

use super::model::check_model;
use super::{rejected, Outcome};

/// The `gltf` target's check (see [`Target::Gltf`](super::Target::Gltf)).
pub(super) fn check(input: &[u8], path: &Path) -> Result<Outcome, String> {
    let nothing_beside = |_: &Path| Err(std::io::ErrorKind::NotFound.into());
    // Read for its shape too (a bake's HIGH: a primitive without UVs is taken).
    if let Ok(shape) = load_shape_bytes(input, path, nothing_beside) {
        check_model(&shape)?;
    }
    match load_model_bytes(input, path, &MapOverrides::default(), nothing_beside) {
        Err(e) => rejected(path, e),
        Ok(model) => {
            check_model(&model)?;
            check_file_tangents(&model).map(|_| Outcome::Loaded)
        }
    }
}

/// A glTF model's own tangents: one per corner, xyz of unit length and w = ±1 where the file
/// supplies them, zeros (MikkTSpace's to be) in runs of whole triangles where it does not.
fn check_file_tangents(model: &Model) -> Result<(), String> {
    let Some(file) = &model.file_tangents else {
        return Ok(());
    };
    let corners = model.soup.vertices.len();
    if file.per_corner.len() != corners {
        return Err(format!(
            "{} file tangents for {corners} corners",
            file.per_corner.len()
        ));
    }
    let mut computed = vec![false; corners];
    let mut end = 0;
    for r in &file.missing {
        if r.start < end || r.start >= r.end || 3 * r.end > corners {
            return Err(format!(
                "missing runs {:?} for {corners} corners",
                file.missing
            ));
        }
        computed[3 * r.start..3 * r.end].fill(true);
        end = r.end;
    }
    let bad = |(t, computed): &(&[f32; 4], &bool)| match computed {
        true => **t != [0.0; 4],
        false => {
            let length = glam::Vec3::new(t[0], t[1], t[2]).length();
            (length - 1.0).abs() > 1e-3 || t[3].abs() != 1.0
        }
    };
    match file.per_corner.iter().zip(&computed).find(bad) {
        Some((t, _)) => Err(format!("a file tangent {t:?}")),
        None => Ok(()),
    }
}
