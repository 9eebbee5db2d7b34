//! The GL context without a window: EGL on Mesa (llvmpipe), and offscreen framebuffers to render
//! into and read back. The tutorial itself only ever opens a GLFW window; this is what lets the same
//! frame code run in tests and on machines with no display or GPU.
//!
//! The context is created on an EGL *device* (`EGL_EXT_platform_device`) rather than on an X11 or
//! Wayland display, so no server and no environment variables are needed. Such displays only offer
//! pbuffer-capable configs, and the context is made current with no surface at all
//! (`EGL_KHR_surfaceless_context`): every frame goes into an [`OffscreenTarget`].

use std::ffi::{c_void, CStr};
use std::fmt;
use std::rc::Rc;

use glow::HasContext;
use glutin::api::egl::context::PossiblyCurrentContext;
use glutin::api::egl::device::Device;
use glutin::api::egl::display::Display;
use glutin::config::{Api, ConfigSurfaceTypes, ConfigTemplateBuilder};
use glutin::context::{
    ContextApi, ContextAttributesBuilder, GlProfile, PossiblyCurrentGlContext, Version,
};
use glutin::display::GlDisplay;

use super::image::read_pixels_rgba;
use super::{check_gl_errors, context_info, ContextInfo, Gl, Profile};
use crate::{Error, Result};

/// Mesa marks its software rasterizer's EGL device with this extension.
const SOFTWARE_DEVICE_EXTENSION: &str = "EGL_MESA_device_software";

const INSTALL_HINT: &str = "install Debian's libegl1 libegl-mesa0 libgl1-mesa-dri";

/// An OpenGL context with no window, current on the thread that created it.
///
/// Not `Send`: an EGL context is current on one thread, and [`Gl`] is an `Rc`. Objects made through
/// [`HeadlessContext::gl`] (and [`OffscreenTarget`]s) must be dropped before the context is.
pub struct HeadlessContext {
    // Field order is drop order: the function table, then the context, then the display.
    gl: Gl,
    info: ContextInfo,
    device: String,
    context: PossiblyCurrentContext,
    display: Display,
}

impl HeadlessContext {
    /// Creates a GL 3.3 (or later) context of `profile` on an EGL device and makes it current.
    ///
    /// `prefer_hardware`: false = use Mesa's software device (llvmpipe), the deterministic choice for
    /// tests; true = try the GPU devices first and fall back to the software one.
    pub fn new(profile: Profile, prefer_hardware: bool) -> Result<Self> {
        let devices: Vec<Device> = match Device::query_devices() {
            Ok(devices) => devices.collect(),
            Err(e) if e.error_kind() == glutin::error::ErrorKind::NotFound => {
                return Err(Error::Context(format!(
                    "EGL is not available (libEGL.so.1 could not be loaded): {INSTALL_HINT}"
                )))
            }
            Err(e) => {
                return Err(Error::Context(format!(
                    "EGL cannot list its devices ({e}): {INSTALL_HINT}"
                )))
            }
        };
        log::debug!(
            "EGL devices: {}",
            devices
                .iter()
                .map(describe_device)
                .collect::<Vec<_>>()
                .join("; ")
        );
        if devices.is_empty() {
            return Err(Error::Context(format!(
                "EGL lists no devices: {INSTALL_HINT}"
            )));
        }

        let is_software = |d: &&Device| d.extensions().contains(SOFTWARE_DEVICE_EXTENSION);
        let software = devices.iter().filter(is_software);
        let candidates: Vec<&Device> = if prefer_hardware {
            let hardware = devices.iter().filter(|d| !is_software(d));
            hardware.chain(software).collect()
        } else {
            software.collect()
        };
        if candidates.is_empty() {
            return Err(Error::Context(format!(
                "no software (llvmpipe) EGL device among {}: {INSTALL_HINT}",
                devices
                    .iter()
                    .map(describe_device)
                    .collect::<Vec<_>>()
                    .join(", ")
            )));
        }

        let mut failures = Vec::new();
        for device in candidates {
            match Self::on_device(device, profile) {
                Ok(context) => return Ok(context),
                Err(e) => {
                    log::debug!("{}: {e}", describe_device(device));
                    failures.push(match e {
                        Error::Context(reason) => reason,
                        other => other.to_string(),
                    });
                }
            }
        }
        // One device is the usual case: its reason alone is the clearest message.
        Err(Error::Context(failures.join("; ")))
    }

