//! The window: glutin + winit in place of the tutorial's GLFW, any scene's frame exactly as headless.
//!
//! 1024×768, "Tutorial 13 - Normal Mapping", a GL 3.3 context of the asked profile, a config without
//! multisampling (the original's screenshot test turns MSAA off, and MSAA blurs the debug lines).
//! The panel ([`super::panel`]) is painted over the frame, F1 hides it; while it shows, the cursor
//! starts free and clicks on the panel are its own. For a scene with mouse look a click on the frame
//! grabs and hides the cursor; raw mouse motion turns the camera, the arrow keys move it; Tab or
//! losing focus releases the cursor; R puts the camera back at the start; Esc or closing the window
//! quits. Letter keys go to the scene. The projection's aspect and the viewport follow the window's
//! size. Once a second "`<x> ms/frame`" is printed and shown in the title, after the scene's name and
//! main switches.

mod bench;
mod gl_window;
mod input;
mod renderer;

use std::path::{Path, PathBuf};
use std::time::Instant;

use glam::Vec2;
use winit::application::ApplicationHandler;
use winit::event::{
    DeviceEvent, DeviceId, ElementState, KeyEvent, MouseButton, MouseScrollDelta, WindowEvent,
};
use winit::event_loop::{ActiveEventLoop, EventLoop};
use winit::keyboard::{KeyCode, PhysicalKey};
use winit::window::WindowId;

use super::{key_list, FrontEnd, HostAction, HostKey};
use crate::gl::Profile;
use crate::scenes::{MouseMode, SceneDescriptor, SceneOptions};
use crate::{Error, Result};
use bench::{Next, PanelBench};
use gl_window::GlWindow;
pub use input::key_char;
use input::CursorGrab;
use renderer::Renderer;

/// The original's window title, until the first frame names the scene.
pub const TITLE: &str = "Tutorial 13 - Normal Mapping";
/// The end of every title after that (what a search for the window finds).
pub const TITLE_SHORT: &str = "Tutorial 13";

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
    /// `--panel`: screenshots of `--frames N` include the panel.
    pub panel: bool,
    /// `--bench-panel K`: time K frames with the panel shown and K hidden, print, close.
    pub bench_panel: Option<u32>,
}

/// The message for a machine without a display, with the command that works there, as the user
/// runs it from where they are (see [`super::invocation`]).
pub fn no_display_message(reason: &str) -> String {
    format!(
        "no display to open a window on ({}); render without one: \
         {} --headless --frames 1 --screenshot frame.png",
        without_source_location(reason),
        super::invocation()
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
        bench: options.bench_panel.map(PanelBench::new),
        options,
        running: None,
        outcome: Ok(()),
    };
    // winit 0.30 panics (BadDrawable, "Failed to destroy input context") when another program
    // destroys the window instead of closing it: its X11 back end `expect`s every input-method call
    // (upstream: rust-windowing/winit#480, seen again in bevyengine/bevy#11150), so there is no
    // error to handle. That panic alone is caught here and becomes one error line (and its message
    // is kept off the terminal); any other panic is re-raised as it was.
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

/// What a key event is to the window: a new press runs the key's action once; a repeat (the key
/// held down) or a synthetic press (focus gained with the key down) only keeps an arrow key held.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum KeyPress {
    New,
    Again,
    Released,
}

/// The event handler: routes winit's events to the window, the input state and the renderer.
struct App {
    options: WindowOptions,
    running: Option<Running>,
    outcome: Result<()>,
    bench: Option<PanelBench>,
}

/// Everything alive while the window is open. Field order is drop order: the scene's and the
/// panel's GL objects first, then the window with its surface and context.
struct Running {
    renderer: Renderer,
    /// Whether the cursor is grabbed for mouse look.
    grab: CursorGrab,
    /// egui's winit glue, which turns the window's events into the panel's input (`None` if the
    /// panel's painter could not be built: the window runs without it).
    panel_glue: Option<egui_winit::State>,
    /// Ctrl is held (Ctrl+P saves the window as shown, the panel with it).
    ctrl_held: bool,
    gl_window: GlWindow,
}

