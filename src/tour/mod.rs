//! The tutorial's sections as a tour: one [`Step`] per section of the tutorial's page, in its
//! order ([`STEPS`]), each a state of the program (a scene, its controls set through its table,
//! the camera), a caption in this project's words, and the code that does it: Rust items and
//! shader regions taken from the files the binary is built from ([`excerpt`]), and the lines of the
//! C++ original they port, named and linked ([`original`]).
//!
//! One table behind the tour and the reading guide: docs/reading-guide.md's section table is made
//! from [`STEPS`] ([`reading_guide_table`]) and checked against it by `tests/all/docs.rs`.
//!
//! Layers: the tour reads the scenes' tables and descriptors; the front ends and the commands
//! (`--tour`, `--check-exercise`) apply it. It knows no window.

pub mod excerpt;
pub mod exercise;
pub mod original;
pub mod sources;
mod steps;

pub use excerpt::Excerpt;
pub use original::{Cpp, CppFile};
pub use steps::STEPS;

use crate::common::controls::Controls;
use crate::scenes::{self, ControlValue, SceneControls, SceneDescriptor, SetTo};
use crate::{Error, Result};

/// One section of the tutorial.
#[derive(Debug)]
pub struct Step {
    /// The section's title, as the tutorial's page heads it.
    pub section: &'static str,
    /// A short name for `--tour NAME` (lower case, words joined by `-`).
    pub name: &'static str,
    /// What to look at now and what the key does, in a few lines.
    pub caption: &'static str,
    /// The program's state at this step.
    pub state: State,
    /// Rust items by path (see [`excerpt::rust_item`]).
    pub rust: &'static [&'static str],
    /// Marked regions: (file in the repository, region name) (see [`excerpt::region`]).
    pub regions: &'static [(&'static str, &'static str)],
    /// The lines of the C++ original this step's code ports.
    pub cpp: &'static [Cpp],
}

/// A full snapshot of the program's state: the scene as it starts (with the command line's own
/// flags), then `controls` set through its table as the panel sets them, then the camera. Stepping
/// back to a step builds its scene again, so that nothing set by a later step stays.
#[derive(Debug)]
pub struct State {
    /// The scene's name in `SCENES`.
    pub scene: &'static str,
    /// Controls by their label in the scene's table, and the value each is set to.
    pub controls: &'static [(&'static str, Value)],
    pub camera: Camera,
}

/// A control's value in a [`State`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Value {
    /// A switch on or off.
    On(bool),
    /// A choice, by the name the panel shows.
    Choice(&'static str),
    /// A slider's value.
    Slider(f32),
}

impl Value {
    /// The value as the table sets it.
    pub fn set_to(self) -> SetTo {
        match self {
            Value::On(on) => SetTo::Toggle(on),
            Value::Choice(name) => SetTo::Choice(name.into()),
            Value::Slider(value) => SetTo::Slider(value),
        }
    }

    /// Whether a control whose state is `control` takes this value as it is: a toggle's on or off,
    /// one of a choice's names here, a slider's value within its range (the table would clamp it,
    /// or log and ignore a name it lacks).
    fn fits(self, control: &ControlValue) -> bool {
        match (self, control) {
            (Value::On(_), ControlValue::Toggle(_)) => true,
            (Value::Choice(name), ControlValue::Choice { choices, .. }) => {
                choices.iter().any(|choice| choice == name)
            }
            (Value::Slider(value), ControlValue::Slider { range, .. }) => {
                (range.0..=range.1).contains(&value)
            }
            _ => false,
        }
    }
}

/// Where the camera is at a step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Camera {
    /// The scene's start (what R goes back to).
    Start,
    /// The tutorial's camera moved: its position and its two angles (radians, as `controls.cpp`
    /// keeps them).
    At {
        position: [f32; 3],
        horizontal_angle: f32,
        vertical_angle: f32,
    },
}

