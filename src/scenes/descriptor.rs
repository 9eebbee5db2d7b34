//! How a scene describes itself to the rest of the program ([`SceneDescriptor`]) and what its type
//! gives for it ([`SceneType`]). The list of scenes ([`super::SCENES`]) sits above the scenes and
//! this file below them, so no scene imports the module that imports it.

use std::fmt;
use std::path::Path;

use super::flags::Shared;
use super::options::{OwnArgs, SceneOptions};
use super::scene::{MouseMode, Scene, SceneContext};
use super::starts::{Setting, Starts};
use super::table::{
    control_for_key, Control, ControlState, KeyHelp, KeyList, Kind, SceneControls, SetTo,
};
use crate::gl::state::GlState;
use crate::Result;

/// All the rest of the program knows of a scene, made from its type by [`SceneDescriptor::of`]: one
/// line in [`super::SCENES`] adds it to the command line, the Enter key, `--help` and `docs/keys.md`.
pub struct SceneDescriptor {
    /// The `--scene` name ([`SceneType::NAME`]).
    pub name: &'static str,
    /// One line for `--help`, the README and the title: what the scene shows and where it comes from.
    pub description: &'static str,
    /// Mouse look (the tutorial's) or a free cursor.
    pub mouse_mode: MouseMode,
    /// The scene's keys: those of its table ([`SceneType::CONTROLS`]), in its order.
    pub keys: &'static [KeyHelp],
    /// What the mouse, wheel and click do in a scene with [`MouseMode::Cursor`] (mouse-look scenes
    /// have the window's mouse look and list nothing here).
    pub mouse_help: &'static [(&'static str, &'static str)],
    /// The scene's command-line arguments, under a heading of its own: its own (files), then the
    /// flag of each control of its table that has one.
    pub args: fn(clap::Command) -> clap::Command,
    /// Which of the flags several scenes share ([`super::flags::SharedArgs`]) the scene reads:
    /// those its table's controls read, and those its own arguments read.
    pub shared_args: SharedFlags,
    /// Reads the scene's arguments and its controls' flags from the parsed command line into
    /// [`SceneOptions`].
    pub read_args: fn(&clap::ArgMatches, &mut SceneOptions) -> std::result::Result<(), clap::Error>,
    /// Loads the scene on the current context, with its options and its controls' starts from
    /// `options` (its defaults where `options` holds none).
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

    /// The descriptor of scene type `S`.
    pub const fn of<S: SceneType>() -> Self {
        SceneDescriptor {
            name: S::NAME,
            description: S::DESCRIPTION,
            mouse_mode: S::MOUSE_MODE,
            keys: <S as Derived>::KEYS.as_slice(),
            mouse_help: S::MOUSE_HELP,
            args: scene_args::<S>,
            shared_args: SharedFlags::of(S::CONTROLS, S::ARGS.shared),
            read_args: read_scene_args::<S>,
            build: build::<S>,
            generate_assets: S::generate_assets,
            asset_files: S::ASSET_FILES,
            open_file: S::open_file,
            gl_state: S::GL_STATE,
        }
    }
}

/// A scene's type: all a new scene gives beside its [`Scene`] methods (only `Scene::draw` is
/// required there). Its name, description, GL state, table of controls and `new` are required; the
/// rest have defaults for a mouse-look scene without files of its own.
pub trait SceneType: Scene + Sized + 'static {
    /// The `--scene` name.
    const NAME: &'static str;

    /// One line for `--help`, the README and the title: what the scene shows and where it comes
    /// from.
    const DESCRIPTION: &'static str;

    /// The GL state the scene draws in (clear colour, depth test, culling): the host sets it before
    /// each frame, as another scene may have drawn on the context since this one was built.
    const GL_STATE: GlState;

    /// Every switch, choice and slider of the scene, each declared once (see [`Control`]), with
    /// its key and its flag.
    const CONTROLS: &'static [Control<Self>];

    /// Loads the scene on the current context: its files from `options` (`--assets`, `--shaders`,
    /// its own arguments' options). Its controls start as the scene makes them here; `starts` then
    /// sets those a flag or a caller gives, through the table, once the scene is built (a scene
    /// whose load depends on one takes it first: [`Starts::take`]).
    fn new(
        context: &SceneContext,
        options: &SceneOptions,
        starts: &mut Starts<Self>,
    ) -> Result<Self>;

    /// Mouse look (the tutorial's) unless the scene says.
    const MOUSE_MODE: MouseMode = MouseMode::Look;

    /// What the mouse does in a scene with [`MouseMode::Cursor`].
    const MOUSE_HELP: &'static [(&'static str, &'static str)] = &[];

    /// The scene's own command-line arguments, for what no control holds (files): none unless it
    /// says ([`OwnArgs::of`] its [`super::SceneArgs`] struct).
    const ARGS: OwnArgs = OwnArgs::NONE;

    /// The paths (under the assets folder) of the files `make-assets` generates for the scene.
    const ASSET_FILES: &'static [&'static str] = &[];

    /// Those files, generated: none unless the scene says.
    fn generate_assets() -> Result<crate::assets::GeneratedFiles> {
        Ok(Vec::new())
    }

    /// A file dropped on the window: `true` if the scene opens it (having put it in `options`).
    fn open_file(_path: &Path, _options: &mut SceneOptions) -> bool {
        false
    }

    /// Once the scene is built and its starts are set through its table: what it says of the state
    /// it starts in (a warning that a flag may have made moot). Nothing unless the scene says.
    fn started(&mut self) {}
}

