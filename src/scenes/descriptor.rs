//! How a scene describes itself to the rest of the program ([`SceneDescriptor`]) and how its type
//! loads ([`SceneType`]). The list of scenes ([`super::SCENES`]) sits above the scenes and this file
//! below them, so no scene imports the module that imports it.

use std::fmt;
use std::marker::PhantomData;
use std::path::Path;

use super::flags::Start;
use super::options::{read_args, SceneArgs, SceneOptions, Shared};
use super::scene::{MouseMode, Scene, SceneContext};
use super::table::{control_for_key, Control, ControlState, KeyHelp, Kind, SceneControls, SetTo};
use crate::gl::state::GlState;
use crate::Result;

/// All the rest of the program knows of a scene: each scene's folder defines one (`SCENE`), and one
/// line in [`super::SCENES`] adds it to the command line, the Enter key, `--help` and `docs/keys.md`.
pub struct SceneDescriptor {
    /// The `--scene` name.
    pub name: &'static str,
    /// One line for `--help`, the README and the title: what the scene shows and where it comes from.
    pub description: &'static str,
    /// Mouse look (the tutorial's) or a free cursor.
    pub mouse_mode: MouseMode,
    /// The scene's keys: those of its table ([`SceneType::CONTROLS`], through [`super::table::key_help`]).
    pub keys: &'static [KeyHelp],
    /// What the mouse, wheel and click do in a scene with [`MouseMode::Cursor`] (mouse-look scenes
    /// have the window's mouse look and list nothing here).
    pub mouse_help: &'static [(&'static str, &'static str)],
    /// The scene's command-line arguments: its [`SceneArgs`] struct, under a heading of its own.
    pub args: fn(clap::Command) -> clap::Command,
    /// Which of the flags several scenes read ([`super::SharedArgs`]) this one reads.
    pub shared_args: &'static [Shared],
    /// Reads the scene's arguments from the parsed command line into [`SceneOptions`].
    pub read_args: fn(&clap::ArgMatches, &mut SceneOptions) -> std::result::Result<(), clap::Error>,
    /// Loads the scene on the current context, with its options from `options` (its defaults where
    /// `options` holds none).
    pub build: fn(&SceneContext, &SceneOptions) -> Result<Box<dyn Scene>>,
    /// The files `make-assets` generates for the scene: paths under the assets folder, and bytes.
    pub generate_assets: fn() -> Result<crate::assets::GeneratedFiles>,
    /// Their paths alone, without generating them: what the browser page fetches for the scene.
    pub asset_files: &'static [&'static str],
    /// A file dropped on the window: puts it into the scene's options and returns `true` if the
    /// scene opens files of its kind (the cylinder opens an `.obj` as `--model`).
    pub open_file: fn(&Path, &mut SceneOptions) -> bool,
    /// What the host sets before each of the scene's frames ([`SceneType::GL_STATE`]).
    pub gl_state: GlState,
}

impl SceneDescriptor {
    /// Whether the scene reads the shared flag whose argument id is `id`.
    pub fn reads_shared(&self, id: &str) -> bool {
        Shared::of_id(id).is_some_and(|flag| self.shared_args.contains(&flag))
    }

    /// The descriptor of scene type `S`: mouse look, no mouse help, no shared flags, no generated
    /// or asset files (a scene that differs sets those fields over this one).
    pub const fn of<S: SceneType>(
        name: &'static str,
        description: &'static str,
        keys: &'static [KeyHelp],
    ) -> Self {
        SceneDescriptor {
            name,
            description,
            mouse_mode: MouseMode::Look,
            keys,
            mouse_help: &[],
            args: scene_args::<S>,
            shared_args: &[],
            read_args: read_scene_args::<S>,
            build: build::<S>,
            generate_assets: || Ok(Vec::new()),
            asset_files: &[],
            open_file: |_, _| false,
            gl_state: S::GL_STATE,
        }
    }
}

/// A scene's type as its folder defines it: its arguments, and how it loads.
pub trait SceneType: Scene + Sized + 'static {
    /// The scene's command-line arguments, and through them its options type.
    type Args: SceneArgs;

    /// Every switch, choice and slider of the scene, each declared once (see [`Control`]).
    const CONTROLS: &'static [Control<Self>];

    /// The GL state the scene draws in (clear colour, depth test, culling): the host sets it before
    /// each frame, as another scene may have drawn on the context since this one was built.
    const GL_STATE: GlState;

    /// Loads the scene on the current context: its files from `files` (`--assets`, `--shaders`),
    /// its switches from `options`.
    fn new(
        context: &SceneContext,
        files: &SceneOptions,
        options: <Self::Args as SceneArgs>::Options,
    ) -> Result<Self>;

    /// Once the scene is built and the controls its flags name are set through its table: what it
    /// says of the state it starts in (a warning that a flag may have made moot). Nothing unless
    /// the scene says.
    fn started(&mut self) {}
}

/// [`SceneDescriptor::args`] of scene type `S`: its `Args` struct's, then the flag of each control
/// of its table that has one ([`Flag`]), under the same heading.
fn scene_args<S: SceneType>(command: clap::Command) -> clap::Command {
    // The `Args` struct's `next_help_heading` stays set for the arguments added after it.
    let command = <S::Args as clap::Args>::augment_args(command);
    let flags = S::CONTROLS
        .iter()
        .filter_map(|control| Some(control.flag?.args(control.key)))
        .flatten();
    command.args(flags)
}

