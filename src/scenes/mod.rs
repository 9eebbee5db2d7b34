//! Scenes: the programs the front ends can run. Each is a folder that owns its meshes, textures,
//! shaders, uniforms, GL state, command-line arguments, keys and status line, and whose type says
//! what it is ([`SceneType`]); [`SCENES`] lists their descriptors ([`SceneDescriptor::of`] each
//! type), and is all the rest of the program knows. The window, headless mode, `--bench` and the
//! tests drive any of them through the [`Scene`] trait.
//!
//! | scene      | program                                                | folder         |
//! |------------|--------------------------------------------------------|----------------|
//! | `cylinder` | Tutorial 13 (`tutorial13.cpp`), its debugging aids as keys | [`cylinder`] ([`cylinder::tutorial13`]) |
//! | `sprite`   | article 001: a 2D normal-mapped sprite, its light on the mouse | [`sprite`] |
//! | `cube`     | article 003: Blinn-Phong in tangent space, normal mapping on/off | [`cube`] |
//! | `wall`     | article 004: a stone wall lit in view space or in tangent space | [`wall`] |

pub mod cube;
pub mod cylinder;
mod descriptor;
pub mod flags;
pub mod lights;
mod options;
mod scene;
pub mod sprite;
pub mod starts;
pub mod table;
pub mod wall;

use clap::parser::ValueSource;

pub use descriptor::{SceneDescriptor, SceneType, SharedFlags};
pub use flags::{Flag, Shared, SharedArgs, Start};
pub use options::{OwnArgs, PerScene, SceneArgs, SceneOption, SceneOptions};
pub use scene::{
    CompareLabels, DrawingProgram, FrameInput, MouseMode, Scene, SceneContext, ShaderSet,
};
pub use starts::{Handle, Setting, Starts};
pub use table::{
    control_for_key, Control, ControlState, ControlValue, KeyHelp, KeyList, Kind, SceneControls,
    SetTo,
};

/// Every scene, in the order the Enter key steps through them; the first is the default. Adding a
/// scene is its folder (its type's [`SceneType`]), one line here, and its tests.
pub static SCENES: [&SceneDescriptor; 4] = [
    &SceneDescriptor::of::<cylinder::Cylinder>(),
    &SceneDescriptor::of::<sprite::Sprite>(),
    &SceneDescriptor::of::<cube::Cube>(),
    &SceneDescriptor::of::<wall::Wall>(),
];

/// The descriptor in [`SCENES`] of scene type `S`.
pub fn descriptor<S: SceneType>() -> &'static SceneDescriptor {
    SCENES
        .iter()
        .copied()
        .find(|scene| scene.name == S::NAME)
        .expect("the scene type is listed in SCENES")
}

/// The scene the program starts with when `--scene` is not given.
pub fn default_scene() -> &'static SceneDescriptor {
    SCENES[0]
}

/// The scene `--scene NAME` names.
pub fn find(name: &str) -> Result<&'static SceneDescriptor, String> {
    SCENES
        .iter()
        .copied()
        .find(|scene| scene.name == name)
        .ok_or_else(|| {
            let names: Vec<_> = SCENES.iter().map(|s| s.name).collect();
            format!("unknown scene '{name}': use {}", names.join(", "))
        })
}

/// The first scene that opens `path` (a file dropped on the window), with `options` changed to open
/// it; an error naming the file if no scene opens files of its kind.
pub fn open_file(
    path: &std::path::Path,
    options: &mut SceneOptions,
) -> crate::Result<&'static SceneDescriptor> {
    SCENES
        .iter()
        .copied()
        .find(|scene| (scene.open_file)(path, options))
        .ok_or_else(|| crate::Error::Open {
            path: path.to_path_buf(),
            reason: format!(
                "no scene opens this kind of file (drop {} model)",
                crate::model::Format::listed()
            ),
        })
}

