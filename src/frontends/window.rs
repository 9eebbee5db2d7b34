//! The window: glutin + winit in place of the tutorial's GLFW, any scene's frame exactly as headless.
//!
//! 1024×768, "Tutorial 13 - Normal Mapping", a GL 3.3 context of the asked profile, a config without
//! multisampling (the original's screenshot test turns MSAA off, and MSAA blurs the debug lines).
//! For a scene with mouse look the cursor is grabbed and hidden; raw mouse motion turns the camera,
//! the arrow keys move it; Tab or losing focus releases the cursor and a click grabs it again; R puts
//! the camera back at the tutorial's start; Esc or closing the window quits. Letter keys go to the
//! scene. The projection's aspect and the viewport follow the window's size. Once a second
//! "<x> ms/frame" is printed and shown in the title, beside the scene's status.

use std::ffi::CString;
use std::num::NonZeroU32;
use std::path::PathBuf;
use std::time::Instant;

use glam::Vec2;
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
use winit::event::{
    DeviceEvent, DeviceId, ElementState, KeyEvent, MouseButton, MouseScrollDelta, WindowEvent,
};
use winit::event_loop::{ActiveEventLoop, EventLoop};
use winit::keyboard::{KeyCode, PhysicalKey};
use winit::window::{CursorGrabMode, Window, WindowId};

use super::{key_list, FrameTimer, ShaderWatch};
use crate::common::controls::{Controls, Input};
use crate::gl::image::{read_pixels_rgba, write_screenshot};
use crate::gl::offscreen::OffscreenTarget;
use crate::gl::{check_gl_errors, context_info, ContextInfo, Gl, Profile};
use crate::scenes::{FrameInput, MouseMode, Scene, SceneContext, SceneDescriptor, SceneOptions};
use crate::{Error, Result};

pub const TITLE: &str = "Tutorial 13 - Normal Mapping";

/// The command line's window-mode settings.
#[derive(Debug, Clone)]
pub struct WindowOptions {
    pub descriptor: &'static SceneDescriptor,
    pub scene: SceneOptions,
    pub size: (u32, u32),
    pub profile: Profile,
    /// Render this many frames with time frozen at 0, then exit.
    pub frames: Option<u32>,
    /// Save the last frame here.
    pub screenshot: Option<PathBuf>,
    /// Samples per pixel of the window's config (`--msaa`; 0 = none).
    pub msaa: u8,
}

/// The message for a machine without a display, with the command that works there.
pub fn no_display_message(reason: &str) -> String {
    format!(
        "no display to open a window on ({}); render without one: \
         tutorial13 --headless --frames 1 --screenshot frame.png",
        without_source_location(reason)
    )
}

/// winit's OS errors read "os error at /home/.../winit-0.30/src/...rs:788: Failed to open ...": the
/// user needs the reason, not where in winit's source it was raised.
fn without_source_location(reason: &str) -> String {
    const MARK: &str = "os error at ";
    match reason.find(MARK) {
        Some(start) => match reason[start + MARK.len()..].find(": ") {
            Some(end) => {
                let rest = &reason[start + MARK.len() + end + 2..];
                format!("{}{rest}", &reason[..start])
            }
            None => reason.to_string(),
        },
        None => reason.to_string(),
    }
}

