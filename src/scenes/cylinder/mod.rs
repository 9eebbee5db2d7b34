//! The `cylinder` scene: Tutorial 13 ([`Tutorial13`]) with the article's debugging aids as keys.
//!
//! The tutorial's experiments are edits to its source; here they are switches: the colour views and
//! shader experiments (drawn with `NormalMappingDebug.*`, see [`crate::debug::views`]), the CPU
//! pipeline's switches (Gram-Schmidt, handedness, normalize before summing: the mesh is rebuilt), and
//! the TBN debug lines (immediate mode, or the line shader).

pub mod args;
pub mod maps;
pub mod tutorial13;

use std::path::{Path, PathBuf};
use std::rc::Rc;

use glam::Vec3;
use glow::HasContext;

use crate::common::objloader::{load_obj, TriangleSoup};
use crate::common::shader::shader_paths;
use crate::debug::compare::{CompareMode, CompareView};
use crate::debug::lines::{DebugLines, LegacyGl, LineMode, LINE_LENGTH, LINE_SHADERS};
use crate::debug::views::{ColorView, ShaderSwitches};
use crate::gl::buffers::MeshBuffers;
use crate::gl::state::GlState;
use crate::gl::Gl;
use crate::mesh::MeshOptions;
use crate::model::{
    load_model, MapOverrides, Model, TUTORIAL_CYLINDER_CENTER, TUTORIAL_CYLINDER_RADIUS,
};
use crate::progress::Progress;
use crate::tangents::TangentSource;
use crate::Result;

use super::descriptor::{SceneDescriptor, SceneType};
use super::options::SceneOptions;
use super::scene::{
    drawing_program, CompareLabels, DrawingProgram, FrameInput, Scene, SceneContext,
};
use super::table::{
    key_count, key_help, light_slider, power_slider, Control, KeyHelp, PointLight, SceneControls,
};
pub use args::CylinderArgs;
use maps::{model_texture_sets, override_tutorial_maps};
use tutorial13::{NormalMappingProgram, Tutorial13, CLEAR_COLOR, SHADERS};

/// The scene as the rest of the program knows it.
pub static SCENE: SceneDescriptor = SceneDescriptor {
    shared_args: &["green", "light"],
    generate_assets: crate::assets::generate_cylinder_assets,
    open_file: open_model,
    ..SceneDescriptor::of::<Cylinder>(
        "cylinder",
        "Tutorial 13: the normal-mapped cylinder, with its debugging aids as keys (the \
                  default)",
        KEYS,
    )
};

/// `indexVBO_TBN` merges a corner into an earlier vertex within 0.01 of it (position, UV and normal,
/// in the tutorial's units): on a model much denser than the tutorial's cylinder that moves corners.
/// Says so once, with how many moved, since the model then looks coarser than it is.
fn warn_of_merged_corners(model: &Model, mesh: &crate::common::vboindexer::IndexedMesh) {
    let moved = (0..mesh.indices.len())
        .filter(|&i| mesh.vertices[mesh.indices.get(i) as usize] != model.soup.vertices[i])
        .count();
    if moved > 0 {
        log::warn!(
            "{}: indexVBO_TBN's 0.01 tolerance moved {moved} of {} corners onto a neighbour (the \
             tutorial's indexer, on a model denser than its cylinder); F switches to MikkTSpace, \
             which merges only equal corners",
            model.path.display(),
            mesh.indices.len()
        );
    }
}

/// The flags of `options` that the per-pixel frame (`--tangents derivative`, alone) does nothing
/// with, as they were given.
fn flags_without_effect(options: &CylinderOptions) -> Vec<String> {
    if options.tangents != TangentSource::Derivative || options.compare.is_some() {
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

/// A dropped `.obj` file is opened as `--model` (the other options stay as they were).
fn open_model(path: &Path, options: &mut SceneOptions) -> bool {
    let is_obj = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("obj"));
    if is_obj {
        options.get_mut::<CylinderOptions>().model = Some(path.to_path_buf());
    }
    is_obj
}

/// The tutorial's state (`init_gl_state`), applied at the start of every frame: another scene may
/// have drawn on this context since the cylinder was built.
const GL_STATE: GlState = GlState::opaque_3d(CLEAR_COLOR);

/// What the compare view starts with (`--compare A,B`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CompareOptions {
    /// Left of the split, and right of it (or subtracted from each other).
    pub sources: [TangentSource; 2],
    pub mode: CompareMode,
    /// Fraction of the width left of the split.
    pub split: f32,
}

/// The cylinder's switches, as the command line sets them.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct CylinderOptions {
    /// The CPU pipeline's switches (Gram-Schmidt, handedness, normalize before summing).
    pub mesh: MeshOptions,
    /// The shader's switches and the colour view.
    pub switches: ShaderSwitches,
    /// Start with the TBN debug lines on.
    pub debug_lines: bool,
    /// `None`: immediate mode where the context allows it, else the line shader.
    pub line_mode: Option<LineMode>,
    /// Where the tangent frame comes from (`--tangents`).
    pub tangents: TangentSource,
    /// Start in the compare view.
    pub compare: Option<CompareOptions>,
    /// `--model FILE.obj`: a learner's model in place of the tutorial's cylinder.
    pub model: Option<PathBuf>,
    /// `--diffuse`, `--normal-map`, `--specular`, `--height`: maps over the model's or the tutorial's.
    pub maps: MapOverrides,
    /// `--light X,Y,Z`: world space for the tutorial's cylinder, the file's coordinates for a model.
    pub light: Option<Vec3>,
}

