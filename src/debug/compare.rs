//! The compare view: one frame drawn twice, by two ways of doing the same thing (two tangent
//! sources), shown side by side on either side of a split line, or as a heat map of their per-pixel
//! difference with the largest difference reported. Given two drawing closures; it never reaches
//! into the scene that supplies them.
//!
//! Each side is drawn whole into a target of its own, stored like the window's buffers (so that a
//! side is exactly the frame its source draws alone), then the columns left of the split are copied
//! from the first and the rest from the second. The heat map is computed on the CPU from the two
//! frames read back, which also gives the exact largest difference.

use glow::HasContext;

use crate::gl::extensions::GlExtensions;
use crate::gl::offscreen::{ColorBuffer, OffscreenTarget};
use crate::gl::Gl;
use crate::Result;

/// Split (side by side) or the difference as a heat map.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum CompareMode {
    #[default]
    Split,
    Difference,
}

/// What the last compared frame showed.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Difference {
    /// Pixels whose colour differs between the two sides.
    pub pixels: usize,
    /// The largest difference of one channel, in levels (0..255).
    pub max: u8,
}

pub struct CompareView {
    gl: Gl,
    /// To store the targets like a window.
    extensions: GlExtensions,
    /// The two sides, and the heat map, at the size of the last frame.
    targets: Option<[OffscreenTarget; 3]>,
    pub mode: CompareMode,
    /// Where the split is, as a fraction of the width from the left.
    pub split: f32,
    /// Measured in the last frame in [`CompareMode::Difference`].
    pub difference: Option<Difference>,
}

impl CompareView {
    pub fn new(gl: &Gl, extensions: &GlExtensions, mode: CompareMode, split: f32) -> Self {
        CompareView {
            gl: gl.clone(),
            extensions: extensions.clone(),
            targets: None,
            mode,
            split: split.clamp(0.0, 1.0),
            difference: None,
        }
    }

    /// The column where the second side starts, for a frame `width` wide.
    pub fn split_column(&self, width: u32) -> u32 {
        (self.split * width as f32).round() as u32
    }

    /// Draws `first` and `second` into their own targets and shows them, into the framebuffer that
    /// was bound (whose viewport is `size`).
    pub fn draw(
        &mut self,
        size: (u32, u32),
        first: impl FnOnce(),
        second: impl FnOnce(),
    ) -> Result<()> {
        let gl = self.gl.clone();
        // SAFETY: a binding query on the current context.
        let destination =
            unsafe { crate::gl::bound_framebuffer(&gl, glow::DRAW_FRAMEBUFFER_BINDING) };
        let targets = self.targets_for(size)?;
        targets[0].bind();
        first();
        targets[1].bind();
        second();
        // SAFETY: rebinding the front end's framebuffer and its viewport.
        unsafe {
            gl.bind_framebuffer(glow::FRAMEBUFFER, destination);
            gl.viewport(0, 0, size.0 as i32, size.1 as i32);
        }
        match self.mode {
            CompareMode::Split => {
                let targets = self.targets.as_ref().expect("made above");
                let column = self.split_column(size.0);
                targets[0].blit_columns_to(destination, 0, column);
                targets[1].blit_columns_to(destination, column, size.0);
                self.difference = None;
                // The split line, one white column (not where it would hide a whole side).
                if column > 0 && column < size.0 {
                    draw_column(&gl, column, size.1);
                }
            }
            CompareMode::Difference => {
                let targets = self.targets.as_ref().expect("made above");
                let (a, b) = (targets[0].read_rgba(), targets[1].read_rgba());
                let (heat, difference) = heat_map(&a, &b);
                targets[2].upload_rgba(&heat);
                targets[2].blit_columns_to(destination, 0, size.0);
                self.difference = Some(difference);
            }
        }
        Ok(())
    }

    fn targets_for(&mut self, (width, height): (u32, u32)) -> Result<&[OffscreenTarget; 3]> {
        let fits = self
            .targets
            .as_ref()
            .is_some_and(|t| (t[0].width(), t[0].height()) == (width, height));
        if !fits {
            let make = |color| -> Result<OffscreenTarget> {
                let mut target = OffscreenTarget::with_color(&self.gl, width, height, color)?;
                target.set_window_orientation(&self.extensions)?;
                Ok(target)
            };
            self.targets = Some([
                make(ColorBuffer::Renderbuffer)?,
                make(ColorBuffer::Renderbuffer)?,
                make(ColorBuffer::Texture)?,
            ]);
        }
        Ok(self.targets.as_ref().expect("made above"))
    }
}

/// A one-pixel white column at `x` of the bound framebuffer, `height` tall.
fn draw_column(gl: &Gl, x: u32, height: u32) {
    // SAFETY: state changes on the current context, each restored.
    unsafe {
        let mut clear = [0.0f32; 4];
        gl.get_parameter_f32_slice(glow::COLOR_CLEAR_VALUE, &mut clear);
        gl.enable(glow::SCISSOR_TEST);
        gl.scissor(x as i32, 0, 1, height as i32);
        gl.clear_color(1.0, 1.0, 1.0, 1.0);
        gl.clear(glow::COLOR_BUFFER_BIT);
        gl.clear_color(clear[0], clear[1], clear[2], clear[3]);
        gl.disable(glow::SCISSOR_TEST);
    }
}

/// The per-pixel difference of two frames of the same size as a heat map (black where equal, then
/// dark red, orange, yellow, white at the largest difference), and how large it is.
pub fn heat_map(a: &image::RgbaImage, b: &image::RgbaImage) -> (image::RgbaImage, Difference) {
    assert_eq!(a.dimensions(), b.dimensions(), "frames of different sizes");
    let deltas: Vec<u8> = a
        .pixels()
        .zip(b.pixels())
        .map(|(p, q)| (0..3).map(|c| p[c].abs_diff(q[c])).max().unwrap_or(0))
        .collect();
    let max = deltas.iter().copied().max().unwrap_or(0);
    let pixels = deltas.iter().filter(|&&d| d > 0).count();
    let heat = image::RgbaImage::from_fn(a.width(), a.height(), |x, y| {
        let d = deltas[(y * a.width() + x) as usize];
        image::Rgba(heat_colour(d, max))
    });
    (heat, Difference { pixels, max })
}

/// Black for 0; otherwise a ramp through red and yellow to white, relative to `max`, starting at a
/// visible dark red so that a difference of one level still shows.
fn heat_colour(d: u8, max: u8) -> [u8; 4] {
    if d == 0 {
        return [0, 0, 0, 255];
    }
    let t = d as f32 / max.max(1) as f32;
    let ramp = |from: f32, to: f32| (((t - from) / (to - from)).clamp(0.0, 1.0) * 255.0) as u8;
    [
        ramp(-0.5, 0.34).max(96),
        ramp(0.34, 0.67),
        ramp(0.67, 1.0),
        255,
    ]
}