/// egui's input for the panel's next frame: what `egui_winit::State::take_egui_input` gives, but
/// for the `size` the frame was drawn at, where that function asks the X server again (a round
/// trip: 0.15 ms a frame under Xvfb).
fn take_panel_input(
    state: &mut egui_winit::State,
    window: &winit::window::Window,
    (width, height): (u32, u32),
    seconds: f64,
) -> egui::RawInput {
    let pixels = egui::vec2(width as f32, height as f32);
    // winit keeps the scale factor; reading it asks the server nothing.
    let points = pixels / egui_winit::pixels_per_point(state.egui_ctx(), window);
    let input = state.egui_input_mut();
    input.time = Some(seconds);
    input.screen_rect = Some(egui::Rect::from_min_size(egui::Pos2::ZERO, points));
    input.viewport_id = egui::ViewportId::ROOT;
    let viewport = input.viewports.entry(egui::ViewportId::ROOT).or_default();
    viewport.native_pixels_per_point = Some(window.scale_factor() as f32);
    input.take()
}

impl Running {
    fn new(event_loop: &ActiveEventLoop, options: &WindowOptions) -> Result<Self> {
        let gl_window = GlWindow::open(event_loop, options.size, options.profile, options.msaa)?;
        let mut renderer = Renderer::new(&gl_window, options.descriptor, &options.scene)?;
        let panel_glue = match renderer.host.show_panel() {
            Ok(panel) => {
                panel.store_cache_like_a_window();
                let window = &gl_window.window;
                Some(egui_winit::State::new(
                    panel.context().clone(),
                    egui::ViewportId::ROOT,
                    window,
                    Some(window.scale_factor() as f32),
                    None,
                    None,
                ))
            }
            Err(e) => {
                log::error!("{e} (the window runs without its panel)");
                None
            }
        };
        let mut running = Running {
            renderer,
            grab: CursorGrab::default(),
            panel_glue,
            ctrl_held: false,
            gl_window,
        };
        // With the panel shown the cursor starts free, so that the panel can be clicked; a click on
        // the frame grabs it for mouse look, as it does after Tab.
        if options.frames.is_none() && !running.renderer.host.panel_shown() {
            running.grab_cursor(true);
        } else if options.frames.is_none()
            && running.renderer.host.descriptor().mouse_mode == MouseMode::Look
        {
            log::info!("click the frame to look around (F1 hides the panel)");
        }
        Ok(running)
    }

    /// Lays out and paints the panel over the frame just drawn (before the swap), if it is shown.
    fn paint_panel(&mut self) {
        let host = &mut self.renderer.host;
        let Some(state) = self.panel_glue.as_mut().filter(|_| host.panel_shown()) else {
            return;
        };
        let window = &self.gl_window.window;
        let seconds = host.clock.seconds();
        let input = take_panel_input(state, window, host.size(), seconds);
        let platform = host.draw_panel(input);
        // The cursor's shape is egui's only while it is free (a grabbed cursor stays hidden).
        if let (Some(platform), false) = (platform, self.grab.grabbed()) {
            state.handle_platform_output(window, platform);
        }
    }

    /// Whether the panel takes this event (a click or a wheel over it), so that the frame does not.
    fn panel_takes(&mut self, event: &WindowEvent) -> bool {
        let Some(state) = self.panel_glue.as_mut() else {
            return false;
        };
        let panel_shown = self.renderer.host.panel_shown();
        // Every button release reaches egui, also one that comes while the cursor is grabbed or
        // the panel hidden: the click that grabs the cursor went down before the grab, and egui,
        // never told of its release, would hold the button down and ignore every later click.
        // egui clicks a widget only on a press and a release over it, so this clicks nothing.
        if let WindowEvent::MouseInput {
            state: ElementState::Released,
            ..
        } = event
        {
            let consumed = state
                .on_window_event(&self.gl_window.window, event)
                .consumed;
            return consumed && panel_shown && !self.grab.grabbed();
        }
        // Keys stay the scene's and the window's; a grabbed cursor is mouse look, not a pointer.
        let keys = matches!(event, WindowEvent::KeyboardInput { .. });
        if !panel_shown || keys || self.grab.grabbed() {
            return false;
        }
        state
            .on_window_event(&self.gl_window.window, event)
            .consumed
    }

    fn grab_cursor(&mut self, grab: bool) {
        let mode = self.renderer.host.descriptor().mouse_mode;
        if self.grab.set(&self.gl_window.window, grab, mode) {
            self.renderer.host.forget_motion();
        }
    }