/// Why a switch of the colour views and shader experiments does nothing with the per-pixel frame.
const PER_PIXEL: &str =
    "the per-pixel frame (F = derivative) draws the lit picture without the experiments";

/// Whether the per-pixel frame draws (alone: the compare view draws each side's own).
fn per_pixel(cylinder: &Cylinder) -> Option<&'static str> {
    let alone = cylinder.comparison.is_none();
    (alone && cylinder.tangent_source == TangentSource::Derivative).then_some(PER_PIXEL)
}

/// Why the TBN lines are not drawn, if they cannot be.
fn no_lines(cylinder: &Cylinder) -> Option<&'static str> {
    if cylinder.comparison.is_some() {
        Some("the compare view draws no TBN lines")
    } else if cylinder.tangent_source == TangentSource::Derivative {
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

/// Runs the CPU pipeline again with `change` made to its switches.
fn mesh_switch(cylinder: &mut Cylinder, change: impl FnOnce(&mut MeshOptions)) -> Result<()> {
    let mut mesh = cylinder.mesh_options;
    change(&mut mesh);
    cylinder.set_mesh_options(mesh)
}

/// The colour view's component names, [`ColorView::component`] `None`, 0, 1, 2.
const COMPONENTS: [&str; 4] = ["all", "x", "y", "z"];

/// The compare view's states on the panel: off, [`CompareMode::Split`], [`CompareMode::Difference`].
const COMPARE_NAMES: [&str; 3] = ["off", "side by side", "difference"];

fn names(names: &[&str]) -> Vec<String> {
    names.iter().map(|n| n.to_string()).collect()
}

/// Every switch, choice and slider of the scene, in the order they are listed.
const CONTROLS: &[C] = &[
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
    C::toggle(
        'N',
        "normalize before summing",
        "normalize tangents before summing them (exercise 1)",
        |c| c.mesh_options.indexing.normalize_before_sum,
        |c, on| mesh_switch(c, |m| m.indexing.normalize_before_sum = on),
    ),
    C::toggle(
        'G',
        "Gram-Schmidt",
        "Gram-Schmidt on / off",
        |c| c.mesh_options.tangents.gram_schmidt,
        |c, on| mesh_switch(c, |m| m.tangents.gram_schmidt = on),
    ),
    C::toggle(
        'H',
        "handedness fix",
        "handedness fix on / off",
        |c| c.mesh_options.tangents.handedness,
        |c, on| mesh_switch(c, |m| m.tangents.handedness = on),
    ),
    C::toggle(
        'S',
        "specular texture",
        "specular texture / constant 0.3",
        |c| c.switches.specular_texture,
        |c, on| switch(c, |sw| sw.specular_texture = on),
    )
    .inert_when(per_pixel),
    C::toggle(
        'T',
        "normalized TBN (article)",
        "TBN as summed (repository shader) / normalized (article)",
        |c| c.switches.normalize_tbn,
        |c, on| switch(c, |sw| sw.normalize_tbn = on),
    )
    .inert_when(per_pixel),
    C::choice(
        'F',
        "tangent frame",
        "tangent frame: tutorial, MikkTSpace, per-pixel derivatives",
        |_| crate::choices::names::<TangentSource>(),
        |c| c.tangent_source.to_string(),
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
    C::toggle(
        'Y',
        "green down (DirectX)",
        "normal map green up (OpenGL) / down (DirectX)",
        |c| c.switches.convention.green_down,
        |c, on| switch(c, |sw| sw.convention.green_down = on),
    )
    .inert_when(per_pixel),
    C::toggle(
        'E',
        "exact expansion",
        "normal map expansion 2c-1 / c*255/127-128/127 (exact 0 at 128)",
        |c| c.switches.convention.exact_expansion,
        |c, on| switch(c, |sw| sw.convention.exact_expansion = on),
    )
    .inert_when(per_pixel),
    C::toggle(
        'Z',
        "two channels",
        "normal map of three channels / two (z rebuilt)",
        |c| c.switches.convention.two_channel,
        |c, on| switch(c, |sw| sw.convention.two_channel = on),
    )
    .inert_when(per_pixel),
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
        |c| c.compare_start_split,
        |c| c.compare_view.split,
        |c, value| {
            c.compare_view.split = value;
            Ok(())
        },
    )
    .inert_when(no_split),
];

/// A colour view's name without its component ("light01").
fn view_name(vector: crate::debug::views::DebugVector, mapped: bool) -> String {
    ColorView::default().with_vector(vector, mapped).to_string()
}

/// A control of this scene.
type C = Control<Cylinder>;

/// The key list `--help` and the window print.
pub const KEYS: &[KeyHelp] = &key_help::<Cylinder, { key_count(CONTROLS) }>(CONTROLS);

/// Tutorial 13 and the state of its debugging aids.
pub struct Cylinder {
    // Field order is drop order; all hold GL objects of the same context.
    /// Built the first time they are shown, so that a run without them neither loads their shader
    /// nor prints the core-profile notice.
    lines: Option<DebugLines>,
    /// `NormalMappingDebug`: the same lighting with the experiments and colour views as uniforms.
    debug_program: DebugProgram,
    /// `NormalMappingDerivative`: the per-pixel tangent frame, for [`TangentSource::Derivative`].
    derivative_program: NormalMappingProgram,
    /// Its light power and normal strength.
    derivative_knobs: KnobUniforms,
    /// The panel's light power and normal strength (the tutorial's unless moved).
    pub knobs: Knobs,
    /// The compare view's split at the start (`--compare`'s, or the middle).
    compare_start_split: f32,
    /// The light as the panel shows it, in the space `--light` uses (the model's own coordinates
    /// with `--model`, else world space): set there, it is placed as `--light` is, to the bit.
    light: Vec3,
    /// Where it started (`--light`, or the tutorial's), in that space and in world space.
    light_start: Vec3,
    light_start_world: Vec3,
    /// The TBN lines' length (the tutorial's [`LINE_LENGTH`] unless the panel moved it).
    line_length: f32,
    /// Where the tangent frame comes from.
    pub tangent_source: TangentSource,
    /// The two sources compared, with their meshes uploaded, while the compare view is on.
    comparison: Option<([TangentSource; 2], [MeshBuffers; 2])>,
    /// The sources the compare key compares (`--compare`, else the current one and the next).
    compare_sources: Option<[TangentSource; 2]>,
    /// The compare view's mode, split and last difference (drawn while `comparison` is on).
    compare_view: CompareView,
    pub tutorial: Tutorial13,
    gl: Gl,
    pub switches: ShaderSwitches,
    /// Draw through `NormalMappingDebug` even with the tutorial's switches (to compare the two
    /// programs, which must give the same frame).
    pub use_debug_program: bool,
    mesh_options: MeshOptions,
    show_lines: bool,
    /// The immediate-mode entry points, or why this context has none.
    legacy: std::result::Result<LegacyGl, String>,
    line_mode: Option<LineMode>,
    /// Where the CPU pipeline's soup comes from when a switch re-runs it.
    soup_source: SoupSource,
    shader_dir: Option<PathBuf>,
    /// The tangent source of every mesh the CPU pipeline built since the scene was loaded.
    meshes_built: Vec<TangentSource>,
}

/// The mesh the scene draws: the tutorial's `cylinder.obj` (read again by `loadOBJ` whenever the
/// pipeline re-runs, as an edit of the tutorial would), or a learner's model, read once.
enum SoupSource {
    Tutorial(PathBuf),
    Model(Rc<Model>),
}

impl SoupSource {
    /// A point of the space `--light` uses (the model's own coordinates, or the tutorial's world
    /// space) where the program draws it.
    fn to_world(&self, p: Vec3) -> Vec3 {
        match self {
            SoupSource::Model(model) => model.placement.to_world(p),
            SoupSource::Tutorial(_) => p,
        }
    }

    fn soup(&self) -> Result<std::borrow::Cow<'_, TriangleSoup>> {
        Ok(match self {
            SoupSource::Tutorial(path) => std::borrow::Cow::Owned(load_obj(path)?),
            SoupSource::Model(model) => std::borrow::Cow::Borrowed(&model.soup),
        })
    }
}

