//! `tutorial13.cpp`: the normal-mapped cylinder as a scene, and the frame every front end draws.
//!
//! Read top to bottom beside the C++: set the GL state, load the program and its uniforms, the three
//! textures, the mesh through the CPU pipeline, the buffers; then each frame clear, bind, set the
//! matrices and light, and draw the elements. Window and headless modes call the same
//! [`render_frame`], so a test's pixels are the window's pixels.

use std::path::PathBuf;
use std::rc::Rc;

use glam::{Mat3, Mat4, Vec3};
use glow::HasContext;

use crate::context::{ContextInfo, Gl};
use crate::controls::Controls;
use crate::debuglines::{DebugLines, LegacyGl, LineMode};
use crate::mesh::{load_mesh, MeshOptions};
use crate::shader::{load_program, Program};
use crate::texture::{load_bmp_custom, load_dds, Texture};
use crate::vboindexer::{IndexedMesh, Indices};
use crate::{Error, Result};

/// The light's place in the world, as the tutorial's `lightPos`.
pub const LIGHT_POSITION_WORLDSPACE: Vec3 = Vec3::new(0.0, 0.0, 4.0);
/// `glClearColor(0.0f, 0.0f, 0.4f, 0.0f)`.
pub const CLEAR_COLOR: [f32; 4] = [0.0, 0.0, 0.4, 0.0];

/// Where the scene's files come from, and every switch a learner can start with.
#[derive(Debug, Clone, Default)]
pub struct SceneOptions {
    /// Holds cylinder.obj, diffuse.DDS, normal.bmp, specular.DDS.
    pub assets: PathBuf,
    /// `--shaders DIR`; `None` = the crate's shaders/ folder, else the embedded copies.
    pub shaders: Option<PathBuf>,
    /// The CPU pipeline's switches (Gram-Schmidt, handedness, normalize before summing).
    pub mesh: MeshOptions,
    /// The shader's switches and the colour view.
    pub switches: ShaderSwitches,
    /// Start with the TBN debug lines on.
    pub debug_lines: bool,
    /// `None`: immediate mode where the context allows it, else the line shader.
    pub line_mode: Option<LineMode>,
}

/// The vector a colour view shows ("Debugging with colors"): 0 = the lit result.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum DebugVector {
    #[default]
    Lit = 0,
    /// `normalize(LightDirection_tangentspace)`.
    Light = 1,
    /// `normalize(EyeDirection_tangentspace)`.
    Eye = 2,
    /// The normal read from the normal map.
    TextureNormal = 3,
}

/// What the fragment shader outputs: the lit colour, or one tangent-space vector raw or as
/// (v + 1) / 2, all three components or one as grey.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ColorView {
    pub vector: DebugVector,
    /// (v + 1) / 2 instead of v (whose negative parts clamp to black).
    pub mapped: bool,
    /// `None`: RGB = xyz; `Some(0..=2)`: that component alone, as grey.
    pub component: Option<u8>,
}

impl ColorView {
    /// Every view the `V` key steps through, in order (components are stepped by `C`).
    pub const CYCLE: [(DebugVector, bool); 7] = [
        (DebugVector::Lit, false),
        (DebugVector::Light, false),
        (DebugVector::Light, true),
        (DebugVector::Eye, false),
        (DebugVector::Eye, true),
        (DebugVector::TextureNormal, false),
        (DebugVector::TextureNormal, true),
    ];

    /// The next vector view, components kept.
    pub fn next_vector(self) -> Self {
        let i = Self::CYCLE
            .iter()
            .position(|&(v, m)| v == self.vector && (m == self.mapped || v == DebugVector::Lit))
            .unwrap_or(0);
        let (vector, mapped) = Self::CYCLE[(i + 1) % Self::CYCLE.len()];
        ColorView {
            vector,
            mapped,
            ..self
        }
    }

    /// All → x → y → z → all.
    pub fn next_component(self) -> Self {
        let component = match self.component {
            None => Some(0),
            Some(c) if c < 2 => Some(c + 1),
            Some(_) => None,
        };
        ColorView { component, ..self }
    }
}

