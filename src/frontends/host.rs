//! The scene host: what every front end drives. It owns the scene, its descriptor, the options it
//! was built with, the tutorial's camera (`controls.cpp`) and the input that moves it, the cursor,
//! the frame clock and the panel. Keys, mouse motion, the wheel, clicks, dropped files and what is
//! clicked on the panel reach the scene through it. The window, the browser page, headless
//! rendering and the tests differ only in where the frame goes and where their input comes from,
//! so Enter, a dropped file, R or a click on the panel does the same in each.

use std::any::Any;
use std::path::Path;

use glam::Vec2;

use super::panel::{Panel, PanelAction, PanelFrame, PanelInfo};
use super::{FrameClock, FrontEnd};
use crate::common::controls::{Controls, Input};
use crate::gl::extensions::GlExtensions;
use crate::gl::{ContextInfo, Gl};
use crate::scenes::{
    ControlValue, FrameInput, Scene, SceneContext, SceneDescriptor, SceneOptions, SetTo,
};
use crate::{Error, Result};

/// An arrow key: the tutorial's camera moves while one is held.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Arrow {
    Up,
    Down,
    Left,
    Right,
}

/// The GL context the host builds its scenes on and draws them with: the front end's, shared.
#[derive(Clone)]
struct HostContext {
    gl: Gl,
    info: ContextInfo,
    extensions: GlExtensions,
}

impl HostContext {
    fn scene_context(&self) -> SceneContext<'_> {
        SceneContext {
            gl: &self.gl,
            info: &self.info,
            extensions: &self.extensions,
        }
    }
}

/// The scene being drawn, its camera and its input.
pub struct SceneHost {
    // Field order is drop order: the scene's GL objects go first.
    /// The scene (see [`SceneHost::scene_as`] to reach a particular scene's internals).
    pub scene: Box<dyn Scene>,
    descriptor: &'static SceneDescriptor,
    /// What the scenes are built with: `--assets`, `--shaders` and each scene's own options; a
    /// dropped file changes them, Enter keeps them.
    options: SceneOptions,
    /// The tutorial's camera.
    pub controls: Controls,
    /// Arrow keys held and mouse motion since the last frame.
    input: Input,
    /// The cursor in frame pixels (x right, y down), for scenes that follow it; `None` off the
    /// frame (or over the panel).
    pub cursor: Option<Vec2>,
    /// The size of the frame the camera's projection is for.
    size: (u32, u32),
    /// What every scene it builds is built on (Enter, a dropped file).
    context: HostContext,
    /// The front end's clock: each frame's time and the once-a-second "ms/frame" figure.
    pub clock: FrameClock,
    /// The last shader reload's error in one line (the title and the panel show it) until a good
    /// version is read or another scene draws.
    shader_error: Option<String>,
    /// The panel over the frame, once shown ([`SceneHost::show_panel`]).
    panel: Option<Panel>,
    /// F1 hides the panel and shows it again.
    panel_shown: bool,
    /// Which front end's keys the panel lists (the page has fewer).
    front_end: FrontEnd,
    /// The panel's input for its next frame where no platform glue makes it (headless, the page).
    panel_events: Vec<egui::Event>,
}

impl SceneHost {
    /// Builds `descriptor`'s scene with `options` on `context`, the camera at its start for a frame
    /// of `size`, for `front_end`.
    pub fn new(
        context: &SceneContext,
        descriptor: &'static SceneDescriptor,
        options: &SceneOptions,
        size: (u32, u32),
        front_end: FrontEnd,
    ) -> Result<Self> {
        let scene = (descriptor.build)(context, options)?;
        log::info!("{}", scene.status());
        let controls = scene.start_controls(size.0, size.1);
        Ok(SceneHost {
            scene,
            descriptor,
            options: options.clone(),
            controls,
            input: Input::default(),
            cursor: None,
            size,
            context: HostContext {
                gl: context.gl.clone(),
                info: context.info.clone(),
                extensions: context.extensions.clone(),
            },
            clock: FrameClock::new(),
            shader_error: None,
            panel: None,
            panel_shown: false,
            front_end,
            panel_events: Vec::new(),
        })
    }

