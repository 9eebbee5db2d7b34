//! The scene host, which runs every scene alike in each front end (what wgpu's `framework.rs` and
//! sokol_app's callbacks are to their programs). It owns the context's [`GlContext`], the scene, its
//! descriptor and the options it was built with, the tutorial's camera (`controls.cpp`) and the
//! input that moves it, the cursor, the frame clock and the panel. A front end creates its context,
//! translates its platform's events into [`Event`](super::events::Event)s ([`SceneHost::event`], in
//! `input.rs`), draws each frame with [`SceneHost::frame`], presents it, and honours the
//! [`Request`]s the host gives back ([`SceneHost::next_request`]): quit, grab the cursor, save a
//! screenshot, fetch files, set the title. So the window, the browser page, headless rendering and the tests differ only in where
//! the frame goes and where their input comes from: Enter, a dropped file, R or a click on the
//! panel does the same in each.

mod exercise;
mod input;
pub mod scene_box;

use std::any::Any;
use std::collections::VecDeque;
use std::path::Path;

use glam::Vec2;
use glow::HasContext;

use super::events::{AfterFetch, FrameTime, Request};
use super::frame_clock::FrameClock;
use super::keys::{FrontEnd, HostKey, HOST_KEYS};
use super::panel::{Panel, PanelAction, PanelFrame, PanelInfo};
use super::tour_pane::{TourClick, TOUR_WIDTH};
use crate::common::controls::{Controls, Input};
use crate::gl::check_gl_errors;
use crate::gl::current::GlContext;
use crate::scenes::MouseMode;
use crate::scenes::{
    ControlValue, FrameInput, Scene, SceneContext, SceneDescriptor, SceneOptions, SetTo,
};
use crate::tour::exercise::ExerciseCheck;
use crate::tour::{Step, STEPS};
use crate::{Error, Result};

/// The end of every title (what a search for the window finds).
pub const TITLE_SHORT: &str = "Tutorial 13";

/// While time runs, the host asks for GL errors once in this many frames: asking is a sync point in
/// a browser (it waits for the GPU), and a bug shows within two seconds either way. A frame with time
/// frozen or stepped (what the tests, `--frames` and screenshots read) is checked every time.
const ERROR_CHECK_FRAMES: u32 = 120;

/// Where the pointer is and what holds it.
#[derive(Debug, Default)]
struct Pointer {
    /// In frame pixels; `None` off the frame.
    at: Option<Vec2>,
    /// The button went down on the panel and is still down (a slider's drag): the pointer is the
    /// panel's until it goes up, also off the panel.
    on_panel: bool,
    /// Where the last drag step was, while a drag looks around (a front end that cannot grab the
    /// cursor: [`FrontEnd::grabs_cursor`]).
    dragging: Option<Vec2>,
}

