//! The window driven as a user drives it: real key presses and mouse motion through the X server's
//! XTEST extension (`xdotool`), under a private Xvfb. Needs the Debian packages xvfb and xdotool
//! (.ci/run installs them). Screenshots taken with the window's own P key are compared with the
//! headless frame, which equals the window's frame bit for bit at the tutorial's start.

use std::path::Path;
use std::time::Duration;

use tutorial13::frontends::headless::{HeadlessOptions, HeadlessRenderer};
use tutorial13::frontends::panel::PanelWidget;

use crate::common::xvfb::{wait_exit, wait_for, Xvfb};

use crate::common;

fn headless_first_frame(dir: &Path) -> image::RgbImage {
    common::headless_screenshot(dir, "headless.png", &[])
}

// Fails if mouse motion does not turn the grabbed camera, if R does not bring the camera back to the
// tutorial's start (the frame must equal the headless first frame bit for bit), if Tab does not
// release the cursor (motion must then leave the frame alone), if a click does not grab it again, or
// if the title loses the scene's status when the ms/frame figure arrives.
#[test]
fn mouse_look_reset_release_and_grab() {
    if !common::reference_renderer_here("mouse_look_reset_release_and_grab") {
        return;
    }
    let dir = common::scratch("keys");
    let start_frame = headless_first_frame(&dir);
    let xvfb = Xvfb::start();
    let (mut app, window) = xvfb.open_window::<&str>(&dir, &[]);
    // Each step: what to do, whether to move the mouse after it, and whether the frame must then be
    // the start frame (the camera reset or left alone) or not (the camera turned).
    let steps: [(&[&str], bool, bool, &str); 4] = [
        // A click grabs the cursor (Xvfb has no window manager, so focus may have come and gone).
        (
            &["mousemove", "640", "512", "click", "1"],
            true,
            false,
            "mouse motion did not turn the camera",
        ),
        (
            &["key", "r"],
            false,
            true,
            "R did not restore the tutorial's start frame",
        ),
        (
            &["key", "Tab"],
            true,
            true,
            "the released cursor still turned the camera",
        ),
        (
            &["click", "1"],
            true,
            false,
            "a click did not grab the cursor again",
        ),
    ];
    for ((action, then_move, unchanged, failure), n) in steps.into_iter().zip(1..) {
        xvfb.xdotool(action);
        if then_move {
            std::thread::sleep(Duration::from_millis(300));
            xvfb.xdotool(&["mousemove_relative", "80", "30"]);
            std::thread::sleep(Duration::from_millis(300));
        }
        let shot = xvfb.screenshot(&dir, n);
        assert!((shot == start_frame) == unchanged, "{failure}");
    }

    // The once-a-second figure joins the status in the title instead of replacing it.
    let title = wait_for_title(&xvfb, &window, "ms/frame", |t| t.contains("ms/frame"));
    for part in [
        "cylinder: ",
        "view lit",
        "lines off",
        "tangents tutorial",
        " | Tutorial 13",
    ] {
        assert!(
            title.contains(part),
            "{part:?} missing from the title {title:?}"
        );
    }

    xvfb.quit(&mut app);
}

// Fails if a window destroyed by another program (XDestroyWindow, not a close request) makes the
// program panic (winit 0.30 raises BadDrawable) instead of exiting with one error line.
#[test]
fn a_window_destroyed_from_outside_ends_with_one_line() {
    let dir = common::scratch("destroyed");
    let xvfb = Xvfb::start();
    let mut app = xvfb.start_program::<&str>(&dir, &[]);
    let window = xvfb.wait_for_window(&mut app);
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
    wait_for(what, || {
        let title = xvfb.xdotool(&["getwindowname", window]);
        ok(&title).then_some(title)
    })
}

