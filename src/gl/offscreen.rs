//! Offscreen framebuffers to render into and read back: where headless frames go (the surfaceless
//! context has no default framebuffer), and the window's compare view and screenshots.

use std::fmt;

use glow::HasContext;

use super::extensions::{GlExtensions, FLIP_Y_EXTENSION};
use super::image::read_pixels_rgba;
use super::objects::Owned;
use super::{check_gl_errors, Gl};
use crate::{Error, Result};

/// Where an [`OffscreenTarget`]'s colour goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ColorBuffer {
    /// A renderbuffer: only read back (headless frames, screenshots).
    Renderbuffer,
    /// A texture a later pass can sample (e.g. one half of a comparison view).
    Texture,
    /// A texture stored blue, green, red, alpha in memory, as X11 and Wayland keep a window's
    /// buffers on little-endian machines: Mesa blits from it into a window with a plain memory
    /// copy, where a blit from RGBA into one is a draw (on llvmpipe about 1 ms for the panel's
    /// columns of a 1024×768 window).
    WindowOrderTexture,
    /// A texture of two 32-bit unsigned integers a texel (RG32UI), renderable in GL 3.3 and
    /// WebGL2 alike: counts a later pass adds up (the compare view's reduction).
    UintPairs,
}

#[derive(Debug)]
enum Color {
    Renderbuffer(Owned<glow::Renderbuffer>),
    Texture(Owned<glow::Texture>),
}

/// An offscreen framebuffer: 8-bit RGBA colour (a renderbuffer or a texture) and a 24-bit depth
/// renderbuffer of `width × height`.
///
/// This is where headless frames go (the surfaceless context has no default framebuffer). Drop it
/// before its context.
pub struct OffscreenTarget {
    gl: Gl,
    // Field order is drop order: the framebuffer before what is attached to it.
    framebuffer: Owned<glow::Framebuffer>,
    color: Color,
    depth: Owned<glow::Renderbuffer>,
    width: u32,
    height: u32,
    /// `GL_FRAMEBUFFER_FLIP_Y_MESA` is set: stored top row first, as Mesa stores a window.
    flipped_y: bool,
    /// Samples per pixel (0: not multisampled).
    samples: u32,
    /// A multisampled target's single-sampled twin: frames are resolved into it to be read.
    resolve: Option<Box<OffscreenTarget>>,
}

const PART: &str = "offscreen target";

/// `GL_MESA_framebuffer_flip_y`'s framebuffer parameter (glow has neither it nor the call that sets
/// it: [`GlExtensions`] holds the call).
const FRAMEBUFFER_FLIP_Y_MESA: u32 = 0x8BBB;

/// The missing extension is reported once per process, not once per target.
static FLIP_Y_MISSING_LOGGED: std::sync::Once = std::sync::Once::new();

impl OffscreenTarget {
    /// A target with a renderbuffer for colour. Checks that the driver accepts it as complete and
    /// leaves framebuffer 0 bound (call [`OffscreenTarget::bind`] to draw into it).
    pub fn new(gl: &Gl, width: u32, height: u32) -> Result<Self> {
        Self::with_color(gl, width, height, ColorBuffer::Renderbuffer)
    }

    /// A target whose colour is a renderbuffer or a texture.
    pub fn with_color(gl: &Gl, width: u32, height: u32, color: ColorBuffer) -> Result<Self> {
        Self::create(gl, width, height, color, 0)
    }

    /// A multisampled target (`samples` ≥ 1 per pixel, colour in a renderbuffer), as a window with a
    /// multisampled config has: [`OffscreenTarget::read_rgba`] resolves it first, as reading a
    /// window's multisampled buffer does. `samples` = 0 is [`OffscreenTarget::new`].
    pub fn multisampled(gl: &Gl, width: u32, height: u32, samples: u32) -> Result<Self> {
        if samples == 0 {
            return Self::new(gl, width, height);
        }
        // SAFETY: a plain query on the current context.
        let max = unsafe { gl.get_parameter_i32(glow::MAX_SAMPLES) }.max(0) as u32;
        if samples > max {
            return Err(Error::gl(
                PART,
                format!("{samples} samples per pixel asked, this driver allows at most {max}"),
            ));
        }
        let mut target = Self::create(gl, width, height, ColorBuffer::Renderbuffer, samples)?;
        target.resolve = Some(Box::new(Self::new(gl, width, height)?));
        Ok(target)
    }

