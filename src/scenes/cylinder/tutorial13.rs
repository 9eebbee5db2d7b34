//! `tutorial13.cpp`: read it top to bottom beside the C++.
//!
//! Set-up, in the C++'s order: the GL state, the program and its uniform handles, the three textures,
//! the CPU pipeline (`loadOBJ`, `computeTangentBasis`, `indexVBO_TBN`), the buffers. Then the frame
//! ([`Tutorial13::draw_with`]): clear, matrices, uniforms, textures, the draw, and the immediate-mode debug
//! lines. The window and the GLFW loop are the front ends' (`frontends/`); the learner's switches,
//! colour views and keys are the cylinder scene's ([`super`]).

use std::path::{Path, PathBuf};
use std::rc::Rc;

use glam::{Mat3, Mat4, Vec3};
use glow::HasContext;

use crate::common::objloader::TriangleSoup;
use crate::common::shader::load_program;
use crate::common::tangentspace::compute_tangent_basis;
use crate::common::texture::{load_bmp_custom, load_dds, Texture};
use crate::common::vboindexer::IndexedMesh;
use crate::debug::lines::DebugLines;
use crate::gl::buffers::MeshBuffers;
use crate::gl::{bind_textures, Gl};
use crate::mesh::{index_vbo_tbn_by_size, load_obj_by_size, BuiltBy, MeshOptions};
use crate::Result;

/// `glClearColor(0.0f, 0.0f, 0.4f, 0.0f)`: dark blue.
pub const CLEAR_COLOR: [f32; 4] = [0.0, 0.0, 0.4, 0.0];

/// `glm::vec3 lightPos = glm::vec3(0,0,4)`.
pub const LIGHT_POS: Vec3 = Vec3::new(0.0, 0.0, 4.0);

/// The tutorial's global GL state: dark blue background, depth test (LESS), back faces culled.
pub fn init_gl_state(gl: &Gl) {
    let [r, g, b, a] = CLEAR_COLOR;
    // SAFETY: state-setting calls on the current context.
    unsafe {
        gl.clear_color(r, g, b, a);
        // Enable depth test; accept a fragment if it is closer to the camera than the former one.
        gl.enable(glow::DEPTH_TEST);
        gl.depth_func(glow::LESS);
        // Cull triangles whose normal is not towards the camera.
        gl.enable(glow::CULL_FACE);
    }
}

/// The tutorial's two shader files.
pub const SHADERS: [&str; 2] = ["NormalMapping.vertexshader", "NormalMapping.fragmentshader"];

crate::uniforms! {
    /// `programID` and the handles the tutorial gets with `glGetUniformLocation`. The debugging
    /// shaders (`NormalMappingDebug.*`) and the per-pixel frame's (`NormalMappingDerivative.*`) use
    /// the same names.
    pub struct NormalMappingProgram for Program {
        matrix_id: "MVP",
        view_matrix_id: "V",
        model_matrix_id: "M",
        model_view_3x3_matrix_id: "MV3x3",
        diffuse_texture_id: "DiffuseTextureSampler",
        normal_texture_id: "NormalTextureSampler",
        specular_texture_id: "SpecularTextureSampler",
        light_id: "LightPosition_worldspace",
    }
}

impl NormalMappingProgram {
    /// `LoadShaders(vertex, fragment)` and every handle.
    pub fn load(gl: &Gl, vertex: &str, fragment: &str, shader_dir: Option<&Path>) -> Result<Self> {
        Self::new(load_program(gl, vertex, fragment, shader_dir)?)
    }
}

/// `DiffuseTexture`, `NormalTexture`, `SpecularTexture`, and the triangles drawn with them: the
/// tutorial has one set for its whole cylinder; a learner's model has one per material.
pub struct TextureSet {
    pub diffuse_texture: Texture,
    pub normal_texture: Texture,
    pub specular_texture: Texture,
    /// Soup triangles drawn with these maps; `None` = all of them, in one `glDrawElements` as the
    /// tutorial's.
    pub triangles: Option<std::ops::Range<usize>>,
}

/// What `main` keeps between its set-up and its loop.
pub struct Tutorial13 {
    gl: Gl,
    /// `programID` with its handles: `NormalMapping.vertexshader`, `NormalMapping.fragmentshader`.
    pub program: NormalMappingProgram,
    /// The tutorial's three textures (one set), or a model's per material.
    pub texture_sets: Vec<TextureSet>,
    /// `lightPos`: the tutorial's [`LIGHT_POS`] unless `--light` moves it.
    pub light_position_worldspace: Vec3,
    /// `indexed_vertices`, `indexed_uvs`, ... and `indices`, shared with the debug lines.
    pub mesh: Rc<IndexedMesh>,
    /// `VertexArrayID`, `vertexbuffer` ... `bitangentbuffer`, `elementbuffer`.
    buffers: MeshBuffers,
    /// `glm::mat4 ModelMatrix = glm::mat4(1.0)`.
    pub model_matrix: Mat4,
    /// Which code built [`Tutorial13::mesh`]: the ports in `common/` or their fast twins (`None`
    /// for a mesh of another tangent source).
    pub built_by: Option<BuiltBy>,
}