impl SceneType for Cylinder {
    type Args = CylinderArgs;
    const CONTROLS: &'static [Control<Self>] = CONTROLS;

    /// Loads the tutorial's four files from `assets` and the shaders from `shader_dir` (or the
    /// crate's), and starts with `cylinder`'s switches.
    fn new(
        context: &SceneContext,
        files: &SceneOptions,
        cylinder: CylinderOptions,
    ) -> Result<Self> {
        let shader_dir = files.shader_dir();
        let gl = context.gl;
        let (mut tutorial, soup_source) = match &cylinder.model {
            None => {
                let assets = files.asset_files(crate::assets::ASSET_FILES)?;
                let mut tutorial = Tutorial13::new(gl, &assets, shader_dir, cylinder.mesh)?;
                override_tutorial_maps(gl, &mut tutorial.texture_sets[0], &cylinder.maps)?;
                let [obj, ..] = assets;
                (tutorial, SoupSource::Tutorial(obj))
            }
            Some(path) => {
                let _progress = Progress::start(format!("loading {}", path.display()));
                let start = std::time::Instant::now();
                let model = load_model(path, &cylinder.maps)?;
                let parsed = start.elapsed();
                let sets = model_texture_sets(gl, &model)?;
                log::debug!(
                    "{}: read and parsed in {:.1} ms, maps decoded and uploaded in {:.1} ms",
                    path.display(),
                    parsed.as_secs_f64() * 1000.0,
                    (start.elapsed() - parsed).as_secs_f64() * 1000.0
                );
                let tutorial =
                    Tutorial13::from_soup(gl, shader_dir, &model.soup, cylinder.mesh, sets)?;
                warn_of_merged_corners(&model, &tutorial.mesh);
                (tutorial, SoupSource::Model(Rc::new(model)))
            }
        };
        if let Some(light) = cylinder.light {
            tutorial.light_position_worldspace = soup_source.to_world(light);
        }
        // The panel shows the light where `--light` puts it: in the model's own coordinates.
        let light_start_world = tutorial.light_position_worldspace;
        let light_start = match (cylinder.light, &soup_source) {
            (Some(light), _) => light,
            (None, SoupSource::Model(model)) => model.placement.to_file(light_start_world),
            (None, SoupSource::Tutorial(_)) => light_start_world,
        };
        let debug_program = DebugProgram::load(gl, shader_dir)?;
        let [vertex_shader, fragment_shader] = DERIVATIVE_SHADERS;
        let derivative_program =
            NormalMappingProgram::load(gl, vertex_shader, fragment_shader, shader_dir)?;
        let mut scene = Cylinder {
            lines: None,
            debug_program,
            derivative_knobs: KnobUniforms::locate(&derivative_program.program)?,
            derivative_program,
            knobs: Knobs::TUTORIAL,
            light: light_start,
            light_start,
            light_start_world,
            line_length: LINE_LENGTH,
            compare_start_split: cylinder.compare.map_or(0.5, |c| c.split.clamp(0.0, 1.0)),
            tangent_source: TangentSource::Tutorial,
            comparison: None,
            compare_sources: cylinder.compare.map(|c| c.sources),
            compare_view: CompareView::new(
                gl,
                context.info,
                context.loader,
                cylinder.compare.map_or(CompareMode::Split, |c| c.mode),
                cylinder.compare.map_or(0.5, |c| c.split),
            ),
            tutorial,
            gl: gl.clone(),
            switches: cylinder.switches,
            use_debug_program: false,
            mesh_options: cylinder.mesh,
            show_lines: false,
            legacy: LegacyGl::load_or_reason(context.info, context.loader),
            line_mode: cylinder.line_mode,
            soup_source,
            shader_dir: shader_dir.map(Path::to_path_buf),
            meshes_built: Vec::new(),
        };
        scene.set_tangent_source(cylinder.tangents)?;
        if let Some(compare) = cylinder.compare {
            scene.start_comparison(compare.sources)?;
        }
        scene.set_show_lines(cylinder.debug_lines)?;
        let flags = flags_without_effect(&cylinder);
        if !flags.is_empty() {
            log::warn!(
                "--tangents derivative: {PER_PIXEL}: {} change nothing",
                flags.join(", ")
            );
        }
        if let Some(reason) = scene.comparison.as_ref().and(scene.unlike_comparison()) {
            log::warn!("--compare: {reason}");
        }
        Ok(scene)
    }
}

