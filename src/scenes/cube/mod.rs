//! The `cube` scene: article 003, "Tangent space normal mapping with GLSL". A stone cube lit with
//! Blinn-Phong (the halfway vector, exponent 200) in tangent space, with normal mapping switched on
//! and off as the article's `flag` does.
//!
//! The article solves the edge/UV system for T and B per vertex in its `computeTangentSpaceMatrix`;
//! that is the system Tutorial 13's `computeTangentBasis` solves per triangle, so the cube goes through
//! the crate's CPU pipeline like the cylinder: a triangle soup with UVs per face →
//! [`compute_tangent_basis`](crate::common::tangentspace::compute_tangent_basis) →
//! [`index_vbo_tbn`](crate::common::vboindexer::index_vbo_tbn). The shaders
//! (`CubeBlinnPhong.*`) do the rest, as the article's do: the light, halfway and normal vectors are
//! brought into tangent space per vertex, the lighting is done per fragment.

pub mod assets;

use std::path::PathBuf;

use glam::{Mat4, Vec2, Vec3};
use glow::HasContext;

use crate::common::objloader::TriangleSoup;
use crate::common::vboindexer::IndexedMesh;
use crate::gl::buffers::MeshBuffers;
use crate::gl::state::GlState;
use crate::gl::{Gl, Maps};
use crate::mesh::{build_mesh, MeshOptions};
use crate::Result;
use assets::FILES;

use super::descriptor::SceneType;
use super::lights::{light_slider, power_slider, Light, WorldLight};
use super::options::SceneOptions;
use super::scene::{DrawingProgram, FrameInput, Scene, SceneContext, ShaderSet};
use super::starts::{Handle, Starts};
use super::table::Control;

/// The scene's switch and sliders, in the order they are listed.
const CONTROLS: &[C] = &[
    C::toggle(
        'N',
        "normal mapping",
        "normal mapping on / off (the article's flag)",
        |cube| cube.normal_mapping,
        |cube, on| {
            cube.normal_mapping = on;
            Ok(())
        },
    )
    .flag(
        "no-normal-map",
        false,
        "The article's `flag`, perturbing the normal with the normal map: start with it off",
    )
    .in_title("normal mapping"),
    light_slider::<Cube, 0>(),
    light_slider::<Cube, 1>(),
    light_slider::<Cube, 2>(),
    power_slider::<Cube>(),
];

/// A control of this scene.
type C = Control<Cube>;

/// The article's flag (`--no-normal-map`, key N).
pub const NORMAL_MAPPING: Handle<Cube, bool> = Handle::new(CONTROLS, "normal mapping");

/// The scene's two shader files.
pub const SHADERS: [&str; 2] = [
    "CubeBlinnPhong.vertexshader",
    "CubeBlinnPhong.fragmentshader",
];

/// Half the cube's side: the article's cube spans -1..1.
pub const HALF_SIZE: f32 = 1.0;

/// Turn about y, then tilt about x (radians): seen from the tutorial's start camera at (0, 0, 5), the
/// cube shows its front (+z), right (+x) and top (+y) faces, the front one the largest, and fills
/// about two thirds of the frame's height. The article
/// gives no placement; the cube stays at the origin, as its vertices are.
pub const YAW: f32 = -30.0 * std::f32::consts::PI / 180.0;
pub const PITCH: f32 = 20.0 * std::f32::consts::PI / 180.0;

/// The light, in world space. The article uses a `light_position` it never gives. Chosen up and to
/// the left, in front of the cube and a little behind the camera: the front face is lit at 0.75–0.91
/// of full diffuse, the top at a grazing 0.31–0.41, and the right face is turned away (only the
/// emissive and ambient terms reach it). The exponent-200 highlight needs the halfway vector within
/// about 10° of the normal; on the flat faces it comes no closer than 19° (the front face's upper right
/// corner), so from the start camera normal mapping off shows no highlight, and normal mapping on
/// makes the stones' shoulders that lean that way glint. A highlight on the flat front face would need
/// the light at the camera's mirror image in that face, below and to the left, which would turn both
/// other faces away from it.
pub const LIGHT_POSITION_WORLDSPACE: Vec3 = Vec3::new(-4.0, 1.5, 6.0);

/// The cube's model matrix: [`YAW`] about y, then [`PITCH`] about x.
pub fn model_matrix() -> Mat4 {
    Mat4::from_rotation_x(PITCH) * Mat4::from_rotation_y(YAW)
}

/// One face of the cube in model space: its outward normal, and the directions in which U and V
/// grow across it. `u × v = normal`, so a texture is seen the right way round from outside.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Face {
    pub normal: Vec3,
    pub u: Vec3,
    pub v: Vec3,
}

