//! What passes between a front end and the scene host, which runs every scene alike: platform-neutral
//! [`Event`]s in (each front end translates its own: winit's, the DOM's, a test's), [`Request`]s out
//! for what only a platform can do, and how a front end's frames keep time ([`FrameTime`]).

use std::path::PathBuf;

use glam::Vec2;

use super::keys::Key;
use crate::scenes::SceneDescriptor;

/// Something the user did, as the host takes it from any front end.
#[derive(Debug, Clone, PartialEq)]
pub enum Event {
    /// A key went down (`pressed`) or up. `repeat`: the platform's auto-repeat of a key held down,
    /// or a press it made up (a window gaining focus with the key down): only an arrow counts it,
    /// so that no action runs twice (a switch would flip back, P would save two screenshots).
    /// `ctrl`: Ctrl is held (Ctrl+P saves the window as shown).
    Key {
        key: Key,
        pressed: bool,
        repeat: bool,
        ctrl: bool,
    },
    /// The pointer is at this point of the frame, in pixels (x right, y down from the top-left).
    PointerMoved(Vec2),
    /// The pointer left the frame.
    PointerLeft,
    /// The primary button went down or up, where the pointer last moved to.
    Button { pressed: bool },
    /// The wheel turned, in notches (a touchpad's pixels turned into notches by its front end):
    /// `y` positive away from the user, `x` to the right.
    Wheel(Vec2),
    /// Raw mouse motion in pixels, for the tutorial's mouse look (it turns the camera only while the
    /// host has the cursor grabbed).
    Look(f64, f64),
    /// Files dropped on the frame (the page's, once read and kept where the loaders find them): the
    /// model among them opens.
    DroppedFiles(Vec<PathBuf>),
    /// The frame's size in pixels changed (the projection and the viewport follow it).
    Resized((u32, u32)),
    /// Pixels per point of the display (a window's scale factor): the panel's size in pixels.
    ScaleFactor(f32),
    /// The frame gained or lost the keyboard's focus (losing it releases a grabbed cursor).
    Focused(bool),
}

/// What the host asks of its front end: what only a platform can do.
#[derive(Debug, Clone, PartialEq)]
pub enum Request {
    /// Close and exit (Esc).
    Quit,
    /// Grab and hide the cursor for mouse look, or release it (the host has already counted its
    /// mouse look from or to this).
    GrabCursor(bool),
    /// Save the frame as a numbered screenshot (P): the host's frame drawn again with time frozen,
    /// the panel over it where `with_panel` (Ctrl+P: the window as shown).
    Screenshot { with_panel: bool },
    /// Make `scene`'s files readable (the page fetches them; on disk they are there), then give the
    /// host `then` (`SceneHost::fetched`).
    Fetch {
        scene: &'static SceneDescriptor,
        then: AfterFetch,
    },
    /// The title, where the platform has one: the scene, its main switches, the ms/frame figure, a
    /// shader that failed to reload. Asked for only when it changes.
    SetTitle(String),
    /// Another scene draws now (Enter, a dropped file): its keys to list where the platform prints
    /// them, its shader files to watch.
    NewScene(&'static SceneDescriptor),
}

/// What the host does once a [`Request::Fetch`]'s files are in.
#[derive(Debug, Clone, PartialEq)]
pub enum AfterFetch {
    /// Enter: `to`, if `from` still draws (a second Enter while the files came in switched
    /// already).
    Switch {
        from: &'static SceneDescriptor,
        to: &'static SceneDescriptor,
    },
    /// A dropped model, opened by the scene that opens it.
    Open(PathBuf),
    /// PageDown, PageUp: the tour's step of this index in `tour::STEPS` (its scene's files in).
    Tour(usize),
}

/// How a front end's frames keep time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FrameTime {
    /// Each frame's time is the clock's, and the camera moves by the time since the last frame.
    Running,
    /// Time stays at 0 and no input moves the camera, nor does a click or the wheel reach the scene:
    /// the original's screenshot test (`--frames N`, headless rendering, the window's P).
    Frozen,
    /// Time stays at 0, but input moves the camera by this many seconds a frame (the page's
    /// `frames=N`, so that a test predicts the frame its input gives).
    Stepped(f32),
}