impl Cylinder {
    /// The CPU pipeline's current switches.
    pub fn mesh_options(&self) -> MeshOptions {
        self.mesh_options
    }

    /// The tangent source of every mesh the CPU pipeline built since the scene was loaded (the
    /// first one aside), in order.
    pub fn meshes_built(&self) -> &[TangentSource] {
        &self.meshes_built
    }

    /// Whether the TBN lines are shown.
    pub fn show_lines(&self) -> bool {
        self.show_lines
    }

    /// Draws with another tangent source: the mesh is rebuilt (with the tutorial's tangents,
    /// MikkTSpace's, or none for the per-pixel frame) and the lines with it.
    pub fn set_tangent_source(&mut self, source: TangentSource) -> Result<()> {
        if source == self.tangent_source {
            return Ok(());
        }
        self.rebuild_mesh(source, self.mesh_options)?;
        self.tangent_source = source;
        Ok(())
    }

    /// Shows `sources` in the compare view (each drawn whole, the first left of the split).
    pub fn start_comparison(&mut self, sources: [TangentSource; 2]) -> Result<()> {
        let soup = self.soup_source.soup()?;
        self.meshes_built.extend(sources);
        let upload = |source: TangentSource| -> Result<MeshBuffers> {
            MeshBuffers::new(&self.gl, &source.mesh(&soup, self.mesh_options)?)
        };
        self.comparison = Some((sources, [upload(sources[0])?, upload(sources[1])?]));
        Ok(())
    }

    /// Back to one frame.
    pub fn stop_comparison(&mut self) {
        self.comparison = None;
    }

    /// The compare view's state, while it is on.
    pub fn compare_view(&self) -> Option<&CompareView> {
        self.comparison.as_ref().map(|_| &self.compare_view)
    }

    /// " | compare A | B at 50 %" or " | compare A − B: N pixels differ, max M levels", or nothing.
    fn compare_status(&self) -> String {
        let (Some((sources, _)), view) = (&self.comparison, &self.compare_view) else {
            return String::new();
        };
        let [a, b] = sources;
        match (view.mode, view.difference) {
            (CompareMode::Split, _) => {
                format!(" | compare {a} | {b} at {:.0} %", view.split * 100.0)
            }
            (CompareMode::Difference, Some(d)) => format!(
                " | compare {a} - {b}: {} pixels differ, max {} levels",
                d.pixels, d.max
            ),
            (CompareMode::Difference, None) => format!(" | compare {a} - {b}"),
        }
    }

