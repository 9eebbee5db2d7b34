//! A private X server for the window tests, driven with xdotool as a user would drive the window.
//! Needs the Debian packages xvfb and xdotool (.ci/run installs them).

use std::ffi::OsStr;
use std::io::{BufRead, BufReader, Read};
use std::path::Path;
use std::process::{Child, Command, ExitStatus, Stdio};
use std::sync::{mpsc, Arc, Mutex, MutexGuard};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// How long the server may take to accept a client on two busy cores.
const READY_TIMEOUT: Duration = Duration::from_secs(60);

/// How long a window step (a window appearing, a screenshot, an exit) may take on two busy cores.
pub const STEP_TIMEOUT: Duration = Duration::from_secs(60);

/// One server at a time in the test binary: two started at once can both pick the same free display.
static ONE_SERVER: Mutex<()> = Mutex::new(());

/// The programs started on the server now running (one window test at a time, [`ONE_SERVER`]): a
/// wait that runs out says what became of each ([`programs_report`]), since a window that stopped
/// answering and a program that died look alike from xdotool.
static PROGRAMS: Mutex<Vec<(u32, Arc<Mutex<String>>)>> = Mutex::new(Vec::new());

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
        match rx.recv_timeout(Duration::from_secs(30)) {
            Ok(Some(Ok(n))) if n.trim().parse::<u32>().is_ok() => Xvfb {
                child,
                display: format!(":{}", n.trim()),
                _one_at_a_time: guard,
            }
            .wait_ready(),
            other => {
                let _ = child.kill();
                let _ = child.wait();
                panic!("Xvfb reported no display within 30 s: {other:?}");
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

/// How a window test runs the program: its own log at info, its window's at debug, where the window
/// acknowledges a resize ("resized to WxH") and a key's auto-repeat ("KeyP repeated").
const PROGRAM_LOG: &str = "info,tutorial13::frontends::window=debug";

/// The program in a window on an [`Xvfb`], and what it has printed so far: its stdout and stderr are
/// read on threads as they come, so that a test can wait for a line. Killed when dropped if it is
/// still running (a test that fails leaves no program behind).
pub struct Program {
    child: Child,
    /// Taken just before the program started, so before its clock started.
    started: Instant,
    stdout: Arc<Mutex<String>>,
    stderr: Arc<Mutex<String>>,
    readers: Vec<JoinHandle<()>>,
}

/// Appends what `pipe` gives to `into`, a line at a time, until it closes.
fn keep_reading(pipe: impl Read + Send + 'static, into: Arc<Mutex<String>>) -> JoinHandle<()> {
    std::thread::spawn(move || {
        let mut pipe = BufReader::new(pipe);
        let mut line = Vec::new();
        while pipe.read_until(b'\n', &mut line).is_ok_and(|n| n > 0) {
            into.lock()
                .unwrap()
                .push_str(&String::from_utf8_lossy(&line));
            line.clear();
        }
    })
}

impl Program {
    /// What it has written to stderr so far: its log and error lines.
    pub fn stderr(&self) -> String {
        self.stderr.lock().unwrap().clone()
    }

    /// What it has written to stdout so far: the key lists and the "ms/frame" figures.
    pub fn stdout(&self) -> String {
        self.stdout.lock().unwrap().clone()
    }

    /// The lines of its log (stderr) that contain `part`, so far.
    pub fn log_lines(&self, part: &str) -> Vec<String> {
        let stderr = self.stderr.lock().unwrap();
        stderr
            .lines()
            .filter(|l| l.contains(part))
            .map(str::to_string)
            .collect()
    }

    /// Fails with its stderr if it has exited (so that a wait does not run to its deadline on a
    /// program that has gone).
    fn assert_running(&mut self, what: &str) {
        if self.child.try_wait().unwrap().is_some() {
            let (status, stderr) = wait_exit(self);
            panic!("{what}: the program exited ({status}) first; its stderr:\n{stderr}");
        }
    }

    /// Waits until its stderr, as a whole, satisfies `ok`; fails (with the stderr) after
    /// [`STEP_TIMEOUT`] or if it exits first.
    pub fn wait_for_stderr(&mut self, what: &str, ok: impl Fn(&str) -> bool) {
        let start = Instant::now();
        while !ok(&self.stderr()) {
            self.assert_running(what);
            assert!(
                start.elapsed() < STEP_TIMEOUT,
                "{what}: not seen within {STEP_TIMEOUT:?}{}",
                programs_report()
            );
            std::thread::sleep(POLL);
        }
    }

    /// Waits until `n` lines of its log contain `part` (the program's acknowledgement of something:
    /// "shaders reloaded", "resized to 800x600", "panel hidden"), counting from its start.
    pub fn wait_for_log(&mut self, part: &str, n: usize) {
        let what = format!("{n} line(s) of the program's log with {part:?}");
        self.wait_for_stderr(&what, |stderr| {
            stderr.lines().filter(|l| l.contains(part)).count() >= n
        });
    }

    /// Waits for a frame the program draws at `at` or later by its own clock, as its once-a-second
    /// "ms/frame" figure on stdout shows: the k-th figure comes from a frame at least k seconds after
    /// its frame timer started, which is after [`Program::started`] (both processes read the same
    /// monotonic clock). For what the program does by the clock in its frames, not on an input (the
    /// shader watcher's looks).
    pub fn wait_for_a_frame_at(&mut self, at: Instant) {
        let k = at
            .saturating_duration_since(self.started)
            .as_secs_f64()
            .ceil()
            .max(1.0) as usize;
        let what = format!(
            "the program's ms/frame figure number {k} (a frame drawn {:?} after it started)",
            at - self.started
        );
        let start = Instant::now();
        while self
            .stdout()
            .lines()
            .filter(|l| l.ends_with(" ms/frame"))
            .count()
            < k
        {
            self.assert_running(&what);
            assert!(
                start.elapsed() < STEP_TIMEOUT,
                "{what}: not seen within {STEP_TIMEOUT:?}; its stdout:\n{}{}",
                self.stdout(),
                programs_report()
            );
            std::thread::sleep(POLL);
        }
    }
}

impl Drop for Program {
    fn drop(&mut self) {
        let pid = self.child.id();
        PROGRAMS
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .retain(|(p, _)| *p != pid);
        if let Ok(None) = self.child.try_wait() {
            let _ = self.child.kill();
            let _ = self.child.wait();
        }
    }
}

/// Window tests: the program itself on this server, and what a user sees of it.
impl Xvfb {
    /// The program in a window on this display, started in `dir` (where P writes tutorial13-N.png),
    /// its output kept ([`Program`]) and its log as [`PROGRAM_LOG`] says.
    pub fn start_program<S: AsRef<OsStr>>(&self, dir: &Path, args: &[S]) -> Program {
        let started = Instant::now();
        let mut child = super::tutorial13()
            .args(args)
            .current_dir(dir)
            .env("DISPLAY", &self.display)
            .env("RUST_LOG", PROGRAM_LOG)
            .env_remove("WAYLAND_DISPLAY")
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let (stdout, stderr) = (Arc::default(), Arc::default());
        PROGRAMS
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .push((child.id(), Arc::clone(&stderr)));
        let readers = vec![
            keep_reading(child.stdout.take().unwrap(), Arc::clone(&stdout)),
            keep_reading(child.stderr.take().unwrap(), Arc::clone(&stderr)),
        ];
        Program {
            child,
            started,
            stdout,
            stderr,
            readers,
        }
    }

    /// The id of the program's window once it has drawn its first frame (the title then names the
    /// scene: input sent before that could reach a window whose scene is still loading); fails with
    /// the program's stderr if it exits first.
    pub fn wait_for_window(&self, app: &mut Program) -> String {
        wait_for(
            "the window's first frame (a title ending in \" | Tutorial 13\")",
            || {
                app.assert_running("the window's first frame");
                let found = self.xdotool(&["search", "--name", "Tutorial 13"]);
                let window = found.lines().next()?.to_string();
                self.title(&window)
                    .trim_end()
                    .ends_with(" | Tutorial 13")
                    .then_some(window)
            },
        )
    }

    /// [`Xvfb::start_program`], then waits for its window and gives it the focus; returns the
    /// program and its window's id.
    pub fn open_window<S: AsRef<OsStr>>(&self, dir: &Path, args: &[S]) -> (Program, String) {
        let mut app = self.start_program(dir, args);
        let window = self.wait_for_window(&mut app);
        self.xdotool(&["windowfocus", "--sync", &window]);
        (app, window)
    }

    /// Presses Esc and checks that the program quits cleanly; returns its stderr.
    pub fn quit(&self, app: &mut Program) -> String {
        self.xdotool(&["key", "Escape"]);
        let (status, stderr) = wait_exit(app);
        assert!(status.success(), "{stderr}");
        stderr
    }

    /// The window's title now.
    pub fn title(&self, window: &str) -> String {
        self.xdotool(&["getwindowname", window])
    }

    /// Waits until the window's title satisfies `ok` (`what` says what the test waits for), and
    /// returns it. The title is set by a frame: one that satisfies `ok` after an input that made it
    /// so comes from a frame drawn after every input sent before that one was handled.
    pub fn wait_for_title(&self, window: &str, what: &str, ok: impl Fn(&str) -> bool) -> String {
        wait_for(&format!("the title: {what}"), || {
            let title = self.title(window);
            ok(&title).then_some(title)
        })
    }

    /// Moves the pointer over `window` to each of `spots` (window pixels) in turn, again and again,
    /// looking at the title after each move, until the title satisfies `ok`; returns it. For what
    /// takes the cursor only once it has seen it move between two frames (the sprite's light): a
    /// single move may come before the frame that first sees the cursor.
    pub fn move_pointer_until(
        &self,
        window: &str,
        spots: &[(u32, u32)],
        what: &str,
        ok: impl Fn(&str) -> bool,
    ) -> String {
        let mut spots = spots.iter().cycle();
        wait_for(&format!("the title: {what}"), || {
            let (x, y) = spots.next().unwrap();
            let (x, y) = (x.to_string(), y.to_string());
            self.xdotool(&["mousemove", "--window", window, &x, &y]);
            let title = self.title(window);
            ok(&title).then_some(title)
        })
    }

    /// Presses P and waits for the numbered screenshot the window writes into `dir`.
    pub fn screenshot(&self, dir: &Path, n: u32) -> image::RgbImage {
        self.screenshot_with(dir, n, "p")
    }

    /// Presses `keys` (P, or Ctrl+P: the window as shown, the panel laid out with every input sent
    /// before) and waits for the numbered screenshot the window writes into `dir`.
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

/// How often a wait looks again.
const POLL: Duration = Duration::from_millis(100);

/// Polls `get` every [`POLL`] until it gives something, or fails after [`STEP_TIMEOUT`] saying
/// what was not seen: the one way the window tests wait (never a set time).
pub fn wait_for<T>(what: &str, mut get: impl FnMut() -> Option<T>) -> T {
    let start = Instant::now();
    loop {
        if let Some(value) = get() {
            return value;
        }
        if start.elapsed() >= STEP_TIMEOUT {
            panic!(
                "{what}: not seen within {STEP_TIMEOUT:?}{}",
                programs_report()
            );
        }
        std::thread::sleep(POLL);
    }
}

/// What became of each program started on the server: exited (how, from `/proc/PID/stat`'s exit
/// code, before it is reaped) or still running (each thread's name, state and kernel wait, and its
/// stacks by gdb where gdb is installed), with the end of its stderr.
fn programs_report() -> String {
    let programs = PROGRAMS.lock().unwrap_or_else(|e| e.into_inner()).clone();
    let mut report = String::new();
    for (pid, stderr) in programs {
        let state = match proc_stat(&format!("/proc/{pid}/stat")) {
            None => "gone".to_string(),
            Some(fields) if fields[0] == "Z" => {
                let code: i32 = fields.get(49).and_then(|c| c.parse().ok()).unwrap_or(-1);
                match (code & 0x7f, code >> 8) {
                    (0, status) => format!("exited with status {status}"),
                    (signal, _) => format!("killed by signal {signal}"),
                }
            }
            Some(fields) => format!("running (state {}){}", fields[0], threads_report(pid)),
        };
        let stderr = stderr.lock().unwrap_or_else(|e| e.into_inner()).clone();
        let lines: Vec<&str> = stderr.lines().collect();
        let tail = lines[lines.len().saturating_sub(30)..].join("\n");
        report += &format!("\nthe program (pid {pid}): {state}; the end of its stderr:\n{tail}");
    }
    report
}

/// The fields of a `/proc/.../stat` file after the command's name (which may hold spaces): the
/// state first.
fn proc_stat(path: &str) -> Option<Vec<String>> {
    let stat = std::fs::read_to_string(path).ok()?;
    let after_name = &stat[stat.rfind(')')? + 1..];
    Some(after_name.split_whitespace().map(str::to_string).collect())
}

/// A running program's threads: name, state and kernel wait channel each, then gdb's stacks.
fn threads_report(pid: u32) -> String {
    let mut report = String::from("; its threads:");
    let tasks = std::fs::read_dir(format!("/proc/{pid}/task"))
        .into_iter()
        .flatten();
    for task in tasks.flatten() {
        let dir = task.path();
        let read = |name: &str| std::fs::read_to_string(dir.join(name)).unwrap_or_default();
        let state = proc_stat(&dir.join("stat").to_string_lossy())
            .map_or("?".to_string(), |f| f[0].clone());
        report += &format!(
            "\n  {} {} {}",
            read("comm").trim(),
            state,
            read("wchan").trim()
        );
    }
    let gdb = Command::new("timeout")
        .args(["60", "gdb", "-p", &pid.to_string(), "-batch", "-q"])
        .args(["-ex", "thread apply all bt 16"])
        .stdin(Stdio::null())
        .output();
    if let Ok(out) = gdb {
        report += &format!("\ngdb's stacks:\n{}", String::from_utf8_lossy(&out.stdout));
    }
    report
}

/// [`wait_for`] a condition.
pub fn wait_until(what: &str, mut ok: impl FnMut() -> bool) {
    wait_for(what, || ok().then_some(()))
}

/// Waits for the program to exit (killing it after [`STEP_TIMEOUT`]): its status and stderr.
pub fn wait_exit(app: &mut Program) -> (ExitStatus, String) {
    let start = Instant::now();
    let status = loop {
        if let Some(status) = app.child.try_wait().unwrap() {
            break status;
        }
        if start.elapsed() > STEP_TIMEOUT {
            let _ = app.child.kill();
            let _ = app.child.wait();
            panic!(
                "the program did not exit within {STEP_TIMEOUT:?}; its stderr:\n{}",
                app.stderr()
            );
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    // Its pipes close as it exits: the readers end once they have read everything.
    for reader in app.readers.drain(..) {
        let _ = reader.join();
    }
    (status, app.stderr())
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
