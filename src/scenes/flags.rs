//! A control's command-line flag ([`Flag`]): the argument the descriptor declares for it, and the
//! start ([`Start`]) it gives the control, which the table sets once the scene is built (see
//! [`Control::flag`](super::table::Control::flag) and [`Control::value_flag`](super::table::Control::value_flag)).

use std::fmt;

/// A control's command-line flag: given, the scene starts with the control at the flag's value,
/// set through the table once the scene is built, as its key or the panel would set it. Its help
/// line is `help` and the key ("(key L)").
#[derive(Clone, Copy)]
pub struct Flag {
    /// The flag without its dashes (`debug-lines`), also its argument's id.
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
            Takes::Value { .. } => None,
        }
    }

    /// Its clap arguments: its own (none where another control's flag of the same name declares
    /// it), then its modifier's.
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
