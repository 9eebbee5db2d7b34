//! Keys as every front end names them: [`Key`] (what a platform's key code or DOM name becomes),
//! the front ends' own keys ([`HOST_KEYS`]: their help rows and the action the host runs for each),
//! and the key lists built from them and the scene's keys (printed at start and by `--help`, shown
//! on the panel, written to docs/keys.md).

use std::fmt;

use crate::scenes::{MouseMode, SceneDescriptor};

/// An arrow key: the tutorial's camera moves while one is held.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Arrow {
    Up,
    Down,
    Left,
    Right,
}

/// A key as the key lists name it, whatever the platform calls it: each front end turns its own
/// key codes into these in one place (the window's `KeyCode`s, the page's DOM names).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Key {
    /// Held, it moves the tutorial's camera.
    Arrow(Arrow),
    /// A letter (upper-case) or a digit: a scene's key, or one of [`HOST_KEYS`] (R, P).
    Char(char),
    Esc,
    Tab,
    Enter,
    /// F1 to F12.
    F(u8),
    PageDown,
    PageUp,
}

impl fmt::Display for Key {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Key::Arrow(arrow) => write!(f, "{arrow:?}"),
            Key::Char(c) => write!(f, "{c}"),
            Key::Esc => f.write_str("Esc"),
            Key::Tab => f.write_str("Tab"),
            Key::Enter => f.write_str("Enter"),
            Key::F(n) => write!(f, "F{n}"),
            Key::PageDown => f.write_str("PageDown"),
            Key::PageUp => f.write_str("PageUp"),
        }
    }
}

/// Which front end a key list is for: the browser page lacks the keys a tab cannot honour (a
/// grabbed cursor, files on disk, quitting).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum FrontEnd {
    /// The window, and headless rendering, which draws the window's frame.
    #[default]
    Window,
    /// The WebGL2 page.
    Page,
}

impl FrontEnd {
    /// Whether a click grabs the cursor for mouse look until Tab or a loss of focus releases it.
    /// A page cannot grab it without the user's leave: there a drag looks around instead.
    pub fn grabs_cursor(self) -> bool {
        self == FrontEnd::Window
    }
}

/// The mouse and the arrow keys, listed before a mouse-look scene's keys (the host's look and arrow
/// input: not keys of [`HOST_KEYS`]). The page looks around with a drag instead.
pub(crate) const LOOK_ROWS: [(&str, &str); 2] = [
    ("mouse", "look around (the cursor is grabbed and hidden)"),
    ("arrow keys", "move forward / back, strafe left / right"),
];
const PAGE_LOOK_ROWS: [(&str, &str); 2] = [
    ("drag", "look around"),
    ("arrow keys", "move forward / back, strafe left / right"),
];

/// What one of the front ends' own keys does (the host runs it: `SceneHost::event`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum HostAction {
    ResetCamera,
    ReleaseCursor,
    NextScene,
    ReloadShaders,
    Screenshot,
    TogglePanel,
    TourNext,
    TourBack,
    CheckExercise,
    Quit,
}

/// A key of the front ends' own, whatever the scene.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct HostKey {
    pub key: Key,
    pub help: &'static str,
    pub action: HostAction,
    /// Listed for mouse-look scenes only (a free-cursor scene has no camera to steer).
    pub look_only: bool,
    /// The page has it too.
    pub on_page: bool,
}

/// The front ends' own keys, in the order they are listed after the scene's: their help rows and
/// their dispatch (the host's, [`host_action`]) both come from here.
pub const HOST_KEYS: &[HostKey] = &[
    HostKey {
        key: Key::Char('R'),
        help: "camera back to the tutorial's start",
        action: HostAction::ResetCamera,
        look_only: true,
        on_page: true,
    },
    HostKey {
        key: Key::Tab,
        help: "release the cursor (losing focus does too); a click grabs it again",
        action: HostAction::ReleaseCursor,
        look_only: true,
        on_page: false,
    },
    HostKey {
        key: Key::Enter,
        help: "next scene (see --scene)",
        action: HostAction::NextScene,
        look_only: false,
        on_page: true,
    },
    HostKey {
        key: Key::F(5),
        help: "reload the shaders (saving a shader file does it too)",
        action: HostAction::ReloadShaders,
        look_only: false,
        on_page: false,
    },
    HostKey {
        key: Key::Char('P'),
        help: "save a screenshot (tutorial13-N.png in the current folder); Ctrl+P: with the panel",
        action: HostAction::Screenshot,
        look_only: false,
        on_page: false,
    },
    HostKey {
        key: Key::F(1),
        help: "show / hide the panel (keys, switches, sliders)",
        action: HostAction::TogglePanel,
        look_only: false,
        on_page: true,
    },
    HostKey {
        key: Key::PageDown,
        help: "the tour of the tutorial: next section",
        action: HostAction::TourNext,
        look_only: false,
        on_page: true,
    },
    HostKey {
        key: Key::PageUp,
        help: "the tour: the section before",
        action: HostAction::TourBack,
        look_only: false,
        on_page: true,
    },
    HostKey {
        key: Key::F(2),
        help: "the tour's exercise steps: check your exercise",
        action: HostAction::CheckExercise,
        look_only: false,
        on_page: true,
    },
    HostKey {
        key: Key::Esc,
        help: "quit (closing the window quits too)",
        action: HostAction::Quit,
        look_only: false,
        on_page: false,
    },
];

impl HostKey {
    /// Whether `front_end` has this key.
    pub fn on(&self, front_end: FrontEnd) -> bool {
        front_end == FrontEnd::Window || self.on_page
    }

