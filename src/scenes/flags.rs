//! A control's command-line flag ([`Flag`]): the argument the descriptor declares for it, or the
//! flag several scenes share that it reads ([`SharedArgs`], [`Shared`]), and the start ([`Start`])
//! it gives the control, which the table sets once the scene is built (see
//! [`Control::flag`](super::table::Control::flag), [`Control::value_flag`](super::table::Control::value_flag)
//! and [`Control::shared_flag`](super::table::Control::shared_flag)). The parsers of the flags'
//! numbers are here too.

use std::fmt;

/// A control's command-line flag: given, the scene starts with the control at the flag's value,
/// set through the table once the scene is built, as its key or the panel would set it. Its help
/// line is `help` and the key ("(key L)").
#[derive(Clone, Copy)]
pub struct Flag {
    /// The flag without its dashes (`debug-lines`), also its argument's id (a shared flag's id is
    /// [`Shared::id`]).
    pub long: &'static str,
    pub help: &'static str,
    pub takes: Takes,
    /// A switch that only goes with this flag and changes the start it gives (`--compare-difference`
    /// with `--compare`): its name without dashes and its help line. `read` reads it.
    pub modifier: Option<(&'static str, &'static str)>,
}

/// What a flag takes, and how its control's start is read from the parsed command line.
#[derive(Clone, Copy)]
pub enum Takes {
    /// No value (a toggle's): given, it starts the toggle `value` (`--debug-lines` on,
    /// `--no-handedness` off).
    Switch(bool),
    /// A value named `value_name` in `--help`: `arg` gives the argument its parser (`None`: the
    /// argument is another control's flag of the same name, of which this control takes a part, as
    /// the colour view's component is part of `--view`), `read` the control's start from it.
    Value {
        value_name: &'static str,
        arg: Option<fn(clap::Arg) -> clap::Arg>,
        read: fn(&clap::ArgMatches, &str) -> Option<Start>,
    },
    /// A flag several scenes share, declared once in [`SharedArgs`] (its help names the scenes
    /// whose tables read it): `read` the control's start from the argument of id [`Shared::id`].
    Shared {
        flag: Shared,
        read: fn(&clap::ArgMatches, &str) -> Option<Start>,
    },
}

/// A flag's start value for its control.
#[derive(Clone)]
pub enum Start {
    Toggle(bool),
    /// One of a choice's typed values (the `T` of its [`Choices`](super::table::Choices)).
    Choice(std::sync::Arc<dyn std::any::Any + Send + Sync>),
    /// A slider's value, which the table does not clamp: a flag may go past what a drag reaches
    /// (`--normal-strength 8`); the panel's range is the sliders' room, not the scene's limit.
    Slider(f32),
}

impl Start {
    /// A choice's start: `value`, of the choice's own type.
    pub fn choice<T: Send + Sync + 'static>(value: T) -> Start {
        Start::Choice(std::sync::Arc::new(value))
    }
}

impl fmt::Debug for Start {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Start::Toggle(on) => write!(f, "Toggle({on})"),
            Start::Choice(_) => f.write_str("Choice(..)"),
            Start::Slider(value) => write!(f, "Slider({value})"),
        }
    }
}

impl Flag {
    /// Its line in `--help`: what it does, and the key that does it later.
    pub fn help_line(&self, key: Option<char>) -> String {
        match key {
            Some(key) => format!("{} (key {key})", self.help),
            None => self.help.to_string(),
        }
    }

    /// The value a toggle's flag starts it with (`None` for a flag that takes a value).
    pub fn toggle_value(&self) -> Option<bool> {
        match self.takes {
            Takes::Switch(value) => Some(value),
            Takes::Value { .. } | Takes::Shared { .. } => None,
        }
    }

    /// The flag several scenes share that it is, if it is one.
    pub const fn shared(&self) -> Option<Shared> {
        match self.takes {
            Takes::Shared { flag, .. } => Some(flag),
            Takes::Switch(_) | Takes::Value { .. } => None,
        }
    }

    /// Its clap arguments: its own (none where another control's flag of the same name declares
    /// it, or [`SharedArgs`] does), then its modifier's.
    pub fn args(&self, key: Option<char>) -> Vec<clap::Arg> {
        let arg = clap::Arg::new(self.long)
            .long(self.long)
            .help(self.help_line(key));
        let own = match self.takes {
            Takes::Switch(_) => Some(arg.action(clap::ArgAction::SetTrue)),
            Takes::Value {
                value_name,
                arg: declare,
                ..
            } => declare.map(|declare| declare(arg.value_name(value_name))),
            Takes::Shared { .. } => None,
        };
        let modifier = self.modifier.map(|(long, help)| {
            clap::Arg::new(long)
                .long(long)
                .help(help)
                .action(clap::ArgAction::SetTrue)
                .requires(self.long)
        });
        own.into_iter().chain(modifier).collect()
    }

