//! The seam between the front ends and a program: what a scene is built on, what it gets each frame,
//! what it must answer, and how it describes itself ([`SceneDescriptor`]). The list of scenes
//! ([`super::SCENES`]) sits above the scenes and this file below them, so no scene imports the module
//! that imports it.

use std::any::Any;
use std::ffi::{c_void, CStr};
use std::fmt;
use std::io;
use std::path::{Path, PathBuf};
use std::sync::{Mutex, PoisonError};

use glam::{Mat4, Vec2};

use super::table::{Control, KeyHelp, SceneControls};
use crate::gl::{ContextInfo, Gl};
use crate::{Error, Result};

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
    /// Which of the flags several scenes read ([`SharedArgs`]) this one reads, by argument id.
    pub shared_args: &'static [&'static str],
    /// Reads the scene's arguments from the parsed command line into [`SceneOptions`].
    pub read_args: fn(&clap::ArgMatches, &mut SceneOptions) -> std::result::Result<(), clap::Error>,
    /// Loads the scene on the current context, with its options from `options` (its defaults where
    /// `options` holds none).
    pub build: fn(&SceneContext, &SceneOptions) -> Result<Box<dyn Scene>>,
    /// The files `make-assets` generates for the scene: paths under the assets folder, and bytes.
    pub generate_assets: fn() -> Result<crate::assets::GeneratedFiles>,
    /// A file dropped on the window: puts it into the scene's options and returns `true` if the
    /// scene opens files of its kind (the cylinder opens an `.obj` as `--model`).
    pub open_file: fn(&Path, &mut SceneOptions) -> bool,
}

impl SceneDescriptor {
    /// The descriptor of scene type `S`: mouse look, no mouse help, no shared flags, no generated
    /// files (a scene that differs sets those fields over this one).
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
            args: <S::Args as clap::Args>::augment_args,
            shared_args: &[],
            read_args: read_args::<S::Args>,
            build: build::<S>,
            generate_assets: || Ok(Vec::new()),
            open_file: |_, _| false,
        }
    }
}

/// A scene's type as its folder defines it: its arguments, and how it loads.
pub trait SceneType: Scene + Sized + 'static {
    /// The scene's command-line arguments, and through them its options type.
    type Args: SceneArgs;

    /// Every switch, choice and slider of the scene, each declared once (see [`Control`]).
    const CONTROLS: &'static [Control<Self>];

    /// Loads the scene on the current context: its files from `files` (`--assets`, `--shaders`),
    /// its switches from `options`.
    fn new(
        context: &SceneContext,
        files: &SceneOptions,
        options: <Self::Args as SceneArgs>::Options,
    ) -> Result<Self>;
}

/// [`SceneDescriptor::build`] of scene type `S`, with its options from `options`.
fn build<S: SceneType>(context: &SceneContext, options: &SceneOptions) -> Result<Box<dyn Scene>> {
    Ok(Box::new(S::new(context, options, options.get())?))
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

/// A scene's command-line arguments (a `clap::Args` struct in its folder) and the options they give.
pub trait SceneArgs: clap::Args + clap::FromArgMatches {
    /// What the scene is built with; its `Default` is the scene without any flag.
    type Options: SceneOption + Clone + Default;

    /// The options these arguments (and the flags several scenes share) ask for, or why they
    /// cannot be (a value this scene cannot use: the message names the flag).
    fn options(&self, shared: &SharedArgs) -> std::result::Result<Self::Options, String>;
}

/// Arguments that are the scene's options as they are (a scene whose every switch is a flag).
pub trait OwnOptions: clap::Args + clap::FromArgMatches + SceneOption + Clone + Default {}

impl<T: OwnOptions> SceneArgs for T {
    type Options = T;

    fn options(&self, _shared: &SharedArgs) -> std::result::Result<T, String> {
        Ok(self.clone())
    }
}

/// [`SceneDescriptor::read_args`] for a scene whose arguments are `A`.
pub fn read_args<A: SceneArgs>(
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

// Flags that mean the same in several scenes: each scene's descriptor names those it reads, so that
// one given to a scene that does not read it is an error, not ignored. (A plain comment: clap would
// make a doc comment the program's `about`.)
#[derive(clap::Args, Debug, Clone, Default)]
#[command(next_help_heading = "Several scenes")]
pub struct SharedArgs {
    /// Normal map's green channel: up the picture (OpenGL, the tutorial's) or down (DirectX) (key Y)
    #[arg(long, value_enum, value_name = "DIR", default_value_t = crate::normalmap::Green::Up)]
    pub green: crate::normalmap::Green,

    /// Where the light is. cylinder: X,Y,Z in world space [default: the tutorial's lightPos 0,0,4],
    /// or in the model's own coordinates with --model [default: where the tutorial's light is
    /// beside its cylinder, scaled to the model]. sprite: X,Y across the window (0 to 1, y up) and
    /// the height Z > 0 [default: 0.4,0.6,0.075]; in the window the mouse takes over once it moves
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_vec3, allow_hyphen_values = true)]
    pub light: Option<glam::Vec3>,
}

