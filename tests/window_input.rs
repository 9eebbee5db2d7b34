//! The window driven as a user drives it: real key presses and mouse motion through the X server's
//! XTEST extension (`xdotool`), under a private Xvfb. Needs the Debian packages xvfb and xdotool
//! (.ci/run installs them). Screenshots taken with the window's own P key are compared with the
//! headless frame, which equals the window's frame bit for bit at the tutorial's start.

use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use common::xvfb::Xvfb;

mod common;

/// How long a step may take on two busy cores before the test gives up.
const STEP_TIMEOUT: Duration = Duration::from_secs(60);

/// The id of the tutorial's window, once it is mapped.
fn wait_for_window(xvfb: &Xvfb, app: &mut Child) -> String {
    let start = Instant::now();
    loop {
        let found = xvfb.xdotool(&["search", "--name", "Tutorial 13"]);
        if let Some(id) = found.lines().next() {
            return id.to_string();
        }
        if app.try_wait().unwrap().is_some() {
            let (status, stderr) = wait_exit(app);
            panic!("the program exited ({status}) before its window appeared:\n{stderr}");
        }
        assert!(
            start.elapsed() < STEP_TIMEOUT,
            "no window after {STEP_TIMEOUT:?}"
        );
        std::thread::sleep(Duration::from_millis(100));
    }
}

/// The program in a window on `xvfb`, started in `dir` (where P writes tutorial13-N.png).
fn start_window(xvfb: &Xvfb, dir: &Path) -> Child {
    start_window_with(xvfb, dir, &[])
}

/// [`start_window`] with more arguments.
fn start_window_with(xvfb: &Xvfb, dir: &Path, args: &[&std::ffi::OsStr]) -> Child {
    Command::new(env!("CARGO_BIN_EXE_tutorial13"))
        .args(args)
        .current_dir(dir)
        .env("DISPLAY", &xvfb.display)
        .env_remove("WAYLAND_DISPLAY")
        .env_remove("RUST_LOG")
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap()
}

fn wait_exit(app: &mut Child) -> (std::process::ExitStatus, String) {
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
    use std::io::Read;
    app.stderr
        .take()
        .unwrap()
        .read_to_string(&mut stderr)
        .unwrap();
    (status, stderr)
}

/// Presses P and waits for the numbered screenshot it writes.
fn screenshot(xvfb: &Xvfb, dir: &Path, n: u32) -> image::RgbImage {
    xvfb.xdotool(&["key", "p"]);
    let path = dir.join(format!("tutorial13-{n}.png"));
    let start = Instant::now();
    loop {
        // The file appears by rename, so it is whole once it exists.
        if let Ok(image) = image::open(&path) {
            return image.into_rgb8();
        }
        assert!(
            start.elapsed() < STEP_TIMEOUT,
            "{} not written",
            path.display()
        );
        std::thread::sleep(Duration::from_millis(100));
    }
}

fn headless_first_frame(dir: &Path) -> image::RgbImage {
    common::headless_screenshot(dir, "headless.png", &[])
}

// Fails if mouse motion does not turn the grabbed camera, if R does not bring the camera back to the
// tutorial's start (the frame must equal the headless first frame bit for bit), if Tab does not
// release the cursor (motion must then leave the frame alone), if a click does not grab it again, or
// if the title loses the scene's status when the ms/frame figure arrives.
#[test]
fn mouse_look_reset_release_and_grab() {
    let dir = common::scratch("keys");
    let start_frame = headless_first_frame(&dir);
    let xvfb = Xvfb::start();
    let mut app = start_window(&xvfb, &dir);
    let window = wait_for_window(&xvfb, &mut app);
    xvfb.xdotool(&["windowfocus", "--sync", &window]);
    // A click grabs the cursor (Xvfb has no window manager, so focus may have come and gone).
    xvfb.xdotool(&["mousemove", "640", "512", "click", "1"]);
    std::thread::sleep(Duration::from_millis(300));
    xvfb.xdotool(&["mousemove_relative", "80", "30"]);
    std::thread::sleep(Duration::from_millis(300));
    let turned = screenshot(&xvfb, &dir, 1);
    assert!(
        turned != start_frame,
        "mouse motion did not turn the camera"
    );

    xvfb.xdotool(&["key", "r"]);
    let reset = screenshot(&xvfb, &dir, 2);
    assert!(
        reset == start_frame,
        "R did not restore the tutorial's start frame"
    );

    xvfb.xdotool(&["key", "Tab"]);
    std::thread::sleep(Duration::from_millis(300));
    xvfb.xdotool(&["mousemove_relative", "80", "30"]);
    std::thread::sleep(Duration::from_millis(300));
    let released = screenshot(&xvfb, &dir, 3);
    assert!(
        released == start_frame,
        "the released cursor still turned the camera"
    );

    xvfb.xdotool(&["click", "1"]);
    std::thread::sleep(Duration::from_millis(300));
    xvfb.xdotool(&["mousemove_relative", "80", "30"]);
    std::thread::sleep(Duration::from_millis(300));
    let grabbed = screenshot(&xvfb, &dir, 4);
    assert!(
        grabbed != start_frame,
        "a click did not grab the cursor again"
    );

    // The once-a-second figure joins the status in the title instead of replacing it.
    let start = Instant::now();
    let title = loop {
        let title = xvfb.xdotool(&["getwindowname", &window]);
        if title.contains("ms/frame") {
            break title;
        }
        assert!(
            start.elapsed() < STEP_TIMEOUT,
            "no ms/frame in the title: {title}"
        );
        std::thread::sleep(Duration::from_millis(200));
    };
    for part in [
        "Tutorial 13 - Normal Mapping",
        "view lit",
        "lines off",
        "Gram-Schmidt on",
    ] {
        assert!(
            title.contains(part),
            "{part:?} missing from the title {title:?}"
        );
    }

    xvfb.xdotool(&["key", "Escape"]);
    let (status, stderr) = wait_exit(&mut app);
    assert!(status.success(), "{stderr}");
}

