//! The panel over the frame: the scene's keys with its switches as checkboxes and choices, sliders
//! for what a learner wants to move, the program that draws (and its shader files), ms/frame, and
//! labels on the two sides of a compare view. Drawn with egui on the scene's own context after the
//! scene, over it (the scene's viewport is not shrunk), so every pixel outside the panel's
//! rectangle is the scene's frame as it was. The window shows it (F1 hides it); `--panel` puts it
//! into headless screenshots. It knows nothing of any one scene: it reads the descriptor's keys, the
//! scene's table of controls ([`crate::scenes::SceneControls`]), [`Scene::drawing_programs`] and
//! [`Scene::compare_labels`]; what is clicked on it comes back as [`PanelAction`]s, which the scene
//! host does to the scene as its keys and its table's `set` do. It takes its input (a frame's
//! `egui::RawInput`) from the host, and knows nothing of the host.

use glow::HasContext;

use super::keys::{panel_key_rows, FrontEnd};
use super::tour_pane::{show_tour, TourClick, TourExcerpts, TOUR_WIDTH};
use crate::gl::extensions::GlExtensions;
use crate::gl::offscreen::{ColorBuffer, OffscreenTarget};
use crate::gl::Gl;
use crate::scenes::{ControlState, ControlValue, Scene, SceneDescriptor, SetTo};
use crate::tour::exercise::ExerciseCheck;
use crate::{Error, Result};

/// Width of the panel, in points.
pub const PANEL_WIDTH: f32 = 330.0;
/// Width of the panel folded beside the tour's pane, in points: the scene's name, the figure and the
/// button that unfolds it.
pub const FOLDED_WIDTH: f32 = 120.0;
/// The scene's least width between the panel and the tour's pane, in points: in a frame narrower
/// than both and this (the tutorial's 1024 pixels among them) the panel folds while the pane shows,
/// which leaves the scene 464 points there where it had 254.
pub const SCENE_BESIDE_TOUR: f32 = 400.0;

/// What the panel asks of the scene after a frame's layout: applied once the layout is done, so
/// that the scene is not borrowed while egui runs.
#[derive(Debug, Clone, PartialEq)]
pub enum PanelAction {
    /// Press this key of the scene (a button beside a key that is no switch).
    Key(char),
    /// Set the control of this index in the scene's table (a checkbox, a choice, a slider).
    Set(usize, SetTo),
    /// Every slider back to its start value.
    StartValues,
    /// A button of the tour's pane.
    Tour(TourClick),
}

/// A widget of the panel, for finding where it is (tests, and a learner's scripts driving the
/// window).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum PanelWidget {
    /// The checkbox, choice or button of a scene key.
    Key(char),
    /// A slider, by its index in the scene's table.
    Slider(usize),
    /// Choice `n` of a scene key's list, while the list is open.
    Choice(char, usize),
    /// The "tutorial's values" button.
    StartValues,
    /// The once-a-second "ms/frame" figure (a label).
    Figure,
    /// A button of the tour's pane.
    Tour(TourClick),
    /// The button that folds the panel beside the tour's pane, or unfolds it.
    Fold,
}

/// Besides the scene, what the panel shows: the front end's own figures.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PanelInfo {
    /// The last once-a-second ms/frame figure.
    pub ms_per_frame: Option<f64>,
    /// A shader that failed to reload (the last good one draws).
    pub shader_error: Option<String>,
    /// Whose keys the key list gives (the page has fewer).
    pub front_end: FrontEnd,
    /// The tour's step (an index in `tour::STEPS`) whose pane shows; `None`: no pane.
    pub tour: Option<usize>,
    /// The answer of the exercise check at the tour's step (F2), for the pane.
    pub exercise: Option<ExerciseCheck>,
}

