//! The cylinder scene's textures when they are not the tutorial's three files: a learner's model's,
//! per material, and maps named on the command line over the tutorial's own.

use std::path::Path;

use crate::common::texture::{load_bmp_custom, load_dds, Texture};
use crate::gl::map_uploads::upload_map;
use crate::gl::Gl;
use crate::model::maps::{decode, Slot};
use crate::model::{MapOverrides, MapSource, Model};
use crate::Result;

use super::tutorial13::TextureSet;

/// One set per material of `model`, each drawing its range. What the model leaves out (maps not
/// named, options ignored) goes to the log as information; a named map that cannot be read, as a
/// warning.
pub fn model_texture_sets(gl: &Gl, model: &Model) -> Result<Vec<TextureSet>> {
    let mut notices = Vec::new();
    let mut sets = Vec::with_capacity(model.ranges.len());
    for range in &model.ranges {
        let material = &model.materials[range.material];
        let mut load = |source: &MapSource, slot: Slot| -> Result<Texture> {
            let pixels = decode(source, slot, &mut notices)?;
            // V as written: GL's bottom-row-first for the maps read at UV, top row first for the
            // normal map, which the tutorial's shader reads at (UV.x, -UV.y).
            upload_map(gl, pixels, slot != Slot::Normal)
        };
        sets.push(TextureSet {
            diffuse_texture: load(&material.diffuse, Slot::Diffuse)?,
            normal_texture: load(&material.normal, Slot::Normal)?,
            specular_texture: load(&material.specular, Slot::Specular)?,
            triangles: Some(range.triangles.clone()),
        });
    }
    for notice in &model.notices {
        log::info!("{notice}");
    }
    // A map the model names that is missing or cannot be read: the learner's files need a look.
    for notice in &notices {
        log::warn!("{notice}");
    }
    Ok(sets)
}

/// Replaces the tutorial's maps with those `overrides` names. A file in the tutorial's own format
/// for its slot (DDS diffuse and specular, BMP normal map) goes through the tutorial's loader, so
/// that naming the tutorial's own files changes nothing; any other picture is decoded and uploaded
/// the way the tutorial's negated V reads it. A height map is turned by 180° first (its strength
/// negated), because the tutorial's frame on its cylinder is (see docs/model.md, "Which way is up").
pub fn override_tutorial_maps(
    gl: &Gl,
    set: &mut TextureSet,
    overrides: &MapOverrides,
) -> Result<()> {
    let is = |path: &Path, extension: &str| {
        path.extension()
            .is_some_and(|e| e.eq_ignore_ascii_case(extension))
    };
    let load = |source: MapSource, slot: Slot| -> Result<Texture> {
        match (&source, slot) {
            (MapSource::File { path, .. }, Slot::Normal) if is(path, "bmp") => {
                load_bmp_custom(gl, path)
            }
            (MapSource::File { path, .. }, _) if slot != Slot::Normal && is(path, "dds") => {
                load_dds(gl, path)
            }
            _ => {
                let pixels = decode(&source, slot, &mut Vec::new())?;
                // The tutorial's V is negated: the normal map (read at (U, V)) bottom row first,
                // the others (read at (U, -V)) top row first.
                upload_map(gl, pixels, slot == Slot::Normal)
            }
        }
    };
    if let Some(path) = &overrides.diffuse {
        set.diffuse_texture = load(MapSource::command_line(path, "--diffuse"), Slot::Diffuse)?;
    }
    if let Some(source) = overrides.normal_source() {
        let source = match source {
            MapSource::Height { path, strength } => MapSource::Height {
                path,
                strength: -strength,
            },
            other => other,
        };
        set.normal_texture = load(source, Slot::Normal)?;
    }
    if let Some(path) = &overrides.specular {
        set.specular_texture = load(MapSource::command_line(path, "--specular"), Slot::Specular)?;
    }
    Ok(())
}
