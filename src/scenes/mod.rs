//! Scenes: the programs the front ends can run. Each owns its meshes, textures, shaders, uniforms,
//! keys and status line; the window, headless mode, `--bench` and the tests drive any of them through
//! the small [`Scene`] trait and know nothing of cylinders.
//!
//! | scene      | program                                                         | file            |
//! |------------|-----------------------------------------------------------------|-----------------|
//! | `cylinder` | Tutorial 13 (`tutorial13.cpp`), with its debugging aids as keys | [`cylinder`], [`tutorial13`] |
//! | `sprite`   | Article 001: a 2D normal-mapped sprite, its light on the mouse   | [`sprite`]      |
//! | `cube`     | article 003: Blinn-Phong in tangent space, normal mapping on/off | [`cube`]        |
//! | `wall`     | article 004: a stone wall lit in view space or in tangent space  | [`wall`]        |

pub mod cube;
pub mod cylinder;
mod scene;
pub mod sprite;
pub mod tutorial13;
pub mod wall;

use std::fmt;
use std::path::{Path, PathBuf};

use crate::Result;

pub use scene::{
    action_for_key, key_help, Binding, FrameInput, KeyHelp, MouseMode, Scene, SceneContext,
};

/// The scenes `--scene` can name.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash)]
pub enum SceneName {
    /// Tutorial 13's normal-mapped cylinder.
    #[default]
    Cylinder,
    /// Article 001's 2D normal-mapped sprite with a mouse-driven light.
    Sprite,
    /// Article 004's stone wall, lit in view space or in tangent space.
    Wall,
    /// Article 003's stone cube: Blinn-Phong in tangent space.
    Cube,
}

impl SceneName {
    /// Every scene, in the order the scene key steps through them.
    pub const ALL: &'static [SceneName] = &[
        SceneName::Cylinder,
        SceneName::Sprite,
        SceneName::Cube,
        SceneName::Wall,
    ];

    /// The `--scene` name.
    pub fn name(self) -> &'static str {
        match self {
            SceneName::Cylinder => "cylinder",
            SceneName::Sprite => "sprite",
            SceneName::Wall => "wall",
            SceneName::Cube => "cube",
        }
    }

    /// One line for `--help` and the README.
    pub fn description(self) -> &'static str {
        match self {
            SceneName::Cylinder => "Tutorial 13: the normal-mapped cylinder (the default)",
            SceneName::Sprite => {
                "Article 001: a 2D normal-mapped rock lit by a light on the mouse (wheel: height, \
                 click: reset)"
            }
            SceneName::Wall => "a stone wall lit in view space or in tangent space (article 004)",
            SceneName::Cube => "article 003: a stone cube, Blinn-Phong in tangent space",
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
            SceneName::Sprite => sprite::KEYS,
            SceneName::Wall => wall::KEYS,
            SceneName::Cube => cube::KEYS,
        }
    }

    /// Mouse look (the tutorial's) or the free cursor, known without building the scene (like its
    /// keys) so that the key list can say what the mouse does.
    pub fn mouse_mode(self) -> MouseMode {
        match self {
            SceneName::Sprite => MouseMode::Cursor,
            SceneName::Cylinder | SceneName::Wall | SceneName::Cube => MouseMode::Look,
        }
    }

    /// What the mouse, wheel and click do in a scene with [`MouseMode::Cursor`] (mouse-look scenes
    /// have the window's mouse look and list nothing here).
    pub fn mouse_help(self) -> &'static [(&'static str, &'static str)] {
        match self {
            SceneName::Sprite => sprite::MOUSE_HELP,
            SceneName::Cylinder | SceneName::Wall | SceneName::Cube => &[],
        }
    }

    /// Loads the scene on the current context.
    pub fn build(self, context: &SceneContext, options: &SceneOptions) -> Result<Box<dyn Scene>> {
        Ok(match self {
            SceneName::Cylinder => Box::new(cylinder::Cylinder::new(
                context,
                &options.assets_dir(),
                options.shader_dir(),
                options.cylinder,
            )?),
            SceneName::Wall => Box::new(wall::Wall::new(
                context,
                &options.assets_dir(),
                options.shader_dir(),
                options.wall,
            )?),
            SceneName::Sprite => Box::new(sprite::Sprite::new(
                context,
                &options.assets_dir(),
                options.shader_dir(),
                options.sprite,
            )?),
            SceneName::Cube => Box::new(cube::Cube::new(
                context,
                &options.assets_dir(),
                options.shader_dir(),
                options.cube,
            )?),
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
    /// The sprite scene's light and switches.
    pub sprite: sprite::SpriteOptions,
    /// The wall scene's switches.
    pub wall: wall::WallOptions,
    /// The cube scene's switches.
    pub cube: cube::CubeOptions,
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
