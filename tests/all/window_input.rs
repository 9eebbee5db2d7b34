//! The window driven as a user drives it: real key presses and mouse motion through the X server's
//! XTEST extension (`xdotool`), under a private Xvfb. Needs the Debian packages xvfb and xdotool
//! (.ci/run installs them). Screenshots taken with the window's own P key are compared with the
//! headless frame, which equals the window's frame bit for bit at the tutorial's start.

use std::path::Path;
use std::time::{Duration, Instant};

use glam::Vec2;
use tutorial13::frontends::headless::{HeadlessOptions, HeadlessRenderer};
use tutorial13::frontends::panel::PanelWidget;
use tutorial13::scenes::sprite::{cursor_to_light, DEFAULT_LIGHT_Z};

use crate::common::xvfb::{wait_exit, Program, Xvfb};

use crate::common;

fn headless_first_frame(dir: &Path) -> image::RgbImage {
    common::headless_screenshot(dir, "headless.png", &[])
}

// Fails if mouse motion does not turn the grabbed camera, if R does not bring the camera back to the
// tutorial's start (the frame must equal the headless first frame bit for bit), if Tab does not
// release the cursor (motion must then leave the frame alone), if a click does not grab it again, or
// if the title loses the scene's status when the ms/frame figure arrives. Each screenshot is taken
// once L pressed twice after the step shows in the title: the step and its motion handled, and a
// frame drawn since that turned the camera by the motion (a screenshot's own frame drops motion no
// frame has used yet).
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
            xvfb.xdotool(&["mousemove_relative", "80", "30"]);
        }
        handled_and_drawn(&xvfb, &window);
        let shot = xvfb.screenshot(&dir, n);
        assert!((shot == start_frame) == unchanged, "{failure}");
    }

    // The once-a-second figure joins the status in the title instead of replacing it.
    let title = xvfb.wait_for_title(&window, "the ms/frame figure", |t| t.contains("ms/frame"));
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

// Fails if a window destroyed by another program (XDestroyWindow, not a close request) while the
// program runs (it has handled a key and drawn the frame after it) makes the program panic (winit
// 0.30 raises BadDrawable) instead of exiting with one error line.
#[test]
fn a_window_destroyed_from_outside_ends_with_one_line() {
    let dir = common::scratch("destroyed");
    let xvfb = Xvfb::start();
    let (mut app, window) = xvfb.open_window::<&str>(&dir, &[]);
    xvfb.xdotool(&["key", "l"]);
    xvfb.wait_for_title(&window, "lines on (L, the program past its start)", |t| {
        t.contains("lines on")
    });
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

/// In a cylinder window with the lines off: L, then L again, each waited for in the title ("lines
/// on", then "lines off"). Events are handled in order, so every input sent before is then handled,
/// and a frame has been drawn since (the title is set by a frame, and no screenshot was pending, so
/// not by a screenshot's): a frame that used the motion sent before. The lines are off again.
fn handled_and_drawn(xvfb: &Xvfb, window: &str) {
    xvfb.xdotool(&["key", "l"]);
    xvfb.wait_for_title(window, "lines on (L, sent after the step)", |t| {
        t.contains("lines on")
    });
    xvfb.xdotool(&["key", "l"]);
    xvfb.wait_for_title(window, "lines off (L again)", |t| t.contains("lines off"));
}

// Fails if saving a shader file in the --shaders folder does not change what the running window
// draws (once the window says "shaders reloaded"), if saving a broken one does not put the error in the title and the driver's log on stderr
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
    // A save while the watcher looks can be read half written (it fails, and the next look reloads
    // the whole file): the first "shaders reloaded" is the whole edit.
    app.wait_for_log("shaders reloaded", 1);
    let edited = shot();
    assert!(
        edited != start_frame,
        "the reloaded shader did not change the frame"
    );

    // A typo, saved: the title says so, the edited shader keeps drawing.
    std::fs::write(&fragment, halved.replace("color *= 0.5;", "color *= 0.5")).unwrap();
    let title = xvfb.wait_for_title(&window, "the broken shader's error", |t| {
        t.contains("shader compilation failed: NormalMapping.fragmentshader")
    });
    assert!(
        title.contains("view lit"),
        "the status left the title: {title:?}"
    );
    assert!(shot() == edited, "a broken shader changed the frame");

    // The original, saved back: the error leaves the title and the first frame is back.
    std::fs::write(&fragment, &good).unwrap();
    xvfb.wait_for_title(&window, "no error once fixed", |t| !t.contains("failed"));
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
    let mut shots = Shots::new(xvfb, dir);
    move || shots.frame()
}