    /// Whether `front_end` lists this key for `scene`.
    fn listed(&self, scene: &SceneDescriptor, front_end: FrontEnd) -> bool {
        let look = scene.mouse_mode == MouseMode::Look;
        (look || !self.look_only) && self.on(front_end)
    }
}

/// What `key` does in `front_end` by `table` ([`HOST_KEYS`]), if it is one of its keys there.
pub fn host_action(table: &[HostKey], key: Key, front_end: FrontEnd) -> Option<HostAction> {
    table
        .iter()
        .find(|k| k.key == key && k.on(front_end))
        .map(|k| k.action)
}

/// The key list printed at start and by `--help`: what the mouse does (the window's mouse look, or
/// the scene's own use of a free cursor), the scene's keys, then the window's.
pub fn key_list(scene: &'static SceneDescriptor) -> String {
    let mut text = format!("Keys (window, scene {scene}):");
    for (key, help) in key_rows(scene, FrontEnd::Window) {
        text.push_str(&format!("\n  {key:<15} {help}"));
    }
    text
}

/// The rows of a scene's key list in `front_end`, in the order [`key_list`] and docs/keys.md give
/// them: the mouse's (or the scene's own use of a free cursor), the scene's keys, then the front
/// end's own ([`HOST_KEYS`]).
pub fn key_rows(
    scene: &'static SceneDescriptor,
    front_end: FrontEnd,
) -> Vec<(String, &'static str)> {
    let before: &[(&str, &'static str)] = match (scene.mouse_mode, front_end) {
        (MouseMode::Look, FrontEnd::Window) => &LOOK_ROWS,
        (MouseMode::Look, FrontEnd::Page) => &PAGE_LOOK_ROWS,
        (MouseMode::Cursor, _) => scene.mouse_help,
    };
    let before = before.iter().map(|&(key, help)| (key.to_string(), help));
    let scene_keys = scene.keys.iter().map(|k| (k.key.to_string(), k.help));
    let host = HOST_KEYS.iter().filter(|k| k.listed(scene, front_end));
    before
        .chain(scene_keys)
        .chain(host.map(|k| (k.key.to_string(), k.help)))
        .collect()
}

/// One row of the panel's key list.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PanelKeyRow {
    /// The key as listed ("L", "arrow keys").
    pub key: String,
    pub help: &'static str,
    /// The scene's key, where the row is one (the panel presses it).
    pub scene_key: Option<char>,
}

/// The panel's key list in `front_end`: the rows `--help` and the window print for the scene (the
/// page's own where it is the page), the scene's own keys marked as such.
pub fn panel_key_rows(
    descriptor: &'static SceneDescriptor,
    front_end: FrontEnd,
) -> Vec<PanelKeyRow> {
    let is_host_key = |key: &str| HOST_KEYS.iter().any(|k| k.key.to_string() == key);
    key_rows(descriptor, front_end)
        .into_iter()
        .map(|(key, help)| {
            let scene_key = descriptor
                .keys
                .iter()
                .find(|k| k.key.to_string() == key && k.help == help)
                .map(|k| k.key)
                .filter(|_| !is_host_key(&key));
            PanelKeyRow {
                key,
                help,
                scene_key,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    // Fails if a scene binds a key the window already uses (the window would take it first and the
    // scene's action could never be reached), if the key list leaves out a window or scene key, or
    // if it promises mouse look where the cursor stays free (or leaves the mouse out).
    #[test]
    fn scene_keys_are_free_and_listed() {
        for scene in crate::scenes::SCENES {
            let list = key_list(scene);
            for help in scene.keys {
                let mut taken = HOST_KEYS
                    .iter()
                    .map(|k| k.key.to_string())
                    .chain(LOOK_ROWS.map(|(k, _)| k.to_string()));
                let taken = taken.any(|key| key == help.key.to_string());
                assert!(!taken, "{scene}: key {} is the window's", help.key);
                assert!(list.contains(&format!("\n  {:<15} {}", help.key, help.help)));
            }
            let look = scene.mouse_mode == MouseMode::Look;
            for k in HOST_KEYS {
                let listed = list.contains(&format!("\n  {:<15} {}", k.key.to_string(), k.help));
                assert_eq!(listed, look || !k.look_only, "{scene}: {}", k.key);
            }
            for (key, help) in LOOK_ROWS {
                let listed = list.contains(&format!("\n  {key:<15} {help}"));
                assert_eq!(listed, look, "{scene}: {key}");
            }
            assert_eq!(scene.mouse_help.is_empty(), look, "{scene}");
            assert!(
                list.contains("\n  mouse "),
                "{scene}: the mouse is not listed"
            );
        }
    }

    // Fails if the page's key list names a key the page does nothing with (F5, P, Tab, Esc), or
    // leaves out one it has, or if a key it lists does not reach the same action as in the window:
    // the panel shows this list, and the page dispatches through the same table.
    #[test]
    fn the_page_lists_the_keys_it_has() {
        for scene in crate::scenes::SCENES {
            let rows = key_rows(scene, FrontEnd::Page);
            for k in HOST_KEYS {
                let listed = rows.iter().any(|(key, _)| *key == k.key.to_string());
                let has = host_action(HOST_KEYS, k.key, FrontEnd::Page);
                assert_eq!(
                    listed,
                    has.is_some() && k.listed(scene, FrontEnd::Window),
                    "{scene}: {}",
                    k.key
                );
                if let Some(action) = has {
                    assert_eq!(
                        Some(action),
                        host_action(HOST_KEYS, k.key, FrontEnd::Window)
                    );
                }
            }
            for absent in ["F5", "P", "Tab", "Esc"] {
                assert!(
                    !rows.iter().any(|(key, _)| key == absent),
                    "{scene}: {absent}"
                );
            }
        }
    }
}
