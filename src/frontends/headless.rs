//! Rendering without a window: an EGL context on Mesa, an offscreen framebuffer, any scene's frame
//! exactly as the window draws it, through the same host (its clock ticks, so its panel shows the
//! ms/frame figure). Used by `--headless`, `--bench` and the tests.

use std::time::Instant;

use glow::HasContext;

use super::events::{Event, FrameTime, Request};
use super::host::SceneHost;
use crate::gl::context::{EglContext, HeadlessContext};
use crate::gl::offscreen::OffscreenTarget;
use crate::gl::{check_gl_errors, Profile};
use crate::scenes::{Scene, SceneDescriptor, SceneOptions};
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

/// A ready-to-draw headless set-up: the EGL context, the target, and the [`SceneHost`] with the
/// scene and its camera at the start, its time frozen. Tests and tools reach the scene, its camera,
/// the cursor, the panel and the GL context through [`HeadlessRenderer::host`], as the window's own
/// front end does, and give it input as the window does ([`HeadlessRenderer::event`]).
pub struct HeadlessRenderer {
    // Field order is drop order: GL objects go before the context that owns them.
    pub host: SceneHost,
    pub target: OffscreenTarget,
    /// The EGL context the host's [`GlContext`](crate::gl::current::GlContext) draws on.
    pub context: EglContext,
}

impl HeadlessRenderer {
    pub fn new(options: &HeadlessOptions) -> Result<Self> {
        let context = HeadlessContext::new(options.profile, options.prefer_hardware)?;
        log::debug!("headless context: {}", context.info());
        // Stored like a window's buffers, so that the headless frame is the window's frame.
        let size = (options.width, options.height);
        let target = OffscreenTarget::with_window_orientation(
            context.gl(),
            size,
            options.msaa,
            context.extensions(),
        )?;
        let (gl, context) = context.split();
        // The original's screenshot test: time frozen at 0, no input moves the camera.
        let frozen = FrameTime::Frozen;
        let host = SceneHost::for_window(gl, options.descriptor, &options.scene, size, frozen)?;
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

    /// Gives the host one event, as a window gives it one of its own, and returns what the host
    /// asked for, having done what headless rendering can: the files are on disk, so a fetch is done
    /// at once (the others are for a window: quit, the cursor, a screenshot, the title, the key
    /// list).
    pub fn event(&mut self, event: Event) -> Result<Vec<Request>> {
        self.host.event(event)?;
        self.requests()
    }

    /// What the host asked for since the last call, a fetch done (see [`HeadlessRenderer::event`]).
    pub fn requests(&mut self) -> Result<Vec<Request>> {
        let mut asked = Vec::new();
        while let Some(request) = self.host.next_request() {
            if let Request::Fetch { then, .. } = &request {
                self.host.fetched(then.clone())?;
            }
            asked.push(request);
        }
        Ok(asked)
    }

    /// One frame into the target, the panel over it if it is shown (with the events given since
    /// the last frame as its input). Fails if GL reported an error.
    pub fn render(&mut self) -> Result<()> {
        self.target.bind();
        self.host.frame(true)?;
        // Nothing a frame asks for is headless rendering's to do (the title).
        while self.host.next_request().is_some() {}
        Ok(())
    }

    /// Renders `frames` frames (at least one) and returns the last, top row first. Fails if GL
    /// reported any error along the way.
    pub fn render_frames(&mut self, frames: u32) -> Result<image::RgbaImage> {
        for _ in 0..frames.max(1) {
            self.render()?;
        }
        // Every command of the frame complete, the fences among them signalled: reading the
        // target back only waits for the target, so the compare view's numbers of this frame,
        // behind their own fence, could still be pending when the status is read after it (seen:
        // compare_view's status without them, in the debug profile under load).
        // SAFETY: waits for the current context's queued work.
        unsafe { self.host.gl().gl.finish() };
        let image = self.target.read_rgba();
        self.check_errors()?;
        Ok(image)
    }

    /// Drains GL's error flags: an error is a bug in this program, so it is reported, not ignored.
    pub fn check_errors(&self) -> Result<()> {
        check_gl_errors(&self.host.gl().gl, "frame")
    }

    /// Milliseconds per frame for `frames` frames, each timed to completion (`glFinish`).
    pub fn bench(&mut self, frames: u32) -> Result<Vec<f64>> {
        let gl = self.host.gl().gl.clone();
        let mut times = Vec::with_capacity(frames as usize);
        for _ in 0..frames {
            let start = Instant::now();
            self.render()?;
            // SAFETY: waits for the current context's queued work.
            unsafe { gl.finish() };
            times.push(start.elapsed().as_secs_f64() * 1000.0);
        }
        self.check_errors()?;
        Ok(times)
    }
}