impl std::fmt::Display for ColorView {
    /// The `--view` name: `lit`, `light`, `light01`, `eye`, `eye01`, `normal`, `normal01`, with
    /// `.x`, `.y` or `.z` for one component.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let name = match self.vector {
            DebugVector::Lit => return f.write_str("lit"),
            DebugVector::Light => "light",
            DebugVector::Eye => "eye",
            DebugVector::TextureNormal => "normal",
        };
        let mapped = if self.mapped { "01" } else { "" };
        let component = match self.component {
            None => "",
            Some(0) => ".x",
            Some(1) => ".y",
            Some(_) => ".z",
        };
        write!(f, "{name}{mapped}{component}")
    }
}

impl std::str::FromStr for ColorView {
    type Err = String;

    fn from_str(s: &str) -> std::result::Result<Self, String> {
        let bad = || {
            format!(
                "unknown view '{s}': use lit, light, light01, eye, eye01, normal or normal01, \
                 optionally with .x, .y or .z"
            )
        };
        let (name, component) = match s.rsplit_once('.') {
            Some((name, "x")) => (name, Some(0)),
            Some((name, "y")) => (name, Some(1)),
            Some((name, "z")) => (name, Some(2)),
            Some(_) => return Err(bad()),
            None => (s, None),
        };
        let (base, mapped) = match name.strip_suffix("01") {
            Some(base) => (base, true),
            None => (name, false),
        };
        let vector = match base {
            "lit" if !mapped && component.is_none() => DebugVector::Lit,
            "light" => DebugVector::Light,
            "eye" => DebugVector::Eye,
            "normal" => DebugVector::TextureNormal,
            _ => return Err(bad()),
        };
        Ok(ColorView {
            vector,
            mapped,
            component,
        })
    }
}

/// The tutorial's shader-side experiments.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ShaderSwitches {
    /// Normalize T, B, N in camera space before building the TBN matrix, as the article's text does
    /// (the repository's shader does not).
    pub normalize_tbn: bool,
    /// Specular colour from the specular texture (× 0.3); off: the constant vec3(0.3).
    pub specular_texture: bool,
    pub view: ColorView,
}

impl Default for ShaderSwitches {
    /// The tutorial's repository shader.
    fn default() -> Self {
        ShaderSwitches {
            normalize_tbn: false,
            specular_texture: true,
            view: ColorView::default(),
        }
    }
}

/// The tutorial's global GL state: depth test (LESS), back faces culled, the dark blue clear colour.
pub fn init_gl_state(gl: &Gl) {
    // SAFETY: state-setting calls on the current context.
    unsafe {
        let [r, g, b, a] = CLEAR_COLOR;
        gl.clear_color(r, g, b, a);
        gl.enable(glow::DEPTH_TEST);
        gl.depth_func(glow::LESS);
        gl.enable(glow::CULL_FACE);
    }
}

/// The five attribute buffers and the element buffer of one mesh, with the VAO they are drawn
/// through. Deleted with the value.
pub struct MeshBuffers {
    gl: Gl,
    vao: glow::VertexArray,
    /// vertex, uv, normal, tangent, bitangent: attribute locations 0..4.
    attributes: [glow::Buffer; 5],
    elements: glow::Buffer,
    index_count: i32,
    index_type: u32,
}

/// Components per attribute, in location order.
const ATTRIBUTE_SIZES: [i32; 5] = [3, 2, 3, 3, 3];

