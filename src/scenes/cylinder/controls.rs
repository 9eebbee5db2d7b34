//! The cylinder's table: every switch, choice and slider declared once, with its flag, when it
//! does nothing (the per-pixel frame draws the lit picture only), and the light's sliders in the
//! space `--light` uses; the typed handles that start its controls ([`TANGENTS`], …).

use glam::Vec3;

use crate::debug::compare::{CompareMode, SPLIT_START};
use crate::debug::lines::{LineMode, LINE_LENGTH};
use crate::debug::views::{ColorView, DebugVector, NormalMapConvention, ShaderSwitches};
use crate::mesh::MeshOptions;

use crate::scenes::flags::{given, parse_finite, read_green_down, read_slider, Shared, Start};
use crate::scenes::lights::{light_slider, power_slider, PointLight, LIGHT_RANGE};
use crate::scenes::starts::{Handle, Setting};
use crate::scenes::table::{ChoiceValue, Choices, Control};
use crate::tangent_source::TangentSource;
use crate::Result;

pub use super::compare::Comparing;
use super::programs::Knobs;
use super::{Cylinder, SoupSource};

/// Why a switch of the colour views and shader experiments does nothing with the per-pixel frame.
const PER_PIXEL: &str =
    "the per-pixel frame (F = derivative) draws the lit picture without the experiments";

/// Whether the per-pixel frame draws (alone: the compare view draws each side's own).
pub(super) fn per_pixel(cylinder: &Cylinder) -> Option<&'static str> {
    let alone = cylinder.comparison.is_none();
    (alone && !cylinder.mesh.source.has_vertex_tangents()).then_some(PER_PIXEL)
}

/// Why the TBN lines are not drawn, if they cannot be.
pub(super) fn no_lines(cylinder: &Cylinder) -> Option<&'static str> {
    if cylinder.comparison.is_some() {
        Some("the compare view draws no TBN lines")
    } else if !cylinder.mesh.source.has_vertex_tangents() {
        Some("the per-pixel frame (F = derivative) has no vertex tangents to draw lines from")
    } else {
        None
    }
}

/// Why the compare view's split line does nothing, if it does nothing.
fn no_split(cylinder: &Cylinder) -> Option<&'static str> {
    match (&cylinder.comparison, cylinder.compare_view.mode) {
        (None, _) => Some("the compare view is off (K turns it on)"),
        (Some(_), CompareMode::Difference) => Some("the difference view has no split line"),
        (Some(_), CompareMode::Split) => None,
    }
}

/// Sets the shader switches with `change`: a uniform, nothing rebuilt.
fn switch(cylinder: &mut Cylinder, change: impl FnOnce(&mut ShaderSwitches)) -> Result<()> {
    change(&mut cylinder.switches);
    Ok(())
}

/// A switch of the CPU pipeline (the mesh is rebuilt), `field` of [`MeshOptions`].
macro_rules! mesh_toggle {
    ($key:literal, $label:literal, $help:literal, $($field:ident).+) => {
        C::toggle(
            $key,
            $label,
            $help,
            |c| c.mesh.options.$($field).+,
            |c, on| mesh_switch(c, |m| m.$($field).+ = on),
        )
    };
}

/// A switch of the debugging shader (a uniform), `field` of [`ShaderSwitches`]: the per-pixel
/// frame's program has none of them.
macro_rules! shader_toggle {
    ($key:literal, $label:literal, $help:literal, $($field:ident).+) => {
        C::toggle(
            $key,
            $label,
            $help,
            |c| c.switches.$($field).+,
            |c, on| switch(c, |sw| sw.$($field).+ = on),
        )
        .inert_when(per_pixel)
    };
}

/// Runs the CPU pipeline again with `change` made to its switches.
fn mesh_switch(cylinder: &mut Cylinder, change: impl FnOnce(&mut MeshOptions)) -> Result<()> {
    let mut mesh = cylinder.mesh.options;
    change(&mut mesh);
    cylinder.set_mesh_options(mesh)
}

/// The colour view's component ([`ColorView::component`]): all, or x, y or z alone.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Component(pub Option<u8>);

impl Component {
    const ALL: [Component; 4] = [
        Component(None),
        Component(Some(0)),
        Component(Some(1)),
        Component(Some(2)),
    ];
}

