//! The `model` target: a model's OBJ with its MTL; the input's format (shared by the targets that
//! read models) and what `load_model` promises beyond a soup.

use std::path::Path;

use tutorial13::model::{load_model_bytes, MapOverrides, Model};

use super::obj::check_soup;
use super::{rejected, Outcome};
use crate::differential::shape_differs_from_rewrite;

/// Where a `model` input's MTL text starts (the OBJ's `mtllib` should name `fuzz.mtl`).
pub const MTL_SEPARATOR: &str = "#--- fuzz.mtl ---\n";

/// The `model` target's check (see [`Target::Model`](super::Target::Model)).
pub(super) fn check(input: &[u8], path: &Path) -> Result<Outcome, String> {
    // Read as a bake's HIGH too (a sculpt without UVs is taken in one pass): as the rewrite it
    // replaced read it.
    let (obj, mtl) = split_model_input(input);
    if let Ok(shape) = shape_differs_from_rewrite(&obj, path, read_fuzz_mtl(&mtl))? {
        check_model(&shape)?;
    }
    match load_model_input(input, path) {
        Err(e) => rejected(path, e),
        Ok(model) => check_model(&model).map(|_| Outcome::Loaded),
    }
}

/// A model input (the OBJ, then the MTL its `mtllib fuzz.mtl` reads) loaded in memory as `path`.
pub(super) fn load_model_input(input: &[u8], path: &Path) -> tutorial13::Result<Model> {
    let (obj, mtl) = split_model_input(input);
    load_model_bytes(&obj, path, &MapOverrides::default(), read_fuzz_mtl(&mtl))
}

/// The files a model input's OBJ may read: `fuzz.mtl` (the input's MTL text), and no other.
fn read_fuzz_mtl(mtl: &[u8]) -> impl Fn(&Path) -> std::io::Result<Vec<u8>> + Copy + '_ {
    move |p: &Path| {
        if p.file_name() == Some("fuzz.mtl".as_ref()) {
            Ok(mtl.to_vec())
        } else {
            Err(std::io::Error::from(std::io::ErrorKind::NotFound))
        }
    }
}

/// A model input split into the OBJ and the MTL its `mtllib fuzz.mtl` reads.
pub(super) fn split_model_input(input: &[u8]) -> (Vec<u8>, Vec<u8>) {
    let text = String::from_utf8_lossy(input);
    match text.split_once(MTL_SEPARATOR) {
        Some((obj, mtl)) => (obj.as_bytes().to_vec(), mtl.as_bytes().to_vec()),
        None => (input.to_vec(), Vec::new()),
    }
}

/// What `load_model` promises beyond a soup.
pub(super) fn check_model(model: &Model) -> Result<(), String> {
    check_soup(&model.soup)?;
    let unit = |n: &&glam::Vec3| (n.length() - 1.0).abs() <= 1e-3;
    let normals = &model.soup.normals;
    if let Some(n) = normals.iter().find(|n| model.normals_computed && !unit(n)) {
        return Err(format!("a computed normal of length {}", n.length()));
    }
    let center = tutorial13::model::TUTORIAL_CYLINDER_CENTER;
    let radius = tutorial13::model::TUTORIAL_CYLINDER_RADIUS;
    if let Some(p) = model
        .soup
        .vertices
        .iter()
        .find(|p| p.distance(center) > radius * 1.001)
    {
        return Err(format!("a vertex at {p}, outside the bounding sphere"));
    }
    let mut next = 0;
    for range in &model.ranges {
        if range.triangles.start != next || range.triangles.end <= next {
            return Err(format!("ranges {:?} leave a gap or overlap", model.ranges));
        }
        if range.material >= model.materials.len() {
            return Err(format!("range names material {}", range.material));
        }
        next = range.triangles.end;
    }
    if next != model.soup.triangle_count() {
        return Err(format!(
            "ranges end at {next} of {} triangles",
            model.soup.triangle_count()
        ));
    }
    Ok(())
}