    /// Runs the CPU pipeline of `source` with `options` and uploads the result; the lines follow
    /// (the per-pixel frame has no vertex tangents to show, so they are dropped until another source).
    fn rebuild_mesh(&mut self, source: TangentSource, options: MeshOptions) -> Result<()> {
        self.meshes_built.push(source);
        match (&self.soup_source, source) {
            (SoupSource::Tutorial(path), TangentSource::Tutorial) => {
                self.tutorial.reload_mesh(path, options)?
            }
            (soup_source, _) => {
                let soup = soup_source.soup()?;
                self.tutorial.set_mesh(source.mesh(&soup, options)?)?;
            }
        }
        if source == TangentSource::Derivative {
            self.lines = None;
        } else if let Some(lines) = &mut self.lines {
            lines.rebuild(&self.tutorial.mesh)?;
        } else if self.show_lines {
            self.tangent_source = source;
            self.set_show_lines(true)?;
        }
        Ok(())
    }

    /// Shows or hides the TBN lines, building them (from the current mesh) the first time. With the
    /// per-pixel frame there are no vertex tangents to draw: the switch is kept, nothing is drawn.
    pub fn set_show_lines(&mut self, show: bool) -> Result<()> {
        let has_tangents = self.tangent_source != TangentSource::Derivative;
        if show && has_tangents && self.lines.is_none() {
            let lines = DebugLines::with_legacy(
                &self.gl,
                self.legacy.clone(),
                &self.tutorial.mesh,
                self.tutorial.light_position_worldspace,
                self.line_mode,
                self.shader_dir.as_deref(),
            )?;
            self.lines = Some(lines);
            self.set_line_length(self.line_length)?;
        }
        self.show_lines = show;
        Ok(())
    }

    /// The path the lines are drawn with, once they have been shown.
    pub fn line_mode(&self) -> Option<LineMode> {
        self.lines.as_ref().map(DebugLines::mode)
    }

    /// Why immediate mode is not used, if it was wanted and is not.
    pub fn line_notice(&self) -> Option<&str> {
        self.lines.as_ref().and_then(DebugLines::notice)
    }

    /// The path the lines are drawn with (or will be, once shown).
    fn shown_line_mode(&self) -> LineMode {
        match self.line_mode().or(self.line_mode) {
            Some(LineMode::Legacy) | None if self.legacy.is_ok() => LineMode::Legacy,
            _ => LineMode::Shader,
        }
    }

    /// Draws the lines with `mode` (immediate mode falls back to the line shader, with a notice,
    /// where the context has none).
    pub fn set_line_mode(&mut self, mode: LineMode) -> Result<()> {
        self.line_mode = Some(mode);
        if let Some(lines) = &mut self.lines {
            lines.set_mode(mode)?;
        }
        Ok(())
    }

    /// Runs the CPU pipeline again with `mesh` (the compare view's meshes too), if it changed.
    pub fn set_mesh_options(&mut self, mesh: MeshOptions) -> Result<()> {
        if mesh != self.mesh_options {
            self.rebuild_mesh(self.tangent_source, mesh)?;
            self.mesh_options = mesh;
            if let Some((sources, _)) = self.comparison {
                self.start_comparison(sources)?;
            }
        }
        Ok(())
    }

    /// The compare view `name` (one of [`COMPARE_NAMES`]): off, or on in that mode, comparing
    /// `--compare`'s sources, else the current one and the next. A comparison of a colour view
    /// with the per-pixel frame, which draws none, is not started.
    fn set_compare(&mut self, name: &str) -> Result<()> {
        let mode = match name {
            "side by side" => CompareMode::Split,
            "difference" => CompareMode::Difference,
            _ => {
                self.stop_comparison();
                return Ok(());
            }
        };
        if self.comparison.is_none() {
            if self.unlike_comparison().is_some() {
                return Ok(());
            }
            self.compare_view.mode = mode;
            self.start_comparison(self.sources_to_compare())?;
        }
        self.compare_view.mode = mode;
        Ok(())
    }

    /// The sources the compare key compares.
    fn sources_to_compare(&self) -> [TangentSource; 2] {
        let current = self.tangent_source;
        let compared = self.comparison.as_ref().map(|(sources, _)| *sources);
        compared
            .or(self.compare_sources)
            .unwrap_or([current, current.next()])
    }

    /// Why the compare view would not compare like with like: a colour view on, and a side drawn
    /// with the per-pixel frame, which draws the lit picture only.
    fn unlike_comparison(&self) -> Option<&'static str> {
        let colour_view = self.switches.view != ColorView::default();
        let derivative = self
            .sources_to_compare()
            .contains(&TangentSource::Derivative);
        (colour_view && derivative).then_some(
            "a colour view is on (V) and a side is the per-pixel frame, which draws none: the two \
             sides would not show the same thing",
        )
    }

    /// Moves the compare view's split line by `step` of the width.
    fn move_split(&mut self, step: f32) -> Result<()> {
        let view = &mut self.compare_view;
        view.split = (view.split + step).clamp(0.0, 1.0);
        Ok(())
    }
}

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
        let world = (Vec3::splat(-10.0), Vec3::splat(10.0));
        match &self.soup_source {
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
            false => self.soup_source.to_world(position),
        };
        self.move_light(world)
    }
}