/// egui's context and its glow painter, on the scene's GL context.
pub struct Panel {
    ctx: egui::Context,
    painter: egui_glow::Painter,
    gl: Gl,
    /// The panel's rectangle in the last frame, in pixels (x right, y down from the top-left).
    rect: Option<egui::Rect>,
    /// The tour's pane's, where it showed.
    tour_rect: Option<egui::Rect>,
    /// The excerpts of the tour's step last shown (resolved once per step).
    tour_excerpts: Option<TourExcerpts>,
    /// The heat map of the last exercise check's answer, as a texture, with the answer's serial.
    heat_map: Option<(u32, egui::TextureHandle)>,
    /// Unfolded by the learner beside the tour's pane where it would fold ([`SCENE_BESIDE_TOUR`]).
    unfolded: bool,
    /// The scene the last frame was laid out for (see [`Panel::run`]); `None` before the first.
    laid_out_for: Option<&'static str>,
    /// Where each widget was in the last frame, in pixels.
    widgets: Vec<(PanelWidget, egui::Rect)>,
    /// What the last layout showed, and whether egui asked for another frame (an animation).
    shown: Option<(SceneView, PanelInfo, egui::Rect)>,
    repaint: bool,
    /// The panel as last painted, kept to be copied over each frame until it changes (painting it
    /// again costs llvmpipe as much as the tutorial's whole frame). `None` until first painted.
    cache: Option<OffscreenTarget>,
    /// Paint with egui every frame instead (what the cache saves, measured; and the test that the
    /// copy is the painting).
    pub paint_every_frame: bool,
    /// How the cache stores its colour: as the frame it is copied into does, so that the copy is a
    /// plain memory copy where the driver makes one (see [`Panel::store_cache_like_a_window`]).
    cache_color: ColorBuffer,
    /// For storing the cache like a window (see [`OffscreenTarget::set_window_orientation`]).
    extensions: GlExtensions,
}

/// What [`Panel::run`] gives [`Panel::paint`].
pub enum PanelFrame {
    /// A new layout to paint.
    Laid(Box<egui::FullOutput>),
    /// Nothing changed: the cached panel is copied over the frame.
    Unchanged,
}

impl Panel {
    /// Builds the painter (a program and buffers) on the current context; `extensions` has the one
    /// entry point glow lacks (`glFramebufferParameteri`, to store the cache like a window).
    pub fn new(gl: &Gl, extensions: &GlExtensions) -> Result<Self> {
        let painter =
            egui_glow::Painter::new(gl.clone(), "", None, false).map_err(|e| Error::Gl {
                part: "panel",
                reason: e.to_string(),
            })?;
        let ctx = egui::Context::default();
        // Nothing is saved between runs (no `persistence`), and the panel's look is egui's dark one
        // whatever the desktop's theme, so that its pixels are the same everywhere.
        ctx.set_theme(egui::Theme::Dark);
        Ok(Panel {
            ctx,
            painter,
            gl: gl.clone(),
            rect: None,
            tour_rect: None,
            tour_excerpts: None,
            heat_map: None,
            unfolded: false,
            laid_out_for: None,
            widgets: Vec::new(),
            shown: None,
            repaint: false,
            cache: None,
            paint_every_frame: false,
            // An offscreen target's colour is an RGBA8 renderbuffer.
            cache_color: ColorBuffer::Renderbuffer,
            extensions: extensions.clone(),
        })
    }

    /// Stores the cache in a window's byte order (blue, green, red, alpha), for a panel painted over
    /// a window: llvmpipe then copies it over each frame with a memory copy instead of a draw, and
    /// that draw was most of what the panel cost the window (BENCHMARKS.md, "The panel's cost").
    pub fn store_cache_like_a_window(&mut self) {
        self.cache_color = ColorBuffer::WindowOrderTexture;
        // The next frame lays out and paints into a new cache.
        self.cache = None;
        self.shown = None;
    }

    /// egui's context (the window's egui-winit state is built on it).
    pub fn context(&self) -> &egui::Context {
        &self.ctx
    }

    /// `input`'s screen, scale and time without its events (a pass that must not click anything).
    /// The time is the frame's own: a pass without one steps egui's clock by its predicted 1/60 s,
    /// and the frame's own pass after two such, less than 33 ms later, ran the clock backwards (the
    /// window's fades with it).
    fn headless_input_like(input: &egui::RawInput) -> egui::RawInput {
        egui::RawInput {
            screen_rect: input.screen_rect,
            viewports: input.viewports.clone(),
            time: input.time,
            ..Default::default()
        }
    }

