//! The compare view: one frame drawn twice, by two ways of doing the same thing (two tangent
//! sources), shown side by side on either side of a split line, or as a heat map of their per-pixel
//! difference with the largest difference reported. Given two drawing closures; it never reaches
//! into the scene that supplies them.
//!
//! Each side is drawn whole into a target of its own, stored like the window's buffers (so that a
//! side is exactly the frame its source draws alone), then the columns left of the split are copied
//! from the first and the rest from the second. The heat map is drawn by the GPU from the two
//! sides' textures (`HeatPasses`, below): no frame comes back to the CPU, and the two numbers it
//! reports (pixels that differ, the largest difference) are read a frame later, without waiting.

use std::cell::{Cell, RefCell};

use glow::HasContext;

use crate::common::shader::load_program;
use crate::gl::extensions::GlExtensions;
use crate::gl::objects::Owned;
use crate::gl::offscreen::{nearest_texels, ColorBuffer, OffscreenTarget};
use crate::gl::Gl;
use crate::{Error, Result};

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

/// Where the split line starts, as a fraction of the width: the middle (`--split`'s default, and
/// the panel's "tutorial's values").
pub const SPLIT_START: f32 = 0.5;

pub struct CompareView {
    gl: Gl,
    /// To store the targets like a window.
    extensions: GlExtensions,
    /// The two sides, at the size of the last frame (textures, which the heat map samples).
    targets: Option<[OffscreenTarget; 2]>,
    /// Made the first time the difference is shown.
    heat: Option<HeatPasses>,
    pub mode: CompareMode,
    /// Where the split is, as a fraction of the width from the left.
    pub split: f32,
    /// The last difference read back ([`CompareView::difference`]).
    measured: Cell<Option<Difference>>,
    /// The last one [`CompareView::new_difference`] gave.
    announced: Option<Difference>,
}

impl CompareView {
    pub fn new(gl: &Gl, extensions: &GlExtensions, mode: CompareMode, split: f32) -> Self {
        CompareView {
            gl: gl.clone(),
            extensions: extensions.clone(),
            targets: None,
            heat: None,
            mode,
            split: split.clamp(0.0, 1.0),
            measured: Cell::new(None),
            announced: None,
        }
    }

    /// The difference of the latest heat map whose numbers have come back from the GPU (in the
    /// difference mode; `None` before the first). Asking never waits: a window shows the frame
    /// before's until the GPU is done with the last, and a frame read back (headless, a screenshot)
    /// has waited for its own.
    pub fn difference(&self) -> Option<Difference> {
        if self.mode != CompareMode::Difference {
            return None;
        }
        if let Some(d) = self.heat.as_ref().and_then(HeatPasses::poll) {
            self.measured.set(Some(d));
        }
        self.measured.get()
    }

    /// [`CompareView::difference`] when it is not the one this gave last (for the log).
    pub fn new_difference(&mut self) -> Option<Difference> {
        let difference = self.difference();
        if difference == self.announced {
            return None;
        }
        self.announced = difference;
        difference
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
        let targets = self.targets.as_ref().expect("made above");
        match self.mode {
            CompareMode::Split => {
                let column = self.split_column(size.0);
                targets[0].blit_columns_to(destination, 0, column);
                targets[1].blit_columns_to(destination, column, size.0);
                self.measured.set(None);
                // The split line, one white column (not where it would hide a whole side).
                if column > 0 && column < size.0 {
                    draw_column(&gl, column, size.1);
                }
            }
            CompareMode::Difference => {
                if self.heat.is_none() {
                    self.heat = Some(HeatPasses::new(&gl)?);
                }
                let heat = self.heat.as_mut().expect("made above");
                heat.draw(targets, destination, size)?;
            }
        }
        Ok(())
    }

    fn targets_for(&mut self, (width, height): (u32, u32)) -> Result<&[OffscreenTarget; 2]> {
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
            self.targets = Some([make(ColorBuffer::Texture)?, make(ColorBuffer::Texture)?]);
        }
        Ok(self.targets.as_ref().expect("made above"))
    }
}