impl ChoiceValue for Component {
    fn choice_name(self) -> String {
        let Component(component) = self;
        ["all", "x", "y", "z"][component.map_or(0, |i| usize::from(i) + 1)].into()
    }
}

/// A colour view without its component: what it shows, mapped to 0..1 or not ("light01").
impl ChoiceValue for (DebugVector, bool) {
    fn choice_name(self) -> String {
        let (vector, mapped) = self;
        ColorView::default().with_vector(vector, mapped).to_string()
    }
}

/// The compare view by its mode: off (`None`), or on in a mode.
impl ChoiceValue for Comparing {
    fn choice_name(self) -> String {
        match self.mode {
            None => "off",
            Some(CompareMode::Split) => "side by side",
            Some(CompareMode::Difference) => "difference",
        }
        .into()
    }
}

impl ChoiceValue for LineMode {
    fn choice_name(self) -> String {
        match self {
            LineMode::Legacy => "immediate mode",
            LineMode::Shader => "line shader",
        }
        .into()
    }
}

impl ChoiceValue for TangentSource {
    fn choice_name(self) -> String {
        crate::choices::name(&self)
    }
}

/// Every switch, choice and slider of the scene, in the order they are listed.
pub(super) const CONTROLS: &[C] = &[
    C::toggle(
        'L',
        "TBN debug lines",
        "TBN debug lines on / off (normals blue, tangents red, bitangents green)",
        |c| c.show_lines,
        Cylinder::set_show_lines,
    )
    .flag("debug-lines", true, "Start with the TBN debug lines on")
    .in_title("lines")
    .inert_when(no_lines),
    C::choice(
        'M',
        "lines drawn with",
        "debug lines: immediate mode (compatibility profile) / line shader",
        &Choice {
            // A core context has no immediate mode to choose.
            values: |c| match c.legacy {
                Ok(_) => vec![LineMode::Legacy, LineMode::Shader],
                Err(_) => vec![LineMode::Shader],
            },
            get: Cylinder::shown_line_mode,
            set: Cylinder::set_line_mode,
        },
    )
    .enum_flag::<LineMode>(
        "debug-lines-mode",
        "MODE",
        "How to draw the debug lines: the tutorial's immediate mode (legacy, needs --profile \
         compat) or a line shader [default: immediate mode where the context allows it, else the \
         shader, with a notice]",
    )
    .inert_when(|c| {
        c.legacy
            .as_ref()
            .err()
            .map(|_| "this context has no immediate mode (a compatibility context has)")
    }),
    C::choice(
        'V',
        "colour view",
        "colour view: lit, light, light01, eye, eye01, normal, normal01",
        &Choice {
            values: |_| ColorView::CYCLE.to_vec(),
            get: |c| (c.switches.view.vector, c.switches.view.mapped),
            set: |c, (vector, mapped)| {
                switch(c, |sw| sw.view = sw.view.with_vector(vector, mapped))
            },
        },
    )
    .value_flag(
        "view",
        "NAME",
        "Colour view: lit, light, light01, eye, eye01, normal, normal01, optionally .x/.y/.z for \
         one component (key C) [default: lit]",
        Some(|arg| arg.value_parser(clap::value_parser!(ColorView))),
        |matches, long| {
            let view = given::<ColorView>(matches, long)?;
            Some(Start::choice((view.vector, view.mapped)))
        },
    )
    .in_title("view")
    .inert_when(per_pixel),
    C::choice(
        'C',
        "component",
        "colour view component: all, x, y, z",
        &Choice {
            values: |_| Component::ALL.to_vec(),
            get: |c| Component(c.switches.view.component),
            set: |c, Component(component)| switch(c, |sw| sw.view.component = component),
        },
    )
    // Its part of --view (normal01.y), which the colour view declares.
    .value_flag("view", "NAME", "", None, |matches, long| {
        let view = given::<ColorView>(matches, long)?;
        Some(Start::choice(Component(view.component)))
    })
    .inert_when(per_pixel),
    mesh_toggle!(
        'N',
        "normalize before summing",
        "normalize tangents before summing them (exercise 1)",
        indexing.normalize_before_sum
    )
    .flag(
        "normalize-before-sum",
        true,
        "Exercise 1: normalize tangents and bitangents before summing them",
    ),
    mesh_toggle!(
        'G',
        "Gram-Schmidt",
        "Gram-Schmidt on / off",
        tangents.gram_schmidt
    )
    .flag(
        "no-gram-schmidt",
        false,
        "Skip the Gram-Schmidt step of the tangent basis",
    ),
    mesh_toggle!(
        'H',
        "handedness fix",
        "handedness fix on / off",
        tangents.handedness
    )
    .flag(
        "no-handedness",
        false,
        "Skip the handedness fix of the tangent basis",
    ),
    shader_toggle!(
        'S',
        "specular texture",
        "specular texture / constant 0.3",
        specular_texture
    )
    .flag(
        "no-specular-texture",
        false,
        "Constant specular colour 0.3 instead of the specular texture",
    ),
    shader_toggle!(
        'T',
        "normalized TBN (article)",
        "TBN as summed (repository shader) / normalized (article)",
        normalize_tbn
    )
    .flag(
        "normalize-tbn",
        true,
        "Normalize the camera-space T, B, N as the article's text does",
    ),
    C::choice(
        'F',
        "tangent frame",
        "tangent frame: tutorial, MikkTSpace, per-pixel derivatives, a glTF file's own",
        &Choice {
            values: |c| c.mesh.soup.tangent_sources(),
            get: |c| c.mesh.source,
            set: Cylinder::set_tangent_source,
        },
    )
    .enum_flag::<TangentSource>(
        "tangents",
        "SOURCE",
        "Where the tangent frame comes from: the tutorial's computeTangentBasis + indexVBO_TBN, \
         MikkTSpace, none (a per-pixel frame from screen-space derivatives), or a glTF model's own \
         TANGENTs (MikkTSpace where it has none) [default: file for a glTF model, else tutorial]",
    )
    .in_title("tangents"),
    C::choice(
        'K',
        "compare view",
        "compare two tangent frames: off, side by side, difference heat map",
        &Choice {
            values: |_| Comparing::KEYS.to_vec(),
            get: Cylinder::comparing,
            set: Cylinder::set_comparing,
        },
    )
    .value_flag(
        "compare",
        "A,B",
        "Compare two tangent sources in one frame: A left of the split line, B right of it \
         (e.g. tutorial,mikktspace; A and D move the split)",
        Some(|arg| arg.value_parser(parse_pair)),
        read_compare,
    )
    .flag_modifier(
        COMPARE_DIFFERENCE,
        "With --compare: show the per-pixel difference as a heat map (its largest difference is \
         printed and in the title) instead of the two sides",
    )
    .inert_when(|c| c.unlike_comparison()),
    C::press(
        'A',
        "split line left",
        "compare view: split line left",
        |c| c.move_split(-0.05),
    )
    .inert_when(no_split),
    C::press(
        'D',
        "split line right",
        "compare view: split line right",
        |c| c.move_split(0.05),
    )
    .inert_when(no_split),
    shader_toggle!(
        'Y',
        "green down (DirectX)",
        "normal map green up (OpenGL) / down (DirectX)",
        convention.green_down
    )
    .shared_flag(Shared::Green, read_green_down),
    shader_toggle!(
        'E',
        "exact expansion",
        "normal map expansion 2c-1 / c*255/127-128/127 (exact 0 at 128)",
        convention.exact_expansion
    )
    .flag(
        "exact-expansion",
        true,
        "Read normal-map bytes as c*255/127-128/127 (128 is exactly 0) instead of 2c-1",
    ),
    shader_toggle!(
        'Z',
        "two channels",
        "normal map of three channels / two (z rebuilt)",
        convention.two_channel
    )
    .flag(
        "two-channel",
        true,
        "The normal map holds x and y only; rebuild z = sqrt(1 - x² - y²)",
    ),
    light_slider::<Cylinder, 0>(),
    light_slider::<Cylinder, 1>(),
    light_slider::<Cylinder, 2>(),
    power_slider::<Cylinder>(),
    C::slider(
        "normal strength",
        |_| (0.0, 4.0),
        |_| Knobs::TUTORIAL.normal_strength,
        |c| c.knobs.normal_strength,
        |c, value| {
            c.knobs.normal_strength = value;
            Ok(())
        },
    )
    .value_flag(
        "normal-strength",
        "S",
        "A factor on the normal map's x and y, as the panel's \"normal strength\" slider sets it \
         [default: 1, the map as it is]",
        Some(|arg| arg.value_parser(parse_finite)),
        read_slider,
    ),
    C::slider(
        "TBN line length",
        |_| (0.01, 1.0),
        |_| LINE_LENGTH,
        |c| c.line_length,
        Cylinder::set_line_length,
    )
    .value_flag(
        "line-length",
        "L",
        "The TBN debug lines' length, as the panel's slider sets it [default: the tutorial's 0.1]",
        Some(|arg| arg.value_parser(parse_length)),
        read_slider,
    )
    .inert_when(|c| match c.show_lines {
        true => no_lines(c),
        false => Some("the TBN lines are off (L)"),
    }),
    C::slider(
        "compare split",
        |_| (0.0, 1.0),
        |_| SPLIT_START,
        |c| c.compare_view.split,
        |c, value| {
            c.compare_view.split = value;
            Ok(())
        },
    )
    .value_flag(
        "split",
        "F",
        "With --compare: where the split line is, as a fraction of the width from the left \
         [default: 0.5]",
        Some(|arg| arg.value_parser(parse_fraction).requires("compare")),
        read_slider,
    )
    .inert_when(no_split),
];