/// What [`SceneHost::frame`] measured and what the panel asks of the platform.
#[derive(Default)]
pub struct FrameDone {
    /// A new once-a-second "ms/frame" figure (the window prints it, as the tutorial does).
    pub ms_per_frame: Option<f64>,
    /// egui's platform output of a new layout of the panel (the cursor's shape, for a window).
    pub panel_output: Option<egui::PlatformOutput>,
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
    /// The panel over the frame, once shown ([`SceneHost::show_panel`]).
    panel: Option<Panel>,
    /// The tutorial's camera.
    pub controls: Controls,
    /// Arrow keys held and mouse motion since the last frame.
    input: Input,
    /// The cursor in frame pixels (x right, y down), for scenes that follow it; `None` off the
    /// frame (or over the panel).
    pub cursor: Option<Vec2>,
    pointer: Pointer,
    /// Whether the cursor is grabbed for mouse look (asked of the front end).
    grabbed: bool,
    /// The size of the frame the camera's projection is for.
    size: (u32, u32),
    /// The display's pixels per point, where the front end said (a window's scale factor).
    pixels_per_point: Option<f32>,
    /// The front end's clock: each frame's time and the once-a-second "ms/frame" figure.
    pub clock: FrameClock,
    time: FrameTime,
    frames_drawn: u32,
    /// The last shader reload's error in one line (the title and the panel show it) until a good
    /// version is read or another scene draws.
    shader_error: Option<String>,
    /// F1 hides the panel and shows it again.
    panel_shown: bool,
    /// Where the learner is in the tutorial's tour (an index in [`STEPS`]), while its pane shows.
    tour: Option<usize>,
    /// The step PageDown or PageUp asked for last, while its scene's files come in: the next key
    /// steps on from it, and a step whose files came in after a later key's is not shown.
    tour_asked: Option<usize>,
    /// The answer of the last exercise check (F2) at the tour's step on show.
    exercise_answer: Option<ExerciseCheck>,
    /// Checks done so far (each answer's serial number).
    exercise_checks: u32,
    /// The panel's input for its next frame, made from the events.
    panel_events: Vec<egui::Event>,
    /// Which front end this is: the keys it has and lists, how it looks around.
    front_end: FrontEnd,
    /// The front ends' own keys this host answers.
    host_keys: &'static [HostKey],
    requests: VecDeque<Request>,
    /// The title last asked for.
    title: String,
    /// The scene's own target while the tour's pane shows ([`scene_box`]); before the context,
    /// which must outlive it.
    boxed: scene_box::BoxedScene,
    /// What every scene it builds is built on (Enter, a dropped file), and the panel.
    context: GlContext,
}

impl SceneHost {
    /// Builds `descriptor`'s scene with `options` on `context`, the camera at its start for a frame
    /// of `size`, for `front_end`, its time running.
    pub fn new(
        context: GlContext,
        descriptor: &'static SceneDescriptor,
        options: &SceneOptions,
        size: (u32, u32),
        front_end: FrontEnd,
    ) -> Result<Self> {
        let scene = (descriptor.build)(&scene_context(&context), options)?;
        log::info!("{}", scene.status());
        let controls = scene.start_controls(size.0, size.1);
        Ok(SceneHost {
            scene,
            descriptor,
            options: options.clone(),
            panel: None,
            controls,
            input: Input::default(),
            cursor: None,
            pointer: Pointer::default(),
            grabbed: false,
            size,
            pixels_per_point: None,
            clock: FrameClock::new(),
            time: FrameTime::Running,
            frames_drawn: 0,
            shader_error: None,
            panel_shown: false,
            tour: None,
            tour_asked: None,
            exercise_answer: None,
            exercise_checks: 0,
            panel_events: Vec::new(),
            front_end,
            host_keys: HOST_KEYS,
            boxed: scene_box::BoxedScene::default(),
            requests: VecDeque::new(),
            title: String::new(),
            context,
        })
    }

    /// [`SceneHost::new`] for the window and for headless rendering, which draws the window's
    /// frame, keeping `time` from the first frame (frozen at 0 for the original's screenshot test
    /// and `--frames N`).
    pub fn for_window(
        context: GlContext,
        descriptor: &'static SceneDescriptor,
        options: &SceneOptions,
        size: (u32, u32),
        time: FrameTime,
    ) -> Result<Self> {
        let mut host = SceneHost::new(context, descriptor, options, size, FrontEnd::Window)?;
        host.set_time(time);
        Ok(host)
    }