// Fails if a window destroyed by another program (XDestroyWindow, not a close request) makes the
// program panic (winit 0.30 raises BadDrawable) instead of exiting with one error line.
#[test]
fn a_window_destroyed_from_outside_ends_with_one_line() {
    let dir = common::scratch("destroyed");
    let xvfb = Xvfb::start();
    let mut app = start_window(&xvfb, &dir);
    let window = wait_for_window(&xvfb, &mut app);
    std::thread::sleep(Duration::from_millis(500));
    xvfb.xdotool(&["windowclose", &window]);
    let (status, stderr) = wait_exit(&mut app);
    assert_eq!(status.code(), Some(1), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    let errors: Vec<&str> = stderr
        .lines()
        .filter(|l| l.starts_with("tutorial13:"))
        .collect();
    assert_eq!(errors.len(), 1, "{stderr}");
    assert!(
        errors[0].contains("destroyed by another program"),
        "{stderr}"
    );
}

/// Waits until the window's title satisfies `ok`, and returns it.
fn wait_for_title(xvfb: &Xvfb, window: &str, what: &str, ok: impl Fn(&str) -> bool) -> String {
    let start = Instant::now();
    loop {
        let title = xvfb.xdotool(&["getwindowname", window]);
        if ok(&title) {
            return title;
        }
        assert!(
            start.elapsed() < STEP_TIMEOUT,
            "{what}: the title is still {title:?}"
        );
        std::thread::sleep(Duration::from_millis(200));
    }
}

// Fails if saving a shader file in the --shaders folder does not change what the running window
// draws, if saving a broken one does not put the error in the title and the driver's log on stderr
// while the last good shaders keep drawing, or if saving a good version does not clear the error.
#[test]
fn saving_a_shader_reloads_it_in_the_window() {
    let dir = common::scratch("live-shaders");
    let shaders = dir.join("shaders");
    std::fs::create_dir_all(&shaders).unwrap();
    for entry in std::fs::read_dir(common::manifest().join("shaders")).unwrap() {
        let path = entry.unwrap().path();
        std::fs::copy(&path, shaders.join(path.file_name().unwrap())).unwrap();
    }
    let fragment = shaders.join("NormalMapping.fragmentshader");
    let good = std::fs::read_to_string(&fragment).unwrap();
    let start_frame = headless_first_frame(&dir);
    let xvfb = Xvfb::start();
    let args = ["--shaders".as_ref(), shaders.as_os_str()];
    let mut app = start_window_with(&xvfb, &dir, &args);
    let window = wait_for_window(&xvfb, &mut app);
    xvfb.xdotool(&["windowfocus", "--sync", &window]);
    let mut shots = 0;
    let mut shot = || {
        shots += 1;
        screenshot(&xvfb, &dir, shots)
    };
    assert!(
        shot() == start_frame,
        "the first frame is not the tutorial's"
    );

    // A learner's edit, saved: the frames change without a key press.
    let end = good.rfind('}').unwrap();
    let halved = format!("{}    color *= 0.5;\n}}\n", &good[..end]);
    std::fs::write(&fragment, &halved).unwrap();
    let start = Instant::now();
    let edited = loop {
        std::thread::sleep(Duration::from_millis(300));
        let frame = shot();
        if frame != start_frame {
            break frame;
        }
        assert!(
            start.elapsed() < STEP_TIMEOUT,
            "the saved shader was not reloaded"
        );
    };

    // A typo, saved: the title says so, the edited shader keeps drawing.
    std::fs::write(&fragment, halved.replace("color *= 0.5;", "color *= 0.5")).unwrap();
    let title = wait_for_title(&xvfb, &window, "broken shader", |t| {
        t.contains("shader compilation failed: NormalMapping.fragmentshader")
    });
    assert!(
        title.contains("view lit"),
        "the status left the title: {title:?}"
    );
    assert!(shot() == edited, "a broken shader changed the frame");

    // The original, saved back: the error leaves the title and the first frame is back.
    std::fs::write(&fragment, &good).unwrap();
    wait_for_title(&xvfb, &window, "fixed shader", |t| !t.contains("failed"));
    assert!(
        shot() == start_frame,
        "the original shader does not give the first frame back"
    );

    xvfb.xdotool(&["key", "Escape"]);
    let (status, stderr) = wait_exit(&mut app);
    assert!(status.success(), "{stderr}");
    assert!(
        stderr.contains("NormalMapping.fragmentshader: compilation failed: ")
            && stderr.contains("error"),
        "no driver log on stderr: {stderr}"
    );
}
