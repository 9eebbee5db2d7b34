//! The front ends: the window (glutin + winit, in place of the tutorial's GLFW) and headless
//! rendering (EGL + an offscreen target), which also serves `--bench`, screenshots and the tests.
//! Both drive any [`Scene`] through the same seam, so a test's pixels are the
//! window's pixels. In a wasm32 build the browser page (`web`) drives it too, and the window and
//! headless rendering are left out.

#[cfg(not(target_arch = "wasm32"))]
pub mod headless;
pub mod host;
pub mod page_contract;
pub mod panel;
#[cfg(target_arch = "wasm32")]
pub mod web;
#[cfg(not(target_arch = "wasm32"))]
pub mod window;

use std::path::PathBuf;
use std::time::{Duration, SystemTime};

use crate::clock::Instant;

use crate::scenes::{MouseMode, Scene, SceneDescriptor};

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

/// The mouse and the arrow keys, listed before a mouse-look scene's keys (the host's look and arrow
/// input: not keys of [`HOST_KEYS`]). The page looks around with a drag instead.
const LOOK_ROWS: [(&str, &str); 2] = [
    ("mouse", "look around (the cursor is grabbed and hidden)"),
    ("arrow keys", "move forward / back, strafe left / right"),
];
const PAGE_LOOK_ROWS: [(&str, &str); 2] = [
    ("drag", "look around"),
    ("arrow keys", "move forward / back, strafe left / right"),
];

/// What one of the front ends' own keys does.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum HostAction {
    ResetCamera,
    ReleaseCursor,
    NextScene,
    ReloadShaders,
    Screenshot,
    TogglePanel,
    Quit,
}

/// A key of the front ends' own, whatever the scene.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct HostKey {
    /// As the key lists name it ("Enter", "F5", "R").
    pub key: &'static str,
    pub help: &'static str,
    pub action: HostAction,
    /// Listed for mouse-look scenes only (a free-cursor scene has no camera to steer).
    pub look_only: bool,
    /// The page has it too.
    pub on_page: bool,
}

/// The front ends' own keys, in the order they are listed after the scene's: their help rows and
/// their dispatch both come from here ([`HostKey::find`]).
pub const HOST_KEYS: &[HostKey] = &[
    HostKey {
        key: "R",
        help: "camera back to the tutorial's start",
        action: HostAction::ResetCamera,
        look_only: true,
        on_page: true,
    },
    HostKey {
        key: "Tab",
        help: "release the cursor (losing focus does too); a click grabs it again",
        action: HostAction::ReleaseCursor,
        look_only: true,
        on_page: false,
    },
    HostKey {
        key: "Enter",
        help: "next scene (see --scene)",
        action: HostAction::NextScene,
        look_only: false,
        on_page: true,
    },
    HostKey {
        key: "F5",
        help: "reload the shaders (saving a shader file does it too)",
        action: HostAction::ReloadShaders,
        look_only: false,
        on_page: false,
    },
    HostKey {
        key: "P",
        help: "save a screenshot (tutorial13-N.png in the current folder); Ctrl+P: with the panel",
        action: HostAction::Screenshot,
        look_only: false,
        on_page: false,
    },
    HostKey {
        key: "F1",
        help: "show / hide the panel (keys, switches, sliders)",
        action: HostAction::TogglePanel,
        look_only: false,
        on_page: true,
    },
    HostKey {
        key: "Esc",
        help: "quit (closing the window quits too)",
        action: HostAction::Quit,
        look_only: false,
        on_page: false,
    },
];

impl HostKey {
    /// What `key` (as the key lists name it) does in `front_end`, if it is one of its own keys.
    pub fn find(key: &str, front_end: FrontEnd) -> Option<HostAction> {
        HOST_KEYS
            .iter()
            .find(|k| k.key == key && (front_end == FrontEnd::Window || k.on_page))
            .map(|k| k.action)
    }

    /// Whether `front_end` lists this key for `scene`.
    fn listed(&self, scene: &SceneDescriptor, front_end: FrontEnd) -> bool {
        let look = scene.mouse_mode == MouseMode::Look;
        (look || !self.look_only) && (front_end == FrontEnd::Window || self.on_page)
    }
}

/// How the user runs this program from where they are, for the commands its messages suggest:
/// `cargo run --release --` when the binary is the one cargo built in a crate's target folder (a
/// clone, where it is not on PATH), else its name.
pub fn invocation() -> String {
    invocation_for(std::env::current_exe().ok().as_deref())
}

