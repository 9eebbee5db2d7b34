//! The tutorial's exercises checked by the host: F2 (or the tour pane's button) at an exercise step
//! in every front end, and `tutorial13 --headless --check-exercise N` (`tools::tour`), which asks
//! the same host. The learner's frame, the reference and the frame nobody changed are drawn on the
//! host's own context, each by a cylinder built for the check with the host's options (so that the
//! scene on show, and its frame, stay as they were), at the host's frame size, the camera at its
//! start and time frozen; [`Verdict`] compares them.

use std::path::PathBuf;
use std::sync::Arc;

use glow::HasContext;
use image::RgbaImage;

use super::{scene_context, SceneHost};
use crate::common::controls::Input;
use crate::frontends::keys::FrontEnd;
use crate::gl::check_gl_errors;
use crate::gl::offscreen::OffscreenTarget;
use crate::mesh::{Code, MeshOptions};
use crate::scenes::cylinder::Cylinder;
use crate::scenes::{FrameInput, Scene, SceneDescriptor, SceneOptions};
use crate::tour::exercise::{
    Exercise, ExerciseCheck, FrameDifference, Verdict, HEAT_MAP_WIDTH, PAGE_CHECK_LINE,
};
use crate::tour::Value;
use crate::{Error, Result};

impl SceneHost {
    /// Checks `exercise`: the learner's frame against the reference and the unchanged frame, each
    /// drawn by a cylinder built for the check (see the module's comment).
    pub fn check_exercise(&mut self, exercise: &Exercise) -> Result<ExerciseCheck> {
        let cylinder = crate::scenes::descriptor::<Cylinder>();
        let [learner, reference, unchanged] = match exercise.number {
            1 => self.exercise_1_frames(cylinder)?,
            _ => self.exercise_2_frames(cylinder)?,
        };
        let verdict = Verdict::of(&learner, &reference, &unchanged);
        let heat_map = match verdict {
            Verdict::Differs(FrameDifference { max, .. }) => {
                let block = learner.width().div_ceil(HEAT_MAP_WIDTH).max(1);
                let map = crate::debug::compare::heat_map(&learner, &reference, max, block);
                Some(Arc::new(map))
            }
            _ => None,
        };
        self.exercise_checks += 1;
        Ok(ExerciseCheck {
            verdict: Some(verdict),
            line: verdict.line(exercise),
            heat_map,
            serial: self.exercise_checks,
        })
    }

    /// F2 or the pane's button: the exercise of the tour's step checked, its answer for the pane
    /// (and the log). Elsewhere than at an exercise step, and in the page, one line says why not.
    pub(super) fn check_tour_exercise(&mut self) {
        let exercise = self
            .tour_step()
            .and_then(|step| crate::tour::exercise::for_step(step.name));
        let Some(exercise) = exercise else {
            return log::info!(
                "F2 checks an exercise at the tour's exercise steps (tutorial13 --tour exercise-1)"
            );
        };
        let answer = if self.front_end == FrontEnd::Page {
            Err(PAGE_CHECK_LINE.to_string())
        } else {
            self.check_exercise(exercise).map_err(|e| e.to_string())
        };
        self.exercise_answer = Some(match answer {
            Ok(check) => {
                log::info!("{}", check.line);
                check
            }
            Err(line) => {
                log::warn!("{line}");
                self.exercise_checks += 1;
                ExerciseCheck {
                    verdict: None,
                    line,
                    heat_map: None,
                    serial: self.exercise_checks,
                }
            }
        });
    }

    /// The last check's answer at the tour's step on show.
    pub fn exercise_answer(&self) -> Option<&ExerciseCheck> {
        self.exercise_answer.as_ref()
    }

