//! winit's input as the host's: each key code, pointer, button, wheel, drop, resize and focus event
//! of the window turned into an [`Event`] in one place ([`translate`], [`key`]); and the cursor's
//! grab, which only a window can do.

use glam::Vec2;
use winit::event::{ElementState, KeyEvent, MouseButton, MouseScrollDelta, WindowEvent};
use winit::keyboard::{KeyCode, PhysicalKey};
use winit::window::{CursorGrabMode, Window};

use crate::frontends::events::Event;
use crate::frontends::keys::{Arrow, Key};
use crate::scenes::MouseMode;

/// A touchpad's pixels per notch of a wheel (winit reports a wheel in lines, a touchpad in pixels).
const PIXELS_PER_NOTCH: f64 = 20.0;

/// The host's event for one of the window's, if it is one the host takes (`ctrl`: Ctrl is held).
/// Closing, a redraw, the modifiers and a resize's surface are the window's own.
pub fn translate(event: &WindowEvent, ctrl: bool) -> Option<Event> {
    Some(match event {
        WindowEvent::KeyboardInput {
            event:
                KeyEvent {
                    physical_key: PhysicalKey::Code(code),
                    state,
                    repeat,
                    ..
                },
            is_synthetic,
            ..
        } => {
            if *repeat {
                log::debug!("{code:?} repeated (held down)");
            }
            // A window gaining focus with a key down gets a synthetic press: no new press either.
            return key_event(*code, *state, *repeat || *is_synthetic, ctrl);
        }
        WindowEvent::CursorMoved { position, .. } => {
            Event::PointerMoved(Vec2::new(position.x as f32, position.y as f32))
        }
        WindowEvent::CursorLeft { .. } => Event::PointerLeft,
        WindowEvent::MouseInput {
            state,
            button: MouseButton::Left,
            ..
        } => Event::Button {
            pressed: *state == ElementState::Pressed,
        },
        WindowEvent::MouseWheel { delta, .. } => Event::Wheel(match *delta {
            MouseScrollDelta::LineDelta(x, y) => Vec2::new(x, y),
            MouseScrollDelta::PixelDelta(p) => Vec2::new(
                (p.x / PIXELS_PER_NOTCH) as f32,
                (p.y / PIXELS_PER_NOTCH) as f32,
            ),
        }),
        WindowEvent::DroppedFile(path) => Event::DroppedFiles(vec![path.clone()]),
        WindowEvent::Resized(size) => Event::Resized((size.width.max(1), size.height.max(1))),
        WindowEvent::ScaleFactorChanged { scale_factor, .. } => {
            Event::ScaleFactor(*scale_factor as f32)
        }
        WindowEvent::Focused(focused) => Event::Focused(*focused),
        _ => return None,
    })
}

/// A key of `code` gone down or up (`repeat`: not a new press), if it is a key the lists name.
pub fn key_event(code: KeyCode, state: ElementState, repeat: bool, ctrl: bool) -> Option<Event> {
    Some(Event::Key {
        key: key(code)?,
        pressed: state == ElementState::Pressed,
        repeat,
        ctrl,
    })
}

/// The key a key code is, as the key lists name it: the arrows, letters (upper-case) and digits,
/// Esc, Tab, Enter, F1 to F12, PageDown, PageUp.
pub fn key(code: KeyCode) -> Option<Key> {
    let at = |codes: &[KeyCode]| codes.iter().position(|&c| c == code).map(|i| i as u8);
    if let Some(i) = at(&LETTERS) {
        return Some(Key::Char((b'A' + i) as char));
    }
    if let Some(i) = at(&DIGITS) {
        return Some(Key::Char((b'0' + i) as char));
    }
    if let Some(i) = at(&FUNCTION_KEYS) {
        return Some(Key::F(i + 1));
    }
    NAMED.iter().find(|(c, _)| *c == code).map(|&(_, key)| key)
}

/// The other keys the lists name.
const NAMED: [(KeyCode, Key); 9] = [
    (KeyCode::ArrowUp, Key::Arrow(Arrow::Up)),
    (KeyCode::ArrowDown, Key::Arrow(Arrow::Down)),
    (KeyCode::ArrowLeft, Key::Arrow(Arrow::Left)),
    (KeyCode::ArrowRight, Key::Arrow(Arrow::Right)),
    (KeyCode::Escape, Key::Esc),
    (KeyCode::Tab, Key::Tab),
    (KeyCode::Enter, Key::Enter),
    (KeyCode::PageDown, Key::PageDown),
    (KeyCode::PageUp, Key::PageUp),
];

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
const FUNCTION_KEYS: [KeyCode; 12] = [
    KeyCode::F1,
    KeyCode::F2,
    KeyCode::F3,
    KeyCode::F4,
    KeyCode::F5,
    KeyCode::F6,
    KeyCode::F7,
    KeyCode::F8,
    KeyCode::F9,
    KeyCode::F10,
    KeyCode::F11,
    KeyCode::F12,
];
/// Grabs (and hides) the cursor for the tutorial's mouse look, or releases it, as the host asked
/// ([`crate::frontends::events::Request::GrabCursor`]); `mode`: the scene's, now.
pub fn grab_cursor(window: &Window, grab: bool, mode: MouseMode) {
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
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frontends::keys::HOST_KEYS;

    // Fails if a key a scene lists cannot be typed (every listed key must map back from a key
    // code), if the codes are not the keys the lists name, or if a key of the front ends' table has
    // no key code here: a row added to HOST_KEYS with any key the lists can name needs no other
    // line.
    #[test]
    fn every_listed_key_can_be_typed() {
        let codes = || {
            (LETTERS.iter().chain(&DIGITS).chain(&FUNCTION_KEYS))
                .copied()
                .chain(NAMED.map(|(code, _)| code))
        };
        let typed: Vec<Key> = codes().filter_map(key).collect();
        assert_eq!(typed.len(), codes().count());
        assert_eq!(key(KeyCode::KeyR), Some(Key::Char('R')));
        assert_eq!(key(KeyCode::Digit9), Some(Key::Char('9')));
        assert_eq!(key(KeyCode::F12), Some(Key::F(12)));
        assert_eq!(key(KeyCode::Escape), Some(Key::Esc));
        assert_eq!(key(KeyCode::ShiftLeft), None);
        for k in HOST_KEYS {
            assert!(typed.contains(&k.key), "{} has no key code", k.key);
        }
        for scene in crate::scenes::SCENES {
            for help in scene.keys {
                assert!(
                    typed.contains(&Key::Char(help.key)),
                    "{scene}: key {:?} cannot be typed",
                    help.key
                );
            }
        }
    }
}
