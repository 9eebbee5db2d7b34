//! Rendering without a window: an EGL context on Mesa, an offscreen framebuffer, any scene's frame
//! exactly as the window draws it. Used by `--headless`, `--bench` and the tests.

use std::time::Instant;

use glow::HasContext;

use super::host::SceneHost;
use super::FrontEnd;
use crate::gl::context::HeadlessContext;
use crate::gl::offscreen::OffscreenTarget;
use crate::gl::{check_gl_errors, Profile};
use crate::scenes::{Scene, SceneContext, SceneDescriptor, SceneOptions};
use crate::Result;

/// What to render headless.
#[derive(Debug, Clone)]
pub struct HeadlessOptions {
    pub descriptor: &'static SceneDescriptor,
    pub scene: SceneOptions,
    pub width: u32,
    pub height: u32,
    pub profile: Profile,
    /// Use a GPU's EGL device where there is one; otherwise llvmpipe.
    pub prefer_hardware: bool,
    /// Samples per pixel of the target (`--msaa`; 0 = none, the tutorial's screenshot).
    pub msaa: u32,
}

impl Default for HeadlessOptions {
    /// The tutorial's frame: the cylinder, 1024×768, core profile, llvmpipe.
    fn default() -> Self {
        HeadlessOptions {
            descriptor: crate::scenes::default_scene(),
            scene: SceneOptions::default(),
            width: 1024,
            height: 768,
            profile: Profile::Core,
            prefer_hardware: false,
            msaa: 0,
        }
    }
}

/// A ready-to-draw headless set-up: context, target, and the [`SceneHost`] with the scene and its
/// camera at the start. Tests and tools reach the scene, its camera, the cursor and the panel
/// through [`HeadlessRenderer::host`], as the window's own front end does.
pub struct HeadlessRenderer {
    // Field order is drop order: GL objects go before the context that owns them.
    pub host: SceneHost,
    pub target: OffscreenTarget,
    pub context: HeadlessContext,
}

impl HeadlessRenderer {
    pub fn new(options: &HeadlessOptions) -> Result<Self> {
        let context = HeadlessContext::new(options.profile, options.prefer_hardware)?;
        log::debug!("headless context: {}", context.info());
        let gl = context.gl().clone();
        // Stored like a window's buffers, so that the headless frame is the window's frame.
        let target = OffscreenTarget::with_window_orientation(
            &gl,
            (options.width, options.height),
            options.msaa,
            context.extensions(),
        )?;
        let size = (options.width, options.height);
        let host = with_scene_context(&context, |c| {
            SceneHost::new(
                c,
                options.descriptor,
                &options.scene,
                size,
                FrontEnd::Window,
            )
        })?;
        Ok(HeadlessRenderer {
            host,
            target,
            context,
        })
    }

    /// The scene as its own type, for tests and tools that reach into it. Panics if the renderer
    /// holds another scene.
    pub fn scene_mut<S: Scene>(&mut self) -> &mut S {
        let name = self.host.descriptor().name;
        self.host
            .scene_as()
            .unwrap_or_else(|| panic!("the renderer holds scene {name}, not the one asked for"))
    }

    /// [`HeadlessRenderer::scene_mut`], shared.
    pub fn scene_ref<S: Scene>(&self) -> &S {
        let name = self.host.descriptor().name;
        self.host
            .scene_as_ref()
            .unwrap_or_else(|| panic!("the renderer holds scene {name}, not the one asked for"))
    }

    /// One frame with time frozen at 0 and no input, as the original's screenshot test; the panel
    /// over it if it is shown (with the events of [`SceneHost::panel_event`] as its input).
    pub fn render(&mut self) {
        self.target.bind();
        let size = (self.target.width(), self.target.height());
        self.host.set_size(size);
        self.host.draw(0.0, 0.0, true);
        let panel_input = self.host.panel_input(None);
        self.host.draw_panel(panel_input);
    }

    /// Renders `frames` frames (at least one) and returns the last, top row first. Fails if GL
    /// reported any error along the way.
    pub fn render_frames(&mut self, frames: u32) -> Result<image::RgbaImage> {
        for _ in 0..frames.max(1) {
            self.render();
        }
        let image = self.target.read_rgba();
        self.check_errors()?;
        Ok(image)
    }

    /// Drains GL's error flags: an error is a bug in this program, so it is reported, not ignored.
    pub fn check_errors(&self) -> Result<()> {
        check_gl_errors(self.context.gl(), "frame")
    }

    /// Milliseconds per frame for `frames` frames, each timed to completion (`glFinish`).
    pub fn bench(&mut self, frames: u32) -> Result<Vec<f64>> {
        let gl = self.context.gl().clone();
        let mut times = Vec::with_capacity(frames as usize);
        for _ in 0..frames {
            let start = Instant::now();
            self.render();
            // SAFETY: waits for the current context's queued work.
            unsafe { gl.finish() };
            times.push(start.elapsed().as_secs_f64() * 1000.0);
        }
        self.check_errors()?;
        Ok(times)
    }
}

/// `f` with the scene context of the headless `context`.
fn with_scene_context<T>(context: &HeadlessContext, f: impl FnOnce(&SceneContext) -> T) -> T {
    f(&SceneContext {
        gl: context.gl(),
        info: context.info(),
        extensions: context.extensions(),
    })
}