    /// Whether the panel is folded in a frame `width` points wide, with the tour's pane or without.
    pub fn folded(&self, width: f32, tour: bool) -> bool {
        tour && !self.unfolded && too_narrow_for_both(width)
    }

    /// The panel's width in points in a frame `width` points wide, with the tour's pane or without.
    pub fn width(&self, width: f32, tour: bool) -> f32 {
        if self.folded(width, tour) {
            FOLDED_WIDTH
        } else {
            PANEL_WIDTH
        }
    }

    /// The panel's rectangle in the last frame, in pixels (x right, y down from the top-left).
    pub fn rect(&self) -> Option<egui::Rect> {
        self.rect
    }

    /// The tour's pane's rectangle in the last frame, in pixels; `None` where it did not show.
    pub fn tour_rect(&self) -> Option<egui::Rect> {
        self.tour_rect
    }

    /// Where `widget` was in the last frame, in pixels (x right, y down from the top-left); `None`
    /// if the panel did not show it.
    pub fn widget_rect(&self, widget: &PanelWidget) -> Option<egui::Rect> {
        self.widgets
            .iter()
            .find(|(w, _)| w == widget)
            .map(|&(_, rect)| rect)
    }

    /// Lays the panel out for one frame of `input` over `scene`. Returns what to paint (see
    /// [`Panel::paint`]) and what was clicked, for the host to do. With
    /// no input, nothing new to show and no animation running, the last layout stands and nothing
    /// is laid out.
    pub fn run(
        &mut self,
        input: egui::RawInput,
        descriptor: &'static SceneDescriptor,
        scene: &dyn Scene,
        info: PanelInfo,
    ) -> (PanelFrame, Vec<PanelAction>) {
        let view = SceneView::of(descriptor, scene);
        let screen = input.screen_rect.unwrap_or(egui::Rect::NOTHING);
        let same = self
            .shown
            .as_ref()
            .is_some_and(|(v, i, r)| *v == view && *i == info && *r == screen);
        let idle = input.events.is_empty() && !self.repaint && !self.paint_every_frame;
        if same && idle && self.cache.is_some() {
            return (PanelFrame::Unchanged, Vec::new());
        }
        let shown = (view.clone(), info.clone(), screen);
        let mut actions = Vec::new();
        let mut widgets = Vec::new();
        let mut panel_rect = None;
        let mut tour_rect = None;
        let cached = self.tour_excerpts.take();
        self.tour_excerpts = info.tour.and_then(|index| TourExcerpts::of(index, cached));
        let tour = self.tour_excerpts.as_ref();
        let answer = info.exercise.as_ref();
        self.heat_map = heat_map_texture(&self.ctx, answer, self.heat_map.take());
        let heat_map = self.heat_map.as_ref().map(|(_, texture)| texture);
        // Beside the pane in a narrow frame the panel folds unless the learner unfolded it: its
        // button turns it over at once (the pass is laid out again).
        let folded = self.folded(screen.width(), tour.is_some());
        let foldable = tour.is_some() && too_narrow_for_both(screen.width());
        let mut turned = false;
        let mut layout = |ui: &mut egui::Ui| {
            // A pass egui discards runs the closure again: only the last pass's clicks count.
            actions.clear();
            widgets.clear();
            // The tour's pane first, so that the panel leaves it its side.
            tour_rect = tour.map(|tour| {
                let (rect, buttons, clicked) = show_tour(ui, tour, answer, heat_map);
                let buttons = buttons.into_iter().map(|(b, r)| (PanelWidget::Tour(b), r));
                widgets.extend(buttons);
                actions.extend(clicked.map(PanelAction::Tour));
                rect
            });
            // Once turned, this frame's passes lay it out the other way.
            let folded = folded != turned;
            let mut record = Record {
                actions: &mut actions,
                widgets: &mut widgets,
            };
            let response = egui::Panel::left("tutorial13-panel")
                .exact_size(if folded { FOLDED_WIDTH } else { PANEL_WIDTH })
                .resizable(false)
                .show(ui, |ui| {
                    let clicked = if folded {
                        view.show_folded(ui, &info, &mut record)
                    } else {
                        egui::ScrollArea::vertical()
                            .show(ui, |ui| view.show(ui, &info, foldable, &mut record))
                            .inner
                    };
                    if clicked && !turned {
                        turned = true;
                        ui.ctx().request_discard("the panel folded or unfolded");
                    }
                });
            panel_rect = Some(response.response.rect);
            view.show_compare_labels(ui.ctx());
        };
        // egui sizes a grid's columns from the frame before, and its rows' stripes from the one
        // before that: the very first frame is laid out twice (the first, with no input, not
        // painted), and the first after a change of scene three times (two frames would show the
        // last scene's sizes: 4,352 then 1,272 pixels of the sprite's panel, a screenshot taken
        // just after Enter among them). Their texture uploads (the font atlas) are kept.
        let mut textures = egui::TexturesDelta::default();
        let warm_ups = match self.laid_out_for {
            None => 1,
            Some(name) if name != descriptor.name => 2,
            Some(_) => 0,
        };
        for _ in 0..warm_ups {
            let warm_up = Panel::headless_input_like(&input);
            let first = self.ctx.run_ui(warm_up, &mut layout);
            textures.append(first.textures_delta);
        }
        self.laid_out_for = Some(descriptor.name);
        let mut output = self.ctx.run_ui(input, &mut layout);
        textures.append(std::mem::take(&mut output.textures_delta));
        output.textures_delta = textures;
        if turned {
            self.unfolded = !self.unfolded;
        }
        let ppp = output.pixels_per_point;
        self.rect = panel_rect.map(|r| r * ppp);
        self.tour_rect = tour_rect.map(|r| r * ppp);
        self.widgets = widgets.into_iter().map(|(w, r)| (w, r * ppp)).collect();
        self.repaint = output
            .viewport_output
            .values()
            .any(|v| v.repaint_delay.is_zero());
        self.shown = Some(shown);
        (PanelFrame::Laid(Box::new(output)), actions)
    }

