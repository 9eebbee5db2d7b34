//! What the user's hands are doing: the tutorial's camera and arrow keys, the cursor (position, and
//! whether it is grabbed for mouse look), and which scene key a key code is.

use glam::Vec2;
use winit::keyboard::KeyCode;
use winit::window::{CursorGrabMode, Window};

use crate::common::controls::{Controls, Input};
use crate::scenes::{MouseMode, Scene};

/// The camera and the input that moves it.
#[derive(Default)]
pub struct InputState {
    /// The tutorial's `computeMatricesFromInputs` state.
    pub controls: Controls,
    /// Arrow keys held and mouse motion since the last frame.
    pub input: Input,
    /// The cursor in window pixels, for scenes that follow it.
    pub cursor: Option<Vec2>,
    /// The cursor is grabbed and hidden for mouse look (only in a scene that wants it).
    grabbed: bool,
}

impl InputState {
    /// An arrow key went down or up; `false` for any other key.
    pub fn arrow(&mut self, code: KeyCode, pressed: bool) -> bool {
        let held = match code {
            KeyCode::ArrowUp => &mut self.input.up,
            KeyCode::ArrowDown => &mut self.input.down,
            KeyCode::ArrowLeft => &mut self.input.left,
            KeyCode::ArrowRight => &mut self.input.right,
            _ => return false,
        };
        *held = pressed;
        true
    }

    /// Raw mouse motion: the same pixel deltas the tutorial reads after re-centring the cursor,
    /// counted only while the cursor is grabbed (a released cursor moves without turning the camera).
    pub fn mouse_motion(&mut self, (dx, dy): (f64, f64)) {
        if self.grabbed {
            self.input.mouse_dx += dx;
            self.input.mouse_dy += dy;
        }
    }

    /// Whether the cursor is grabbed for mouse look.
    pub fn grabbed(&self) -> bool {
        self.grabbed
    }

    /// The camera back at the start of `scene` (the tutorial's, or framing the scene's model) for
    /// the window's `size`.
    pub fn reset_camera(&mut self, scene: &dyn Scene, size: (u32, u32)) {
        self.controls = scene.start_controls(size.0, size.1);
    }

    /// This frame's input (none while time is frozen); the motion is consumed.
    pub fn take_frame_input(&mut self, frozen: bool) -> Input {
        let input = if frozen { Input::default() } else { self.input };
        self.input.mouse_dx = 0.0;
        self.input.mouse_dy = 0.0;
        input
    }

    /// Grabs (and hides) the cursor for mouse look, or releases it; a scene that follows the
    /// absolute cursor is never grabbed. Says so only when the grab changes.
    pub fn set_cursor_grab(&mut self, window: &Window, grab: bool, mode: MouseMode) {
        let grab = grab && mode == MouseMode::Look;
        if grab == self.grabbed {
            return;
        }
        if grab {
            let grabbed = window
                .set_cursor_grab(CursorGrabMode::Locked)
                .or_else(|_| window.set_cursor_grab(CursorGrabMode::Confined));
            match grabbed {
                Ok(()) => log::info!("cursor grabbed for mouse look: Tab releases it"),
                Err(e) => log::warn!(
                    "cursor not grabbed ({e}): mouse look still works while it is over the window"
                ),
            }
        } else {
            if let Err(e) = window.set_cursor_grab(CursorGrabMode::None) {
                log::warn!("cursor not released: {e}");
            }
            // Only where a click grabs it again: a scene that uses the free cursor never grabs it.
            if mode == MouseMode::Look {
                log::info!("cursor released: click the window to look around again");
            }
        }
        window.set_cursor_visible(!grab);
        self.input.mouse_dx = 0.0;
        self.input.mouse_dy = 0.0;
        self.grabbed = grab;
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
