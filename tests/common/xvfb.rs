//! A private X server for the window tests, driven with xdotool as a user would drive the window.
//! Needs the Debian packages xvfb and xdotool (.ci/run installs them).

use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Stdio};
use std::sync::{mpsc, Mutex, MutexGuard};
use std::time::{Duration, Instant};

/// How long the server may take to accept a client on two busy cores.
const READY_TIMEOUT: Duration = Duration::from_secs(60);

/// One server at a time per test binary: two started at once can both pick the same free display.
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