impl MeshBuffers {
    pub fn new(gl: &Gl, mesh: &IndexedMesh) -> Result<Self> {
        let data: [&[u8]; 5] = [
            bytemuck::cast_slice(&mesh.vertices),
            bytemuck::cast_slice(&mesh.uvs),
            bytemuck::cast_slice(&mesh.normals),
            bytemuck::cast_slice(&mesh.tangents),
            bytemuck::cast_slice(&mesh.bitangents),
        ];
        // SAFETY: buffers are created and filled on the current context with slices that live
        // through the calls.
        unsafe {
            let vao = gl.create_vertex_array().map_err(Error::Gl)?;
            gl.bind_vertex_array(Some(vao));
            let mut attributes = Vec::with_capacity(5);
            for bytes in data {
                let buffer = gl.create_buffer().map_err(Error::Gl)?;
                gl.bind_buffer(glow::ARRAY_BUFFER, Some(buffer));
                gl.buffer_data_u8_slice(glow::ARRAY_BUFFER, bytes, glow::STATIC_DRAW);
                attributes.push(buffer);
            }
            let elements = gl.create_buffer().map_err(Error::Gl)?;
            gl.bind_buffer(glow::ELEMENT_ARRAY_BUFFER, Some(elements));
            let (bytes, index_type): (&[u8], u32) = match &mesh.indices {
                Indices::U16(v) => (bytemuck::cast_slice(v), glow::UNSIGNED_SHORT),
                Indices::U32(v) => (bytemuck::cast_slice(v), glow::UNSIGNED_INT),
            };
            gl.buffer_data_u8_slice(glow::ELEMENT_ARRAY_BUFFER, bytes, glow::STATIC_DRAW);
            Ok(MeshBuffers {
                gl: gl.clone(),
                vao,
                attributes: attributes.try_into().expect("five attribute buffers"),
                elements,
                index_count: mesh.indices.len() as i32,
                index_type,
            })
        }
    }

    /// The tutorial's draw: enable and point each attribute array, draw the elements, disable.
    pub fn draw(&self) {
        let gl = &self.gl;
        // SAFETY: every buffer belongs to this context; the pointers describe the data uploaded in `new`.
        unsafe {
            gl.bind_vertex_array(Some(self.vao));
            for (location, (&buffer, &size)) in
                self.attributes.iter().zip(&ATTRIBUTE_SIZES).enumerate()
            {
                gl.enable_vertex_attrib_array(location as u32);
                gl.bind_buffer(glow::ARRAY_BUFFER, Some(buffer));
                gl.vertex_attrib_pointer_f32(location as u32, size, glow::FLOAT, false, 0, 0);
            }
            gl.bind_buffer(glow::ELEMENT_ARRAY_BUFFER, Some(self.elements));
            gl.draw_elements(glow::TRIANGLES, self.index_count, self.index_type, 0);
            for location in 0..ATTRIBUTE_SIZES.len() {
                gl.disable_vertex_attrib_array(location as u32);
            }
        }
    }
}

impl Drop for MeshBuffers {
    fn drop(&mut self) {
        // SAFETY: all made by this context, which the shared `Gl` keeps alive.
        unsafe {
            for &buffer in &self.attributes {
                self.gl.delete_buffer(buffer);
            }
            self.gl.delete_buffer(self.elements);
            self.gl.delete_vertex_array(self.vao);
        }
    }
}

type Uniform = Option<glow::UniformLocation>;

/// Uniform locations of a NormalMapping program, looked up once. The debug program has five more.
struct Uniforms {
    mvp: Uniform,
    view: Uniform,
    model: Uniform,
    model_view_3x3: Uniform,
    light_position_worldspace: Uniform,
    samplers: [Uniform; 3],
    normalize_tbn: Uniform,
    specular_texture: Uniform,
    debug_view: Uniform,
    debug_mapped: Uniform,
    debug_component: Uniform,
}

impl Uniforms {
    fn new(program: &Program) -> Self {
        Uniforms {
            mvp: program.uniform("MVP"),
            view: program.uniform("V"),
            model: program.uniform("M"),
            model_view_3x3: program.uniform("MV3x3"),
            light_position_worldspace: program.uniform("LightPosition_worldspace"),
            samplers: [
                program.uniform("DiffuseTextureSampler"),
                program.uniform("NormalTextureSampler"),
                program.uniform("SpecularTextureSampler"),
            ],
            normalize_tbn: program.uniform("NormalizeTBN"),
            specular_texture: program.uniform("UseSpecularTexture"),
            debug_view: program.uniform("DebugView"),
            debug_mapped: program.uniform("DebugMapped"),
            debug_component: program.uniform("DebugComponent"),
        }
    }
}