/// The window's numbered screenshots, counted: P (the frame alone) or Ctrl+P (the window as shown).
struct Shots<'a> {
    xvfb: &'a Xvfb,
    dir: &'a Path,
    taken: u32,
}

impl<'a> Shots<'a> {
    fn new(xvfb: &'a Xvfb, dir: &'a Path) -> Self {
        Shots {
            xvfb,
            dir,
            taken: 0,
        }
    }

    /// P: the frame alone.
    fn frame(&mut self) -> image::RgbImage {
        self.take("p")
    }

    /// Ctrl+P: the window as shown, the panel laid out (one pass of egui) with every input sent
    /// before. The file is the acknowledgement that the panel has seen that input: where the
    /// pointer is (egui takes a press only where its last pass saw the pointer over the panel), a
    /// button held down (the slider takes its value while it is), a release (a click).
    fn as_shown(&mut self) -> image::RgbImage {
        self.take("ctrl+p")
    }

    fn take(&mut self, keys: &str) -> image::RgbImage {
        self.taken += 1;
        self.xvfb.screenshot_with(self.dir, self.taken, keys)
    }
}

// Fails if F5 does not reload the shaders: an edit the file watcher cannot see (the same length and
// modification time as the file it replaces) must stay off the screen until F5, also in a frame drawn
// after the watcher has looked at the edited file, and F5 must then draw bit for bit the headless
// frame of the edited shaders.
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
    // Written beside it with the old time, then renamed over it: the watcher never sees the file
    // half written or with a new time.
    let modified = std::fs::metadata(&fragment).unwrap().modified().unwrap();
    let beside = dir.join("edited.fragmentshader");
    std::fs::write(&beside, &edited).unwrap();
    let file = std::fs::File::options().write(true).open(&beside).unwrap();
    file.set_modified(modified).unwrap();
    drop(file);
    std::fs::rename(&beside, &fragment).unwrap();
    // The watcher looks in a frame once 250 ms have passed since its last look: a frame drawn 250 ms
    // after the edit, or later, has looked at the edited file (in that frame or before).
    app.wait_for_a_frame_at(Instant::now() + Duration::from_millis(250));
    assert!(
        shot() == start_frame,
        "the watcher saw an edit it should not see"
    );
    assert!(
        app.log_lines("shaders reloaded").is_empty(),
        "shaders reloaded before F5:\n{}",
        app.stderr()
    );
    xvfb.xdotool(&["key", "F5"]);
    app.wait_for_log("shaders reloaded", 1);
    let reloaded = shot();
    assert!(
        reloaded == edited_frame,
        "{} pixels differ from the edited shaders' headless frame after F5",
        common::differing_pixels(&reloaded, &edited_frame)
    );
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
    layout.host.show_panel().unwrap();
    layout.render_frames(1).unwrap();
    let panel = layout.host.panel().unwrap();
    let at = |w: PanelWidget| panel.widget_rect(&w).unwrap();
    let light_x = layout.host.scene.control_index("light x").unwrap();
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
// turns the camera (every frame compared is at the tutorial's start). Each step of a click waits for
// a pass of the panel that has seen it (a Ctrl+P screenshot), as a hand's press and release come
// frames apart.
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
    let mut shots = Shots::new(&xvfb, &dir);

    let shown = shots.as_shown();
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
    app.wait_for_log("panel hidden", 1);
    assert!(
        shots.as_shown() == start,
        "with the panel hidden the window is not the headless frame"
    );
    xvfb.xdotool(&["key", "F1"]);
    app.wait_for_log("panel shown", 1);

    click(&xvfb, &window, &mut shots, layout.lines_checkbox);
    xvfb.wait_for_title(&window, "lines on (the L checkbox clicked)", |t| {
        t.contains("lines on")
    });
    assert!(
        shots.frame() == with_lines,
        "the checkbox did not draw L's frame"
    );

    click(&xvfb, &window, &mut shots, layout.light_x_rail);
    assert!(
        shots.frame() != with_lines,
        "the light slider changed nothing"
    );
    click(&xvfb, &window, &mut shots, layout.start_values);
    assert!(
        shots.frame() == with_lines,
        "the tutorial's values did not bring the frame back"
    );

    xvfb.quit(&mut app);
}

