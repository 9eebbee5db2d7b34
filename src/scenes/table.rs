//! A scene's controls, each declared once: its key, label, key-list line, kind (on / off, a choice of
//! named values, a slider, a plain press), how it is read and set, its command-line flag, its name
//! in the title, and when it does nothing. The key handling, the key list (`--help`, the window,
//! `docs/keys.md`), the panel's rows, the title's short status, the log's status line and every
//! start from outside (a flag, a library caller, a test: [`super::starts`]) are all read from this
//! one table.

use std::any::TypeId;

use super::flags::{enum_arg, read_choice, Flag, Shared, Start, Takes};
use crate::Result;

/// One control of scene type `S` (see the module's doc).
pub struct Control<S: 'static> {
    /// The key that flips, steps or presses it (a slider has none).
    pub key: Option<char>,
    /// A few words: what it is, on the panel.
    pub label: &'static str,
    /// Its line in the key list (a control without a key is not listed there).
    pub help: &'static str,
    pub kind: Kind<S>,
    /// Its name in the title's short status, where it appears there.
    pub title: Option<&'static str>,
    /// Why it does nothing in the scene's current state, if it does nothing.
    pub inert: fn(&S) -> Option<&'static str>,
    /// The command-line flag that starts it ([`Control::flag`], [`Control::value_flag`]).
    pub flag: Option<Flag>,
}

/// What a control is, and how it reads and sets its scene.
pub enum Kind<S: 'static> {
    /// On or off (a checkbox); the key flips it.
    Toggle {
        get: fn(&S) -> bool,
        set: fn(&mut S, bool) -> Result<()>,
    },
    /// One of several named values; the key steps to the next in the order of its values. The
    /// scene reads and sets typed values ([`Choices`]); names exist only for the panel, the title
    /// and the log. (`Sync`: a table is shared by every thread that starts a scene's controls.)
    Choice(&'static (dyn AnyChoice<S> + Sync)),
    /// A value within `range`, starting at the tutorial's (or the article's) `start`.
    Slider {
        range: fn(&S) -> (f32, f32),
        start: fn(&S) -> f32,
        get: fn(&S) -> f32,
        set: fn(&mut S, f32) -> Result<()>,
    },
    /// An action with no state of its own ("split line left").
    Press { press: fn(&mut S) -> Result<()> },
}

/// A value a choice takes, with its name on the panel, in the title and in the log.
pub trait ChoiceValue: Copy + PartialEq + 'static {
    fn choice_name(self) -> String;
}

/// A choice's typed functions: the values the scene can take here (a context may offer fewer), the
/// one it has, and setting one (doing only what that value needs). Written in a scene's table as
/// `&Choices { values, get, set }`.
pub struct Choices<S, T> {
    pub values: fn(&S) -> Vec<T>,
    pub get: fn(&S) -> T,
    pub set: fn(&mut S, T) -> Result<()>,
}

/// What the table asks of a choice whatever its value's type: [`Choices`] by name.
pub trait AnyChoice<S> {
    /// Every value's name, in the order the key steps through them.
    fn names(&self, scene: &S) -> Vec<String>;
    /// The current value's name.
    fn current(&self, scene: &S) -> String;
    /// Sets the value at `index` of [`AnyChoice::names`].
    fn set_index(&self, scene: &mut S, index: usize) -> Result<()>;
    /// Sets `value`, one of the choice's type (a flag's start, [`Start::Choice`]), whether or not
    /// the scene offers it now (the flag's parser has checked it): `false` if it is of another
    /// type.
    fn set_any(&self, scene: &mut S, value: &dyn std::any::Any) -> Result<bool>;
    /// The type of its values (what a typed handle on it must name).
    fn value_type(&self) -> TypeId;
}

impl<S, T: ChoiceValue> AnyChoice<S> for Choices<S, T> {
    fn names(&self, scene: &S) -> Vec<String> {
        let values = (self.values)(scene);
        values.into_iter().map(ChoiceValue::choice_name).collect()
    }

    fn current(&self, scene: &S) -> String {
        (self.get)(scene).choice_name()
    }

    fn set_index(&self, scene: &mut S, index: usize) -> Result<()> {
        match (self.values)(scene).get(index) {
            Some(&value) => (self.set)(scene, value),
            None => Ok(()),
        }
    }

    fn set_any(&self, scene: &mut S, value: &dyn std::any::Any) -> Result<bool> {
        match value.downcast_ref::<T>() {
            Some(&value) => (self.set)(scene, value).map(|()| true),
            None => Ok(false),
        }
    }