    fn on_device(device: &Device, profile: Profile) -> Result<Self> {
        let name = describe_device(device);
        // SAFETY: no native display handle is passed, which is the documented-safe case.
        let display = unsafe { Display::with_device(device, None) }
            .map_err(|e| Error::Context(format!("cannot open an EGL display on {name}: {e}")))?;

        // Device displays have no window system, so ask for no surface type at all: the context will
        // be made current without a surface and draw into framebuffer objects.
        let template = ConfigTemplateBuilder::new()
            .with_surface_type(ConfigSurfaceTypes::empty())
            .with_api(Api::OPENGL)
            .build();
        // SAFETY: the template holds no native window handle.
        let config = unsafe { display.find_configs(template) }
            .ok()
            .and_then(|mut configs| configs.next())
            .ok_or_else(|| {
                Error::Context(format!("{name} has no EGL config for desktop OpenGL"))
            })?;

        let attributes = ContextAttributesBuilder::new()
            .with_profile(match profile {
                Profile::Core => GlProfile::Core,
                Profile::Compat => GlProfile::Compatibility,
            })
            .with_context_api(ContextApi::OpenGl(Some(Version::new(3, 3))))
            .build(None);
        // SAFETY: the attributes hold no native window handle and share with no other context.
        let context = unsafe { display.create_context(&config, &attributes) }.map_err(|e| {
            Error::Context(match profile {
                Profile::Compat => format!("no compatibility profile on this driver ({name}: {e})"),
                Profile::Core => format!("cannot create an OpenGL 3.3 core context on {name}: {e}"),
            })
        })?;
        let context = context.make_current_surfaceless().map_err(|e| {
            Error::Context(format!("cannot make the context current on {name}: {e}"))
        })?;

        check_gl_version_string(&display)
            .map_err(|reason| Error::Context(format!("{name}: {reason}")))?;
        // SAFETY: the context is current on this thread and glGetString(GL_VERSION) was just checked
        // to return a parsable string, which is what glow's loader otherwise panics on.
        let gl =
            unsafe { glow::Context::from_loader_function_cstr(|s| display.get_proc_address(s)) };
        let info = context_info(&gl);
        let headless = HeadlessContext {
            gl: Rc::new(gl),
            info,
            device: name,
            context,
            display,
        };
        let info = &headless.info;
        if !info.at_least(3, 3) {
            return Err(Error::Context(format!(
                "OpenGL 3.3 is needed, {} gives {}.{}",
                info.renderer, info.version.0, info.version.1
            )));
        }
        if info.profile != profile {
            return Err(Error::Context(match profile {
                Profile::Compat => format!(
                    "no compatibility profile on this driver ({} gave a {} context)",
                    info.renderer, info.profile
                ),
                Profile::Core => format!(
                    "no core profile on this driver ({} gave a {} context)",
                    info.renderer, info.profile
                ),
            }));
        }
        log::debug!("{}: {}", headless.device, headless.info);
        Ok(headless)
    }

    /// The GL function table; clone it into objects that must delete themselves.
    pub fn gl(&self) -> &Gl {
        &self.gl
    }

    /// What the context is (version, profile, renderer), as read back from GL.
    pub fn info(&self) -> &ContextInfo {
        &self.info
    }

    /// A short description of the EGL device the context runs on.
    pub fn device(&self) -> &str {
        &self.device
    }

    /// Looks up a GL entry point, e.g. the legacy immediate-mode ones glow does not load.
    /// Null when the driver does not have it.
    pub fn get_proc_address(&self, name: &CStr) -> *const c_void {
        self.display.get_proc_address(name)
    }
}

impl Drop for HeadlessContext {
    fn drop(&mut self) {
        // EGL only frees a context once no thread has it current: release it now rather than when
        // the thread exits, but only if it is still the current one (not a context made after it).
        if self.context.is_current() {
            let _ = self.context.make_not_current_in_place();
        }
    }
}

impl fmt::Debug for HeadlessContext {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("HeadlessContext")
            .field("device", &self.device)
            .field("info", &format_args!("{}", self.info))
            .finish_non_exhaustive()
    }
}

