//! The tutorial's "Debugging with the immediate mode": after the cylinder, a short line from every
//! vertex along its normal (blue), tangent (red) and bitangent (green), and a white cross at the light.
//!
//! Two ways to draw the same lines:
//!
//! - [`LineMode::Legacy`] is the tutorial's code, call for call: the fixed-function matrix stacks,
//!   `glUseProgram(0)`, then `glBegin(GL_LINES)` … `glEnd()` over every index. It needs a
//!   compatibility-profile context; glow has no immediate mode, so the entry points are loaded into
//!   [`LegacyGl`].
//! - [`LineMode::Shader`] is for core-profile contexts (the tutorial's default, and all macOS has):
//!   the same segments in the same order and colours, in one vertex buffer built once, drawn with a
//!   small line shader and one `glDrawArrays(GL_LINES)`.
//!
//! Both draw with the depth test on, so the lines are hidden where the cylinder is in front of them,
//! and both leave the GL state as they found it, so the next frame is unaffected.

use std::path::{Path, PathBuf};
use std::rc::Rc;

use glam::{Mat4, Vec3};
use glow::HasContext;

use crate::common::shader::load_program;
use crate::common::vboindexer::IndexedMesh;
use crate::gl::extensions::GlExtensions;
pub use crate::gl::extensions::LegacyGl;
use crate::gl::objects::Owned;
use crate::gl::Gl;
use crate::{Error, Result};

/// Names this part in errors.
const PART: &str = "debug lines";

/// Length of every debug line, in model-space units (`p += o*0.1f`).
pub const LINE_LENGTH: f32 = 0.1;
/// `glColor3f(0, 0, 1)`: normals.
pub const NORMAL_COLOR: [f32; 3] = [0.0, 0.0, 1.0];
/// `glColor3f(1, 0, 0)`: tangents.
pub const TANGENT_COLOR: [f32; 3] = [1.0, 0.0, 0.0];
/// `glColor3f(0, 1, 0)`: bitangents.
pub const BITANGENT_COLOR: [f32; 3] = [0.0, 1.0, 0.0];
/// `glColor3f(1, 1, 1)`: the light's cross.
pub const LIGHT_COLOR: [f32; 3] = [1.0, 1.0, 1.0];

// Fixed-function enums; glow only exports the core ones.
const GL_MODELVIEW: u32 = 0x1700;
const GL_PROJECTION: u32 = 0x1701;
/// glPushAttrib group holding the current colour (and normal, texture coordinates).
const GL_CURRENT_BIT: u32 = 0x0001;
/// glPushAttrib group holding GL_MATRIX_MODE.
const GL_TRANSFORM_BIT: u32 = 0x1000;

/// How the debug lines are drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum LineMode {
    /// The tutorial's immediate mode (compatibility profile only).
    Legacy,
    /// One vertex buffer and a line shader (any 3.3 context).
    Shader,
}

/// The end of a debug line from `p` along `v`: `o = normalize(v); p += o*0.1f`.
///
/// A zero vector gives a zero-length line instead of the tutorial's NaN vertex.
fn line_end(p: Vec3, v: Vec3, length: f32) -> Vec3 {
    p + v.normalize_or_zero() * length
}

/// The light's cross as the tutorial draws it, by moving `lightPos` back and forth: four vertices,
/// two lines.
fn light_cross(mut light_pos: Vec3, length: f32) -> [Vec3; 4] {
    let a = light_pos;
    light_pos += Vec3::X * length;
    let b = light_pos;
    light_pos -= Vec3::X * length;
    let c = light_pos;
    light_pos += Vec3::Y * length;
    [a, b, c, light_pos]
}

/// What the lines are drawn from: the scene's CPU mesh, shared (not copied), checked once so that
/// drawing never indexes out of bounds, and the light's position (world space). Its tangents are
/// empty for a mesh from `index_vbo` (then no red and green lines).
#[derive(Debug, Clone)]
struct TbnSource {
    mesh: Rc<IndexedMesh>,
    light_position_worldspace: Vec3,
    /// Of every line ([`LINE_LENGTH`], the tutorial's, unless the panel moved it).
    length: f32,
}

