//! The `bake` target: the bake on the model targets' inputs, onto itself, a small UV sphere and
//! the sphere onto it; the model, sphere, frames and checks of a baked map that the `cage` target
//! shares.

use std::path::Path;

use glam::Vec3;

use tutorial13::bake::{bake_soups, BakeInput, BakeSettings, BakedMap, Bitangents, CornerFrames};
use tutorial13::bake::{Pairing, Space, TexelState};
use tutorial13::common::objloader::TriangleSoup;
use tutorial13::model::{load_model_bytes, MapOverrides, Model};
use tutorial13::pipeline::mikktspace::mikktspace_tangents_on;
use tutorial13::tangent_source::TangentSource;

use super::model::load_model_input;
use super::{message_kind, Outcome, Target};

/// The `bake` target's check (see [`Target::Bake`]).
pub(super) fn check(input: &[u8], _path: &Path) -> Result<Outcome, String> {
    match load_bake_model(input) {
        // The loaders' errors are the model and gltf targets' business.
        Err(e) => Ok(Outcome::Rejected(message_kind(&e.to_string()))),
        Ok(model) => check_bake(&model).map(|_| Outcome::Loaded),
    }
}

/// A `bake` input as a model: a binary glTF by its magic, glTF JSON by its opening brace, else an
/// OBJ with its MTL (as the `model` target's input), all read in memory.
pub(super) fn load_bake_model(input: &[u8]) -> tutorial13::Result<Model> {
    let json = input.iter().find(|b| !b.is_ascii_whitespace()) == Some(&b'{');
    if input.starts_with(b"glTF") || json {
        let nothing_beside = |_: &Path| Err(std::io::ErrorKind::NotFound.into());
        return load_model_bytes(
            input,
            Path::new("fuzz.gltf"),
            &MapOverrides::default(),
            nothing_beside,
        );
    }
    load_model_input(input, Path::new(Target::Bake.file_name()))
}

/// The `bake` target's fixed other model: a UV sphere of 8 segments and 4 rings (its UVs cover
/// the map; mirrored nowhere), with its MikkTSpace frames and its tutorial frames (normalized).
pub(super) struct BakeSphere {
    pub(super) model: Model,
    mikktspace: CornerFrames,
    tutorial: CornerFrames,
}

pub(super) fn bake_sphere() -> &'static BakeSphere {
    static SPHERE: std::sync::OnceLock<BakeSphere> = std::sync::OnceLock::new();
    SPHERE.get_or_init(|| {
        let text = tutorial13::assets::obj_text::sphere_obj_text(
            8,
            4,
            &tutorial13::assets::obj_text::round,
            false,
        );
        let nothing = |_: &Path| Err(std::io::ErrorKind::NotFound.into());
        let model = load_model_bytes(
            text.as_bytes(),
            Path::new("sphere.obj"),
            &MapOverrides::default(),
            nothing,
        )
        .expect("the sphere loads");
        let tangents = mikktspace_tangents_on(&model.soup, 1).expect("the sphere has tangents");
        BakeSphere {
            mikktspace: CornerFrames::mikktspace(&model.soup, &tangents),
            tutorial: CornerFrames::tutorial(&model.soup, true),
            model,
        }
    })
}

/// LOW's frames as `BakeFiles::load` computes them for `tangents` (MikkTSpace on one thread: the
/// same result on any number), or `None` where it refuses the model (or the frame).
pub(super) fn bake_frames(
    low: &Model,
    tangents: TangentSource,
    normalize: bool,
) -> Option<CornerFrames> {
    match tangents {
        TangentSource::MikkTSpace => mikktspace_tangents_on(&low.soup, 1)
            .ok()
            .map(|t| CornerFrames::mikktspace(&low.soup, &t)),
        TangentSource::File => {
            let file = low.file_tangents.as_ref()?;
            let all = file.complete(&low.soup).ok()?;
            Some(CornerFrames::mikktspace(&low.soup, &all))
        }
        TangentSource::Tutorial => Some(CornerFrames::tutorial(&low.soup, normalize)),
        // The per-pixel frame has no corner frames: the bake refuses it.
        TangentSource::Derivative => None,
    }
}

