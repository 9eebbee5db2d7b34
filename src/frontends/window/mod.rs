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
pub mod input;
mod no_display;
mod running;
mod shader_watch;

use std::path::PathBuf;
use std::time::Instant;

use winit::application::ApplicationHandler;
use winit::event::{DeviceEvent, DeviceId, WindowEvent};
use winit::event_loop::{ActiveEventLoop, EventLoop};
use winit::window::WindowId;

use crate::frontends::events::Event;
use crate::frontends::keys::key_list;
use crate::gl::Profile;
use crate::scenes::{SceneDescriptor, SceneOptions};
use crate::{Error, Result};
use bench::{Next, PanelBench};
use no_display::{no_display_message, without_source_location};
use running::Running;

/// The original's window title, until the first frame names the scene (see
/// [`crate::frontends::host::TITLE_SHORT`] for the end of every title after that).
pub const TITLE: &str = "Tutorial 13 - Normal Mapping";

/// The command line's window-mode settings.
#[derive(Debug, Clone)]
pub struct WindowOptions {
    pub descriptor: &'static SceneDescriptor,
    /// `--tour N`: start at this step of the tour (its scene is `descriptor`), its pane shown.
    pub tour: Option<&'static crate::tour::Step>,
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

/// The event handler: routes winit's events to the open window and its host.
struct App {
    options: WindowOptions,
    running: Option<Running>,
    outcome: Result<()>,
    bench: Option<PanelBench>,
}

impl App {
    fn fail(&mut self, event_loop: &ActiveEventLoop, error: Error) {
        self.outcome = Err(error);
        event_loop.exit();
    }

    /// A frame was asked for: draw it, then swap, or (after `--frames N`) save and exit.
    fn redraw(&mut self, event_loop: &ActiveEventLoop) {
        let Some(running) = self.running.as_mut() else {
            return;
        };
        if let Some(bench) = self.bench.as_mut() {
            if running.host.panel().is_none() {
                let reason =
                    "--bench-panel: the window has no panel to measure (see the error above)";
                return self.fail(event_loop, Error::Window(reason.into()));
            }
            match bench.next_frame(Instant::now(), running.host.panel_shown()) {
                Next::Draw { panel_shown } => running.host.set_panel_shown(panel_shown),
                Next::Done => {
                    println!("{}", bench.report());
                    return event_loop.exit();
                }
            }
        }
        let drawn = running.host.frames_drawn();
        let last = self.options.frames.is_some_and(|n| drawn + 1 >= n.max(1));
        // `--panel` saves the window as shown; without it, the scene's frame alone.
        if let Err(e) = running.frame(event_loop, !last || self.options.panel) {
            return self.fail(event_loop, e);
        }
        if last {
            if let Some(path) = &self.options.screenshot {
                if let Err(e) = running.save(path) {
                    return self.fail(event_loop, e);
                }
            }
            return event_loop.exit();
        }
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
        if let WindowEvent::RedrawRequested = event {
            return self.redraw(event_loop);
        }
        let Some(running) = self.running.as_mut() else {
            return;
        };
        match &event {
            WindowEvent::CloseRequested => return event_loop.exit(),
            WindowEvent::ModifiersChanged(modifiers) => {
                running.ctrl_held = modifiers.state().control_key();
            }
            WindowEvent::Resized(size) => {
                running.gl_window.resize();
                log::debug!("resized to {}x{}", size.width, size.height);
            }
            _ => {}
        }
        running.window_event(event_loop, &event);
    }

    fn device_event(&mut self, event_loop: &ActiveEventLoop, _: DeviceId, event: DeviceEvent) {
        if let (Some(running), DeviceEvent::MouseMotion { delta }) = (self.running.as_mut(), event)
        {
            // Raw motion turns the camera only while the host has the cursor grabbed for it (a free
            // cursor moves over the window and the panel without turning it).
            running.event(event_loop, Event::Look(delta.0, delta.1));
        }
    }

    fn exiting(&mut self, _: &ActiveEventLoop) {
        // An interactive run with --screenshot saves the frame the user last saw.
        if let (Some(running), Some(path), None) = (
            self.running.as_mut(),
            self.options.screenshot.clone(),
            self.options.frames,
        ) {
            let saved = (running.host.frame(self.options.panel)).and_then(|_| running.save(&path));
            if let Err(e) = saved {
                self.outcome = Err(e);
            }
        }
        self.running = None;
    }
}
