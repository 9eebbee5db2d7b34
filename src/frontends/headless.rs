//! Rendering without a window: an EGL context on Mesa, an offscreen framebuffer, any scene's frame
//! exactly as the window draws it. Used by `--headless`, `--bench` and the tests.

use std::time::Instant;

use glam::Vec2;
use glow::HasContext;

use super::panel::{Panel, PanelInfo};
use crate::common::controls::{Controls, Input};
use crate::gl::context::HeadlessContext;
use crate::gl::offscreen::OffscreenTarget;
use crate::gl::{check_gl_errors, Profile};
use crate::scenes::{FrameInput, Scene, SceneContext, SceneDescriptor, SceneOptions};
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

/// A ready-to-draw headless set-up: context, target, scene, camera at the tutorial's start.
pub struct HeadlessRenderer {
    // Field order is drop order: GL objects go before the context that owns them.
    pub scene: Box<dyn Scene>,
    /// Which scene [`HeadlessRenderer::scene`] is.
    pub descriptor: &'static SceneDescriptor,
    scene_options: SceneOptions,
    pub target: OffscreenTarget,
    pub controls: Controls,
    /// Where a window's cursor would be (x right, y down, pixels), for scenes that follow it.
    pub cursor: Option<Vec2>,
    /// The window's panel, drawn over every frame (`--panel`), and the input it gets next frame.
    pub panel: Option<Panel>,
    pub panel_events: Vec<egui::Event>,
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
            context.info(),
            |name| context.get_proc_address(name),
        )?;
        let scene = build_scene(&context, options.descriptor, &options.scene)?;
        let controls = scene.start_controls(options.width, options.height);
        Ok(HeadlessRenderer {
            scene,
            descriptor: options.descriptor,
            scene_options: options.scene.clone(),
            target,
            controls,
            cursor: None,
            panel: None,
            panel_events: Vec::new(),
            context,
        })
    }

    /// Replaces the scene with `name`, built from the same options (the window's scene key). The new
    /// scene is built first, so a failure leaves the current one in place; the old one's GL objects
    /// are deleted when it is dropped.
    pub fn switch_scene(&mut self, name: &'static SceneDescriptor) -> Result<()> {
        self.scene = build_scene(&self.context, name, &self.scene_options)?;
        self.descriptor = name;
        Ok(())
    }

    /// What the window does with a dropped file ([`crate::scenes::open_file`]): the scene that opens
    /// it, built with it, and the camera at that scene's start. On an error the current scene stays.
    pub fn open_file(&mut self, path: &std::path::Path) -> Result<()> {
        let mut options = self.scene_options.clone();
        let next = crate::scenes::open_file(path, &mut options)?;
        self.scene = build_scene(&self.context, next, &options)?;
        self.scene_options = options;
        self.descriptor = next;
        let (width, height) = (self.target.width(), self.target.height());
        self.controls = self.scene.start_controls(width, height);
        Ok(())
    }

    /// Reads the scene's shader files again (what the window does when one is saved): on an error the
    /// scene keeps drawing with the programs it had.
    pub fn reload_shaders(&mut self) -> Result<()> {
        self.scene.reload_shaders()
    }

    /// The scene as its own type, for tests and tools that reach into it. Panics if the renderer
    /// holds another scene.
    pub fn scene_mut<S: Scene + 'static>(&mut self) -> &mut S {
        // `*self.scene`: the scene in the box (the box itself is `Any` too).
        (*self.scene)
            .as_any_mut()
            .downcast_mut()
            .expect("the renderer holds another scene")
    }

    /// [`HeadlessRenderer::scene_mut`], shared.
    pub fn scene_ref<S: Scene + 'static>(&self) -> &S {
        (*self.scene)
            .as_any()
            .downcast_ref()
            .expect("the renderer holds another scene")
    }

    /// What the scene is given this frame: the camera, the target's size, time frozen at 0.
    pub fn frame_input(&self) -> FrameInput {
        FrameInput {
            projection: self.controls.projection_matrix(),
            view: self.controls.view_matrix(),
            cursor: self.cursor,
            size: (self.target.width(), self.target.height()),
            time: 0.0,
        }
    }

    /// Draws the window's panel over every frame from now on (`--panel`).
    pub fn show_panel(&mut self) -> Result<()> {
        if self.panel.is_none() {
            let context = &self.context;
            let loader = |name: &std::ffi::CStr| context.get_proc_address(name);
            self.panel = Some(Panel::new(context.gl(), context.info(), &loader)?);
        }
        Ok(())
    }

    /// One frame with time frozen at 0 and no input, as the original's screenshot test; the panel
    /// over it if it is shown (with [`HeadlessRenderer::panel_events`] as its input).
    pub fn render(&mut self) {
        self.controls
            .compute_matrices_from_inputs(&Input::default(), 0.0);
        self.target.bind();
        let input = self.frame_input();
        self.scene.draw(&input);
        if let Some(panel) = &mut self.panel {
            let mut panel_input = Panel::headless_input(input.size);
            panel_input.events = std::mem::take(&mut self.panel_events);
            let (output, _) = panel.run(
                panel_input,
                self.descriptor,
                &mut *self.scene,
                PanelInfo::default(),
            );
            // The scene's viewport (the target's size) is the panel's too.
            self.target.bind();
            panel.paint(input.size, output);
        }
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

fn build_scene(
    context: &HeadlessContext,
    name: &'static SceneDescriptor,
    options: &SceneOptions,
) -> Result<Box<dyn Scene>> {
    let loader = |symbol: &std::ffi::CStr| context.get_proc_address(symbol);
    let scene_context = SceneContext {
        gl: context.gl(),
        info: context.info(),
        loader: &loader,
    };
    (name.build)(&scene_context, options)
}
