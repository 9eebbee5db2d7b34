//! Rendering without a window: an EGL context on Mesa, an offscreen framebuffer, the same frame as the
//! window's. Used by `--headless`, `--bench` and the tests.

use std::time::Instant;

use glow::HasContext;

use crate::context::{format_errors, gl_errors, HeadlessContext, OffscreenTarget, Profile};
use crate::controls::{Controls, Input};
use crate::tutorial13::{SceneOptions, Tutorial13};
use crate::{Error, Result};

/// What to render headless.
#[derive(Debug, Clone)]
pub struct HeadlessOptions {
    pub scene: SceneOptions,
    pub width: u32,
    pub height: u32,
    pub profile: Profile,
    /// Use a GPU's EGL device where there is one; otherwise llvmpipe.
    pub prefer_hardware: bool,
}

/// A ready-to-draw headless set-up: context, target, scene, camera at the tutorial's start.
pub struct HeadlessRenderer {
    // Field order is drop order: GL objects go before the context that owns them.
    pub tutorial: Tutorial13,
    pub target: OffscreenTarget,
    pub controls: Controls,
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
            options.width,
            options.height,
            context.info(),
            |name| context.get_proc_address(name),
        )?;
        let tutorial = Tutorial13::new(
            &gl,
            context.info(),
            |name| context.get_proc_address(name),
            &options.scene,
        )?;
        Ok(HeadlessRenderer {
            tutorial,
            target,
            controls: Controls::default(),
            context,
        })
    }

    /// One frame with time frozen at 0 and no input, as the original's screenshot test.
    pub fn render(&mut self) {
        self.controls
            .compute_matrices_from_inputs(&Input::default(), 0.0);
        self.target.bind();
        self.tutorial.render(self.context.gl(), &self.controls);
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
        let errors = gl_errors(self.context.gl());
        if errors.is_empty() {
            Ok(())
        } else {
            Err(Error::Gl(format!("GL reported {}", format_errors(&errors))))
        }
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

/// (min, median) of a list of timings.
pub fn min_median(times: &[f64]) -> (f64, f64) {
    let mut sorted = times.to_vec();
    sorted.sort_by(f64::total_cmp);
    let min = sorted.first().copied().unwrap_or(f64::NAN);
    let median = sorted.get(sorted.len() / 2).copied().unwrap_or(f64::NAN);
    (min, median)
}