/// "llvmpipe device (software, Mesa)" style description for error messages and logs.
fn describe_device(device: &Device) -> String {
    let kind = if device.extensions().contains(SOFTWARE_DEVICE_EXTENSION) {
        "software".to_string()
    } else if let Some(node) = device
        .drm_render_device_node_path()
        .or_else(|| device.drm_device_node_path())
    {
        node.display().to_string()
    } else {
        "hardware".to_string()
    };
    // Mesa gives its devices no name; the vendor is absent too.
    let name = device.name().unwrap_or("EGL device");
    match device.vendor() {
        Some(vendor) => format!("{name} ({kind}, {vendor})"),
        None => format!("{name} ({kind})"),
    }
}

/// Checks that the current context answers glGetString(GL_VERSION) with something that starts like
/// "3.3": glow's loader panics on anything else, and a panic is not an error message.
fn check_gl_version_string(display: &Display) -> std::result::Result<(), String> {
    let get_string = display.get_proc_address(c"glGetString");
    if get_string.is_null() {
        return Err("the driver has no glGetString".into());
    }
    // SAFETY: glGetString's signature is `const GLubyte *glGetString(GLenum)` with the platform's
    // GL calling convention ("system"); the pointer comes from the driver for that exact name.
    let get_string: unsafe extern "system" fn(u32) -> *const u8 =
        unsafe { std::mem::transmute(get_string) };
    // SAFETY: a context is current; the result is null or a NUL-terminated static string.
    let version = unsafe { get_string(glow::VERSION) };
    if version.is_null() {
        return Err("glGetString(GL_VERSION) returned nothing".into());
    }
    // SAFETY: non-null, NUL-terminated, owned by the driver for the context's lifetime.
    let version = unsafe { CStr::from_ptr(version.cast()) };
    match version.to_str() {
        Ok(v) if v.starts_with(|c: char| c.is_ascii_digit()) && v.contains('.') => Ok(()),
        _ => Err(format!("unexpected GL_VERSION {version:?}")),
    }
}

/// Where an [`OffscreenTarget`]'s colour goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ColorBuffer {
    /// A renderbuffer: only read back (headless frames, screenshots).
    Renderbuffer,
    /// A texture a later pass can sample (e.g. one half of a comparison view).
    Texture,
}

#[derive(Debug)]
enum Color {
    Renderbuffer(glow::Renderbuffer),
    Texture(glow::Texture),
}

