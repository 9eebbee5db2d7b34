//! The window: glutin + winit in place of the tutorial's GLFW, the same frame as headless.
//!
//! 1024×768, "Tutorial 13 - Normal Mapping", a GL 3.3 context of the asked profile, a config without
//! multisampling (the original's screenshot test turns MSAA off, and MSAA blurs the debug lines).
//! The cursor is grabbed and hidden; raw mouse motion turns the camera, the arrow keys move it; Esc or
//! closing the window quits. Once a second "<x> ms/frame" is printed and shown in the title.

use std::ffi::CString;
use std::num::NonZeroU32;
use std::path::PathBuf;
use std::time::{Duration, Instant};

use glow::HasContext;
use glutin::config::{Config, ConfigTemplateBuilder, GlConfig};
use glutin::context::{
    ContextApi, ContextAttributesBuilder, GlProfile, NotCurrentGlContext, PossiblyCurrentContext,
    Version,
};
use glutin::display::{GetGlDisplay, GlDisplay};
use glutin::surface::{GlSurface, Surface, WindowSurface};
use glutin_winit::{DisplayBuilder, GlWindow};
use raw_window_handle::HasWindowHandle;
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{DeviceEvent, DeviceId, ElementState, KeyEvent, WindowEvent};
use winit::event_loop::{ActiveEventLoop, EventLoop};
use winit::keyboard::{KeyCode, PhysicalKey};
use winit::window::{CursorGrabMode, Window, WindowId};

use crate::context::{
    context_info, format_errors, gl_errors, read_pixels_rgba, write_screenshot, Gl, Profile,
};
use crate::controls::{Controls, Input};
use crate::tutorial13::{Action, SceneOptions, Tutorial13};
use crate::{Error, Result};

pub const TITLE: &str = "Tutorial 13 - Normal Mapping";

/// The command line's window-mode settings.
#[derive(Debug, Clone)]
pub struct WindowOptions {
    pub scene: SceneOptions,
    pub size: (u32, u32),
    pub profile: Profile,
    /// Render this many frames with time frozen at 0, then exit.
    pub frames: Option<u32>,
    /// Save the last frame here.
    pub screenshot: Option<PathBuf>,
}

/// The message for a machine without a display, with the command that works there.
pub fn no_display_message(reason: &str) -> String {
    format!(
        "no display to open a window on ({reason}); render without one: \
         tutorial13 --headless --frames 1 --screenshot frame.png"
    )
}

/// Opens the window and runs until Esc, a close, or `frames` frames.
pub fn run_window(options: WindowOptions) -> Result<()> {
    let no_var = |name: &str| std::env::var_os(name).is_none_or(|v| v.is_empty());
    if no_var("DISPLAY") && no_var("WAYLAND_DISPLAY") {
        return Err(Error::Gl(no_display_message(
            "neither DISPLAY nor WAYLAND_DISPLAY is set",
        )));
    }
    let event_loop = EventLoop::new().map_err(|e| Error::Gl(no_display_message(&e.to_string())))?;
    let mut app = App {
        options,
        running: None,
        outcome: Ok(()),
    };
    event_loop
        .run_app(&mut app)
        .map_err(|e| Error::Gl(format!("window event loop: {e}")))?;
    app.outcome
}

struct App {
    options: WindowOptions,
    running: Option<Running>,
    outcome: Result<()>,
}

/// Everything alive while the window is open. Field order is drop order: the GL objects first, then
/// the surface and context, then the window.
struct Running {
    tutorial: Tutorial13,
    gl: Gl,
    surface: Surface<WindowSurface>,
    context: PossiblyCurrentContext,
    window: Window,
    controls: Controls,
    input: Input,
    last_time: Instant,
    frames_drawn: u32,
    timer: FrameTimer,
    /// The last "ms/frame" figure, kept for the title.
    ms_per_frame: Option<f64>,
    screenshots_taken: u32,
}

impl App {
    fn fail(&mut self, event_loop: &ActiveEventLoop, error: Error) {
        self.outcome = Err(error);
        event_loop.exit();
    }