/// Which program draws a tangent source's frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Drawing {
    /// `NormalMapping.*`, the tutorial's, as it is.
    Tutorial,
    /// `NormalMappingDebug.*`: an experiment, a colour view or a panel slider is away from the
    /// tutorial's.
    Debug,
    /// `NormalMappingDerivative.*`: the per-pixel frame.
    Derivative,
}

impl Drawing {
    /// The program's name and its two files.
    fn shaders(self) -> (&'static str, [&'static str; 2]) {
        match self {
            Drawing::Tutorial => ("NormalMapping (the tutorial's)", SHADERS),
            Drawing::Debug => ("NormalMappingDebug (the experiments)", DEBUG_SHADERS),
            Drawing::Derivative => (
                "NormalMappingDerivative (per-pixel frame)",
                DERIVATIVE_SHADERS,
            ),
        }
    }
}

/// What draws one tangent source's frame: the tutorial with the program that the source and the
/// switches need. Borrowed from the scene's fields, apart from its compare view (which calls it).
struct SourceDrawer<'a> {
    tutorial: &'a Tutorial13,
    debug_program: &'a DebugProgram,
    derivative_program: &'a NormalMappingProgram,
    derivative_knobs: &'a KnobUniforms,
    switches: ShaderSwitches,
    knobs: Knobs,
    use_debug_program: bool,
}

impl SourceDrawer<'_> {
    /// The tutorial's own program unless an experiment, a colour view or a slider asks for the
    /// debug one; the per-pixel frame has a program of its own (without the experiments).
    fn drawing(&self, source: TangentSource) -> Drawing {
        if source == TangentSource::Derivative {
            Drawing::Derivative
        } else if self.switches == ShaderSwitches::default()
            && self.knobs == Knobs::TUTORIAL
            && !self.use_debug_program
        {
            Drawing::Tutorial
        } else {
            Drawing::Debug
        }
    }

    /// The program for `source`, current and with its switches set.
    fn program(&self, source: TangentSource) -> &NormalMappingProgram {
        match self.drawing(source) {
            Drawing::Tutorial => &self.tutorial.program,
            Drawing::Debug => {
                self.debug_program.set_switches(self.switches, self.knobs);
                &self.debug_program.program
            }
            Drawing::Derivative => {
                let program = self.derivative_program;
                self.knobs
                    .set(&self.debug_program.gl, program, self.derivative_knobs);
                program
            }
        }
    }

    /// One frame of `source` from `buffers`.
    fn draw(&self, source: TangentSource, buffers: &MeshBuffers, frame: &FrameInput) {
        let (projection, view) = (frame.projection, frame.view);
        let program = self.program(source);
        self.tutorial
            .draw_mesh_with(program, buffers, projection, view, None);
    }
}

/// The scene's [`SourceDrawer`], borrowing only the fields it names (a macro, not a method, so
/// that the compare view can be borrowed mutably beside it).
macro_rules! drawer {
    ($scene:expr) => {
        SourceDrawer {
            tutorial: &$scene.tutorial,
            debug_program: &$scene.debug_program,
            derivative_program: &$scene.derivative_program,
            derivative_knobs: &$scene.derivative_knobs,
            switches: $scene.switches,
            knobs: $scene.knobs,
            use_debug_program: $scene.use_debug_program,
        }
    };
}

impl Cylinder {
    /// Makes every TBN line `length` long (the tutorial's is [`LINE_LENGTH`]).
    pub fn set_line_length(&mut self, length: f32) -> Result<()> {
        self.line_length = length;
        match &mut self.lines {
            Some(lines) => lines.reshape(self.tutorial.light_position_worldspace, length),
            None => Ok(()),
        }
    }

    /// Moves the light (world space): the lighting's and the debug lines' cross.
    fn move_light(&mut self, light_position_worldspace: Vec3) -> Result<()> {
        self.tutorial.light_position_worldspace = light_position_worldspace;
        if let Some(lines) = &mut self.lines {
            let (_, length) = lines.shape();
            lines.reshape(light_position_worldspace, length)?;
        }
        Ok(())
    }
}

impl Scene for Cylinder {
    fn draw(&mut self, frame: &FrameInput) {
        GL_STATE.apply(&self.gl);
        let drawer = drawer!(self);
        if let Some((sources, buffers)) = &self.comparison {
            let view = &mut self.compare_view;
            let before = view.difference;
            let drawn = view.draw(
                frame.size,
                || drawer.draw(sources[0], &buffers[0], frame),
                || drawer.draw(sources[1], &buffers[1], frame),
            );
            if let Err(e) = drawn {
                log::error!("compare view: {e}");
            }
            if let Some(d) = view.difference.filter(|&d| Some(d) != before) {
                log::info!(
                    "{} vs {}: {} pixels differ, by at most {} levels",
                    sources[0],
                    sources[1],
                    d.pixels,
                    d.max
                );
            }
            return;
        }
        // The per-pixel frame has no vertex tangents to draw lines from.
        let lines = self
            .lines
            .as_ref()
            .filter(|_| self.show_lines && self.tangent_source != TangentSource::Derivative);
        let program = drawer.program(self.tangent_source);
        self.tutorial
            .draw_with(program, frame.projection, frame.view, lines);
    }