    fn frame(&mut self, frozen: bool) -> Result<()> {
        self.renderer.frame(&self.gl_window, frozen)
    }

    /// A frame drawn to be read back for a screenshot: the scene's alone, or with the panel over
    /// it (`with_panel`: the window as shown).
    fn frame_to_save(&mut self, frozen: bool, with_panel: bool) -> Result<()> {
        self.frame(frozen)?;
        if with_panel {
            self.paint_panel();
        }
        Ok(())
    }

    /// A file dropped on the window (an .obj: `--model`); an error (an unreadable model, another
    /// kind of file) is logged and the scene stays.
    fn open_file(&mut self, path: &Path) {
        let opened = self.renderer.open_file(path);
        self.start_scene(opened);
    }

    /// Enter: the next scene.
    fn next_scene(&mut self) {
        let switched = self.renderer.next_scene();
        self.start_scene(switched);
    }

    /// After the host built another scene (its camera at the start) or failed to: the cursor as
    /// the new scene wants it, or the error logged.
    fn start_scene(&mut self, built: Result<()>) {
        match built {
            Ok(()) => {
                self.grab_cursor(false);
                // As at the start: while the panel shows the cursor stays free for it, and a
                // click on the frame grabs it.
                if !self.renderer.host.panel_shown() {
                    self.grab_cursor(true);
                }
            }
            Err(e) => log::error!("{e}"),
        }
    }

    /// A key went down or up.
    fn key(&mut self, event_loop: &ActiveEventLoop, code: KeyCode, press: KeyPress) {
        if let Some(arrow) = input::arrow(code) {
            return self.renderer.host.arrow(arrow, press != KeyPress::Released);
        }
        if press != KeyPress::New {
            return;
        }
        let action = input::host_key_name(code).and_then(|k| HostKey::find(k, FrontEnd::Window));
        match action {
            Some(HostAction::Quit) => event_loop.exit(),
            Some(HostAction::ReleaseCursor) => self.grab_cursor(false),
            Some(HostAction::NextScene) => self.next_scene(),
            Some(HostAction::ReloadShaders) => self.renderer.reload_shaders(),
            Some(HostAction::TogglePanel) => self.renderer.host.toggle_panel(),
            Some(HostAction::ResetCamera) => {
                self.renderer.host.reset_camera();
                log::info!("camera back at the start");
            }
            Some(HostAction::Screenshot) => {
                // The frame on screen is the front buffer: draw it again and read it back, before
                // the panel is painted over it (P), or after (Ctrl+P: the window as shown).
                let saved = self
                    .frame_to_save(true, self.ctrl_held)
                    .and_then(|()| self.renderer.save_numbered(&self.gl_window));
                if let Err(e) = saved {
                    log::error!("{e}");
                }
            }
            None => {
                if let Some(key) = key_char(code) {
                    self.renderer.scene_key(key);
                }
            }
        }
    }

    /// A left click: grabs the cursor for mouse look, or goes to a scene that uses the cursor.
    fn click(&mut self) {
        match self.renderer.host.descriptor().mouse_mode {
            MouseMode::Look => self.grab_cursor(true),
            MouseMode::Cursor => self.renderer.host.click(),
        }
    }
}

impl App {
    fn fail(&mut self, event_loop: &ActiveEventLoop, error: Error) {
        self.outcome = Err(error);
        event_loop.exit();
    }

    fn frozen(&self) -> bool {
        self.options.frames.is_some()
    }

