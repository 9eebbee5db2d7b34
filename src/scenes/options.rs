//! What a scene is built with: its command-line arguments ([`SceneArgs`], the flags several scenes
//! share in [`SharedArgs`]) and the options they give, kept by type in [`SceneOptions`].

use std::any::Any;
use std::fmt;
use std::path::{Path, PathBuf};

use crate::assets::{crate_assets_dir, find_assets, say_taken_from_crate};
use crate::Result;

/// A scene's command-line arguments (a `clap::Args` struct in its folder) and the options they give.
pub trait SceneArgs: clap::Args + clap::FromArgMatches {
    /// What the scene is built with; its `Default` is the scene without any flag.
    type Options: SceneOption + Clone + Default;

    /// The options these arguments (and the flags several scenes share) ask for, or why they
    /// cannot be (a value this scene cannot use: the message names the flag).
    fn options(&self, shared: &SharedArgs) -> std::result::Result<Self::Options, String>;
}

/// Arguments that are the scene's options as they are (a scene whose every switch is a flag).
pub trait OwnOptions: clap::Args + clap::FromArgMatches + SceneOption + Clone + Default {
    /// These options with the shared flags the scene reads: none unless it says.
    fn with_shared(self, _shared: &SharedArgs) -> Self {
        self
    }
}

impl<T: OwnOptions> SceneArgs for T {
    type Options = T;

    fn options(&self, shared: &SharedArgs) -> std::result::Result<T, String> {
        Ok(self.clone().with_shared(shared))
    }
}

/// `--light` and `--light-power` as a scene with one point light in world space reads them;
/// `None`: the scene's own.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct LightFlags {
    pub position: Option<glam::Vec3>,
    pub power: Option<f32>,
}

impl LightFlags {
    pub fn of(shared: &SharedArgs) -> Self {
        LightFlags {
            position: shared.light,
            power: shared.light_power,
        }
    }
}

/// [`super::SceneDescriptor::read_args`] for a scene whose arguments are `A`.
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
    /// the height Z > 0 [default: 0.4,0.6,0.075]; in the window the mouse takes over once it moves.
    /// cube, wall: X,Y,Z in world space [default: the article's, -4,1.5,6 and 4,0,4]
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_vec3, allow_hyphen_values = true)]
    pub light: Option<glam::Vec3>,

    /// The light's power, as the panel's slider sets it [default: the tutorial's LightPower 40;
    /// cube: a factor 1 on its light; wall: the article's intensity 50]
    #[arg(long, value_name = "P", value_parser = parse_power)]
    pub light_power: Option<f32>,
}

/// A flag of [`SharedArgs`], as a scene's descriptor names those it reads
/// ([`super::SceneDescriptor::shared_args`]): a misspelt one does not compile, and a unit test
/// checks that every field of [`SharedArgs`] has one.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Shared {
    Green,
    Light,
    LightPower,
}

impl Shared {
    pub const ALL: [Shared; 3] = [Shared::Green, Shared::Light, Shared::LightPower];

    /// Its argument's id in [`SharedArgs`] (clap's: the field's name).
    pub const fn id(self) -> &'static str {
        match self {
            Shared::Green => "green",
            Shared::Light => "light",
            Shared::LightPower => "light_power",
        }
    }

    /// The flag whose argument id is `id`.
    pub fn of_id(id: &str) -> Option<Shared> {
        Shared::ALL.into_iter().find(|s| s.id() == id)
    }
}

/// A finite number (a flag's value: NaN and infinities refused).
pub fn parse_finite(s: &str) -> std::result::Result<f32, String> {
    s.trim()
        .parse::<f32>()
        .ok()
        .filter(|f| f.is_finite())
        .ok_or_else(|| format!("'{s}' is not a finite number"))
}

/// A light's power: a finite number, 0 or more.
fn parse_power(s: &str) -> std::result::Result<f32, String> {
    parse_finite(s)
        .ok()
        .filter(|p| *p >= 0.0)
        .ok_or_else(|| format!("'{s}' is not a finite number of 0 or more"))
}

/// `X,Y,Z` of three finite numbers.
pub fn parse_vec3(s: &str) -> std::result::Result<glam::Vec3, String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    let [x, y, z] = parts[..] else {
        return Err(format!("'{s}' is not X,Y,Z, e.g. 0,0,4"));
    };
    Ok(glam::Vec3::new(
        parse_finite(x)?,
        parse_finite(y)?,
        parse_finite(z)?,
    ))
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

#[cfg(test)]
mod tests {
    use super::*;

    // Fails if a field of SharedArgs has no `Shared` (a scene could not say it reads it) or a
    // `Shared` names no argument of SharedArgs: the two lists must be the same, in order.
    #[test]
    fn every_shared_flag_has_its_name() {
        let command = <SharedArgs as clap::Args>::augment_args(clap::Command::new("shared"));
        let ids: Vec<String> = command
            .get_arguments()
            .map(|a| a.get_id().to_string())
            .collect();
        let named: Vec<&str> = Shared::ALL.iter().map(|s| s.id()).collect();
        assert_eq!(ids, named);
        for flag in Shared::ALL {
            assert_eq!(Shared::of_id(flag.id()), Some(flag));
        }
    }
}
