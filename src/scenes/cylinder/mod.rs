//! The `cylinder` scene: Tutorial 13 ([`Tutorial13`]) with the article's debugging aids as keys.
//!
//! The tutorial's experiments are edits to its source; here they are switches: the colour views and
//! shader experiments (drawn with `NormalMappingDebug.*`, see [`crate::debug::views`]), the CPU
//! pipeline's switches (Gram-Schmidt, handedness, normalize before summing: the mesh is rebuilt), and
//! the TBN debug lines (immediate mode, or the line shader).

pub mod args;
mod compare;
mod controls;
mod lines;
pub mod maps;
mod mesh;
mod programs;
pub mod tutorial13;

use std::path::{Path, PathBuf};
use std::rc::Rc;

use glam::Vec3;

use crate::debug::compare::{CompareMode, CompareView, SPLIT_START};
use crate::debug::lines::{LegacyGl, LineMode, LINE_LENGTH, LINE_SHADERS};
use crate::debug::views::ShaderSwitches;
use crate::gl::buffers::MeshBuffers;
use crate::gl::state::GlState;
use crate::gl::Gl;
use crate::mesh::MeshOptions;
use crate::model::{load_model, MapOverrides, TUTORIAL_CYLINDER_CENTER, TUTORIAL_CYLINDER_RADIUS};
use crate::progress::Progress;
use crate::tangent_source::TangentSource;
use crate::Result;

use super::descriptor::SceneType;
use super::options::{OwnArgs, SceneOptions};
use super::scene::{CompareLabels, DrawingProgram, FrameInput, Scene, SceneContext, ShaderSet};
use super::starts::Starts;
use super::table::{Control, SceneControls};
pub use args::{CylinderArgs, CylinderFiles};
pub use controls::{
    convention, light_at, pipeline, view, Comparing, Component, COMPARE, COMPONENT,
    EXACT_EXPANSION, GRAM_SCHMIDT, GREEN_DOWN, HANDEDNESS, LIGHT_POWER, LINES, LINE_MODE,
    NORMALIZE_BEFORE_SUM, NORMALIZE_TBN, NORMAL_STRENGTH, SPECULAR_TEXTURE, SPLIT, TANGENTS,
    TBN_LINE_LENGTH, TWO_CHANNEL, VIEW,
};
use controls::{default_tangents, CONTROLS};
use lines::TbnLines;
use maps::{model_texture_sets, override_tutorial_maps};
use mesh::{say_merged_corners, warn_of_far_frame, MeshState, SoupSource};
pub use programs::{DebugProgram, Knobs, DEBUG_SHADERS, DERIVATIVE_SHADERS};
use programs::{Drawing, Programs};
use tutorial13::{NormalMappingProgram, Tutorial13, CLEAR_COLOR, SHADERS};

/// Every shader the scene reads: the tutorial's program, the debugging and per-pixel ones, the
/// line shader.
const ALL_SHADERS: [[&str; 2]; 4] = [SHADERS, DEBUG_SHADERS, DERIVATIVE_SHADERS, LINE_SHADERS];

/// Tutorial 13 and the state of its debugging aids.
pub struct Cylinder {
    // Field order is drop order; all hold GL objects of the same context.
    /// The TBN lines (built the first time they are shown), or the path they are to be drawn with.
    lines: TbnLines,
    /// The debugging and per-pixel programs.
    programs: Programs,
    /// The panel's light power and normal strength (the tutorial's unless moved).
    pub knobs: Knobs,
    /// The light as the panel shows it, in the space `--light` uses (the model's own coordinates
    /// with `--model`, else world space): set there, it is placed as `--light` is, to the bit.
    light: Vec3,
    /// The tutorial's light (the panel's start, whatever `--light` says), in that space and in
    /// world space.
    light_start: Vec3,
    light_start_world: Vec3,
    /// The TBN lines' length (the tutorial's [`LINE_LENGTH`] unless the panel moved it).
    line_length: f32,
    /// What the mesh is made from: the soup, the CPU pipeline's switches, the tangent source.
    mesh: MeshState,
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
    show_lines: bool,
    /// The immediate-mode entry points, or why this context has none.
    legacy: std::result::Result<LegacyGl, String>,
    /// [`ALL_SHADERS`], from `--shaders` or the crate's.
    shaders: ShaderSet,
}