impl Tutorial13 {
    /// The set-up before the loop. `files` are the tutorial's four files (cylinder.obj, diffuse.DDS,
    /// normal.bmp, specular.DDS: `assets::ASSET_FILES` found in the assets folder); `mesh_options`
    /// are the CPU pipeline's switches (the tutorial's code = the default).
    pub fn new(
        gl: &Gl,
        files: &[PathBuf; 4],
        shader_dir: Option<&Path>,
        mesh_options: MeshOptions,
    ) -> Result<Self> {
        let [obj, diffuse, normal, specular] = files;
        init_gl_state(gl);

        // Create and compile our GLSL program from the shaders, and get the handles.
        let [vertex_shader, fragment_shader] = SHADERS;
        let program = NormalMappingProgram::load(gl, vertex_shader, fragment_shader, shader_dir)?;

        // Load the textures.
        let diffuse_texture = load_dds(gl, diffuse)?;
        let normal_texture = load_bmp_custom(gl, normal)?;
        let specular_texture = load_dds(gl, specular)?;

        // Read our .obj file, compute the tangents, index the VBO.
        let (mesh, built_by) = load_mesh(obj, mesh_options)?;
        log::info!(
            "{}: {} triangles; {built_by}",
            obj.display(),
            mesh.indices.len() / 3
        );

        // Load it into VBOs (and the VAO that draws them).
        let buffers = MeshBuffers::new(gl, &mesh)?;

        Ok(Tutorial13 {
            gl: gl.clone(),
            program,
            texture_sets: vec![TextureSet {
                diffuse_texture,
                normal_texture,
                specular_texture,
                triangles: None,
            }],
            light_position_worldspace: LIGHT_POS,
            mesh: Rc::new(mesh),
            buffers,
            model_matrix: Mat4::IDENTITY,
            built_by: Some(built_by),
        })
    }

    /// The same set-up for a mesh read another way (a learner's model) with its textures already
    /// loaded: the GL state, the program, the CPU pipeline on `soup`, the buffers.
    pub fn from_soup(
        gl: &Gl,
        shader_dir: Option<&Path>,
        soup: &TriangleSoup,
        mesh_options: MeshOptions,
        texture_sets: Vec<TextureSet>,
    ) -> Result<Self> {
        let start = crate::clock::Instant::now();
        let basis = compute_tangent_basis(soup, mesh_options.tangents);
        let tangents = start.elapsed();
        let (mesh, code) = index_vbo_tbn_by_size(soup, &basis, mesh_options);
        let indexing = start.elapsed() - tangents;
        let mut tutorial = Self::from_mesh(gl, shader_dir, mesh, texture_sets)?;
        let built_by = BuiltBy {
            load_obj: None,
            index_vbo_tbn: code,
        };
        tutorial.built_by = Some(built_by);
        let ms = |d: std::time::Duration| d.as_secs_f64() * 1000.0;
        log::debug!(
            "computeTangentBasis {:.1} ms, indexVBO_TBN {:.1} ms, upload {:.1} ms ({built_by})",
            ms(tangents),
            ms(indexing),
            ms(start.elapsed() - tangents - indexing)
        );
        Ok(tutorial)
    }

    /// The tutorial's program and state with a mesh made another way (another tangent source).
    pub fn from_mesh(
        gl: &Gl,
        shader_dir: Option<&Path>,
        mesh: IndexedMesh,
        texture_sets: Vec<TextureSet>,
    ) -> Result<Self> {
        init_gl_state(gl);
        let [vertex_shader, fragment_shader] = SHADERS;
        let program = NormalMappingProgram::load(gl, vertex_shader, fragment_shader, shader_dir)?;
        let buffers = MeshBuffers::new(gl, &mesh)?;
        Ok(Tutorial13 {
            gl: gl.clone(),
            program,
            texture_sets,
            light_position_worldspace: LIGHT_POS,
            mesh: Rc::new(mesh),
            buffers,
            model_matrix: Mat4::IDENTITY,
            built_by: None,
        })
    }

    /// Re-runs the CPU pipeline with other switches and reloads the VBOs (the tutorial's experiments
    /// are edits to this part).
    pub fn reload_mesh(&mut self, obj_path: &Path, options: MeshOptions) -> Result<()> {
        let (mesh, built_by) = load_mesh(obj_path, options)?;
        log::debug!("{}: {built_by}", obj_path.display());
        self.buffers = MeshBuffers::new(&self.gl, &mesh)?;
        self.mesh = Rc::new(mesh);
        self.built_by = Some(built_by);
        Ok(())
    }