/// [`invocation`] for a binary at `exe`.
pub fn invocation_for(exe: Option<&std::path::Path>) -> String {
    let folder = |p: &std::path::Path, up: usize| {
        p.ancestors()
            .nth(up)
            .and_then(|d| d.file_name())
            .and_then(|n| n.to_str())
            .map(str::to_owned)
    };
    let Some(exe) = exe else {
        return "tutorial13".into();
    };
    match (folder(exe, 1).as_deref(), folder(exe, 2).as_deref()) {
        (Some("release"), Some("target")) => "cargo run --release --".into(),
        (Some("debug"), Some("target")) => "cargo run --".into(),
        _ => "tutorial13".into(),
    }
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

/// `docs/keys.md`: every scene of [`SCENES`](crate::scenes::SCENES), in their order, with its
/// description and a table of the rows [`key_list`] prints for it. A test (tests/all/docs.rs) fails
/// when the committed file differs from this.
pub fn keys_markdown() -> String {
    let cell = |text: &str| text.replace('|', "\\|");
    let mut text = String::from(
        "# Keys, scene by scene\n\n\
         *Generated from the scenes' key bindings by `keys_markdown` (src/frontends/mod.rs); do not \
         edit: the test `docs::keys_md_matches_the_code` (tests/all/docs.rs) fails when this file \
         differs, and rewrites it when run with `TUTORIAL13_UPDATE_DOCS=1`.*\n\n\
         The window prints the same list when a scene starts, and `--scene NAME --help` prints that scene's.\n",
    );
    for scene in crate::scenes::SCENES {
        text.push_str(&format!(
            "\n## {}\n\n`--scene {}`: {}\n\n| key | does |\n|---|---|\n",
            scene.name,
            scene.name,
            cell(scene.description)
        ));
        for (key, help) in key_rows(scene, FrontEnd::Window) {
            text.push_str(&format!("| {} | {} |\n", cell(&key), cell(help)));
        }
    }
    text
}

/// The rows of a scene's key list in `front_end`, in the order [`key_list`] and [`keys_markdown`]
/// give them: the mouse's (or the scene's own use of a free cursor), the scene's keys, then the
/// front end's own ([`HOST_KEYS`]).
pub(crate) fn key_rows(
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
    let is_window_key = |key: &str| HOST_KEYS.iter().any(|k| k.key == key);
    key_rows(descriptor, front_end)
        .into_iter()
        .map(|(key, help)| {
            let scene_key = descriptor
                .keys
                .iter()
                .find(|k| k.key.to_string() == key && k.help == help)
                .map(|k| k.key)
                .filter(|_| !is_window_key(&key));
            PanelKeyRow {
                key,
                help,
                scene_key,
            }
        })
        .collect()
}

/// A front end's clock: the time since it started and since the last frame (what the camera moves
/// by), and the tutorial's once-a-second "ms/frame" figure ([`FrameTimer`]).
pub struct FrameClock {
    started: Instant,
    last_time: Instant,
    timer: FrameTimer,
    ms_per_frame: Option<f64>,
}

/// What [`FrameClock::tick`] measured for a frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tick {
    /// Seconds since the last frame.
    pub delta_time: f32,
    /// Seconds since the clock started.
    pub time: f32,
    /// A new "ms/frame" figure, once a second.
    pub ms_per_frame: Option<f64>,
}

impl FrameClock {
    pub fn new() -> Self {
        let now = Instant::now();
        FrameClock {
            started: now,
            last_time: now,
            timer: FrameTimer::new(),
            ms_per_frame: None,
        }
    }

    /// A frame starts now.
    pub fn tick(&mut self) -> Tick {
        let now = Instant::now();
        let delta_time = (now - self.last_time).as_secs_f32();
        self.last_time = now;
        let ms_per_frame = self.timer.tick(now);
        if ms_per_frame.is_some() {
            self.ms_per_frame = ms_per_frame;
        }
        Tick {
            delta_time,
            time: (now - self.started).as_secs_f32(),
            ms_per_frame,
        }
    }

    /// Seconds since the clock started, now (the panel's clock: egui's animations and double
    /// clicks).
    pub fn seconds(&self) -> f64 {
        self.started.elapsed().as_secs_f64()
    }

    /// The last "ms/frame" figure (`None` in the first second).
    pub fn ms_per_frame(&self) -> Option<f64> {
        self.ms_per_frame
    }
}

impl Default for FrameClock {
    fn default() -> Self {
        Self::new()
    }
}

/// The tutorial's once-a-second "ms/frame" figure, computed as the tutorial does: 1000 divided by
/// the frames counted since the last print, and the next second starts exactly one second after the
/// last (not when the print happened), so a slow frame does not shift every later figure.
pub struct FrameTimer {
    last_time: Instant,
    nb_frames: u32,
}

impl FrameTimer {
    pub fn new() -> Self {
        FrameTimer {
            last_time: Instant::now(),
            nb_frames: 0,
        }
    }

    /// Counts a frame; once a second or more has passed since `last_time`, returns ms/frame.
    pub fn tick(&mut self, now: Instant) -> Option<f64> {
        self.nb_frames += 1;
        if now.duration_since(self.last_time) < Duration::from_secs(1) {
            return None;
        }
        let ms = 1000.0 / f64::from(self.nb_frames);
        self.nb_frames = 0;
        self.last_time += Duration::from_secs(1);
        Some(ms)
    }
}