/// `--compare A,B`'s switch for the difference view.
const COMPARE_DIFFERENCE: &str = "compare-difference";

/// `--compare A,B [--compare-difference]`: the pair, compared side by side or as their difference.
fn read_compare(matches: &clap::ArgMatches, long: &str) -> Option<Start> {
    let pair = *given::<[TangentSource; 2]>(matches, long)?;
    let mode = match given::<bool>(matches, COMPARE_DIFFERENCE) {
        Some(true) => CompareMode::Difference,
        _ => CompareMode::Split,
    };
    Some(Start::choice(Comparing::pair(pair, mode)))
}

fn parse_pair(s: &str) -> std::result::Result<[TangentSource; 2], String> {
    let (a, b) = s
        .split_once(',')
        .ok_or_else(|| format!("'{s}' is not A,B, e.g. tutorial,mikktspace"))?;
    let parse = |name: &str| <TangentSource as clap::ValueEnum>::from_str(name.trim(), false);
    Ok([parse(a)?, parse(b)?])
}

fn parse_length(s: &str) -> std::result::Result<f32, String> {
    parse_finite(s)
        .ok()
        .filter(|l| *l > 0.0)
        .ok_or_else(|| format!("'{s}' is not a length above 0"))
}

fn parse_fraction(s: &str) -> std::result::Result<f32, String> {
    s.parse::<f32>()
        .ok()
        .filter(|f| (0.0..=1.0).contains(f))
        .ok_or_else(|| format!("'{s}' is not a number from 0 to 1"))
}