    fn create(gl: &Gl, width: u32, height: u32, color: ColorBuffer, samples: u32) -> Result<Self> {
        // SAFETY: a plain query on the current context.
        let max = unsafe { gl.get_parameter_i32(glow::MAX_RENDERBUFFER_SIZE) }.max(0) as u32;
        if width == 0 || height == 0 || width > max || height > max {
            return Err(Error::gl(
                PART,
                format!("{width}×{height}: each side must be between 1 and {max}"),
            ));
        }
        // Sizes were checked against MAX_RENDERBUFFER_SIZE, so they fit in i32.
        let (w, h) = (width as i32, height as i32);
        // Each object is owned as soon as it exists, so a failure below deletes what was made.
        let target = OffscreenTarget {
            gl: Gl::clone(gl),
            framebuffer: Owned::create(gl, PART)?,
            depth: Owned::create(gl, PART)?,
            color: match color {
                ColorBuffer::Renderbuffer => Color::Renderbuffer(Owned::create(gl, PART)?),
                ColorBuffer::Texture | ColorBuffer::WindowOrderTexture | ColorBuffer::UintPairs => {
                    Color::Texture(Owned::create(gl, PART)?)
                }
            },
            width,
            height,
            flipped_y: false,
            samples,
            resolve: None,
        };
        let (framebuffer, depth) = (target.framebuffer.name(), target.depth.name());
        // SAFETY: storage, attachments and binds on the current context for objects `target` owns.
        unsafe {
            gl.bind_renderbuffer(glow::RENDERBUFFER, Some(depth));
            renderbuffer_storage(gl, samples, glow::DEPTH_COMPONENT24, (w, h));
            gl.bind_framebuffer(glow::FRAMEBUFFER, Some(framebuffer));
            attach_color(gl, &target.color, color, samples, (w, h));
            gl.bind_renderbuffer(glow::RENDERBUFFER, None);
            let point = glow::DEPTH_ATTACHMENT;
            gl.framebuffer_renderbuffer(glow::FRAMEBUFFER, point, glow::RENDERBUFFER, Some(depth));
            let status = gl.check_framebuffer_status(glow::FRAMEBUFFER);
            gl.bind_framebuffer(glow::FRAMEBUFFER, None);
            if status != glow::FRAMEBUFFER_COMPLETE {
                return Err(Error::gl(
                    PART,
                    format!(
                        "{width}×{height} is incomplete: {} (0x{status:04X})",
                        framebuffer_status_name(status)
                    ),
                ));
            }
            check_gl_errors(gl, PART)?;
            Ok(target)
        }
    }

    /// Like [`OffscreenTarget::multisampled`] (`samples` = 0: none), but stored y-flipped as Mesa stores a window's buffers, so that
    /// a frame drawn into it is the window's frame bit for bit.
    ///
    /// Mesa keeps window buffers top row first, and llvmpipe's rasterization rules (which pixel an
    /// edge or a line covers) follow that storage: a plain framebuffer object gets a few edge pixels
    /// and line pixels different from a window. `GL_MESA_framebuffer_flip_y` makes a framebuffer
    /// object stored like a window. Where the context lacks the extension this is a plain target
    /// (said once in the debug log), and [`OffscreenTarget::flipped_y`] is false.
    pub fn with_window_orientation(
        gl: &Gl,
        (width, height): (u32, u32),
        samples: u32,
        extensions: &GlExtensions,
    ) -> Result<Self> {
        let mut target = Self::multisampled(gl, width, height, samples)?;
        target.set_window_orientation(extensions)?;
        Ok(target)
    }