    /// Which scene [`SceneHost::scene`] is.
    pub fn descriptor(&self) -> &'static SceneDescriptor {
        self.descriptor
    }

    /// The scene as its own type, for tests and tools that reach into it; `None` if the host holds
    /// another scene.
    pub fn scene_as<S: Scene>(&mut self) -> Option<&mut S> {
        let scene: &mut dyn Any = &mut *self.scene;
        scene.downcast_mut()
    }

    /// [`SceneHost::scene_as`], shared.
    pub fn scene_as_ref<S: Scene>(&self) -> Option<&S> {
        let scene: &dyn Any = &*self.scene;
        scene.downcast_ref()
    }

    /// Enter: the next scene of [`crate::scenes::SCENES`] with the same options, the camera at its
    /// start. On an error the current scene stays.
    pub fn next_scene(&mut self) -> Result<()> {
        let next = crate::scenes::next(self.descriptor);
        self.switch_scene(next)
    }

    /// `next`'s scene with the same options, the camera at its start. On an error the current scene
    /// stays.
    pub fn switch_scene(&mut self, next: &'static SceneDescriptor) -> Result<()> {
        let options = self.options.clone();
        self.install(next, options)
    }

    /// A file dropped on the window: the scene that opens it ([`crate::scenes::open_file`]), built
    /// with it, the camera at its start. On an error the current scene stays.
    pub fn open_file(&mut self, path: &Path) -> Result<()> {
        self.open_file_with(path, |_| {})
    }

    /// [`SceneHost::open_file`] with the options `change` makes for this opening only (the page's
    /// baked map drawn on LOW): Enter, or the next file, starts from the options without them.
    pub fn open_file_with(
        &mut self,
        path: &Path,
        change: impl FnOnce(&mut SceneOptions),
    ) -> Result<()> {
        let mut options = self.options.clone();
        let next = crate::scenes::open_file(path, &mut options)?;
        let kept = options.clone();
        change(&mut options);
        self.install(next, options)?;
        self.options = kept;
        Ok(())
    }

    /// Builds `next` with `options` first (so that a failure leaves the current scene), then drops
    /// the old scene's GL objects and puts the camera at the new one's start.
    fn install(&mut self, next: &'static SceneDescriptor, options: SceneOptions) -> Result<()> {
        self.scene = (next.build)(&self.context.scene_context(), &options)?;
        self.options = options;
        self.descriptor = next;
        self.shader_error = None;
        self.reset_camera();
        log::info!("scene {next}: {}", self.scene.status());
        Ok(())
    }

    /// R: the camera back at the scene's start (the tutorial's, or framing the scene's model).
    pub fn reset_camera(&mut self) {
        self.controls = self.scene.start_controls(self.size.0, self.size.1);
        self.input = Input::default();
    }

    /// The size of the frame drawn last (or next, once set).
    pub fn size(&self) -> (u32, u32) {
        self.size
    }

    /// The frame's size changed: the projection follows it from the next frame.
    pub fn set_size(&mut self, size: (u32, u32)) {
        self.size = size;
        self.controls.set_viewport(size.0, size.1);
    }

    /// A key of the scene's list (letters upper-case): `Ok(false)` if it is none of them. The
    /// scene's status is logged when it was one.
    pub fn scene_key(&mut self, key: char) -> Result<bool> {
        let taken = self.scene.key(key)?;
        if taken {
            log::info!("{}", self.scene.status());
        }
        Ok(taken)
    }

    /// An arrow key went down (`held`) or up.
    pub fn arrow(&mut self, arrow: Arrow, held: bool) {
        let key = match arrow {
            Arrow::Up => &mut self.input.up,
            Arrow::Down => &mut self.input.down,
            Arrow::Left => &mut self.input.left,
            Arrow::Right => &mut self.input.right,
        };
        *key = held;
    }

    /// Mouse motion for the tutorial's mouse look, in pixels (a front end sends it only while the
    /// cursor is grabbed for it).
    pub fn look(&mut self, (dx, dy): (f64, f64)) {
        self.input.mouse_dx += dx;
        self.input.mouse_dy += dy;
    }

    /// Motion sent so far is dropped (the cursor was just grabbed or released).
    pub fn forget_motion(&mut self) {
        self.input.mouse_dx = 0.0;
        self.input.mouse_dy = 0.0;
    }

    /// The mouse wheel turned by `notches` (positive: away from the user).
    pub fn scroll(&mut self, notches: f32) {
        self.scene.scroll(notches);
    }

    /// A left click for a scene that uses the free cursor.
    pub fn click(&mut self) {
        self.scene.click();
    }

    /// Reads the scene's shader files again: on an error the scene keeps the programs it had, and
    /// [`SceneHost::shader_error`] says which file failed until a good version is read.
    pub fn reload_shaders(&mut self) -> Result<()> {
        let reloaded = self.scene.reload_shaders();
        self.shader_error = reloaded.as_ref().err().map(shader_error_line);
        reloaded
    }

    /// The last shader reload's error in one line, if it failed.
    pub fn shader_error(&self) -> Option<&str> {
        self.shader_error.as_deref()
    }

    /// Moves the camera by this frame's input (none while time is `frozen`, as with `--frames`),
    /// consuming the mouse motion, and gives what the scene draws the frame with.
    pub fn frame_input(&mut self, delta_time: f32, time: f32, frozen: bool) -> FrameInput {
        let input = if frozen { Input::default() } else { self.input };
        self.forget_motion();
        self.controls
            .compute_matrices_from_inputs(&input, if frozen { 0.0 } else { delta_time });
        FrameInput {
            projection: self.controls.projection_matrix(),
            view: self.controls.view_matrix(),
            cursor: self.cursor,
            size: self.size,
            time: if frozen { 0.0 } else { time },
        }
    }

    /// Draws one frame into the bound framebuffer (whose viewport covers `size`), in the scene's
    /// GL state ([`SceneDescriptor::gl_state`]).
    pub fn draw(&mut self, delta_time: f32, time: f32, frozen: bool) -> FrameInput {
        let input = self.frame_input(delta_time, time, frozen);
        self.descriptor.gl_state.apply(&self.context.gl);
        self.scene.draw(&input);
        input
    }

    /// Builds the panel on the host's context if it has none yet, and shows it.
    pub fn show_panel(&mut self) -> Result<&mut Panel> {
        if self.panel.is_none() {
            let context = &self.context;
            self.panel = Some(Panel::new(&context.gl, &context.extensions)?);
        }
        self.panel_shown = true;
        Ok(self.panel.as_mut().expect("built above"))
    }

    /// The panel, shown or hidden; `None` before [`SceneHost::show_panel`].
    pub fn panel(&self) -> Option<&Panel> {
        self.panel.as_ref()
    }

    /// [`SceneHost::panel`], to change how it paints (tests, the window's cache).
    pub fn panel_mut(&mut self) -> Option<&mut Panel> {
        self.panel.as_mut()
    }

    /// Whether the panel is drawn over the frame.
    pub fn panel_shown(&self) -> bool {
        self.panel.is_some() && self.panel_shown
    }

    /// Hides the panel or shows it again (one that was never built stays unbuilt).
    pub fn set_panel_shown(&mut self, shown: bool) {
        self.panel_shown = shown;
    }

    /// F1: the panel on or off.
    pub fn toggle_panel(&mut self) {
        if self.panel.is_none() {
            return log::warn!("no panel here (see the error above)");
        }
        self.panel_shown = !self.panel_shown;
        let shown = if self.panel_shown { "shown" } else { "hidden" };
        log::info!("panel {shown}");
    }

    /// Whether `at` (frame pixels, y down) is on the panel as it was last drawn.
    pub fn over_panel(&self, at: Vec2) -> bool {
        let panel = self.panel.as_ref().filter(|_| self.panel_shown);
        panel
            .and_then(Panel::rect)
            .is_some_and(|r| r.contains(egui::pos2(at.x, at.y)))
    }

    /// A pointer or wheel event for the panel's next frame, where no platform glue gathers them
    /// (headless, the page).
    pub fn panel_event(&mut self, event: egui::Event) {
        self.panel_events.push(event);
    }

    /// The panel's input for a frame of the host's size, one pixel per point, with the events sent
    /// by [`SceneHost::panel_event`] since the last frame and the time (`None`: none, as headless).
    pub fn panel_input(&mut self, time: Option<f64>) -> egui::RawInput {
        let mut input = Panel::headless_input(self.size);
        input.events = std::mem::take(&mut self.panel_events);
        input.time = time;
        input
    }

    /// What the panel shows of the front end's own figures.
    fn panel_info(&self) -> PanelInfo {
        PanelInfo {
            ms_per_frame: self.clock.ms_per_frame(),
            shader_error: self.shader_error.clone(),
            front_end: self.front_end,
        }
    }

    /// Lays out and paints the panel over the bound framebuffer (the frame just drawn, of the
    /// host's size) if it is shown, then does what was clicked on it. Returns egui's platform
    /// output of a new layout (the cursor's shape, for a window).
    pub fn draw_panel(&mut self, input: egui::RawInput) -> Option<egui::PlatformOutput> {
        if !self.panel_shown {
            return None;
        }
        let info = self.panel_info();
        let panel = self.panel.as_mut()?;
        let (mut output, actions) = panel.run(input, self.descriptor, &*self.scene, info);
        // Painting needs none of it: taken, not copied.
        let platform = match &mut output {
            PanelFrame::Laid(output) => Some(std::mem::take(&mut output.platform_output)),
            PanelFrame::Unchanged => None,
        };
        panel.paint(self.size, output);
        // After the paint, which showed the scene as it was drawn: an action may bind another
        // framebuffer (a compare view's targets are made on a click).
        if !actions.is_empty() {
            log::debug!("panel: {actions:?}");
        }
        for action in &actions {
            self.panel_action(action);
        }
        platform
    }

    /// Does to the scene what a click on the panel asks, as its key or its table's `set` does.
    fn panel_action(&mut self, action: &PanelAction) {
        let scene = &mut self.scene;
        let done =
            match action {
                PanelAction::Key(key) => scene.key(*key).map(|_| ()),
                PanelAction::Set(index, to) => scene.set_control(*index, to.clone()),
                PanelAction::StartValues => scene.controls().into_iter().try_for_each(|c| match c
                    .value
                {
                    ControlValue::Slider { start, .. } => {
                        scene.set_control(c.index, SetTo::Slider(start))
                    }
                    _ => Ok(()),
                }),
            };
        if let Err(e) = done {
            log::error!("{e}");
        }
        // A slider's drag sets it every frame: its value shows on the panel, not in the log.
        if !matches!(action, PanelAction::Set(_, SetTo::Slider(_))) {
            log::info!("{}", self.scene.status());
        }
    }
}

/// One short line for the title and the panel: which file failed and how (the log itself is on
/// stderr).
fn shader_error_line(error: &Error) -> String {
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