impl TbnSource {
    fn new(mesh: &Rc<IndexedMesh>, light_position_worldspace: Vec3, length: f32) -> Result<Self> {
        let n = mesh.vertices.len();
        for (name, len) in [
            ("normals", mesh.normals.len()),
            ("tangents", mesh.tangents.len()),
            ("bitangents", mesh.bitangents.len()),
        ] {
            if len != n && !(len == 0 && name != "normals") {
                return Err(Error::Mesh(format!(
                    "debug lines: {n} vertices but {len} {name}"
                )));
            }
        }
        let indices = &mesh.indices;
        if let Some(bad) = (0..indices.len())
            .map(|i| indices.get(i))
            .find(|&i| i as usize >= n)
        {
            return Err(Error::Mesh(format!(
                "debug lines: index {bad} is past the {n} vertices"
            )));
        }
        Ok(TbnSource {
            mesh: mesh.clone(),
            light_position_worldspace,
            length,
        })
    }

    /// The three sets of lines in the tutorial's order; sets the mesh does not have are left out.
    fn sets(&self) -> impl Iterator<Item = ([f32; 3], &[Vec3])> {
        [
            (NORMAL_COLOR, self.mesh.normals.as_slice()),
            (TANGENT_COLOR, self.mesh.tangents.as_slice()),
            (BITANGENT_COLOR, self.mesh.bitangents.as_slice()),
        ]
        .into_iter()
        .filter(|(_, directions)| !directions.is_empty())
    }

    /// The shader path's buffer: the legacy path's lines, each drawn once. The tutorial draws a
    /// vertex's lines once per index that names it; the repeats lie exactly on the first (same
    /// ends, same colour, same depth), so under the depth test (LESS) they change no pixel, but they
    /// cost llvmpipe as much as the first. Sets stay in the tutorial's order (normals, tangents,
    /// bitangents, light), and each vertex keeps the place of its first index, so lines of different
    /// colours overlap exactly as in immediate mode (a test compares the two images).
    fn line_vertices(&self) -> Vec<LineVertex> {
        let mesh = &self.mesh;
        let mut seen = vec![false; mesh.vertices.len()];
        let first_uses: Vec<usize> = (0..mesh.indices.len())
            .map(|i| mesh.indices.get(i) as usize)
            .filter(|&index| !std::mem::replace(&mut seen[index], true))
            .collect();
        let mut out = Vec::with_capacity(self.sets().count() * first_uses.len() * 2 + 4);
        for (color, directions) in self.sets() {
            for &index in &first_uses {
                let p = mesh.vertices[index];
                out.push(LineVertex::new(p, color));
                out.push(LineVertex::new(
                    line_end(p, directions[index], self.length),
                    color,
                ));
            }
        }
        let cross = light_cross(self.light_position_worldspace, self.length);
        out.extend(cross.map(|p| LineVertex::new(p, LIGHT_COLOR)));
        out
    }
}

/// One vertex of the shader path's buffer: position, then colour as normalized bytes (0 and 255
/// are exactly 0.0 and 1.0, so the colours equal glColor3f's).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
struct LineVertex {
    position: [f32; 3],
    color: [u8; 4],
}

// SAFETY: repr(C) of 3 f32 and 4 u8: 16 bytes, no padding, every bit pattern valid.
unsafe impl bytemuck::Zeroable for LineVertex {}
// SAFETY: as above; Copy and 'static.
unsafe impl bytemuck::Pod for LineVertex {}

impl LineVertex {
    fn new(position: Vec3, color: [f32; 3]) -> Self {
        let [r, g, b] = color.map(|c| (c * 255.0).round() as u8);
        LineVertex {
            position: position.to_array(),
            color: [r, g, b, 255],
        }
    }
}

/// Vertices per glDrawArrays (even: whole lines). Measured on llvmpipe with 150k triangles: 256
/// beat 64, 128, 1024, 4096 and one single draw (11.6 ms against 12.6 to 18 ms).
const DRAW_BATCH: i32 = 256;

const LINE_VERTEX_STRIDE: i32 = std::mem::size_of::<LineVertex>() as i32;

/// The line shader's two files.
pub const LINE_SHADERS: [&str; 2] = ["DebugLines.vertexshader", "DebugLines.fragmentshader"];

crate::uniforms! {
    /// `DebugLines.*`: one matrix.
    struct LineProgram for Program {
        mvp: "MVP",
    }
}

fn load_line_program(gl: &Gl, shader_dir: Option<&Path>) -> Result<LineProgram> {
    let [vertex, fragment] = LINE_SHADERS;
    LineProgram::new(load_program(gl, vertex, fragment, shader_dir)?)
}