    fn frozen(&self) -> bool {
        self.options.frames.is_some()
    }
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.running.is_some() {
            return;
        }
        match Running::new(event_loop, &self.options) {
            Ok(running) => {
                running.window.request_redraw();
                self.running = Some(running);
            }
            Err(e) => self.fail(event_loop, e),
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let frozen = self.frozen();
        let Some(running) = self.running.as_mut() else {
            return;
        };
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::KeyboardInput {
                event:
                    KeyEvent {
                        physical_key: PhysicalKey::Code(code),
                        state,
                        ..
                    },
                ..
            } => {
                let pressed = state == ElementState::Pressed;
                match code {
                    KeyCode::Escape if pressed => event_loop.exit(),
                    KeyCode::ArrowUp => running.input.up = pressed,
                    KeyCode::ArrowDown => running.input.down = pressed,
                    KeyCode::ArrowLeft => running.input.left = pressed,
                    KeyCode::ArrowRight => running.input.right = pressed,
                    KeyCode::KeyP if pressed => {
                        // The frame on screen is the front buffer: draw it again and read it back.
                        if let Err(e) = running.frame(true).and_then(|()| running.save_numbered()) {
                            log::error!("{e}");
                        }
                    }
                    _ if pressed => {
                        if let Some(action) = action_for_key(code) {
                            match running.tutorial.apply(action) {
                                Ok(()) => {
                                    log::info!("{}", running.tutorial.status());
                                    running.update_title();
                                }
                                Err(e) => log::error!("{e}"),
                            }
                        }
                    }
                    _ => {}
                }
            }
            WindowEvent::Resized(size) => {
                running
                    .window
                    .resize_surface(&running.surface, &running.context);
                log::debug!("resized to {}x{}", size.width, size.height);
            }
            WindowEvent::RedrawRequested => {
                let result = running.frame(frozen);
                let done = self
                    .options
                    .frames
                    .is_some_and(|n| running.frames_drawn >= n.max(1));
                match result {
                    Err(e) => self.fail(event_loop, e),
                    Ok(()) if done => {
                        if let Some(path) = self.options.screenshot.clone() {
                            if let Err(e) = running.save(&path) {
                                return self.fail(event_loop, e);
                            }
                        }
                        event_loop.exit();
                    }
                    Ok(()) => {
                        if let Err(e) = running.surface.swap_buffers(&running.context) {
                            return self.fail(event_loop, Error::Gl(format!("swap buffers: {e}")));
                        }
                        running.window.request_redraw();
                    }
                }
            }
            _ => {}
        }
    }

    fn device_event(&mut self, _: &ActiveEventLoop, _: DeviceId, event: DeviceEvent) {
        // Raw motion: the same pixel deltas the tutorial reads after re-centring the cursor.
        if let (Some(running), DeviceEvent::MouseMotion { delta }) = (self.running.as_mut(), event)
        {
            running.input.mouse_dx += delta.0;
            running.input.mouse_dy += delta.1;
        }
    }

    fn exiting(&mut self, _: &ActiveEventLoop) {
        // An interactive run with --screenshot saves the frame the user last saw.
        if let (Some(running), Some(path), None) = (
            self.running.as_mut(),
            self.options.screenshot.clone(),
            self.options.frames,
        ) {
            let saved = running.frame(false).and_then(|()| running.save(&path));
            if let Err(e) = saved {
                self.outcome = Err(e);
            }
        }
        self.running = None;
    }
}

/// The keys of the tutorial's switches (Esc, arrows and P are handled by the window itself).
pub fn action_for_key(code: KeyCode) -> Option<Action> {
    Some(match code {
        KeyCode::KeyL => Action::ToggleLines,
        KeyCode::KeyM => Action::ToggleLineMode,
        KeyCode::KeyV => Action::NextView,
        KeyCode::KeyC => Action::NextComponent,
        KeyCode::KeyN => Action::ToggleNormalizeBeforeSum,
        KeyCode::KeyG => Action::ToggleGramSchmidt,
        KeyCode::KeyH => Action::ToggleHandedness,
        KeyCode::KeyS => Action::ToggleSpecularTexture,
        KeyCode::KeyT => Action::ToggleNormalizedTbn,
        _ => return None,
    })
}

/// Printed at start and in `--help`.
pub const KEYS: &str = "Keys (window):
  mouse           look around (the cursor is grabbed and hidden)
  arrow keys      move forward / back, strafe left / right
  L               TBN debug lines on / off (normals blue, tangents red, bitangents green)
  M               debug lines: immediate mode (compatibility profile) / line shader
  V               colour view: lit, light, light01, eye, eye01, normal, normal01
  C               colour view component: all, x, y, z
  N               normalize tangents before summing them (exercise 1)
  G               Gram-Schmidt on / off
  H               handedness fix on / off
  S               specular texture / constant 0.3
  T               TBN as summed (repository shader) / normalized (article)
  P               save a screenshot (tutorial13-N.png in the current folder)
  Esc             quit (closing the window quits too)";