    /// A model is placed on the tutorial's cylinder's bounding sphere; the camera starts framing it.
    /// The tutorial's own cylinder keeps the tutorial's start.
    fn framing(&self) -> Option<(Vec3, f32)> {
        match self.soup_source {
            SoupSource::Model(_) => Some((TUTORIAL_CYLINDER_CENTER, TUTORIAL_CYLINDER_RADIUS)),
            SoupSource::Tutorial(_) => None,
        }
    }

    /// The tutorial's program, the debugging program and the line shader.
    fn shader_files(&self) -> Vec<PathBuf> {
        let programs = [SHADERS, DEBUG_SHADERS, DERIVATIVE_SHADERS, LINE_SHADERS];
        shader_paths(programs.into_iter().flatten(), self.shader_dir.as_deref())
    }

    /// All or nothing: every program is built before any replaces the one in use.
    fn reload_shaders(&mut self) -> Result<()> {
        let dir = self.shader_dir.as_deref();
        let [vertex_shader, fragment_shader] = SHADERS;
        let program = NormalMappingProgram::load(&self.gl, vertex_shader, fragment_shader, dir)?;
        let debug_program = DebugProgram::load(&self.gl, dir)?;
        let [vertex_shader, fragment_shader] = DERIVATIVE_SHADERS;
        let derivative = NormalMappingProgram::load(&self.gl, vertex_shader, fragment_shader, dir)?;
        let derivative_knobs = KnobUniforms::locate(&derivative.program)?;
        if let Some(lines) = &mut self.lines {
            lines.reload_shaders()?;
        }
        self.tutorial.program = program;
        self.debug_program = debug_program;
        self.derivative_program = derivative;
        self.derivative_knobs = derivative_knobs;
        Ok(())
    }

    /// The program each side draws with (and the lines' program when they are shown).
    fn drawing_programs(&self) -> Vec<DrawingProgram> {
        let drawer = drawer!(self);
        let sources = match &self.comparison {
            Some((sources, _)) => sources.to_vec(),
            None => vec![self.tangent_source],
        };
        let mut drawings: Vec<Drawing> = sources.iter().map(|&s| drawer.drawing(s)).collect();
        drawings.dedup();
        let dir = self.shader_dir.as_deref();
        let mut programs: Vec<DrawingProgram> = drawings
            .into_iter()
            .map(|d| {
                let (name, files) = d.shaders();
                drawing_program(name, files, dir)
            })
            .collect();
        let lines_drawn = self.show_lines
            && self.comparison.is_none()
            && self.tangent_source != TangentSource::Derivative;
        match self.line_mode().filter(|_| lines_drawn) {
            Some(LineMode::Legacy) => programs.push(DrawingProgram {
                name: "TBN lines: immediate mode (glBegin/glEnd, no shader)".into(),
                shaders: Vec::new(),
                dir: None,
            }),
            Some(LineMode::Shader) => {
                programs.push(drawing_program("TBN lines: DebugLines", LINE_SHADERS, dir))
            }
            None => {}
        }
        programs
    }

    fn compare_labels(&self) -> Option<CompareLabels> {
        let (sources, _) = self.comparison.as_ref()?;
        Some(CompareLabels {
            split: (self.compare_view.mode == CompareMode::Split)
                .then_some(self.compare_view.split),
            left: sources[0].to_string(),
            right: sources[1].to_string(),
        })
    }

    /// The colour view, the lines and the tangent frame (and the compare view or model if on).
    /// Those the table names in the title, where they apply (with the per-pixel frame, neither
    /// view nor lines).
    fn short_status(&self) -> String {
        let mut text = self.title_status().join(", ");
        if let Some((sources, _)) = &self.comparison {
            text += &format!(", compare {} | {}", sources[0], sources[1]);
        }
        if let SoupSource::Model(model) = &self.soup_source {
            let name = model.path.file_name().unwrap_or(model.path.as_os_str());
            text += &format!(", model {}", name.to_string_lossy());
        }
        text
    }

    /// View, lines, and every experiment switch (those that do nothing now left out: the
    /// per-pixel frame draws neither colour views, lines nor the shader's experiments).
    fn status(&self) -> String {
        let on = |b: bool| if b { "on" } else { "off" };
        let sw = self.switches;
        let mesh = self.mesh_options;
        let lines = match (self.show_lines, self.line_mode()) {
            (true, Some(LineMode::Legacy)) => "immediate mode",
            (true, _) => "line shader",
            (false, _) => "off",
        };
        let shader = per_pixel(self).is_none();
        let tbn = match sw.normalize_tbn {
            true => "normalized (article)",
            false => "as summed (repository)",
        };
        let mut parts = Vec::new();
        if let SoupSource::Model(model) = &self.soup_source {
            parts.push(format!("model {}", model.path.display()));
        }
        if shader {
            parts.push(format!("view {}", sw.view));
        }
        if no_lines(self).is_none() {
            parts.push(format!("lines {lines}"));
        }
        parts.extend([
            format!("Gram-Schmidt {}", on(mesh.tangents.gram_schmidt)),
            format!("handedness {}", on(mesh.tangents.handedness)),
            format!(
                "normalize before sum {}",
                on(mesh.indexing.normalize_before_sum)
            ),
        ]);
        if shader {
            parts.extend([
                format!("specular texture {}", on(sw.specular_texture)),
                format!("TBN {tbn}"),
                format!("normal map {}", sw.convention),
            ]);
        }
        parts.push(format!("tangents {}", self.tangent_source));
        parts.join(" | ") + &self.compare_status()
    }
}

