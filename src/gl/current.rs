//! The context a front end made current, as everything draws with it ([`GlContext`]): made once by
//! the front end that opens it (the window, headless EGL, the page's WebGL2) and owned from then on
//! by the scene host, which builds every scene and the panel on it.

use super::extensions::GlExtensions;
use super::{ContextInfo, Gl};

/// glow's function table, what the context is, and the entry points glow does not load (looked up
/// once with the context).
pub struct GlContext {
    pub gl: Gl,
    pub info: ContextInfo,
    pub extensions: GlExtensions,
}