/// The core-profile path's GL objects: program, VAO and the one vertex buffer. Deleted on drop.
struct ShaderLines {
    gl: Gl,
    // Field order is drop order: the buffer, the VAO that points at it, then the program.
    buffer: Owned<glow::Buffer>,
    vao: Owned<glow::VertexArray>,
    program: LineProgram,
    vertex_count: i32,
}

impl ShaderLines {
    fn new(gl: &Gl, shader_dir: Option<&Path>, source: &TbnSource) -> Result<Self> {
        let program = load_line_program(gl, shader_dir)?;
        let lines_vao = Owned::<glow::VertexArray>::create(gl, PART)?;
        let buffer = Owned::<glow::Buffer>::create(gl, PART)?;
        // SAFETY: the objects belong to this context; the previous bindings are restored.
        unsafe {
            let previous_vao = crate::gl::bound_vertex_array(gl, glow::VERTEX_ARRAY_BINDING);
            let previous_buffer = crate::gl::bound_buffer(gl, glow::ARRAY_BUFFER_BINDING);
            gl.bind_vertex_array(Some(lines_vao.name()));
            gl.bind_buffer(glow::ARRAY_BUFFER, Some(buffer.name()));
            gl.enable_vertex_attrib_array(0);
            gl.vertex_attrib_pointer_f32(0, 3, glow::FLOAT, false, LINE_VERTEX_STRIDE, 0);
            gl.enable_vertex_attrib_array(1);
            gl.vertex_attrib_pointer_f32(1, 4, glow::UNSIGNED_BYTE, true, LINE_VERTEX_STRIDE, 12);
            gl.bind_vertex_array(previous_vao);
            gl.bind_buffer(glow::ARRAY_BUFFER, previous_buffer);
        }
        let mut lines = ShaderLines {
            gl: gl.clone(),
            buffer,
            vao: lines_vao,
            program,
            vertex_count: 0,
        };
        lines.upload(source)?;
        Ok(lines)
    }

    /// (Re)fills the buffer; the VAO keeps pointing at it.
    fn upload(&mut self, source: &TbnSource) -> Result<()> {
        let vertices = source.line_vertices();
        let count = i32::try_from(vertices.len()).map_err(|_| {
            Error::Mesh(format!(
                "debug lines: {} line vertices are more than one glDrawArrays can draw",
                vertices.len()
            ))
        })?;
        let gl = &self.gl;
        // SAFETY: the buffer belongs to this context; the slice lives through the call; the previous
        // ARRAY_BUFFER binding is restored.
        unsafe {
            let previous = crate::gl::bound_buffer(gl, glow::ARRAY_BUFFER_BINDING);
            gl.bind_buffer(glow::ARRAY_BUFFER, Some(self.buffer.name()));
            gl.buffer_data_u8_slice(
                glow::ARRAY_BUFFER,
                bytemuck::cast_slice(&vertices),
                glow::STATIC_DRAW,
            );
            gl.bind_buffer(glow::ARRAY_BUFFER, previous);
        }
        self.vertex_count = count;
        Ok(())
    }

    fn draw(&self, mvp: Mat4) {
        let gl = &self.gl;
        // SAFETY: program and VAO belong to this context; the previous program and VAO are restored.
        unsafe {
            let previous_program = crate::gl::bound_program(gl, glow::CURRENT_PROGRAM);
            let previous_vao = crate::gl::bound_vertex_array(gl, glow::VERTEX_ARRAY_BINDING);
            gl.use_program(Some(self.program.program.id));
            let location = self.program.mvp.as_ref();
            gl.uniform_matrix_4_f32_slice(location, false, &mvp.to_cols_array());
            gl.bind_vertex_array(Some(self.vao.name()));
            // In batches: llvmpipe sets up a long draw's lines much more slowly than short draws'.
            let mut first = 0;
            while first < self.vertex_count {
                let count = (self.vertex_count - first).min(DRAW_BATCH);
                gl.draw_arrays(glow::LINES, first, count);
                first += count;
            }
            gl.bind_vertex_array(previous_vao);
            gl.use_program(previous_program);
        }
    }
}