    /// The context the host draws with (the front end's, handed over once).
    pub fn gl(&self) -> &GlContext {
        &self.context
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

    /// How the frames keep time from now on ([`FrameTime::Running`] until set).
    pub fn set_time(&mut self, time: FrameTime) {
        self.time = time;
    }

    /// The front ends' own keys this host answers from now on ([`HOST_KEYS`] until set): a row added
    /// to the table is a key the host runs, in every front end whose translation names it.
    pub fn set_host_keys(&mut self, keys: &'static [HostKey]) {
        self.host_keys = keys;
    }

    /// Whether the host has the cursor grabbed for mouse look (asked of the front end by
    /// [`Request::GrabCursor`]).
    pub fn cursor_grabbed(&self) -> bool {
        self.grabbed
    }

    /// Frames drawn so far (the screenshots' redraws among them).
    pub fn frames_drawn(&self) -> u32 {
        self.frames_drawn
    }

    /// The next thing the front end must do for the host, oldest first.
    pub fn next_request(&mut self) -> Option<Request> {
        self.requests.pop_front()
    }

    fn request(&mut self, request: Request) {
        // A title not yet set is replaced, not queued: a front end without one never takes them.
        if let Request::SetTitle(_) = request {
            self.requests.retain(|r| !matches!(r, Request::SetTitle(_)));
        }
        self.requests.push_back(request);
    }

    /// Enter: the next scene of [`crate::scenes::SCENES`] with the same options, the camera at its
    /// start (its files are on disk: see [`Request::Fetch`] for a front end that fetches them). On an
    /// error the current scene stays.
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

    /// A dropped file: the scene that opens it ([`crate::scenes::open_file`]), built with it, the
    /// camera at its start. On an error the current scene stays.
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

    /// A [`Request::Fetch`]'s files are in: does what was waiting for them.
    pub fn fetched(&mut self, then: AfterFetch) -> Result<()> {
        match then {
            AfterFetch::Switch { from, to } if self.descriptor == from => self.switch_scene(to),
            AfterFetch::Switch { .. } => Ok(()),
            AfterFetch::Open(path) => self.open_file(&path),
            AfterFetch::Tour(index) if self.tour_asked == Some(index) => {
                self.tour_asked = None;
                match STEPS.get(index) {
                    Some(step) => self.show_step(step),
                    None => Ok(()),
                }
            }
            AfterFetch::Tour(_) => Ok(()),
        }
    }

    /// The tour's step the learner is at, while its pane shows.
    pub fn tour_step(&self) -> Option<&'static Step> {
        self.tour.and_then(|index| STEPS.get(index))
    }

    /// The host's state in one line: the tour's step, the scene with every control (its status) and
    /// the camera (position, then the horizontal and vertical angles, each number as Rust writes it,
    /// so read back exactly). The page keeps one per change (`data-states`, with `frames=N`), which
    /// its tests compare with the native host's in the same state.
    pub fn state_line(&self) -> String {
        let step = self.tour_step().map_or("no step".to_string(), |step| {
            format!("step {}", step.number())
        });
        format!(
            "{step} | {}: {} | camera {}",
            self.descriptor.name,
            self.scene.status(),
            self.camera_line()
        )
    }

    /// The camera: position x y z, then the horizontal and vertical angles (radians), each as Rust
    /// writes an f32 (read back exactly). The page's `data-camera`, and the end of
    /// [`SceneHost::state_line`].
    pub fn camera_line(&self) -> String {
        let c = &self.controls;
        format!(
            "{} {} {} {} {}",
            c.position.x, c.position.y, c.position.z, c.horizontal_angle, c.vertical_angle
        )
    }

    /// Puts the host in `step`'s state: its scene built again (with the command line's options, so
    /// that nothing an earlier step set stays), then [`SceneHost::set_step_state`]. On an error the
    /// scene that was built stays, and so does the tour's step.
    pub fn show_step(&mut self, step: &'static Step) -> Result<()> {
        self.switch_scene(step.state.descriptor()?)?;
        self.set_step_state(step)
    }

    /// `step`'s controls set through the table of the scene just built (the step's), its camera
    /// put where the step has it for the host's frame, and the tour's pane at `step`.
    pub fn set_step_state(&mut self, step: &'static Step) -> Result<()> {
        let state = &step.state;
        state.set_controls(self.scene.as_mut())?;
        let start = self.scene.start_controls(self.size.0, self.size.1);
        state.set_camera(&mut self.controls, start);
        self.tour = Some(step.number() - 1);
        self.exercise_answer = None;
        log::info!("the tour, step {}: {}", step.number(), step.section);
        Ok(())
    }