    /// Paints the panel over the bound framebuffer of `size` pixels. A new layout is painted into
    /// the cache and the panel's columns copied from there; an unchanged one is only copied. Where a
    /// copy cannot stand for painting (a multisampled framebuffer, which a blit cannot write, or
    /// labels over the frame outside the panel), egui paints straight over the frame.
    pub fn paint(&mut self, size: (u32, u32), frame: PanelFrame) {
        let gl = self.gl.clone();
        // SAFETY: queries on the current context, and no scissor left on by the frame (it would clip
        // the copy).
        let (destination, samples) = unsafe {
            gl.disable(glow::SCISSOR_TEST);
            (
                crate::gl::bound_framebuffer(&gl, glow::DRAW_FRAMEBUFFER_BINDING),
                gl.get_parameter_i32(glow::SAMPLES),
            )
        };
        let overlays = self
            .shown
            .as_ref()
            .is_some_and(|(view, _, _)| view.compare.is_some());
        let direct = samples > 0 || overlays || self.paint_every_frame;
        let columns = self.rect.map_or(0, |r| r.right().ceil().max(0.0) as u32);
        // The tour's pane's columns, to the frame's right edge (none while it is closed).
        let tour_columns = self
            .tour_rect
            .map(|r| (r.left().floor().max(0.0) as u32, size.0));
        match frame {
            PanelFrame::Laid(output) if direct => {
                self.cache = None;
                self.paint_egui(size, *output);
            }
            PanelFrame::Laid(output) => match self.cache_for(size) {
                Ok(()) => {
                    let cache = self.cache.as_ref().expect("made above");
                    cache.bind();
                    // SAFETY: clearing the cache's colour to transparent.
                    unsafe {
                        gl.clear_color(0.0, 0.0, 0.0, 0.0);
                        gl.clear(glow::COLOR_BUFFER_BIT);
                    }
                    self.paint_egui(size, *output);
                    // SAFETY: the front end's framebuffer again.
                    unsafe { gl.bind_framebuffer(glow::FRAMEBUFFER, destination) };
                    let cache = self.cache.as_ref().expect("made above");
                    cache.blit_columns_to(destination, 0, columns);
                    if let Some((x0, x1)) = tour_columns {
                        cache.blit_columns_to(destination, x0, x1);
                    }
                }
                Err(e) => {
                    log::warn!("{e} (the panel is painted every frame)");
                    self.paint_egui(size, *output);
                }
            },
            PanelFrame::Unchanged => match &self.cache {
                Some(cache) if !direct => {
                    cache.blit_columns_to(destination, 0, columns);
                    if let Some((x0, x1)) = tour_columns {
                        cache.blit_columns_to(destination, x0, x1);
                    }
                }
                // Nothing cached to copy: the next frame lays out again.
                _ => self.shown = None,
            },
        }
        // SAFETY: the front end's viewport again.
        unsafe { gl.viewport(0, 0, size.0 as i32, size.1 as i32) };
    }

