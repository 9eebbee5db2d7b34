//! The seam between the front ends and a program: what a scene is built on, what it gets each frame,
//! and what it must answer. The registry of scenes ([`super::SceneName`]) sits above the scenes and
//! this file below them, so no scene imports the module that imports it.

use std::any::Any;
use std::ffi::{c_void, CStr};
use std::path::PathBuf;

use glam::{Mat4, Vec2};

use crate::gl::{ContextInfo, Gl};
use crate::Result;

/// Everything a scene is built on: the GL function table, what the context is, and the context's
/// entry-point loader (for what glow does not load, such as the immediate-mode functions).
pub struct SceneContext<'a> {
    pub gl: &'a Gl,
    pub info: &'a ContextInfo,
    pub loader: &'a dyn Fn(&CStr) -> *const c_void,
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

/// How a scene wants the mouse (see [`SceneName::mouse_mode`](super::SceneName::mouse_mode)).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MouseMode {
    /// The tutorial's mouse look: the cursor is grabbed and hidden, motion turns the camera.
    Look,
    /// The cursor stays free and visible; its position reaches the scene in [`FrameInput::cursor`]
    /// (a 2D light that follows it).
    Cursor,
}

/// One line of a scene's key list: the key as printed ("L") and what it does.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct KeyHelp {
    pub key: char,
    pub help: &'static str,
}

/// One key of a scene: the key as listed, the scene's action, and what it does.
pub type Binding<A> = (char, A, &'static str);

/// The key list of a scene's bindings, in their order (a `const` so that `--help` can list a
/// scene's keys without building it).
pub const fn key_help<A: Copy, const N: usize>(bindings: &[Binding<A>; N]) -> [KeyHelp; N] {
    let mut keys = [KeyHelp { key: ' ', help: "" }; N];
    let mut i = 0;
    while i < N {
        keys[i] = KeyHelp {
            key: bindings[i].0,
            help: bindings[i].2,
        };
        i += 1;
    }
    keys
}

/// The action bound to `key` (letters either case).
pub fn action_for_key<A: Copy>(bindings: &[Binding<A>], key: char) -> Option<A> {
    bindings
        .iter()
        .find(|(k, _, _)| *k == key.to_ascii_uppercase())
        .map(|&(_, action, _)| action)
}

/// The seam between the front ends and a program.
pub trait Scene {
    /// Draws one frame into the bound framebuffer (the front end has set the viewport): the scene
    /// clears it itself, as the tutorial's loop does.
    fn draw(&mut self, frame: &FrameInput);

    /// A key of the scene's list was pressed (letters upper-case). `Ok(false)`: not one of its keys.
    fn key(&mut self, key: char) -> Result<bool>;

    /// One line for the title bar and the log: the scene's current switches.
    fn status(&self) -> String;

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

    /// A left click in a scene with [`MouseMode::Cursor`] (with mouse look, a click grabs the cursor
    /// instead). Ignored unless the scene uses it.
    fn click(&mut self) {}

    /// For tests and tools that reach into a particular scene.
    fn as_any(&self) -> &dyn Any;
    fn as_any_mut(&mut self) -> &mut dyn Any;
}