    /// A frame was asked for: draw it, then swap, or (after `--frames N`) save and exit.
    fn redraw(&mut self, event_loop: &ActiveEventLoop) {
        let frozen = self.frozen();
        let Some(running) = self.running.as_mut() else {
            return;
        };
        if let Some(bench) = self.bench.as_mut() {
            if running.renderer.host.panel().is_none() {
                let reason =
                    "--bench-panel: the window has no panel to measure (see the error above)";
                return self.fail(event_loop, Error::Window(reason.into()));
            }
            match bench.next_frame(Instant::now(), running.renderer.host.panel_shown()) {
                Next::Draw { panel_shown } => running.renderer.host.set_panel_shown(panel_shown),
                Next::Done => {
                    println!("{}", bench.report());
                    return event_loop.exit();
                }
            }
        }
        if let Err(e) = running.frame(frozen) {
            return self.fail(event_loop, e);
        }
        let done = self
            .options
            .frames
            .is_some_and(|n| running.renderer.frames_drawn >= n.max(1));
        if done {
            // `--panel` saves the window as shown; without it, the scene's frame alone.
            if self.options.panel {
                running.paint_panel();
            }
            if let Some(path) = &self.options.screenshot {
                if let Err(e) = renderer::save(&running.gl_window, path) {
                    return self.fail(event_loop, e);
                }
            }
            return event_loop.exit();
        }
        running.paint_panel();
        if let Err(e) = running.gl_window.swap_buffers() {
            return self.fail(event_loop, e);
        }
        running.gl_window.window.request_redraw();
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
                running.gl_window.window.request_redraw();
                self.running = Some(running);
            }
            Err(e) => self.fail(event_loop, e),
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let frozen = self.frozen();
        if let WindowEvent::RedrawRequested = event {
            return self.redraw(event_loop);
        }
        let Some(running) = self.running.as_mut() else {
            return;
        };
        if running.panel_takes(&event) {
            return;
        }
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::ModifiersChanged(modifiers) => {
                running.ctrl_held = modifiers.state().control_key();
            }
            WindowEvent::KeyboardInput {
                event:
                    KeyEvent {
                        physical_key: PhysicalKey::Code(code),
                        state,
                        repeat,
                        ..
                    },
                is_synthetic,
                ..
            } => {
                let pressed = state == ElementState::Pressed;
                if repeat {
                    log::debug!("{code:?} repeated (held down)");
                }
                // A key held down repeats, and a window gaining focus with a key down gets a
                // synthetic press: neither is a new press, so neither runs an action again (a
                // toggle would flip twice, P would save two screenshots). A held arrow key still
                // counts as held, and every release is taken.
                let press = match (pressed, repeat || is_synthetic) {
                    (true, false) => KeyPress::New,
                    (true, true) => KeyPress::Again,
                    (false, _) => KeyPress::Released,
                };
                running.key(event_loop, code, press)
            }
            WindowEvent::CursorMoved { position, .. } => {
                let at = Vec2::new(position.x as f32, position.y as f32);
                // Over the panel the cursor is the panel's: to the scene it has left the frame (a
                // light that follows it stays where it was).
                let host = &mut running.renderer.host;
                host.cursor = Some(at).filter(|&at| !host.over_panel(at));
            }
            WindowEvent::CursorLeft { .. } => running.renderer.host.cursor = None,
            WindowEvent::Focused(false) => running.grab_cursor(false),
            WindowEvent::MouseInput {
                state: ElementState::Pressed,
                button: MouseButton::Left,
                ..
            } if !frozen => running.click(),
            WindowEvent::MouseWheel { delta, .. } if !frozen => {
                let notches = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y,
                    // Touchpads report pixels; about 20 make one notch of a wheel.
                    MouseScrollDelta::PixelDelta(p) => p.y as f32 / 20.0,
                };
                running.renderer.host.scroll(notches);
            }
            WindowEvent::DroppedFile(path) => running.open_file(&path),
            WindowEvent::Resized(size) => {
                running.gl_window.resize();
                log::debug!("resized to {}x{}", size.width, size.height);
            }
            _ => {}
        }
    }

    fn device_event(&mut self, _: &ActiveEventLoop, _: DeviceId, event: DeviceEvent) {
        if let (Some(running), DeviceEvent::MouseMotion { delta }) = (self.running.as_mut(), event)
        {
            // Raw motion turns the camera only while the cursor is grabbed for it (a free cursor
            // moves over the window and the panel without turning it).
            if running.grab.grabbed() {
                running.renderer.host.look(delta);
            }
        }
    }

    fn exiting(&mut self, _: &ActiveEventLoop) {
        // An interactive run with --screenshot saves the frame the user last saw.
        if let (Some(running), Some(path), None) = (
            self.running.as_mut(),
            self.options.screenshot.clone(),
            self.options.frames,
        ) {
            let saved = running
                .frame_to_save(false, self.options.panel)
                .and_then(|()| renderer::save(&running.gl_window, &path));
            if let Err(e) = saved {
                self.outcome = Err(e);
            }
        }
        self.running = None;
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
