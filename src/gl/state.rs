//! The fixed-function state a frame relies on, as one value a scene declares and applies at the start
//! of each frame. Scenes share one context (the window's Enter key switches them), so a scene that set
//! its state only once, or left it to another scene, would draw differently after another one ran.

use glow::HasContext;

use super::Gl;

/// Everything outside its programs, buffers and textures that a scene's frame depends on. Applying it
/// also puts back what the debugging aids change on the way (scissor, blending, program 0), so that
/// whatever drew before, the frame starts from the same state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GlState {
    /// `glClearColor`.
    pub clear_color: [f32; 4],
    /// Depth test with `GL_LESS` (and depth writes on), or no depth test.
    pub depth_test: bool,
    /// Back faces culled (counter-clockwise fronts), or nothing culled.
    pub cull_back_faces: bool,
}

impl GlState {
    /// The tutorial's: dark blue background `(0, 0, 0.4, 0)`, depth test with LESS, back faces
    /// culled. The articles' 3D scenes draw with it too, so that all scenes sit on one background.
    pub const TUTORIAL: GlState = GlState::opaque_3d([0.0, 0.0, 0.4, 0.0]);

    /// A 3D scene drawn the tutorial's way: depth test with LESS, back faces culled.
    pub const fn opaque_3d(clear_color: [f32; 4]) -> Self {
        GlState {
            clear_color,
            depth_test: true,
            cull_back_faces: true,
        }
    }

    /// A flat picture: no depth test, nothing culled.
    pub const fn flat(clear_color: [f32; 4]) -> Self {
        GlState {
            clear_color,
            depth_test: false,
            cull_back_faces: false,
        }
    }

    /// Sets the state on the current context.
    pub fn apply(&self, gl: &Gl) {
        let [r, g, b, a] = self.clear_color;
        let set = |cap, on: bool| {
            // SAFETY: enabling or disabling a capability of the current context.
            unsafe {
                if on {
                    gl.enable(cap);
                } else {
                    gl.disable(cap);
                }
            }
        };
        // SAFETY: state-setting calls on the current context.
        unsafe {
            gl.clear_color(r, g, b, a);
            gl.depth_func(glow::LESS);
            gl.depth_mask(true);
            gl.cull_face(glow::BACK);
            gl.front_face(glow::CCW);
            gl.color_mask(true, true, true, true);
        }
        set(glow::DEPTH_TEST, self.depth_test);
        set(glow::CULL_FACE, self.cull_back_faces);
        set(glow::BLEND, false);
        set(glow::SCISSOR_TEST, false);
    }
}