/// Opens the window and runs until Esc, a close, or `frames` frames.
pub fn run_window(options: WindowOptions) -> Result<()> {
    let no_var = |name: &str| std::env::var_os(name).is_none_or(|v| v.is_empty());
    if no_var("DISPLAY") && no_var("WAYLAND_DISPLAY") {
        return Err(Error::Window(no_display_message(
            "neither DISPLAY nor WAYLAND_DISPLAY is set",
        )));
    }
    let event_loop =
        EventLoop::new().map_err(|e| Error::Window(no_display_message(&e.to_string())))?;
    let mut app = App {
        options,
        running: None,
        outcome: Ok(()),
    };
    // winit 0.30 panics (BadDrawable, "Failed to destroy input context") when another program
    // destroys the window instead of closing it. That panic is caught here and becomes one error
    // line; any other panic is re-raised as it was.
    let previous_hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        if !is_window_destroyed_panic(info.payload()) {
            previous_hook(info);
        }
    }));
    let ran = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        event_loop.run_app(&mut app)
    }));
    let _ = std::panic::take_hook(); // back to the default hook
    let destroyed =
        || Error::Window("the window was destroyed by another program (not closed)".into());
    match ran {
        Ok(Ok(())) => app.outcome,
        // The same X errors can also come back from the event loop as an error (GLXBadWindow).
        Ok(Err(e)) if is_window_gone(&e.to_string()) => Err(destroyed()),
        Ok(Err(e)) => Err(Error::Window(format!(
            "event loop: {}",
            without_source_location(&e.to_string())
        ))),
        Err(payload) if is_window_destroyed_panic(payload.as_ref()) => {
            // The GL objects of a window that no longer exists: dropped without touching it.
            std::mem::forget(app.running.take());
            Err(destroyed())
        }
        Err(payload) => std::panic::resume_unwind(payload),
    }
}

/// Whether a panic is winit's on a window destroyed from outside: an X error for a drawable or
/// window that is gone, raised in its event processing or a geometry query.
fn is_window_destroyed_panic(payload: &(dyn std::any::Any + Send)) -> bool {
    let message = payload
        .downcast_ref::<String>()
        .map(String::as_str)
        .or_else(|| payload.downcast_ref::<&str>().copied())
        .unwrap_or("");
    is_window_gone(message)
}

/// Whether an X error message says the window (or its drawable) no longer exists.
fn is_window_gone(message: &str) -> bool {
    // Xlib's and GLX's names (BadDrawable, BadWindow, GLXBadWindow) and x11rb's error kinds.
    [
        "BadDrawable",
        "BadWindow",
        "error_kind: Drawable",
        "error_kind: Window",
    ]
    .iter()
    .any(|mark| message.contains(mark))
}

struct App {
    options: WindowOptions,
    running: Option<Running>,
    outcome: Result<()>,
}