/// The line paths' names on the panel: [`LineMode::Legacy`], [`LineMode::Shader`].
const LINE_MODE_NAMES: [&str; 2] = ["immediate mode", "line shader"];

fn line_mode_name(mode: LineMode) -> &'static str {
    match mode {
        LineMode::Legacy => LINE_MODE_NAMES[0],
        LineMode::Shader => LINE_MODE_NAMES[1],
    }
}

/// The per-pixel tangent frame's program.
pub const DERIVATIVE_SHADERS: [&str; 2] = [
    "NormalMappingDerivative.vertexshader",
    "NormalMappingDerivative.fragmentshader",
];

/// The debugging program's two files.
pub const DEBUG_SHADERS: [&str; 2] = [
    "NormalMappingDebug.vertexshader",
    "NormalMappingDebug.fragmentshader",
];

crate::uniforms! {
    /// `NormalMappingDebug.*`'s switches, beside the tutorial's handles.
    pub struct DebugUniforms {
        normalize_tbn: "NormalizeTBN",
        specular_texture: "UseSpecularTexture",
        green_down: "GreenDown",
        exact_expansion: "ExactExpansion",
        two_channel: "TwoChannel",
        debug_view: "DebugView",
        debug_mapped: "DebugMapped",
        debug_component: "DebugComponent",
    }
}

crate::uniforms! {
    /// The panel's light power and normal strength, in the debugging and per-pixel programs (the
    /// tutorial's shader has them as constants).
    pub struct KnobUniforms {
        light_power: "LightPower",
        normal_strength: "NormalStrength",
    }
}

/// The panel's sliders that only the debugging programs read: with the tutorial's values the
/// tutorial's own program draws.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Knobs {
    /// `LightPower`, 40 in the tutorial's shader.
    pub light_power: f32,
    /// A factor on the normal map's x and y before normalizing (1: the map as it is).
    pub normal_strength: f32,
}

impl Knobs {
    pub const TUTORIAL: Knobs = Knobs {
        light_power: 40.0,
        normal_strength: 1.0,
    };

    /// Makes `program` current and sets its two uniforms.
    fn set(&self, gl: &Gl, program: &NormalMappingProgram, uniforms: &KnobUniforms) {
        // SAFETY: the program and its uniforms belong to this context.
        unsafe {
            gl.use_program(Some(program.program.id));
            gl.uniform_1_f32(uniforms.light_power.as_ref(), self.light_power);
            gl.uniform_1_f32(uniforms.normal_strength.as_ref(), self.normal_strength);
        }
    }
}

/// `NormalMappingDebug`: the tutorial's uniforms plus one per switch.
pub struct DebugProgram {
    gl: Gl,
    pub program: NormalMappingProgram,
    switches: DebugUniforms,
    knobs: KnobUniforms,
}

impl DebugProgram {
    pub fn load(gl: &Gl, shader_dir: Option<&Path>) -> Result<Self> {
        let [vertex_shader, fragment_shader] = DEBUG_SHADERS;
        let program = NormalMappingProgram::load(gl, vertex_shader, fragment_shader, shader_dir)?;
        Ok(DebugProgram {
            gl: gl.clone(),
            switches: DebugUniforms::locate(&program.program)?,
            knobs: KnobUniforms::locate(&program.program)?,
            program,
        })
    }

    /// Makes the program current and sets its switches and the panel's sliders (the caller then
    /// draws with it).
    pub fn set_switches(&self, switches: ShaderSwitches, knobs: Knobs) {
        knobs.set(&self.gl, &self.program, &self.knobs);
        let gl = &self.gl;
        let view = switches.view;
        let u = &self.switches;
        // SAFETY: the program and its uniforms belong to this context.
        unsafe {
            gl.use_program(Some(self.program.program.id));
            gl.uniform_1_i32(u.normalize_tbn.as_ref(), switches.normalize_tbn as i32);
            gl.uniform_1_i32(
                u.specular_texture.as_ref(),
                switches.specular_texture as i32,
            );
            let convention = switches.convention;
            gl.uniform_1_i32(u.green_down.as_ref(), convention.green_down as i32);
            let exact = convention.exact_expansion as i32;
            gl.uniform_1_i32(u.exact_expansion.as_ref(), exact);
            gl.uniform_1_i32(u.two_channel.as_ref(), convention.two_channel as i32);
            gl.uniform_1_i32(u.debug_view.as_ref(), view.vector as i32);
            gl.uniform_1_i32(u.debug_mapped.as_ref(), view.mapped as i32);
            let component = view.component.map_or(-1, i32::from);
            gl.uniform_1_i32(u.debug_component.as_ref(), component);
        }
    }
}