// Fails if saving a shader file in the --shaders folder does not change what the running window
// draws, if saving a broken one does not put the error in the title and the driver's log on stderr
// while the last good shaders keep drawing, or if saving a good version does not clear the error.
#[test]
fn saving_a_shader_reloads_it_in_the_window() {
    if !common::reference_renderer_here("saving_a_shader_reloads_it_in_the_window") {
        return;
    }
    let dir = common::scratch("live-shaders");
    let shaders = dir.join("shaders");
    copy_shaders(&shaders);
    let fragment = shaders.join("NormalMapping.fragmentshader");
    let good = std::fs::read_to_string(&fragment).unwrap();
    let start_frame = headless_first_frame(&dir);
    let xvfb = Xvfb::start();
    let args = ["--shaders".as_ref(), shaders.as_os_str()];
    let (mut app, window) = xvfb.open_window(&dir, &args);
    let mut shot = numbered_shots(&xvfb, &dir);
    assert!(
        shot() == start_frame,
        "the first frame is not the tutorial's"
    );

    // A learner's edit, saved: the frames change without a key press.
    let end = good.rfind('}').unwrap();
    let halved = format!("{}    color *= 0.5;\n}}\n", &good[..end]);
    std::fs::write(&fragment, &halved).unwrap();
    let edited = wait_for("the saved shader reloaded", || {
        std::thread::sleep(Duration::from_millis(300));
        Some(shot()).filter(|frame| *frame != start_frame)
    });

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

    let stderr = xvfb.quit(&mut app);
    assert!(
        stderr.contains("NormalMapping.fragmentshader: compilation failed: ")
            && stderr.contains("error"),
        "no driver log on stderr: {stderr}"
    );
}

/// The crate's shader files, copied into `to` for a test to edit.
fn copy_shaders(to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(common::manifest().join("shaders")).unwrap() {
        let path = entry.unwrap().path();
        std::fs::copy(&path, to.join(path.file_name().unwrap())).unwrap();
    }
}

/// Takes the window's screenshots 1, 2, 3, … in turn (P), each as the frame it saved.
fn numbered_shots<'a>(xvfb: &'a Xvfb, dir: &'a Path) -> impl FnMut() -> image::RgbImage + 'a {
    let mut shots = 0;
    move || {
        shots += 1;
        xvfb.screenshot(dir, shots)
    }
}

// Fails if F5 does not reload the shaders: an edit the file watcher cannot see (the same length and
// modification time as the file it replaces) must stay off the screen until F5, and F5 must then draw
// bit for bit the headless frame of the edited shaders.
#[test]
fn f5_reloads_an_edit_the_watcher_cannot_see() {
    if !common::reference_renderer_here("f5_reloads_an_edit_the_watcher_cannot_see") {
        return;
    }
    let dir = common::scratch("f5-reload");
    let (shaders, edited_shaders) = (dir.join("shaders"), dir.join("edited"));
    copy_shaders(&shaders);
    copy_shaders(&edited_shaders);
    let fragment = shaders.join("NormalMapping.fragmentshader");
    let good = std::fs::read_to_string(&fragment).unwrap();
    // The colour halved at the end of main(), and as many letters taken out of the first comment.
    let added = "    color *= 0.5;\n";
    let comment = good.find("// ").unwrap() + 3;
    let end = good.rfind('}').unwrap();
    let edited = format!(
        "{}{}{added}}}\n",
        &good[..comment],
        &good[comment + added.len()..end]
    );
    assert_eq!(edited.len(), good.len());
    std::fs::write(edited_shaders.join("NormalMapping.fragmentshader"), &edited).unwrap();
    let start_frame = headless_first_frame(&dir);
    let edited_arg = edited_shaders.to_str().unwrap();
    let edited_frame = common::headless_screenshot(&dir, "edited.png", &["--shaders", edited_arg]);
    assert!(edited_frame != start_frame, "the edit draws nothing new");

    let xvfb = Xvfb::start();
    let (mut app, _window) = xvfb.open_window(&dir, &["--shaders".as_ref(), shaders.as_os_str()]);
    let mut shot = numbered_shots(&xvfb, &dir);
    assert!(
        shot() == start_frame,
        "the first frame is not the tutorial's"
    );
    let modified = std::fs::metadata(&fragment).unwrap().modified().unwrap();
    std::fs::write(&fragment, &edited).unwrap();
    let file = std::fs::File::options()
        .write(true)
        .open(&fragment)
        .unwrap();
    file.set_modified(modified).unwrap();
    drop(file);
    // The watcher looks every 250 ms: after three of its looks, the frame is still the first one.
    std::thread::sleep(Duration::from_millis(800));
    assert!(
        shot() == start_frame,
        "the watcher saw an edit it should not see"
    );
    xvfb.xdotool(&["key", "F5"]);
    wait_for("F5's reload", || {
        Some(shot()).filter(|f| *f == edited_frame)
    });
    xvfb.quit(&mut app);
}