    /// PageDown (`forward`) or PageUp: the tour's next step or the one before, once its scene's
    /// files are in (the first step where the tour was closed); the last and the first stay.
    fn step_tour(&mut self, forward: bool) {
        let index = match (self.tour_asked.or(self.tour), forward) {
            (None, _) => 0,
            (Some(at), true) => (at + 1).min(STEPS.len() - 1),
            (Some(at), false) => at.saturating_sub(1),
        };
        if Some(index) == self.tour_asked.or(self.tour) {
            let end = if forward { "last" } else { "first" };
            return log::info!("the tour's {end} step is shown");
        }
        // The pane is the panel's: a key that moves the tour shows it.
        if self.panel.is_some() {
            self.panel_shown = true;
        }
        self.tour_asked = Some(index);
        let then = AfterFetch::Tour(index);
        match STEPS[index].state.descriptor() {
            Ok(scene) => self.request(Request::Fetch { scene, then }),
            Err(e) => log::error!("{e}"),
        }
    }

    /// The tour's pane closed (the scene stays in its step's state).
    pub fn close_tour(&mut self) {
        self.tour = None;
        self.tour_asked = None;
        self.exercise_answer = None;
    }

    /// A button of the tour's pane, as its key does.
    fn tour_click(&mut self, action: &PanelAction) {
        match action {
            PanelAction::Tour(TourClick::Close) => self.close_tour(),
            PanelAction::Tour(TourClick::Back) => self.step_tour(false),
            PanelAction::Tour(TourClick::Next) => self.step_tour(true),
            PanelAction::Tour(TourClick::Check) => self.check_tour_exercise(),
            _ => {}
        }
    }

    /// Builds `next` with `options` first (so that a failure leaves the current scene), then drops
    /// the old scene's GL objects and puts the camera at the new one's start; the cursor as the new
    /// scene wants it.
    fn install(&mut self, next: &'static SceneDescriptor, options: SceneOptions) -> Result<()> {
        self.scene = (next.build)(&scene_context(&self.context), &options)?;
        self.options = options;
        self.descriptor = next;
        self.shader_error = None;
        self.reset_camera();
        log::info!("scene {next}: {}", self.scene.status());
        self.request(Request::NewScene(next));
        // As at the start: while the panel shows the cursor stays free for it, and a click on the
        // frame grabs it.
        self.set_grab(false);
        if !self.panel_shown() {
            self.set_grab(true);
        }
        Ok(())
    }

    /// A new window's cursor: grabbed for mouse look unless the panel shows (then a click on the
    /// frame grabs it) or time is frozen (`--frames`, which no hand steers).
    pub fn start(&mut self) {
        if self.time == FrameTime::Frozen {
            return;
        }
        if !self.panel_shown() {
            self.set_grab(true);
        } else if self.descriptor.mouse_mode == MouseMode::Look && self.front_end.grabs_cursor() {
            log::info!("click the frame to look around (F1 hides the panel)");
        }
    }

    /// Asks the front end to grab the cursor for mouse look (a scene that follows the free cursor is
    /// never grabbed, nor is a page's), or to release it, if that changes anything; the motion sent
    /// before then is not mouse look.
    fn set_grab(&mut self, grab: bool) {
        let look = self.descriptor.mouse_mode == MouseMode::Look;
        let grab = grab && look && self.front_end.grabs_cursor();
        if grab == self.grabbed {
            return;
        }
        self.grabbed = grab;
        self.forget_motion();
        self.request(Request::GrabCursor(grab));
    }