/// The six faces: the article's four sides (+z, -z, +x, -x; V up each side), then
/// the top and bottom it leaves open (V towards the back on top, towards the front below).
pub const FACES: [Face; 6] = [
    Face {
        normal: Vec3::Z,
        u: Vec3::X,
        v: Vec3::Y,
    },
    Face {
        normal: Vec3::NEG_Z,
        u: Vec3::NEG_X,
        v: Vec3::Y,
    },
    Face {
        normal: Vec3::X,
        u: Vec3::NEG_Z,
        v: Vec3::Y,
    },
    Face {
        normal: Vec3::NEG_X,
        u: Vec3::Z,
        v: Vec3::Y,
    },
    Face {
        normal: Vec3::Y,
        u: Vec3::X,
        v: Vec3::NEG_Z,
    },
    Face {
        normal: Vec3::NEG_Y,
        u: Vec3::X,
        v: Vec3::Z,
    },
];

/// The cube as a triangle soup, two triangles per face, counter-clockwise seen from outside. Each
/// face carries the whole texture (UV 0..1, V growing up the picture: the BMPs' first row is the
/// picture's bottom, GL's t = 0). Built here rather than read from an OBJ, so V is not negated as the
/// tutorial's loader does.
pub fn cube_soup(half_size: f32) -> TriangleSoup {
    let mut soup = TriangleSoup {
        vertices: Vec::with_capacity(36),
        uvs: Vec::with_capacity(36),
        normals: Vec::with_capacity(36),
    };
    // (U, V) of the corners of a face's two triangles.
    const CORNERS: [Vec2; 6] = [
        Vec2::new(0.0, 0.0),
        Vec2::new(1.0, 0.0),
        Vec2::new(1.0, 1.0),
        Vec2::new(0.0, 0.0),
        Vec2::new(1.0, 1.0),
        Vec2::new(0.0, 1.0),
    ];
    for face in FACES {
        for uv in CORNERS {
            let across = face.u * (2.0 * uv.x - 1.0) + face.v * (2.0 * uv.y - 1.0);
            soup.vertices.push((face.normal + across) * half_size);
            soup.uvs.push(uv);
            soup.normals.push(face.normal);
        }
    }
    soup
}

/// The cube through the tutorial's CPU pipeline: per-corner tangents and bitangents from the UV
/// solve, then indexed (24 vertices, their tangents and bitangents summed over the corners merged).
pub fn cube_mesh() -> IndexedMesh {
    build_mesh(&cube_soup(HALF_SIZE), MeshOptions::default())
}

crate::uniforms! {
    /// The program and its uniform handles.
    pub struct CubeProgram for Program {
        projection: "P",
        view: "V",
        model: "M",
        light: "LightPosition_worldspace",
        light_power: "LightPower",
        normal_mapping: "NormalMapping",
        diffuse_sampler: "DiffuseTextureSampler",
        normal_sampler: "NormalTextureSampler",
    }
}

impl CubeProgram {
    pub fn load(gl: &Gl, shaders: &ShaderSet) -> Result<Self> {
        Self::new(shaders.load(gl, SHADERS)?)
    }
}

/// The stone cube and its switch.
pub struct Cube {
    // All hold GL objects of the same context (kept alive by the shared `Gl`).
    pub program: CubeProgram,
    /// The diffuse and normal maps.
    maps: Maps,
    buffers: MeshBuffers,
    gl: Gl,
    /// The article's `flag`: on, as in the article's first screenshot, unless started off.
    pub normal_mapping: bool,
    /// [`model_matrix`] unless a test moves the cube.
    pub model_matrix: Mat4,
    /// At [`LIGHT_POSITION_WORLDSPACE`] unless a test or the panel moves it; its power is a factor
    /// on the diffuse and specular light (the article's 1, the panel moves it).
    pub light: Light,
    /// `CubeBlinnPhong.*`, from `--shaders` or the crate's.
    shaders: ShaderSet,
}

impl SceneType for Cube {
    const NAME: &'static str = "cube";
    const DESCRIPTION: &'static str = "Article 003: a stone cube lit Blinn-Phong in tangent space";
    /// Drawn in the tutorial's state, applied every frame (another scene may have drawn since).
    const GL_STATE: GlState = GlState::TUTORIAL;
    const CONTROLS: &'static [Control<Self>] = CONTROLS;
    const ASSET_FILES: &'static [&'static str] = &FILES.names();

    /// Loads `cube/diffuse.bmp` and `cube/normal.bmp` from `assets` and the shaders from
    /// `shader_dir` (or the crate's), and builds the cube.
    fn new(context: &SceneContext, options: &SceneOptions, _: &mut Starts<Self>) -> Result<Self> {
        let shaders = ShaderSet::new(options.shader_dir(), [SHADERS]);
        let gl = context.gl;
        let program = CubeProgram::load(gl, &shaders)?;
        let maps = Maps::load(gl, &options.asset_files(FILES.names())?)?;
        let buffers = MeshBuffers::new(gl, &cube_mesh())?;
        Ok(Cube {
            program,
            maps,
            buffers,
            gl: gl.clone(),
            normal_mapping: true,
            model_matrix: model_matrix(),
            light: Self::LIGHT_START,
            shaders,
        })
    }

    fn generate_assets() -> Result<crate::assets::GeneratedFiles> {
        assets::generate()
    }
}