/// An offscreen framebuffer: RGBA8 colour (a renderbuffer or a texture) and a 24-bit depth
/// renderbuffer of `width × height`.
///
/// This is where headless frames go (the surfaceless context has no default framebuffer). Drop it
/// before its context.
pub struct OffscreenTarget {
    gl: Gl,
    framebuffer: glow::Framebuffer,
    color: Color,
    depth: glow::Renderbuffer,
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

/// `GL_MESA_framebuffer_flip_y`'s framebuffer parameter (glow has neither it nor the call that sets it).
const FRAMEBUFFER_FLIP_Y_MESA: u32 = 0x8BBB;
const FLIP_Y_EXTENSION: &str = "GL_MESA_framebuffer_flip_y";

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
        // SAFETY: object creation on the current context; each name is owned by `target` (or deleted
        // here) as soon as it exists, so its Drop deletes them even when a later step fails.
        unsafe {
            let framebuffer = gl
                .create_framebuffer()
                .map_err(|e| Error::gl(PART, format!("glGenFramebuffers failed: {e}")))?;
            let depth = match gl.create_renderbuffer() {
                Ok(rb) => rb,
                Err(e) => {
                    gl.delete_framebuffer(framebuffer);
                    return Err(Error::gl(PART, format!("glGenRenderbuffers failed: {e}")));
                }
            };
            let made = match color {
                ColorBuffer::Renderbuffer => gl.create_renderbuffer().map(Color::Renderbuffer),
                ColorBuffer::Texture => gl.create_texture().map(Color::Texture),
            };
            let color = match made {
                Ok(color) => color,
                Err(e) => {
                    gl.delete_framebuffer(framebuffer);
                    gl.delete_renderbuffer(depth);
                    return Err(Error::gl(
                        PART,
                        format!("cannot create the colour buffer: {e}"),
                    ));
                }
            };
            let target = OffscreenTarget {
                gl: Rc::clone(gl),
                framebuffer,
                color,
                depth,
                width,
                height,
                flipped_y: false,
                samples,
                resolve: None,
            };
            // `samples` ≤ GL_MAX_SAMPLES (checked by the caller), so it fits in i32.
            let storage = |internal_format: u32| {
                if samples == 0 {
                    gl.renderbuffer_storage(glow::RENDERBUFFER, internal_format, w, h);
                } else {
                    let n = samples as i32;
                    let rb = glow::RENDERBUFFER;
                    gl.renderbuffer_storage_multisample(rb, n, internal_format, w, h);
                }
            };
            gl.bind_renderbuffer(glow::RENDERBUFFER, Some(depth));
            storage(glow::DEPTH_COMPONENT24);
            gl.bind_framebuffer(glow::FRAMEBUFFER, Some(framebuffer));
            match target.color {
                Color::Renderbuffer(rb) => {
                    gl.bind_renderbuffer(glow::RENDERBUFFER, Some(rb));
                    storage(glow::RGBA8);
                    let (point, target) = (glow::COLOR_ATTACHMENT0, glow::RENDERBUFFER);
                    gl.framebuffer_renderbuffer(glow::FRAMEBUFFER, point, target, Some(rb));
                }
                Color::Texture(texture) => {
                    let previous = gl.get_parameter_texture(glow::TEXTURE_BINDING_2D);
                    gl.bind_texture(glow::TEXTURE_2D, Some(texture));
                    let format = glow::RGBA8 as i32;
                    let data = glow::PixelUnpackData::Slice(None);
                    let (rgba, byte) = (glow::RGBA, glow::UNSIGNED_BYTE);
                    gl.tex_image_2d(glow::TEXTURE_2D, 0, format, w, h, 0, rgba, byte, data);
                    // One level, sampled 1:1: no mipmaps, nearest texels.
                    let nearest = glow::NEAREST as i32;
                    gl.tex_parameter_i32(glow::TEXTURE_2D, glow::TEXTURE_MIN_FILTER, nearest);
                    gl.tex_parameter_i32(glow::TEXTURE_2D, glow::TEXTURE_MAG_FILTER, nearest);
                    gl.bind_texture(glow::TEXTURE_2D, previous);
                    let point = glow::COLOR_ATTACHMENT0;
                    let tex = Some(texture);
                    gl.framebuffer_texture_2d(glow::FRAMEBUFFER, point, glow::TEXTURE_2D, tex, 0);
                }
            }
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

    /// Like [`OffscreenTarget::new`], but stored y-flipped as Mesa stores a window's buffers, so that
    /// a frame drawn into it is the window's frame bit for bit.
    ///
    /// Mesa keeps window buffers top row first, and llvmpipe's rasterization rules (which pixel an
    /// edge or a line covers) follow that storage: a plain framebuffer object gets a few edge pixels
    /// and line pixels different from a window. `GL_MESA_framebuffer_flip_y` makes a framebuffer
    /// object stored like a window. Where the context lacks the extension this is a plain target
    /// (said once in the log), and [`OffscreenTarget::flipped_y`] is false. `get_proc_address` loads
    /// `glFramebufferParameteri`, which glow does not wrap.
    pub fn with_window_orientation(
        gl: &Gl,
        width: u32,
        height: u32,
        info: &ContextInfo,
        get_proc_address: impl FnMut(&CStr) -> *const c_void,
    ) -> Result<Self> {
        Self::with_window_orientation_multisampled(gl, width, height, 0, info, get_proc_address)
    }

    /// [`OffscreenTarget::with_window_orientation`] with `samples` per pixel (0: none).
    pub fn with_window_orientation_multisampled(
        gl: &Gl,
        width: u32,
        height: u32,
        samples: u32,
        info: &ContextInfo,
        get_proc_address: impl FnMut(&CStr) -> *const c_void,
    ) -> Result<Self> {
        let mut target = Self::multisampled(gl, width, height, samples)?;
        target.set_window_orientation(info, get_proc_address)?;
        Ok(target)
    }

    /// Stores this target like a window (see [`OffscreenTarget::with_window_orientation`]); returns
    /// whether the extension was there to do it. A texture target flipped this way is also stored
    /// top row first, so a pass that samples it must flip its texture coordinates' v.
    pub fn set_window_orientation(
        &mut self,
        info: &ContextInfo,
        mut get_proc_address: impl FnMut(&CStr) -> *const c_void,
    ) -> Result<bool> {
        if !info.has_extension(FLIP_Y_EXTENSION) {
            FLIP_Y_MISSING_LOGGED.call_once(|| {
                log::warn!(
                    "{} has no {FLIP_Y_EXTENSION}: headless frames may differ from a window's in \
                     a few edge pixels",
                    info.renderer
                )
            });
            return Ok(false);
        }
        let pointer = get_proc_address(c"glFramebufferParameteri");
        if pointer.is_null() {
            return Err(Error::gl(
                PART,
                format!(
                    "{} lists {FLIP_Y_EXTENSION} but has no glFramebufferParameteri",
                    info.renderer
                ),
            ));
        }
        // SAFETY: a non-null address the context gives for glFramebufferParameteri, whose C signature
        // is `void (GLenum target, GLenum pname, GLint param)` with the GL calling convention.
        let framebuffer_parameter_i: unsafe extern "system" fn(u32, u32, i32) =
            unsafe { std::mem::transmute::<*const c_void, _>(pointer) };
        // SAFETY: the framebuffer is alive (owned by self); the extension allows this parameter on
        // GL_FRAMEBUFFER; framebuffer 0 is bound again afterwards, as `new` leaves it.
        // A multisampled target's resolved twin is stored the same way, so the blit keeps rows in order.
        let resolve = self.resolve.as_ref().map(|r| r.framebuffer);
        for framebuffer in std::iter::once(self.framebuffer).chain(resolve) {
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
                .bind_framebuffer(glow::FRAMEBUFFER, Some(self.framebuffer));
            self.gl
                .viewport(0, 0, self.width as i32, self.height as i32);
        }
    }

    /// Samples per pixel (0: not multisampled).
    pub fn samples(&self) -> u32 {
        self.samples
    }

    /// The colour buffer, top row first (a multisampled target resolved: each pixel the mean of
    /// its samples). The read and draw bindings are restored afterwards.
    pub fn read_rgba(&self) -> image::RgbaImage {
        if let Some(resolve) = &self.resolve {
            resolve.blit_from(Some(self.framebuffer));
            return resolve.read_rgba();
        }
        // SAFETY: binding queries and binds on the current context; the framebuffer is alive.
        unsafe {
            let previous = self
                .gl
                .get_parameter_framebuffer(glow::READ_FRAMEBUFFER_BINDING);
            self.gl
                .bind_framebuffer(glow::READ_FRAMEBUFFER, Some(self.framebuffer));
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
            let read = gl.get_parameter_framebuffer(glow::READ_FRAMEBUFFER_BINDING);
            let draw = gl.get_parameter_framebuffer(glow::DRAW_FRAMEBUFFER_BINDING);
            gl.bind_framebuffer(glow::READ_FRAMEBUFFER, framebuffer);
            gl.bind_framebuffer(glow::DRAW_FRAMEBUFFER, Some(self.framebuffer));
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
            let read = gl.get_parameter_framebuffer(glow::READ_FRAMEBUFFER_BINDING);
            let draw = gl.get_parameter_framebuffer(glow::DRAW_FRAMEBUFFER_BINDING);
            gl.bind_framebuffer(glow::READ_FRAMEBUFFER, Some(self.framebuffer));
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
            let previous = gl.get_parameter_texture(glow::TEXTURE_BINDING_2D);
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
        match self.color {
            Color::Texture(texture) => Some(texture),
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

impl Drop for OffscreenTarget {
    fn drop(&mut self) {
        // SAFETY: the names were created by this target on this context and are deleted once.
        unsafe {
            self.gl.delete_framebuffer(self.framebuffer);
            match self.color {
                Color::Renderbuffer(rb) => self.gl.delete_renderbuffer(rb),
                Color::Texture(texture) => self.gl.delete_texture(texture),
            }
            self.gl.delete_renderbuffer(self.depth);
        }
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