    /// Exercise 1 (the indexer's sums): the learner's frame indexed by the port of `indexVBO_TBN`
    /// they edit; the reference and the unchanged frame by its fast twin, which their edit leaves as
    /// it was, with and without the N switch's normalization.
    fn exercise_1_frames(&mut self, cylinder: &'static SceneDescriptor) -> Result<[RgbaImage; 3]> {
        let mut scene = (cylinder.build)(&scene_context(&self.context), &self.options)?;
        let mut frame_with = |host: &Self, mesh: MeshOptions| -> Result<RgbaImage> {
            let any: &mut dyn std::any::Any = &mut *scene;
            let Some(cylinder_scene) = any.downcast_mut::<Cylinder>() else {
                return Err(Error::Argument(
                    "exercise 1: the scene is not the cylinder".into(),
                ));
            };
            cylinder_scene.set_mesh_options(mesh)?;
            host.still_frame(cylinder, scene.as_mut())
        };
        let twins = |normalize_before_sum| MeshOptions {
            code: Some(Code::FastTwins),
            indexing: crate::common::vboindexer::IndexOptions {
                normalize_before_sum,
            },
            ..MeshOptions::default()
        };
        let learner = MeshOptions {
            code: Some(Code::Ports),
            ..MeshOptions::default()
        };
        Ok([
            frame_with(self, learner)?,
            frame_with(self, twins(true))?,
            frame_with(self, twins(false))?,
        ])
    }

    /// Exercise 2 (the fragment shader's colour): the learner's frame drawn with their shaders
    /// (`--shaders`, else the crate's folder); the reference (the colour view "eye") and the unchanged
    /// frame with the shaders built into the binary, written to a folder of their own for the check.
    fn exercise_2_frames(&mut self, cylinder: &'static SceneDescriptor) -> Result<[RgbaImage; 3]> {
        let context = scene_context(&self.context);
        let mut learner_scene = (cylinder.build)(&context, &self.options)?;
        let learner = self.still_frame(cylinder, learner_scene.as_mut())?;
        drop(learner_scene);
        let built_in = BuiltInShaders::write()?;
        let stock = SceneOptions {
            shaders: Some(built_in.dir.clone()),
            ..self.options.clone()
        };
        let mut scene = (cylinder.build)(&scene_context(&self.context), &stock)?;
        let unchanged = self.still_frame(cylinder, scene.as_mut())?;
        let view = scene
            .control_index("colour view")
            .ok_or_else(|| Error::Argument("exercise 2: the cylinder has no colour view".into()))?;
        scene.set_control(view, Value::Choice("eye").set_to())?;
        let reference = self.still_frame(cylinder, scene.as_mut())?;
        Ok([learner, reference, unchanged])
    }

    /// `scene`'s first frame at the host's size, as a frozen frame draws it (the camera at the
    /// scene's start, no input, time 0), into a target of its own stored like a window's buffers,
    /// read back top row first; the framebuffer that was bound is bound again.
    fn still_frame(
        &self,
        descriptor: &'static SceneDescriptor,
        scene: &mut dyn Scene,
    ) -> Result<RgbaImage> {
        let gl = &self.context.gl;
        let (width, height) = self.size;
        // SAFETY: a binding query on the current context.
        let bound = unsafe { crate::gl::bound_framebuffer(gl, glow::DRAW_FRAMEBUFFER_BINDING) };
        let target =
            OffscreenTarget::with_window_orientation(gl, self.size, 0, &self.context.extensions)?;
        target.bind();
        // SAFETY: the target's viewport on the current context.
        unsafe { gl.viewport(0, 0, width as i32, height as i32) };
        let mut controls = scene.start_controls(width, height);
        controls.compute_matrices_from_inputs(&Input::default(), 0.0);
        descriptor.gl_state.apply(gl);
        scene.draw(&FrameInput {
            projection: controls.projection_matrix(),
            view: controls.view_matrix(),
            cursor: None,
            size: self.size,
            time: 0.0,
        });
        let image = target.read_rgba();
        check_gl_errors(gl, "exercise check")?;
        // SAFETY: the front end's framebuffer again.
        unsafe { gl.bind_framebuffer(glow::FRAMEBUFFER, bound) };
        Ok(image)
    }
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