/// The `bake` target's check: `model` baked onto itself, onto the sphere and the sphere onto it.
fn check_bake(model: &Model) -> Result<(), String> {
    let sphere = bake_sphere();
    let mikktspace = bake_frames(model, TangentSource::MikkTSpace, false);
    let tutorial = bake_frames(model, TangentSource::Tutorial, false);
    let normalized = bake_frames(model, TangentSource::Tutorial, true);
    let file = bake_frames(model, TangentSource::File, false);
    // MikkTSpace refuses a mesh it cannot take (the program's bake then stops with its error).
    let mikktspace_or_tutorial = mikktspace.as_ref().or(tutorial.as_ref());
    let settings = |width, height, samples, space| BakeSettings {
        width,
        height,
        samples,
        margin: 2,
        space,
        threads: 1,
        ..BakeSettings::default()
    };
    let (tangent, object) = (Space::Tangent, Space::Object);
    let sphere_model = &sphere.model;
    let bakes: [(&str, &Model, &Model, Option<&CornerFrames>, BakeSettings); 7] = [
        (
            "itself, MikkTSpace",
            model,
            model,
            mikktspace.as_ref(),
            settings(16, 16, 1, tangent),
        ),
        (
            "itself, tutorial",
            model,
            model,
            tutorial.as_ref(),
            settings(32, 8, 2, tangent),
        ),
        (
            "itself, object space",
            model,
            model,
            mikktspace_or_tutorial,
            settings(16, 16, 2, object),
        ),
        (
            "onto the sphere, MikkTSpace",
            model,
            sphere_model,
            Some(&sphere.mikktspace),
            settings(16, 16, 2, tangent),
        ),
        (
            "onto the sphere, object space",
            model,
            sphere_model,
            Some(&sphere.tutorial),
            settings(32, 8, 1, object),
        ),
        (
            "the sphere onto it, file tangents",
            sphere_model,
            model,
            file.as_ref().or(mikktspace_or_tutorial),
            settings(16, 16, 2, tangent),
        ),
        (
            "the sphere onto it, tutorial normalized",
            sphere_model,
            model,
            normalized.as_ref(),
            settings(32, 8, 1, tangent),
        ),
    ];
    for (i, (what, high, low, frames, settings)) in bakes.into_iter().enumerate() {
        let Some(frames) = frames else { continue };
        let Some(map) = bake_models(high, low, frames, &settings) else {
            continue;
        };
        check_baked(&map, &low.soup, frames, &settings).map_err(|e| format!("{what}: {e}"))?;
        // Once, on two threads: the same map (bands are shared out as the threads ask).
        if i == 1 {
            let two = BakeSettings {
                threads: 2,
                ..settings.clone()
            };
            let again = bake_models(high, low, frames, &two).expect("the same distances");
            if again.normals != map.normals || again.states != map.states {
                return Err(format!("{what}: 2 threads bake another map than 1"));
            }
            if again.stats != map.stats {
                return Err(format!(
                    "{what}: 2 threads count {:?}, 1 thread {:?}",
                    again.stats, map.stats
                ));
            }
        }
    }
    Ok(())
}

/// `BakeFiles::load` and `BakeFiles::bake` on models already read: HIGH moved back to its file's
/// coordinates and placed as LOW is, the distances `tutorial13 bake`'s defaults (5 % of LOW's
/// radius, twice that) in LOW's file units scaled to its placed ones. `None` where the command
/// would refuse the distances.
fn bake_models(
    high: &Model,
    low: &Model,
    frames: &CornerFrames,
    settings: &BakeSettings,
) -> Option<BakedMap> {
    bake_models_with(high, low, frames, settings, None, None)
}