/// Clicks the panel at `at` (window pixels) as a hand does: the pointer there, the button down,
/// then up, each seen by a pass of the panel before the next ([`Shots::as_shown`]).
fn click(xvfb: &Xvfb, window: &str, shots: &mut Shots, at: egui::Pos2) {
    let (x, y) = (at.x.round().to_string(), at.y.round().to_string());
    xvfb.xdotool(&["mousemove", "--window", window, &x, &y]);
    shots.as_shown();
    // egui's slider takes its value while the button is down, which a press and release within
    // one pass never is.
    xvfb.xdotool(&["mousedown", "1"]);
    shots.as_shown();
    xvfb.xdotool(&["mouseup", "1"]);
    shots.as_shown();
}

/// The sprite's light as the title shows it while it follows the cursor at `pointer` (window
/// pixels) in a 1024×768 window at the start height.
fn light_on_the_mouse(pointer: Vec2) -> String {
    let light = cursor_to_light(pointer, (1024, 768)).extend(DEFAULT_LIGHT_Z);
    format!(
        "light ({:.3}, {:.3}, {:.3}) on the mouse",
        light.x, light.y, light.z
    )
}

// Fails if the sprite's light follows the cursor onto the panel (moving to the panel to click a
// switch would drag the light under it): there the light must stay where the cursor left it, in
// the frame drawn after Y (sent after the move) shows in the title.
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
    // The light takes the cursor once it has seen it move between two frames (a cursor that moves
    // before the first frames is not yet the light's).
    xvfb.move_pointer_until(
        &window,
        &[(560, 280), (600, 300)],
        "the light on the mouse",
        |t| t.contains("on the mouse"),
    );
    xvfb.xdotool(&["mousemove", "--window", &window, "600", "300"]);
    let at_pointer = light_on_the_mouse(Vec2::new(600.0, 300.0));
    let on_frame = xvfb.wait_for_title(&window, &at_pointer, |t| t.contains(&at_pointer));
    xvfb.xdotool(&["mousemove", "--window", &window, "100", "400"]);
    // Y flips the green channel: once its frame shows, the move before it has been handled.
    xvfb.xdotool(&["key", "y"]);
    let on_panel = xvfb.wait_for_title(&window, "green flipped on (Y, sent after the move)", |t| {
        t.contains("green flipped on")
    });
    let left_at = light(&on_frame).expect("the light's place in the title");
    assert_eq!(
        light(&on_panel),
        Some(left_at),
        "the light moved with the cursor onto the panel: {on_panel}"
    );
    xvfb.quit(&mut app);
}

// Fails if the window's frame does not follow a resize (a size kept from before would leave the
// viewport and the projection at 1024×768 on an 800×600 window): once the window has logged the
// resize, its frame must be the headless frame of that size, bit for bit.
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
    app.wait_for_log("resized to 800x600", 1);
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
    let mut shots = Shots::new(&xvfb, &dir);
    // A click on the frame, right of the panel: the cursor is grabbed on the press.
    xvfb.xdotool(&["mousemove", "--window", &window, "800", "400"]);
    xvfb.xdotool(&["mousedown", "1"]);
    app.wait_for_log("cursor grabbed", 1);
    xvfb.xdotool(&["mouseup", "1"]);
    xvfb.xdotool(&["key", "Tab"]);
    app.wait_for_log("cursor released", 1);
    let (x, y) = (layout.lines_checkbox.x, layout.lines_checkbox.y);
    let (x, y) = (x.round().to_string(), y.round().to_string());
    xvfb.xdotool(&["mousemove", "--window", &window, &x, &y]);
    shots.as_shown();
    xvfb.xdotool(&["mousedown", "1"]);
    shots.as_shown();
    xvfb.xdotool(&["mouseup", "1"]);
    xvfb.wait_for_title(
        &window,
        "lines on (the checkbox clicked after a grab)",
        |t| t.contains("lines on"),
    );
    xvfb.quit(&mut app);
}

