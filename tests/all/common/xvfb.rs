//! A private X server for the window tests, driven with xdotool as a user would drive the window.
//! Needs the Debian packages xvfb and xdotool (.ci/run installs them).

use std::ffi::OsStr;
use std::io::{BufRead, BufReader, Read};
use std::path::Path;
use std::process::{Child, Command, ExitStatus, Stdio};
use std::sync::{mpsc, Mutex, MutexGuard};
use std::time::{Duration, Instant};

/// How long the server may take to accept a client on two busy cores.
const READY_TIMEOUT: Duration = Duration::from_secs(60);

/// How long a window step (a window appearing, a screenshot, an exit) may take on two busy cores.
pub const STEP_TIMEOUT: Duration = Duration::from_secs(60);

/// One server at a time in the test binary: two started at once can both pick the same free display.
static ONE_SERVER: Mutex<()> = Mutex::new(());

/// Xvfb on a display it picks itself (`-displayfd`, so a developer's own X server never clashes),
/// killed when dropped (also when the test panics).
pub struct Xvfb {
    child: Child,
    pub display: String,
    _one_at_a_time: MutexGuard<'static, ()>,
}

impl Xvfb {
    /// Starts the server and returns once a client can connect.
    pub fn start() -> Self {
        let guard = ONE_SERVER.lock().unwrap_or_else(|e| e.into_inner());
        let mut child = Command::new("Xvfb")
            .args(["-displayfd", "1", "-screen", "0", "1280x1024x24"])
            .args(["-nolisten", "tcp"])
            // Without it the server resets whenever its last client leaves (the readiness probe,
            // an xdotool call), and a program connecting during the reset is refused: "no display".
            .arg("-noreset")
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .unwrap_or_else(|e| {
                panic!(
                    "cannot start Xvfb ({e}), so the window cannot be tested: apt-get install xvfb"
                )
            });
        let stdout = child.stdout.take().unwrap();
        let (tx, rx) = mpsc::channel();
        std::thread::spawn(move || {
            let mut lines = BufReader::new(stdout).lines();
            let _ = tx.send(lines.next());
            // Keep draining so that the server never blocks on a full pipe.
            for _ in lines {}
        });
        match rx.recv_timeout(Duration::from_secs(10)) {
            Ok(Some(Ok(n))) if n.trim().parse::<u32>().is_ok() => Xvfb {
                child,
                display: format!(":{}", n.trim()),
                _one_at_a_time: guard,
            }
            .wait_ready(),
            other => {
                let _ = child.kill();
                let _ = child.wait();
                panic!("Xvfb reported no display within 10 s: {other:?}");
            }
        }
    }

    /// Waits until a client can connect (the display number can come a moment before that).
    fn wait_ready(self) -> Self {
        let start = Instant::now();
        loop {
            let probe = Command::new("xdotool")
                .arg("getmouselocation")
                .env("DISPLAY", &self.display)
                .stdout(Stdio::null())
                .stderr(Stdio::null())
                .status()
                .unwrap_or_else(|e| panic!("cannot run xdotool ({e}): apt-get install xdotool"));
            if probe.success() {
                return self;
            }
            assert!(
                start.elapsed() < READY_TIMEOUT,
                "no connection to {}",
                self.display
            );
            std::thread::sleep(Duration::from_millis(100));
        }
    }

    /// Runs `xdotool ARGS` on this display and returns its stdout.
    pub fn xdotool(&self, args: &[&str]) -> String {
        let out = Command::new("xdotool")
            .args(args)
            .env("DISPLAY", &self.display)
            .output()
            .unwrap_or_else(|e| panic!("cannot run xdotool ({e}): apt-get install xdotool"));
        String::from_utf8_lossy(&out.stdout).into_owned()
    }
}

/// Window tests: the program itself on this server, and what a user sees of it.
impl Xvfb {
    /// The program in a window on this display, started in `dir` (where P writes tutorial13-N.png),
    /// with its stderr kept for [`wait_exit`].
    pub fn start_program<S: AsRef<OsStr>>(&self, dir: &Path, args: &[S]) -> Child {
        super::tutorial13()
            .args(args)
            .current_dir(dir)
            .env("DISPLAY", &self.display)
            .env_remove("WAYLAND_DISPLAY")
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap()
    }