/// glutin's example picks the config with the most samples; the tutorial's frame wants none, and a
/// 24-bit depth buffer (GLFW's default) where there is one.
fn pick_config(configs: Box<dyn Iterator<Item = Config> + '_>) -> Option<Config> {
    configs.min_by_key(|c| (c.num_samples(), u8::from(c.depth_size() < 24)))
}

/// Opens the window with a config from [`pick_config`]. glutin-winit's picker must return a config,
/// so a display with none at all is carried out of it as a silent unwind and turned into an error.
fn build_window(
    event_loop: &ActiveEventLoop,
    attributes: winit::window::WindowAttributes,
) -> Result<(Option<Window>, Config)> {
    struct NoConfig;
    let previous_hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(|info| {
        if info.payload().downcast_ref::<NoConfig>().is_none() {
            eprintln!("{info}");
        }
    }));
    let built = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        DisplayBuilder::new()
            .with_window_attributes(Some(attributes))
            .build(event_loop, ConfigTemplateBuilder::new(), |configs| {
                pick_config(configs).unwrap_or_else(|| std::panic::panic_any(NoConfig))
            })
    }));
    std::panic::set_hook(previous_hook);
    match built {
        Ok(result) => result.map_err(|e| Error::Gl(no_display_message(&e.to_string()))),
        Err(payload) if payload.is::<NoConfig>() => Err(Error::Gl(
            "the display offers no OpenGL framebuffer configuration".into(),
        )),
        Err(payload) => std::panic::resume_unwind(payload),
    }
}

impl Running {
    fn new(event_loop: &ActiveEventLoop, options: &WindowOptions) -> Result<Self> {
        let (width, height) = options.size;
        let attributes = Window::default_attributes()
            .with_title(TITLE)
            .with_inner_size(PhysicalSize::new(width, height));
        let (window, config) = build_window(event_loop, attributes)?;
        let window = window.ok_or_else(|| Error::Gl("the window could not be created".into()))?;
        let display = config.display();
        let handle = window
            .window_handle()
            .map_err(|e| Error::Gl(format!("window handle: {e}")))?
            .as_raw();
        let profile = match options.profile {
            Profile::Core => GlProfile::Core,
            Profile::Compat => GlProfile::Compatibility,
        };
        let attributes = ContextAttributesBuilder::new()
            .with_profile(profile)
            .with_context_api(ContextApi::OpenGl(Some(Version::new(3, 3))))
            .build(Some(handle));
        // SAFETY: the handle belongs to `window`, which outlives the context (field order).
        let not_current = unsafe { display.create_context(&config, &attributes) }.map_err(|e| {
            Error::Gl(format!(
                "no OpenGL 3.3 {} context on this display: {e}",
                options.profile
            ))
        })?;
        let surface_attributes = window
            .build_surface_attributes(Default::default())
            .map_err(|e| Error::Gl(format!("window surface: {e}")))?;
        // SAFETY: as above, the window outlives the surface.
        let surface = unsafe { display.create_window_surface(&config, &surface_attributes) }
            .map_err(|e| Error::Gl(format!("window surface: {e}")))?;
        let context = not_current
            .make_current(&surface)
            .map_err(|e| Error::Gl(format!("make the context current: {e}")))?;
        // SAFETY: the loader returns entry points of the current context's display.
        let gl: Gl = std::rc::Rc::new(unsafe {
            glow::Context::from_loader_function(|name| {
                let name = CString::new(name).expect("GL names have no NUL");
                display.get_proc_address(&name)
            })
        });
        let info = context_info(&gl);
        if !info.at_least(3, 3) || info.profile != options.profile {
            return Err(Error::Gl(format!(
                "OpenGL 3.3 {} is needed, the display gave {info}",
                options.profile
            )));
        }
        log::info!(
            "window context: {info}, config with {} samples and a {}-bit depth buffer",
            config.num_samples(),
            config.depth_size()
        );

        if options.frames.is_none() {
            window.set_cursor_visible(false);
            let grabbed = window
                .set_cursor_grab(CursorGrabMode::Locked)
                .or_else(|_| window.set_cursor_grab(CursorGrabMode::Confined));
            if let Err(e) = grabbed {
                log::warn!(
                    "cursor not grabbed ({e}): mouse look still works while it is over the window"
                );
            }
        }
        let tutorial = Tutorial13::new(
            &gl,
            &info,
            |name| display.get_proc_address(name),
            &options.scene,
        )?;
        log::info!("{}", tutorial.status());
        let running = Running {
            tutorial,
            gl,
            surface,
            context,
            window,
            controls: Controls::default(),
            input: Input::default(),
            last_time: Instant::now(),
            frames_drawn: 0,
            timer: FrameTimer::new(),
            ms_per_frame: None,
            screenshots_taken: 0,
        };
        running.update_title();
        Ok(running)
    }

