//! The programs that draw a tangent source's frame: the tutorial's `NormalMapping`, the debugging
//! `NormalMappingDebug` (the experiments and colour views as uniforms) and the per-pixel
//! `NormalMappingDerivative`, with the panel's knobs, and which of them draws ([`SourceDrawer`]).

use glow::HasContext;

use crate::debug::views::ShaderSwitches;
use crate::gl::buffers::MeshBuffers;
use crate::gl::Gl;
use crate::scenes::scene::{FrameInput, ShaderSet};
use crate::tangent_source::TangentSource;
use crate::Result;

use super::tutorial13::{NormalMappingProgram, Tutorial13, SHADERS};

/// Which program draws a tangent source's frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Drawing {
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
    pub(super) fn shaders(self) -> (&'static str, [&'static str; 2]) {
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

/// The scene's programs beside the tutorial's own: loaded together, replaced together.
pub(super) struct Programs {
    /// `NormalMappingDebug`: the same lighting with the experiments and colour views as uniforms.
    debug: DebugProgram,
    /// `NormalMappingDerivative`: the per-pixel tangent frame, for [`TangentSource::Derivative`].
    derivative: NormalMappingProgram,
    /// Its light power and normal strength.
    derivative_knobs: KnobUniforms,
}

impl Programs {
    pub(super) fn load(gl: &Gl, shaders: &ShaderSet) -> Result<Self> {
        let derivative = NormalMappingProgram::new(shaders.load(gl, DERIVATIVE_SHADERS)?)?;
        Ok(Programs {
            debug: DebugProgram::load(gl, shaders)?,
            derivative_knobs: KnobUniforms::locate(&derivative.program)?,
            derivative,
        })
    }

    /// What draws a tangent source's frame with these programs and `tutorial`'s, with the shader's
    /// `switches` and the panel's `knobs` (the debugging program even at the tutorial's settings
    /// with `use_debug_program`). It borrows only these, so the compare view that calls it can be
    /// borrowed mutably beside it.
    pub(super) fn drawer<'a>(
        &'a self,
        tutorial: &'a Tutorial13,
        switches: ShaderSwitches,
        knobs: Knobs,
        use_debug_program: bool,
    ) -> SourceDrawer<'a> {
        SourceDrawer {
            tutorial,
            programs: self,
            switches,
            knobs,
            use_debug_program,
        }
    }
}

/// What draws one tangent source's frame: the tutorial with the program that the source and the
/// switches need (see [`Programs::drawer`]).
pub(super) struct SourceDrawer<'a> {
    tutorial: &'a Tutorial13,
    programs: &'a Programs,
    switches: ShaderSwitches,
    knobs: Knobs,
    use_debug_program: bool,
}

impl SourceDrawer<'_> {
    /// The tutorial's own program unless an experiment, a colour view or a slider asks for the
    /// debug one; the per-pixel frame has a program of its own (without the experiments).
    pub(super) fn drawing(&self, source: TangentSource) -> Drawing {
        if !source.has_vertex_tangents() {
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
    pub(super) fn program(&self, source: TangentSource) -> &NormalMappingProgram {
        match self.drawing(source) {
            Drawing::Tutorial => &self.tutorial.program,
            Drawing::Debug => {
                let debug = &self.programs.debug;
                debug.set_switches(self.switches, self.knobs);
                &debug.program
            }
            Drawing::Derivative => {
                let (program, knobs) = (&self.programs.derivative, &self.programs.derivative_knobs);
                self.knobs.set(&self.programs.debug.gl, program, knobs);
                program
            }
        }
    }

    /// One frame of `source` from `buffers`.
    pub(super) fn draw(&self, source: TangentSource, buffers: &MeshBuffers, frame: &FrameInput) {
        let (projection, view) = (frame.projection, frame.view);
        let program = self.program(source);
        self.tutorial
            .draw_mesh_with(program, buffers, projection, view, None);
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
    pub fn load(gl: &Gl, shaders: &ShaderSet) -> Result<Self> {
        let program = NormalMappingProgram::new(shaders.load(gl, DEBUG_SHADERS)?)?;
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
