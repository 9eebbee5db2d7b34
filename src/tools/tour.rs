//! `--tour` and `--check-exercise`, headless: a step of the tutorial's tour put in its state, and an
//! exercise's frame checked against the program's own answer.

use std::path::PathBuf;

use image::RgbaImage;

use crate::frontends::headless::{HeadlessOptions, HeadlessRenderer};
use crate::mesh::{Code, MeshOptions};
use crate::scenes::cylinder::Cylinder;
use crate::scenes::SceneOptions;
use crate::tour::exercise::{exercise, Verdict};
use crate::tour::{Step, Value};
use crate::{Error, Result};

/// What `--tour` asks for.
pub enum TourRequest {
    /// `--tour list`.
    List,
    /// `--tour N` or `--tour NAME`.
    Step(&'static Step),
}

/// `--tour`'s value read: `list`, or a step (a bad one is one line naming what the tour has).
pub fn tour_request(value: &str) -> Result<TourRequest> {
    match value {
        "list" => Ok(TourRequest::List),
        _ => crate::tour::find(value).map(TourRequest::Step),
    }
}

/// `--check-exercise N`: renders the learner's frame, the reference and the unchanged frame with
/// `options` (the command line's, its `--shaders` folder the learner's) and says which it is.
/// `Ok` with the line to print when the learner's frame is the reference; an
/// [`Error::Exercise`] with the line otherwise.
pub fn check_exercise(n: u8, options: &HeadlessOptions) -> Result<String> {
    let exercise = exercise(n).map_err(Error::Argument)?;
    if options.descriptor.name != "cylinder" {
        return Err(Error::Argument(format!(
            "--check-exercise {n}: the exercises are the tutorial's cylinder's (leave out --scene)"
        )));
    }
    let [learner, reference, unchanged] = match n {
        1 => exercise_1_frames(options)?,
        _ => exercise_2_frames(options)?,
    };
    let verdict = Verdict::of(&learner, &reference, &unchanged);
    let line = verdict.line(exercise);
    match verdict.passed() {
        true => Ok(line),
        false => Err(Error::Exercise(line)),
    }
}

/// Exercise 1 (the indexer's sums): the learner's frame indexed by the port of `indexVBO_TBN`
/// they edit; the reference and the unchanged frame by its fast twin, which their edit leaves as
/// it was, with and without the N switch's normalization.
fn exercise_1_frames(options: &HeadlessOptions) -> Result<[RgbaImage; 3]> {
    let mut renderer = HeadlessRenderer::new(options)?;
    let mut frame_with = |mesh: MeshOptions| -> Result<RgbaImage> {
        let cylinder = renderer.host.scene_as::<Cylinder>().ok_or_else(|| {
            Error::Argument("--check-exercise 1: the scene is not the cylinder".into())
        })?;
        cylinder.set_mesh_options(mesh)?;
        renderer.render_frames(1)
    };
    let twins = |normalize_before_sum| MeshOptions {
        code: Some(Code::FastTwins),
        indexing: crate::common::vboindexer::IndexOptions {
            normalize_before_sum,
        },
        ..MeshOptions::default()
    };
    let learner = frame_with(MeshOptions {
        code: Some(Code::Ports),
        ..MeshOptions::default()
    })?;
    Ok([learner, frame_with(twins(true))?, frame_with(twins(false))?])
}

/// Exercise 2 (the fragment shader's colour): the learner's frame drawn with their shaders
/// (`--shaders`, else the crate's folder); the reference (the colour view "eye") and the unchanged
/// frame with the shaders built into the binary, written to a folder of their own for the run.
fn exercise_2_frames(options: &HeadlessOptions) -> Result<[RgbaImage; 3]> {
    let learner = HeadlessRenderer::new(options)?.render_frames(1)?;
    let built_in = BuiltInShaders::write()?;
    let mut stock = options.clone();
    stock.scene = SceneOptions {
        shaders: Some(built_in.dir.clone()),
        ..options.scene.clone()
    };
    let mut renderer = HeadlessRenderer::new(&stock)?;
    let unchanged = renderer.render_frames(1)?;
    let view = renderer
        .host
        .scene
        .control_index("colour view")
        .ok_or_else(|| {
            Error::Argument("--check-exercise 2: the cylinder has no colour view".into())
        })?;
    renderer
        .host
        .scene
        .set_control(view, Value::Choice("eye").set_to())?;
    let reference = renderer.render_frames(1)?;
    Ok([learner, reference, unchanged])
}

/// The shaders built into the binary, written to a fresh folder under the system's temporary
/// folder (removed when dropped), so that a scene reads them instead of the crate's `shaders/`,
/// which a learner may have edited.
struct BuiltInShaders {
    dir: PathBuf,
}

impl BuiltInShaders {
    fn write() -> Result<Self> {
        let dir = std::env::temp_dir().join(format!("tutorial13-shaders-{}", std::process::id()));
        let made = BuiltInShaders { dir };
        std::fs::create_dir_all(&made.dir).map_err(|e| Error::io(&made.dir, e))?;
        for (name, text) in crate::common::shader::embedded_shaders() {
            let path = made.dir.join(name);
            std::fs::write(&path, text).map_err(|e| Error::io(&path, e))?;
        }
        Ok(made)
    }
}

impl Drop for BuiltInShaders {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}