    /// Uploads a mesh made another way (another tangent source) in place of the tutorial's.
    pub fn set_mesh(&mut self, mesh: IndexedMesh) -> Result<()> {
        self.buffers = MeshBuffers::new(&self.gl, &mesh)?;
        self.mesh = Rc::new(mesh);
        self.built_by = None;
        Ok(())
    }

    /// One pass of the loop's body, drawing with `program` (the tutorial's, or the debugging one with
    /// the same uniforms). `projection_matrix` and `view_matrix` are `computeMatricesFromInputs`'.
    pub fn draw_with(
        &self,
        program: &NormalMappingProgram,
        projection_matrix: Mat4,
        view_matrix: Mat4,
        lines: Option<&DebugLines>,
    ) {
        self.draw_mesh_with(
            program,
            &self.buffers,
            projection_matrix,
            view_matrix,
            lines,
        );
    }

    /// [`Tutorial13::draw_with`] for another upload of the mesh (another tangent source's, in the
    /// compare view).
    pub fn draw_mesh_with(
        &self,
        program: &NormalMappingProgram,
        buffers: &MeshBuffers,
        projection_matrix: Mat4,
        view_matrix: Mat4,
        lines: Option<&DebugLines>,
    ) {
        let gl = &self.gl;
        let p = program;
        let model_matrix = self.model_matrix;
        let model_view_matrix = view_matrix * model_matrix;
        // The upper-left 3×3 of the ModelView matrix: it turns directions, not points.
        let model_view_3x3_matrix = Mat3::from_mat4(model_view_matrix);
        let mvp = projection_matrix * model_view_matrix;
        let light_pos = self.light_position_worldspace;
        // SAFETY: the program, uniforms and textures all belong to this context.
        unsafe {
            // Clear the screen.
            gl.clear(glow::COLOR_BUFFER_BIT | glow::DEPTH_BUFFER_BIT);

            // Use our shader.
            gl.use_program(Some(p.program.id));

            // Send our transformation to the currently bound shader.
            gl.uniform_matrix_4_f32_slice(p.matrix_id.as_ref(), false, &mvp.to_cols_array());
            let model = model_matrix.to_cols_array();
            gl.uniform_matrix_4_f32_slice(p.model_matrix_id.as_ref(), false, &model);
            let view = view_matrix.to_cols_array();
            gl.uniform_matrix_4_f32_slice(p.view_matrix_id.as_ref(), false, &view);
            let mv3x3 = model_view_3x3_matrix.to_cols_array();
            gl.uniform_matrix_3_f32_slice(p.model_view_3x3_matrix_id.as_ref(), false, &mv3x3);

            gl.uniform_3_f32(p.light_id.as_ref(), light_pos.x, light_pos.y, light_pos.z);
        }

        for set in &self.texture_sets {
            // Bind the diffuse, normal and specular textures in units 0, 1, 2 and point the
            // samplers at them.
            let textures = [
                (&set.diffuse_texture, &p.diffuse_texture_id),
                (&set.normal_texture, &p.normal_texture_id),
                (&set.specular_texture, &p.specular_texture_id),
            ];
            bind_textures(gl, &textures);

            // The attribute buffers, the index buffer, glDrawElements.
            match &set.triangles {
                None => buffers.draw(),
                Some(triangles) => buffers.draw_triangles(triangles.clone()),
            }
        }

        // "Debugging with the immediate mode": the TBN lines and the light's cross (at lightPos).
        if let Some(lines) = lines {
            lines.draw(projection_matrix, view_matrix, model_matrix);
        }
    }
}

/// `loadOBJ`, `computeTangentBasis`, `indexVBO_TBN`, in that order: for the tutorial's cylinder the
/// ports in `common/` ([`crate::common::objloader::load_obj`], [`compute_tangent_basis`],
/// [`crate::common::vboindexer::index_vbo_tbn`]), for a mesh above
/// [`crate::mesh::PORTS_UP_TO_TRIANGLES`] triangles their fast twins; says which ran.
pub fn load_mesh(obj_path: &Path, options: MeshOptions) -> Result<(IndexedMesh, BuiltBy)> {
    let (soup, load_obj) = load_obj_by_size(obj_path, options.code)?;
    let basis = compute_tangent_basis(&soup, options.tangents);
    let (mesh, index_vbo_tbn) = index_vbo_tbn_by_size(&soup, &basis, options);
    Ok((
        mesh,
        BuiltBy {
            load_obj: Some(load_obj),
            index_vbo_tbn,
        },
    ))
}