    fn value_type(&self) -> TypeId {
        TypeId::of::<T>()
    }
}

/// A control that always applies.
fn applies<S>(_: &S) -> Option<&'static str> {
    None
}

impl<S: 'static> Control<S> {
    /// An on / off switch on `key`.
    pub const fn toggle(
        key: char,
        label: &'static str,
        help: &'static str,
        get: fn(&S) -> bool,
        set: fn(&mut S, bool) -> Result<()>,
    ) -> Self {
        Self::keyed(key, label, help, Kind::Toggle { get, set })
    }

    /// A choice of values on `key` (see [`Choices`]).
    pub const fn choice(
        key: char,
        label: &'static str,
        help: &'static str,
        choices: &'static (dyn AnyChoice<S> + Sync),
    ) -> Self {
        Self::keyed(key, label, help, Kind::Choice(choices))
    }

    /// A plain press on `key`.
    pub const fn press(
        key: char,
        label: &'static str,
        help: &'static str,
        press: fn(&mut S) -> Result<()>,
    ) -> Self {
        Self::keyed(key, label, help, Kind::Press { press })
    }

    /// A slider without a key.
    pub const fn slider(
        label: &'static str,
        range: fn(&S) -> (f32, f32),
        start: fn(&S) -> f32,
        get: fn(&S) -> f32,
        set: fn(&mut S, f32) -> Result<()>,
    ) -> Self {
        Control {
            key: None,
            label,
            help: "",
            kind: Kind::Slider {
                range,
                start,
                get,
                set,
            },
            title: None,
            inert: applies,
            flag: None,
        }
    }

    const fn keyed(key: char, label: &'static str, help: &'static str, kind: Kind<S>) -> Self {
        Control {
            key: Some(key),
            label,
            help,
            kind,
            title: None,
            inert: applies,
            flag: None,
        }
    }

    /// This toggle with the command-line flag `--long` (see [`Flag`]), which starts it `value`.
    pub const fn flag(self, long: &'static str, value: bool, help: &'static str) -> Self {
        // A table that gives a choice or a slider a toggle's flag does not compile.
        assert!(
            matches!(self.kind, Kind::Toggle { .. }),
            "only a toggle takes a flag without a value"
        );
        self.with_flag(long, help, Takes::Switch(value))
    }

    /// This choice or slider with the command-line flag `--long VALUE` (see [`Takes::Value`]).
    pub const fn value_flag(
        self,
        long: &'static str,
        value_name: &'static str,
        help: &'static str,
        arg: Option<fn(clap::Arg) -> clap::Arg>,
        read: fn(&clap::ArgMatches, &str) -> Option<Start>,
    ) -> Self {
        assert!(
            matches!(self.kind, Kind::Choice(_) | Kind::Slider { .. }),
            "only a choice or a slider takes a flag with a value"
        );
        let takes = Takes::Value {
            value_name,
            arg,
            read,
        };
        self.with_flag(long, help, takes)
    }

    const fn with_flag(mut self, long: &'static str, help: &'static str, takes: Takes) -> Self {
        self.flag = Some(Flag {
            long,
            help,
            takes,
            modifier: None,
        });
        self
    }

    /// This toggle or slider with the flag several scenes share `flag` ([`Takes::Shared`]), whose
    /// argument [`super::flags::SharedArgs`] declares; `read` gives the control's start from it.
    pub const fn shared_flag(
        mut self,
        flag: Shared,
        read: fn(&clap::ArgMatches, &str) -> Option<Start>,
    ) -> Self {
        self.flag = Some(Flag {
            long: flag.long(),
            help: "",
            takes: Takes::Shared { flag, read },
            modifier: None,
        });
        self
    }

    /// This control's flag with the switch `--long` beside it, which its `read` takes into account
    /// ([`Flag::modifier`]).
    pub const fn flag_modifier(mut self, long: &'static str, help: &'static str) -> Self {
        match &mut self.flag {
            Some(flag) => flag.modifier = Some((long, help)),
            None => panic!("a modifier needs the control's flag first"),
        }
        self
    }

    /// This choice with the flag `--long VALUE`, its values by the names of their clap `ValueEnum`.
    pub const fn enum_flag<T: clap::ValueEnum + Send + Sync + 'static>(
        self,
        long: &'static str,
        value_name: &'static str,
        help: &'static str,
    ) -> Self {
        self.value_flag(
            long,
            value_name,
            help,
            Some(enum_arg::<T>),
            read_choice::<T>,
        )
    }

    /// This control, shown in the title as "`name` value".
    pub const fn in_title(mut self, name: &'static str) -> Self {
        self.title = Some(name);
        self
    }

    /// This control, doing nothing (for the reason `inert` gives) in some states.
    pub const fn inert_when(mut self, inert: fn(&S) -> Option<&'static str>) -> Self {
        self.inert = inert;
        self
    }

    /// Its value as the title shows it ([`ControlValue::shown`] of its state), read without the
    /// rest of the state (a choice's list of names): the title asks every frame.
    pub(super) fn shown(&self, scene: &S) -> String {
        match &self.kind {
            Kind::Toggle { get, .. } => ControlValue::Toggle(get(scene)).shown(),
            Kind::Choice(choice) => choice.current(scene),
            Kind::Slider { get, .. } => get(scene).to_string(),
            Kind::Press { .. } => String::new(),
        }
    }

    pub(super) fn state(&self, index: usize, scene: &S) -> ControlState {
        let value = match &self.kind {
            Kind::Toggle { get, .. } => ControlValue::Toggle(get(scene)),
            Kind::Choice(choice) => ControlValue::Choice {
                current: choice.current(scene),
                choices: choice.names(scene),
            },
            Kind::Slider {
                range, start, get, ..
            } => ControlValue::Slider {
                value: get(scene),
                start: start(scene),
                range: range(scene),
            },
            Kind::Press { .. } => ControlValue::Press,
        };
        ControlState {
            index,
            key: self.key,
            label: self.label,
            help: self.help,
            title: self.title,
            value,
            inert: (self.inert)(scene),
            flag: self.flag,
        }
    }

    /// Sets it in `scene` to `to`; a value of another kind changes nothing.
    pub(super) fn set(&self, scene: &mut S, to: SetTo) -> Result<()> {
        match (&self.kind, to) {
            (Kind::Toggle { set, .. }, SetTo::Toggle(on)) => set(scene, on),
            (Kind::Choice(choice), SetTo::Choice(name)) => {
                match choice.names(scene).iter().position(|n| *n == name) {
                    Some(index) => choice.set_index(scene, index),
                    None => {
                        log::warn!("{}: no choice {name:?} here", self.label);
                        Ok(())
                    }
                }
            }
            (Kind::Slider { range, set, .. }, SetTo::Slider(value)) => {
                let (lo, hi) = range(scene);
                set(scene, value.clamp(lo, hi))
            }
            (Kind::Press { press }, SetTo::Press) => press(scene),
            (_, to) => {
                log::warn!("{}: cannot be set to {to:?}", self.label);
                Ok(())
            }
        }
    }

    /// Sets it in `scene` to a start (a flag's or a typed handle's, see [`super::starts`]; a slider
    /// unclamped, see [`Start::Slider`]).
    pub(super) fn start(&self, scene: &mut S, start: &Start) -> Result<()> {
        let set = match (&self.kind, start) {
            (Kind::Toggle { set, .. }, &Start::Toggle(on)) => set(scene, on).map(|()| true),
            (Kind::Choice(choice), Start::Choice(value)) => choice.set_any(scene, &**value),
            (Kind::Slider { set, .. }, &Start::Slider(value)) => set(scene, value).map(|()| true),
            _ => Ok(false),
        }?;
        // A table whose flag reads another type than its control's:
        // each_value_flag_starts_its_control_through_the_table (tests/all/table.rs) finds it (a
        // typed handle of another type panics in `Handle::to`).
        if !set {
            log::error!("{}: the start {start:?} is not of its kind", self.label);
        }
        Ok(())
    }

    /// What its key does: flips it, steps it to the next choice, or presses it.
    pub(super) fn key_press(&self, scene: &S) -> SetTo {
        match &self.kind {
            Kind::Toggle { get, .. } => SetTo::Toggle(!get(scene)),
            Kind::Choice(choice) => {
                let (names, current) = (choice.names(scene), choice.current(scene));
                let i = names.iter().position(|c| *c == current).unwrap_or(0);
                let next = names.get((i + 1) % names.len().max(1));
                SetTo::Choice(next.cloned().unwrap_or(current))
            }
            Kind::Slider { get, .. } => SetTo::Slider(get(scene)),
            Kind::Press { .. } => SetTo::Press,
        }
    }
}

