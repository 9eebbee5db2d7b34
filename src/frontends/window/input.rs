//! What the user's hands are doing that only a window has: whether the cursor is grabbed for mouse
//! look, which arrow key a key code is, and which scene key.

use winit::keyboard::KeyCode;
use winit::window::{CursorGrabMode, Window};

use crate::frontends::host::Arrow;
use crate::scenes::MouseMode;

/// Whether the cursor is grabbed (and hidden) for the tutorial's mouse look.
#[derive(Default)]
pub struct CursorGrab {
    grabbed: bool,
}

/// The arrow key a key code is.
pub fn arrow(code: KeyCode) -> Option<Arrow> {
    match code {
        KeyCode::ArrowUp => Some(Arrow::Up),
        KeyCode::ArrowDown => Some(Arrow::Down),
        KeyCode::ArrowLeft => Some(Arrow::Left),
        KeyCode::ArrowRight => Some(Arrow::Right),
        _ => None,
    }
}

impl CursorGrab {
    /// Whether the cursor is grabbed for mouse look.
    pub fn grabbed(&self) -> bool {
        self.grabbed
    }

    /// Grabs (and hides) the cursor for mouse look, or releases it; a scene that follows the
    /// absolute cursor is never grabbed. Says so only when the grab changes, and returns whether it
    /// did (the motion sent before then is not mouse look).
    pub fn set(&mut self, window: &Window, grab: bool, mode: MouseMode) -> bool {
        let grab = grab && mode == MouseMode::Look;
        if grab == self.grabbed {
            return false;
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
        self.grabbed = grab;
        true
    }
}

/// The name the key lists give `code`, where it may be one of the front ends' own keys
/// ([`crate::frontends::HOST_KEYS`]).
pub fn host_key_name(code: KeyCode) -> Option<&'static str> {
    Some(match code {
        KeyCode::Escape => "Esc",
        KeyCode::Tab => "Tab",
        KeyCode::Enter => "Enter",
        KeyCode::F5 => "F5",
        KeyCode::F1 => "F1",
        KeyCode::KeyR => "R",
        KeyCode::KeyP => "P",
        _ => return None,
    })
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
