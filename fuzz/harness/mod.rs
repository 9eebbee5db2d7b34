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

mod bake;
mod bmp;
mod cage;
mod dds;
mod gltf;
mod heightmap;
mod lights;
mod mikktspace;
mod model;
mod mutate;
mod obj;
mod obj_tobj;
mod photo;
mod pipeline;
mod run;

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

// What the including crates use (each a different part).
#[allow(unused_imports)]
pub use mikktspace::mikktspace_soup;
#[allow(unused_imports)]
pub use model::MTL_SEPARATOR;
#[allow(unused_imports)]
pub use mutate::{mutate, Rng};
#[allow(unused_imports)]
pub use run::{fuzz, input_name, Failure, Stats};

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
    /// margin 2 ([`bake::check_bake`]). No panic; every texel's normal finite and unit (exactly +Z
    /// where nothing covers it); the counts equal a rasterization of LOW's UVs made here; the margin
    /// exactly the rings around the covered texels; 1 and 2 threads the same map.
    Bake,
    /// The bake's readers of a cage and of part names on the bake target's inputs
    /// ([`cage::check`]): the model's part names read (`model::parts::part_names`: the OBJ's `o`
    /// and `g` lines counted as the reader counts faces, a glTF's nodes), one per triangle, for
    /// every file the reader takes; the model paired with itself by name, every triangle in one
    /// pair or said unpaired; the model taken as its own cage (`bake::cage::cage_corners`) with its
    /// corners back where they were, and the sphere refused as its cage on one line; the model
    /// baked with a cage (its corners pushed out along their normals, no bound on the rays) and
    /// with its parts paired, the maps as the `bake` target's.
    Cage,
}

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

/// The invariants of one target (each target's `check`). `Err` is a broken invariant.
fn check(target: Target, input: &[u8]) -> Result<Outcome, String> {
    let path = Path::new(target.file_name());
    match target {
        Target::Obj => obj::check(input, path),
        Target::Dds => dds::check(input, path),
        Target::Bmp => bmp::check(input, path),
        Target::Pipeline => pipeline::check(input, path),
        Target::Heightmap => heightmap::check(input, path),
        Target::Model => model::check(input, path),
        Target::Photo => photo::check(input, path),
        Target::ObjTobj => obj_tobj::check(input, path),
        Target::Lights => lights::check(input, path),
        Target::Gltf => gltf::check(input, path),
        Target::Mikktspace => mikktspace::check(input, path),
        Target::Bake => bake::check(input, path),
        Target::Cage => cage::check(input, path),
    }
}

/// A reader's error `e` as a rejection, or a broken invariant where it does not name `path` on
/// one line.
fn rejected(path: &Path, e: tutorial13::Error) -> Result<Outcome, String> {
    let message = e.to_string();
    let prefix = format!("{}: ", path.display());
    if !message.starts_with(&prefix) || message.contains('\n') {
        return Err(format!(
            "error does not name the file on one line: {message}"
        ));
    }
    Ok(Outcome::Rejected(message_kind(&message)))
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