    /// A cache target of `size`, stored as the frame is.
    fn cache_for(&mut self, (width, height): (u32, u32)) -> Result<()> {
        let fits = self
            .cache
            .as_ref()
            .is_some_and(|c| (c.width(), c.height()) == (width, height));
        if !fits {
            let gl = &self.gl;
            let mut target = OffscreenTarget::with_color(gl, width, height, self.cache_color)
                .or_else(|e| {
                    // Only the copy's speed depends on the order; RGBA8 is always renderable.
                    log::debug!("{e}: the panel's cache is stored as RGBA");
                    self.cache_color = ColorBuffer::Renderbuffer;
                    OffscreenTarget::with_color(gl, width, height, self.cache_color)
                })?;
            target.set_window_orientation(&self.extensions)?;
            self.cache = Some(target);
        }
        Ok(())
    }

    /// egui's meshes for `output`, painted over the bound framebuffer; then the state egui changed
    /// that a scene's frame could read is put back (see [`crate::gl::state::GlState`] for the rest).
    fn paint_egui(&mut self, size: (u32, u32), output: egui::FullOutput) {
        let mut textures = output.textures_delta;
        let primitives = self.ctx.tessellate(output.shapes, output.pixels_per_point);
        self.painter.paint_and_update_textures(
            [size.0, size.1],
            output.pixels_per_point,
            &primitives,
            &mut textures,
        );
        // SAFETY: state-setting calls on the current context.
        unsafe {
            let gl = &self.gl;
            gl.disable(glow::BLEND);
            gl.blend_func(glow::ONE, glow::ZERO);
            gl.disable(glow::SCISSOR_TEST);
            gl.use_program(None);
            gl.bind_buffer(glow::ARRAY_BUFFER, None);
            gl.active_texture(glow::TEXTURE0);
            gl.bind_texture(glow::TEXTURE_2D, None);
            gl.pixel_store_i32(glow::UNPACK_ALIGNMENT, 4);
        }
    }
}

impl Drop for Panel {
    fn drop(&mut self) {
        self.painter.destroy();
    }
}

/// What a frame's layout gives: the actions clicked, and where each widget is (points).
struct Record<'a> {
    actions: &'a mut Vec<PanelAction>,
    widgets: &'a mut Vec<(PanelWidget, egui::Rect)>,
}

impl Record<'_> {
    /// Notes where `widget` is, and returns whether it was clicked (or changed).
    fn widget(&mut self, widget: PanelWidget, response: &egui::Response) -> bool {
        self.widgets.push((widget, response.rect));
        response.clicked() || response.changed()
    }
}

/// Whether a frame `width` points wide leaves the scene less than [`SCENE_BESIDE_TOUR`] between the
/// whole panel and the tour's pane.
fn too_narrow_for_both(width: f32) -> bool {
    width < PANEL_WIDTH + TOUR_WIDTH + SCENE_BESIDE_TOUR
}

/// The ms/frame figure, always one line, so that the layout is the same before the first figure and
/// headless.
fn show_figure(ui: &mut egui::Ui, info: &PanelInfo, record: &mut Record) {
    let figure = match info.ms_per_frame {
        Some(ms) => ui.label(format!("{ms:.3} ms/frame")),
        None => ui.label("– ms/frame"),
    };
    record.widgets.push((PanelWidget::Figure, figure.rect));
}

/// What the panel shows of a scene, read before the layout (so the scene is not borrowed in it).
#[derive(Debug, Clone, PartialEq)]
struct SceneView {
    descriptor: &'static SceneDescriptor,
    controls: Vec<ControlState>,
    programs: Vec<crate::scenes::DrawingProgram>,
    compare: Option<crate::scenes::CompareLabels>,
}