/// Where the panel draws what the test clicks, in window pixels: the headless panel of the same
/// size is laid out the same (one pixel per point, the same fonts and rows).
struct PanelLayout {
    rect: egui::Rect,
    lines_checkbox: egui::Pos2,
    light_x_rail: egui::Pos2,
    start_values: egui::Pos2,
}

fn panel_layout() -> PanelLayout {
    let mut layout = HeadlessRenderer::new(&HeadlessOptions::default()).unwrap();
    layout.show_panel().unwrap();
    layout.render_frames(1).unwrap();
    let panel = layout.panel.as_ref().unwrap();
    let at = |w: PanelWidget| panel.widget_rect(&w).unwrap();
    let light_x = layout.scene.control_index("light x").unwrap();
    PanelLayout {
        rect: panel.rect().unwrap(),
        lines_checkbox: at(PanelWidget::Key('L')).center(),
        // Near the left end of the slider's rail.
        light_x_rail: at(PanelWidget::Slider(light_x)).left_center() + egui::vec2(12.0, 0.0),
        start_values: at(PanelWidget::StartValues).center(),
    }
}

// Fails if the panel is not on screen at start (Ctrl+P, the window as shown, must differ from the
// headless frame inside the panel's rectangle and equal it outside), if F1 does not hide it (the
// window must then be the headless frame bit for bit), if clicking the L checkbox does not do what
// L does (title and frame as with --debug-lines), if moving the light slider leaves the frame alone,
// if "tutorial's values" does not bring the frame back bit for bit, or if any click on the panel
// turns the camera (every frame compared is at the tutorial's start).
#[test]
fn the_panel_in_the_window() {
    if !common::reference_renderer_here("the_panel_in_the_window") {
        return;
    }
    let dir = common::scratch("panel-window");
    let start = headless_first_frame(&dir);
    let with_lines = common::headless_screenshot(&dir, "lines.png", &["--debug-lines"]);
    let layout = panel_layout();
    let xvfb = Xvfb::start();
    let (mut app, window) = xvfb.open_window::<&str>(&dir, &[]);
    let settle = || std::thread::sleep(Duration::from_millis(400));
    let click = |at: egui::Pos2| {
        let (x, y) = (at.x.round().to_string(), at.y.round().to_string());
        xvfb.xdotool(&["mousemove", "--window", &window, &x, &y]);
        settle();
        // Down and up a few frames apart, as a hand clicks: egui's slider takes its value while
        // the button is down, which a press and release within one frame never is.
        xvfb.xdotool(&["mousedown", "1"]);
        settle();
        xvfb.xdotool(&["mouseup", "1"]);
        settle();
    };
    settle();

    let shown = xvfb.screenshot_with(&dir, 1, "ctrl+p");
    let (mut inside, mut outside) = (0, 0);
    for (x, y, p) in shown.enumerate_pixels() {
        if start.get_pixel(x, y) != p {
            let pos = egui::pos2(x as f32 + 0.5, y as f32 + 0.5);
            *(if layout.rect.contains(pos) {
                &mut inside
            } else {
                &mut outside
            }) += 1;
        }
    }
    assert!(
        inside > 10_000,
        "the panel is not shown at start ({inside} pixels)"
    );
    assert_eq!(
        outside, 0,
        "pixels outside the panel differ from the headless frame"
    );

    xvfb.xdotool(&["key", "F1"]);
    settle();
    assert!(
        xvfb.screenshot_with(&dir, 2, "ctrl+p") == start,
        "with the panel hidden the window is not the headless frame"
    );
    xvfb.xdotool(&["key", "F1"]);
    settle();

    click(layout.lines_checkbox);
    wait_for_title(&xvfb, &window, "lines on", |t| t.contains("lines on"));
    assert!(
        xvfb.screenshot(&dir, 3) == with_lines,
        "the checkbox did not draw L's frame"
    );

    click(layout.light_x_rail);
    assert!(
        xvfb.screenshot(&dir, 4) != with_lines,
        "the light slider changed nothing"
    );
    click(layout.start_values);
    assert!(
        xvfb.screenshot(&dir, 5) == with_lines,
        "the tutorial's values did not bring the frame back"
    );

    xvfb.quit(&mut app);
}

