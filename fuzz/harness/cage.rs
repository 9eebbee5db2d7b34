//! The `cage` target: the bake's readers of a cage and of part names.

use std::path::Path;

use tutorial13::bake::cage::cage_corners;
use tutorial13::bake::{BakeSettings, Pairing};
use tutorial13::model::parts::part_names;
use tutorial13::model::Model;
use tutorial13::tangent_source::TangentSource;

use super::bake::{bake_frames, bake_models_with, bake_sphere, check_baked, load_bake_model};
use super::model::split_model_input;
use super::{message_kind, Outcome};

/// The `cage` target's check (see [`Target::Cage`](super::Target::Cage)).
pub(super) fn check(input: &[u8], _path: &Path) -> Result<Outcome, String> {
    match load_bake_model(input) {
        Err(e) => Ok(Outcome::Rejected(message_kind(&e.to_string()))),
        Ok(model) => check_cage(&model, input).map(|_| Outcome::Loaded),
    }
}

/// The `cage` target's check (see [`Target::Cage`](super::Target::Cage)); `input` is the model's
/// file as read.
fn check_cage(model: &Model, input: &[u8]) -> Result<(), String> {
    let triangles = model.soup.triangle_count();
    let (obj, _) = split_model_input(input);
    let names = part_names(model, triangles, |_| Ok(obj.clone())).map_err(|e| e.to_string())?;
    let named = names.of_triangle.len() == triangles
        && names
            .of_triangle
            .iter()
            .all(|&n| (n as usize) < names.names.len());
    if !named {
        return Err(format!(
            "{} names for {} triangles of {triangles}",
            names.names.len(),
            names.of_triangle.len()
        ));
    }
    // Paired with itself: each triangle in a pair or in a part said unpaired, on both sides.
    let pairing = Pairing::new(&names, &names);
    let paired = |side: fn(&tutorial13::bake::parts::Pair) -> usize| -> usize {
        pairing.pairs.iter().map(side).sum()
    };
    let unpaired = |parts: &[(String, usize)]| parts.iter().map(|p| p.1).sum::<usize>();
    let low = paired(|p| p.low.triangles) + unpaired(&pairing.unpaired_low);
    let high = paired(|p| p.high.triangles) + unpaired(&pairing.unpaired_high);
    if (low, high) != (triangles, triangles) || pairing.pairs.iter().any(|p| p.key.is_empty()) {
        return Err(format!(
            "pairs over {low} and {high} triangles of {triangles}: {pairing:?}"
        ));
    }
    // Its own cage: accepted, its corners where they were.
    let corners = cage_corners(model, model).map_err(|e| format!("its own cage: {e}"))?;
    let moved = corners
        .iter()
        .zip(&model.soup.vertices)
        .map(|(c, p)| (*c - *p).length())
        .fold(0.0f32, f32::max);
    if moved.is_nan() || moved > 1e-4 {
        return Err(format!("its own cage moves a corner by {moved}"));
    }
    let sphere = bake_sphere();
    if sphere.model.soup.triangle_count() != triangles {
        match cage_corners(&sphere.model, model) {
            Ok(_) => return Err("a cage of other triangles is taken".into()),
            Err(e) if e.contains('\n') => return Err(format!("a refusal on two lines: {e}")),
            Err(_) => {}
        }
    }
    // Baked with a cage pushed out along the normals, and with its parts paired.
    let Some(frames) = bake_frames(model, TangentSource::MikkTSpace, false)
        .or_else(|| bake_frames(model, TangentSource::Tutorial, false))
    else {
        return Ok(());
    };
    let mut pushed = model.clone();
    let out = 0.05 * tutorial13::model::TUTORIAL_CYLINDER_RADIUS;
    for (p, n) in pushed.soup.vertices.iter_mut().zip(&model.soup.normals) {
        *p += n.normalize_or_zero() * out;
    }
    let settings = BakeSettings {
        width: 16,
        height: 16,
        samples: 2,
        margin: 2,
        threads: 1,
        ..BakeSettings::default()
    };
    if let Ok(cage) = cage_corners(&pushed, model) {
        if let Some(map) = bake_models_with(model, model, &frames, &settings, Some(&cage), None) {
            check_baked(&map, &model.soup, &frames, &settings)
                .map_err(|e| format!("caged: {e}"))?;
        }
    }
    if !pairing.pairs.is_empty() {
        let with = Some(&pairing);
        if let Some(map) = bake_models_with(model, model, &frames, &settings, None, with) {
            check_baked(&map, &model.soup, &frames, &settings)
                .map_err(|e| format!("paired: {e}"))?;
        }
    }
    Ok(())
}