/// One line of a scene's key list: the key as printed ("L") and what it does.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct KeyHelp {
    pub key: char,
    pub help: &'static str,
}

/// The most keys one scene's table may have (the key list is built with the crate, in an array of
/// this size).
const MAX_KEYS: usize = 32;

/// The key list of a table, in its order (built when the crate is: `--help` lists a scene's keys
/// without building it). Two controls on one key stop the build: the second could never be reached.
pub struct KeyList {
    keys: [KeyHelp; MAX_KEYS],
    len: usize,
}

impl KeyList {
    /// The keys of `controls`.
    pub const fn of<S: 'static>(controls: &[Control<S>]) -> KeyList {
        let mut keys = [KeyHelp { key: ' ', help: "" }; MAX_KEYS];
        let (mut i, mut n) = (0, 0);
        while i < controls.len() {
            if let Some(key) = controls[i].key {
                let mut j = 0;
                while j < n {
                    assert!(keys[j].key != key, "two controls share a key");
                    j += 1;
                }
                assert!(n < MAX_KEYS, "more keys than MAX_KEYS");
                keys[n] = KeyHelp {
                    key,
                    help: controls[i].help,
                };
                n += 1;
            }
            i += 1;
        }
        KeyList { keys, len: n }
    }

    /// The list (of a list built with the crate).
    pub const fn as_slice(&'static self) -> &'static [KeyHelp] {
        self.keys.split_at(self.len).0
    }
}

