//! The seam between the front ends and a program: what a scene is built on, what it gets each frame
//! and what it must answer ([`Scene`]). How it describes itself is [`super::descriptor`], what it
//! is built with [`super::options`], its controls [`super::table`].

use std::any::Any;
use std::path::{Path, PathBuf};

use glam::{Mat4, Vec2};

use super::table::SceneControls;
use crate::common::shader::{load_program, Program};
use crate::gl::extensions::GlExtensions;
use crate::gl::{ContextInfo, Gl};
use crate::Result;

/// Everything a scene is built on: the GL function table, what the context is, and the entry points
/// glow does not load (the immediate mode's, `glFramebufferParameteri`), looked up once with the
/// context.
pub struct SceneContext<'a> {
    pub gl: &'a Gl,
    pub info: &'a ContextInfo,
    pub extensions: &'a GlExtensions,
}

/// What a front end hands a scene for one frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrameInput {
    /// The tutorial's camera (`computeMatricesFromInputs`): projection and view.
    pub projection: Mat4,
    pub view: Mat4,
    /// The cursor in window pixels (x right, y down from the top-left), where the window has one.
    pub cursor: Option<Vec2>,
    /// The framebuffer's size in pixels; the viewport already covers it.
    pub size: (u32, u32),
    /// Seconds since the start (0 while time is frozen, as with `--frames`).
    pub time: f32,
}

/// How a scene wants the mouse (see [`super::SceneDescriptor::mouse_mode`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MouseMode {
    /// The tutorial's mouse look: the cursor is grabbed and hidden, motion turns the camera.
    Look,
    /// The cursor stays free and visible; its position reaches the scene in [`FrameInput::cursor`]
    /// (a 2D light that follows it).
    Cursor,
}

/// The seam between the front ends and a program.
/// `Any`: a scene is a plain `'static` value, so that [`crate::frontends::host::SceneHost::scene_as`]
/// can give tests and tools a particular scene's own type (by trait upcasting; nothing more is
/// asked of a scene for it).
pub trait Scene: Any + SceneControls {
    /// Draws one frame into the bound framebuffer (the front end has set the viewport): the scene
    /// clears it itself, as the tutorial's loop does.
    fn draw(&mut self, frame: &FrameInput);

    /// A key of the scene's list was pressed (letters either case). `Ok(false)`: not one of its
    /// keys. The key of each control of the scene's table ([`super::SceneType::CONTROLS`]).
    fn key(&mut self, key: char) -> Result<bool> {
        self.press_key(key)
    }

    /// One line for the log: every control of the scene's table that applies now, then what the
    /// table does not hold ([`Scene::status_beyond_table`]).
    fn status(&self) -> String {
        let mut parts = self.table_status();
        parts.extend(self.status_beyond_table());
        parts.join(" | ")
    }

    /// The state the log's status line gives beside the table's controls (a model's path, where the
    /// light is): none unless a scene says.
    fn status_beyond_table(&self) -> Vec<String> {
        Vec::new()
    }

    /// The two or three most important of them, for the title bar (the panel shows the rest):
    /// the controls the table names in the title, where they apply (the whole status where it
    /// names none).
    fn short_status(&self) -> String {
        let title = self.title_status();
        match title.is_empty() {
            true => self.status(),
            false => title.join(", "),
        }
    }

    /// The sphere (centre, radius; world space) the camera starts by framing, and goes back to
    /// with R; `None` = the tutorial's start camera.
    fn framing(&self) -> Option<(glam::Vec3, f32)> {
        None
    }

    /// The tutorial's camera for a viewport of `width × height`, framing [`Scene::framing`] if the
    /// scene has one.
    fn start_controls(&self, width: u32, height: u32) -> crate::common::controls::Controls {
        let mut controls = crate::common::controls::Controls::for_viewport(width, height);
        if let Some((center, radius)) = self.framing() {
            controls.frame_sphere(center, radius);
        }
        controls
    }

    /// The shader files the scene's programs are read from (the copies built into the binary are not
    /// files): the window watches them and calls [`Scene::reload_shaders`] when one is saved.
    fn shader_files(&self) -> Vec<PathBuf> {
        Vec::new()
    }