/// A one-pixel white column at `x` of the bound framebuffer, `height` tall.
fn draw_column(gl: &Gl, x: u32, height: u32) {
    // SAFETY: state changes on the current context. The clear colour is not read back and restored
    // (a query each frame): the host sets the scene's before the next frame.
    unsafe {
        gl.enable(glow::SCISSOR_TEST);
        gl.scissor(x as i32, 0, 1, height as i32);
        gl.clear_color(1.0, 1.0, 1.0, 1.0);
        gl.clear(glow::COLOR_BUFFER_BIT);
        gl.disable(glow::SCISSOR_TEST);
    }
}

/// Black for 0; otherwise a ramp through red and yellow to white, relative to `max`, starting at a
/// visible dark red so that a difference of one level still shows.
pub fn heat_colour(d: u8, max: u8) -> [u8; 4] {
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

/// The largest difference of one channel of two pixels, in levels: red, green and blue (alpha is
/// not shown).
pub fn pixel_difference(a: &image::Rgba<u8>, b: &image::Rgba<u8>) -> u8 {
    (0..3).map(|c| a[c].abs_diff(b[c])).max().unwrap_or(0)
}

/// The heat map of two frames of the same size on the CPU, in [`heat_colour`]'s colours: each
/// `block` × `block` square of pixels becomes one pixel coloured by its largest difference of one
/// channel (red, green, blue) against `max`, so that a map shrunk to fit a pane still shows a
/// single differing pixel. For frames that are already read back (the exercises' check); the
/// compare view draws its own on the GPU.
pub fn heat_map(
    a: &image::RgbaImage,
    b: &image::RgbaImage,
    max: u8,
    block: u32,
) -> image::RgbaImage {
    let block = block.max(1);
    let (width, height) = a.dimensions();
    let mut largest = vec![0u8; (width.div_ceil(block) * height.div_ceil(block)) as usize];
    let columns = width.div_ceil(block);
    for (x, y, pa) in a.enumerate_pixels() {
        let Some(pb) = b.get_pixel_checked(x, y) else {
            continue;
        };
        let d = pixel_difference(pa, pb);
        let cell = &mut largest[((y / block) * columns + x / block) as usize];
        *cell = (*cell).max(d);
    }
    image::RgbaImage::from_fn(columns, height.div_ceil(block), |x, y| {
        image::Rgba(heat_colour(largest[(y * columns + x) as usize], max))
    })
}

/// The heat map's passes, all on the GPU: a reduction by 4 × 4 blocks, from the two sides down to
/// one texel holding the largest difference and the count of differing pixels (`CompareReduce`),
/// then each pixel's colour from a ramp indexed by its difference and the largest
/// (`CompareHeat`), drawn only over the 16 × 16 blocks where a pixel differs
/// (`CompareHeatBlocks`) into a frame cleared to the colour of no difference. The counts are integers in RG32UI textures, renderable in GL 3.3 and WebGL2
/// alike; the ramp is [`heat_colour`]'s table, so the picture is the same byte for byte on every
/// GPU.
struct HeatPasses {
    gl: Gl,
    reduce: ReduceProgram,
    heat: HeatProgram,
    /// Bound while drawing the passes' one triangle (a core context draws nothing without one).
    vao: Owned<glow::VertexArray>,
    ramp: Owned<glow::Texture>,
    /// Each level a quarter of the one before, from a quarter of the frame down to 1 × 1.
    levels: Vec<OffscreenTarget>,
    /// The frame size `levels` are for.
    frame_size: (u32, u32),
    /// The 1 × 1 level's texel, read into this buffer at the end of each frame.
    readback: Owned<glow::Buffer>,
    /// Signalled once the GPU has written `readback`.
    pending: RefCell<Option<glow::Fence>>,
}

crate::uniforms! {
    /// `CompareView.vertexshader` + `CompareReduce.fragmentshader`.
    struct ReduceProgram for Program {
        first: "First",
        second: "Second",
        flip_rows: "FlipRows",
        level: "Level",
        from_sides: "FromSides",
    }
}

crate::uniforms! {
    /// `CompareHeatBlocks.vertexshader` + `CompareHeat.fragmentshader`.
    struct HeatProgram for Program {
        first: "First",
        second: "Second",
        flip_rows: "FlipRows",
        largest: "Largest",
        ramp: "Ramp",
        level: "Level",
        block_size: "BlockSize",
        frame_size: "FrameSize",
    }
}

/// The passes' shader files (the crate's own; a `--shaders` folder does not replace them).
pub const COMPARE_SHADERS: [&str; 4] = [
    "CompareView.vertexshader",
    "CompareReduce.fragmentshader",
    "CompareHeatBlocks.vertexshader",
    "CompareHeat.fragmentshader",
];

const PART: &str = "compare view";

impl HeatPasses {
    fn new(gl: &Gl) -> Result<Self> {
        let [vertex, reduce, blocks, heat] = COMPARE_SHADERS;
        let ramp: Vec<u8> = (0..=255u8)
            .flat_map(|largest| (0..=255u8).flat_map(move |d| heat_colour(d, largest)))
            .collect();
        let passes = HeatPasses {
            gl: gl.clone(),
            reduce: ReduceProgram::new(load_program(gl, vertex, reduce, None)?)?,
            heat: HeatProgram::new(load_program(gl, blocks, heat, None)?)?,
            vao: Owned::create(gl, PART)?,
            ramp: Owned::create(gl, PART)?,
            levels: Vec::new(),
            frame_size: (0, 0),
            readback: Owned::create(gl, PART)?,
            pending: RefCell::new(None),
        };
        // SAFETY: storage for objects `passes` owns, on the current context; bindings restored.
        unsafe {
            let previous = crate::gl::bound_texture(gl, glow::TEXTURE_BINDING_2D);
            gl.bind_texture(glow::TEXTURE_2D, Some(passes.ramp.name()));
            gl.pixel_store_i32(glow::UNPACK_ALIGNMENT, 1);
            let data = glow::PixelUnpackData::Slice(Some(&ramp));
            let (rgba, byte) = (glow::RGBA, glow::UNSIGNED_BYTE);
            gl.tex_image_2d(
                glow::TEXTURE_2D,
                0,
                glow::RGBA8 as i32,
                256,
                256,
                0,
                rgba,
                byte,
                data,
            );
            gl.pixel_store_i32(glow::UNPACK_ALIGNMENT, 4);
            nearest_texels(gl);
            gl.bind_texture(glow::TEXTURE_2D, previous);
            let previous = crate::gl::bound_buffer(gl, glow::PIXEL_PACK_BUFFER_BINDING);
            gl.bind_buffer(glow::PIXEL_PACK_BUFFER, Some(passes.readback.name()));
            gl.buffer_data_size(glow::PIXEL_PACK_BUFFER, 16, glow::STREAM_READ);
            gl.bind_buffer(glow::PIXEL_PACK_BUFFER, previous);
        }
        crate::gl::check_gl_errors(gl, PART)?;
        Ok(passes)
    }

    /// The heat map of `sides` into `destination` (its viewport `size`), and the read of its
    /// numbers started.
    fn draw(
        &mut self,
        sides: &[OffscreenTarget; 2],
        destination: Option<glow::Framebuffer>,
        size: (u32, u32),
    ) -> Result<()> {
        if self.frame_size != size {
            self.levels = level_sizes(size)
                .into_iter()
                .map(|(w, h)| OffscreenTarget::with_color(&self.gl, w, h, ColorBuffer::UintPairs))
                .collect::<Result<_>>()?;
            self.frame_size = size;
        }
        let gl = self.gl.clone();
        let textures = sides.each_ref().map(|side| side.texture());
        let [Some(first), Some(second)] = textures else {
            return Err(Error::gl(PART, "a side has no texture to sample"));
        };
        // SAFETY: draws on the current context with objects this value and `sides` own. The tests
        // turned off here are set again by the host before the next frame (the scene's
        // `GL_STATE`); program, vertex array and texture units are left as the panel leaves them.
        unsafe {
            gl.disable(glow::DEPTH_TEST);
            gl.disable(glow::BLEND);
            gl.disable(glow::CULL_FACE);
            gl.disable(glow::SCISSOR_TEST);
            gl.bind_vertex_array(Some(self.vao.name()));

            let flipped = i32::from(sides[0].flipped_y());
            self.reduce_levels(&gl, [first, second], flipped);
            let largest = self.levels.last().and_then(OffscreenTarget::texture);
            self.start_read(&gl)?;
            self.draw_heat(&gl, [first, second], flipped, largest, (destination, size));
            gl.bind_vertex_array(None);
            gl.use_program(None);
            gl.active_texture(glow::TEXTURE0);
        }
        crate::gl::check_gl_errors(&gl, PART)
    }

    /// The sides' differences summed level by level into `self.levels`, each from the one below
    /// (the first from the sides, `flipped` if stored top row first).
    ///
    /// # Safety
    /// A current context with the passes' vertex array bound.
    unsafe fn reduce_levels(&self, gl: &Gl, [first, second]: [glow::Texture; 2], flipped: i32) {
        gl.use_program(Some(self.reduce.program.id));
        bind_unit(gl, 0, Some(first), self.reduce.first.as_ref());
        bind_unit(gl, 1, Some(second), self.reduce.second.as_ref());
        gl.uniform_1_i32(self.reduce.flip_rows.as_ref(), flipped);
        // Unit 2 holds the level below; nothing for the first pass, which reads the sides (a
        // texture of the target drawn into may not be bound, in WebGL).
        let mut below = None;
        for level in &self.levels {
            level.bind();
            bind_unit(gl, 2, below, self.reduce.level.as_ref());
            let from_sides = i32::from(below.is_none());
            gl.uniform_1_i32(self.reduce.from_sides.as_ref(), from_sides);
            gl.draw_arrays(glow::TRIANGLES, 0, 3);
            below = level.texture();
        }
    }

    /// The largest level's numbers copied into the read-back buffer, behind a fence that
    /// [`HeatPasses::poll`] waits for.
    ///
    /// # Safety
    /// A current context, the largest level drawn.
    unsafe fn start_read(&self, gl: &Gl) -> Result<()> {
        // The numbers, into the read-back buffer: the GPU copies them when it gets there.
        gl.bind_buffer(glow::PIXEL_PACK_BUFFER, Some(self.readback.name()));
        let (format, kind) = (glow::RGBA_INTEGER, glow::UNSIGNED_INT);
        gl.read_pixels(
            0,
            0,
            1,
            1,
            format,
            kind,
            glow::PixelPackData::BufferOffset(0),
        );
        gl.bind_buffer(glow::PIXEL_PACK_BUFFER, None);
        let fence = gl
            .fence_sync(glow::SYNC_GPU_COMMANDS_COMPLETE, 0)
            .map_err(|e| Error::gl(PART, e))?;
        if let Some(old) = self.pending.replace(Some(fence)) {
            gl.delete_sync(old);
        }
        Ok(())
    }

    /// The heat map of the sides (`largest`: the largest level's texture) drawn into
    /// `destination`, its viewport `size`: cleared to black (the ramp's colour of no difference),
    /// then coloured only in the blocks where a pixel differs (a reduction level's texels with a
    /// count above 0), which on a software rasterizer saves most of a full-frame pass (the object
    /// covers a fifth of the tutorial's frame).
    ///
    /// # Safety
    /// A current context with the passes' vertex array bound.
    unsafe fn draw_heat(
        &self,
        gl: &Gl,
        [first, second]: [glow::Texture; 2],
        flipped: i32,
        largest: Option<glow::Texture>,
        (destination, size): (Option<glow::Framebuffer>, (u32, u32)),
    ) {
        gl.bind_framebuffer(glow::FRAMEBUFFER, destination);
        gl.viewport(0, 0, size.0 as i32, size.1 as i32);
        // The clear colour, like the tests below, is the host's to set again before the next frame.
        let [r, g, b, a] = heat_colour(0, 0).map(|c| f32::from(c) / 255.0);
        gl.clear_color(r, g, b, a);
        gl.clear(glow::COLOR_BUFFER_BIT);
        // Blocks of 16 × 16 pixels (the second level), or the first level's 4 × 4 in a frame
        // too small to have two.
        let (level, block_size) = match self.levels.get(1) {
            Some(level) => (level, 16),
            None => (&self.levels[0], 4),
        };
        gl.use_program(Some(self.heat.program.id));
        bind_unit(gl, 0, Some(first), self.heat.first.as_ref());
        bind_unit(gl, 1, Some(second), self.heat.second.as_ref());
        gl.uniform_1_i32(self.heat.flip_rows.as_ref(), flipped);
        bind_unit(gl, 2, largest, self.heat.largest.as_ref());
        bind_unit(gl, 3, Some(self.ramp.name()), self.heat.ramp.as_ref());
        bind_unit(gl, 4, level.texture(), self.heat.level.as_ref());
        gl.uniform_1_i32(self.heat.block_size.as_ref(), block_size);
        let frame_size = self.heat.frame_size.as_ref();
        gl.uniform_2_i32(frame_size, size.0 as i32, size.1 as i32);
        let blocks = (level.width() * level.height()) as i32;
        gl.draw_arrays_instanced(glow::TRIANGLES, 0, 6, blocks);
    }

    /// The numbers of the last heat map, if the GPU has written them (never waits).
    fn poll(&self) -> Option<Difference> {
        let gl = &self.gl;
        let fence = (*self.pending.borrow())?;
        // SAFETY: a fence and a buffer this value owns, on the current context.
        unsafe {
            let status = gl.client_wait_sync(fence, 0, 0);
            if status != glow::ALREADY_SIGNALED && status != glow::CONDITION_SATISFIED {
                return None;
            }
            gl.delete_sync(fence);
            self.pending.replace(None);
            let mut bytes = [0u8; 16];
            let previous = crate::gl::bound_buffer(gl, glow::PIXEL_PACK_BUFFER_BINDING);
            gl.bind_buffer(glow::PIXEL_PACK_BUFFER, Some(self.readback.name()));
            gl.get_buffer_sub_data(glow::PIXEL_PACK_BUFFER, 0, &mut bytes);
            gl.bind_buffer(glow::PIXEL_PACK_BUFFER, previous);
            let word = |i: usize| u32::from_ne_bytes(bytes[4 * i..4 * i + 4].try_into().unwrap());
            Some(Difference {
                max: u8::try_from(word(0)).unwrap_or(u8::MAX),
                pixels: word(1) as usize,
            })
        }
    }
}

impl Drop for HeatPasses {
    fn drop(&mut self) {
        if let Some(fence) = self.pending.get_mut().take() {
            // SAFETY: a fence of this context, deleted once.
            unsafe { self.gl.delete_sync(fence) };
        }
    }
}

/// The sizes of the reduction's levels: each a quarter of the one before (rounded up), from the
/// frame's down to 1 × 1.
fn level_sizes((mut width, mut height): (u32, u32)) -> Vec<(u32, u32)> {
    let mut sizes = Vec::new();
    while sizes.is_empty() || (width, height) != (1, 1) {
        (width, height) = (width.div_ceil(4), height.div_ceil(4));
        sizes.push((width, height));
    }
    sizes
}

/// `texture` on unit `unit`, and the sampler uniform set to it.
///
/// # Safety
/// A current context with the program of `sampler` in use.
unsafe fn bind_unit(
    gl: &Gl,
    unit: u32,
    texture: Option<glow::Texture>,
    sampler: Option<&glow::UniformLocation>,
) {
    gl.active_texture(glow::TEXTURE0 + unit);
    gl.bind_texture(glow::TEXTURE_2D, texture);
    gl.uniform_1_i32(sampler, unit as i32);
}