/// What [`SceneDescriptor::of`] works out from a scene type once, when the crate is built.
trait Derived: SceneType {
    /// The key list of its table.
    const KEYS: &'static KeyList;
    /// "Scene NAME": the heading its flags are listed under in `--help`.
    const HEADING: &'static Heading;
}

impl<S: SceneType> Derived for S {
    const KEYS: &'static KeyList = &KeyList::of(S::CONTROLS);
    const HEADING: &'static Heading = &Heading::of(S::NAME);
}

/// "Scene NAME", made when the crate is built (clap takes a heading as a `&'static str`).
struct Heading {
    text: [u8; 64],
    len: usize,
}

impl Heading {
    const fn of(name: &str) -> Heading {
        let mut text = [0; 64];
        let (prefix, name) = (b"Scene ", name.as_bytes());
        assert!(
            prefix.len() + name.len() <= text.len(),
            "a scene's name is too long"
        );
        let mut len = 0;
        while len < prefix.len() + name.len() {
            text[len] = match len < prefix.len() {
                true => prefix[len],
                false => name[len - prefix.len()],
            };
            len += 1;
        }
        Heading { text, len }
    }

    const fn as_str(&'static self) -> &'static str {
        match std::str::from_utf8(self.text.split_at(self.len).0) {
            Ok(text) => text,
            Err(_) => panic!("a scene's name is not UTF-8"),
        }
    }
}

/// The flags several scenes share that one scene reads (see [`SceneDescriptor::shared_args`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SharedFlags([bool; Shared::ALL.len()]);

impl SharedFlags {
    /// Those the flags of `controls` read, and `also`.
    const fn of<S>(controls: &[Control<S>], also: &[Shared]) -> SharedFlags {
        let mut read = [false; Shared::ALL.len()];
        let mut i = 0;
        while i < controls.len() {
            if let Some(flag) = &controls[i].flag {
                if let Some(shared) = flag.shared() {
                    read[shared as usize] = true;
                }
            }
            i += 1;
        }
        i = 0;
        while i < also.len() {
            read[also[i] as usize] = true;
            i += 1;
        }
        SharedFlags(read)
    }

    /// Whether `flag` is one of them.
    pub fn contains(&self, flag: &Shared) -> bool {
        self.0[*flag as usize]
    }
}

/// [`SceneDescriptor::args`] of scene type `S`: under its heading, its own arguments, then the flag
/// of each control of its table that has one ([`Flag`](super::flags::Flag)).
fn scene_args<S: SceneType>(command: clap::Command) -> clap::Command {
    // The heading stays set for every argument added after it.
    let command = (S::ARGS.augment)(command.next_help_heading(<S as Derived>::HEADING.as_str()));
    let flags = S::CONTROLS
        .iter()
        .filter_map(|control| Some(control.flag?.args(control.key)))
        .flatten();
    command.args(flags)
}

/// [`SceneDescriptor::read_args`] of scene type `S`: its own arguments' options, and a start for
/// each control whose flag was given.
fn read_scene_args<S: SceneType>(
    matches: &clap::ArgMatches,
    options: &mut SceneOptions,
) -> std::result::Result<(), clap::Error> {
    (S::ARGS.read)(matches, options)?;
    for (index, control) in S::CONTROLS.iter().enumerate() {
        let Some(flag) = control.flag else { continue };
        if let Some(start) = flag.read(matches) {
            options.start(Setting::<S>::from_flag(
                S::CONTROLS,
                index,
                start,
                flag.long,
            ));
        }
    }
    Ok(())
}

/// [`SceneDescriptor::build`] of scene type `S`: the scene loaded, then its starts set through its
/// table ([`Starts::apply`]).
fn build<S: SceneType>(context: &SceneContext, options: &SceneOptions) -> Result<Box<dyn Scene>> {
    let mut starts = options.get::<Starts<S>>();
    let mut scene = S::new(context, options, &mut starts)?;
    starts.apply(&mut scene)?;
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