impl SceneView {
    fn of(descriptor: &'static SceneDescriptor, scene: &dyn Scene) -> Self {
        SceneView {
            descriptor,
            controls: scene.controls(),
            programs: scene.drawing_programs(),
            compare: scene.compare_labels(),
        }
    }

    /// The whole panel; where it can fold (beside the tour's pane in a narrow frame) with the
    /// button that folds it first. Returns whether that button was clicked.
    fn show(
        &self,
        ui: &mut egui::Ui,
        info: &PanelInfo,
        foldable: bool,
        record: &mut Record,
    ) -> bool {
        let d = self.descriptor;
        let fold = foldable && record.widget(PanelWidget::Fold, &ui.button("< fold the panel"));
        ui.heading(format!("scene {}", d.name));
        ui.small(d.description);
        show_figure(ui, info, record);
        // The keys and sliders first, at rows that never move (what changes length comes after
        // them), so that a click on one never shifts the next one a learner aims at.
        ui.separator();
        self.show_keys(ui, record, true, info.front_end);
        if self.sliders().next().is_some() {
            ui.separator();
            self.show_sliders(ui, record);
        }
        ui.separator();
        if let Some(error) = &info.shader_error {
            ui.colored_label(egui::Color32::LIGHT_RED, error);
        }
        for program in &self.programs {
            ui.label(format!("drawn by {}", program.name));
            if !program.shaders.is_empty() {
                ui.small(files_line(&program.files()));
            }
        }
        if let Some(c) = &self.compare {
            ui.label(format!("compare view: left {}, right {}", c.left, c.right));
        }
        ui.separator();
        egui::CollapsingHeader::new("mouse and window keys")
            .default_open(false)
            .show(ui, |ui| self.show_keys(ui, record, false, info.front_end));
        ui.small("F1 hides this panel");
        fold
    }

    /// The panel folded beside the tour's pane: the button that unfolds it, the scene's name and
    /// the figure. Returns whether that button was clicked.
    fn show_folded(&self, ui: &mut egui::Ui, info: &PanelInfo, record: &mut Record) -> bool {
        let unfold = record.widget(PanelWidget::Fold, &ui.button("the panel >"));
        ui.heading(self.descriptor.name);
        show_figure(ui, info, record);
        ui.small("its keys work folded; F1 hides it");
        unfold
    }

    /// The controls that are sliders, in the table's order.
    fn sliders(&self) -> impl Iterator<Item = &ControlState> {
        let is_slider = |c: &&ControlState| matches!(c.value, ControlValue::Slider { .. });
        self.controls.iter().filter(is_slider)
    }

    /// The key list (the rows `--help` prints): the scene's own keys, each with its control (a
    /// checkbox, a choice or a button, greyed with the reason as hover text where it does nothing
    /// now), or the mouse's and the window's.
    fn show_keys(
        &self,
        ui: &mut egui::Ui,
        record: &mut Record,
        scene_keys: bool,
        front_end: FrontEnd,
    ) {
        egui::Grid::new(("keys", scene_keys))
            .num_columns(2)
            .striped(true)
            .show(ui, |ui| {
                let rows = panel_key_rows(self.descriptor, front_end).into_iter();
                for row in rows.filter(|r| r.scene_key.is_some() == scene_keys) {
                    let control = row
                        .scene_key
                        .and_then(|k| self.controls.iter().find(|c| c.key == Some(k)));
                    match (row.scene_key, control) {
                        (Some(key), Some(control)) => {
                            let response = show_control(ui, record, key, &row.key, control);
                            if let Some(reason) = control.inert {
                                response.on_disabled_hover_text(reason);
                            }
                        }
                        (Some(key), None) => {
                            let response = ui.button(row.key.clone());
                            if record.widget(PanelWidget::Key(key), &response) {
                                record.actions.push(PanelAction::Key(key));
                            }
                        }
                        (None, _) => {
                            ui.monospace(row.key.clone());
                        }
                    }
                    let help = egui::RichText::new(row.help).small();
                    ui.add(egui::Label::new(help).wrap());
                    ui.end_row();
                }
            });
    }