    /// Reads, compiles and links every program of the scene again. If any fails (the error names
    /// the file and carries the driver's log), the scene keeps all the programs it had and draws as
    /// before, so a learner's typo never ends the program.
    fn reload_shaders(&mut self) -> Result<()> {
        Ok(())
    }

    /// The mouse wheel turned by `notches` (positive: away from the user). Ignored unless the scene
    /// uses it.
    fn scroll(&mut self, _notches: f32) {}

    /// The programs drawing the frame now, and the files they read.
    fn drawing_programs(&self) -> Vec<DrawingProgram> {
        Vec::new()
    }

    /// What the two sides of the frame show while a compare view is on.
    fn compare_labels(&self) -> Option<CompareLabels> {
        None
    }

    /// A left click in a scene with [`MouseMode::Cursor`] (with mouse look, a click grabs the cursor
    /// instead). Ignored unless the scene uses it.
    fn click(&mut self) {}
}

/// The shaders a scene reads and the folder they are read from (`--shaders DIR` first, else the
/// copies built into the binary), said once: the files the window watches
/// ([`Scene::shader_files`]), the programs the panel names ([`Scene::drawing_programs`]) and a
/// reload ([`Scene::reload_shaders`]) all read this one set, so they cannot disagree.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct ShaderSet {
    /// `--shaders DIR`, if given.
    dir: Option<PathBuf>,
    /// Every shader any of the scene's programs reads, program by program (vertex, fragment).
    names: Vec<&'static str>,
}

impl ShaderSet {
    /// The shaders of `programs` (each its vertex and fragment shader), looked for in `dir` first.
    pub fn new(dir: Option<&Path>, programs: impl IntoIterator<Item = [&'static str; 2]>) -> Self {
        ShaderSet {
            dir: dir.map(Path::to_path_buf),
            names: programs.into_iter().flatten().collect(),
        }
    }

    /// `--shaders DIR`, for what loads its shaders itself (the tutorial's set-up, the TBN lines).
    pub fn dir(&self) -> Option<&Path> {
        self.dir.as_deref()
    }

    /// The files the shaders are read from, in the set's order (empty where the copies built into
    /// the binary are used): what [`Scene::shader_files`] answers.
    pub fn files(&self) -> Vec<PathBuf> {
        crate::common::shader::shader_paths(self.names.iter().copied(), self.dir())
    }

    /// Reads, compiles and links the program of `shaders` (vertex, fragment) from this set's folder.
    pub fn load(&self, gl: &Gl, shaders: [&'static str; 2]) -> Result<Program> {
        let [vertex, fragment] = shaders;
        load_program(gl, vertex, fragment, self.dir())
    }

    /// The program of `shaders` as the panel names it (`name`), read from this set's folder.
    pub fn program(&self, name: &str, shaders: [&'static str; 2]) -> DrawingProgram {
        debug_assert!(
            shaders.iter().all(|s| self.names.contains(s)),
            "{shaders:?} are not in the scene's shader set, so the window would not watch them"
        );
        DrawingProgram {
            name: name.into(),
            shaders: shaders.to_vec(),
            dir: self.dir.clone(),
        }
    }
}

/// A program drawing the frame: its name and the shaders it reads by name (none: no shader, as the
/// immediate mode). Only names, so that the panel can ask for it every frame without a look at the
/// disk; [`DrawingProgram::files`] finds the files when they are shown.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DrawingProgram {
    pub name: String,
    pub shaders: Vec<&'static str>,
    /// `--shaders DIR`, where they are looked for first.
    pub dir: Option<PathBuf>,
}

impl DrawingProgram {
    /// The files the shaders are read from (empty where the copies built into the binary are used).
    pub fn files(&self) -> Vec<PathBuf> {
        let names = self.shaders.iter().copied();
        crate::common::shader::shader_paths(names, self.dir.as_deref())
    }
}

/// The two sides of a compare view: where the split is (a fraction of the width; `None` for one
/// picture made from both) and what each side shows.
#[derive(Debug, Clone, PartialEq)]
pub struct CompareLabels {
    pub split: Option<f32>,
    pub left: String,
    pub right: String,
}