    /// The id of the program's window once it has drawn its first frame (the title then names the
    /// scene: input sent before that could reach a window whose scene is still loading); fails with
    /// the program's stderr if it exits first.
    pub fn wait_for_window(&self, app: &mut Child) -> String {
        wait_for("the window's first frame", || {
            if app.try_wait().unwrap().is_some() {
                let (status, stderr) = wait_exit(app);
                panic!("the program exited ({status}) before its first frame:\n{stderr}");
            }
            let found = self.xdotool(&["search", "--name", "Tutorial 13"]);
            let window = found.lines().next()?.to_string();
            let title = self.xdotool(&["getwindowname", &window]);
            title
                .trim_end()
                .ends_with(" | Tutorial 13")
                .then_some(window)
        })
    }

    /// [`Xvfb::start_program`], then waits for its window and gives it the focus; returns the
    /// program and its window's id.
    pub fn open_window<S: AsRef<OsStr>>(&self, dir: &Path, args: &[S]) -> (Child, String) {
        let mut app = self.start_program(dir, args);
        let window = self.wait_for_window(&mut app);
        self.xdotool(&["windowfocus", "--sync", &window]);
        (app, window)
    }

    /// Presses Esc and checks that the program quits cleanly; returns its stderr.
    pub fn quit(&self, app: &mut Child) -> String {
        self.xdotool(&["key", "Escape"]);
        let (status, stderr) = wait_exit(app);
        assert!(status.success(), "{stderr}");
        stderr
    }

    /// Presses P and waits for the numbered screenshot the window writes into `dir`.
    pub fn screenshot(&self, dir: &Path, n: u32) -> image::RgbImage {
        self.screenshot_with(dir, n, "p")
    }

    /// Presses `keys` (P, or Ctrl+P: the window with its panel) and waits for the numbered
    /// screenshot the window writes into `dir`.
    /// Fails if the window has saved more screenshots than the `n` asked for so far (one press
    /// saving two: every later screenshot read would then be one press late).
    pub fn screenshot_with(&self, dir: &Path, n: u32, keys: &str) -> image::RgbImage {
        self.xdotool(&["key", keys]);
        let path = dir.join(format!("tutorial13-{n}.png"));
        // The file appears by rename, so it is whole once it exists.
        let shot = wait_for(&format!("{}", path.display()), || image::open(&path).ok()).into_rgb8();
        let saved = numbered_screenshots(dir);
        assert_eq!(saved, n, "{saved} screenshots saved for {n} presses");
        shot
    }
}

/// How many numbered screenshots (tutorial13-N.png) the window has saved into `dir`.
pub fn numbered_screenshots(dir: &Path) -> u32 {
    let numbered = |name: &str| {
        let n = name.strip_prefix("tutorial13-")?.strip_suffix(".png")?;
        n.parse::<u32>().ok()
    };
    std::fs::read_dir(dir)
        .unwrap()
        .filter(|e| numbered(&e.as_ref().unwrap().file_name().to_string_lossy()).is_some())
        .count() as u32
}

/// Polls `get` every 100 ms until it gives something, or fails after [`STEP_TIMEOUT`].
pub fn wait_for<T>(what: &str, mut get: impl FnMut() -> Option<T>) -> T {
    let start = Instant::now();
    loop {
        if let Some(value) = get() {
            return value;
        }
        assert!(
            start.elapsed() < STEP_TIMEOUT,
            "{what}: nothing after {STEP_TIMEOUT:?}"
        );
        std::thread::sleep(Duration::from_millis(100));
    }
}

/// Waits for the program to exit (killing it after [`STEP_TIMEOUT`]): its status and stderr.
pub fn wait_exit(app: &mut Child) -> (ExitStatus, String) {
    let start = Instant::now();
    let status = loop {
        if let Some(status) = app.try_wait().unwrap() {
            break status;
        }
        if start.elapsed() > STEP_TIMEOUT {
            let _ = app.kill();
            panic!("the program did not exit within {STEP_TIMEOUT:?}");
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    let mut stderr = String::new();
    if let Some(mut pipe) = app.stderr.take() {
        pipe.read_to_string(&mut stderr).unwrap();
    }
    (status, stderr)
}

impl Drop for Xvfb {
    /// SIGTERM first, so that the server removes its socket and lock file (SIGKILL leaves them, and
    /// the next server can then pick the same display number while a client still finds the stale
    /// socket); SIGKILL only if it has not gone within 5 s.
    fn drop(&mut self) {
        let terminated = Command::new("kill")
            .args(["-TERM", &self.child.id().to_string()])
            .status()
            .is_ok_and(|s| s.success());
        let deadline = Instant::now() + Duration::from_secs(5);
        while terminated && Instant::now() < deadline {
            if let Ok(Some(_)) = self.child.try_wait() {
                return;
            }
            std::thread::sleep(Duration::from_millis(20));
        }
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}