/// Holds `key` down until the window has been told of two of the X server's auto-repeats of it
/// (`code`: its winit key code, as the window's log names it), then lets it go.
fn hold(xvfb: &Xvfb, app: &mut Program, key: &str, code: &str) {
    let repeated = format!("{code} repeated");
    let before = app.log_lines(&repeated).len();
    xvfb.xdotool(&["keydown", key]);
    app.wait_for_log(&repeated, before + 2);
    xvfb.xdotool(&["keyup", key]);
}

// Fails if a key held down runs its action again on the X server's auto-repeat: P held until the
// window has had two repeats must save one screenshot (the next P the second, with no third), and L
// held as long must turn the lines on once (its log's status lines: one, "lines on"; an odd number
// of repeats would leave them off, an even number flicker them).
#[test]
fn a_held_key_acts_once() {
    let dir = common::scratch("held-key");
    let xvfb = Xvfb::start();
    let (mut app, window) = xvfb.open_window::<&str>(&dir, &[]);
    hold(&xvfb, &mut app, "p", "KeyP");
    common::xvfb::wait_until("the held P's screenshot", || {
        dir.join("tutorial13-1.png").exists()
    });
    hold(&xvfb, &mut app, "l", "KeyL");
    let title = xvfb.wait_for_title(&window, "lines on (L held)", |t| t.contains("lines on"));
    // P, handled after every repeat of L: then every action they ran has been logged.
    xvfb.screenshot(&dir, 2);
    let lines_status = app.log_lines("TBN debug lines ");
    assert!(
        lines_status.len() == 2 && lines_status[1].contains("TBN debug lines on"),
        "the status the log gave at start and for L held (one press): {lines_status:#?}; the title \
         {title:?}"
    );
    xvfb.quit(&mut app);
}

// Fails if Enter does not do the same in the window as headless: both move the camera first (an
// arrow key held in the window over frames drawn while it is, the camera's position moved
// headless), then press Enter twice; each must then draw the cube's first frame, bit for bit, with
// the camera back at the cube's start.
#[test]
fn enter_does_the_same_in_the_window_and_headless() {
    if !common::reference_renderer_here("enter_does_the_same_in_the_window_and_headless") {
        return;
    }
    let dir = common::scratch("enter");
    let mut headless = HeadlessRenderer::new(&HeadlessOptions::default()).unwrap();
    headless.host.controls.position.z += 2.0;
    headless.host.next_scene().unwrap();
    headless.host.next_scene().unwrap();
    assert_eq!(headless.host.descriptor().name, "cube");
    let headless_cube = image::DynamicImage::from(headless.render_frames(1).unwrap()).into_rgb8();
    let cube_start = common::headless_screenshot(&dir, "cube.png", &["--scene", "cube"]);
    assert!(
        headless_cube == cube_start,
        "headless Enter kept the camera it had"
    );

    let xvfb = Xvfb::start();
    let (mut app, window) = xvfb.open_window::<&str>(&dir, &[]);
    xvfb.xdotool(&["keydown", "Up"]);
    // Frames drawn while it is held move the camera.
    handled_and_drawn(&xvfb, &window);
    xvfb.xdotool(&["keyup", "Up"]);
    assert!(
        xvfb.screenshot(&dir, 1) != headless_first_frame(&dir),
        "the arrow key did not move the camera"
    );
    xvfb.xdotool(&["key", "Return"]);
    xvfb.wait_for_title(&window, "the sprite", |t| t.starts_with("sprite:"));
    xvfb.xdotool(&["key", "Return"]);
    xvfb.wait_for_title(&window, "the cube", |t| t.starts_with("cube:"));
    let shot = xvfb.screenshot(&dir, 2);
    assert!(
        shot == headless_cube,
        "{} pixels differ from headless Enter's cube",
        common::differing_pixels(&shot, &headless_cube)
    );
    xvfb.quit(&mut app);
}