    /// One slider per value, each saying when it is away from its start (greyed, with the reason as
    /// hover text, where it does nothing now); a button puts all back.
    fn show_sliders(&self, ui: &mut egui::Ui, record: &mut Record) {
        for control in self.sliders() {
            let ControlValue::Slider {
                value: now,
                start,
                range: (lo, hi),
            } = control.value
            else {
                continue;
            };
            let mut value = now;
            // Away from its start the name says so, on the same row (the layout stays put).
            let text = if now != start {
                let text = format!("{} (was {start})", control.label);
                egui::RichText::new(text).color(egui::Color32::YELLOW)
            } else {
                egui::RichText::new(control.label)
            };
            let slider = egui::Slider::new(&mut value, lo..=hi).text(text);
            let mut response = ui.add_enabled(control.inert.is_none(), slider);
            if let Some(reason) = control.inert {
                response = response.on_disabled_hover_text(reason);
            }
            let moved = record.widget(PanelWidget::Slider(control.index), &response);
            if moved && value != now {
                let to = SetTo::Slider(value);
                record.actions.push(PanelAction::Set(control.index, to));
            }
        }
        let any_moved = self.sliders().any(|c| match c.value {
            ControlValue::Slider { value, start, .. } => value != start,
            _ => false,
        });
        let response = ui.add_enabled(any_moved, egui::Button::new("tutorial's values"));
        if record.widget(PanelWidget::StartValues, &response) {
            record.actions.push(PanelAction::StartValues);
        }
    }

    /// Labels at the top of each side of a compare view (outside the panel, over the frame): one
    /// each side of the split line, or one over the heat map.
    fn show_compare_labels(&self, ctx: &egui::Context) {
        let Some(c) = &self.compare else { return };
        let width = ctx.content_rect().width();
        let label = |id: &str, pos: egui::Pos2, align: egui::Align2, text: String| {
            egui::Area::new(egui::Id::unique(id))
                .pivot(align)
                .fixed_pos(pos)
                .interactable(false)
                .fade_in(false)
                .show(ctx, |ui| {
                    egui::Frame::popup(ui.style()).show(ui, |ui| ui.label(text));
                });
        };
        match c.split {
            Some(split) => {
                let x = split * width;
                let (left, right) = (format!("left: {}", c.left), format!("right: {}", c.right));
                let top = egui::Align2::RIGHT_TOP;
                label("compare-left", egui::pos2(x - 6.0, 6.0), top, left);
                let top = egui::Align2::LEFT_TOP;
                label("compare-right", egui::pos2(x + 6.0, 6.0), top, right);
            }
            None => {
                let x = (PANEL_WIDTH + width) / 2.0;
                let text = format!("difference: {} vs {}", c.left, c.right);
                label(
                    "compare-difference",
                    egui::pos2(x, 6.0),
                    egui::Align2::CENTER_TOP,
                    text,
                );
            }
        }
    }
}

/// The widget of `control` on `key` (listed as `listed`): a checkbox, a choice of its values, or a
/// button for a plain press, greyed where the control does nothing now. A click sets the control
/// to what was clicked.
fn show_control(
    ui: &mut egui::Ui,
    record: &mut Record,
    key: char,
    listed: &str,
    control: &ControlState,
) -> egui::Response {
    let set = |to| PanelAction::Set(control.index, to);
    let enabled = control.inert.is_none();
    match &control.value {
        ControlValue::Toggle(on) => {
            let mut checked = *on;
            let response = ui.add_enabled(enabled, egui::Checkbox::new(&mut checked, listed));
            if record.widget(PanelWidget::Key(key), &response) {
                record.actions.push(set(SetTo::Toggle(!on)));
            }
            response
        }
        // Greyed, the choice's value only (a combo box cannot be disabled in place in a grid).
        ControlValue::Choice { current, .. } if !enabled => {
            let text = format!("{listed}: {current}");
            let response = ui.add_enabled(false, egui::Button::new(text));
            record.widget(PanelWidget::Key(key), &response);
            response
        }
        ControlValue::Choice { current, choices } => {
            let combo = egui::ComboBox::from_id_salt(("switch", key))
                .selected_text(format!("{listed}: {current}"))
                .show_ui(ui, |ui| {
                    for (n, choice) in choices.iter().enumerate() {
                        let chosen = choice == current;
                        let response = ui.selectable_label(chosen, choice);
                        if record.widget(PanelWidget::Choice(key, n), &response) && !chosen {
                            record.actions.push(set(SetTo::Choice(choice.clone())));
                        }
                    }
                });
            record
                .widgets
                .push((PanelWidget::Key(key), combo.response.rect));
            combo.response
        }
        ControlValue::Slider { .. } | ControlValue::Press => {
            let response = ui.add_enabled(enabled, egui::Button::new(listed));
            if record.widget(PanelWidget::Key(key), &response) {
                record.actions.push(PanelAction::Key(key));
            }
            response
        }
    }
}