/// Everything alive while the window is open. Field order is drop order: the GL objects first, then
/// the surface and context, then the window.
struct Running {
    scene: Box<dyn Scene>,
    descriptor: &'static SceneDescriptor,
    scene_options: SceneOptions,
    info: ContextInfo,
    gl: Gl,
    surface: Surface<WindowSurface>,
    context: PossiblyCurrentContext,
    window: Window,
    controls: Controls,
    input: Input,
    /// The cursor in window pixels, for scenes that follow it.
    cursor: Option<Vec2>,
    start: Instant,
    last_time: Instant,
    frames_drawn: u32,
    timer: FrameTimer,
    /// The last "ms/frame" figure, kept for the title.
    ms_per_frame: Option<f64>,
    /// The title the window has now (set again only when it changes).
    shown_title: String,
    screenshots_taken: u32,
    /// Saving a shader file reloads the scene's programs.
    shader_watch: ShaderWatch,
    /// The last reload's error, for the title, until a good version is saved.
    shader_error: Option<String>,
    /// Samples per pixel of the window's buffers (`--msaa`).
    samples: i32,
    /// The cursor is grabbed and hidden for mouse look (only in a scene that wants it).
    grabbed: bool,
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
                // Only now: a failure before this point prints its error alone, not after the keys.
                println!("{}", key_list(self.options.descriptor));
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
                    KeyCode::Tab if pressed => running.set_cursor_grab(false),
                    KeyCode::Enter if pressed => {
                        if let Err(e) =
                            running.switch_scene(crate::scenes::next(running.descriptor))
                        {
                            log::error!("{e}");
                        }
                    }
                    KeyCode::F5 if pressed => running.reload_shaders(),
                    KeyCode::KeyR if pressed => {
                        running.controls = Controls::default();
                        log::info!("camera back at the tutorial's start");
                    }
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
                        if let Some(key) = key_char(code) {
                            match running.scene.key(key) {
                                Ok(true) => log::info!("{}", running.scene.status()),
                                Ok(false) => {}
                                Err(e) => log::error!("{e}"),
                            }
                        }
                    }
                    _ => {}
                }
            }
            WindowEvent::CursorMoved { position, .. } => {
                running.cursor = Some(Vec2::new(position.x as f32, position.y as f32));
            }
            WindowEvent::CursorLeft { .. } => running.cursor = None,
            WindowEvent::Focused(false) => running.set_cursor_grab(false),
            WindowEvent::MouseInput {
                state: ElementState::Pressed,
                button: MouseButton::Left,
                ..
            } if !frozen => match running.descriptor.mouse_mode {
                MouseMode::Look => running.set_cursor_grab(true),
                MouseMode::Cursor => running.scene.click(),
            },
            WindowEvent::MouseWheel { delta, .. } if !frozen => {
                let notches = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y,
                    // Touchpads report pixels; about 20 make one notch of a wheel.
                    MouseScrollDelta::PixelDelta(p) => p.y as f32 / 20.0,
                };
                running.scene.scroll(notches);
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
                            let error = Error::Window(format!("swap buffers: {e}"));
                            return self.fail(event_loop, error);
                        }
                        running.window.request_redraw();
                    }
                }
            }
            _ => {}
        }
    }

    fn device_event(&mut self, _: &ActiveEventLoop, _: DeviceId, event: DeviceEvent) {
        // Raw motion: the same pixel deltas the tutorial reads after re-centring the cursor. Only
        // while the cursor is grabbed: a released cursor moves freely without turning the camera.
        if let (Some(running), DeviceEvent::MouseMotion { delta }) = (self.running.as_mut(), event)
        {
            if !running.grabbed {
                return;
            }
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

/// One short line for the title: which file failed and how (the log itself is on stderr).
fn shader_error_title(error: &Error) -> String {
    match error {
        Error::Shader { path, stage, .. } => {
            let file = path.file_name().unwrap_or(path.as_os_str());
            format!(
                "shader {stage} failed: {} (log on the terminal; the last good shaders draw)",
                file.to_string_lossy()
            )
        }
        other => format!("shader reload failed: {other}"),
    }
}

/// The character a scene's key list names for `code`: letters upper-case, digits.
pub fn key_char(code: KeyCode) -> Option<char> {
    const LETTERS: [KeyCode; 26] = [
        KeyCode::KeyA,
        KeyCode::KeyB,
        KeyCode::KeyC,
        KeyCode::KeyD,
        KeyCode::KeyE,
        KeyCode::KeyF,
        KeyCode::KeyG,
        KeyCode::KeyH,
        KeyCode::KeyI,
        KeyCode::KeyJ,
        KeyCode::KeyK,
        KeyCode::KeyL,
        KeyCode::KeyM,
        KeyCode::KeyN,
        KeyCode::KeyO,
        KeyCode::KeyP,
        KeyCode::KeyQ,
        KeyCode::KeyR,
        KeyCode::KeyS,
        KeyCode::KeyT,
        KeyCode::KeyU,
        KeyCode::KeyV,
        KeyCode::KeyW,
        KeyCode::KeyX,
        KeyCode::KeyY,
        KeyCode::KeyZ,
    ];
    const DIGITS: [KeyCode; 10] = [
        KeyCode::Digit0,
        KeyCode::Digit1,
        KeyCode::Digit2,
        KeyCode::Digit3,
        KeyCode::Digit4,
        KeyCode::Digit5,
        KeyCode::Digit6,
        KeyCode::Digit7,
        KeyCode::Digit8,
        KeyCode::Digit9,
    ];
    if let Some(i) = LETTERS.iter().position(|&c| c == code) {
        return Some((b'A' + i as u8) as char);
    }
    DIGITS
        .iter()
        .position(|&c| c == code)
        .map(|i| (b'0' + i as u8) as char)
}

/// glutin's example picks the config with the most samples; the tutorial's frame wants none unless
/// `--msaa N` asks for N, and a 24-bit depth buffer (GLFW's default) where there is one. `Err` lists
/// the sample counts the display has when none has N.
fn pick_config(
    configs: Box<dyn Iterator<Item = Config> + '_>,
    msaa: u8,
) -> std::result::Result<Config, Vec<u8>> {
    let configs: Vec<Config> = configs.collect();
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

/// Opens the window with a config from [`pick_config`]. glutin-winit's picker must return a config,
/// so a display with none at all is carried out of it as a silent unwind and turned into an error.
fn build_window(
    event_loop: &ActiveEventLoop,
    attributes: winit::window::WindowAttributes,
    msaa: u8,
) -> Result<(Option<Window>, Config)> {
    struct NoConfig(Vec<u8>);
    let previous_hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(|info| {
        if info.payload().downcast_ref::<NoConfig>().is_none() {
            eprintln!("{info}");
        }
    }));
    let template = match msaa {
        0 => ConfigTemplateBuilder::new(),
        n => ConfigTemplateBuilder::new().with_multisampling(n),
    };
    let built = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        DisplayBuilder::new()
            .with_window_attributes(Some(attributes))
            .build(event_loop, template, |configs| {
                pick_config(configs, msaa)
                    .unwrap_or_else(|counts| std::panic::panic_any(NoConfig(counts)))
            })
    }));
    std::panic::set_hook(previous_hook);
    match built {
        // A display was opened (winit's event loop has one), so a failure here with a sample count
        // asked for is that count missing: say so rather than "no display".
        Ok(Err(e)) if msaa > 0 => Err(Error::Window(format!(
            "the display has no framebuffer configuration with {msaa} samples per pixel (--msaa): {e}"
        ))),
        Ok(result) => result.map_err(|e| Error::Window(no_display_message(&e.to_string()))),
        Err(payload) if payload.is::<NoConfig>() => {
            let counts = &payload.downcast_ref::<NoConfig>().expect("checked").0;
            Err(Error::Window(if counts.is_empty() {
                "the display offers no OpenGL framebuffer configuration".into()
            } else {
                format!(
                    "the display has no framebuffer configuration with {msaa} samples per pixel \
                     (--msaa): it offers {counts:?}"
                )
            }))
        }
        Err(payload) => std::panic::resume_unwind(payload),
    }
}

