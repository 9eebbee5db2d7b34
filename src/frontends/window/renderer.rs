//! The scene in the window: builds it, draws a frame with the camera's matrices, reloads its shaders
//! when a file is saved, keeps the "ms/frame" figure and the title, and saves screenshots. It is
//! given the window's GL and input; it opens nothing itself.

use std::path::{Path, PathBuf};
use std::time::Instant;

use super::gl_window::GlWindow;
use super::TITLE_SHORT;
use crate::frontends::host::SceneHost;
use crate::frontends::{key_list, FrontEnd, ShaderWatch};
use crate::gl::check_gl_errors;
use crate::gl::image::write_screenshot;
use crate::scenes::{SceneDescriptor, SceneOptions};
use crate::Result;

/// The scene's host and what the window keeps about its frames.
pub struct Renderer {
    /// The scene, its camera, input, clock and panel: every input reaches the scene through it.
    pub host: SceneHost,
    pub frames_drawn: u32,
    /// The title the window has now (set again only when it changes).
    shown_title: String,
    screenshots_taken: u32,
    /// Saving a shader file reloads the scene's programs.
    shader_watch: ShaderWatch,
}

impl Renderer {
    /// Builds `descriptor`'s scene on the window's context.
    pub fn new(
        gl_window: &GlWindow,
        descriptor: &'static SceneDescriptor,
        scene_options: &SceneOptions,
    ) -> Result<Self> {
        let size = gl_window.size();
        let host = gl_window.with_scene_context(|c| {
            SceneHost::new(c, descriptor, scene_options, size, FrontEnd::Window)
        })?;
        Ok(Renderer {
            shader_watch: ShaderWatch::new(&*host.scene),
            host,
            frames_drawn: 0,
            shown_title: String::new(),
            screenshots_taken: 0,
        })
    }

    /// Enter: the next scene ([`SceneHost::next_scene`]), and its keys printed.
    pub fn next_scene(&mut self) -> Result<()> {
        self.host.next_scene()?;
        self.scene_changed();
        Ok(())
    }

    /// A file dropped on the window ([`SceneHost::open_file`]). On an error the current scene
    /// stays.
    pub fn open_file(&mut self, path: &Path) -> Result<()> {
        self.host.open_file(path)?;
        self.scene_changed();
        Ok(())
    }

    /// Another scene draws: its shader files are watched, and its keys printed.
    fn scene_changed(&mut self) {
        self.shader_watch = ShaderWatch::new(&*self.host.scene);
        println!("{}", key_list(self.host.descriptor()));
    }

    /// A key of the scene's list (an error is logged: the scene stays as it was).
    pub fn scene_key(&mut self, key: char) {
        if let Err(e) = self.host.scene_key(key) {
            log::error!("{e}");
        }
    }

    /// One frame into the back buffer (not yet swapped), with time frozen at 0 if `frozen`.
    pub fn frame(&mut self, gl_window: &GlWindow, frozen: bool) -> Result<()> {
        let tick = self.host.clock.tick();
        if self.shader_watch.changed(&*self.host.scene, Instant::now()) {
            self.reload_shaders();
        }
        let size = gl_window.size();
        // The viewport and the projection's aspect follow the window (1024×768 is the tutorial's 4:3).
        self.host.set_size(size);
        // SAFETY: a viewport of the window's size on the current context.
        unsafe {
            use glow::HasContext;
            gl_window.gl.viewport(0, 0, size.0 as i32, size.1 as i32)
        };
        self.host.draw(tick.delta_time, tick.time, frozen);
        check_gl_errors(&gl_window.gl, "frame")?;
        self.frames_drawn += 1;
        if let Some(ms) = tick.ms_per_frame {
            println!("{ms:.3} ms/frame");
        }
        self.update_title(gl_window);
        Ok(())
    }

    /// "cylinder: lines off, view lit, tangents tutorial | 3.2 ms/frame | Tutorial 13": the scene
    /// and its most important switches first (a title bar cuts the end off), the figure, then the
    /// program; a shader that failed to reload comes before all of them. The panel shows the rest.
    /// Called after every frame, so that whatever changed the scene (a key, the panel, the mouse
    /// moving a light, the wheel) shows at once; the window is told only of a change.
    fn update_title(&mut self, gl_window: &GlWindow) {
        let ms = (self.host.clock.ms_per_frame())
            .map_or(String::new(), |ms| format!(" | {ms:.1} ms/frame"));
        let error = (self.host.shader_error()).map_or(String::new(), |e| format!("{e} | "));
        let title = format!(
            "{error}{}: {}{ms} | {TITLE_SHORT}",
            self.host.descriptor().name,
            self.host.scene.short_status()
        );
        if title != self.shown_title {
            gl_window.window.set_title(&title);
            self.shown_title = title;
        }
    }

    /// Live shader editing: compiles the scene's shaders again. A shader that does not compile
    /// leaves the last good programs drawing; its driver log goes to stderr and a short line to the
    /// title until a good version is saved.
    pub fn reload_shaders(&mut self) {
        match self.host.reload_shaders() {
            Ok(()) => log::info!("shaders reloaded"),
            Err(e) => eprintln!("tutorial13: {e}"),
        }
    }

    /// `P`: tutorial13-1.png, tutorial13-2.png, ... in the current folder, never overwriting.
    pub fn save_numbered(&mut self, gl_window: &GlWindow) -> Result<()> {
        let path = loop {
            self.screenshots_taken += 1;
            let path = PathBuf::from(format!("tutorial13-{}.png", self.screenshots_taken));
            if !path.exists() {
                break path;
            }
        };
        save(gl_window, &path)
    }
}

/// Reads the back buffer (the frame just drawn) and writes it as PNG.
pub fn save(gl_window: &GlWindow, path: &Path) -> Result<()> {
    write_screenshot(path, &gl_window.read_frame()?)?;
    log::info!("wrote {}", path.display());
    Ok(())
}