impl WorldLight for Cube {
    const LIGHT_START: Light = Light {
        position_worldspace: LIGHT_POSITION_WORLDSPACE,
        power: 1.0,
    };
    const LIGHT_POWER_MAX: f32 = 4.0;

    fn world_light(&self) -> &Light {
        &self.light
    }
    fn world_light_mut(&mut self) -> &mut Light {
        &mut self.light
    }
}

impl Scene for Cube {
    fn draw(&mut self, frame: &FrameInput) {
        let gl = &self.gl;
        let p = &self.program;
        let light = self.light.position_worldspace;
        // SAFETY: the program, its uniforms and the textures all belong to this context.
        unsafe {
            gl.clear(glow::COLOR_BUFFER_BIT | glow::DEPTH_BUFFER_BIT);
            gl.use_program(Some(p.program.id));
            // The article's three matrices, separately: the vertex shader needs V and M on their own
            // to carry vectors back from camera and world space into model space.
            let matrices = [
                (&p.projection, frame.projection),
                (&p.view, frame.view),
                (&p.model, self.model_matrix),
            ];
            for (uniform, matrix) in matrices {
                gl.uniform_matrix_4_f32_slice(uniform.as_ref(), false, &matrix.to_cols_array());
            }
            gl.uniform_3_f32(p.light.as_ref(), light.x, light.y, light.z);
            gl.uniform_1_f32(p.light_power.as_ref(), self.light.power);
            gl.uniform_1_i32(p.normal_mapping.as_ref(), i32::from(self.normal_mapping));
            self.maps.bind(gl, &p.diffuse_sampler, &p.normal_sampler);
        }
        self.buffers.draw();
    }

    fn shader_files(&self) -> Vec<PathBuf> {
        self.shaders.files()
    }

    fn drawing_programs(&self) -> Vec<DrawingProgram> {
        let name = "CubeBlinnPhong (article 003's)";
        vec![self.shaders.program(name, SHADERS)]
    }

    /// The scene's one program: replaced only once the new one has linked.
    fn reload_shaders(&mut self) -> Result<()> {
        self.program = CubeProgram::load(&self.gl, &self.shaders)?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    // Fails if a face is wound clockwise seen from outside, its normal is not the outward one, or a
    // texture would be mirrored on it (U × V must be the outward normal).
    #[test]
    fn faces_are_outward_and_counter_clockwise() {
        let soup = cube_soup(HALF_SIZE);
        assert_eq!(soup.vertices.len(), 36);
        for (corners, normals) in soup.vertices.chunks(3).zip(soup.normals.chunks(3)) {
            let winding = (corners[1] - corners[0]).cross(corners[2] - corners[0]);
            assert!(winding.dot(normals[0]) > 0.0, "{corners:?}");
            let centre = (corners[0] + corners[1] + corners[2]) / 3.0;
            assert!(centre.dot(normals[0]) > 0.0, "{corners:?} faces inwards");
        }
        for face in FACES {
            assert_eq!(face.u.cross(face.v), face.normal);
        }
    }

    // Fails if the CPU pipeline does not give each face's own frame: 24 vertices (4 per face), 36
    // indices, T along the face's U, B along its V (summed, so not unit length), N outward, and a
    // right-handed frame (T × B along N), which is what the green-up normal map assumes.
    #[test]
    fn pipeline_gives_each_face_its_uv_frame() {
        let mesh = cube_mesh();
        assert_eq!(mesh.vertices.len(), 24);
        assert_eq!(mesh.indices.len(), 36);
        for i in 0..24 {
            let n = mesh.normals[i];
            let face = FACES.iter().find(|f| f.normal == n).expect("a face normal");
            let (t, b) = (mesh.tangents[i], mesh.bitangents[i]);
            assert!(t.normalize().abs_diff_eq(face.u, 1e-6), "{i}: T {t}");
            assert!(b.normalize().abs_diff_eq(face.v, 1e-6), "{i}: B {b}");
            assert!(t.cross(b).normalize().abs_diff_eq(n, 1e-6));
            assert!(mesh.vertices[i].dot(n) > 0.0);
        }
    }
}
