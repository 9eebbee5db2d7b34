//! The host's input: every front end's [`Event`]s reach the scene, the camera, the panel and the
//! front end's [`Request`]s through here. The front ends' own keys are run from the one table
//! ([`HostKey`], [`host_action`]); a click on the frame does what the scene's [`MouseMode`] asks; the
//! pointer is the panel's over the panel, the frame's elsewhere.

use std::path::{Path, PathBuf};

use glam::Vec2;

use super::SceneHost;
use crate::frontends::events::{AfterFetch, Event, FrameTime, Request};
use crate::frontends::keys::{host_action, Arrow, HostAction, Key};
use crate::scenes::MouseMode;
use crate::Result;

#[cfg(doc)]
use crate::frontends::keys::HostKey;

impl SceneHost {
    /// Takes one event of the front end's: what it asks of the front end comes back through
    /// [`SceneHost::next_request`]. An error (a scene that cannot be built, a shader that does not
    /// compile, a file no scene opens) leaves the scene as it was; the front end shows it.
    pub fn event(&mut self, event: Event) -> Result<()> {
        match event {
            Event::Key {
                key: Key::Arrow(arrow),
                pressed,
                ..
            } => self.arrow(arrow, pressed),
            // Only a new press runs a key's action, once.
            Event::Key {
                key,
                pressed: true,
                repeat: false,
                ctrl,
            } => return self.key(key, ctrl),
            Event::Key { .. } => {}
            Event::PointerMoved(at) => self.pointer_moved(at),
            Event::PointerLeft => {
                self.pointer.at = None;
                self.pointer.dragging = None;
                self.cursor = None;
                self.panel_pointer(egui::Event::PointerGone);
            }
            Event::Button { pressed } => self.button(pressed),
            Event::Wheel(notches) => self.wheel(notches),
            Event::Look(dx, dy) if self.grabbed => self.look((dx, dy)),
            Event::Look(..) => {}
            Event::DroppedFiles(paths) => return self.dropped(&paths),
            Event::Resized(size) => self.set_size(size),
            Event::ScaleFactor(scale) => self.pixels_per_point = Some(scale),
            Event::Focused(focused) => {
                if !focused {
                    self.set_grab(false);
                }
            }
        }
        Ok(())
    }

    /// What `key` does as one of the front ends' own keys here, if it is one.
    pub fn host_key(&self, key: Key) -> Option<HostAction> {
        host_action(self.host_keys, key, self.front_end)
    }

    /// A new press: one of the front ends' own keys, else a scene key.
    fn key(&mut self, key: Key, ctrl: bool) -> Result<()> {
        match (self.host_key(key), key) {
            (Some(action), _) => self.run(action, ctrl),
            (None, Key::Char(c)) => self.scene_key(c).map(|_| ()),
            (None, _) => Ok(()),
        }
    }