/// A control of this scene, and a choice's values.
type C = Control<Cylinder>;
type Choice<T> = Choices<Cylinder, T>;

// The typed handles on the table's controls: what a caller starts them through
// (`SceneOptions::start`), as their flags do.
pub const LINES: Handle<Cylinder, bool> = Handle::new(CONTROLS, "TBN debug lines");
pub const LINE_MODE: Handle<Cylinder, LineMode> = Handle::new(CONTROLS, "lines drawn with");
pub const VIEW: Handle<Cylinder, (DebugVector, bool)> = Handle::new(CONTROLS, "colour view");
pub const COMPONENT: Handle<Cylinder, Component> = Handle::new(CONTROLS, "component");
pub const NORMALIZE_BEFORE_SUM: Handle<Cylinder, bool> =
    Handle::new(CONTROLS, "normalize before summing");
pub const GRAM_SCHMIDT: Handle<Cylinder, bool> = Handle::new(CONTROLS, "Gram-Schmidt");
pub const HANDEDNESS: Handle<Cylinder, bool> = Handle::new(CONTROLS, "handedness fix");
pub const SPECULAR_TEXTURE: Handle<Cylinder, bool> = Handle::new(CONTROLS, "specular texture");
pub const NORMALIZE_TBN: Handle<Cylinder, bool> = Handle::new(CONTROLS, "normalized TBN (article)");
pub const TANGENTS: Handle<Cylinder, TangentSource> = Handle::new(CONTROLS, "tangent frame");
pub const COMPARE: Handle<Cylinder, Comparing> = Handle::new(CONTROLS, "compare view");
pub const GREEN_DOWN: Handle<Cylinder, bool> = Handle::new(CONTROLS, "green down (DirectX)");
pub const EXACT_EXPANSION: Handle<Cylinder, bool> = Handle::new(CONTROLS, "exact expansion");
pub const TWO_CHANNEL: Handle<Cylinder, bool> = Handle::new(CONTROLS, "two channels");
pub const NORMAL_STRENGTH: Handle<Cylinder, f32> = Handle::new(CONTROLS, "normal strength");
pub const TBN_LINE_LENGTH: Handle<Cylinder, f32> = Handle::new(CONTROLS, "TBN line length");
pub const SPLIT: Handle<Cylinder, f32> = Handle::new(CONTROLS, "compare split");
pub const LIGHT_POWER: Handle<Cylinder, f32> = crate::scenes::lights::light_power(CONTROLS);

