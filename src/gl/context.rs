//! The GL context without a window: EGL on Mesa (llvmpipe). Its frames go into offscreen targets
//! ([`super::offscreen`]). The tutorial itself only ever opens a GLFW window; this is what lets the same
//! frame code run in tests and on machines with no display or GPU.
//!
//! The context is created on an EGL *device* (`EGL_EXT_platform_device`) rather than on an X11 or
//! Wayland display, so no server and no environment variables are needed. Such displays only offer
//! pbuffer-capable configs, and the context is made current with no surface at all
//! (`EGL_KHR_surfaceless_context`): every frame goes into an [`OffscreenTarget`](super::offscreen::OffscreenTarget).

use std::ffi::{c_void, CStr};
use std::fmt;

use glutin::api::egl::context::PossiblyCurrentContext;
use glutin::api::egl::device::Device;
use glutin::api::egl::display::Display;
use glutin::config::{Api, ConfigSurfaceTypes, ConfigTemplateBuilder};
use glutin::context::{
    ContextApi, ContextAttributesBuilder, GlProfile, PossiblyCurrentGlContext, Version,
};
use glutin::display::GlDisplay;

use super::current::GlContext;
use super::extensions::GlExtensions;
use super::{context_info, ContextInfo, Gl, Profile};
use crate::{Error, Result};

/// Mesa marks its software rasterizer's EGL device with this extension.
const SOFTWARE_DEVICE_EXTENSION: &str = "EGL_MESA_device_software";

const INSTALL_HINT: &str = "install Debian's libegl1 libegl-mesa0 libgl1-mesa-dri";

/// An OpenGL context with no window, current on the thread that created it: what draws with it
/// ([`GlContext`]) and the EGL context and display that keep it alive ([`EglContext`]).
///
/// Not `Send`: an EGL context is current on one thread (glutin's current context is not `Send`, nor is
/// glow's function table). Objects made through
/// [`HeadlessContext::gl`] (and offscreen targets) must be dropped before the context is.
pub struct HeadlessContext {
    // Field order is drop order: the function table, then the context and its display.
    gl: GlContext,
    egl: EglContext,
}

/// The EGL side of a [`HeadlessContext`]: the context and the display it is current on, kept alive
/// by whoever draws (the headless front end, once the scene host owns the [`GlContext`]).
pub struct EglContext {
    // Field order is drop order: the context, then the display.
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
        let extensions = GlExtensions::load(&info, |s| display.get_proc_address(s));
        let headless = HeadlessContext {
            gl: GlContext {
                gl: std::sync::Arc::new(gl),
                info,
                extensions,
            },
            egl: EglContext {
                device: name,
                context,
                display,
            },
        };
        let info = &headless.gl.info;
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
        log::debug!("{}: {}", headless.egl.device, headless.gl.info);
        Ok(headless)
    }

    /// The GL function table; clone it into objects that must delete themselves.
    pub fn gl(&self) -> &Gl {
        &self.gl.gl
    }

    /// What the context is (version, profile, renderer), as read back from GL.
    pub fn info(&self) -> &ContextInfo {
        &self.gl.info
    }

    /// The entry points glow does not load, looked up when the context was made.
    pub fn extensions(&self) -> &GlExtensions {
        &self.gl.extensions
    }

    /// A short description of the EGL device the context runs on.
    pub fn device(&self) -> &str {
        self.egl.device()
    }

    /// Looks up a GL entry point, e.g. the legacy immediate-mode ones glow does not load.
    /// Null when the driver does not have it.
    pub fn get_proc_address(&self, name: &CStr) -> *const c_void {
        self.egl.get_proc_address(name)
    }

    /// What draws with the context, for the scene host to own, and the EGL context that keeps it
    /// alive (to be dropped after every GL object).
    pub fn split(self) -> (GlContext, EglContext) {
        (self.gl, self.egl)
    }
}

impl EglContext {
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

impl Drop for EglContext {
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
            .field("device", &self.egl.device)
            .field("info", &format_args!("{}", self.gl.info))
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
