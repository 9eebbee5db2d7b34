//! The GL context without a window: EGL on Mesa (llvmpipe), plus an offscreen framebuffer to render
//! into and read back. The tutorial itself only ever opens a GLFW window; this is what lets the same
//! frame code run in tests and on machines with no display or GPU.
//!
//! The context is created on an EGL *device* (`EGL_EXT_platform_device`) rather than on an X11 or
//! Wayland display, so no server and no environment variables are needed. Such displays only offer
//! pbuffer-capable configs, and the context is made current with no surface at all
//! (`EGL_KHR_surfaceless_context`): every frame goes into an [`OffscreenTarget`].

use std::ffi::{c_void, CStr};
use std::fmt;
use std::fs;
use std::io::{BufWriter, Write};
use std::path::Path;
use std::rc::Rc;
use std::sync::atomic::{AtomicU64, Ordering};

use glow::HasContext;
use glutin::api::egl::context::PossiblyCurrentContext;
use glutin::api::egl::device::Device;
use glutin::api::egl::display::Display;
use glutin::config::{Api, ConfigSurfaceTypes, ConfigTemplateBuilder};
use glutin::context::{
    ContextApi, ContextAttributesBuilder, GlProfile, PossiblyCurrentGlContext, Version,
};
use glutin::display::GlDisplay;

use crate::{Error, Result};

/// The GL function table, shared by the RAII wrappers (buffers, textures, programs) so that each can
/// delete its object on drop.
pub type Gl = Rc<glow::Context>;

/// Which OpenGL profile a context has (or is asked for).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Profile {
    /// 3.2+ core profile: what the tutorial asks GLFW for.
    Core,
    /// Compatibility profile: needed for the fixed-function TBN debug lines.
    Compat,
}

impl fmt::Display for Profile {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Profile::Core => "core",
            Profile::Compat => "compatibility",
        })
    }
}

/// What the context actually is, read back from GL rather than assumed from what was asked for:
/// drivers may give a higher version than requested, or refuse a profile.
#[derive(Debug, Clone)]
pub struct ContextInfo {
    /// `GL_MAJOR_VERSION`, `GL_MINOR_VERSION`.
    pub version: (u32, u32),
    /// From `GL_CONTEXT_PROFILE_MASK`.
    pub profile: Profile,
    /// `GL_CONTEXT_FLAG_FORWARD_COMPATIBLE_BIT` of `GL_CONTEXT_FLAGS`.
    pub forward_compatible: bool,
    /// `GL_RENDERER`, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)".
    pub renderer: String,
    /// `GL_VENDOR`.
    pub vendor: String,
    /// The full `GL_VERSION` string (it names the Mesa release).
    pub version_string: String,
    /// Every extension the context reports, sorted.
    pub extensions: Vec<String>,
}

impl ContextInfo {
    /// Whether the context reports `name` (e.g. "GL_EXT_texture_compression_s3tc").
    pub fn has_extension(&self, name: &str) -> bool {
        self.extensions
            .binary_search_by(|e| e.as_str().cmp(name))
            .is_ok()
    }

    /// Whether the context is at least `major.minor`.
    pub fn at_least(&self, major: u32, minor: u32) -> bool {
        self.version >= (major, minor)
    }
}

impl fmt::Display for ContextInfo {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "OpenGL {}.{} {} profile on {} ({})",
            self.version.0, self.version.1, self.profile, self.renderer, self.vendor
        )
    }
}

// GL_CONTEXT_PROFILE_MASK's core bit and the forward-compatible flag; named here because not every GL
// binding exports them under the same name.
const CONTEXT_CORE_PROFILE_BIT: i32 = 0x1;
const CONTEXT_FLAG_FORWARD_COMPATIBLE_BIT: i32 = 0x1;