/// Everything the tutorial loads before its main loop.
pub struct NormalMappingScene {
    pub(crate) gl: Gl,
    /// The tutorial's NormalMapping program, used whenever the switches are the tutorial's.
    program: Program,
    uniforms: Uniforms,
    /// NormalMappingDebug: the same lighting with the experiments and colour views as uniforms.
    debug_program: Program,
    debug_uniforms: Uniforms,
    pub switches: ShaderSwitches,
    /// Draw through NormalMappingDebug even with the tutorial's switches (to compare the two paths,
    /// which must give the same frame).
    pub use_debug_program: bool,
    /// diffuse, normal, specular: texture units 0, 1, 2.
    textures: [Texture; 3],
    buffers: MeshBuffers,
    /// The CPU mesh, kept for the debug lines (which share it) and for re-running the pipeline.
    pub mesh: Rc<IndexedMesh>,
    obj_path: PathBuf,
    mesh_options: MeshOptions,
    pub model_matrix: Mat4,
}

impl NormalMappingScene {
    pub fn new(gl: &Gl, options: &SceneOptions) -> Result<Self> {
        let program = load_program(
            gl,
            "NormalMapping.vertexshader",
            "NormalMapping.fragmentshader",
            options.shaders.as_deref(),
        )?;
        let uniforms = Uniforms::new(&program);
        let debug_program = load_program(
            gl,
            "NormalMappingDebug.vertexshader",
            "NormalMappingDebug.fragmentshader",
            options.shaders.as_deref(),
        )?;
        let debug_uniforms = Uniforms::new(&debug_program);
        let assets = &options.assets;
        let textures = [
            load_dds(gl, &assets.join("diffuse.DDS"))?,
            load_bmp_custom(gl, &assets.join("normal.bmp"))?,
            load_dds(gl, &assets.join("specular.DDS"))?,
        ];
        let obj_path = assets.join("cylinder.obj");
        let mesh = Rc::new(load_mesh(&obj_path, options.mesh)?);
        let buffers = MeshBuffers::new(gl, &mesh)?;
        Ok(NormalMappingScene {
            gl: gl.clone(),
            program,
            uniforms,
            debug_program,
            debug_uniforms,
            switches: options.switches,
            use_debug_program: false,
            textures,
            buffers,
            mesh,
            obj_path,
            mesh_options: options.mesh,
            model_matrix: Mat4::IDENTITY,
        })
    }

    /// The CPU pipeline's current switches.
    pub fn mesh_options(&self) -> MeshOptions {
        self.mesh_options
    }

    /// Re-runs the CPU pipeline with other switches and re-uploads the buffers; textures and programs
    /// stay as they are.
    pub fn rebuild_mesh(&mut self, options: MeshOptions) -> Result<()> {
        let mesh = load_mesh(&self.obj_path, options)?;
        self.buffers = MeshBuffers::new(&self.gl, &mesh)?;
        self.mesh = Rc::new(mesh);
        self.mesh_options = options;
        Ok(())
    }