    /// "Tutorial 13 - Normal Mapping - 3.2 ms/frame - view lit | lines off | ...".
    fn update_title(&self) {
        let ms = self
            .ms_per_frame
            .map_or(String::new(), |ms| format!(" - {ms:.3} ms/frame"));
        self.window
            .set_title(&format!("{TITLE}{ms} - {}", self.tutorial.status()));
    }

    /// `P`: tutorial13-1.png, tutorial13-2.png, ... in the current folder, never overwriting.
    fn save_numbered(&mut self) -> Result<()> {
        let path = loop {
            self.screenshots_taken += 1;
            let path = PathBuf::from(format!("tutorial13-{}.png", self.screenshots_taken));
            if !path.exists() {
                break path;
            }
        };
        self.save(&path)
    }

    /// One frame into the back buffer (not yet swapped).
    fn frame(&mut self, frozen: bool) -> Result<()> {
        let now = Instant::now();
        let delta_time = if frozen {
            0.0
        } else {
            (now - self.last_time).as_secs_f32()
        };
        self.last_time = now;
        let input = if frozen { Input::default() } else { self.input };
        self.controls
            .compute_matrices_from_inputs(&input, delta_time);
        self.input.mouse_dx = 0.0;
        self.input.mouse_dy = 0.0;

        let size = self.window.inner_size();
        // SAFETY: the viewport follows the window; the projection stays 4:3 as the tutorial's.
        unsafe {
            self.gl
                .viewport(0, 0, size.width as i32, size.height as i32)
        };
        self.tutorial.render(&self.gl, &self.controls);
        let errors = gl_errors(&self.gl);
        if !errors.is_empty() {
            return Err(Error::Gl(format!("GL reported {}", format_errors(&errors))));
        }
        self.frames_drawn += 1;
        if let Some(ms) = self.timer.tick(now) {
            println!("{ms:.3} ms/frame");
            self.window
                .set_title(&format!("{TITLE} - {ms:.3} ms/frame"));
        }
        Ok(())
    }

    /// Reads the back buffer (the frame just drawn) and writes it as PNG.
    fn save(&self, path: &std::path::Path) -> Result<()> {
        let size = self.window.inner_size();
        let (w, h) = (
            NonZeroU32::new(size.width).map_or(1, |v| v.get()),
            NonZeroU32::new(size.height).map_or(1, |v| v.get()),
        );
        let image = read_pixels_rgba(&self.gl, w, h);
        write_screenshot(path, &image)?;
        log::info!("wrote {}", path.display());
        Ok(())
    }
}

/// The tutorial's once-a-second "ms/frame" figure.
pub struct FrameTimer {
    since: Instant,
    frames: u32,
}

impl FrameTimer {
    pub fn new() -> Self {
        FrameTimer {
            since: Instant::now(),
            frames: 0,
        }
    }

    /// Counts a frame; once a second or more has passed, returns the mean ms/frame and restarts.
    pub fn tick(&mut self, now: Instant) -> Option<f64> {
        self.frames += 1;
        let elapsed = now.duration_since(self.since);
        if elapsed < Duration::from_secs(1) {
            return None;
        }
        let ms = elapsed.as_secs_f64() * 1000.0 / self.frames as f64;
        self.since = now;
        self.frames = 0;
        Some(ms)
    }
}

impl Default for FrameTimer {
    fn default() -> Self {
        Self::new()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    // Fails if a key listed in KEYS has no action, or two keys share one.
    #[test]
    fn every_listed_switch_key_has_its_own_action() {
        let keys = [
            (KeyCode::KeyL, 'L'),
            (KeyCode::KeyM, 'M'),
            (KeyCode::KeyV, 'V'),
            (KeyCode::KeyC, 'C'),
            (KeyCode::KeyN, 'N'),
            (KeyCode::KeyG, 'G'),
            (KeyCode::KeyH, 'H'),
            (KeyCode::KeyS, 'S'),
            (KeyCode::KeyT, 'T'),
        ];
        let mut actions = Vec::new();
        for (code, letter) in keys {
            let action = action_for_key(code).unwrap_or_else(|| panic!("{letter} has no action"));
            assert!(!actions.contains(&action), "{letter} repeats {action:?}");
            actions.push(action);
            assert!(
                KEYS.lines()
                    .any(|l| l.trim_start().starts_with(&format!("{letter} "))),
                "{letter} is not listed in KEYS"
            );
        }
        assert_eq!(action_for_key(KeyCode::KeyQ), None);
    }
}
