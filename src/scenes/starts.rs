//! Starting a scene's controls from outside, through its table: a typed handle on one control
//! ([`Handle`]), the value it starts at ([`Setting`]), and every start a scene is built with
//! ([`Starts`], kept in [`super::SceneOptions`]). A flag, a library caller, a test and a step of a
//! tour all start a control this one way: `options.start(cylinder::TANGENTS.to(TangentSource::MikkTSpace))`
//! is what `--tangents mikktspace` gives.

use std::any::TypeId;
use std::fmt;
use std::marker::PhantomData;

use super::flags::Start;
use super::scene::Scene;
use super::table::{ChoiceValue, Control, Kind};
use crate::Result;

/// The kind of control a value type starts (see [`StartValue`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StartKind {
    Toggle,
    Choice,
    Slider,
}

/// A value a control starts at: a toggle's `bool`, a slider's `f32`, or a choice's own type.
pub trait StartValue: Sized + 'static {
    const KIND: StartKind;
    /// The start it gives.
    fn start(self) -> Start;
    /// The value of a start of its kind.
    fn of_start(start: &Start) -> Option<Self>;
}

impl StartValue for bool {
    const KIND: StartKind = StartKind::Toggle;
    fn start(self) -> Start {
        Start::Toggle(self)
    }
    fn of_start(start: &Start) -> Option<bool> {
        match start {
            &Start::Toggle(on) => Some(on),
            _ => None,
        }
    }
}

impl StartValue for f32 {
    const KIND: StartKind = StartKind::Slider;
    fn start(self) -> Start {
        Start::Slider(self)
    }
    fn of_start(start: &Start) -> Option<f32> {
        match start {
            &Start::Slider(value) => Some(value),
            _ => None,
        }
    }
}

impl<T: ChoiceValue + Send + Sync> StartValue for T {
    const KIND: StartKind = StartKind::Choice;
    fn start(self) -> Start {
        Start::choice(self)
    }
    fn of_start(start: &Start) -> Option<T> {
        match start {
            Start::Choice(value) => value.downcast_ref::<T>().copied(),
            _ => None,
        }
    }
}

/// The control labelled so in a scene's table, whose values are `T`: what a caller names to start
/// it. Declared once beside the table (`pub const TANGENTS: Handle<Cylinder, TangentSource> =
/// Handle::new(CONTROLS, "tangent frame")`): a label no control has, or a control of another kind,
/// stops the build; a choice of values of another type than `T` panics on the first start.
pub struct Handle<S: 'static, T> {
    controls: &'static [Control<S>],
    index: usize,
    value: PhantomData<fn(T)>,
}

impl<S: 'static, T: StartValue> Handle<S, T> {
    /// The control of `controls` labelled `label`.
    pub const fn new(controls: &'static [Control<S>], label: &str) -> Self {
        let mut found = None;
        let mut i = 0;
        while i < controls.len() {
            if same_text(controls[i].label, label) {
                assert!(found.is_none(), "two controls have this label");
                found = Some(i);
            }
            i += 1;
        }
        let Some(index) = found else {
            panic!("no control has this label")
        };
        let kind = match controls[index].kind {
            Kind::Toggle { .. } => Some(StartKind::Toggle),
            Kind::Choice(_) => Some(StartKind::Choice),
            Kind::Slider { .. } => Some(StartKind::Slider),
            Kind::Press { .. } => None,
        };
        assert!(
            matches!(
                (kind, T::KIND),
                (Some(StartKind::Toggle), StartKind::Toggle)
                    | (Some(StartKind::Choice), StartKind::Choice)
                    | (Some(StartKind::Slider), StartKind::Slider)
            ),
            "the control is not of the handle's kind (a bool is a toggle's, an f32 a slider's)"
        );
        Handle {
            controls,
            index,
            value: PhantomData,
        }
    }

    /// Its place in the table (what [`super::SceneControls::set_control`] takes).
    pub fn index(self) -> usize {
        self.index
    }

    /// The control started at `value`.
    pub fn to(self, value: T) -> Setting<S> {
        if let Kind::Choice(choice) = self.controls[self.index].kind {
            assert!(
                choice.value_type() == TypeId::of::<T>(),
                "{}: a handle of another type than its values",
                self.controls[self.index].label
            );
        }
        Setting {
            controls: self.controls,
            index: self.index,
            start: value.start(),
            flag: None,
        }
    }
}

impl<S, T> Clone for Handle<S, T> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<S, T> Copy for Handle<S, T> {}

impl<S, T> fmt::Debug for Handle<S, T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Handle({})", self.controls[self.index].label)
    }
}

/// Whether `a` and `b` are the same text (a `const fn`, for [`Handle::new`]).
const fn same_text(a: &str, b: &str) -> bool {
    let (a, b) = (a.as_bytes(), b.as_bytes());
    if a.len() != b.len() {
        return false;
    }
    let mut i = 0;
    while i < a.len() {
        if a[i] != b[i] {
            return false;
        }
        i += 1;
    }
    true
}