    /// Stores this target like a window (see [`OffscreenTarget::with_window_orientation`]); returns
    /// whether the extension was there to do it. A texture target flipped this way is also stored
    /// top row first, so a pass that samples it must flip its texture coordinates' v.
    pub fn set_window_orientation(&mut self, extensions: &GlExtensions) -> Result<bool> {
        let framebuffer_parameter_i = match &extensions.flip_y {
            Some(Ok(function)) => *function,
            Some(Err(reason)) => return Err(Error::gl(PART, reason.clone())),
            None => {
                FLIP_Y_MISSING_LOGGED.call_once(|| {
                    // The debug log, not a warning: on such a renderer every headless run would
                    // otherwise start with this line, and a one-line error would become two.
                    log::debug!(
                        "{} has no {FLIP_Y_EXTENSION}: headless frames may differ from a \
                         window's in a few edge pixels",
                        extensions.renderer
                    )
                });
                return Ok(false);
            }
        };
        // SAFETY: the framebuffer is alive (owned by self); the extension allows this parameter on
        // GL_FRAMEBUFFER; framebuffer 0 is bound again afterwards, as `new` leaves it.
        // A multisampled target's resolved twin is stored the same way, so the blit keeps rows in order.
        let resolve = self.resolve.as_ref().map(|r| r.framebuffer.name());
        for framebuffer in std::iter::once(self.framebuffer.name()).chain(resolve) {
            unsafe {
                self.gl
                    .bind_framebuffer(glow::FRAMEBUFFER, Some(framebuffer));
                framebuffer_parameter_i(glow::FRAMEBUFFER, FRAMEBUFFER_FLIP_Y_MESA, 1);
                self.gl.bind_framebuffer(glow::FRAMEBUFFER, None);
            }
        }
        self.flipped_y = true;
        if let Some(resolve) = &mut self.resolve {
            resolve.flipped_y = true;
        }
        check_gl_errors(&self.gl, "offscreen target (GL_FRAMEBUFFER_FLIP_Y_MESA)")?;
        Ok(true)
    }

    /// Whether the target is stored y-flipped like a window.
    pub fn flipped_y(&self) -> bool {
        self.flipped_y
    }

    /// Binds the framebuffer for drawing and reading, and sets the viewport to cover it.
    pub fn bind(&self) {
        // SAFETY: the framebuffer is alive (owned by self); sizes fit in i32 (checked in new).
        unsafe {
            self.gl
                .bind_framebuffer(glow::FRAMEBUFFER, Some(self.framebuffer.name()));
            self.gl
                .viewport(0, 0, self.width as i32, self.height as i32);
        }
    }

    /// The framebuffer, to blit from or into.
    pub fn framebuffer(&self) -> Option<glow::Framebuffer> {
        Some(self.framebuffer.name())
    }

    /// Samples per pixel (0: not multisampled).
    pub fn samples(&self) -> u32 {
        self.samples
    }

    /// The colour buffer, top row first (a multisampled target resolved: each pixel the mean of
    /// its samples). The read and draw bindings are restored afterwards.
    pub fn read_rgba(&self) -> image::RgbaImage {
        if let Some(resolve) = &self.resolve {
            resolve.blit_from(Some(self.framebuffer.name()));
            return resolve.read_rgba();
        }
        // SAFETY: binding queries and binds on the current context; the framebuffer is alive.
        unsafe {
            let previous = crate::gl::bound_framebuffer(&self.gl, glow::READ_FRAMEBUFFER_BINDING);
            self.gl
                .bind_framebuffer(glow::READ_FRAMEBUFFER, Some(self.framebuffer.name()));
            self.gl.read_buffer(glow::COLOR_ATTACHMENT0);
            let image = read_pixels_rgba(&self.gl, self.width, self.height);
            self.gl.bind_framebuffer(glow::READ_FRAMEBUFFER, previous);
            image
        }
    }

    /// Copies the colour of `framebuffer` (`None`: the window's) into this target, resolving its
    /// samples if it is multisampled. It must be this target's size. Bindings are restored.
    pub fn blit_from(&self, framebuffer: Option<glow::Framebuffer>) {
        let (w, h) = (self.width as i32, self.height as i32);
        // SAFETY: binding queries, binds and a blit on the current context; this target is alive.
        unsafe {
            let gl = &self.gl;
            let read = crate::gl::bound_framebuffer(gl, glow::READ_FRAMEBUFFER_BINDING);
            let draw = crate::gl::bound_framebuffer(gl, glow::DRAW_FRAMEBUFFER_BINDING);
            gl.bind_framebuffer(glow::READ_FRAMEBUFFER, framebuffer);
            gl.bind_framebuffer(glow::DRAW_FRAMEBUFFER, Some(self.framebuffer.name()));
            let (mask, filter) = (glow::COLOR_BUFFER_BIT, glow::NEAREST);
            gl.blit_framebuffer(0, 0, w, h, 0, 0, w, h, mask, filter);
            gl.bind_framebuffer(glow::READ_FRAMEBUFFER, read);
            gl.bind_framebuffer(glow::DRAW_FRAMEBUFFER, draw);
        }
    }