/// Reads what the current context is. Reusable for the window's context.
///
/// Only queries that are valid for the context's version are made, so this never raises a GL error.
pub fn context_info(gl: &glow::Context) -> ContextInfo {
    // glow parsed GL_VERSION when it was loaded; GL_MAJOR/MINOR_VERSION only exist from 3.0 on.
    let parsed = gl.version();
    // SAFETY: plain queries on the current context, each valid for the version it is guarded by.
    unsafe {
        let version = if parsed.major >= 3 {
            let major = gl.get_parameter_i32(glow::MAJOR_VERSION);
            let minor = gl.get_parameter_i32(glow::MINOR_VERSION);
            (major.max(0) as u32, minor.max(0) as u32)
        } else {
            (parsed.major, parsed.minor)
        };
        let mut extensions: Vec<String> = gl.supported_extensions().iter().cloned().collect();
        extensions.sort();
        let profile = if version >= (3, 2) {
            let mask = gl.get_parameter_i32(glow::CONTEXT_PROFILE_MASK);
            if mask & CONTEXT_CORE_PROFILE_BIT != 0 {
                Profile::Core
            } else {
                // The COMPATIBILITY bit (0x2), or (non-conforming) no bit: legacy calls are allowed.
                Profile::Compat
            }
        } else if version >= (3, 1) {
            // 3.1 has no profiles: legacy entry points exist only with ARB_compatibility.
            if extensions.iter().any(|e| e == "GL_ARB_compatibility") {
                Profile::Compat
            } else {
                Profile::Core
            }
        } else {
            Profile::Compat
        };
        let forward_compatible = version >= (3, 0)
            && gl.get_parameter_i32(glow::CONTEXT_FLAGS) & CONTEXT_FLAG_FORWARD_COMPATIBLE_BIT != 0;
        ContextInfo {
            version,
            profile,
            forward_compatible,
            renderer: gl.get_parameter_string(glow::RENDERER),
            vendor: gl.get_parameter_string(glow::VENDOR),
            version_string: gl.get_parameter_string(glow::VERSION),
            extensions,
        }
    }
}

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
                return Err(Error::Gl(format!(
                    "EGL is not available (libEGL.so.1 could not be loaded): {INSTALL_HINT}"
                )))
            }
            Err(e) => {
                return Err(Error::Gl(format!(
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
            return Err(Error::Gl(format!("EGL lists no devices: {INSTALL_HINT}")));
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
            return Err(Error::Gl(format!(
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
                    failures.push(e.to_string());
                }
            }
        }
        // One device is the usual case: its reason alone is the clearest message.
        Err(Error::Gl(failures.join("; ")))
    }

    fn on_device(device: &Device, profile: Profile) -> Result<Self> {
        let name = describe_device(device);
        // SAFETY: no native display handle is passed, which is the documented-safe case.
        let display = unsafe { Display::with_device(device, None) }
            .map_err(|e| Error::Gl(format!("cannot open an EGL display on {name}: {e}")))?;

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
            .ok_or_else(|| Error::Gl(format!("{name} has no EGL config for desktop OpenGL")))?;

        let attributes = ContextAttributesBuilder::new()
            .with_profile(match profile {
                Profile::Core => GlProfile::Core,
                Profile::Compat => GlProfile::Compatibility,
            })
            .with_context_api(ContextApi::OpenGl(Some(Version::new(3, 3))))
            .build(None);
        // SAFETY: the attributes hold no native window handle and share with no other context.
        let context = unsafe { display.create_context(&config, &attributes) }.map_err(|e| {
            Error::Gl(match profile {
                Profile::Compat => format!("no compatibility profile on this driver ({name}: {e})"),
                Profile::Core => format!("cannot create an OpenGL 3.3 core context on {name}: {e}"),
            })
        })?;
        let context = context
            .make_current_surfaceless()
            .map_err(|e| Error::Gl(format!("cannot make the context current on {name}: {e}")))?;

        check_gl_version_string(&display)
            .map_err(|reason| Error::Gl(format!("{name}: {reason}")))?;
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
            return Err(Error::Gl(format!(
                "OpenGL 3.3 is needed, {} gives {}.{}",
                info.renderer, info.version.0, info.version.1
            )));
        }
        if info.profile != profile {
            return Err(Error::Gl(match profile {
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

    /// Makes this context current again, for a thread that holds several contexts (creating a context
    /// makes it current and releases the previous one).
    pub fn make_current(&self) -> Result<()> {
        self.context.make_current_surfaceless().map_err(|e| {
            Error::Gl(format!(
                "cannot make the context current on {}: {e}",
                self.device
            ))
        })
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

/// An offscreen framebuffer: RGBA8 colour and 24-bit depth renderbuffers of `width × height`.
///
/// This is where headless frames go (the surfaceless context has no default framebuffer). Drop it
/// before its context.
pub struct OffscreenTarget {
    gl: Gl,
    framebuffer: glow::Framebuffer,
    color: glow::Renderbuffer,
    depth: glow::Renderbuffer,
    width: u32,
    height: u32,
    /// `GL_FRAMEBUFFER_FLIP_Y_MESA` is set: stored top row first, as Mesa stores a window.
    flipped_y: bool,
}

/// `GL_MESA_framebuffer_flip_y`'s framebuffer parameter (glow has neither it nor the call that sets it).
const FRAMEBUFFER_FLIP_Y_MESA: u32 = 0x8BBB;
const FLIP_Y_EXTENSION: &str = "GL_MESA_framebuffer_flip_y";

/// The missing extension is reported once per process, not once per target.
static FLIP_Y_MISSING_LOGGED: std::sync::Once = std::sync::Once::new();

impl OffscreenTarget {
    /// Creates the framebuffer and checks that the driver accepts it as complete.
    /// Leaves framebuffer 0 bound (call [`OffscreenTarget::bind`] to draw into it).
    pub fn new(gl: &Gl, width: u32, height: u32) -> Result<Self> {
        // SAFETY: a plain query on the current context.
        let max = unsafe { gl.get_parameter_i32(glow::MAX_RENDERBUFFER_SIZE) }.max(0) as u32;
        if width == 0 || height == 0 || width > max || height > max {
            return Err(Error::Gl(format!(
                "offscreen target of {width}×{height}: each side must be between 1 and {max}"
            )));
        }
        // SAFETY: object creation on the current context; the names are owned by `target` from here
        // on, so its Drop deletes them even when a later step fails.
        unsafe {
            let framebuffer = gl
                .create_framebuffer()
                .map_err(|e| Error::Gl(format!("glGenFramebuffers failed: {e}")))?;
            let color = match gl.create_renderbuffer() {
                Ok(rb) => rb,
                Err(e) => {
                    gl.delete_framebuffer(framebuffer);
                    return Err(Error::Gl(format!("glGenRenderbuffers failed: {e}")));
                }
            };
            let depth = match gl.create_renderbuffer() {
                Ok(rb) => rb,
                Err(e) => {
                    gl.delete_framebuffer(framebuffer);
                    gl.delete_renderbuffer(color);
                    return Err(Error::Gl(format!("glGenRenderbuffers failed: {e}")));
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
            };
            // Sizes were checked against MAX_RENDERBUFFER_SIZE, so they fit in i32.
            let (w, h) = (width as i32, height as i32);
            gl.bind_renderbuffer(glow::RENDERBUFFER, Some(color));
            gl.renderbuffer_storage(glow::RENDERBUFFER, glow::RGBA8, w, h);
            gl.bind_renderbuffer(glow::RENDERBUFFER, Some(depth));
            gl.renderbuffer_storage(glow::RENDERBUFFER, glow::DEPTH_COMPONENT24, w, h);
            gl.bind_renderbuffer(glow::RENDERBUFFER, None);

            gl.bind_framebuffer(glow::FRAMEBUFFER, Some(framebuffer));
            let attach = |point, rb| {
                gl.framebuffer_renderbuffer(glow::FRAMEBUFFER, point, glow::RENDERBUFFER, Some(rb))
            };
            attach(glow::COLOR_ATTACHMENT0, color);
            attach(glow::DEPTH_ATTACHMENT, depth);
            let status = gl.check_framebuffer_status(glow::FRAMEBUFFER);
            gl.bind_framebuffer(glow::FRAMEBUFFER, None);
            if status != glow::FRAMEBUFFER_COMPLETE {
                return Err(Error::Gl(format!(
                    "offscreen framebuffer of {width}×{height} is incomplete: {} (0x{status:04X})",
                    framebuffer_status_name(status)
                )));
            }
            let errors = gl_errors(gl);
            if !errors.is_empty() {
                return Err(Error::Gl(format!(
                    "creating the offscreen framebuffer of {width}×{height} raised GL errors {}",
                    format_errors(&errors)
                )));
            }
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
        mut get_proc_address: impl FnMut(&CStr) -> *const c_void,
    ) -> Result<Self> {
        let mut target = Self::new(gl, width, height)?;
        if !info.has_extension(FLIP_Y_EXTENSION) {
            FLIP_Y_MISSING_LOGGED.call_once(|| {
                log::warn!(
                    "{} has no {FLIP_Y_EXTENSION}: headless frames may differ from a window's in \
                     a few edge pixels",
                    info.renderer
                )
            });
            return Ok(target);
        }
        let pointer = get_proc_address(c"glFramebufferParameteri");
        if pointer.is_null() {
            return Err(Error::Gl(format!(
                "{} lists {FLIP_Y_EXTENSION} but has no glFramebufferParameteri",
                info.renderer
            )));
        }
        // SAFETY: a non-null address the context gives for glFramebufferParameteri, whose C signature
        // is `void (GLenum target, GLenum pname, GLint param)` with the GL calling convention.
        let framebuffer_parameter_i: unsafe extern "system" fn(u32, u32, i32) =
            unsafe { std::mem::transmute::<*const c_void, _>(pointer) };
        // SAFETY: the framebuffer is alive (owned by target); the extension allows this parameter on
        // GL_FRAMEBUFFER; framebuffer 0 is bound again afterwards, as `new` leaves it.
        unsafe {
            gl.bind_framebuffer(glow::FRAMEBUFFER, Some(target.framebuffer));
            framebuffer_parameter_i(glow::FRAMEBUFFER, FRAMEBUFFER_FLIP_Y_MESA, 1);
            gl.bind_framebuffer(glow::FRAMEBUFFER, None);
        }
        let errors = gl_errors(gl);
        if !errors.is_empty() {
            return Err(Error::Gl(format!(
                "setting GL_FRAMEBUFFER_FLIP_Y_MESA on the offscreen framebuffer raised GL errors {}",
                format_errors(&errors)
            )));
        }
        target.flipped_y = true;
        Ok(target)
    }

    /// Whether the target is stored y-flipped like a window ([`OffscreenTarget::with_window_orientation`]
    /// on a context with `GL_MESA_framebuffer_flip_y`).
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

    /// The colour buffer, top row first. The read binding is restored afterwards.
    pub fn read_rgba(&self) -> image::RgbaImage {
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

    pub fn width(&self) -> u32 {
        self.width
    }

    pub fn height(&self) -> u32 {
        self.height
    }

    /// The GL framebuffer object, for code that binds it itself (e.g. as a blit source).
    pub fn framebuffer(&self) -> glow::Framebuffer {
        self.framebuffer
    }
}

impl Drop for OffscreenTarget {
    fn drop(&mut self) {
        // SAFETY: the names were created by this target on this context and are deleted once.
        unsafe {
            self.gl.delete_framebuffer(self.framebuffer);
            self.gl.delete_renderbuffer(self.color);
            self.gl.delete_renderbuffer(self.depth);
        }
    }
}

impl fmt::Debug for OffscreenTarget {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("OffscreenTarget")
            .field("framebuffer", &self.framebuffer)
            .field("width", &self.width)
            .field("height", &self.height)
            .field("flipped_y", &self.flipped_y)
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

/// Reads `width × height` RGBA8 pixels from the bottom-left of the currently bound READ framebuffer
/// (also used for the window's back buffer), flipped so that row 0 is the top row as in image files.
///
/// The pack state that decides how many bytes GL writes (alignment, row length, skips, pack buffer)
/// is set to tight packing for the read and restored afterwards.
pub fn read_pixels_rgba(gl: &glow::Context, width: u32, height: u32) -> image::RgbaImage {
    let mut image = image::RgbaImage::new(width, height);
    let (Ok(w), Ok(h)) = (i32::try_from(width), i32::try_from(height)) else {
        // No GL framebuffer can be this large; nothing to read.
        return image;
    };
    let stride = width as usize * 4;
    let mut raw = vec![0u8; stride * height as usize];
    if raw.is_empty() {
        return image;
    }
    const PACK_STATE: [u32; 4] = [
        glow::PACK_ALIGNMENT,
        glow::PACK_ROW_LENGTH,
        glow::PACK_SKIP_ROWS,
        glow::PACK_SKIP_PIXELS,
    ];
    // SAFETY: with the pack state below (alignment 1, no row length, no skips, no pack buffer) GL
    // writes exactly width × height × 4 bytes from the start of `raw`, which is that long.
    unsafe {
        let saved = PACK_STATE.map(|p| gl.get_parameter_i32(p));
        let pack_buffer = gl.get_parameter_buffer(glow::PIXEL_PACK_BUFFER_BINDING);
        gl.bind_buffer(glow::PIXEL_PACK_BUFFER, None);
        for (param, value) in PACK_STATE.into_iter().zip([1, 0, 0, 0]) {
            gl.pixel_store_i32(param, value);
        }
        gl.read_pixels(
            0,
            0,
            w,
            h,
            glow::RGBA,
            glow::UNSIGNED_BYTE,
            glow::PixelPackData::Slice(Some(&mut raw)),
        );
        for (param, value) in PACK_STATE.into_iter().zip(saved) {
            gl.pixel_store_i32(param, value);
        }
        gl.bind_buffer(glow::PIXEL_PACK_BUFFER, pack_buffer);
    }
    // GL's row 0 is the bottom one.
    for (dst, src) in image
        .chunks_exact_mut(stride)
        .zip(raw.chunks_exact(stride).rev())
    {
        dst.copy_from_slice(src);
    }
    image
}

/// Distinguishes temporary files of concurrent writers in the same process.
static TEMP_COUNTER: AtomicU64 = AtomicU64::new(0);

/// Writes `image` as a PNG at `path`, atomically: the PNG goes to a temporary file in the same
/// folder, which is renamed over `path` only once complete, so a reader (or a crash) never sees a
/// half-written screenshot. On failure nothing is left behind.
pub fn write_png(path: &Path, image: &image::RgbaImage) -> Result<()> {
    let size = (image.width(), image.height());
    write_png_raw(path, image.as_raw(), size, image::ExtendedColorType::Rgba8)
}

/// Writes a frame as a screenshot: RGB, alpha dropped, because a frame on screen is opaque (the
/// tutorial clears with alpha 0, which viewers would show as transparent).
pub fn write_screenshot(path: &Path, image: &image::RgbaImage) -> Result<()> {
    let rgb = image::DynamicImage::ImageRgba8(image.clone()).into_rgb8();
    let size = (rgb.width(), rgb.height());
    write_png_raw(path, rgb.as_raw(), size, image::ExtendedColorType::Rgb8)
}

fn write_png_raw(
    path: &Path,
    raw: &[u8],
    size: (u32, u32),
    color: image::ExtendedColorType,
) -> Result<()> {
    let Some(file_name) = path.file_name() else {
        return Err(Error::Write {
            path: path.to_path_buf(),
            reason: "not a file name".into(),
        });
    };
    let folder = match path.parent() {
        Some(parent) if !parent.as_os_str().is_empty() => parent,
        _ => Path::new("."),
    };
    let temp = folder.join(format!(
        ".{}.{}-{}.tmp",
        file_name.to_string_lossy(),
        std::process::id(),
        TEMP_COUNTER.fetch_add(1, Ordering::Relaxed)
    ));

    let file = fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&temp)
        .map_err(|e| Error::io(path, e))?;
    let written = encode_png(file, raw, size, color, path)
        .and_then(|()| fs::rename(&temp, path).map_err(|e| Error::io(path, e)));
    if written.is_err() {
        let _ = fs::remove_file(&temp);
    }
    written
}

/// Encodes into `file` and makes it durable before the rename publishes it.
fn encode_png(
    file: fs::File,
    raw: &[u8],
    (width, height): (u32, u32),
    color: image::ExtendedColorType,
    path: &Path,
) -> Result<()> {
    use image::ImageEncoder;
    let mut out = BufWriter::new(file);
    image::codecs::png::PngEncoder::new(&mut out)
        .write_image(raw, width, height, color)
        .map_err(|e| match e {
            image::ImageError::IoError(e) => Error::io(path, e),
            other => Error::Write {
                path: path.to_path_buf(),
                reason: other.to_string(),
            },
        })?;
    out.flush().map_err(|e| Error::io(path, e))?;
    let file = out
        .into_inner()
        .map_err(|e| Error::io(path, e.into_error()))?;
    file.sync_all().map_err(|e| Error::io(path, e))
}

/// Drains glGetError; returns the error codes seen, oldest first (empty = none).
///
/// Bounded, because a lost context may keep reporting an error.
pub fn gl_errors(gl: &glow::Context) -> Vec<u32> {
    let mut errors = Vec::new();
    for _ in 0..64 {
        // SAFETY: glGetError has no preconditions beyond a current context.
        match unsafe { gl.get_error() } {
            glow::NO_ERROR => break,
            e => errors.push(e),
        }
    }
    errors
}

/// "GL_INVALID_ENUM, GL_INVALID_OPERATION" for messages.
pub fn format_errors(errors: &[u32]) -> String {
    errors
        .iter()
        .map(|&e| match e {
            glow::INVALID_ENUM => "GL_INVALID_ENUM".to_string(),
            glow::INVALID_VALUE => "GL_INVALID_VALUE".to_string(),
            glow::INVALID_OPERATION => "GL_INVALID_OPERATION".to_string(),
            glow::INVALID_FRAMEBUFFER_OPERATION => "GL_INVALID_FRAMEBUFFER_OPERATION".to_string(),
            glow::OUT_OF_MEMORY => "GL_OUT_OF_MEMORY".to_string(),
            glow::STACK_OVERFLOW => "GL_STACK_OVERFLOW".to_string(),
            glow::STACK_UNDERFLOW => "GL_STACK_UNDERFLOW".to_string(),
            glow::CONTEXT_LOST => "GL_CONTEXT_LOST".to_string(),
            other => format!("0x{other:04X}"),
        })
        .collect::<Vec<_>>()
        .join(", ")
}