impl SceneType for Cylinder {
    const NAME: &'static str = "cylinder";
    const DESCRIPTION: &'static str =
        "Tutorial 13: the normal-mapped cylinder, with its debugging aids as keys (the default)";
    /// The tutorial's state (`init_gl_state`), applied at the start of every frame: another scene may
    /// have drawn on this context since the cylinder was built.
    const GL_STATE: GlState = GlState::opaque_3d(CLEAR_COLOR);
    const CONTROLS: &'static [Control<Self>] = CONTROLS;
    const ARGS: OwnArgs = OwnArgs::of::<CylinderArgs>();
    const ASSET_FILES: &'static [&'static str] = &crate::assets::ASSET_FILES;

    /// Loads the tutorial's four files (or `--model`) and the shaders from `--shaders` (or the
    /// crate's), with the tutorial's switches; its starts set the rest once it is built.
    fn new(
        context: &SceneContext,
        options: &SceneOptions,
        starts: &mut Starts<Self>,
    ) -> Result<Self> {
        let files = options.get::<CylinderFiles>();
        // `--tangents` (key F's start): the mesh is built for it straight away, not for the
        // default and then again when the table sets it (seconds on a large model).
        let tangents =
            (starts.take(TANGENTS)).unwrap_or_else(|| default_tangents(files.model.as_deref()));
        let shaders = ShaderSet::new(options.shader_dir(), ALL_SHADERS);
        let shader_dir = shaders.dir();
        let gl = context.gl;
        let mesh_options = MeshOptions {
            code: files.code,
            ..MeshOptions::default()
        };
        let (tutorial, soup_source) = match &files.model {
            None => load_tutorial(gl, options, shader_dir, &files.maps, mesh_options)?,
            Some(path) => {
                load_model_scene(gl, shader_dir, path, &files.maps, tangents, mesh_options)?
            }
        };
        // The panel shows the light where `--light` puts it: in the model's own coordinates. Its
        // start is the tutorial's light, in those coordinates too.
        let light_start_world = tutorial.light_position_worldspace;
        let light_start = match &soup_source {
            SoupSource::Model(model) => model.placement.to_file(light_start_world),
            SoupSource::Tutorial(_) => light_start_world,
        };
        let mut scene = Cylinder {
            lines: TbnLines::Wanted(None),
            programs: Programs::load(gl, &shaders)?,
            knobs: Knobs::TUTORIAL,
            light: light_start,
            light_start,
            light_start_world,
            line_length: LINE_LENGTH,
            mesh: MeshState {
                // A model's mesh is already the chosen source's; the tutorial's cylinder's is the
                // tutorial's until the source is set below.
                source: match &soup_source {
                    SoupSource::Model(_) => tangents,
                    SoupSource::Tutorial(_) => TangentSource::Tutorial,
                },
                soup: soup_source,
                options: mesh_options,
                built: Vec::new(),
            },
            comparison: None,
            compare_sources: None,
            compare_view: CompareView::new(gl, context.extensions, CompareMode::Split, SPLIT_START),
            tutorial,
            gl: gl.clone(),
            switches: ShaderSwitches::default(),
            use_debug_program: false,
            show_lines: false,
            legacy: context.extensions.legacy.clone(),
            shaders,
        };
        scene.set_tangent_source(tangents)?;
        Ok(scene)
    }

    /// A dropped `.obj`, `.gltf` or `.glb` file is opened as `--model` (the other options and
    /// starts stay as they were; without `--tangents`, the new model's default source).
    fn open_file(path: &Path, options: &mut SceneOptions) -> bool {
        let opened = crate::model::Format::of(path).is_some();
        if opened {
            options.get_mut::<CylinderFiles>().model = Some(path.to_path_buf());
        }
        opened
    }

    fn generate_assets() -> Result<crate::assets::GeneratedFiles> {
        crate::assets::generate_cylinder_assets()
    }

    /// A model drawn with the tutorial's frame far from MikkTSpace's is warned of once the starts
    /// have set the table (`--normalize-tbn` undoes the stretch; `--no-gram-schmidt` changes the
    /// mesh).
    fn started(&mut self) {
        if let (SoupSource::Model(model), TangentSource::Tutorial) =
            (&self.mesh.soup, self.mesh.source)
        {
            warn_of_far_frame(model, &self.tutorial.mesh, self.switches.normalize_tbn);
        }
    }
}

/// The tutorial's cylinder from its four files (in `options`' assets folder, or the crate's), with
/// `maps` over the tutorial's, its mesh built with `mesh_options`.
fn load_tutorial(
    gl: &Gl,
    options: &SceneOptions,
    shader_dir: Option<&Path>,
    maps: &MapOverrides,
    mesh_options: MeshOptions,
) -> Result<(Tutorial13, SoupSource)> {
    let assets = options.asset_files(crate::assets::ASSET_FILES)?;
    let mut tutorial = Tutorial13::new(gl, &assets, shader_dir, mesh_options)?;
    override_tutorial_maps(gl, &mut tutorial.texture_sets[0], maps)?;
    let [obj, ..] = assets;
    Ok((tutorial, SoupSource::Tutorial(obj)))
}