    /// Copies columns `x0..x1` of this target's colour into the same columns of `framebuffer`
    /// (`None`: the window's), which must be at least this target's size. Bindings are restored.
    pub fn blit_columns_to(&self, framebuffer: Option<glow::Framebuffer>, x0: u32, x1: u32) {
        let (x0, x1) = (x0.min(self.width) as i32, x1.min(self.width) as i32);
        let h = self.height as i32;
        // SAFETY: binding queries, binds and a blit on the current context; this target is alive.
        unsafe {
            let gl = &self.gl;
            let read = crate::gl::bound_framebuffer(gl, glow::READ_FRAMEBUFFER_BINDING);
            let draw = crate::gl::bound_framebuffer(gl, glow::DRAW_FRAMEBUFFER_BINDING);
            gl.bind_framebuffer(glow::READ_FRAMEBUFFER, Some(self.framebuffer.name()));
            gl.bind_framebuffer(glow::DRAW_FRAMEBUFFER, framebuffer);
            let (mask, filter) = (glow::COLOR_BUFFER_BIT, glow::NEAREST);
            gl.blit_framebuffer(x0, 0, x1, h, x0, 0, x1, h, mask, filter);
            gl.bind_framebuffer(glow::READ_FRAMEBUFFER, read);
            gl.bind_framebuffer(glow::DRAW_FRAMEBUFFER, draw);
        }
    }

    /// Replaces the colour of a texture-backed target with `image` (top row first, this target's
    /// size), stored the way the target is (see [`OffscreenTarget::flipped_y`]).
    pub fn upload_rgba(&self, image: &image::RgbaImage) {
        let Some(texture) = self.texture() else {
            return;
        };
        assert_eq!(
            image.dimensions(),
            (self.width, self.height),
            "image of another size"
        );
        // A plain target keeps GL's bottom row first; a window-oriented one keeps the top row first.
        let bytes: Vec<u8> = if self.flipped_y {
            image.as_raw().clone()
        } else {
            image
                .rows()
                .rev()
                .flat_map(|row| row.flat_map(|p| p.0))
                .collect()
        };
        let (w, h) = (self.width as i32, self.height as i32);
        // SAFETY: the texture is alive and of this size; the previous binding is restored.
        unsafe {
            let gl = &self.gl;
            let previous = crate::gl::bound_texture(gl, glow::TEXTURE_BINDING_2D);
            gl.bind_texture(glow::TEXTURE_2D, Some(texture));
            gl.pixel_store_i32(glow::UNPACK_ALIGNMENT, 1);
            let data = glow::PixelUnpackData::Slice(Some(&bytes));
            let (rgba, byte) = (glow::RGBA, glow::UNSIGNED_BYTE);
            gl.tex_sub_image_2d(glow::TEXTURE_2D, 0, 0, 0, w, h, rgba, byte, data);
            gl.pixel_store_i32(glow::UNPACK_ALIGNMENT, 4);
            gl.bind_texture(glow::TEXTURE_2D, previous);
        }
    }

    /// The colour texture, for a target made with [`ColorBuffer::Texture`].
    pub fn texture(&self) -> Option<glow::Texture> {
        match &self.color {
            Color::Texture(texture) => Some(texture.name()),
            Color::Renderbuffer(_) => None,
        }
    }

    pub fn width(&self) -> u32 {
        self.width
    }

    pub fn height(&self) -> u32 {
        self.height
    }
}

impl fmt::Debug for OffscreenTarget {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("OffscreenTarget")
            .field("color", &self.color)
            .field("width", &self.width)
            .field("height", &self.height)
            .field("flipped_y", &self.flipped_y)
            .field("samples", &self.samples)
            .finish_non_exhaustive()
    }
}