/// A control of scene type `S` and the value it starts at: from a typed handle ([`Handle::to`]) or
/// from its flag on the command line.
pub struct Setting<S: 'static> {
    controls: &'static [Control<S>],
    index: usize,
    start: Start,
    /// The flag (without its dashes) it was read from, if it was: a warning names it.
    flag: Option<&'static str>,
}

impl<S: 'static> Setting<S> {
    /// Control `index` of `controls` started at `start` by the flag `--long`.
    pub(super) fn from_flag(
        controls: &'static [Control<S>],
        index: usize,
        start: Start,
        long: &'static str,
    ) -> Self {
        Setting {
            controls,
            index,
            start,
            flag: Some(long),
        }
    }

    /// Its control's place in the table.
    pub fn index(&self) -> usize {
        self.index
    }

    /// The value it starts its control at.
    pub fn start(&self) -> &Start {
        &self.start
    }

    /// Sets its control in `scene` through the table, as its flag would (a slider unclamped).
    pub fn apply(&self, scene: &mut S) -> Result<()> {
        self.controls[self.index].start(scene, &self.start)
    }

    /// Why its control does nothing in `scene` now, named as the user gave it: `--flag` or the
    /// control's label.
    fn inert(&self, scene: &S) -> Option<(String, &'static str)> {
        let control = &self.controls[self.index];
        let reason = (control.inert)(scene)?;
        let name = match self.flag {
            Some(long) => format!("--{long}"),
            None => control.label.to_string(),
        };
        Some((name, reason))
    }
}

impl<S> Clone for Setting<S> {
    fn clone(&self) -> Self {
        Setting {
            controls: self.controls,
            index: self.index,
            start: self.start.clone(),
            flag: self.flag,
        }
    }
}

impl<S> fmt::Debug for Setting<S> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let label = self.controls[self.index].label;
        write!(f, "{label:?} = {:?}", self.start)
    }
}

/// Every start scene type `S` is built with: set through its table once the scene is built
/// ([`Starts::apply`]), except those the scene took to load with ([`Starts::take`]).
pub struct Starts<S: 'static> {
    settings: Vec<Setting<S>>,
    /// The indices (in `settings`) of those the scene took.
    taken: Vec<usize>,
}

impl<S: 'static> Starts<S> {
    /// Adds `setting`, in place of an earlier start of the same control.
    pub fn set(&mut self, setting: Setting<S>) {
        match self.settings.iter().position(|s| s.index == setting.index) {
            Some(i) => self.settings[i] = setting,
            None => self.settings.push(setting),
        }
    }

    /// Every start, in the order they were given.
    pub fn settings(&self) -> &[Setting<S>] {
        &self.settings
    }

    /// The value `handle`'s control starts at, if a start gives it.
    pub fn get<T: StartValue>(&self, handle: Handle<S, T>) -> Option<T> {
        let setting = self.settings.iter().find(|s| s.index == handle.index)?;
        T::of_start(&setting.start)
    }

    /// [`Starts::get`], for a scene whose load depends on the value (the cylinder builds a model's
    /// mesh for `--tangents` straight away): the table does not set it again, but still says when
    /// it does nothing.
    pub fn take<T: StartValue>(&mut self, handle: Handle<S, T>) -> Option<T> {
        let i = self.settings.iter().position(|s| s.index == handle.index)?;
        self.taken.push(i);
        T::of_start(&self.settings[i].start)
    }

    /// Sets each start (but those taken) through the table: choices and sliders first, then
    /// toggles (turning the TBN lines on builds them, with the line mode and length already set).
    /// A start that does nothing in the state the scene starts in says why, once per flag (`--view`
    /// starts two controls), as the panel does.
    pub fn apply(&self, scene: &mut S) -> Result<()> {
        let given = self
            .settings
            .iter()
            .enumerate()
            .filter(|(i, _)| !self.taken.contains(i))
            .map(|(_, setting)| setting);
        let (toggles, values): (Vec<_>, Vec<_>) =
            given.partition(|s| matches!(s.start, Start::Toggle(_)));
        for setting in values.into_iter().chain(toggles) {
            setting.apply(scene)?;
        }
        let mut warned = Vec::new();
        for (name, reason) in self.settings.iter().filter_map(|s| s.inert(scene)) {
            if !warned.contains(&name) {
                log::warn!("{name}: {reason}");
                warned.push(name);
            }
        }
        Ok(())
    }

    /// [`Starts::apply`] to a running scene seen as `dyn Scene` (a step of a tour: "L on, F =
    /// mikktspace, normal strength 2"): `Ok(false)` if it is not an `S`.
    pub fn apply_to(&self, scene: &mut dyn Scene) -> Result<bool> {
        let any: &mut dyn std::any::Any = scene;
        match any.downcast_mut::<S>() {
            Some(scene) => self.apply(scene).map(|()| true),
            None => Ok(false),
        }
    }
}