    /// One draw of the cylinder with the given camera.
    pub fn draw(&self, projection: Mat4, view: Mat4) {
        let gl = &self.gl;
        let model = self.model_matrix;
        let model_view = view * model;
        let mvp = projection * model_view;
        let model_view_3x3 = Mat3::from_mat4(model_view);
        // The tutorial's own program unless an experiment or a colour view asks for the debug one.
        let tutorial = self.switches == ShaderSwitches::default() && !self.use_debug_program;
        let (program, u) = if tutorial {
            (&self.program, &self.uniforms)
        } else {
            (&self.debug_program, &self.debug_uniforms)
        };
        // SAFETY: program, uniforms and textures all belong to this context.
        unsafe {
            gl.use_program(Some(program.id));
            if !tutorial {
                let sw = self.switches;
                gl.uniform_1_i32(u.normalize_tbn.as_ref(), sw.normalize_tbn as i32);
                gl.uniform_1_i32(u.specular_texture.as_ref(), sw.specular_texture as i32);
                gl.uniform_1_i32(u.debug_view.as_ref(), sw.view.vector as i32);
                gl.uniform_1_i32(u.debug_mapped.as_ref(), sw.view.mapped as i32);
                let component = sw.view.component.map_or(-1, i32::from);
                gl.uniform_1_i32(u.debug_component.as_ref(), component);
            }
            gl.uniform_matrix_4_f32_slice(u.mvp.as_ref(), false, &mvp.to_cols_array());
            gl.uniform_matrix_4_f32_slice(u.model.as_ref(), false, &model.to_cols_array());
            gl.uniform_matrix_4_f32_slice(u.view.as_ref(), false, &view.to_cols_array());
            gl.uniform_matrix_3_f32_slice(
                u.model_view_3x3.as_ref(),
                false,
                &model_view_3x3.to_cols_array(),
            );
            gl.uniform_3_f32_slice(
                u.light_position_worldspace.as_ref(),
                &LIGHT_POSITION_WORLDSPACE.to_array(),
            );
            for (unit, (texture, sampler)) in self.textures.iter().zip(&u.samplers).enumerate() {
                gl.active_texture(glow::TEXTURE0 + unit as u32);
                gl.bind_texture(glow::TEXTURE_2D, Some(texture.id));
                gl.uniform_1_i32(sampler.as_ref(), unit as i32);
            }
        }
        self.buffers.draw();
    }
}

/// What a key or a flag can change while the program runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Action {
    /// Show or hide the TBN debug lines.
    ToggleLines,
    /// Immediate mode ↔ line shader.
    ToggleLineMode,
    /// Next colour view (lit, light, eye, texture normal; raw and (v+1)/2).
    NextView,
    /// All components → x → y → z.
    NextComponent,
    /// Exercise 1: normalize tangents before summing them (CPU pipeline re-run).
    ToggleNormalizeBeforeSum,
    /// Gram-Schmidt on/off (CPU pipeline re-run).
    ToggleGramSchmidt,
    /// Handedness fix on/off (CPU pipeline re-run).
    ToggleHandedness,
    /// Specular texture ↔ constant 0.3.
    ToggleSpecularTexture,
    /// The article's normalized TBN ↔ the repository shader's.
    ToggleNormalizedTbn,
}

/// The tutorial's main-loop state, shared by the window and headless front ends: the scene, its
/// debug lines and whether they show. [`Tutorial13::render`] is the frame both draw.
pub struct Tutorial13 {
    // Field order is drop order; both hold GL objects of the same context.
    /// Built the first time they are shown, so that a run without them neither loads their shader
    /// nor prints the core-profile notice.
    lines: Option<DebugLines>,
    pub scene: NormalMappingScene,
    show_lines: bool,
    /// The immediate-mode entry points, or why this context has none.
    legacy: std::result::Result<LegacyGl, String>,
    line_mode: Option<LineMode>,
    shader_dir: Option<PathBuf>,
}

impl Tutorial13 {
    /// Loads the scene (and its lines, if they start on). `loader` resolves GL entry points of the
    /// current context, for the immediate-mode functions glow does not have.
    pub fn new(
        gl: &Gl,
        info: &ContextInfo,
        loader: impl FnMut(&std::ffi::CStr) -> *const std::ffi::c_void,
        options: &SceneOptions,
    ) -> Result<Self> {
        init_gl_state(gl);
        let scene = NormalMappingScene::new(gl, options)?;
        let mut tutorial = Tutorial13 {
            lines: None,
            scene,
            show_lines: false,
            legacy: LegacyGl::load(info, loader).map_err(|e| e.to_string()),
            line_mode: options.line_mode,
            shader_dir: options.shaders.clone(),
        };
        tutorial.set_show_lines(options.debug_lines)?;
        Ok(tutorial)
    }