impl Running {
    fn new(event_loop: &ActiveEventLoop, options: &WindowOptions) -> Result<Self> {
        let (width, height) = options.size;
        let attributes = Window::default_attributes()
            .with_title(TITLE)
            .with_inner_size(PhysicalSize::new(width, height));
        let (window, config) = build_window(event_loop, attributes, options.msaa)?;
        let window = window.ok_or_else(|| Error::Window("it could not be created".into()))?;
        let display = config.display();
        let handle = window
            .window_handle()
            .map_err(|e| Error::Window(format!("window handle: {e}")))?
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
            Error::Context(format!(
                "no OpenGL 3.3 {} context on this display: {e}",
                options.profile
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
        let gl: Gl = std::rc::Rc::new(unsafe {
            glow::Context::from_loader_function(|name| {
                let name = CString::new(name).expect("GL names have no NUL");
                display.get_proc_address(&name)
            })
        });
        let info = context_info(&gl);
        if !info.at_least(3, 3) || info.profile != options.profile {
            return Err(Error::Context(format!(
                "OpenGL 3.3 {} is needed, the display gave {info}",
                options.profile
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

        let loader = |name: &std::ffi::CStr| display.get_proc_address(name);
        let scene_context = SceneContext {
            gl: &gl,
            info: &info,
            loader: &loader,
        };
        let scene = (options.descriptor.build)(&scene_context, &options.scene)?;
        log::info!("{}", scene.status());
        let now = Instant::now();
        let shader_watch = ShaderWatch::new(&*scene);
        let mut running = Running {
            scene,
            descriptor: options.descriptor,
            scene_options: options.scene.clone(),
            info,
            gl,
            surface,
            context,
            window,
            controls: Controls::default(),
            input: Input::default(),
            cursor: None,
            start: now,
            last_time: now,
            frames_drawn: 0,
            timer: FrameTimer::new(),
            ms_per_frame: None,
            shown_title: String::new(),
            screenshots_taken: 0,
            shader_watch,
            shader_error: None,
            samples,
            grabbed: false,
        };
        if options.frames.is_none() {
            running.set_cursor_grab(true);
        }
        Ok(running)
    }

    /// The scene key: builds `name` on this context (the current scene stays if that fails), drops
    /// the old scene's GL objects, and prints the new scene's keys.
    fn switch_scene(&mut self, name: &'static SceneDescriptor) -> Result<()> {
        let display = self.context.display();
        let loader = |symbol: &std::ffi::CStr| display.get_proc_address(symbol);
        let scene_context = SceneContext {
            gl: &self.gl,
            info: &self.info,
            loader: &loader,
        };
        let scene = (name.build)(&scene_context, &self.scene_options)?;
        self.set_cursor_grab(false);
        self.scene = scene;
        self.descriptor = name;
        self.shader_watch = ShaderWatch::new(&*self.scene);
        self.shader_error = None;
        self.controls = Controls::default();
        self.set_cursor_grab(true);
        println!("{}", key_list(name));
        log::info!("scene {name}: {}", self.scene.status());
        Ok(())
    }

    /// Grabs (and hides) the cursor for mouse look, or releases it. A scene that follows the absolute
    /// cursor is never grabbed.
    fn set_cursor_grab(&mut self, grab: bool) {
        let grab = grab && self.descriptor.mouse_mode == MouseMode::Look;
        if grab == self.grabbed {
            return;
        }
        if grab {
            let grabbed = self
                .window
                .set_cursor_grab(CursorGrabMode::Locked)
                .or_else(|_| self.window.set_cursor_grab(CursorGrabMode::Confined));
            if let Err(e) = grabbed {
                log::warn!(
                    "cursor not grabbed ({e}): mouse look still works while it is over the window"
                );
            }
        } else {
            if let Err(e) = self.window.set_cursor_grab(CursorGrabMode::None) {
                log::warn!("cursor not released: {e}");
            }
            log::info!("cursor released: click the window to look around again");
        }
        self.window.set_cursor_visible(!grab);
        self.input.mouse_dx = 0.0;
        self.input.mouse_dy = 0.0;
        self.grabbed = grab;
    }

    /// "Tutorial 13 - Normal Mapping - 3.2 ms/frame - view lit | lines off | ...": the figure and
    /// the scene's switches together, so that neither hides the other; a shader that failed to
    /// reload comes first. Called after every frame, so that whatever changed the scene (a key, the
    /// mouse moving a light, the wheel) shows at once; the window is told only of a change.
    fn update_title(&mut self) {
        let ms = self
            .ms_per_frame
            .map_or(String::new(), |ms| format!(" - {ms:.3} ms/frame"));
        let error = self
            .shader_error
            .as_ref()
            .map_or(String::new(), |e| format!(" - {e}"));
        let title = format!("{TITLE}{error}{ms} - {}", self.scene.status());
        if title != self.shown_title {
            self.window.set_title(&title);
            self.shown_title = title;
        }
    }

    /// Live shader editing: compiles the scene's shaders again. A shader that does not compile
    /// leaves the last good programs drawing; its driver log goes to stderr and a short line to the
    /// title until a good version is saved.
    fn reload_shaders(&mut self) {
        match self.scene.reload_shaders() {
            Ok(()) => {
                log::info!("shaders reloaded");
                self.shader_error = None;
            }
            Err(e) => {
                eprintln!("tutorial13: {e}");
                self.shader_error = Some(shader_error_title(&e));
            }
        }
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
        if self.shader_watch.changed(&*self.scene, now) {
            self.reload_shaders();
        }
        let input = if frozen { Input::default() } else { self.input };
        let size = self.window.inner_size();
        // The viewport and the projection's aspect follow the window (1024×768 is the tutorial's 4:3).
        self.controls.set_viewport(size.width, size.height);
        self.controls
            .compute_matrices_from_inputs(&input, delta_time);
        self.input.mouse_dx = 0.0;
        self.input.mouse_dy = 0.0;

        // SAFETY: a viewport of the window's size on the current context.
        unsafe {
            self.gl
                .viewport(0, 0, size.width as i32, size.height as i32)
        };
        let time = if frozen {
            0.0
        } else {
            (now - self.start).as_secs_f32()
        };
        self.scene.draw(&FrameInput {
            projection: self.controls.projection_matrix(),
            view: self.controls.view_matrix(),
            cursor: self.cursor,
            size: (size.width, size.height),
            time,
        });
        check_gl_errors(&self.gl, "frame")?;
        self.frames_drawn += 1;
        if let Some(ms) = self.timer.tick(now) {
            println!("{ms:.3} ms/frame");
            self.ms_per_frame = Some(ms);
        }
        self.update_title();
        Ok(())
    }

    /// Reads the back buffer (the frame just drawn) and writes it as PNG.
    fn save(&self, path: &std::path::Path) -> Result<()> {
        let size = self.window.inner_size();
        let (w, h) = (
            NonZeroU32::new(size.width).map_or(1, |v| v.get()),
            NonZeroU32::new(size.height).map_or(1, |v| v.get()),
        );
        let image = if self.samples > 0 {
            // Mesa's glReadPixels on a multisampled window buffer does not give the frame the
            // window shows (measured: 2006 pixels differ from an xwd capture, which equals the
            // headless frame): resolve it into a single-sampled target first, as the swap does.
            let display = self.context.display();
            let loader = |name: &std::ffi::CStr| display.get_proc_address(name);
            let target =
                OffscreenTarget::with_window_orientation(&self.gl, (w, h), 0, &self.info, loader)?;
            target.blit_from(None);
            target.read_rgba()
        } else {
            read_pixels_rgba(&self.gl, w, h)
        };
        write_screenshot(path, &image)?;
        log::info!("wrote {}", path.display());
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    // Fails if winit's source path reaches the user's error line, or if other reasons are altered.
    #[test]
    fn display_errors_drop_winits_source_path() {
        let winit =
            "os error at /root/.cargo/registry/src/x/winit-0.30.13/src/platform_impl/linux/\
                     mod.rs:788: Failed to open connection to X server";
        let message = no_display_message(winit);
        assert!(
            message.contains("(Failed to open connection to X server)"),
            "{message}"
        );
        assert!(
            !message.contains(".rs:") && !message.contains("cargo"),
            "{message}"
        );
        let plain = "neither DISPLAY nor WAYLAND_DISPLAY is set";
        assert!(no_display_message(plain).contains(&format!("({plain})")));
    }

    // Fails if a key a scene lists cannot be typed: every listed key must map back from a key code.
    #[test]
    fn every_listed_scene_key_can_be_typed() {
        let typeable: Vec<char> = [
            KeyCode::KeyA,
            KeyCode::KeyZ,
            KeyCode::Digit0,
            KeyCode::Digit9,
        ]
        .into_iter()
        .filter_map(key_char)
        .collect();
        assert_eq!(typeable, ['A', 'Z', '0', '9']);
        assert_eq!(key_char(KeyCode::Escape), None);
        for scene in crate::scenes::SCENES {
            for help in scene.keys {
                assert!(
                    help.key.is_ascii_uppercase() || help.key.is_ascii_digit(),
                    "{scene}: key {:?} cannot be typed",
                    help.key
                );
            }
        }
    }
}
