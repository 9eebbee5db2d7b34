//! A stable-toolchain fuzz harness for the readers and the CPU pipeline (no libFuzzer, no nightly).
//!
//! Shared by `fuzz/main.rs` (the long runs) and `tests/all/fuzz.rs` (regression replay and a short
//! seeded run inside `cargo test`). Each case runs in-process under `catch_unwind`: a panic, a
//! broken invariant or a case slower than the limit is a failure, and the input is saved to
//! `fuzz/regressions/<target>/`. Inputs come from a seed corpus (`fuzz/corpus/<target>/`) through a
//! seeded mutator: byte flips, splices and truncations for every target, plus OBJ-aware edits
//! (extreme indices, `l`/`p` lines, NaN/inf/1e38 numbers) and header-field edits for DDS and BMP.
//! There is no coverage feedback; a mutant joins the pool when it loads, or when it fails to load
//! with an error message of a kind not seen before.

#![allow(dead_code)] // each including crate uses a different part

use std::collections::HashSet;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use glam::Vec3;

use tutorial13::bake::cage::cage_corners;
use tutorial13::bake::{bake_soups, BakeInput, BakeSettings, BakedMap, Bitangents, CornerFrames};
use tutorial13::bake::{Pairing, Space, Tangents, TexelState};
use tutorial13::common::objloader::TriangleSoup;
use tutorial13::common::tangentspace::{compute_tangent_basis, TangentOptions};
use tutorial13::common::texture::{dxt_level_size, read_bmp_bytes, read_dds_bytes};
use tutorial13::common::vboindexer::{self, IndexOptions, IndexedMesh};
use tutorial13::mesh::MeshOptions;
use tutorial13::model::parts::part_names;
use tutorial13::model::{load_model_bytes, load_shape_bytes, MapOverrides, Model};
use tutorial13::normalmap::{decode_image, normal_map, HeightMap, Kernel, NormalMapOptions};
use tutorial13::photo::{height_from_photo, Photo};
use tutorial13::photometric::{parse_intensities_file, parse_lights_file};
use tutorial13::photometric::{recover, PhotometricOptions};
use tutorial13::pipeline::indexer::index_vbo_tbn_hashed;
use tutorial13::pipeline::mikktspace::mikktspace_tangents_on;
use tutorial13::pipeline::obj_parse::load_obj_bytes_threaded;

use crate::differential::{differ_from_tobj, shape_differs_from_rewrite};
use crate::mikktspace_reference::{first_difference, reference_can_take, reference_tangents};

/// What is fuzzed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Target {
    /// `load_obj_bytes_threaded`: an error naming the file, or a finite triangle soup.
    Obj,
    /// `read_dds_bytes`: an error naming the file, or levels of exactly the tutorial's sizes.
    Dds,
    /// `read_bmp_bytes`: an error naming the file, or `width × height` BGR triples.
    Bmp,
    /// OBJ text through tangents and indexing, under every switch setting: finite outputs, indices
    /// in range, and the grid indexer equal to the linear reference on small meshes.
    Pipeline,
    /// `HeightMap::from_bytes` then `normal_map` with every kernel: an error naming the file, or
    /// one texel per height texel, each a normal facing out of the surface (blue ≥ 128).
    Heightmap,
    /// `model::load_model_bytes` on an OBJ and its `.mtl` (one input: the OBJ, then a line
    /// [`MTL_SEPARATOR`], then the MTL text): an error naming the OBJ, or a soup as `load_obj`'s
    /// (computed normals of unit length), every vertex on the tutorial's cylinder's bounding sphere
    /// or inside it, and material ranges covering every triangle once, each naming a material. The
    /// same OBJ read as a bake's HIGH (`model::load_shape_bytes`: a file none of whose corners names
    /// a UV read in one pass) gives what the rewrite it replaced gave (`shape_differs_from_rewrite`),
    /// and a model as above.
    Model,
    /// A photo (any format the `image` crate reads here, JPEG included) through `Photo::from_image`,
    /// `height_from_photo` and `photometric::recover` (three copies under three lights, albedo on):
    /// an error naming the file, or one height, normal and albedo per texel, heights finite.
    Photo,
    /// A capture's light-directions and light-intensities text (`photometric --lights`,
    /// `--intensities`), the same input through both parsers: an error naming the file on one line,
    /// or one finite, nonzero direction (and one finite brightness above zero per channel) per line.
    Lights,
    /// The project's OBJ reader against tobj's parse (an input as the model target's: the OBJ, then
    /// the MTL every `mtllib` reads), in its three modes, in one piece and cut into several: the same
    /// soup to the bit, the same materials, or the same error (`differ_from_tobj`).
    ObjTobj,
    /// `model::load_model_bytes` on a glTF (JSON or binary; a file it names beside it is never
    /// there): an error naming the file on one line, or a model as the `model` target's, with
    /// file tangents (if any) one per corner, unit, w = ±1.
    Gltf,
    /// The program's MikkTSpace (`pipeline::mikktspace`) on a soup made from the bytes
    /// ([`mikktspace_soup`]: few values, so corners weld, triangles degenerate, zeros of both signs):
    /// the `mikktspace` crate's tangents to the bit, the same on 1 and 3 threads; where every
    /// triangle is degenerate (which the crate cannot take), the fallback frame everywhere.
    Mikktspace,
    /// The bake (`bake::bake_soups`, as `tutorial13 bake` runs it) on the model targets' inputs (an
    /// OBJ with its MTL as the `model` target's, or a glTF as the `gltf` target's, told apart by
    /// their first bytes): a model that loads is baked onto itself, onto a small UV sphere, and the
    /// sphere onto it, in every frame and both spaces, 16×16 and 32×8 texels, 1 and 2 samples,
    /// margin 2 ([`check_bake`]). No panic; every texel's normal finite and unit (exactly +Z where
    /// nothing covers it); the counts equal a rasterization of LOW's UVs made here; the margin
    /// exactly the rings around the covered texels; 1 and 2 threads the same map.
    Bake,
    /// The bake's readers of a cage and of part names on the bake target's inputs
    /// ([`check_cage`]): the model's part names read (`model::parts::part_names`: the OBJ's `o`
    /// and `g` lines counted as the reader counts faces, a glTF's nodes), one per triangle, for
    /// every file the reader takes; the model paired with itself by name, every triangle in one
    /// pair or said unpaired; the model taken as its own cage (`bake::cage::cage_corners`) with its
    /// corners back where they were, and the sphere refused as its cage on one line; the model
    /// baked with a cage (its corners pushed out along their normals, no bound on the rays) and
    /// with its parts paired, the maps as the `bake` target's.
    Cage,
}

