//! Scenes: the programs the front ends can run. Each owns its meshes, textures, shaders, uniforms,
//! keys and status line; the window, headless mode, `--bench` and the tests drive any of them through
//! the small [`Scene`] trait and know nothing of cylinders.
//!
//! | scene      | program                                                         | file            |
//! |------------|-----------------------------------------------------------------|-----------------|
//! | `cylinder` | Tutorial 13 (`tutorial13.cpp`), with its debugging aids as keys | [`cylinder`], [`tutorial13`] |

pub mod cylinder;
pub mod tutorial13;

use std::any::Any;
use std::ffi::{c_void, CStr};
use std::fmt;
use std::path::{Path, PathBuf};

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

/// How a scene wants the mouse.
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

/// The seam between the front ends and a program.
pub trait Scene {
    /// Draws one frame into the bound framebuffer (the front end has set the viewport): the scene
    /// clears it itself, as the tutorial's loop does.
    fn draw(&mut self, frame: &FrameInput);

    /// A key of the scene's list was pressed (letters upper-case). `Ok(false)`: not one of its keys.
    fn key(&mut self, key: char) -> Result<bool>;

    /// The scene's keys, for the start-up message, `--help` and the README.
    fn keys(&self) -> &'static [KeyHelp];

    /// One line for the title bar and the log: the scene's current switches.
    fn status(&self) -> String;

    /// Mouse look (the default) or the free cursor.
    fn mouse_mode(&self) -> MouseMode {
        MouseMode::Look
    }

    /// For tests and tools that reach into a particular scene.
    fn as_any(&self) -> &dyn Any;
    fn as_any_mut(&mut self) -> &mut dyn Any;
}

/// The scenes `--scene` can name.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash)]
pub enum SceneName {
    /// Tutorial 13's normal-mapped cylinder.
    #[default]
    Cylinder,
}

impl SceneName {
    /// Every scene, in the order the scene key steps through them.
    pub const ALL: &'static [SceneName] = &[SceneName::Cylinder];

    /// The `--scene` name.
    pub fn name(self) -> &'static str {
        match self {
            SceneName::Cylinder => "cylinder",
        }
    }

    /// One line for `--help` and the README.
    pub fn description(self) -> &'static str {
        match self {
            SceneName::Cylinder => "Tutorial 13: the normal-mapped cylinder (the default)",
        }
    }

    /// The next scene, wrapping around.
    pub fn next(self) -> SceneName {
        let i = Self::ALL.iter().position(|&s| s == self).unwrap_or(0);
        Self::ALL[(i + 1) % Self::ALL.len()]
    }

    /// The scene's keys, without building it (for `--help`).
    pub fn keys(self) -> &'static [KeyHelp] {
        match self {
            SceneName::Cylinder => cylinder::KEYS,
        }
    }

    /// Loads the scene on the current context.
    pub fn build(self, context: &SceneContext, options: &SceneOptions) -> Result<Box<dyn Scene>> {
        Ok(match self {
            SceneName::Cylinder => Box::new(cylinder::Cylinder::new(context, options)?),
        })
    }
}

impl fmt::Display for SceneName {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for SceneName {
    type Err = String;

    fn from_str(s: &str) -> std::result::Result<Self, String> {
        Self::ALL
            .iter()
            .copied()
            .find(|scene| scene.name() == s)
            .ok_or_else(|| {
                let names: Vec<_> = Self::ALL.iter().map(|s| s.name()).collect();
                format!("unknown scene '{s}': use {}", names.join(", "))
            })
    }
}

/// Where a scene's files come from, and the switches it starts with.
#[derive(Debug, Clone, Default)]
pub struct SceneOptions {
    /// `--assets DIR`; `None` = the crate's own assets/ folder.
    pub assets: Option<PathBuf>,
    /// `--shaders DIR`; `None` = the crate's shaders/ folder, else the copies built into the binary.
    pub shaders: Option<PathBuf>,
    /// The cylinder scene's switches.
    pub cylinder: cylinder::CylinderOptions,
}

impl SceneOptions {
    /// The asset folder in use.
    pub fn assets_dir(&self) -> PathBuf {
        self.assets.clone().unwrap_or_else(crate_assets_dir)
    }

    /// The shader folder given on the command line, if any.
    pub fn shader_dir(&self) -> Option<&Path> {
        self.shaders.as_deref()
    }
}

/// The crate's own assets/ folder, wherever the binary is started from.
pub fn crate_assets_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("assets")
}