/// The starts of the colour view `view` (its vector and mapping, and its component), as `--view`
/// gives them.
pub fn view(view: ColorView) -> [Setting<Cylinder>; 2] {
    [
        VIEW.to((view.vector, view.mapped)),
        COMPONENT.to(Component(view.component)),
    ]
}

/// The starts of the CPU pipeline's switches `options` (Gram-Schmidt, handedness, normalize before
/// summing), as their flags give them.
pub fn pipeline(options: MeshOptions) -> [Setting<Cylinder>; 3] {
    [
        GRAM_SCHMIDT.to(options.tangents.gram_schmidt),
        HANDEDNESS.to(options.tangents.handedness),
        NORMALIZE_BEFORE_SUM.to(options.indexing.normalize_before_sum),
    ]
}

/// The starts of the normal map's convention `convention` (green down, exact expansion, two
/// channels), as their flags give them.
pub fn convention(convention: NormalMapConvention) -> [Setting<Cylinder>; 3] {
    [
        GREEN_DOWN.to(convention.green_down),
        EXACT_EXPANSION.to(convention.exact_expansion),
        TWO_CHANNEL.to(convention.two_channel),
    ]
}

/// The starts of the light at `position` (world space, or a model's own coordinates), as `--light`
/// gives them.
pub fn light_at(position: Vec3) -> [Setting<Cylinder>; 3] {
    crate::scenes::lights::light_at(CONTROLS, position)
}

/// The tangent source the scene starts with where no start gives one (`--tangents`): a glTF
/// model's own tangents, as its specification says; the tutorial's otherwise.
pub(super) fn default_tangents(model: Option<&std::path::Path>) -> TangentSource {
    match model.is_some_and(crate::model::Format::is_gltf) {
        true => TangentSource::File,
        false => TangentSource::Tutorial,
    }
}

/// Not a [`crate::scenes::lights::WorldLight`] as the cube's and the wall's: the panel moves the light
/// in the space `--light` uses (a model's own coordinates), which is placed into world space, with
/// its box and start in that space and its power one of the shader's knobs.
impl PointLight for Cylinder {
    const POWER_MAX: f32 = 200.0;

    /// The light (in the space `--light` uses) and the panel's light power.
    fn light(&self) -> (Vec3, f32) {
        (self.light, self.knobs.light_power)
    }
    fn light_start(&self) -> (Vec3, f32) {
        (self.light_start, Knobs::TUTORIAL.light_power)
    }
    /// Room around the tutorial's cylinder (radius 1, height 2, light 4 away), or around the model
    /// placed on its bounding sphere, in the model's own coordinates.
    fn light_range(&self) -> (Vec3, Vec3) {
        let world = LIGHT_RANGE;
        match &self.mesh.soup {
            SoupSource::Model(model) => {
                let [a, b] = [world.0, world.1].map(|p| model.placement.to_file(p));
                (a.min(b), a.max(b))
            }
            SoupSource::Tutorial(_) => world,
        }
    }
    /// Back at its start, the light is where the scene started, whatever the placement rounds.
    fn set_light(&mut self, position: Vec3, power: f32) -> Result<()> {
        self.knobs.light_power = power;
        self.light = position;
        let world = match position == self.light_start {
            true => self.light_start_world,
            false => self.mesh.soup.to_world(position),
        };
        self.move_light(world)
    }
}