/// Where a `model` input's MTL text starts (the OBJ's `mtllib` should name `fuzz.mtl`).
pub const MTL_SEPARATOR: &str = "#--- fuzz.mtl ---\n";

pub const TARGETS: [Target; 13] = [
    Target::Obj,
    Target::Dds,
    Target::Bmp,
    Target::Pipeline,
    Target::Heightmap,
    Target::Model,
    Target::Photo,
    Target::ObjTobj,
    Target::Lights,
    Target::Gltf,
    Target::Mikktspace,
    Target::Bake,
    Target::Cage,
];

/// Meshes up to this many corners are also indexed by the quadratic reference.
const LINEAR_REFERENCE_MAX_CORNERS: usize = 3000;
/// Inputs are cut to this size after mutation, so that a case stays quick.
const MAX_INPUT: usize = 256 * 1024;

impl Target {
    pub fn name(self) -> &'static str {
        match self {
            Target::Obj => "obj",
            Target::Dds => "dds",
            Target::Bmp => "bmp",
            Target::Pipeline => "pipeline",
            Target::Heightmap => "heightmap",
            Target::Model => "model",
            Target::Photo => "photo",
            Target::ObjTobj => "obj-tobj",
            Target::Lights => "lights",
            Target::Gltf => "gltf",
            Target::Mikktspace => "mikktspace",
            Target::Bake => "bake",
            Target::Cage => "cage",
        }
    }

    pub fn from_name(name: &str) -> Option<Target> {
        TARGETS.into_iter().find(|t| t.name() == name)
    }

    fn file_name(self) -> &'static str {
        match self {
            Target::Obj | Target::Pipeline | Target::ObjTobj => "fuzz.obj",
            Target::Dds => "fuzz.DDS",
            Target::Bmp => "fuzz.bmp",
            Target::Heightmap => "fuzz-height.png",
            Target::Model | Target::Bake | Target::Cage => "fuzz-model.obj",
            Target::Photo => "fuzz-photo.jpg",
            Target::Lights => "fuzz-lights.txt",
            Target::Gltf => "fuzz.gltf",
            Target::Mikktspace => "fuzz.mesh",
        }
    }

    fn is_text(self) -> bool {
        matches!(
            self,
            Target::Obj
                | Target::Pipeline
                | Target::Model
                | Target::ObjTobj
                | Target::Lights
                | Target::Bake
                | Target::Cage
        )
    }
}

/// The repository's `fuzz/` folder: the manifest's own folder when this file is built into the
/// fuzz runner (package `tutorial13-fuzz`, whose manifest is there), its `fuzz/` when it is built
/// into the tests (the root package). Found by the corpus, so that neither build misses the seeds.
pub fn fuzz_dir() -> PathBuf {
    let manifest = Path::new(env!("CARGO_MANIFEST_DIR"));
    match manifest.join("corpus").is_dir() {
        true => manifest.to_path_buf(),
        false => manifest.join("fuzz"),
    }
}

pub fn corpus_dir(target: Target) -> PathBuf {
    // The pipeline reads OBJ text: it shares the OBJ seeds.
    let name = if target == Target::Pipeline {
        "obj"
    } else {
        target.name()
    };
    fuzz_dir().join("corpus").join(name)
}

/// Where `target`'s seeds are: its corpus, and for `obj-tobj` the OBJ and model targets'.
pub fn seed_dirs(target: Target) -> Vec<PathBuf> {
    match target {
        // Every OBJ the other targets keep, their saved failures too.
        Target::ObjTobj => vec![
            corpus_dir(Target::Obj),
            corpus_dir(Target::Model),
            regressions_dir(Target::Model),
            regressions_dir(Target::Pipeline),
        ],
        // The models the model targets read, their saved failures too (and for the cage, models
        // of named parts).
        Target::Bake | Target::Cage => vec![
            corpus_dir(Target::Cage),
            corpus_dir(Target::Model),
            corpus_dir(Target::Obj),
            corpus_dir(Target::Gltf),
            regressions_dir(Target::Model),
            regressions_dir(Target::Gltf),
            regressions_dir(Target::Pipeline),
        ],
        _ => vec![corpus_dir(target)],
    }
}

pub fn regressions_dir(target: Target) -> PathBuf {
    fuzz_dir().join("regressions").join(target.name())
}