impl Default for FrameTimer {
    fn default() -> Self {
        Self::new()
    }
}

/// Notices when a shader file a scene reads is saved, so that the window reloads it while it runs.
/// It polls the files' modification times and sizes (a few `stat` calls, four times a second) rather
/// than subscribing to file-system events: editors save by rewriting, renaming or replacing a file,
/// and all of them change what `stat` reports.
pub struct ShaderWatch {
    stamps: Vec<(PathBuf, Option<(SystemTime, u64)>)>,
    last_poll: Instant,
}

/// How often the files are looked at.
const SHADER_POLL: Duration = Duration::from_millis(250);

impl ShaderWatch {
    /// Starts from the files `scene` reads now.
    pub fn new(scene: &dyn Scene) -> Self {
        ShaderWatch {
            stamps: stamps(scene),
            last_poll: Instant::now(),
        }
    }

    /// Whether a file changed (or another file is now read in its place) since the last time this
    /// said so; looks at most every 250 ms.
    pub fn changed(&mut self, scene: &dyn Scene, now: Instant) -> bool {
        if now.duration_since(self.last_poll) < SHADER_POLL {
            return false;
        }
        self.last_poll = now;
        let stamps = stamps(scene);
        if stamps == self.stamps {
            return false;
        }
        self.stamps = stamps;
        true
    }
}

fn stamps(scene: &dyn Scene) -> Vec<(PathBuf, Option<(SystemTime, u64)>)> {
    let stamp = |path: &PathBuf| {
        let meta = std::fs::metadata(path).ok()?;
        Some((meta.modified().ok()?, meta.len()))
    };
    scene
        .shader_files()
        .into_iter()
        .map(|path| {
            let stamp = stamp(&path);
            (path, stamp)
        })
        .collect()
}

/// (min, median) of a list of timings.
pub fn min_median(times: &[f64]) -> (f64, f64) {
    let mut sorted = times.to_vec();
    sorted.sort_by(f64::total_cmp);
    let min = sorted.first().copied().unwrap_or(f64::NAN);
    let median = sorted.get(sorted.len() / 2).copied().unwrap_or(f64::NAN);
    (min, median)
}

#[cfg(test)]
mod tests {
    use super::*;

    // Fails if a message suggests `tutorial13 ...` to a user who runs the binary cargo built in a
    // clone (not on PATH), or `cargo run` to one who installed it.
    #[test]
    fn suggested_commands_run_from_where_the_user_is() {
        use std::path::Path;
        let at = |p: &str| invocation_for(Some(Path::new(p)));
        assert_eq!(
            at("/home/l/tutorial13/target/release/tutorial13"),
            "cargo run --release --"
        );
        assert_eq!(
            at("/home/l/tutorial13/target/debug/tutorial13"),
            "cargo run --"
        );
        assert_eq!(at("/usr/local/bin/tutorial13"), "tutorial13");
        assert_eq!(at("/opt/release/tutorial13"), "tutorial13");
        assert_eq!(invocation_for(None), "tutorial13");
    }

    // Fails if the figure is not the tutorial's 1000 / frames, or the next second does not start
    // exactly one second after the last one.
    #[test]
    fn frame_timer_counts_as_the_tutorial() {
        let mut timer = FrameTimer::new();
        let start = timer.last_time;
        let ms = |t: f64| start + Duration::from_secs_f64(t);
        assert_eq!(timer.tick(ms(0.3)), None);
        assert_eq!(timer.tick(ms(0.6)), None);
        assert_eq!(timer.tick(ms(0.9)), None);
        assert_eq!(timer.tick(ms(1.25)), Some(250.0)); // 4 frames in the first second
        assert_eq!(timer.last_time, ms(1.0));
        assert_eq!(timer.tick(ms(1.5)), None);
        assert_eq!(timer.tick(ms(2.0)), Some(500.0)); // 2 frames in the next
    }

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
                    .map(|k| k.key)
                    .chain(LOOK_ROWS.map(|(k, _)| k));
                let taken = taken.any(|key| key == help.key.to_string());
                assert!(!taken, "{scene}: key {} is the window's", help.key);
                assert!(list.contains(&format!("\n  {:<15} {}", help.key, help.help)));
            }
            let look = scene.mouse_mode == MouseMode::Look;
            for k in HOST_KEYS {
                let listed = list.contains(&format!("\n  {:<15} {}", k.key, k.help));
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
                let listed = rows.iter().any(|(key, _)| key == k.key);
                let has = HostKey::find(k.key, FrontEnd::Page);
                assert_eq!(
                    listed,
                    has.is_some() && k.listed(scene, FrontEnd::Window),
                    "{scene}: {}",
                    k.key
                );
                if let Some(action) = has {
                    assert_eq!(Some(action), HostKey::find(k.key, FrontEnd::Window));
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