thread_local! {
    /// Whether this run logged the fallback to the line shader (its GL thread's: a process's
    /// window, a test's renderer).
    static FALLBACK_LOGGED: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// The TBN debug lines of one mesh, drawn after the scene with the scene's matrices.
pub struct DebugLines {
    gl: Gl,
    source: TbnSource,
    /// Loaded when the context is a compatibility one; otherwise why it is not.
    legacy: std::result::Result<LegacyGl, String>,
    /// Built when first needed, so a legacy-only run keeps no second copy of the lines on the GPU.
    shader: Option<ShaderLines>,
    shader_dir: Option<PathBuf>,
    mode: LineMode,
    notice: Option<String>,
}

impl DebugLines {
    /// Prepares the lines of `mesh` on the current context.
    ///
    /// `requested`: `None` or `Some(Legacy)` = the tutorial's immediate mode where the context is a
    /// compatibility one, else the shader path with a one-line warning (see [`DebugLines::notice`]);
    /// `Some(Shader)` = the shader path. `shader_dir` is passed to [`load_program`].
    pub fn new(
        gl: &Gl,
        extensions: &GlExtensions,
        mesh: &Rc<IndexedMesh>,
        light_position_worldspace: Vec3,
        requested: Option<LineMode>,
        shader_dir: Option<&Path>,
    ) -> Result<Self> {
        let legacy = extensions.legacy.clone();
        let light = light_position_worldspace;
        Self::with_legacy(gl, legacy, mesh, light, requested, shader_dir)
    }

    /// [`DebugLines::new`] with the immediate-mode table already loaded (or the reason it is not),
    /// for callers that build the lines only once they are first shown.
    pub fn with_legacy(
        gl: &Gl,
        legacy: std::result::Result<LegacyGl, String>,
        mesh: &Rc<IndexedMesh>,
        light_position_worldspace: Vec3,
        requested: Option<LineMode>,
        shader_dir: Option<&Path>,
    ) -> Result<Self> {
        let mut lines = DebugLines {
            gl: gl.clone(),
            source: TbnSource::new(mesh, light_position_worldspace, LINE_LENGTH)?,
            legacy,
            shader: None,
            shader_dir: shader_dir.map(Path::to_path_buf),
            mode: LineMode::Shader,
            notice: None,
        };
        lines.set_mode(requested.unwrap_or(LineMode::Legacy))?;
        Ok(lines)
    }

    /// Switches paths; returns the mode now in use. Legacy in a core context falls back to Shader
    /// with a notice rather than drawing nothing or raising GL errors.
    pub fn set_mode(&mut self, requested: LineMode) -> Result<LineMode> {
        let (mode, notice) = match (requested, &self.legacy) {
            (LineMode::Legacy, Ok(_)) => (LineMode::Legacy, None),
            (LineMode::Legacy, Err(reason)) => (
                LineMode::Shader,
                Some(format!(
                    "TBN debug lines: falling back to the core-profile line shader: {reason}"
                )),
            ),
            (LineMode::Shader, _) => (LineMode::Shader, None),
        };
        if mode == LineMode::Shader && self.shader.is_none() {
            self.shader = Some(ShaderLines::new(
                &self.gl,
                self.shader_dir.as_deref(),
                &self.source,
            )?);
        }
        if let Some(notice) = &notice {
            // Once a run: every step of the tour builds the scene again, for the same reason.
            match FALLBACK_LOGGED.with(|logged| logged.replace(true)) {
                false => log::warn!("{notice}"),
                true => log::debug!("{notice}"),
            }
        }
        self.mode = mode;
        self.notice = notice;
        Ok(mode)
    }

    /// The path in use.
    pub fn mode(&self) -> LineMode {
        self.mode
    }

    /// Why the requested immediate mode is not used, if it is not.
    pub fn notice(&self) -> Option<&str> {
        self.notice.as_deref()
    }

    /// Compiles the line shader again from its files (live shader editing). On an error the lines
    /// keep the program they had.
    pub fn reload_shaders(&mut self) -> Result<()> {
        if let Some(shader) = &mut self.shader {
            shader.program = load_line_program(&self.gl, self.shader_dir.as_deref())?;
        }
        Ok(())
    }

    /// Takes the lines from another mesh (e.g. after the scene re-ran its CPU pipeline).
    pub fn rebuild(&mut self, mesh: &Rc<IndexedMesh>) -> Result<()> {
        let source = &self.source;
        self.set_source(TbnSource::new(
            mesh,
            source.light_position_worldspace,
            source.length,
        )?)
    }

    /// Moves the light's cross to `light_position_worldspace` and makes every line `length` long
    /// (the panel's sliders; the tutorial's length is [`LINE_LENGTH`]).
    /// Nothing is rebuilt when both are as they are (the panel's "tutorial's values" sets every
    /// slider, most of them unmoved).
    pub fn reshape(&mut self, light_position_worldspace: Vec3, length: f32) -> Result<()> {
        if self.shape() == (light_position_worldspace, length) {
            return Ok(());
        }
        let mesh = self.source.mesh.clone();
        self.set_source(TbnSource::new(&mesh, light_position_worldspace, length)?)
    }

    /// The light's position and the lines' length now.
    pub fn shape(&self) -> (Vec3, f32) {
        (self.source.light_position_worldspace, self.source.length)
    }

    fn set_source(&mut self, source: TbnSource) -> Result<()> {
        if let Some(shader) = &mut self.shader {
            shader.upload(&source)?;
        }
        self.source = source;
        Ok(())
    }

    /// Draws the lines into the bound framebuffer, depth-tested against what is there, with the
    /// scene's matrices. GL state is left as it was found.
    pub fn draw(&self, projection: Mat4, view: Mat4, model: Mat4) {
        match (self.mode, &self.legacy, &self.shader) {
            (LineMode::Legacy, Ok(legacy), _) => self.draw_legacy(legacy, projection, view, model),
            (_, _, Some(shader)) => shader.draw(projection * (view * model)),
            // set_mode builds the shader path before selecting it.
            _ => unreachable!("debug lines selected a path they did not build"),
        }
    }

    /// The tutorial's code, with the state it changes saved first and restored after.
    fn draw_legacy(&self, legacy: &LegacyGl, projection: Mat4, view: Mat4, model: Mat4) {
        let gl = &self.gl;
        let mesh = &self.source.mesh;
        let model_view = view * model;
        // SAFETY: the entry points were loaded from this context, a compatibility one, which is
        // current; every pointer passed points at 16 (matrices) or 3 (vertices) live floats.
        unsafe {
            let previous_program = crate::gl::bound_program(gl, glow::CURRENT_PROGRAM);
            // Saves the current colour and the matrix mode; the matrices themselves are pushed.
            (legacy.push_attrib)(GL_CURRENT_BIT | GL_TRANSFORM_BIT);
            (legacy.matrix_mode)(GL_PROJECTION);
            (legacy.push_matrix)();
            (legacy.load_matrix_f)(projection.to_cols_array().as_ptr());
            (legacy.matrix_mode)(GL_MODELVIEW);
            (legacy.push_matrix)();
            (legacy.load_matrix_f)(model_view.to_cols_array().as_ptr());

            gl.use_program(None);

            // normals (blue), tangents (red), bitangents (green): one line per *index*, so shared
            // vertices get theirs drawn several times, as in the tutorial.
            for ([r, g, b], directions) in self.source.sets() {
                (legacy.color_3f)(r, g, b);
                (legacy.begin)(glow::LINES);
                for i in 0..mesh.indices.len() {
                    let index = mesh.indices.get(i) as usize;
                    let p = mesh.vertices[index];
                    (legacy.vertex_3fv)(p.to_array().as_ptr());
                    let p = line_end(p, directions[index], self.source.length);
                    (legacy.vertex_3fv)(p.to_array().as_ptr());
                }
                (legacy.end)();
            }

            // The light, as a cross of two lines along +x and +y.
            let [r, g, b] = LIGHT_COLOR;
            (legacy.color_3f)(r, g, b);
            (legacy.begin)(glow::LINES);
            for p in light_cross(self.source.light_position_worldspace, self.source.length) {
                (legacy.vertex_3fv)(p.to_array().as_ptr());
            }
            (legacy.end)();

            (legacy.matrix_mode)(GL_PROJECTION);
            (legacy.pop_matrix)();
            (legacy.matrix_mode)(GL_MODELVIEW);
            (legacy.pop_matrix)();
            (legacy.pop_attrib)();
            gl.use_program(previous_program);
        }
    }
}

impl std::fmt::Debug for DebugLines {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("DebugLines")
            .field("mode", &self.mode)
            .field("notice", &self.notice)
            .field("indices", &self.source.mesh.indices.len())
            .finish_non_exhaustive()
    }
}
