//! The open window: the scene host it drives, and what only a window does for it: the panel's cursor
//! shape, Ctrl, numbered screenshots, the shader files it watches, the title, and each of the host's
//! requests done ([`Running::honour`]).

use std::path::{Path, PathBuf};
use std::time::Instant;

use winit::event::WindowEvent;
use winit::event_loop::ActiveEventLoop;

use super::gl_window::GlWindow;
use super::input::{grab_cursor, translate};
use super::shader_watch::ShaderWatch;
use super::WindowOptions;
use crate::frontends::events::{Event, FrameTime, Request};
use crate::frontends::host::SceneHost;
use crate::frontends::keys::key_list;
use crate::gl::image::write_screenshot;
use crate::Result;

/// Everything alive while the window is open. Field order is drop order: the scene's and the
/// panel's GL objects first, then the window with its surface and context.
pub struct Running {
    /// The scene, its camera, input, clock and panel: every input reaches the scene through it.
    pub host: SceneHost,
    /// egui's winit glue, which sets the cursor's shape the panel asks for (`None` if the panel's
    /// painter could not be built: the window runs without it).
    panel_glue: Option<egui_winit::State>,
    /// Ctrl is held (Ctrl+P saves the window as shown, the panel with it).
    pub ctrl_held: bool,
    screenshots_taken: u32,
    /// Saving a shader file reloads the scene's programs.
    shader_watch: ShaderWatch,
    pub gl_window: GlWindow,
}

impl Running {
    /// Opens the window, builds the scene on its context and shows the panel; the cursor as a new
    /// window wants it.
    pub fn new(event_loop: &ActiveEventLoop, options: &WindowOptions) -> Result<Self> {
        let (gl_window, gl) =
            GlWindow::open(event_loop, options.size, options.profile, options.msaa)?;
        let size = gl_window.size();
        let time = match options.frames {
            Some(_) => FrameTime::Frozen,
            None => FrameTime::Running,
        };
        let mut host = SceneHost::for_window(gl, options.descriptor, &options.scene, size, time)?;
        if let Some(step) = options.tour {
            host.set_step_state(step)?;
        }
        let window = &gl_window.window;
        host.event(Event::ScaleFactor(window.scale_factor() as f32))?;
        let panel_glue = match host.show_panel() {
            Ok(panel) => {
                panel.store_cache_like_a_window();
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
            shader_watch: ShaderWatch::new(&*host.scene),
            host,
            panel_glue,
            ctrl_held: false,
            screenshots_taken: 0,
            gl_window,
        };
        running.host.start();
        running.honour(event_loop);
        Ok(running)
    }

    /// One of winit's events, translated for the host.
    pub fn window_event(&mut self, event_loop: &ActiveEventLoop, event: &WindowEvent) {
        if let Some(event) = translate(event, self.ctrl_held) {
            self.event(event_loop, event);
        }
    }

    /// An event for the host; an error is logged and the scene stays as it was.
    pub fn event(&mut self, event_loop: &ActiveEventLoop, event: Event) {
        if let Err(e) = self.host.event(event) {
            log::error!("{e}");
        }
        self.honour(event_loop);
    }

    /// One frame into the back buffer (not yet swapped), the panel over it if `panel`: a saved
    /// shader file reloaded first, the frame's size the window's now; the figure printed as the
    /// tutorial prints it.
    pub fn frame(&mut self, event_loop: &ActiveEventLoop, panel: bool) -> Result<()> {
        if self.shader_watch.changed(&*self.host.scene, Instant::now()) {
            // The error is logged with the driver's log, and a short line goes to the title.
            if let Err(e) = self.host.reload_shaders() {
                log::error!("{e}");
            }
        }
        // Asked of the server each frame (the viewport and the projection's aspect follow the
        // window), which also finds a window another program destroyed before a swap draws into it
        // (Mesa's swap to a destroyed window crashes the process).
        let size = self.gl_window.size();
        if size != self.host.size() {
            self.host.event(Event::Resized(size))?;
        }
        let done = self.host.frame(panel)?;
        if let Some(ms) = done.ms_per_frame {
            println!("{ms:.3} ms/frame");
        }
        self.set_cursor_shape(done.panel_output);
        self.honour(event_loop);
        Ok(())
    }

    /// The cursor's shape is egui's only while it is free (a grabbed cursor stays hidden).
    fn set_cursor_shape(&mut self, output: Option<egui::PlatformOutput>) {
        let grabbed = self.host.cursor_grabbed();
        if let (Some(glue), Some(output), false) = (self.panel_glue.as_mut(), output, grabbed) {
            glue.handle_platform_output(&self.gl_window.window, output);
        }
    }

    /// Does what the host asked for, in order.
    fn honour(&mut self, event_loop: &ActiveEventLoop) {
        while let Some(request) = self.host.next_request() {
            match request {
                Request::Quit => event_loop.exit(),
                Request::GrabCursor(grab) => {
                    let mode = self.host.descriptor().mouse_mode;
                    grab_cursor(&self.gl_window.window, grab, mode);
                }
                Request::Screenshot { with_panel } => {
                    if let Err(e) = self.save_numbered(with_panel) {
                        log::error!("{e}");
                    }
                }
                // The files are on disk.
                Request::Fetch { then, .. } => {
                    if let Err(e) = self.host.fetched(then) {
                        log::error!("{e}");
                    }
                }
                Request::SetTitle(title) => self.gl_window.window.set_title(&title),
                Request::NewScene(scene) => {
                    self.shader_watch = ShaderWatch::new(&*self.host.scene);
                    println!("{}", key_list(scene));
                }
            }
        }
    }

    /// `P`: tutorial13-1.png, tutorial13-2.png, ... in the current folder, never overwriting. The
    /// frame on screen is the front buffer: it is drawn again (time frozen) and read back, before the
    /// panel is painted over it (P), or after (Ctrl+P: the window as shown).
    fn save_numbered(&mut self, with_panel: bool) -> Result<()> {
        let done = self.host.frame_frozen(with_panel)?;
        self.set_cursor_shape(done.panel_output);
        let path = loop {
            self.screenshots_taken += 1;
            let path = PathBuf::from(format!("tutorial13-{}.png", self.screenshots_taken));
            if !path.exists() {
                break path;
            }
        };
        self.save(&path)
    }

    /// Reads the back buffer (the frame just drawn) and writes it as PNG.
    pub fn save(&self, path: &Path) -> Result<()> {
        write_screenshot(path, &self.gl_window.read_frame(self.host.gl())?)?;
        log::info!("wrote {}", path.display());
        Ok(())
    }
}