// Fails if the sprite's light follows the cursor onto the panel (moving to the panel to click a
// switch would drag the light under it): there the light must stay where the cursor left it.
#[test]
fn over_the_panel_the_sprite_light_stays() {
    let dir = common::scratch("panel-sprite");
    let xvfb = Xvfb::start();
    let (mut app, window) = xvfb.open_window(&dir, &["--scene", "sprite"]);
    let light = |title: &str| {
        title
            .split("light (")
            .nth(1)
            .map(|t| t.split(')').next().unwrap_or("").to_string())
    };
    // After the first frames (a cursor that moves before them is not yet the light's).
    std::thread::sleep(Duration::from_millis(500));
    xvfb.xdotool(&["mousemove", "--window", &window, "600", "300"]);
    let on_frame = wait_for_title(&xvfb, &window, "the light on the mouse", |t| {
        t.contains("on the mouse")
    });
    xvfb.xdotool(&["mousemove", "--window", &window, "100", "400"]);
    std::thread::sleep(Duration::from_millis(500));
    let on_panel = xvfb.xdotool(&["getwindowname", &window]);
    let left_at = light(&on_frame).expect("the light's place in the title");
    assert_eq!(light(&on_panel), Some(left_at), "{on_panel}");
    xvfb.quit(&mut app);
}

// Fails if the window's frame does not follow a resize (a size kept from before would leave the
// viewport and the projection at 1024×768 on an 800×600 window): the frame must then be the
// headless frame of that size, bit for bit.
#[test]
fn a_resized_window_draws_the_frame_of_its_new_size() {
    if !common::reference_renderer_here("a_resized_window_draws_the_frame_of_its_new_size") {
        return;
    }
    let dir = common::scratch("resize");
    let small = common::headless_screenshot(&dir, "small.png", &["--size", "800x600"]);
    let xvfb = Xvfb::start();
    let (mut app, window) = xvfb.open_window::<&str>(&dir, &[]);
    xvfb.xdotool(&["windowsize", "--sync", &window, "800", "600"]);
    std::thread::sleep(Duration::from_millis(400));
    let shot = xvfb.screenshot(&dir, 1);
    assert_eq!(shot.dimensions(), (800, 600), "the frame kept its old size");
    assert!(
        shot == small,
        "{} pixels differ from the headless 800×600 frame",
        common::differing_pixels(&shot, &small)
    );
    xvfb.quit(&mut app);
}