/// Every file of `dir` (sorted by name), or nothing if it does not exist.
pub fn read_dir_files(dir: &Path) -> Vec<(PathBuf, Vec<u8>)> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    let mut paths: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.is_file())
        .collect();
    paths.sort();
    paths
        .into_iter()
        .filter_map(|p| std::fs::read(&p).ok().map(|b| (p, b)))
        .collect()
}

/// How one case went.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Outcome {
    /// The input loaded (and, for the pipeline, went through every stage).
    Loaded,
    /// The reader refused it; the message's kind (digits and quoted text dropped) for the pool.
    Rejected(String),
    /// A panic, a broken invariant or a case slower than the limit.
    Failed(String),
}

/// Runs `target` on `input` once, catching panics. `slow` is the time limit for one case.
pub fn run_case(target: Target, input: &[u8], slow: Duration) -> Outcome {
    let start = Instant::now();
    let result = catch_unwind(AssertUnwindSafe(|| check(target, input)));
    let elapsed = start.elapsed();
    match result {
        Err(panic) => {
            let message = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "(non-string panic)".into());
            Outcome::Failed(format!("panic: {message}"))
        }
        Ok(Err(broken)) => Outcome::Failed(broken),
        Ok(Ok(_)) if elapsed > slow => Outcome::Failed(format!(
            "slow: {:.2} s for {} bytes",
            elapsed.as_secs_f64(),
            input.len()
        )),
        Ok(Ok(outcome)) => outcome,
    }
}

/// The invariants of one target. `Err` is a broken invariant.
fn check(target: Target, input: &[u8]) -> Result<Outcome, String> {
    let path = Path::new(target.file_name());
    let rejected = |e: tutorial13::Error| -> Result<Outcome, String> {
        let message = e.to_string();
        let prefix = format!("{}: ", path.display());
        if !message.starts_with(&prefix) || message.contains('\n') {
            return Err(format!(
                "error does not name the file on one line: {message}"
            ));
        }
        Ok(Outcome::Rejected(message_kind(&message)))
    };
    match target {
        Target::Obj => match load_obj_bytes_threaded(input, path) {
            Err(e) => rejected(e),
            Ok(soup) => check_soup(&soup).map(|_| Outcome::Loaded),
        },
        Target::Pipeline => match load_obj_bytes_threaded(input, path) {
            Err(e) => rejected(e),
            Ok(soup) => {
                check_soup(&soup)?;
                check_pipeline(&soup)?;
                Ok(Outcome::Loaded)
            }
        },
        Target::Dds => match read_dds_bytes(input, path) {
            Err(e) => rejected(e),
            Ok(dds) => {
                let (mut w, mut h) = (dds.width, dds.height);
                if dds.levels.is_empty() || w == 0 || h == 0 {
                    return Err(format!("DDS loaded with no level or size {w}x{h}"));
                }
                for (i, level) in dds.levels.iter().enumerate() {
                    let size = dxt_level_size(dds.format, w, h);
                    if (level.width, level.height, level.data.len()) != (w, h, size) {
                        return Err(format!(
                            "DDS level {i} is {}x{} with {} bytes, expected {w}x{h} with {size}",
                            level.width,
                            level.height,
                            level.data.len()
                        ));
                    }
                    w = (w / 2).max(1);
                    h = (h / 2).max(1);
                }
                Ok(Outcome::Loaded)
            }
        },
        Target::Heightmap => match HeightMap::from_bytes(input, path) {
            Err(e) => rejected(e),
            Ok(heights) => {
                let texels = heights.width as usize * heights.height as usize;
                if texels == 0 || heights.values.len() != texels {
                    return Err(format!(
                        "height map loaded as {}x{} with {} values",
                        heights.width,
                        heights.height,
                        heights.values.len()
                    ));
                }
                for kernel in [Kernel::Sobel, Kernel::Scharr, Kernel::Central] {
                    let options = NormalMapOptions {
                        kernel,
                        strength: 50.0,
                        ..Default::default()
                    };
                    let normals = normal_map(&heights, options);
                    if normals.len() != texels {
                        return Err(format!("{} normals for {texels} texels", normals.len()));
                    }
                    if let Some(t) = normals.iter().find(|t| t[2] < 128) {
                        return Err(format!(
                            "{kernel:?}: a normal facing into the surface: {t:?}"
                        ));
                    }
                }
                Ok(Outcome::Loaded)
            }
        },
        Target::ObjTobj => {
            let (obj, mtl) = split_model_input(input);
            differ_from_tobj(&obj, &mtl)?;
            match load_obj_bytes_threaded(&obj, path) {
                Err(e) => rejected(e),
                Ok(_) => Ok(Outcome::Loaded),
            }
        }
        Target::Model => {
            let (obj, mtl) = split_model_input(input);
            let read_mtl = |p: &Path| {
                if p.file_name() == Some("fuzz.mtl".as_ref()) {
                    Ok(mtl.clone())
                } else {
                    Err(std::io::Error::from(std::io::ErrorKind::NotFound))
                }
            };
            // Read as a bake's HIGH too (a sculpt without UVs is taken in one pass): as the
            // rewrite it replaced read it.
            if let Ok(shape) = shape_differs_from_rewrite(&obj, path, read_mtl)? {
                check_model(&shape)?;
            }
            match load_model_bytes(&obj, path, &MapOverrides::default(), read_mtl) {
                Err(e) => rejected(e),
                Ok(model) => check_model(&model).map(|_| Outcome::Loaded),
            }
        }
        Target::Lights => {
            let Ok(text) = std::str::from_utf8(input) else {
                return Ok(Outcome::Rejected("not UTF-8".into()));
            };
            let lights = parse_lights_file(text, path)
                .map(|lights| lights.iter().all(|l| l.is_finite() && *l != Vec3::ZERO));
            let intensities = parse_intensities_file(text, path)
                .map(|rgb| rgb.iter().flatten().all(|c| c.is_finite() && *c > 0.0));
            let mut outcome = Outcome::Loaded;
            for (what, parsed) in [("direction", lights), ("intensity", intensities)] {
                match parsed {
                    Ok(true) => {}
                    Ok(false) => return Err(format!("a {what} accepted that is not one")),
                    Err(e) => outcome = rejected(e)?,
                }
            }
            Ok(outcome)
        }
        Target::Gltf => {
            let nothing_beside = |_: &Path| Err(std::io::ErrorKind::NotFound.into());
            // Read for its shape too (a bake's HIGH: a primitive without UVs is taken).
            if let Ok(shape) = load_shape_bytes(input, path, nothing_beside) {
                check_model(&shape)?;
            }
            match load_model_bytes(input, path, &MapOverrides::default(), nothing_beside) {
                Err(e) => rejected(e),
                Ok(model) => {
                    check_model(&model)?;
                    check_file_tangents(&model).map(|_| Outcome::Loaded)
                }
            }
        }
        Target::Mikktspace => check_mikktspace(input),
        Target::Bake => match load_bake_model(input) {
            // The loaders' errors are the model and gltf targets' business.
            Err(e) => Ok(Outcome::Rejected(message_kind(&e.to_string()))),
            Ok(model) => check_bake(&model).map(|_| Outcome::Loaded),
        },
        Target::Cage => match load_bake_model(input) {
            Err(e) => Ok(Outcome::Rejected(message_kind(&e.to_string()))),
            Ok(model) => check_cage(&model, input).map(|_| Outcome::Loaded),
        },
        Target::Photo => match check_photo_bytes(input, path) {
            None => Ok(Outcome::Rejected("larger than the harness decodes".into())),
            Some(Err(e)) => rejected(e),
            Some(Ok(photo)) => check_photo(photo).map(|_| Outcome::Loaded),
        },
        Target::Bmp => match read_bmp_bytes(input, path) {
            Err(e) => rejected(e),
            Ok(bmp) => {
                let expected = bmp.width as usize * bmp.height as usize * 3;
                if bmp.width == 0 || bmp.height == 0 || bmp.bgr.len() != expected {
                    return Err(format!(
                        "BMP loaded as {}x{} with {} bytes",
                        bmp.width,
                        bmp.height,
                        bmp.bgr.len()
                    ));
                }
                Ok(Outcome::Loaded)
            }
        },
    }
}

