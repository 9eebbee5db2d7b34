//! GL objects owned by a value that deletes them: a constructor that creates several and fails half
//! way drops the ones it made, with no delete-on-error branch written by hand.

use std::fmt;

use glow::HasContext;

use super::Gl;
use crate::{Error, Result};

/// A kind of GL object glow creates and deletes by name.
pub trait GlObject: Copy + fmt::Debug {
    /// What it is called in an error ("glGenBuffers failed: ...").
    const CREATE: &'static str;

    /// # Safety
    /// A current context.
    unsafe fn create(gl: &Gl) -> std::result::Result<Self, String>;

    /// # Safety
    /// A name of `gl`'s context, deleted once.
    unsafe fn delete(self, gl: &Gl);
}

macro_rules! gl_object {
    ($type:ty, $create_name:literal, $create:ident, $delete:ident) => {
        impl GlObject for $type {
            const CREATE: &'static str = $create_name;

            unsafe fn create(gl: &Gl) -> std::result::Result<Self, String> {
                gl.$create()
            }

            unsafe fn delete(self, gl: &Gl) {
                gl.$delete(self)
            }
        }
    };
}

// The concrete types (not glow's `Buffer`, … aliases, which the trait system cannot tell apart):
// desktop GL's names natively, glow's keys into WebGL2's objects in the browser.
#[cfg(not(target_arch = "wasm32"))]
use glow::{
    NativeBuffer as BufferName, NativeFramebuffer as FramebufferName,
    NativeRenderbuffer as RenderbufferName, NativeTexture as TextureName,
    NativeVertexArray as VertexArrayName,
};
#[cfg(target_arch = "wasm32")]
use glow::{
    WebBufferKey as BufferName, WebFramebufferKey as FramebufferName,
    WebRenderbufferKey as RenderbufferName, WebTextureKey as TextureName,
    WebVertexArrayKey as VertexArrayName,
};

gl_object!(BufferName, "glGenBuffers", create_buffer, delete_buffer);
gl_object!(
    VertexArrayName,
    "glGenVertexArrays",
    create_vertex_array,
    delete_vertex_array
);
gl_object!(
    FramebufferName,
    "glGenFramebuffers",
    create_framebuffer,
    delete_framebuffer
);
gl_object!(
    RenderbufferName,
    "glGenRenderbuffers",
    create_renderbuffer,
    delete_renderbuffer
);
gl_object!(TextureName, "glGenTextures", create_texture, delete_texture);

/// One GL object, deleted when the value is dropped. Keep it (or what holds it) shorter-lived than
/// its context; the shared `Gl` keeps the function table alive.
pub struct Owned<T: GlObject> {
    gl: Gl,
    name: T,
}

impl<T: GlObject> Owned<T> {
    /// Creates one object on the current context; `part` names what it is for in the error.
    pub fn create(gl: &Gl, part: &'static str) -> Result<Self> {
        // SAFETY: object creation on the current context.
        let name = unsafe { T::create(gl) }
            .map_err(|e| Error::gl(part, format!("{} failed: {e}", T::CREATE)))?;
        Ok(Owned {
            gl: gl.clone(),
            name,
        })
    }

    /// The GL name, for binding and attaching.
    pub fn name(&self) -> T {
        self.name
    }
}

impl<T: GlObject> Drop for Owned<T> {
    fn drop(&mut self) {
        // SAFETY: made by this context (kept alive by the shared `Gl`), deleted once, here.
        unsafe { self.name.delete(&self.gl) }
    }
}

impl<T: GlObject> fmt::Debug for Owned<T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Owned({:?})", self.name)
    }
}