/// `X,Y,Z` of three finite numbers.
pub fn parse_vec3(s: &str) -> std::result::Result<glam::Vec3, String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    let [x, y, z] = parts[..] else {
        return Err(format!("'{s}' is not X,Y,Z, e.g. 0,0,4"));
    };
    let parse = |v: &str| {
        v.parse::<f32>()
            .ok()
            .filter(|n| n.is_finite())
            .ok_or_else(|| format!("'{v}' is not a finite number"))
    };
    Ok(glam::Vec3::new(parse(x)?, parse(y)?, parse(z)?))
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

/// Where the scenes' files come from, and each scene's options (by type: a scene that finds none of
/// its type starts with its defaults). A new scene needs no field here.
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

/// The crate's own assets/ folder, wherever the binary is started from.
pub fn crate_assets_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("assets")
}

/// Where one scene load's asset files are (see [`find_assets`]).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct AssetFiles<const N: usize> {
    /// Each file: in the `--assets` folder where it is there, else the crate's copy.
    pub paths: [PathBuf; N],
    /// The files the `--assets` folder lacks (their paths in it), whose crate's copies `paths` holds.
    pub missing: Vec<PathBuf>,
}

/// Finds each of `names` in `dir` (the `--assets` folder), else in `crate_dir`. A file in neither is
/// an error naming the one in `dir` (what the user asked for) and saying the crate's is missing too;
/// a file that `dir` has is taken as it is, readable or not (its loader names it if it is broken).
pub fn find_assets<const N: usize>(
    dir: &Path,
    crate_dir: &Path,
    names: [&str; N],
) -> Result<AssetFiles<N>> {
    let mut missing = Vec::new();
    let mut paths = Vec::with_capacity(N);
    for name in names {
        let (asked, own) = (dir.join(name), crate_dir.join(name));
        // `dir` being the crate's folder, its loader says what is wrong with the file.
        if own == asked || asked.try_exists().map_err(|e| Error::io(&asked, e))? {
            paths.push(asked);
        } else if own.is_file() {
            missing.push(asked);
            paths.push(own);
        } else {
            let reason = format!(
                "no such file, and the crate's own {} is missing too (make-assets writes it)",
                own.display()
            );
            let error = io::Error::new(io::ErrorKind::NotFound, reason);
            return Err(Error::io(asked, error));
        }
    }
    let paths = paths.try_into().expect("one path per name");
    Ok(AssetFiles { paths, missing })
}

/// Every file of an `--assets` folder that this process took from the crate's assets/ instead, in
/// the order they were first missed: each is said once (see [`SceneOptions::asset_files`]).
static TAKEN_FROM_CRATE: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// The files (their paths in an `--assets` folder) taken from the crate's assets/ so far in this
/// process: those the notices have named.
pub fn taken_from_crate() -> Vec<PathBuf> {
    TAKEN_FROM_CRATE
        .lock()
        .unwrap_or_else(PoisonError::into_inner)
        .clone()
}

/// One notice for a scene load: the files of `missing` (in `dir`) not said before in this process.
fn say_taken_from_crate(dir: &Path, missing: &[PathBuf]) {
    let mut taken = TAKEN_FROM_CRATE
        .lock()
        .unwrap_or_else(PoisonError::into_inner);
    let mut new = Vec::new();
    for path in missing {
        if !taken.contains(path) {
            taken.push(path.clone());
            new.push(path.strip_prefix(dir).unwrap_or(path).display().to_string());
        }
    }
    if !new.is_empty() {
        log::warn!(
            "--assets {} has no {}: using the crate's own from {} (made by make-assets)",
            dir.display(),
            new.join(", "),
            crate_assets_dir().display()
        );
    }
}

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

/// How a scene wants the mouse (see [`SceneDescriptor::mouse_mode`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MouseMode {
    /// The tutorial's mouse look: the cursor is grabbed and hidden, motion turns the camera.
    Look,
    /// The cursor stays free and visible; its position reaches the scene in [`FrameInput::cursor`]
    /// (a 2D light that follows it).
    Cursor,
}

/// The seam between the front ends and a program.
pub trait Scene: AsAny + SceneControls {
    /// Draws one frame into the bound framebuffer (the front end has set the viewport): the scene
    /// clears it itself, as the tutorial's loop does.
    fn draw(&mut self, frame: &FrameInput);

    /// A key of the scene's list was pressed (letters either case). `Ok(false)`: not one of its
    /// keys. The key of each control of the scene's table ([`SceneType::CONTROLS`]).
    fn key(&mut self, key: char) -> Result<bool> {
        self.press_key(key)
    }

    /// One line for the log: the scene's current switches.
    fn status(&self) -> String;

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

/// The program of `names` (vertex and fragment shader, read from `dir` as the scene reads them) as
/// the panel names it.
pub fn drawing_program(name: &str, names: [&'static str; 2], dir: Option<&Path>) -> DrawingProgram {
    DrawingProgram {
        name: name.into(),
        shaders: names.to_vec(),
        dir: dir.map(Path::to_path_buf),
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

/// For tests and tools that reach into a particular scene: every scene has it, none writes it.
pub trait AsAny: Any {
    fn as_any(&self) -> &dyn Any;
    fn as_any_mut(&mut self) -> &mut dyn Any;
}

impl<T: Any> AsAny for T {
    fn as_any(&self) -> &dyn Any {
        self
    }
    fn as_any_mut(&mut self) -> &mut dyn Any {
        self
    }
}