/// The model at `path` with `maps`, its mesh built with `tangents` and `mesh_options`.
fn load_model_scene(
    gl: &Gl,
    shader_dir: Option<&Path>,
    path: &Path,
    maps: &MapOverrides,
    tangents: TangentSource,
    mesh_options: MeshOptions,
) -> Result<(Tutorial13, SoupSource)> {
    let _progress = Progress::start(format!("loading {}", path.display()));
    let start = crate::clock::Instant::now();
    let model = load_model(path, maps)?;
    let parsed = start.elapsed();
    let sets = model_texture_sets(gl, &model)?;
    // Once the file and its maps are read: a refused file gets its one line alone.
    if crate::model::Format::is_gltf(path) {
        log::info!(
            "{}: {}",
            path.display(),
            crate::model::gltf::METALLIC_ROUGHNESS
        );
    }
    log::debug!(
        "{}: read and parsed in {:.1} ms, maps decoded and uploaded in {:.1} ms",
        path.display(),
        parsed.as_secs_f64() * 1000.0,
        (start.elapsed() - parsed).as_secs_f64() * 1000.0
    );
    let model = Rc::new(model);
    let soup_source = SoupSource::Model(Rc::clone(&model));
    let tutorial = match tangents {
        TangentSource::Tutorial => {
            let tutorial = Tutorial13::from_soup(gl, shader_dir, &model.soup, mesh_options, sets)?;
            say_merged_corners(&model, &tutorial.mesh);
            tutorial
        }
        // Another source's mesh straight away: the tutorial's would be built for
        // nothing (seconds on a large model).
        source => {
            let start = crate::clock::Instant::now();
            let mesh = soup_source.mesh(source, mesh_options)?;
            log::debug!(
                "{source} tangents and indexing: {:.1} ms",
                start.elapsed().as_secs_f64() * 1000.0
            );
            Tutorial13::from_mesh(gl, shader_dir, mesh, sets)?
        }
    };
    Ok((tutorial, soup_source))
}

impl Scene for Cylinder {
    fn draw(&mut self, frame: &FrameInput) {
        let drawer = (self.programs).drawer(
            &self.tutorial,
            self.switches,
            self.knobs,
            self.use_debug_program,
        );
        if let Some((sources, buffers)) = &self.comparison {
            let view = &mut self.compare_view;
            let drawn = view.draw(
                frame.size,
                || drawer.draw(sources[0], &buffers[0], frame),
                || drawer.draw(sources[1], &buffers[1], frame),
            );
            if let Err(e) = drawn {
                log::error!("compare view: {e}");
            }
            // The numbers of a frame before (or of this one where it has been waited for).
            if let Some(d) = view.new_difference() {
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
        let lines = self.lines.built().filter(|_| self.lines_drawn());
        let program = drawer.program(self.mesh.source);
        self.tutorial
            .draw_with(program, frame.projection, frame.view, lines);
    }

    /// A model is placed on the tutorial's cylinder's bounding sphere; the camera starts framing it.
    /// The tutorial's own cylinder keeps the tutorial's start.
    fn framing(&self) -> Option<(Vec3, f32)> {
        match self.mesh.soup {
            SoupSource::Model(_) => Some((TUTORIAL_CYLINDER_CENTER, TUTORIAL_CYLINDER_RADIUS)),
            SoupSource::Tutorial(_) => None,
        }
    }

    /// The tutorial's program, the debugging program and the line shader.
    fn shader_files(&self) -> Vec<PathBuf> {
        self.shaders.files()
    }

    /// All or nothing: every program is built before any replaces the one in use.
    fn reload_shaders(&mut self) -> Result<()> {
        let program = NormalMappingProgram::new(self.shaders.load(&self.gl, SHADERS)?)?;
        let programs = Programs::load(&self.gl, &self.shaders)?;
        if let Some(lines) = self.lines.built_mut() {
            lines.reload_shaders()?;
        }
        self.tutorial.program = program;
        self.programs = programs;
        Ok(())
    }

    /// The program each side draws with (and the lines' program when they are shown).
    fn drawing_programs(&self) -> Vec<DrawingProgram> {
        let drawer = (self.programs).drawer(
            &self.tutorial,
            self.switches,
            self.knobs,
            self.use_debug_program,
        );
        let sources = match &self.comparison {
            Some((sources, _)) => sources.to_vec(),
            None => vec![self.mesh.source],
        };
        let mut drawings: Vec<Drawing> = sources.iter().map(|&s| drawer.drawing(s)).collect();
        drawings.dedup();
        let mut programs: Vec<DrawingProgram> = drawings
            .into_iter()
            .map(|d| {
                let (name, files) = d.shaders();
                self.shaders.program(name, files)
            })
            .collect();
        match self.line_mode().filter(|_| self.lines_drawn()) {
            Some(LineMode::Legacy) => programs.push(DrawingProgram {
                name: "TBN lines: immediate mode (glBegin/glEnd, no shader)".into(),
                shaders: Vec::new(),
                dir: None,
            }),
            Some(LineMode::Shader) => {
                programs.push(self.shaders.program("TBN lines: DebugLines", LINE_SHADERS))
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
        if let SoupSource::Model(model) = &self.mesh.soup {
            let name = model.path.file_name().unwrap_or(model.path.as_os_str());
            text += &format!(", model {}", name.to_string_lossy());
        }
        text
    }

    /// The model drawn in place of the cylinder, and what the compare view measured.
    fn status_beyond_table(&self) -> Vec<String> {
        let model = match &self.mesh.soup {
            SoupSource::Model(model) => Some(format!("model {}", model.path.display())),
            _ => None,
        };
        model.into_iter().chain(self.compare_status()).collect()
    }
}
