//! GL helpers every scene and front end shares: the `Gl` handle, what the context is ([`ContextInfo`]),
//! GL error draining, mesh buffers ([`buffers`]), pixel read-back and image files ([`image`]), the
//! headless EGL context with its offscreen targets ([`context`]), and what a made context draws
//! with ([`current::GlContext`]).

pub mod buffers;
#[cfg(not(target_arch = "wasm32"))]
pub mod context;
pub mod current;
pub mod extensions;
pub mod image;
pub mod map_uploads;
pub mod objects;
pub mod offscreen;
pub mod state;
pub mod uniforms;

use std::fmt;

use glow::HasContext;

pub use crate::common::Gl;
use crate::{Error, Result};

/// Which OpenGL profile a context has (or is asked for).
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
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

/// The object bound at binding point `pname` (e.g. `GL_ARRAY_BUFFER_BINDING`), asked through
/// `query` (glow's `get_parameter_buffer`, …): `None` where none is bound. In the browser glow
/// panics on WebGL's null for "none", so the page's raw context is asked first
/// (`set_webgl2_context`, in a wasm32 build).
///
/// # Safety
/// A current context.
pub unsafe fn bound<T>(
    gl: &glow::Context,
    pname: u32,
    query: unsafe fn(&glow::Context, u32) -> Option<T>,
) -> Option<T> {
    #[cfg(target_arch = "wasm32")]
    if WEBGL2.with(|raw| {
        raw.borrow()
            .as_ref()
            .is_some_and(|raw| raw.get_parameter(pname).map_or(true, |v| v.is_null()))
    }) {
        return None;
    }
    query(gl, pname)
}

/// [`bound`] for each kind of object the program saves and restores a binding of.
macro_rules! bound_kind {
    ($($name:ident, $query:ident, $kind:ty;)*) => {$(
        /// The object bound at `pname`, if any (see [`bound`]).
        ///
        /// # Safety
        /// A current context.
        pub unsafe fn $name(gl: &glow::Context, pname: u32) -> Option<$kind> {
            bound(gl, pname, glow::Context::$query)
        }
    )*};
}

bound_kind! {
    bound_buffer, get_parameter_buffer, glow::Buffer;
    bound_framebuffer, get_parameter_framebuffer, glow::Framebuffer;
    bound_program, get_parameter_program, glow::Program;
    bound_texture, get_parameter_texture, glow::Texture;
    bound_vertex_array, get_parameter_vertex_array, glow::VertexArray;
}

#[cfg(target_arch = "wasm32")]
thread_local! {
    /// The page's WebGL2 context, for [`bound`].
    static WEBGL2: std::cell::RefCell<Option<web_sys::WebGl2RenderingContext>> =
        const { std::cell::RefCell::new(None) };
}

/// Gives [`bound`] the page's WebGL2 context (the one glow's context wraps).
#[cfg(target_arch = "wasm32")]
pub fn set_webgl2_context(raw: &web_sys::WebGl2RenderingContext) {
    WEBGL2.with(|c| *c.borrow_mut() = Some(raw.clone()));
}

// GL_CONTEXT_PROFILE_MASK's core bit; named here because not every GL binding exports it.
const CONTEXT_CORE_PROFILE_BIT: i32 = 0x1;

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
        ContextInfo {
            version,
            profile,
            renderer: gl.get_parameter_string(glow::RENDERER),
            vendor: gl.get_parameter_string(glow::VENDOR),
            version_string: gl.get_parameter_string(glow::VERSION),
            extensions,
        }
    }
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

/// [`gl_errors`] as a result: an error flag is a bug in this program, so it is reported with the
/// `part` that was being drawn, not ignored.
pub fn check_gl_errors(gl: &glow::Context, part: &'static str) -> Result<()> {
    let errors = gl_errors(gl);
    if errors.is_empty() {
        Ok(())
    } else {
        Err(Error::gl(
            part,
            format!("GL reported {}", format_errors(&errors)),
        ))
    }
}

/// Binds each texture to its own unit (0, 1, 2, … in order) and points its sampler uniform there:
/// the tutorial's `glActiveTexture`, `glBindTexture`, `glUniform1i` for any number of maps. The
/// current program must be the samplers'.
pub fn bind_textures(
    gl: &Gl,
    textures: &[(
        &crate::common::texture::Texture,
        &Option<glow::UniformLocation>,
    )],
) {
    // SAFETY: textures and uniforms of the current context and program.
    unsafe {
        for (unit, (texture, sampler)) in textures.iter().enumerate() {
            gl.active_texture(glow::TEXTURE0 + unit as u32);
            gl.bind_texture(glow::TEXTURE_2D, Some(texture.id));
            gl.uniform_1_i32(sampler.as_ref(), unit as i32);
        }
    }
}

/// A scene's two generated maps, loaded through the tutorial's `loadBMP_custom`.
pub struct Maps {
    pub diffuse: crate::common::texture::Texture,
    pub normal: crate::common::texture::Texture,
}

impl Maps {
    /// Both maps, the diffuse map first (their files found by `SceneOptions::asset_files`).
    pub fn load(gl: &Gl, [diffuse, normal]: &[std::path::PathBuf; 2]) -> Result<Self> {
        use crate::common::texture::load_bmp_custom;
        let diffuse = load_bmp_custom(gl, diffuse)?;
        let normal = load_bmp_custom(gl, normal)?;
        Ok(Maps { diffuse, normal })
    }

    /// The diffuse map in unit 0 and the normal map in unit 1, for the current program's samplers.
    pub fn bind(&self, gl: &Gl, diffuse: &uniforms::Uniform, normal: &uniforms::Uniform) {
        bind_textures(gl, &[(&self.diffuse, diffuse), (&self.normal, normal)]);
    }
}