impl State {
    /// The scene this state is of.
    pub fn descriptor(&self) -> Result<&'static SceneDescriptor> {
        scenes::find(self.scene).map_err(Error::Argument)
    }

    /// Sets `controls` in `scene` (built fresh, at its start) through its table. A label the table
    /// does not have, or a value the control does not take, is an error naming it.
    pub fn set_controls(&self, scene: &mut dyn SceneControls) -> Result<()> {
        for &(label, value) in self.controls {
            let control = scene.controls().into_iter().find(|c| c.label == label);
            let control = control.filter(|c| value.fits(&c.value)).ok_or_else(|| {
                Error::Argument(format!(
                    "the tour: scene {} has no control {label:?} that takes {value:?}",
                    self.scene
                ))
            })?;
            scene.set_control(control.index, value.set_to())?;
        }
        Ok(())
    }

    /// Puts the camera where this state has it; `start` is the scene's start camera.
    pub fn set_camera(&self, camera: &mut Controls, start: Controls) {
        *camera = start;
        if let Camera::At {
            position,
            horizontal_angle,
            vertical_angle,
        } = self.camera
        {
            camera.position = position.into();
            camera.horizontal_angle = horizontal_angle;
            camera.vertical_angle = vertical_angle;
        }
    }
}

impl Step {
    /// Its number in the tour, from 1.
    pub fn number(&self) -> usize {
        STEPS
            .iter()
            .position(|step| std::ptr::eq(step, self))
            .map_or(0, |i| i + 1)
    }

    /// Every excerpt of its code, Rust items first, then regions, each with what was asked for.
    pub fn excerpts(&self) -> Vec<(String, std::result::Result<Excerpt, excerpt::Missing>)> {
        let rust = self
            .rust
            .iter()
            .map(|path| (path.to_string(), excerpt::rust_item(path)));
        let regions = self
            .regions
            .iter()
            .map(|&(file, name)| (format!("{file} #{name}"), excerpt::region(file, name)));
        rust.chain(regions).collect()
    }
}

/// The step `--tour` names: its number (from 1) or its name. A bad value is one line saying what
/// the tour has.
pub fn find(value: &str) -> Result<&'static Step> {
    let found = match value.parse::<usize>() {
        Ok(n) => STEPS.get(n.wrapping_sub(1)),
        Err(_) => STEPS.iter().find(|step| step.name == value),
    };
    found.ok_or_else(|| {
        Error::Argument(format!(
            "--tour {value}: no such step (a number from 1 to {}, a name such as {}, or list)",
            STEPS.len(),
            STEPS[0].name
        ))
    })
}

/// `--tour list`: each step on a line, its number and its section.
pub fn list() -> String {
    STEPS
        .iter()
        .enumerate()
        .map(|(i, step)| format!("{:>2}  {}\n", i + 1, step.section))
        .collect()
}

/// docs/reading-guide.md's table of the tutorial's sections: each step's section, the C++ lines it
/// ports (linked, with what they do) and the Rust and GLSL that do it (linked to their files), made
/// from [`STEPS`].
pub fn reading_guide_table() -> String {
    let mut table =
        String::from("| # | section | C++ original | Rust and GLSL |\n|---|---|---|---|\n");
    for (i, step) in STEPS.iter().enumerate() {
        let cpp: Vec<String> = step
            .cpp
            .iter()
            .map(|cpp| format!("[{}]({}): {}", cpp.label(), cpp.url(), cpp.what))
            .collect();
        let code: Vec<String> = step
            .excerpts()
            .into_iter()
            .map(|(asked, found)| match found {
                // The file without its lines: an edit above an item would otherwise change the
                // guide; the tour itself shows the lines.
                Ok(excerpt) => {
                    let link = format!("../{}", excerpt.file);
                    match asked.split_once(" #") {
                        Some((file, region)) => {
                            let name = file.rsplit('/').next().unwrap_or(file);
                            format!("[{name}, region {region}]({link})")
                        }
                        None => format!("[`{}`]({link})", shown_name(&asked)),
                    }
                }
                Err(missing) => format!("missing: {missing}"),
            })
            .collect();
        let none = |v: Vec<String>| match v.is_empty() {
            true => "none".to_string(),
            false => v.join("; "),
        };
        table += &format!(
            "| {} | {} | {} | {} |\n",
            i + 1,
            step.section,
            none(cpp),
            none(code)
        );
    }
    table
}

/// A Rust path from its type on (`Tutorial13::draw_with`), or its last segment (`index_vbo_tbn`).
fn shown_name(asked: &str) -> String {
    let segments: Vec<&str> = asked.split("::").collect();
    let start = segments
        .iter()
        .position(|s| s.starts_with(char::is_uppercase) || s.starts_with("impl "))
        .unwrap_or(segments.len() - 1);
    segments[start..].join("::")
}