    /// Motion sent so far is dropped (the cursor was just grabbed or released).
    pub fn forget_motion(&mut self) {
        self.input.mouse_dx = 0.0;
        self.input.mouse_dy = 0.0;
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

    /// Reads the scene's shader files again: on an error the scene keeps the programs it had, and
    /// [`SceneHost::shader_error`] says which file failed until a good version is read.
    pub fn reload_shaders(&mut self) -> Result<()> {
        let reloaded = self.scene.reload_shaders();
        self.shader_error = reloaded.as_ref().err().map(shader_error_line);
        if reloaded.is_ok() {
            log::info!("shaders reloaded");
        }
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

    /// One frame into the bound framebuffer, kept in time as [`SceneHost::set_time`] says: the clock
    /// ticked, the viewport set to the frame's size, the scene drawn in its GL state
    /// ([`SceneDescriptor::gl_state`]), the panel run and painted over it if shown and `panel`, what
    /// was clicked on it done, then GL's errors drained (every frozen or stepped frame, once in 120
    /// while time runs: an error is a bug in this program, so it is returned, not ignored).
    pub fn frame(&mut self, panel: bool) -> Result<FrameDone> {
        self.frame_in(self.time, panel)
    }

    /// [`SceneHost::frame`] with time frozen, whatever the front end's time: the window's P draws its
    /// frame again so to read it back.
    pub fn frame_frozen(&mut self, panel: bool) -> Result<FrameDone> {
        self.frame_in(FrameTime::Frozen, panel)
    }

    fn frame_in(&mut self, time: FrameTime, panel: bool) -> Result<FrameDone> {
        let tick = self.clock.tick();
        let (width, height) = self.size;
        let scene_box = if panel { self.scene_box() } else { None };
        let destination = match &scene_box {
            Some(b) => Some(
                self.boxed
                    .bind(&self.context.gl, &self.context.extensions, b)?,
            ),
            // SAFETY: a viewport of the frame's size on the current context.
            None => {
                unsafe { self.context.gl.viewport(0, 0, width as i32, height as i32) };
                None
            }
        };
        let (delta_time, seconds, frozen) = match time {
            FrameTime::Running => (tick.delta_time, tick.time, false),
            FrameTime::Frozen => (0.0, 0.0, true),
            FrameTime::Stepped(step) => (step, 0.0, false),
        };
        // In a box, the scene is drawn as in a window of the box's size: its projection, its size
        // and the cursor are the box's.
        if let Some(b) = &scene_box {
            self.controls.set_viewport(b.width, b.height);
        }
        let mut input = self.frame_input(delta_time, seconds, frozen);
        if let Some(b) = &scene_box {
            self.controls.set_viewport(width, height);
            input.size = b.size();
            input.cursor = input.cursor.map(|at| b.from_frame(at));
        }
        self.descriptor.gl_state.apply(&self.context.gl);
        self.scene.draw(&input);
        if let (Some(b), Some(destination)) = (&scene_box, destination) {
            (self.boxed).show(&self.context.gl, destination, self.size, b);
        }
        // The panel's clock is the host's where the front end's time runs (a screenshot's frozen
        // redraw included: a click spans it); where frames are frozen or stepped it gets none (egui
        // steps its own), so that such a frame's panel is the same in every front end.
        let panel_time = (self.time == FrameTime::Running).then(|| self.clock.seconds());
        // A frame without the panel (the window's P) leaves its input for the next that has it.
        let panel_output = if panel {
            let events = std::mem::take(&mut self.panel_events);
            self.draw_panel(events, panel_time)
        } else {
            None
        };
        let check = time != FrameTime::Running || self.frames_drawn % ERROR_CHECK_FRAMES == 0;
        self.frames_drawn += 1;
        if check {
            check_gl_errors(&self.context.gl, "frame")?;
        }
        let title = self.title();
        if title != self.title {
            self.title = title.clone();
            self.request(Request::SetTitle(title));
        }
        Ok(FrameDone {
            ms_per_frame: tick.ms_per_frame,
            panel_output,
        })
    }

    /// Where the scene is drawn this frame if the tour's pane shows beside the panel: the box
    /// between them ([`scene_box`]). `None` (the whole frame) without the pane, or into a
    /// multisampled framebuffer, which a blit cannot write at another place.
    pub fn scene_box(&self) -> Option<scene_box::SceneBox> {
        let panel = self.panel.as_ref().filter(|_| self.panel_shown)?;
        self.tour?;
        // SAFETY: a plain query on the current context.
        let samples = unsafe { self.context.gl.get_parameter_i32(glow::SAMPLES) };
        if samples > 0 {
            return None;
        }
        let ppp = self.pixels_per_point.unwrap_or(1.0);
        let width = self.size.0 as f32;
        let left = panel.width(width / ppp, true) * ppp;
        scene_box::SceneBox::between(self.size, left, width - TOUR_WIDTH * ppp)
    }

    /// "cylinder: lines off, view lit, tangents tutorial | 3.2 ms/frame | Tutorial 13": the scene
    /// and its most important switches first (a title bar cuts the end off), the figure, then the
    /// program; a shader that failed to reload comes before all of them. The panel shows the rest.
    /// Made after every frame, so that whatever changed the scene (a key, the panel, the mouse
    /// moving a light, the wheel) shows at once.
    fn title(&self) -> String {
        let ms =
            (self.clock.ms_per_frame()).map_or(String::new(), |ms| format!(" | {ms:.1} ms/frame"));
        let error = (self.shader_error()).map_or(String::new(), |e| format!("{e} | "));
        format!(
            "{error}{}: {}{ms} | {TITLE_SHORT}",
            self.descriptor.name,
            self.scene.short_status()
        )
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
        let at = egui::pos2(at.x, at.y);
        panel.is_some_and(|panel| {
            let rects = [panel.rect(), panel.tour_rect()];
            rects.into_iter().flatten().any(|r| r.contains(at))
        })
    }

    /// The panel's input for a frame of the host's size: `events` and the time (`None`: egui steps
    /// its own), in points of the display's scale.
    fn panel_input(&self, events: Vec<egui::Event>, time: Option<f64>) -> egui::RawInput {
        let (width, height) = self.size;
        let points = egui::vec2(width as f32, height as f32) / self.pixels_per_point.unwrap_or(1.0);
        let mut input = egui::RawInput {
            screen_rect: Some(egui::Rect::from_min_size(egui::Pos2::ZERO, points)),
            events,
            time,
            ..Default::default()
        };
        if let Some(scale) = self.pixels_per_point {
            let viewport = input.viewports.entry(egui::ViewportId::ROOT).or_default();
            viewport.native_pixels_per_point = Some(scale);
        }
        input
    }

    /// What the panel shows of the front end's own figures.
    fn panel_info(&self) -> PanelInfo {
        PanelInfo {
            // A frozen or stepped frame (a screenshot, a test's frame, the page's `frames=N`) is
            // made of the program's state alone, so that two runs and two front ends draw it
            // alike: a figure of the wall clock would change it once a second had passed.
            ms_per_frame: (self.clock.ms_per_frame()).filter(|_| self.time == FrameTime::Running),
            shader_error: self.shader_error.clone(),
            front_end: self.front_end,
            tour: self.tour,
            exercise: self.exercise_answer.clone(),
        }
    }

    /// Lays out and paints the panel over the bound framebuffer (the frame just drawn, of the
    /// host's size) if it is shown, with `events` since the last frame, then does what was clicked
    /// on it. Returns egui's platform output of a new layout.
    fn draw_panel(
        &mut self,
        events: Vec<egui::Event>,
        time: Option<f64>,
    ) -> Option<egui::PlatformOutput> {
        if !self.panel_shown {
            return None;
        }
        let info = self.panel_info();
        let input = self.panel_input(events, time);
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
                PanelAction::Tour(_) => return self.tour_click(action),
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

/// What a scene is built on, made here alone: the host's context, lent.
fn scene_context(context: &GlContext) -> SceneContext<'_> {
    SceneContext {
        gl: &context.gl,
        info: &context.info,
        extensions: &context.extensions,
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