/// The texture of `answer`'s heat map: `cached` if it is that answer's, else loaded now; `None`
/// where the answer has none.
fn heat_map_texture(
    ctx: &egui::Context,
    answer: Option<&ExerciseCheck>,
    cached: Option<(u32, egui::TextureHandle)>,
) -> Option<(u32, egui::TextureHandle)> {
    let answer = answer?;
    let map = answer.heat_map.as_ref()?;
    match cached {
        Some((serial, texture)) if serial == answer.serial => Some((serial, texture)),
        _ => {
            let size = [map.width() as usize, map.height() as usize];
            let image = egui::ColorImage::from_rgba_unmultiplied(size, map.as_raw());
            let texture =
                ctx.load_texture("exercise-heat-map", image, egui::TextureOptions::NEAREST);
            Some((answer.serial, texture))
        }
    }
}

/// "A, B (in DIR)" for files of one folder, or "shaders built into the binary".
fn files_line(files: &[std::path::PathBuf]) -> String {
    let Some(first) = files.first() else {
        return "  shaders built into the binary".into();
    };
    let names: Vec<String> = files
        .iter()
        .map(|f| {
            f.file_name()
                .unwrap_or(f.as_os_str())
                .to_string_lossy()
                .into_owned()
        })
        .collect();
    match first.parent() {
        Some(dir) if files.iter().all(|f| f.parent() == Some(dir)) => {
            // Where the learner edits them: from the current folder when they are below it (asked
            // once: the panel draws this every frame, and the program never changes folder).
            static CWD: std::sync::OnceLock<std::path::PathBuf> = std::sync::OnceLock::new();
            let cwd = CWD.get_or_init(|| std::env::current_dir().unwrap_or_default());
            let shown = match dir.strip_prefix(cwd) {
                Ok(relative) if relative.as_os_str().is_empty() => std::path::Path::new("."),
                Ok(relative) => relative,
                Err(_) => dir,
            };
            format!("  {} (in {})", names.join(", "), shown.display())
        }
        _ => format!(
            "  {}",
            files
                .iter()
                .map(|f| f.display().to_string())
                .collect::<Vec<_>>()
                .join(", ")
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::Panel;

    // Fails if the passes that lay the panel out again before a frame (the first after a change of
    // scene) move egui's clock: without the frame's time each stepped it by 1/60 s, and the frame's
    // own pass, 10 ms after the last frame, saw the time run 23 ms backwards.
    #[test]
    fn warm_up_passes_keep_the_frames_time() {
        let ctx = egui::Context::default();
        let at = |seconds| egui::RawInput {
            time: Some(seconds),
            ..Default::default()
        };
        // A pass whose textures nothing paints (epaint's debug build refuses to drop them unseen).
        let pass = |input, ui: &mut dyn FnMut(&mut egui::Ui)| {
            ctx.run_ui(input, ui).textures_delta.clear();
        };
        pass(at(1.0), &mut |_| {});
        let frame = at(1.01);
        for _ in 0..2 {
            pass(Panel::headless_input_like(&frame), &mut |_| {});
        }
        let mut dt = f32::NAN;
        pass(frame, &mut |ui| dt = ui.input(|i| i.unstable_dt));
        assert!(dt >= 0.0, "egui's clock ran backwards: dt {dt} s");
    }
}