/// Storage of `internal_format` for the bound renderbuffer, `samples` per pixel (0: not
/// multisampled).
///
/// # Safety
/// A current context with a renderbuffer bound.
unsafe fn renderbuffer_storage(gl: &Gl, samples: u32, internal_format: u32, (w, h): (i32, i32)) {
    // `samples` ≤ GL_MAX_SAMPLES (checked by the caller), so it fits in i32.
    if samples == 0 {
        gl.renderbuffer_storage(glow::RENDERBUFFER, internal_format, w, h);
    } else {
        let n = samples as i32;
        let rb = glow::RENDERBUFFER;
        gl.renderbuffer_storage_multisample(rb, n, internal_format, w, h);
    }
}

/// Storage for `color` (a texture's stored as `kind` says), attached as the bound framebuffer's
/// colour.
///
/// # Safety
/// A current context with the target's framebuffer bound.
unsafe fn attach_color(
    gl: &Gl,
    color: &Color,
    kind: ColorBuffer,
    samples: u32,
    (w, h): (i32, i32),
) {
    match color {
        Color::Renderbuffer(rb) => {
            let rb = rb.name();
            gl.bind_renderbuffer(glow::RENDERBUFFER, Some(rb));
            renderbuffer_storage(gl, samples, glow::RGBA8, (w, h));
            let (point, target) = (glow::COLOR_ATTACHMENT0, glow::RENDERBUFFER);
            gl.framebuffer_renderbuffer(glow::FRAMEBUFFER, point, target, Some(rb));
        }
        Color::Texture(texture) => {
            let texture = texture.name();
            let previous = crate::gl::bound_texture(gl, glow::TEXTURE_BINDING_2D);
            gl.bind_texture(glow::TEXTURE_2D, Some(texture));
            // Mesa stores an unsized RGBA texture in the order of the data it is given.
            let (format, order, kind) = match kind {
                ColorBuffer::WindowOrderTexture => (glow::RGBA, glow::BGRA, glow::UNSIGNED_BYTE),
                ColorBuffer::UintPairs => (glow::RG32UI, glow::RG_INTEGER, glow::UNSIGNED_INT),
                _ => (glow::RGBA8, glow::RGBA, glow::UNSIGNED_BYTE),
            };
            let data = glow::PixelUnpackData::Slice(None);
            let format = format as i32;
            gl.tex_image_2d(glow::TEXTURE_2D, 0, format, w, h, 0, order, kind, data);
            nearest_texels(gl);
            gl.bind_texture(glow::TEXTURE_2D, previous);
            let point = glow::COLOR_ATTACHMENT0;
            let tex = Some(texture);
            gl.framebuffer_texture_2d(glow::FRAMEBUFFER, point, glow::TEXTURE_2D, tex, 0);
        }
    }
}

/// The bound 2D texture sampled 1:1: one level, no mipmaps, nearest texels.
///
/// # Safety
/// A current context with a texture bound to `TEXTURE_2D`.
pub(crate) unsafe fn nearest_texels(gl: &Gl) {
    let nearest = glow::NEAREST as i32;
    gl.tex_parameter_i32(glow::TEXTURE_2D, glow::TEXTURE_MIN_FILTER, nearest);
    gl.tex_parameter_i32(glow::TEXTURE_2D, glow::TEXTURE_MAG_FILTER, nearest);
}

fn framebuffer_status_name(status: u32) -> &'static str {
    match status {
        glow::FRAMEBUFFER_UNDEFINED => "GL_FRAMEBUFFER_UNDEFINED",
        glow::FRAMEBUFFER_INCOMPLETE_ATTACHMENT => "GL_FRAMEBUFFER_INCOMPLETE_ATTACHMENT",
        glow::FRAMEBUFFER_INCOMPLETE_MISSING_ATTACHMENT => {
            "GL_FRAMEBUFFER_INCOMPLETE_MISSING_ATTACHMENT"
        }
        glow::FRAMEBUFFER_UNSUPPORTED => "GL_FRAMEBUFFER_UNSUPPORTED",
        glow::FRAMEBUFFER_INCOMPLETE_MULTISAMPLE => "GL_FRAMEBUFFER_INCOMPLETE_MULTISAMPLE",
        _ => "unknown status",
    }
}