/// [`bake_models`] with a cage (its corners in LOW's placed space; the rays then unbounded, the
/// command's default with a cage) or parts paired by name.
pub(super) fn bake_models_with(
    high: &Model,
    low: &Model,
    frames: &CornerFrames,
    settings: &BakeSettings,
    cage: Option<&[Vec3]>,
    pairing: Option<&Pairing>,
) -> Option<BakedMap> {
    let mut high_soup = high.soup.clone();
    for p in &mut high_soup.vertices {
        *p = low.placement.to_world(high.placement.to_file(*p));
    }
    let extrusion = 0.05 * low.placement.radius;
    let max_distance = 2.0 * extrusion;
    let usable = |d: f32| d.is_finite() && d >= 0.0;
    if !(usable(extrusion) && usable(max_distance) && max_distance > 0.0) {
        return None;
    }
    let scale = low.placement.scale();
    let input = BakeInput {
        low: &low.soup,
        frames,
        high: &high_soup,
        high_face_normals: high.normals_computed,
        extrusion: extrusion * scale,
        max_distance: match cage {
            Some(_) => f32::INFINITY,
            None => max_distance * scale,
        },
        cage,
        pairing,
    };
    Some(bake_soups(&input, settings))
}

/// A baked map against what it must be (see [`Target::Bake`]).
pub(super) fn check_baked(
    map: &BakedMap,
    low: &TriangleSoup,
    frames: &CornerFrames,
    settings: &BakeSettings,
) -> Result<(), String> {
    let (w, h) = (settings.width as usize, settings.height as usize);
    let texels = w * h;
    if (map.width, map.height) != (settings.width, settings.height)
        || map.normals.len() != texels
        || map.states.len() != texels
    {
        return Err(format!(
            "a {}×{} map of {} normals and {} states for {w}×{h}",
            map.width,
            map.height,
            map.normals.len(),
            map.states.len()
        ));
    }
    for (i, (n, state)) in map.normals.iter().zip(&map.states).enumerate() {
        let right = match state {
            TexelState::Empty => *n == Vec3::Z,
            _ => n.is_finite() && (n.length() - 1.0).abs() <= 1e-3,
        };
        if !right {
            return Err(format!("texel {i} ({state:?}) holds {n}"));
        }
    }
    // The counts against a rasterization of LOW's UVs made here.
    let reference = ReferenceRaster::new(low, w, h, settings.samples.max(1) as usize);
    let stats = &map.stats;
    let count = |state: TexelState| map.states.iter().filter(|s| **s == state).count();
    let expected = (
        reference.rays,
        reference.covered(),
        reference.overlapping(),
        reference.flat,
    );
    let found = (
        stats.rays,
        stats.covered,
        stats.overlapping,
        stats.flat_uv_triangles,
    );
    if found != expected {
        return Err(format!(
            "rays, covered, overlapping, flat UV triangles {found:?}, rasterized {expected:?}"
        ));
    }
    if let Some(i) =
        (0..texels).find(|&i| (map.states[i] == TexelState::Covered) != (reference.samples[i] > 0))
    {
        return Err(format!(
            "texel {i} is {:?} with {} covered samples",
            map.states[i], reference.samples[i]
        ));
    }
    if count(TexelState::Covered) != stats.covered
        || count(TexelState::Margin) != stats.margin
        || stats.covered > texels
    {
        return Err(format!(
            "{} covered and {} margin texels counted {} and {}",
            count(TexelState::Covered),
            count(TexelState::Margin),
            stats.covered,
            stats.margin
        ));
    }
    if stats.missed > stats.rays
        || stats.missed_beyond > stats.missed
        || stats.missed_outside > stats.missed
        || stats.singular + stats.missed > stats.rays
    {
        return Err(format!("inconsistent ray counts: {stats:?}"));
    }
    // The margin: exactly the texels within `margin` rings (Chebyshev) of a covered one.
    let m = settings.margin as isize;
    for i in 0..texels {
        if map.states[i] == TexelState::Covered {
            continue;
        }
        let (x, y) = ((i % w) as isize, (i / w) as isize);
        let near = (-m..=m).any(|dy| {
            (-m..=m).any(|dx| {
                let (nx, ny) = (x + dx, y + dy);
                (0..w as isize).contains(&nx)
                    && (0..h as isize).contains(&ny)
                    && map.states[ny as usize * w + nx as usize] == TexelState::Covered
            })
        });
        if near != (map.states[i] == TexelState::Margin) {
            return Err(format!(
                "texel {i} is {:?} with a covered texel within {m}: {near}",
                map.states[i]
            ));
        }
    }
    // Skew: measured for the tutorial's frame in tangent space, over the covered texels.
    let measured = matches!(frames.bitangents, Bitangents::Given(_))
        && settings.space == Space::Tangent
        && stats.covered > 0;
    match (&stats.skew, measured) {
        (None, false) => {}
        (Some(skew), true)
            if skew.skewed <= stats.covered
                && skew.median >= 1.0 - 1e-3
                && skew.max >= skew.median =>
        {
            // (NaN fails the comparisons.)
        }
        (skew, _) => return Err(format!("skew {skew:?} for {} covered", stats.covered)),
    }
    Ok(())
}