    /// Runs one of the front ends' own keys ([`HostKey`]), for every front end.
    fn run(&mut self, action: HostAction, ctrl: bool) -> Result<()> {
        match action {
            HostAction::ResetCamera => {
                self.reset_camera();
                log::info!("camera back at the start");
            }
            HostAction::ReleaseCursor => self.set_grab(false),
            HostAction::NextScene => {
                let from = self.descriptor;
                let to = crate::scenes::next(from);
                let then = AfterFetch::Switch { from, to };
                self.request(Request::Fetch { scene: to, then });
            }
            HostAction::ReloadShaders => return self.reload_shaders(),
            HostAction::Screenshot => self.request(Request::Screenshot { with_panel: ctrl }),
            HostAction::TogglePanel => self.toggle_panel(),
            HostAction::TourNext => self.step_tour(true),
            HostAction::TourBack => self.step_tour(false),
            HostAction::CheckExercise => self.check_tour_exercise(),
            HostAction::Quit => self.request(Request::Quit),
        }
        Ok(())
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

    /// Mouse motion for the tutorial's mouse look, in pixels.
    pub fn look(&mut self, (dx, dy): (f64, f64)) {
        self.input.mouse_dx += dx;
        self.input.mouse_dy += dy;
    }

    /// The mouse wheel turned by `notches` (positive: away from the user).
    pub fn scroll(&mut self, notches: f32) {
        self.scene.scroll(notches);
    }

    /// A left click for a scene that uses the free cursor.
    pub fn click(&mut self) {
        self.scene.click();
    }

    /// An event for the panel's next frame, unless the cursor is grabbed (then it is mouse look, not
    /// a pointer).
    fn panel_pointer(&mut self, event: egui::Event) {
        if !self.grabbed {
            self.panel_events.push(event);
        }
    }

    /// `at` in the panel's points.
    fn points(&self, at: Vec2) -> egui::Pos2 {
        egui::pos2(at.x, at.y) / self.pixels_per_point.unwrap_or(1.0)
    }

    fn pointer_moved(&mut self, at: Vec2) {
        self.pointer.at = Some(at);
        self.panel_pointer(egui::Event::PointerMoved(self.points(at)));
        if let Some(from) = self.pointer.dragging {
            self.pointer.dragging = Some(at);
            let moved = at - from;
            self.look((f64::from(moved.x), f64::from(moved.y)));
        }
        // Over the panel, or while it holds the button, the pointer is the panel's: to the scene
        // it has left the frame (a light that follows it stays where it was).
        if !self.pointer.on_panel {
            self.cursor = Some(at).filter(|&at| !self.over_panel(at));
        }
    }

    fn button(&mut self, pressed: bool) {
        let at = self.pointer.at;
        let over_panel = at.is_some_and(|at| self.over_panel(at)) && !self.grabbed;
        let panel_event = |host: &Self, at: Vec2| egui::Event::PointerButton {
            pos: host.points(at),
            button: egui::PointerButton::Primary,
            pressed,
            modifiers: egui::Modifiers::default(),
        };
        if !pressed {
            // Every release reaches the panel, also one after a press on the frame: egui clicks a
            // widget only on a press and a release over it, so this clicks nothing, and a press it
            // never saw released would hold its button down and ignore every later click.
            if let Some(at) = at {
                self.panel_pointer(panel_event(self, at));
            }
            self.pointer.on_panel = false;
            self.pointer.dragging = None;
            return;
        }
        if over_panel {
            let event = at.map(|at| panel_event(self, at));
            self.panel_events.extend(event);
            self.pointer.on_panel = true;
            return;
        }
        // A stray click in a `--frames` run neither grabs the cursor nor reaches the scene.
        if self.time == FrameTime::Frozen {
            return;
        }
        match self.descriptor.mouse_mode {
            MouseMode::Look if self.front_end.grabs_cursor() => self.set_grab(true),
            MouseMode::Look => self.pointer.dragging = at,
            MouseMode::Cursor => self.click(),
        }
    }

    fn wheel(&mut self, notches: Vec2) {
        let over_panel = self.pointer.at.is_some_and(|at| self.over_panel(at));
        if over_panel && !self.grabbed {
            self.panel_events.push(egui::Event::MouseWheel {
                unit: egui::MouseWheelUnit::Line,
                delta: egui::vec2(notches.x, notches.y),
                modifiers: egui::Modifiers::default(),
                phase: egui::TouchPhase::Move,
                source: egui::MouseWheelSource::Unknown,
            });
        } else if self.time != FrameTime::Frozen {
            self.scroll(notches.y);
        }
    }

    /// Dropped files: the model among them opens (once the scene that opens it has its files).
    fn dropped(&mut self, paths: &[PathBuf]) -> Result<()> {
        let Some(model) = model_among(paths) else {
            return Ok(());
        };
        let scene = crate::scenes::open_file(model, &mut self.options.clone())?;
        let then = AfterFetch::Open(model.to_path_buf());
        self.request(Request::Fetch { scene, then });
        Ok(())
    }
}

/// The model among dropped files: an `.obj`, `.gltf` or `.glb`, else the first file (whose scene
/// says what it is, or that none opens it).
fn model_among(paths: &[PathBuf]) -> Option<&Path> {
    let is_model = |p: &&PathBuf| crate::model::Format::of(p).is_some();
    paths
        .iter()
        .find(is_model)
        .or(paths.first())
        .map(PathBuf::as_path)
}