/// The scene after `scene`, wrapping around (the Enter key).
pub fn next(scene: &SceneDescriptor) -> &'static SceneDescriptor {
    let i = SCENES.iter().position(|s| *s == scene).unwrap_or(0);
    SCENES[(i + 1) % SCENES.len()]
}

/// Every file `make-assets` writes, scene by scene in [`SCENES`] order, made in memory before anything
/// is written.
pub fn generate_assets() -> crate::Result<crate::assets::GeneratedFiles> {
    let mut files = Vec::new();
    for scene in SCENES {
        files.extend((scene.generate_assets)()?);
    }
    Ok(files)
}

/// `command` with the flags several scenes share and every scene's own arguments, each scene's under
/// a heading of its own.
pub fn command_line(command: clap::Command) -> clap::Command {
    let mut command = <SharedArgs as clap::Args>::augment_args(command);
    // Each shared flag's help names the scenes that read it, from their descriptors.
    for arg in shared_args().get_arguments() {
        let help = arg.get_help().map(|h| h.to_string()).unwrap_or_default();
        let help = format!("{help} [{}]", readers(arg.get_id().as_str()));
        command = command.mut_arg(arg.get_id().clone(), |arg| arg.help(help));
    }
    SCENES
        .iter()
        .fold(command, |command, scene| (scene.args)(command))
}

/// The flags several scenes share, alone in a command of their own (to list them).
fn shared_args() -> clap::Command {
    <SharedArgs as clap::Args>::augment_args(clap::Command::new("shared"))
}

/// "scene NAME" or "scenes A, B and C": the scenes whose descriptors read the shared flag `id`.
fn readers(id: &str) -> String {
    let names: Vec<_> = SCENES
        .iter()
        .filter(|s| s.reads_shared(id))
        .map(|s| s.name)
        .collect();
    match names.split_last() {
        Some((last, [])) => format!("scene {last}"),
        Some((last, others)) => format!("scenes {} and {last}", others.join(", ")),
        None => "no scene".to_string(),
    }
}

/// Every scene's options from a command line parsed with [`command_line`], for a program that starts
/// with `scene`. A flag that `scene` does not read is an error naming the scenes that do: no flag is
/// ever silently ignored.
pub fn scene_options(
    matches: &clap::ArgMatches,
    scene: &SceneDescriptor,
    mut options: SceneOptions,
) -> Result<SceneOptions, String> {
    let given = |id: &str| matches.value_source(id) == Some(ValueSource::CommandLine);
    for arg in shared_args().get_arguments() {
        let id = arg.get_id().as_str();
        if given(id) && !scene.reads_shared(id) {
            return Err(format!(
                "{} is an option of {}, not of scene {} (choose one with --scene)",
                flag(arg),
                readers(id),
                scene.name
            ));
        }
    }
    for other in SCENES.iter().filter(|s| ***s != *scene) {
        let args = (other.args)(clap::Command::new(other.name));
        let stray = args
            .get_arguments()
            .find(|a| given(a.get_id().as_str()))
            .map(flag);
        if let Some(stray) = stray {
            return Err(format!(
                "{stray} is an option of scene {}, not of scene {} (add --scene {})",
                other.name, scene.name, other.name
            ));
        }
    }
    // Every scene's options, so that a scene switched to keeps the flags it reads; only the chosen
    // scene's may refuse them (`--light 0,0,-4` is a place for the cylinder, no height over the
    // sprite: the sprite then starts with its own light).
    for other in SCENES {
        if let Err(e) = (other.read_args)(matches, &mut options) {
            if *other == *scene {
                let text = e.to_string();
                return Err(text.trim().trim_start_matches("error: ").to_string());
            }
        }
    }
    Ok(options)
}

/// `--long` as the user typed it.
fn flag(arg: &clap::Arg) -> String {
    match arg.get_long() {
        Some(long) => format!("--{long}"),
        None => arg.get_id().to_string(),
    }
}