/// A model input split into the OBJ and the MTL its `mtllib fuzz.mtl` reads.
fn split_model_input(input: &[u8]) -> (Vec<u8>, Vec<u8>) {
    let text = String::from_utf8_lossy(input);
    match text.split_once(MTL_SEPARATOR) {
        Some((obj, mtl)) => (obj.as_bytes().to_vec(), mtl.as_bytes().to_vec()),
        None => (input.to_vec(), Vec::new()),
    }
}

/// What `load_model` promises beyond a soup.
fn check_model(model: &Model) -> Result<(), String> {
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

/// A `mikktspace` input's triangles are cut to this many: the crate's search for degenerate
/// triangles' corners takes time quadratic in the mesh.
const MIKKTSPACE_MAX_TRIANGLES: usize = 2000;

/// A `mikktspace` input as a soup: its first 16 bytes are 16 values (byte b is `b as i8` / 16, and
/// 0x80 is −0), then 3 bytes make a corner, each choosing values by its nibbles: the position
/// (low, high, and bits 2–5), the normal (low, high, bits 1–4; not unit, which MikkTSpace allows)
/// and the UV (low, high).
pub fn mikktspace_soup(input: &[u8]) -> TriangleSoup {
    let value = |k: usize| match input.get(k).copied().unwrap_or(0) {
        0x80 => -0.0,
        b => (b as i8) as f32 / 16.0,
    };
    let v: Vec<f32> = (0..16).map(value).collect();
    let pick = |b: u8, shift: u32| v[(b >> shift) as usize & 15];
    let mut soup = TriangleSoup::default();
    let corners = input.get(16..).unwrap_or(&[]).chunks_exact(3);
    let count = (corners.len() / 3).min(MIKKTSPACE_MAX_TRIANGLES) * 3;
    for c in corners.take(count) {
        let (p, n, uv) = (c[0], c[1], c[2]);
        soup.vertices
            .push(Vec3::new(pick(p, 0), pick(p, 4), pick(p, 2)));
        soup.normals
            .push(Vec3::new(pick(n, 0), pick(n, 4), pick(n, 1)));
        soup.uvs.push(glam::Vec2::new(pick(uv, 0), pick(uv, 4)));
    }
    soup
}

/// The `mikktspace` target's check (see [`Target::Mikktspace`]).
fn check_mikktspace(input: &[u8]) -> Result<Outcome, String> {
    let soup = mikktspace_soup(input);
    if soup.vertices.is_empty() {
        return Ok(Outcome::Rejected("no triangle".into()));
    }
    let ours = mikktspace_tangents_on(&soup, 1).map_err(|e| format!("refused: {e}"))?;
    let threads = mikktspace_tangents_on(&soup, 3).map_err(|e| format!("refused: {e}"))?;
    if let Some(difference) = first_difference(&threads, &ours) {
        return Err(format!("3 threads against 1: {difference}"));
    }
    if reference_can_take(&soup) {
        let reference = reference_tangents(&soup).ok_or("the crate refused the mesh")?;
        if let Some(difference) = first_difference(&ours, &reference) {
            return Err(format!("against the crate: {difference}"));
        }
    } else if let Some(t) = ours.iter().find(|t| **t != [1.0, 0.0, 0.0, -1.0]) {
        return Err(format!("every triangle degenerate, yet a tangent {t:?}"));
    }
    Ok(Outcome::Loaded)
}

/// Photos that declare more texels than this are not decoded: a few hundred bytes of JPEG can
/// declare 46 million (seconds and a gigabyte per case, the decoder's time, not the tools'), and the
/// mutants of such a file would fill the pool. The tools' code is the same at any size.
const MAX_PHOTO_TEXELS: u64 = 1 << 16;

/// The photo target: `input`'s declared size first, then decoding and the photo tools.
fn check_photo_bytes(input: &[u8], path: &Path) -> Option<Result<Photo, tutorial13::Error>> {
    let reader = image::ImageReader::new(std::io::Cursor::new(input)).with_guessed_format();
    if let Ok((w, h)) = reader
        .map_err(drop)
        .and_then(|r| r.into_dimensions().map_err(drop))
    {
        if u64::from(w) * u64::from(h) > MAX_PHOTO_TEXELS {
            return None;
        }
    }
    Some(decode_image(input, path, "a photo").map(Photo::from_image))
}

/// The photo tools' promises: one height (finite), normal and albedo texel per texel.
fn check_photo(photo: Photo) -> Result<(), String> {
    let texels = photo.width as usize * photo.height as usize;
    let heights = height_from_photo(&photo, 2);
    if heights.values.len() != texels || !heights.values.iter().all(|h| h.is_finite()) {
        return Err(format!(
            "{} heights (finite: {}) for {texels} texels",
            heights.values.len(),
            heights.values.iter().all(|h| h.is_finite())
        ));
    }
    let lights = [(1.0, 0.0, 1.0), (-0.5, 0.8, 1.0), (-0.5, -0.8, 1.0)].map(Vec3::from);
    let options = PhotometricOptions {
        albedo: true,
        ..Default::default()
    };
    let photos = [photo.clone(), photo.clone(), photo];
    let recovered = recover(&photos, &lights, &options).map_err(|e| e.to_string())?;
    let albedo = recovered.albedo.as_ref().map_or(0, Vec::len);
    if recovered.normals.len() != texels || albedo != texels || recovered.unsolved > texels {
        return Err(format!(
            "{} normals, {albedo} albedo texels, {} unsolved for {texels} texels",
            recovered.normals.len(),
            recovered.unsolved
        ));
    }
    Ok(())
}

// -------------------------------------------------------------------------------------------------
// The bake

/// A `bake` input as a model: a binary glTF by its magic, glTF JSON by its opening brace, else an
/// OBJ with its MTL (as the `model` target's input), all read in memory.
fn load_bake_model(input: &[u8]) -> tutorial13::Result<Model> {
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
    let (obj, mtl) = split_model_input(input);
    let read_mtl = |p: &Path| {
        if p.file_name() == Some("fuzz.mtl".as_ref()) {
            Ok(mtl.clone())
        } else {
            Err(std::io::Error::from(std::io::ErrorKind::NotFound))
        }
    };
    load_model_bytes(
        &obj,
        Path::new(Target::Bake.file_name()),
        &MapOverrides::default(),
        read_mtl,
    )
}

/// The `bake` target's fixed other model: a UV sphere of 8 segments and 4 rings (its UVs cover
/// the map; mirrored nowhere), with its MikkTSpace frames and its tutorial frames (normalized).
struct BakeSphere {
    model: Model,
    mikktspace: CornerFrames,
    tutorial: CornerFrames,
}

fn bake_sphere() -> &'static BakeSphere {
    static SPHERE: std::sync::OnceLock<BakeSphere> = std::sync::OnceLock::new();
    SPHERE.get_or_init(|| {
        let text = tutorial13::mesh::sphere_obj_text(8, 4, &tutorial13::mesh::round, false);
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
/// same result on any number), or `None` where it refuses the model.
fn bake_frames(low: &Model, tangents: Tangents, normalize: bool) -> Option<CornerFrames> {
    match tangents {
        Tangents::MikkTSpace => mikktspace_tangents_on(&low.soup, 1)
            .ok()
            .map(|t| CornerFrames::mikktspace(&low.soup, &t)),
        Tangents::File => {
            let file = low.file_tangents.as_ref()?;
            let all = file.complete(&low.soup).ok()?;
            Some(CornerFrames::mikktspace(&low.soup, &all))
        }
        Tangents::Tutorial => Some(CornerFrames::tutorial(&low.soup, normalize)),
    }
}

/// The `bake` target's check: `model` baked onto itself, onto the sphere and the sphere onto it.
fn check_bake(model: &Model) -> Result<(), String> {
    let sphere = bake_sphere();
    let mikktspace = bake_frames(model, Tangents::MikkTSpace, false);
    let tutorial = bake_frames(model, Tangents::Tutorial, false);
    let normalized = bake_frames(model, Tangents::Tutorial, true);
    let file = bake_frames(model, Tangents::File, false);
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
fn bake_models_with(
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

/// The `cage` target's check (see [`Target::Cage`]); `input` is the model's file as read.
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
    let Some(frames) = bake_frames(model, Tangents::MikkTSpace, false)
        .or_else(|| bake_frames(model, Tangents::Tutorial, false))
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

/// A baked map against what it must be (see [`Target::Bake`]).
fn check_baked(
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

/// What `load_obj` promises: three corners per triangle, every number finite.
fn check_soup(soup: &TriangleSoup) -> Result<(), String> {
    let n = soup.vertices.len();
    if n == 0 || n % 3 != 0 || soup.uvs.len() != n || soup.normals.len() != n {
        return Err(format!(
            "soup of {n} positions, {} UVs, {} normals",
            soup.uvs.len(),
            soup.normals.len()
        ));
    }
    let finite = soup.vertices.iter().all(|v| v.is_finite())
        && soup.uvs.iter().all(|v| v.is_finite())
        && soup.normals.iter().all(|v| v.is_finite());
    if !finite {
        return Err("soup holds a non-finite number".into());
    }
    Ok(())
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

/// An error message without its numbers and quoted parts: "what kind of rejection".
fn message_kind(message: &str) -> String {
    let mut kind = String::new();
    let mut quoted = false;
    for c in message.chars() {
        if c == '\'' || c == '"' {
            quoted = !quoted;
        } else if !quoted && !c.is_ascii_digit() {
            kind.push(c);
        }
    }
    kind
}

// -------------------------------------------------------------------------------------------------
// Randomness and mutation

/// SplitMix64: tiny, seedable, good enough to pick mutations.
#[derive(Debug, Clone)]
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng(seed)
    }

    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `0..n` (n > 0; the tiny modulo bias does not matter here).
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }

    pub fn chance(&mut self, one_in: usize) -> bool {
        self.below(one_in) == 0
    }

    fn pick<'a, T>(&mut self, items: &'a [T]) -> &'a T {
        &items[self.below(items.len())]
    }
}

/// Numbers that have broken parsers and float code before: index extremes, non-finite and
/// near-overflow floats, the 0.01 tolerance.
const NUMBERS: &[&str] = &[
    "0",
    "1",
    "-1",
    "2",
    "-2",
    "3",
    "-3",
    "7",
    "-9223372036854775808",
    "9223372036854775807",
    "-9223372036854775807",
    "-9223372036854775809",
    "18446744073709551616",
    "4294967296",
    "4294967297",
    "-4294967296",
    "2147483648",
    "65536",
    "65535",
    "nan",
    "NaN",
    "-nan",
    "inf",
    "-inf",
    "infinity",
    "1e38",
    "-1e38",
    "3.4e38",
    "3.4028235e38",
    "-3.4028235e38",
    "1.7e38",
    "-1.7e38",
    "1e39",
    "1e30",
    "1e20",
    "1e-45",
    "1e-38",
    "-0",
    "0.01",
    "0.0099",
    "0.0101",
    "0.005",
    "1e-30",
    "0x10",
    "+1",
    "1.",
    ".5",
];

/// Whole lines worth inserting into OBJ text.
const LINES: &[&str] = &[
    "l 1 2 3",
    "l 1/-3/1 1/1/1 1/1/1",
    "l 1 2",
    "l",
    "p 1",
    "p 1 2 3",
    "f 1/1/1 1/1/1 1/1/1",
    "f -1/-1/-1 -2/-2/-1 -3/-3/-1",
    "f 1//1 2//1 3//1",
    "f 1/1/1 2/2/1",
    "f 1/1/1 2/2/1 3/3/1 4/4/1 5/5/1",
    "f 1/1 2/2 3/3",
    "f",
    "v 1e38 1e38 1e38",
    "v 3.4e38 -3.4e38 0",
    "v -3.4e38 3.4e38 3.4e38",
    "v 0 0 0",
    "v 1 2 3 0",
    "v 1 2 3 1e-40",
    "v 1 2 3 0.5 0.5 0.5",
    "v 1 2",
    "vt 0 0",
    "vt 0.005 0",
    "vt 1e-30 0",
    "vt 0 0 0",
    "vn 0 0 1",
    "vn 0 0 0",
    "vn 1e38 1e38 1e38",
    "o x",
    "o",
    "g group",
    "g",
    "s off",
    "s 1",
    "usemtl m",
    "mtllib m.mtl",
    "# comment",
    "\\",
    "",
];

/// Offsets of header fields: DDS (size, flags, height, width, pitch, depth, mipmap count, pixel
/// format size/flags/FourCC/bits, caps, the DX10 header) and BMP (file size, data offset, DIB size,
/// width, height, planes, bits per pixel, compression, image size).
const DDS_FIELDS: &[usize] = &[4, 8, 12, 16, 20, 24, 28, 76, 80, 84, 88, 108, 112, 128, 132];
const BMP_FIELDS: &[usize] = &[2, 10, 14, 18, 22, 26, 28, 30, 34];
const U32S: &[u32] = &[
    0,
    1,
    2,
    3,
    4,
    5,
    8,
    15,
    16,
    17,
    31,
    32,
    124,
    0x7FFF_FFFF,
    0x8000_0000,
    0xFFFF_FFFF,
    0xFFFF_FFFE,
    0xFFFF,
    0x1_0000,
    16384,
    16385,
    24,
    40,
    54,
    0x3154_5844,
    0x3354_5844,
    0x3554_5844,
    0x3031_5844,
];

/// One random input derived from `base` (and maybe a second pool entry for splices).
pub fn mutate(target: Target, rng: &mut Rng, base: &[u8], pool: &[Vec<u8>]) -> Vec<u8> {
    let mut data = base.to_vec();
    let rounds = 1 + rng.below(4);
    for _ in 0..rounds {
        let text_op = target.is_text() && rng.below(3) != 0;
        if text_op {
            mutate_text(rng, &mut data);
        } else if !target.is_text() && rng.chance(2) {
            mutate_header(target, rng, &mut data);
        } else {
            mutate_bytes(rng, &mut data, pool);
        }
    }
    data.truncate(MAX_INPUT);
    data
}

fn mutate_bytes(rng: &mut Rng, data: &mut Vec<u8>, pool: &[Vec<u8>]) {
    let len = data.len();
    match rng.below(8) {
        0 if len > 0 => {
            let i = rng.below(len);
            data[i] ^= 1 << rng.below(8);
        }
        1 if len > 0 => {
            let i = rng.below(len);
            data[i] = *rng.pick(&[0u8, 0xFF, 0x7F, 0x80, 1, b'\n', b'/', b'-', b' ', b'9']);
        }
        2 if len > 0 => {
            // Delete a range.
            let start = rng.below(len);
            let end = (start + 1 + rng.below(64)).min(len);
            data.drain(start..end);
        }
        3 if len > 0 => {
            // Copy a range elsewhere.
            let start = rng.below(len);
            let end = (start + 1 + rng.below(256)).min(len);
            let piece = data[start..end].to_vec();
            let at = rng.below(len + 1);
            data.splice(at..at, piece);
        }
        4 => {
            let at = rng.below(len + 1);
            let count = 1 + rng.below(16);
            let bytes: Vec<u8> = (0..count).map(|_| rng.next_u64() as u8).collect();
            data.splice(at..at, bytes);
        }
        5 if len > 0 => data.truncate(rng.below(len)),
        6 if !pool.is_empty() => {
            // Splice: a prefix of this input, a suffix of another.
            let other = rng.pick(pool);
            let cut = rng.below(len + 1);
            let from = rng.below(other.len() + 1);
            data.truncate(cut);
            data.extend_from_slice(&other[from..]);
        }
        _ if len > 0 => {
            let i = rng.below(len);
            data[i] = data[i].wrapping_add(rng.below(5) as u8).wrapping_sub(2);
        }
        _ => data.extend_from_slice(b"v 0 0 0\n"),
    }
}

fn mutate_header(target: Target, rng: &mut Rng, data: &mut Vec<u8>) {
    let fields = if target == Target::Dds {
        DDS_FIELDS
    } else {
        BMP_FIELDS
    };
    let at = *rng.pick(fields);
    let value = if rng.chance(4) {
        rng.next_u64() as u32 >> rng.below(32)
    } else {
        *rng.pick(U32S)
    };
    if data.len() < at + 4 {
        data.resize(at + 4, 0);
    }
    if rng.chance(3) {
        // Negative sizes (BMP top-down), small signed values.
        let v = -(rng.below(70000) as i32);
        data[at..at + 4].copy_from_slice(&v.to_le_bytes());
    } else {
        data[at..at + 4].copy_from_slice(&value.to_le_bytes());
    }
}

/// Number tokens of `text`: byte ranges of runs of digits, signs, dots, exponents, letters of
/// nan/inf.
fn number_spans(text: &[u8]) -> Vec<(usize, usize)> {
    let mut spans = Vec::new();
    let mut i = 0;
    while i < text.len() {
        if text[i].is_ascii_digit() || text[i] == b'-' || text[i] == b'.' {
            let start = i;
            while i < text.len()
                && (text[i].is_ascii_alphanumeric() || matches!(text[i], b'-' | b'+' | b'.'))
            {
                i += 1;
            }
            spans.push((start, i));
        } else {
            i += 1;
        }
    }
    spans
}

fn line_starts(text: &[u8]) -> Vec<usize> {
    let mut starts = vec![0];
    starts.extend(
        text.iter()
            .enumerate()
            .filter(|&(_, &b)| b == b'\n')
            .map(|(i, _)| i + 1),
    );
    starts
}

fn mutate_text(rng: &mut Rng, data: &mut Vec<u8>) {
    match rng.below(7) {
        0 | 1 => {
            // Replace a number with an interesting one.
            let spans = number_spans(data);
            if spans.is_empty() {
                return;
            }
            let (start, end) = *rng.pick(&spans);
            let number = if rng.chance(4) {
                format!("{}", rng.next_u64() as i64 >> rng.below(64))
            } else {
                rng.pick(NUMBERS).to_string()
            };
            data.splice(start..end, number.into_bytes());
        }
        2 => {
            // Insert a line.
            let starts = line_starts(data);
            let at = *rng.pick(&starts);
            let line = if rng.chance(2) {
                random_face(rng)
            } else {
                rng.pick(LINES).to_string()
            };
            data.splice(at..at, format!("{line}\n").into_bytes());
        }
        3 => {
            // Repeat a line (grows the mesh, makes duplicates for the indexer).
            let starts = line_starts(data);
            let i = rng.below(starts.len());
            let end = starts.get(i + 1).copied().unwrap_or(data.len());
            let line = data[starts[i]..end].to_vec();
            let most = if rng.chance(8) { 500 } else { 8 };
            let times = 1 + rng.below(most);
            let mut piece = Vec::new();
            for _ in 0..times {
                piece.extend_from_slice(&line);
                if !line.ends_with(b"\n") {
                    piece.push(b'\n');
                }
            }
            data.splice(end..end, piece);
        }
        4 => {
            // Delete or swap lines.
            let starts = line_starts(data);
            if starts.len() < 2 {
                return;
            }
            let i = rng.below(starts.len() - 1);
            let line = data[starts[i]..starts[i + 1]].to_vec();
            data.drain(starts[i]..starts[i + 1]);
            if rng.chance(2) {
                let starts = line_starts(data);
                let at = *rng.pick(&starts);
                data.splice(at..at, line);
            }
        }
        5 => {
            // Separators and line ends the two parsers might split differently.
            if data.is_empty() {
                return;
            }
            let i = rng.below(data.len());
            const SEPARATORS: &[&[u8]] = &[
                b"\r\n",
                b"\r",
                b"\t",
                b"\x0b",
                b"\x0c",
                "\u{a0}".as_bytes(),
                "\u{2003}".as_bytes(),
                b"/",
                b"//",
                b" ",
                b"\\\n",
                b"#",
            ];
            let with = *rng.pick(SEPARATORS);
            data.splice(i..i + 1, with.iter().copied());
        }
        _ => {
            // Change a keyword.
            let starts = line_starts(data);
            let at = *rng.pick(&starts);
            const KEYWORDS: &[&[u8]] = &[b"l ", b"p ", b"f ", b"v ", b"vt ", b"vn ", b"o "];
            let keyword = *rng.pick(KEYWORDS);
            data.splice(at..at, keyword.iter().copied());
        }
    }
}

/// An `f` line of 1–6 corners with random (often extreme) indices and random slash layouts.
fn random_face(rng: &mut Rng) -> String {
    let corners = 1 + rng.below(6);
    let index = |rng: &mut Rng| -> String {
        match rng.below(4) {
            0 => rng.pick(NUMBERS).to_string(),
            1 => format!("-{}", 1 + rng.below(8)),
            _ => format!("{}", 1 + rng.below(8)),
        }
    };
    let mut line = String::from(if rng.chance(5) { "l" } else { "f" });
    for _ in 0..corners {
        let (v, t, n) = (index(rng), index(rng), index(rng));
        let corner = match rng.below(6) {
            0 => v,
            1 => format!("{v}/{t}"),
            2 => format!("{v}//{n}"),
            _ => format!("{v}/{t}/{n}"),
        };
        line.push(' ');
        line.push_str(&corner);
    }
    line
}

// -------------------------------------------------------------------------------------------------
// Running

/// A failing input, saved.
#[derive(Debug, Clone)]
pub struct Failure {
    pub target: Target,
    pub message: String,
    pub saved: Option<PathBuf>,
}

/// Totals of one run of one target.
#[derive(Debug, Clone, Default)]
pub struct Stats {
    pub cases: u64,
    pub loaded: u64,
    pub rejected: u64,
    pub failures: Vec<Failure>,
}

/// A file name for `input` that is the same for the same bytes (FNV-1a, 64 bits).
pub fn input_name(input: &[u8]) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in input {
        h = (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01B3);
    }
    format!("{h:016x}")
}

/// Fuzzes `target` until `stop` says so. Failing inputs go to `save_to` when given (each distinct
/// failure message once per run, so that one bug does not fill the folder).
pub fn fuzz(
    target: Target,
    seed: u64,
    slow: Duration,
    save_to: Option<&Path>,
    mut stop: impl FnMut(&Stats) -> bool,
) -> Stats {
    let mut rng = Rng::new(seed ^ (target as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15));
    // Two pools: inputs that load (mutated further, they reach the deeper code) and inputs
    // rejected in a new way (they explore the error paths). Three bases in four are loading ones.
    let mut loading: Vec<Vec<u8>> = Vec::new();
    let mut rejected: Vec<Vec<u8>> = vec![Vec::new()];
    let seeds = seed_dirs(target)
        .into_iter()
        .map(|dir| read_dir_files(&dir));
    for (_, bytes) in seeds
        .flatten()
        .chain(read_dir_files(&regressions_dir(target)))
    {
        match run_case(target, &bytes, slow) {
            Outcome::Loaded => loading.push(bytes),
            _ => rejected.push(bytes),
        }
    }
    let mut kinds: HashSet<String> = HashSet::new();
    let mut reported: HashSet<String> = HashSet::new();
    let mut stats = Stats::default();
    while !stop(&stats) {
        let pool = if !loading.is_empty() && rng.below(4) != 0 {
            &loading
        } else {
            &rejected
        };
        let base = rng.pick(pool).clone();
        let input = mutate(target, &mut rng, &base, pool);
        stats.cases += 1;
        match run_case(target, &input, slow) {
            Outcome::Loaded => {
                stats.loaded += 1;
                if rng.chance(4) {
                    add_to_pool(&mut loading, &mut rng, input);
                }
            }
            Outcome::Rejected(kind) => {
                stats.rejected += 1;
                if kinds.insert(kind) {
                    add_to_pool(&mut rejected, &mut rng, input);
                }
            }
            Outcome::Failed(message) => {
                let first_line: String = message
                    .lines()
                    .next()
                    .unwrap_or("")
                    .chars()
                    .take(160)
                    .collect();
                if reported.insert(message_kind(&first_line)) {
                    let saved = save_to.and_then(|dir| {
                        std::fs::create_dir_all(dir).ok()?;
                        let path = dir.join(input_name(&input));
                        std::fs::write(&path, &input).ok()?;
                        Some(path)
                    });
                    stats.failures.push(Failure {
                        target,
                        message: first_line,
                        saved,
                    });
                }
            }
        }
    }
    stats
}

fn add_to_pool(pool: &mut Vec<Vec<u8>>, rng: &mut Rng, input: Vec<u8>) {
    const POOL_MAX: usize = 1000;
    if pool.len() < POOL_MAX {
        pool.push(input);
    } else {
        let i = rng.below(pool.len());
        pool[i] = input;
    }
}