/// The index of the control on `key` (letters either case).
pub fn control_for_key<S: 'static>(controls: &[Control<S>], key: char) -> Option<usize> {
    let key = key.to_ascii_uppercase();
    controls.iter().position(|c| c.key == Some(key))
}

/// A control as the panel and the title see it, with its scene's state now.
#[derive(Debug, Clone, PartialEq)]
pub struct ControlState {
    /// Its place in the scene's table (what [`SceneControls::set_control`] takes).
    pub index: usize,
    pub key: Option<char>,
    pub label: &'static str,
    pub help: &'static str,
    pub title: Option<&'static str>,
    pub value: ControlValue,
    /// Why it does nothing now, if it does nothing.
    pub inert: Option<&'static str>,
    /// The command-line flag that starts it one way, if it has one.
    pub flag: Option<Flag>,
}

/// A control's value now.
#[derive(Debug, Clone, PartialEq)]
pub enum ControlValue {
    Toggle(bool),
    /// `current` is one of `choices`, listed in the order the key steps through them.
    Choice {
        current: String,
        choices: Vec<String>,
    },
    Slider {
        value: f32,
        /// The value the scene starts with.
        start: f32,
        range: (f32, f32),
    },
    Press,
}

impl ControlValue {
    /// As the title and the log say it: "on", "off", a choice's name, a slider's value.
    pub fn shown(&self) -> String {
        match self {
            ControlValue::Toggle(on) => if *on { "on" } else { "off" }.into(),
            ControlValue::Choice { current, .. } => current.clone(),
            ControlValue::Slider { value, .. } => value.to_string(),
            ControlValue::Press => String::new(),
        }
    }
}

/// What a control is set to.
#[derive(Debug, Clone, PartialEq)]
pub enum SetTo {
    Toggle(bool),
    Choice(String),
    /// Clamped to the slider's range.
    Slider(f32),
    Press,
}

/// A scene's table, seen through `dyn Scene` (every scene type has it from its `CONTROLS`).
pub trait SceneControls {
    /// Every control with its state, in the table's order.
    fn controls(&self) -> Vec<ControlState>;

    /// Sets control `index` to `to`, doing only what that value needs. One that does nothing now
    /// is still set (it applies once the state allows it), and says why it does nothing.
    fn set_control(&mut self, index: usize, to: SetTo) -> Result<()>;

    /// `key` was pressed (letters either case): `Ok(false)` if no control has it.
    fn press_key(&mut self, key: char) -> Result<bool>;

    /// "lines off, view lit": the controls named in the title that apply now.
    fn title_status(&self) -> Vec<String>;

    /// "TBN debug lines off", "colour view lit", …: every control with a state that applies now,
    /// by its label (the log's status line).
    fn table_status(&self) -> Vec<String>;

    /// The index of the first control labelled `label` (for tests and scripts; the panel
    /// addresses controls by index).
    fn control_index(&self, label: &str) -> Option<usize> {
        self.controls().iter().position(|c| c.label == label)
    }
}
