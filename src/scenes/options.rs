//! What a scene is built with: its own command-line arguments ([`SceneArgs`], what no control of
//! its table holds: files), the options they give, and the starts of its controls ([`Starts`]), all
//! kept by type in [`SceneOptions`].

use std::any::Any;
use std::fmt;
use std::path::{Path, PathBuf};

use super::flags::{Shared, SharedArgs};
use super::starts::{Setting, Starts};
use crate::assets::{crate_assets_dir, find_assets, say_taken_from_crate};
use crate::Result;

/// A scene's own command-line arguments (a `clap::Args` struct in its folder): what no control of
/// its table holds (the cylinder's `--model` and maps), and the options they give.
pub trait SceneArgs: clap::Args + clap::FromArgMatches {
    /// What the scene is built with; its `Default` is the scene without any flag.
    type Options: SceneOption + Clone + Default;

    /// The flags several scenes share that these arguments read (beside those its table's
    /// controls read): the sprite's `--light`, whose X and Y no control holds.
    const SHARED: &'static [Shared] = &[];

    /// The options these arguments (and the flags several scenes share) ask for, or why they
    /// cannot be (a value this scene cannot use: the message names the flag).
    fn options(&self, shared: &SharedArgs) -> std::result::Result<Self::Options, String>;
}

/// A scene's own arguments as its type names them ([`super::SceneType::ARGS`]): none, or a
/// [`SceneArgs`] struct's.
#[derive(Clone, Copy)]
pub struct OwnArgs {
    /// Adds the arguments to the command.
    pub(super) augment: fn(clap::Command) -> clap::Command,
    /// Reads them (and the shared flags) into [`SceneOptions`].
    pub(super) read:
        fn(&clap::ArgMatches, &mut SceneOptions) -> std::result::Result<(), clap::Error>,
    /// [`SceneArgs::SHARED`].
    pub(super) shared: &'static [Shared],
}

impl OwnArgs {
    /// No arguments of its own: every flag the scene reads is a control's.
    pub const NONE: OwnArgs = OwnArgs {
        augment: |command| command,
        read: |_, _| Ok(()),
        shared: &[],
    };

    /// The arguments of `A`.
    pub const fn of<A: SceneArgs>() -> OwnArgs {
        OwnArgs {
            augment: <A as clap::Args>::augment_args,
            read: read_args::<A>,
            shared: A::SHARED,
        }
    }
}

/// [`OwnArgs::read`] for a scene whose arguments are `A`.
fn read_args<A: SceneArgs>(
    matches: &clap::ArgMatches,
    options: &mut SceneOptions,
) -> std::result::Result<(), clap::Error> {
    let shared = <SharedArgs as clap::FromArgMatches>::from_arg_matches(matches)?;
    let args = A::from_arg_matches(matches)?;
    let value = args.options(&shared).map_err(|message| {
        clap::Error::raw(clap::error::ErrorKind::ValueValidation, message + "\n")
    })?;
    options.set(value);
    Ok(())
}

/// A value a scene is built with (its options type): any plain data.
pub trait SceneOption: Any + fmt::Debug + Send + Sync {
    fn clone_box(&self) -> Box<dyn SceneOption>;
    fn option_any(&self) -> &dyn Any;
    fn option_any_mut(&mut self) -> &mut dyn Any;
}

impl<T: Any + Clone + fmt::Debug + Send + Sync> SceneOption for T {
    fn clone_box(&self) -> Box<dyn SceneOption> {
        Box::new(self.clone())
    }
    fn option_any(&self) -> &dyn Any {
        self
    }
    fn option_any_mut(&mut self) -> &mut dyn Any {
        self
    }
}

impl Clone for Box<dyn SceneOption> {
    fn clone(&self) -> Self {
        // `(**self)`: the boxed value's clone, not the blanket impl's clone of the box itself.
        (**self).clone_box()
    }
}

/// Where the scenes' files come from, each scene's options and the starts of its controls (by type:
/// a scene that finds none of its type starts with its defaults). A new scene needs no field here.
#[derive(Debug, Clone, Default)]
pub struct SceneOptions {
    /// `--assets DIR`; `None` = the crate's own assets/ folder.
    pub assets: Option<PathBuf>,
    /// `--shaders DIR`; `None` = the crate's shaders/ folder, else the copies built into the binary.
    pub shaders: Option<PathBuf>,
    /// Each scene's options, by type (through [`SceneOptions::get`] and [`SceneOptions::set`]).
    pub per_scene: PerScene,
}

/// The scenes' options, one value of each type (see [`SceneOptions`]).
#[derive(Debug, Clone, Default)]
pub struct PerScene(Vec<Box<dyn SceneOption>>);

impl SceneOptions {
    /// The asset files `names` (paths under the assets folder) for one scene load: each from
    /// `--assets` where it is there, else the crate's own copy, with one notice naming the files
    /// taken from the crate (each file once per process, so that Enter cycling through the scenes
    /// does not repeat it). A file that is there but broken is its loader's error, naming it.
    pub fn asset_files<const N: usize>(&self, names: [&str; N]) -> Result<[PathBuf; N]> {
        let Some(dir) = &self.assets else {
            return Ok(names.map(|name| crate_assets_dir().join(name)));
        };
        let found = find_assets(dir, &crate_assets_dir(), names)?;
        say_taken_from_crate(dir, &found.missing);
        Ok(found.paths)
    }

    /// The shader folder given on the command line, if any.
    pub fn shader_dir(&self) -> Option<&Path> {
        self.shaders.as_deref()
    }

    /// The options of type `T`, or `T`'s defaults.
    pub fn get<T: SceneOption + Clone + Default>(&self) -> T {
        self.find::<T>().cloned().unwrap_or_default()
    }

    /// The options of type `T` to change (set to `T`'s defaults first if there were none).
    pub fn get_mut<T: SceneOption + Default>(&mut self) -> &mut T {
        let i = match self.position::<T>() {
            Some(i) => i,
            None => {
                self.per_scene.0.push(Box::new(T::default()));
                self.per_scene.0.len() - 1
            }
        };
        let any = (*self.per_scene.0[i]).option_any_mut();
        any.downcast_mut().expect("found by its type")
    }

    /// Replaces the options of `value`'s type.
    pub fn set<T: SceneOption + Default>(&mut self, value: T) {
        *self.get_mut::<T>() = value;
    }

    /// These options with `value` set.
    pub fn with<T: SceneOption + Default>(mut self, value: T) -> Self {
        self.set(value);
        self
    }

    /// Starts a control of scene type `S` as `setting` says (a typed handle's value, see
    /// [`super::starts::Handle::to`]), through its table once the scene is built, as its flag
    /// would; it replaces an earlier start of the same control.
    pub fn start<S: 'static>(&mut self, setting: Setting<S>) -> &mut Self {
        self.get_mut::<Starts<S>>().set(setting);
        self
    }

    /// These options with each of `settings` started ([`SceneOptions::start`]).
    pub fn starting<S: 'static>(mut self, settings: impl IntoIterator<Item = Setting<S>>) -> Self {
        for setting in settings {
            self.start(setting);
        }
        self
    }

    fn position<T: SceneOption>(&self) -> Option<usize> {
        self.per_scene
            .0
            .iter()
            .position(|o| (**o).option_any().is::<T>())
    }

    fn find<T: SceneOption>(&self) -> Option<&T> {
        let i = self.position::<T>()?;
        (*self.per_scene.0[i]).option_any().downcast_ref()
    }
}
