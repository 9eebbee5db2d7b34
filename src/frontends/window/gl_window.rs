//! The window and its GL context: opened with a config of the asked sample count (what draws with it
//! is handed to the scene host as a [`GlContext`]), read back for screenshots, swapped after each
//! frame. Nothing here knows of scenes or input.

use std::cell::RefCell;
use std::ffi::CString;
use std::num::NonZeroU32;

use glow::HasContext;
use glutin::config::{Config, ConfigTemplateBuilder, GlConfig};
use glutin::context::{
    ContextApi, ContextAttributesBuilder, GlProfile, NotCurrentGlContext, PossiblyCurrentContext,
    Version,
};
use glutin::display::{GetGlDisplay, GlDisplay};
use glutin::surface::{GlSurface, Surface, WindowSurface};
use glutin_winit::{DisplayBuilder, GlWindow as _};
use raw_window_handle::HasWindowHandle;
use winit::dpi::PhysicalSize;
use winit::event_loop::ActiveEventLoop;
use winit::window::Window;

use super::no_display::no_display_message;
use super::TITLE;
use crate::gl::current::GlContext;
use crate::gl::extensions::GlExtensions;
use crate::gl::image::read_pixels_rgba;
use crate::gl::offscreen::OffscreenTarget;
use crate::gl::{context_info, Gl, Profile};
use crate::{Error, Result};

/// The window, its surface and its current context. Field order is drop order: the surface and the
/// context before the window they belong to.
pub struct GlWindow {
    /// Samples per pixel of the window's buffers (`--msaa`).
    samples: i32,
    surface: Surface<WindowSurface>,
    context: PossiblyCurrentContext,
    pub window: Window,
}

impl GlWindow {
    /// Opens a `size` window with a GL 3.3 context of `profile` and a config of `msaa` samples, and
    /// gives what draws with the context (the entry points glow does not load looked up once here).
    pub fn open(
        event_loop: &ActiveEventLoop,
        size: (u32, u32),
        profile: Profile,
        msaa: u8,
    ) -> Result<(Self, GlContext)> {
        let attributes = Window::default_attributes()
            .with_title(TITLE)
            .with_inner_size(PhysicalSize::new(size.0, size.1));
        let (window, config) = build_window(event_loop, attributes, msaa)?;
        let display = config.display();
        let handle = window
            .window_handle()
            .map_err(|e| Error::Window(format!("window handle: {e}")))?
            .as_raw();
        let gl_profile = match profile {
            Profile::Core => GlProfile::Core,
            Profile::Compat => GlProfile::Compatibility,
        };
        let attributes = ContextAttributesBuilder::new()
            .with_profile(gl_profile)
            .with_context_api(ContextApi::OpenGl(Some(Version::new(3, 3))))
            .build(Some(handle));
        // SAFETY: the handle belongs to `window`, which outlives the context (field order).
        let not_current = unsafe { display.create_context(&config, &attributes) }.map_err(|e| {
            Error::Context(format!(
                "no OpenGL 3.3 {profile} context on this display: {e}"
            ))
        })?;
        let surface_attributes = window
            .build_surface_attributes(Default::default())
            .map_err(|e| Error::Window(format!("surface: {e}")))?;
        // SAFETY: as above, the window outlives the surface.
        let surface = unsafe { display.create_window_surface(&config, &surface_attributes) }
            .map_err(|e| Error::Window(format!("surface: {e}")))?;
        let context = not_current
            .make_current(&surface)
            .map_err(|e| Error::Context(format!("cannot make it current: {e}")))?;
        // SAFETY: the loader returns entry points of the current context's display.
        let gl: Gl = std::sync::Arc::new(unsafe {
            glow::Context::from_loader_function(|name| {
                let name = CString::new(name).expect("GL names have no NUL");
                display.get_proc_address(&name)
            })
        });
        let info = context_info(&gl);
        if !info.at_least(3, 3) || info.profile != profile {
            return Err(Error::Context(format!(
                "OpenGL 3.3 {profile} is needed, the display gave {info}"
            )));
        }
        // SAFETY: a plain query on the current context.
        let samples = unsafe { gl.get_parameter_i32(glow::SAMPLES) };
        log::info!(
            "window context: {info}, config with {} samples ({samples} in the default \
             framebuffer) and a {}-bit depth buffer",
            config.num_samples(),
            config.depth_size()
        );
        let extensions = GlExtensions::load(&info, |name| display.get_proc_address(name));
        let window = GlWindow {
            samples,
            surface,
            context,
            window,
        };
        Ok((
            window,
            GlContext {
                gl,
                info,
                extensions,
            },
        ))
    }