    pub fn show_lines(&self) -> bool {
        self.show_lines
    }

    /// Shows or hides the TBN lines, building them (from the current mesh) the first time.
    pub fn set_show_lines(&mut self, show: bool) -> Result<()> {
        if show && self.lines.is_none() {
            let lines = DebugLines::with_legacy(
                &self.scene.gl,
                self.legacy.clone(),
                &self.scene.mesh,
                self.line_mode,
                self.shader_dir.as_deref(),
            )?;
            self.lines = Some(lines);
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

    /// The frame: clear colour and depth, draw the scene from the camera, then the debug lines if
    /// they are on. The caller binds the target (back buffer or offscreen) and sets the viewport.
    pub fn render(&self, gl: &Gl, controls: &Controls) {
        // SAFETY: clearing the bound framebuffer.
        unsafe { gl.clear(glow::COLOR_BUFFER_BIT | glow::DEPTH_BUFFER_BIT) };
        let (projection, view) = (controls.projection_matrix(), controls.view_matrix());
        self.scene.draw(projection, view);
        if let (true, Some(lines)) = (self.show_lines, &self.lines) {
            lines.draw(projection, view, self.scene.model_matrix);
        }
    }

    /// Applies one switch, redoing only what it needs: a uniform for shader switches, the CPU
    /// pipeline and both vertex uploads for mesh switches.
    pub fn apply(&mut self, action: Action) -> Result<()> {
        let mut mesh = self.scene.mesh_options();
        let switches = &mut self.scene.switches;
        match action {
            Action::ToggleLines => self.set_show_lines(!self.show_lines)?,
            Action::ToggleLineMode => {
                let current = self.line_mode().or(self.line_mode);
                let next = match current {
                    Some(LineMode::Shader) => LineMode::Legacy,
                    // Immediate mode is the default where the context has it.
                    _ if self.legacy.is_err() => LineMode::Legacy,
                    _ => LineMode::Shader,
                };
                self.line_mode = Some(next);
                if let Some(lines) = &mut self.lines {
                    lines.set_mode(next)?;
                }
            }
            Action::NextView => switches.view = switches.view.next_vector(),
            Action::NextComponent => switches.view = switches.view.next_component(),
            Action::ToggleSpecularTexture => switches.specular_texture ^= true,
            Action::ToggleNormalizedTbn => switches.normalize_tbn ^= true,
            Action::ToggleNormalizeBeforeSum => mesh.indexing.normalize_before_sum ^= true,
            Action::ToggleGramSchmidt => mesh.tangents.gram_schmidt ^= true,
            Action::ToggleHandedness => mesh.tangents.handedness ^= true,
        }
        if mesh != self.scene.mesh_options() {
            self.scene.rebuild_mesh(mesh)?;
            if let Some(lines) = &mut self.lines {
                lines.rebuild(&self.scene.mesh)?;
            }
        }
        Ok(())
    }

    /// One line for the title bar and the log: view, lines, and every experiment switch.
    pub fn status(&self) -> String {
        let on = |b: bool| if b { "on" } else { "off" };
        let sw = self.scene.switches;
        let mesh = self.scene.mesh_options();
        let lines = match (self.show_lines, self.line_mode()) {
            (true, Some(LineMode::Legacy)) => "immediate mode",
            (true, _) => "line shader",
            (false, _) => "off",
        };
        format!(
            "view {} | lines {lines} | Gram-Schmidt {} | handedness {} | normalize before sum {} | \
             specular texture {} | TBN {}",
            sw.view,
            on(mesh.tangents.gram_schmidt),
            on(mesh.tangents.handedness),
            on(mesh.indexing.normalize_before_sum),
            on(sw.specular_texture),
            if sw.normalize_tbn { "normalized (article)" } else { "as summed (repository)" },
        )
    }
}