/// LOW's UVs rasterized independently of `bake::texels`: each triangle against every sample of a
/// loose box around it (no bands, no clipping of its own), with the same mapping (V up, one unit
/// per sample) and the same rule for samples on an edge (GL's top-left).
struct ReferenceRaster {
    /// Covered samples per texel.
    samples: Vec<usize>,
    /// Whether a sample of the texel is claimed by two triangles.
    overlaps: Vec<bool>,
    rays: usize,
    /// Triangles with no (finite) area in UV space.
    flat: usize,
}

impl ReferenceRaster {
    fn new(soup: &TriangleSoup, w: usize, h: usize, k: usize) -> ReferenceRaster {
        let (columns, rows) = (w * k, h * k);
        let scale = glam::DVec2::new(columns as f64, rows as f64);
        let mut claims = vec![0u32; columns * rows];
        let mut flat = 0;
        for uv in soup.uvs.chunks_exact(3) {
            let at = |i: usize| glam::DVec2::new(uv[i].x as f64, 1.0 - uv[i].y as f64) * scale;
            let (a, mut b, mut c) = (at(0), at(1), at(2));
            let area = (b - a).perp_dot(c - a);
            if area == 0.0 || !area.is_finite() {
                flat += 1;
                continue;
            }
            if area < 0.0 {
                std::mem::swap(&mut b, &mut c);
            }
            let (low, high) = (a.min(b).min(c), a.max(b).max(c));
            // A point outside the corners' box is outside, whatever the edge functions say: on a
            // triangle with corners 1e40 away they cancel to noise (fuzz/regressions/cage/).
            let inside = |p: glam::DVec2| {
                let boxed = p.cmpge(low).all() && p.cmple(high).all();
                boxed
                    && [(b, c), (c, a), (a, b)].iter().all(|&(from, to)| {
                        let edge = to - from;
                        let w = edge.perp_dot(p - from);
                        let owns_edge = edge.y > 0.0 || (edge.y == 0.0 && edge.x < 0.0);
                        w > 0.0 || (w == 0.0 && owns_edge)
                    })
            };
            let span = |l: f64, h: f64, size: usize| {
                let start = (l - 1.0).floor().clamp(0.0, size as f64) as usize;
                let end = (h + 1.0).ceil().clamp(0.0, size as f64) as usize;
                start..end
            };
            for sy in span(low.y, high.y, rows) {
                for sx in span(low.x, high.x, columns) {
                    if inside(glam::DVec2::new(sx as f64 + 0.5, sy as f64 + 0.5)) {
                        claims[sy * columns + sx] += 1;
                    }
                }
            }
        }
        let mut samples = vec![0; w * h];
        let mut overlaps = vec![false; w * h];
        for (at, &c) in claims.iter().enumerate() {
            let texel = (at / columns / k) * w + (at % columns) / k;
            samples[texel] += usize::from(c > 0);
            overlaps[texel] |= c > 1;
        }
        ReferenceRaster {
            rays: samples.iter().sum(),
            samples,
            overlaps,
            flat,
        }
    }

    fn covered(&self) -> usize {
        self.samples.iter().filter(|&&s| s > 0).count()
    }

    fn overlapping(&self) -> usize {
        self.overlaps.iter().filter(|&&o| o).count()
    }
}
