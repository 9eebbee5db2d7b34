//! The entry points glow does not load, resolved once when a context is made ([`GlExtensions`]):
//! the immediate mode's (the tutorial's TBN debug lines) and `glFramebufferParameteri` (for
//! `GL_MESA_framebuffer_flip_y`, which stores an offscreen target as a window is stored). The
//! panel, the compare view, the debug lines and the offscreen targets take them typed from here;
//! nothing else looks up an address.

use std::ffi::{c_void, CStr};

use super::{ContextInfo, Profile};
use crate::{Error, Result};

/// Names the immediate mode in errors.
const PART: &str = "debug lines";

/// The extension that stores a framebuffer object top row first, as Mesa stores a window.
pub const FLIP_Y_EXTENSION: &str = "GL_MESA_framebuffer_flip_y";

/// `glFramebufferParameteri(target, pname, param)`.
pub type FramebufferParameteri = unsafe extern "system" fn(u32, u32, i32);

/// What one context offers beyond glow's table, looked up once.
#[derive(Debug, Clone)]
pub struct GlExtensions {
    /// The renderer's name, for the messages about what it lacks.
    pub renderer: String,
    /// `glFramebufferParameteri` where the context lists [`FLIP_Y_EXTENSION`]; `None` where it does
    /// not, `Err` where it lists it without the function.
    pub flip_y: Option<std::result::Result<FramebufferParameteri, String>>,
    /// The immediate-mode entry points, or why the context has none.
    pub legacy: std::result::Result<LegacyGl, String>,
}

impl GlExtensions {
    /// Looks up every entry point of the context described by `info`, through its `loader`.
    pub fn load(info: &ContextInfo, mut loader: impl FnMut(&CStr) -> *const c_void) -> Self {
        let flip_y = info.has_extension(FLIP_Y_EXTENSION).then(|| {
            let pointer = loader(c"glFramebufferParameteri");
            if pointer.is_null() {
                return Err(format!(
                    "{} lists {FLIP_Y_EXTENSION} but has no glFramebufferParameteri",
                    info.renderer
                ));
            }
            // SAFETY: a non-null address the context gives for glFramebufferParameteri, whose C
            // signature is `void (GLenum target, GLenum pname, GLint param)` with the GL calling
            // convention.
            Ok(unsafe { std::mem::transmute::<*const c_void, FramebufferParameteri>(pointer) })
        });
        GlExtensions {
            renderer: info.renderer.clone(),
            flip_y,
            legacy: LegacyGl::load_or_reason(info, loader),
        }
    }
}

/// The fixed-function entry points the tutorial's debug code calls, which glow does not load.
///
/// Only valid on the context they were loaded from, while it is current.
#[derive(Clone, Copy)]
pub struct LegacyGl {
    pub(crate) matrix_mode: unsafe extern "system" fn(u32),
    pub(crate) load_matrix_f: unsafe extern "system" fn(*const f32),
    pub(crate) push_matrix: unsafe extern "system" fn(),
    pub(crate) pop_matrix: unsafe extern "system" fn(),
    pub(crate) push_attrib: unsafe extern "system" fn(u32),
    pub(crate) pop_attrib: unsafe extern "system" fn(),
    pub(crate) color_3f: unsafe extern "system" fn(f32, f32, f32),
    pub(crate) begin: unsafe extern "system" fn(u32),
    pub(crate) vertex_3fv: unsafe extern "system" fn(*const f32),
    pub(crate) end: unsafe extern "system" fn(),
}

impl std::fmt::Debug for LegacyGl {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LegacyGl").finish_non_exhaustive()
    }
}

/// Looks up one entry point; null means the driver does not have it at all.
fn lookup(loader: &mut impl FnMut(&CStr) -> *const c_void, name: &CStr) -> Result<*const c_void> {
    let ptr = loader(name);
    if ptr.is_null() {
        Err(Error::gl(
            PART,
            format!(
                "the driver has no {} (needed for immediate mode)",
                name.to_string_lossy()
            ),
        ))
    } else {
        Ok(ptr)
    }
}

impl LegacyGl {
    /// [`LegacyGl::load`], or the reason this context has no immediate mode (for the notice).
    pub fn load_or_reason(
        info: &ContextInfo,
        loader: impl FnMut(&CStr) -> *const c_void,
    ) -> std::result::Result<Self, String> {
        Self::load(info, loader).map_err(|e| match e {
            Error::Gl { reason, .. } => reason,
            other => other.to_string(),
        })
    }

    /// Loads the immediate-mode entry points of the context described by `info`.
    ///
    /// Availability is decided by the profile, not by null pointers: Mesa hands out these pointers in
    /// a core context too, where every call only raises GL_INVALID_OPERATION.
    pub fn load(
        info: &ContextInfo,
        mut loader: impl FnMut(&CStr) -> *const c_void,
    ) -> Result<Self> {
        if info.profile != Profile::Compat {
            return Err(Error::gl(
                PART,
                format!(
                    "the tutorial's immediate mode needs a compatibility-profile context, \
                     and this is a {} profile one (OpenGL {}.{} on {})",
                    info.profile, info.version.0, info.version.1, info.renderer
                ),
            ));
        }
        macro_rules! entry {
            ($name:literal, $ty:ty) => {{
                let ptr = lookup(&mut loader, $name)?;
                // SAFETY: `ptr` is the non-null address the context's loader gives for this GL 1.0
                // function, whose C signature is the function-pointer type it is cast to.
                unsafe { std::mem::transmute::<*const c_void, $ty>(ptr) }
            }};
        }
        Ok(LegacyGl {
            matrix_mode: entry!(c"glMatrixMode", unsafe extern "system" fn(u32)),
            load_matrix_f: entry!(c"glLoadMatrixf", unsafe extern "system" fn(*const f32)),
            push_matrix: entry!(c"glPushMatrix", unsafe extern "system" fn()),
            pop_matrix: entry!(c"glPopMatrix", unsafe extern "system" fn()),
            push_attrib: entry!(c"glPushAttrib", unsafe extern "system" fn(u32)),
            pop_attrib: entry!(c"glPopAttrib", unsafe extern "system" fn()),
            color_3f: entry!(c"glColor3f", unsafe extern "system" fn(f32, f32, f32)),
            begin: entry!(c"glBegin", unsafe extern "system" fn(u32)),
            vertex_3fv: entry!(c"glVertex3fv", unsafe extern "system" fn(*const f32)),
            end: entry!(c"glEnd", unsafe extern "system" fn()),
        })
    }
}