/// The starts of `settings`, a later one of a control in place of an earlier one.
impl<S: 'static> FromIterator<Setting<S>> for Starts<S> {
    fn from_iter<I: IntoIterator<Item = Setting<S>>>(settings: I) -> Self {
        let mut starts = Starts::default();
        for setting in settings {
            starts.set(setting);
        }
        starts
    }
}

impl<S> Clone for Starts<S> {
    fn clone(&self) -> Self {
        Starts {
            settings: self.settings.clone(),
            taken: self.taken.clone(),
        }
    }
}

impl<S> Default for Starts<S> {
    fn default() -> Self {
        Starts {
            settings: Vec::new(),
            taken: Vec::new(),
        }
    }
}

impl<S> fmt::Debug for Starts<S> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_list().entries(&self.settings).finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenes::table::Choices;

    /// A lamp: on or off, at a level, in a colour, noting the order its controls are set in.
    #[derive(Default)]
    struct Lamp {
        on: bool,
        level: f32,
        warm: bool,
        set: Vec<&'static str>,
    }

    #[derive(Debug, Clone, Copy, PartialEq)]
    enum Colour {
        Cold,
        Warm,
    }

    impl ChoiceValue for Colour {
        fn choice_name(self) -> String {
            format!("{self:?}")
        }
    }

    /// A value type of no control of the lamp's.
    #[derive(Debug, Clone, Copy, PartialEq)]
    struct Shade;

    impl ChoiceValue for Shade {
        fn choice_name(self) -> String {
            "shade".into()
        }
    }

    const LAMP: &[Control<Lamp>] = &[
        Control::toggle(
            'O',
            "on",
            "on / off",
            |l| l.on,
            |l, on| {
                l.on = on;
                l.set.push("on");
                Ok(())
            },
        ),
        Control::slider(
            "level",
            |_| (0.0, 1.0),
            |_| 0.0,
            |l| l.level,
            |l, level| {
                l.level = level;
                l.set.push("level");
                Ok(())
            },
        ),
        Control::choice(
            'C',
            "colour",
            "cold / warm",
            &Choices {
                values: |_| vec![Colour::Cold, Colour::Warm],
                get: |l: &Lamp| match l.warm {
                    true => Colour::Warm,
                    false => Colour::Cold,
                },
                set: |l: &mut Lamp, colour| {
                    l.warm = colour == Colour::Warm;
                    l.set.push("colour");
                    Ok(())
                },
            },
        ),
    ];
    const ON: Handle<Lamp, bool> = Handle::new(LAMP, "on");
    const LEVEL: Handle<Lamp, f32> = Handle::new(LAMP, "level");
    const COLOUR: Handle<Lamp, Colour> = Handle::new(LAMP, "colour");

    // Fails if a later start of a control does not replace an earlier one, if a start is read back
    // as another value, if a slider's start is held to its range, if the values are not set before
    // the toggles (in the table's order), or if a start the scene took is set again.
    #[test]
    fn each_start_is_set_once_values_first() {
        let mut starts = Starts::default();
        starts.set(ON.to(true));
        starts.set(COLOUR.to(Colour::Warm));
        starts.set(LEVEL.to(0.5));
        starts.set(LEVEL.to(2.0));
        assert_eq!(starts.settings().len(), 3);
        assert_eq!(
            (starts.get(ON), starts.get(LEVEL), starts.get(COLOUR)),
            (Some(true), Some(2.0), Some(Colour::Warm))
        );
        let mut lamp = Lamp::default();
        starts.apply(&mut lamp).unwrap();
        assert_eq!((lamp.on, lamp.level, lamp.warm), (true, 2.0, true));
        assert_eq!(lamp.set, ["colour", "level", "on"]);

        let mut taken = starts.clone();
        assert_eq!(taken.take(COLOUR), Some(Colour::Warm));
        let mut lamp = Lamp::default();
        taken.apply(&mut lamp).unwrap();
        assert_eq!(lamp.set, ["level", "on"]);
    }

    // Fails if a handle whose type is not its choice's values' is accepted (it would start
    // nothing).
    #[test]
    #[should_panic(expected = "a handle of another type than its values")]
    fn a_handle_of_another_type_than_its_choice_is_refused() {
        let _ = Handle::<Lamp, Shade>::new(LAMP, "colour").to(Shade);
    }

    // Fails if a handle of another kind than its control's (an f32 on a toggle) is accepted (in a
    // `const`, this stops the build).
    #[test]
    #[should_panic(expected = "the control is not of the handle's kind")]
    fn a_handle_of_another_kind_is_refused() {
        let _ = Handle::<Lamp, f32>::new(LAMP, "on");
    }

    // Fails if a handle on a label no control has is accepted.
    #[test]
    #[should_panic(expected = "no control has this label")]
    fn a_handle_on_no_control_is_refused() {
        let _ = Handle::<Lamp, bool>::new(LAMP, "off");
    }
}