    /// The drawable size, at least 1×1. Under X this asks the server (a round trip, about 0.15 ms
    /// under Xvfb): each frame asks once, which also finds a window another program destroyed
    /// before a swap draws into it (Mesa's swap to a destroyed window crashes the process); what
    /// else needs the size in that frame takes the frame's.
    pub fn size(&self) -> (u32, u32) {
        let size = self.window.inner_size();
        (
            NonZeroU32::new(size.width).map_or(1, |v| v.get()),
            NonZeroU32::new(size.height).map_or(1, |v| v.get()),
        )
    }

    /// The surface follows the window's new size.
    pub fn resize(&self) {
        self.window.resize_surface(&self.surface, &self.context);
    }

    pub fn swap_buffers(&self) -> Result<()> {
        self.surface
            .swap_buffers(&self.context)
            .map_err(|e| Error::Window(format!("swap buffers: {e}")))
    }

    /// The back buffer (the frame just drawn with `gl`, this window's context), top row first.
    pub fn read_frame(&self, gl: &GlContext) -> Result<image::RgbaImage> {
        let (w, h) = self.size();
        if self.samples == 0 {
            return Ok(read_pixels_rgba(&gl.gl, w, h));
        }
        // Mesa's glReadPixels on a multisampled window buffer does not give the frame the window
        // shows (measured: 2006 pixels differ from an xwd capture, which equals the headless
        // frame): resolve it into a single-sampled target first, as the swap does.
        let target = OffscreenTarget::with_window_orientation(&gl.gl, (w, h), 0, &gl.extensions)?;
        target.blit_from(None);
        Ok(target.read_rgba())
    }
}

/// glutin's example picks the config with the most samples; the tutorial's frame wants none unless
/// `--msaa N` asks for N, and a 24-bit depth buffer (GLFW's default) where there is one. `Err` lists
/// the sample counts the display has when none has N.
fn pick_config(configs: &[Config], msaa: u8) -> std::result::Result<Config, Vec<u8>> {
    let chosen = configs
        .iter()
        .filter(|c| c.num_samples() == msaa)
        .min_by_key(|c| u8::from(c.depth_size() < 24))
        .cloned();
    chosen.ok_or_else(|| {
        let mut counts: Vec<u8> = configs.iter().map(Config::num_samples).collect();
        counts.sort_unstable();
        counts.dedup();
        counts
    })
}

/// Opens the window with a config from [`pick_config`], asking the display for every config (not
/// only those with `msaa` samples) so that a count it lacks is answered with the counts it has.
/// glutin-winit's picker must return a config, and does so before the window exists: when none
/// fits, it returns any, and the window it opens is dropped here with the error.
fn build_window(
    event_loop: &ActiveEventLoop,
    attributes: winit::window::WindowAttributes,
    msaa: u8,
) -> Result<(Window, Config)> {
    let missing: RefCell<Option<Vec<u8>>> = RefCell::new(None);
    let built = DisplayBuilder::new()
        .with_window_attributes(Some(attributes))
        .build(event_loop, ConfigTemplateBuilder::new(), |configs| {
            let configs: Vec<Config> = configs.collect();
            pick_config(&configs, msaa).unwrap_or_else(|counts| {
                *missing.borrow_mut() = Some(counts);
                // glutin returns an error rather than an empty list for a display without any
                // config (BadConfig from glXChooseFBConfig / eglChooseConfig), so there is one.
                configs
                    .into_iter()
                    .next()
                    .expect("glutin lists at least one config")
            })
        });
    let (window, config) = built.map_err(|e| Error::Window(no_display_message(&e.to_string())))?;
    if let Some(counts) = missing.into_inner() {
        return Err(Error::Window(format!(
            "the display has no framebuffer configuration with {msaa} samples per pixel (--msaa): \
             it offers {counts:?}"
        )));
    }
    let window = window.ok_or_else(|| Error::Window("it could not be created".into()))?;
    Ok((window, config))
}