/// The starts that scene type `S`'s flags gave, each with the index of its control in the table:
/// set through the table once the scene is built.
pub struct FlagStarts<S>(pub Vec<(usize, Start)>, PhantomData<fn() -> S>);

impl<S: SceneType> FlagStarts<S> {
    pub fn new(starts: Vec<(usize, Start)>) -> Self {
        FlagStarts(starts, PhantomData)
    }

    /// The value the flag of the choice on `key` starts it with, if given: for a scene whose
    /// load depends on it (the cylinder's mesh is built for `--tangents` straight away; the
    /// table's `set` then finds it set).
    pub fn choice<T: Copy + 'static>(&self, key: char) -> Option<T> {
        let index = control_for_key(S::CONTROLS, key)?;
        self.0.iter().find_map(|(i, start)| match start {
            Start::Choice(value) if *i == index => value.downcast_ref::<T>().copied(),
            _ => None,
        })
    }
}

impl<S> Clone for FlagStarts<S> {
    fn clone(&self) -> Self {
        FlagStarts(self.0.clone(), PhantomData)
    }
}

impl<S> Default for FlagStarts<S> {
    fn default() -> Self {
        FlagStarts(Vec::new(), PhantomData)
    }
}

impl<S> fmt::Debug for FlagStarts<S> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_tuple("FlagStarts").field(&self.0).finish()
    }
}

/// [`SceneDescriptor::read_args`] of scene type `S`: its `Args` struct's options, and the starts
/// of the flags that were given.
fn read_scene_args<S: SceneType>(
    matches: &clap::ArgMatches,
    options: &mut SceneOptions,
) -> std::result::Result<(), clap::Error> {
    read_args::<S::Args>(matches, options)?;
    let given = S::CONTROLS
        .iter()
        .enumerate()
        .filter_map(|(index, control)| Some((index, control.flag?.read(matches)?)));
    options.set(FlagStarts::<S>::new(given.collect()));
    Ok(())
}

/// [`SceneDescriptor::build`] of scene type `S`, with its options from `options`, then each control
/// whose flag was given set through the table: choices and sliders first, then toggles (turning
/// the TBN lines on builds them, with the line mode and length already set). A flag that does
/// nothing in the state the scene starts in says why, as the panel does.
fn build<S: SceneType>(context: &SceneContext, options: &SceneOptions) -> Result<Box<dyn Scene>> {
    let mut scene = S::new(context, options, options.get())?;
    let starts = options.get::<FlagStarts<S>>().0;
    let (toggles, values): (Vec<_>, Vec<_>) = starts
        .iter()
        .partition(|(_, start)| matches!(start, Start::Toggle(_)));
    for (index, start) in values.into_iter().chain(toggles) {
        S::CONTROLS[*index].start(&mut scene, start)?;
    }
    // Once per flag: `--view` starts two controls.
    let mut warned = Vec::new();
    for (index, _) in &starts {
        let control = &S::CONTROLS[*index];
        if let (Some(reason), Some(flag)) = ((control.inert)(&scene), control.flag) {
            if !warned.contains(&flag.long) {
                log::warn!("--{}: {reason}", flag.long);
                warned.push(flag.long);
            }
        }
    }
    scene.started();
    Ok(Box::new(scene))
}

impl PartialEq for SceneDescriptor {
    fn eq(&self, other: &Self) -> bool {
        self.name == other.name
    }
}

impl Eq for SceneDescriptor {}

impl fmt::Debug for SceneDescriptor {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "SceneDescriptor({})", self.name)
    }
}

impl fmt::Display for SceneDescriptor {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name)
    }
}

/// Every scene type's table, seen through `dyn Scene`.
impl<S: SceneType> SceneControls for S {
    fn controls(&self) -> Vec<ControlState> {
        S::CONTROLS
            .iter()
            .enumerate()
            .map(|(i, c)| c.state(i, self))
            .collect()
    }

    /// Only the titled controls are read (the title is set after every frame).
    fn title_status(&self) -> Vec<String> {
        S::CONTROLS
            .iter()
            .filter_map(|c| Some((c.title?, c)))
            .filter(|(_, c)| (c.inert)(self).is_none())
            .map(|(title, c)| format!("{title} {}", c.shown(self)))
            .collect()
    }

    fn table_status(&self) -> Vec<String> {
        S::CONTROLS
            .iter()
            .filter(|c| !matches!(c.kind, Kind::Press { .. }))
            .filter(|c| (c.inert)(self).is_none())
            .map(|c| format!("{} {}", c.label, c.shown(self)))
            .collect()
    }

    fn set_control(&mut self, index: usize, to: SetTo) -> Result<()> {
        let Some(control) = S::CONTROLS.get(index) else {
            log::warn!("no control {index}");
            return Ok(());
        };
        if let Some(reason) = (control.inert)(self) {
            log::warn!("{}: changes nothing now: {reason}", control.label);
        }
        control.set(self, to)
    }

    fn press_key(&mut self, key: char) -> Result<bool> {
        let Some(index) = control_for_key(S::CONTROLS, key) else {
            return Ok(false);
        };
        let to = S::CONTROLS[index].key_press(self);
        self.set_control(index, to).map(|()| true)
    }
}
