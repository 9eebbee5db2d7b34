//! The cylinder's table: every switch, choice and slider declared once, with when each does
//! nothing (the per-pixel frame draws the lit picture only), and the light's sliders in the space
//! `--light` uses.

use glam::Vec3;

use crate::debug::compare::{CompareMode, SPLIT_START};
use crate::debug::lines::{LineMode, LINE_LENGTH};
use crate::debug::views::{ColorView, ShaderSwitches};
use crate::mesh::MeshOptions;
use crate::scenes::table::{
    key_count, key_help, light_slider, power_slider, Control, KeyHelp, PointLight, LIGHT_RANGE,
};
use crate::tangents::TangentSource;
use crate::Result;

use super::programs::Knobs;
use super::{Cylinder, CylinderOptions, SoupSource};

/// The flags of `options` that the per-pixel frame (`--tangents derivative`, alone) does nothing
/// with, as they were given.
pub(super) fn flags_without_effect(options: &CylinderOptions) -> Vec<String> {
    if options.tangents.has_vertex_tangents() || options.compare.is_some() {
        return Vec::new();
    }
    let sw = options.switches;
    let convention = sw.convention;
    let flags = [
        (
            sw.view != ColorView::default(),
            format!("--view {}", sw.view),
        ),
        (!sw.specular_texture, "--no-specular-texture".into()),
        (sw.normalize_tbn, "--normalize-tbn".into()),
        (convention.green_down, "--green down".into()),
        (convention.exact_expansion, "--exact-expansion".into()),
        (convention.two_channel, "--two-channel".into()),
        (options.debug_lines, "--debug-lines".into()),
    ];
    flags
        .into_iter()
        .filter(|(given, _)| *given)
        .map(|(_, flag)| flag)
        .collect()
}

/// Why a switch of the colour views and shader experiments does nothing with the per-pixel frame.
pub(super) const PER_PIXEL: &str =
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

/// The colour view's component names, [`ColorView::component`] `None`, 0, 1, 2.
const COMPONENTS: [&str; 4] = ["all", "x", "y", "z"];

/// The compare view's states on the panel: off, [`CompareMode::Split`], [`CompareMode::Difference`].
pub(super) const COMPARE_NAMES: [&str; 3] = ["off", "side by side", "difference"];

fn names(names: &[&str]) -> Vec<String> {
    names.iter().map(|n| n.to_string()).collect()
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
    .in_title("lines")
    .inert_when(no_lines),
    C::choice(
        'M',
        "lines drawn with",
        "debug lines: immediate mode (compatibility profile) / line shader",
        // A core context has no immediate mode to choose.
        |c| match c.legacy {
            Ok(_) => names(&LINE_MODE_NAMES),
            Err(_) => names(&LINE_MODE_NAMES[1..]),
        },
        |c| line_mode_name(c.shown_line_mode()).into(),
        |c, name| {
            c.set_line_mode(if name == LINE_MODE_NAMES[0] {
                LineMode::Legacy
            } else {
                LineMode::Shader
            })
        },
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
        |_| {
            ColorView::CYCLE
                .iter()
                .map(|&(v, m)| view_name(v, m))
                .collect()
        },
        |c| {
            let view = c.switches.view;
            view_name(view.vector, view.mapped)
        },
        |c, name| {
            let cycle = ColorView::CYCLE.iter();
            let found = cycle.copied().find(|&(v, m)| view_name(v, m) == name);
            switch(c, |sw| {
                if let Some((vector, mapped)) = found {
                    sw.view = sw.view.with_vector(vector, mapped);
                }
            })
        },
    )
    .in_title("view")
    .inert_when(per_pixel),
    C::choice(
        'C',
        "component",
        "colour view component: all, x, y, z",
        |_| names(&COMPONENTS),
        |c| COMPONENTS[c.switches.view.component.map_or(0, |i| usize::from(i) + 1)].into(),
        |c, name| {
            let i = COMPONENTS.iter().position(|&n| n == name).unwrap_or(0);
            switch(c, |sw| {
                sw.view.component = i.checked_sub(1).map(|i| i as u8)
            })
        },
    )
    .inert_when(per_pixel),
    mesh_toggle!(
        'N',
        "normalize before summing",
        "normalize tangents before summing them (exercise 1)",
        indexing.normalize_before_sum
    ),
    mesh_toggle!(
        'G',
        "Gram-Schmidt",
        "Gram-Schmidt on / off",
        tangents.gram_schmidt
    ),
    mesh_toggle!(
        'H',
        "handedness fix",
        "handedness fix on / off",
        tangents.handedness
    ),
    shader_toggle!(
        'S',
        "specular texture",
        "specular texture / constant 0.3",
        specular_texture
    ),
    shader_toggle!(
        'T',
        "normalized TBN (article)",
        "TBN as summed (repository shader) / normalized (article)",
        normalize_tbn
    ),
    C::choice(
        'F',
        "tangent frame",
        "tangent frame: tutorial, MikkTSpace, per-pixel derivatives, a glTF file's own",
        tangent_source_names,
        |c| c.mesh.source.to_string(),
        |c, name| match crate::choices::by_name(name) {
            Some(source) => c.set_tangent_source(source),
            None => Ok(()),
        },
    )
    .in_title("tangents"),
    C::choice(
        'K',
        "compare view",
        "compare two tangent frames: off, side by side, difference heat map",
        |_| names(&COMPARE_NAMES),
        |c| {
            match (&c.comparison, c.compare_view.mode) {
                (None, _) => COMPARE_NAMES[0],
                (Some(_), CompareMode::Split) => COMPARE_NAMES[1],
                (Some(_), CompareMode::Difference) => COMPARE_NAMES[2],
            }
            .into()
        },
        Cylinder::set_compare,
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
    ),
    shader_toggle!(
        'E',
        "exact expansion",
        "normal map expansion 2c-1 / c*255/127-128/127 (exact 0 at 128)",
        convention.exact_expansion
    ),
    shader_toggle!(
        'Z',
        "two channels",
        "normal map of three channels / two (z rebuilt)",
        convention.two_channel
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
    ),
    C::slider(
        "TBN line length",
        |_| (0.01, 1.0),
        |_| LINE_LENGTH,
        |c| c.line_length,
        Cylinder::set_line_length,
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
    .inert_when(no_split),
];

/// The tangent sources key F steps through: `file` only for a glTF model.
pub(super) fn tangent_source_names(cylinder: &Cylinder) -> Vec<String> {
    let mut all = crate::choices::names::<TangentSource>();
    if !cylinder.mesh.soup.is_gltf() {
        all.retain(|n| *n != TangentSource::File.to_string());
    }
    all
}

/// A colour view's name without its component ("light01").
fn view_name(vector: crate::debug::views::DebugVector, mapped: bool) -> String {
    ColorView::default().with_vector(vector, mapped).to_string()
}

/// A control of this scene.
type C = Control<Cylinder>;

/// The key list `--help` and the window print.
pub const KEYS: &[KeyHelp] = &key_help::<Cylinder, { key_count(CONTROLS) }>(CONTROLS);

/// Not a [`crate::scenes::table::WorldLight`] as the cube's and the wall's: the panel moves the light
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

/// The line paths' names on the panel: [`LineMode::Legacy`], [`LineMode::Shader`].
pub(super) const LINE_MODE_NAMES: [&str; 2] = ["immediate mode", "line shader"];

pub(super) fn line_mode_name(mode: LineMode) -> &'static str {
    match mode {
        LineMode::Legacy => LINE_MODE_NAMES[0],
        LineMode::Shader => LINE_MODE_NAMES[1],
    }
}
