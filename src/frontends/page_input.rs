//! The page's input as the host's: DOM key names as [`Key`]s, the wheel's deltas as notches. Pure
//! functions of the DOM's values, compiled natively too, so that their tests run with the others (the
//! page itself, `frontends::web`, is wasm32 only).

use glam::Vec2;

use super::keys::{Arrow, Key};

/// A DOM `KeyboardEvent.key` as the key lists name it: the arrows, a letter (upper-case, either
/// case typed) or digit, Escape, Tab, Enter, F1 to F12, PageDown, PageUp; `None` for any other.
pub fn key(name: &str) -> Option<Key> {
    let mut chars = name.chars();
    if let (Some(c), None) = (chars.next(), chars.next()) {
        return c
            .is_ascii_alphanumeric()
            .then(|| Key::Char(c.to_ascii_uppercase()));
    }
    Some(match name {
        "ArrowUp" => Key::Arrow(Arrow::Up),
        "ArrowDown" => Key::Arrow(Arrow::Down),
        "ArrowLeft" => Key::Arrow(Arrow::Left),
        "ArrowRight" => Key::Arrow(Arrow::Right),
        "Escape" => Key::Esc,
        "Tab" => Key::Tab,
        "Enter" => Key::Enter,
        "PageDown" => Key::PageDown,
        "PageUp" => Key::PageUp,
        _ => {
            let n: u8 = name.strip_prefix('F')?.parse().ok()?;
            return (1..=12).contains(&n).then_some(Key::F(n));
        }
    })
}

/// The DOM's `WheelEvent.deltaMode` in lines (Firefox's for a mouse wheel).
pub const DOM_DELTA_LINE: u32 = 1;

/// About this many pixels of a DOM wheel delta make one notch of a wheel.
const PIXELS_PER_NOTCH: f64 = 100.0;

/// A DOM wheel event's deltas (`deltaX`, `deltaY`, in `deltaMode`'s unit) as notches, `y` positive
/// away from the user (as winit's and the host's).
pub fn wheel_notches(delta_x: f64, delta_y: f64, delta_mode: u32) -> Vec2 {
    let per_notch = if delta_mode == DOM_DELTA_LINE {
        1.0
    } else {
        PIXELS_PER_NOTCH
    };
    Vec2::new((-delta_x / per_notch) as f32, (-delta_y / per_notch) as f32)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frontends::keys::{host_action, FrontEnd, HOST_KEYS};

    // Fails if a DOM key name is not the key the lists name (a letter typed in either case, Escape
    // as Esc), or a key the page has in the table cannot be typed on the page.
    #[test]
    fn dom_keys_are_the_lists_keys() {
        assert_eq!(key("r"), Some(Key::Char('R')));
        assert_eq!(key("R"), Some(Key::Char('R')));
        assert_eq!(key("7"), Some(Key::Char('7')));
        assert_eq!(key("Escape"), Some(Key::Esc));
        assert_eq!(key("F5"), Some(Key::F(5)));
        assert_eq!(key("ArrowLeft"), Some(Key::Arrow(Arrow::Left)));
        for other in ["F0", "F13", "Shift", " ", "é", "Fx"] {
            assert_eq!(key(other), None, "{other:?}");
        }
        for k in HOST_KEYS.iter().filter(|k| k.on_page) {
            let typed = key(&k.key.to_string()).or(key(&k.key.to_string().to_lowercase()));
            assert_eq!(typed, Some(k.key), "{}", k.key);
            assert_eq!(
                host_action(HOST_KEYS, k.key, FrontEnd::Page),
                Some(k.action)
            );
        }
    }

    // Fails if 100 pixels of a DOM delta (Chromium's notch) or one line (Firefox's) is not one
    // notch, or the sign is not winit's (up, away from the user, positive).
    #[test]
    fn dom_wheel_deltas_are_notches() {
        assert_eq!(wheel_notches(0.0, -500.0, 0), Vec2::new(0.0, 5.0));
        assert_eq!(
            wheel_notches(100.0, 3.0, DOM_DELTA_LINE),
            Vec2::new(-100.0, -3.0)
        );
    }
}