    /// The start it gives its control, if it was given.
    pub fn read(&self, matches: &clap::ArgMatches) -> Option<Start> {
        match self.takes {
            Takes::Switch(value) => {
                let given = given::<bool>(matches, self.long) == Some(&true);
                given.then_some(Start::Toggle(value))
            }
            Takes::Value { read, .. } => read(matches, self.long),
            Takes::Shared { flag, read } => read(matches, flag.id()),
        }
    }
}

/// Flags compare by name: two controls' flags of one name are one argument.
impl PartialEq for Flag {
    fn eq(&self, other: &Self) -> bool {
        self.long == other.long
    }
}

impl fmt::Debug for Flag {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Flag(--{})", self.long)
    }
}

/// [`Takes::Value`]'s `arg` of a choice whose values are a clap `ValueEnum` (their command-line
/// names are the enum's).
pub fn enum_arg<T: clap::ValueEnum + Send + Sync + 'static>(arg: clap::Arg) -> clap::Arg {
    arg.value_parser(clap::builder::EnumValueParser::<T>::new())
}

/// The value of the argument `id` as parsed, if it was given (and is a `T`).
pub fn given<'a, T: Clone + Send + Sync + 'static>(
    matches: &'a clap::ArgMatches,
    id: &str,
) -> Option<&'a T> {
    matches.try_get_one::<T>(id).ok().flatten()
}

/// [`Takes::Value`]'s `read` of a choice whose flag's value is the choice's own type `T`.
pub fn read_choice<T: Clone + Send + Sync + 'static>(
    matches: &clap::ArgMatches,
    long: &str,
) -> Option<Start> {
    given::<T>(matches, long).map(|value| Start::choice(value.clone()))
}

/// [`Takes::Value`]'s `read` of a slider, whose flag's value is an `f32`.
pub fn read_slider(matches: &clap::ArgMatches, long: &str) -> Option<Start> {
    given::<f32>(matches, long).map(|&value| Start::Slider(value))
}

/// [`Takes::Shared`]'s `read` of `--green`: `down` turns a "green down" switch on (`up`, the
/// default, starts nothing).
pub fn read_green_down(matches: &clap::ArgMatches, id: &str) -> Option<Start> {
    let down =
        given::<crate::normalmap::Green>(matches, id) == Some(&crate::normalmap::Green::Down);
    down.then_some(Start::Toggle(true))
}

// Flags that mean the same in several scenes: a control's flag in each scene's table that reads
// it ([`Takes::Shared`]; the sprite's own arguments read `--light` too), so that one given to a
// scene that does not read it is an error, not ignored. (A plain comment: clap would make a doc
// comment the program's `about`.)
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

/// A flag of [`SharedArgs`], as a control's flag ([`Takes::Shared`]) or a scene's own arguments
/// name it: a misspelt one does not compile, and a unit test checks that every field of
/// [`SharedArgs`] has one.
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

    /// The flag without its dashes, as a warning names it.
    pub const fn long(self) -> &'static str {
        match self {
            Shared::Green => "green",
            Shared::Light => "light",
            Shared::LightPower => "light-power",
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

#[cfg(test)]
mod tests {
    use super::*;

    // Fails if a field of SharedArgs has no `Shared` (a scene could not say it reads it) or a
    // `Shared` names no argument of SharedArgs: the two lists must be the same, in order, and
    // each flag's long name its argument's.
    #[test]
    fn every_shared_flag_has_its_name() {
        let command = <SharedArgs as clap::Args>::augment_args(clap::Command::new("shared"));
        let args: Vec<(String, String)> = command
            .get_arguments()
            .map(|a| {
                (
                    a.get_id().to_string(),
                    a.get_long().unwrap_or("").to_string(),
                )
            })
            .collect();
        let named: Vec<(String, String)> = Shared::ALL
            .iter()
            .map(|s| (s.id().to_string(), s.long().to_string()))
            .collect();
        assert_eq!(args, named);
        for flag in Shared::ALL {
            assert_eq!(Shared::of_id(flag.id()), Some(flag));
        }
    }
}
