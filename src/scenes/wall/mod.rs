//! The `wall` scene: article 004's stone wall, one square lit by one white light, in view space or in
//! tangent space (or, for comparison, without its normal map).
//!
//! The article's numbers: the square at the origin, the light at (4, 0, 4) with colour (1, 1, 1) and
//! intensity 50, falloff 1/d², specular reflectivity 0.3 and lobe density (Phong exponent) 5, the
//! diffuse texel as specular colour, no ambient term. Decided here, as the article does not say: the
//! square is 2 × 2 facing +z (the tutorial's start camera at (0, 0, 5) sees it whole), its UVs run 0..1
//! with v up, and the camera is the tutorial's. The article claims both spaces give the same result;
//! that holds exactly in arithmetic when the TBN matrix is a rotation (unit, orthogonal T, B, N, as on
//! this square), and the tests measure how close the two programs' frames are in floating point.

pub mod assets;

use std::path::PathBuf;

use clap::ValueEnum;
use glam::{Mat4, Vec2, Vec3};
use glow::HasContext;

use crate::common::objloader::TriangleSoup;
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
use super::table::{ChoiceValue, Choices, Control};

/// The article's light.
pub const LIGHT_POSITION_WORLDSPACE: Vec3 = Vec3::new(4.0, 0.0, 4.0);
const LIGHT_COLOR: Vec3 = Vec3::ONE;
const LIGHT_INTENSITY: f32 = 50.0;
/// The article's square.
const SPECULAR_REFLECTIVITY: f32 = 0.3;
const SPECULAR_LOBE_FACTOR: f32 = 5.0;
/// Half the square's side.
const HALF_SIDE: f32 = 1.0;

/// Where the lighting is computed.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum LightingSpace {
    /// The TBN matrix brings the map's normal into view space (the article's first program).
    #[default]
    View,
    /// Everything else is brought into tangent space (the article's second program).
    Tangent,
    /// No normal map: the square's own normal, in view space (the article's starting point).
    #[value(name = "none")]
    NoNormalMap,
}

impl LightingSpace {
    fn shaders(self) -> [&'static str; 2] {
        match self {
            Self::View => ["WallViewSpace.vertexshader", "WallViewSpace.fragmentshader"],
            Self::Tangent => [
                "WallTangentSpace.vertexshader",
                "WallTangentSpace.fragmentshader",
            ],
            Self::NoNormalMap => [
                "WallNoNormalMap.vertexshader",
                "WallNoNormalMap.fragmentshader",
            ],
        }
    }

    /// The `--space` name.
    pub fn name(self) -> String {
        crate::choices::name(&self)
    }
}

impl ChoiceValue for LightingSpace {
    fn choice_name(self) -> String {
        self.name()
    }
}

/// The scene's choice and sliders, in the order they are listed.
const CONTROLS: &[C] = &[
    C::choice(
        'S',
        "lighting space",
        "lighting space: view, tangent, none (no normal map)",
        &Choices::<Wall, _> {
            values: |_| LightingSpace::value_variants().to_vec(),
            get: |wall| wall.space,
            set: |wall, space| {
                wall.space = space;
                Ok(())
            },
        },
    )
    .enum_flag::<LightingSpace>(
        "space",
        "SPACE",
        "Light the stone wall in view space, in tangent space, or without its normal map \
         [default: view]",
    )
    .in_title("lighting space"),
    light_slider::<Wall, 0>(),
    light_slider::<Wall, 1>(),
    light_slider::<Wall, 2>(),
    power_slider::<Wall>(),
];

/// A control of this scene.
type C = Control<Wall>;

/// Where the wall is lit (`--space`, key S).
pub const SPACE: Handle<Wall, LightingSpace> = Handle::new(CONTROLS, "lighting space");

crate::uniforms! {
    /// One of the three programs and its uniforms (the same names in all three).
    struct WallProgram for Program {
        m: "M",
        v: "V",
        p: "P",
        light_position: "LightPosition_worldspace",
        light_color: "LightColor",
        light_intensity: "LightIntensity",
        specular_reflectivity: "SpecularReflectivity",
        specular_lobe_factor: "SpecularLobeFactor",
        diffuse_sampler: "DiffuseTextureSampler",
        normal_sampler: "NormalTextureSampler" optional("WallNoNormalMap has no normal map"),
    }
}

pub struct Wall {
    gl: Gl,
    /// One per [`LightingSpace`], in declaration order (indexed by `space as usize`).
    programs: Vec<WallProgram>,
    /// View space (the article's first program) unless started otherwise.
    pub space: LightingSpace,
    /// The diffuse and normal maps.
    maps: Maps,
    buffers: MeshBuffers,
    model_matrix: Mat4,
    /// The three programs' shaders, from `--shaders` or the crate's.
    shaders: ShaderSet,
    /// The article's light unless the panel moves it; its power is the light's intensity.
    pub light: Light,
}