// Fails if the click that grabs the cursor for mouse look leaves egui holding its button down (its
// release came while the cursor was grabbed and never reached egui): every later click on the panel
// would then be ignored, and L's checkbox would not turn the lines on.
#[test]
fn after_a_grab_the_panel_still_takes_clicks() {
    let dir = common::scratch("panel-after-grab");
    let layout = panel_layout();
    let xvfb = Xvfb::start();
    let (mut app, window) = xvfb.open_window::<&str>(&dir, &[]);
    let settle = || std::thread::sleep(Duration::from_millis(400));
    // A click on the frame, right of the panel: the cursor is grabbed on the press.
    xvfb.xdotool(&["mousemove", "--window", &window, "800", "400"]);
    settle();
    xvfb.xdotool(&["mousedown", "1"]);
    settle();
    xvfb.xdotool(&["mouseup", "1"]);
    settle();
    xvfb.xdotool(&["key", "Tab"]);
    settle();
    let (x, y) = (layout.lines_checkbox.x, layout.lines_checkbox.y);
    let (x, y) = (x.round().to_string(), y.round().to_string());
    xvfb.xdotool(&["mousemove", "--window", &window, &x, &y]);
    settle();
    xvfb.xdotool(&["mousedown", "1"]);
    settle();
    xvfb.xdotool(&["mouseup", "1"]);
    wait_for_title(&xvfb, &window, "lines on after a grab", |t| {
        t.contains("lines on")
    });
    xvfb.quit(&mut app);
}

// Fails if a key held down runs its action again on the X server's auto-repeat: P held for 1.5 s
// must save one screenshot (the next P the second, with no third), and L held as long must turn the
// lines on once (an odd number of repeats would leave them off, an even number flicker them).
#[test]
fn a_held_key_acts_once() {
    let dir = common::scratch("held-key");
    let xvfb = Xvfb::start();
    let (mut app, window) = xvfb.open_window::<&str>(&dir, &[]);
    let hold = |key: &str| {
        xvfb.xdotool(&["keydown", key]);
        std::thread::sleep(Duration::from_millis(1500));
        xvfb.xdotool(&["keyup", key]);
    };
    hold("p");
    wait_for("the held P's screenshot", || {
        dir.join("tutorial13-1.png").exists().then_some(())
    });
    hold("l");
    let title = wait_for_title(&xvfb, &window, "lines on", |t| t.contains("lines on"));
    std::thread::sleep(Duration::from_millis(500));
    let now = xvfb.xdotool(&["getwindowname", &window]);
    assert!(now.contains("lines on"), "{title:?} then {now:?}");
    xvfb.screenshot(&dir, 2);
    xvfb.quit(&mut app);
}

// Fails if Enter does not do the same in the window as headless: both move the camera first (an
// arrow key held in the window, the camera's position moved headless), then press Enter twice; each
// must then draw the cube's first frame, bit for bit, with the camera back at the cube's start.
#[test]
fn enter_does_the_same_in_the_window_and_headless() {
    if !common::reference_renderer_here("enter_does_the_same_in_the_window_and_headless") {
        return;
    }
    let dir = common::scratch("enter");
    let mut headless = HeadlessRenderer::new(&HeadlessOptions::default()).unwrap();
    headless.controls.position.z += 2.0;
    headless.next_scene().unwrap();
    headless.next_scene().unwrap();
    assert_eq!(headless.descriptor().name, "cube");
    let headless_cube = image::DynamicImage::from(headless.render_frames(1).unwrap()).into_rgb8();
    let cube_start = common::headless_screenshot(&dir, "cube.png", &["--scene", "cube"]);
    assert!(
        headless_cube == cube_start,
        "headless Enter kept the camera it had"
    );

    let xvfb = Xvfb::start();
    let (mut app, window) = xvfb.open_window::<&str>(&dir, &[]);
    xvfb.xdotool(&["keydown", "Up"]);
    std::thread::sleep(Duration::from_millis(400));
    xvfb.xdotool(&["keyup", "Up"]);
    assert!(
        xvfb.screenshot(&dir, 1) != headless_first_frame(&dir),
        "the arrow key did not move the camera"
    );
    xvfb.xdotool(&["key", "Return"]);
    wait_for_title(&xvfb, &window, "the sprite", |t| t.starts_with("sprite:"));
    xvfb.xdotool(&["key", "Return"]);
    wait_for_title(&xvfb, &window, "the cube", |t| t.starts_with("cube:"));
    let shot = xvfb.screenshot(&dir, 2);
    assert!(
        shot == headless_cube,
        "{} pixels differ from headless Enter's cube",
        common::differing_pixels(&shot, &headless_cube)
    );
    xvfb.quit(&mut app);
}