impl SceneType for Wall {
    const NAME: &'static str = "wall";
    const DESCRIPTION: &'static str =
        "Article 004: a stone wall lit in view space or in tangent space";
    /// The article's wall in the tutorial's frame: its state, set before each frame.
    const GL_STATE: GlState = GlState::TUTORIAL;
    const CONTROLS: &'static [Control<Self>] = CONTROLS;
    const ASSET_FILES: &'static [&'static str] = &FILES.names();

    /// Loads the stone wall's two maps from `assets`/wall/ and the three programs.
    fn new(context: &SceneContext, options: &SceneOptions, _: &mut Starts<Self>) -> Result<Self> {
        let spaces = LightingSpace::value_variants().iter();
        let shaders = ShaderSet::new(options.shader_dir(), spaces.map(|space| space.shaders()));
        let gl = context.gl;
        let programs = load_programs(gl, &shaders)?;
        let maps = Maps::load(gl, &options.asset_files(FILES.names())?)?;
        // The tutorial's CPU pipeline gives the square its tangents: T = +x (dP/du), B = +y (dP/dv).
        let mesh = build_mesh(&square(), MeshOptions::default());
        let buffers = MeshBuffers::new(gl, &mesh)?;
        Ok(Wall {
            gl: gl.clone(),
            programs,
            space: LightingSpace::default(),
            maps,
            buffers,
            model_matrix: Mat4::IDENTITY,
            shaders,
            light: Self::LIGHT_START,
        })
    }

    fn generate_assets() -> Result<crate::assets::GeneratedFiles> {
        assets::generate()
    }
}

/// One program per [`LightingSpace`], in declaration order.
fn load_programs(gl: &Gl, shaders: &ShaderSet) -> Result<Vec<WallProgram>> {
    LightingSpace::value_variants()
        .iter()
        .map(|space| WallProgram::new(shaders.load(gl, space.shaders())?))
        .collect()
}

/// The 2 × 2 square at the origin facing +z, as two counter-clockwise triangles; UV (0, 0) at the
/// bottom left, v up (the BMP maps are stored bottom row first, so the picture stands upright).
fn square() -> TriangleSoup {
    let h = HALF_SIDE;
    let corners = [
        (Vec3::new(-h, -h, 0.0), Vec2::new(0.0, 0.0)),
        (Vec3::new(h, -h, 0.0), Vec2::new(1.0, 0.0)),
        (Vec3::new(h, h, 0.0), Vec2::new(1.0, 1.0)),
        (Vec3::new(-h, h, 0.0), Vec2::new(0.0, 1.0)),
    ];
    let mut soup = TriangleSoup::default();
    for i in [0, 1, 2, 0, 2, 3] {
        let (position, uv) = corners[i];
        soup.vertices.push(position);
        soup.uvs.push(uv);
        soup.normals.push(Vec3::Z);
    }
    soup
}

impl WorldLight for Wall {
    const LIGHT_START: Light = Light {
        position_worldspace: LIGHT_POSITION_WORLDSPACE,
        power: LIGHT_INTENSITY,
    };
    const LIGHT_POWER_MAX: f32 = 200.0;

    fn world_light(&self) -> &Light {
        &self.light
    }
    fn world_light_mut(&mut self) -> &mut Light {
        &mut self.light
    }
}

impl Scene for Wall {
    fn draw(&mut self, frame: &FrameInput) {
        let gl = &self.gl;
        let p = &self.programs[self.space as usize];
        let light = self.light.position_worldspace;
        // SAFETY: the program, uniforms and textures all belong to this context.
        unsafe {
            gl.clear(glow::COLOR_BUFFER_BIT | glow::DEPTH_BUFFER_BIT);
            gl.use_program(Some(p.program.id));
            let matrix = |location: &crate::gl::uniforms::Uniform, m: Mat4| {
                gl.uniform_matrix_4_f32_slice(location.as_ref(), false, &m.to_cols_array());
            };
            matrix(&p.m, self.model_matrix);
            matrix(&p.v, frame.view);
            matrix(&p.p, frame.projection);
            gl.uniform_3_f32(p.light_position.as_ref(), light.x, light.y, light.z);
            let c = LIGHT_COLOR;
            gl.uniform_3_f32(p.light_color.as_ref(), c.x, c.y, c.z);
            gl.uniform_1_f32(p.light_intensity.as_ref(), self.light.power);
            let reflectivity = p.specular_reflectivity.as_ref();
            gl.uniform_1_f32(reflectivity, SPECULAR_REFLECTIVITY);
            gl.uniform_1_f32(p.specular_lobe_factor.as_ref(), SPECULAR_LOBE_FACTOR);
            self.maps.bind(gl, &p.diffuse_sampler, &p.normal_sampler);
        }
        self.buffers.draw();
    }

    fn drawing_programs(&self) -> Vec<DrawingProgram> {
        let name = format!(
            "{} (article 004's)",
            self.space.shaders()[0].trim_end_matches(".vertexshader")
        );
        vec![self.shaders.program(&name, self.space.shaders())]
    }

    fn shader_files(&self) -> Vec<PathBuf> {
        self.shaders.files()
    }

    /// All three programs or none.
    fn reload_shaders(&mut self) -> Result<()> {
        self.programs = load_programs(&self.gl, &self.shaders)?;
        Ok(())
    }
}
