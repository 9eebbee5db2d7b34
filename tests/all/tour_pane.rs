//! The tour in the host: PageDown and PageUp, given as any front end gives its keys, step through
//! the whole tour and back, each step's frame the frame `--tour N` draws and each state restored on
//! the way back, also in the real window under Xvfb; the tour's pane is drawn where it says it is
//! and nowhere else.

use image::RgbImage;
use tutorial13::frontends::events::{AfterFetch, Event, Request};
use tutorial13::frontends::headless::{HeadlessOptions, HeadlessRenderer};
use tutorial13::frontends::keys::Key;
use tutorial13::frontends::panel::{PanelWidget, FOLDED_WIDTH, PANEL_WIDTH};
use tutorial13::frontends::tour_pane::TourClick;
use tutorial13::scenes::{ControlState, SceneOptions};
use tutorial13::tour::exercise::Verdict;
use tutorial13::tour::{Step, STEPS};

use crate::cli::assert_one_line_failure;
use crate::common::xvfb::Xvfb;
use crate::common::{self, run, tutorial13};

fn project_assets() -> SceneOptions {
    SceneOptions {
        assets: Some(common::own_assets()),
        ..Default::default()
    }
}

/// A key pressed and released, as every front end gives it to the host (the renderer honours the
/// fetch the host asks for, as the window does).
fn press(renderer: &mut HeadlessRenderer, key: Key) {
    for pressed in [true, false] {
        renderer
            .event(Event::Key {
                key,
                pressed,
                repeat: false,
                ctrl: false,
            })
            .expect("the key is taken");
    }
}

/// What `--headless --tour N` does: the step's scene built with the command line's options, then
/// its state set (tools::run's path).
fn tour_n(step: &'static Step) -> HeadlessRenderer {
    let mut renderer = common::renderer(&HeadlessOptions {
        descriptor: step.state.descriptor().unwrap(),
        scene: project_assets(),
        ..Default::default()
    });
    renderer.host.set_step_state(step).unwrap();
    renderer
}

/// What a step's state is, as the host holds it: the scene, every control of its table, the camera.
fn state_of(renderer: &HeadlessRenderer) -> (String, Vec<ControlState>, String) {
    let host = &renderer.host;
    let c = &host.controls;
    let camera = format!(
        "{:?} {} {}",
        c.position, c.horizontal_angle, c.vertical_angle
    );
    (host.descriptor().name.into(), host.scene.controls(), camera)
}

// Fails if PageDown or PageUp do not reach the tour (a key missing from HOST_KEYS or from the
// host's dispatch: the step stays), if a step they reach is put in another state than `--tour N`
// puts it (a control set otherwise, the camera left where the last step had it, a scene not built
// again: its frame differs from the `--tour N` frame), or if stepping back leaves anything a later
// step set (the state read back on the way down differs from the way up). Past the last step
// PageDown stays, and so does PageUp at the first.
#[test]
fn page_keys_step_through_the_whole_tour_and_back() {
    let expected: Vec<RgbImage> = STEPS
        .iter()
        .map(|step| common::frame(&mut tour_n(step)))
        .collect();
    let mut renderer = common::renderer(&HeadlessOptions {
        scene: project_assets(),
        ..Default::default()
    });
    assert!(renderer.host.tour_step().is_none());
    let mut forward_states = Vec::new();
    let walk = |renderer: &mut HeadlessRenderer, key: Key, i: usize, way: &str| {
        press(renderer, key);
        let at = renderer.host.tour_step().map(Step::number);
        assert_eq!(at, Some(i + 1), "{key} on the way {way}");
        let frame = common::frame(renderer);
        let d = common::frame_diff(&expected[i], &frame);
        assert_eq!(
            d.differing(),
            0,
            "step {} ({}) on the way {way}: {} pixels differ from --tour {} (within {:?})",
            i + 1,
            STEPS[i].name,
            d.differing(),
            i + 1,
            d.bbox
        );
        state_of(renderer)
    };
    for i in 0..STEPS.len() {
        forward_states.push(walk(&mut renderer, Key::PageDown, i, "up"));
    }
    let last = STEPS.len() - 1;
    walk(&mut renderer, Key::PageDown, last, "up, past the last");
    for i in (0..last).rev() {
        let state = walk(&mut renderer, Key::PageUp, i, "down");
        assert_eq!(
            state,
            forward_states[i],
            "step {}: not restored on the way back",
            i + 1
        );
    }
    walk(&mut renderer, Key::PageUp, 0, "down, before the first");
}

/// What `--tour N` draws for `step` in a frame of `size` (the scene alone, as in a window of that
/// size).
fn tour_n_sized(step: &'static Step, size: (u32, u32)) -> HeadlessRenderer {
    let mut renderer = common::renderer(&HeadlessOptions {
        descriptor: step.state.descriptor().unwrap(),
        scene: project_assets(),
        width: size.0,
        height: size.1,
        ..Default::default()
    });
    renderer.host.set_step_state(step).unwrap();
    renderer
}

/// Clicks the panel's `widget` as a front end gives a click (the pointer moved there, the button
/// down and up), draws the frame the panel takes it in, then the next, which shows what it did:
/// the scene is drawn before the panel, so its box follows the panel a frame later.
fn click(renderer: &mut HeadlessRenderer, widget: PanelWidget) -> RgbImage {
    let rect = renderer.host.panel().unwrap().widget_rect(&widget);
    let rect = rect.unwrap_or_else(|| panic!("{widget:?} is on the panel"));
    let at = glam::Vec2::new(rect.center().x, rect.center().y);
    renderer.event(Event::PointerMoved(at)).unwrap();
    for pressed in [true, false] {
        renderer.event(Event::Button { pressed }).unwrap();
    }
    common::frame(renderer);
    common::frame(renderer)
}

/// The frame once egui's fades are over (a lit button, a scroll bar shown by the pointer): frozen
/// frames step its clock a 60th of a second each, and half a second is more than any fade takes.
fn settled(renderer: &mut HeadlessRenderer) -> RgbImage {
    (0..30).map(|_| common::frame(renderer)).last().unwrap()
}

/// Checks a frame with the tour's pane: outside the panel's and the pane's rectangles, the box
/// between them is `alone` (`--tour N`'s frame at the box's size, drawn before: the renderers do
/// not take turns on one thread) to the pixel, and the rest the ground's grey; the box fills the
/// room between the two at the frame's aspect.
fn check_between(renderer: &HeadlessRenderer, frame: &RgbImage, alone: &RgbImage) {
    let panel = renderer.host.panel().unwrap();
    let (panel_rect, pane) = (panel.rect().unwrap(), panel.tour_rect().unwrap());
    let b = renderer.host.scene_box().expect("a box beside the pane");
    assert_eq!(
        b.x as f32,
        panel_rect.right().ceil(),
        "the box starts at the panel"
    );
    assert_eq!(
        b.width,
        (pane.left() - panel_rect.right()) as u32,
        "the room's width"
    );
    assert_eq!(b.size(), alone.dimensions(), "the box's size");
    let mut ground = 0;
    for (x, y, p) in frame.enumerate_pixels() {
        let (fx, fy) = (x as f32 + 0.5, y as f32 + 0.5);
        if [panel_rect, pane]
            .iter()
            .any(|r| r.contains(egui::pos2(fx, fy)))
        {
            continue;
        }
        let inside = (b.x..b.x + b.width).contains(&x) && (b.y..b.y + b.height).contains(&y);
        if inside {
            let expected = alone.get_pixel(x - b.x, y - b.y);
            assert_eq!(p, expected, "pixel ({x}, {y}) in {b:?} is not the scene's");
        } else {
            assert_eq!(
                p.0,
                [27, 27, 27],
                "pixel ({x}, {y}) around {b:?} is not the ground"
            );
            ground += 1;
        }
    }
    let room = (pane.left() - panel_rect.right()) as usize * frame.height() as usize;
    assert_eq!(ground, room - (b.width * b.height) as usize);
}

// Fails if the scene beside the tour's pane is not `--tour N`'s frame drawn whole at the size of the
// box between the panel and the pane, to the pixel (a scene drawn under the pane as before, one
// squeezed to another aspect, a cursor or size the scene was not given), on the panel's grey; if the
// panel does not fold beside the pane in the tutorial's 1024-pixel frame (its scene would keep 254
// pixels, not 464), or its button does not unfold it and fold it again; if the pane draws outside
// the rectangle it reports or nothing in it, if the copy of it from the panel's cache is not egui's
// painting of it (columns left out), or if closing it (its button, clicked through the host's
// pointer events) does not give back the frame of the panel alone, the scene whole under it, to
// the pixel.
#[test]
fn the_tour_pane_draws_only_where_it_is() {
    let step = &STEPS[8];
    // The scene alone: whole, and in the boxes beside the folded and the whole panel.
    let scene_alone = common::frame(&mut tour_n(step));
    let in_folded = common::frame(&mut tour_n_sized(step, (464, 348)));
    let in_unfolded = common::frame(&mut tour_n_sized(step, (254, 190)));
    let mut renderer = tour_n(step);
    renderer.host.show_panel().unwrap();
    let with_pane = common::frame(&mut renderer);
    let panel = renderer.host.panel().unwrap();
    let pane = panel.tour_rect().expect("the pane shows at a tour's step");
    assert_eq!(
        panel.rect().unwrap().width(),
        FOLDED_WIDTH,
        "the panel folds beside the pane in a 1024-pixel frame"
    );
    check_between(&renderer, &with_pane, &in_folded);

    // The pane is copied from the panel's cache each frame: the copy must be egui's painting.
    renderer.host.panel_mut().unwrap().paint_every_frame = true;
    let painted = common::frame(&mut renderer);
    renderer.host.panel_mut().unwrap().paint_every_frame = false;
    let d = common::frame_diff(&painted, &with_pane);
    assert_eq!(
        d.differing(),
        0,
        "the cached pane differs within {:?}",
        d.bbox
    );

    // Unfolded, the whole panel and a smaller box; folded again, the first frame.
    let unfolded = click(&mut renderer, PanelWidget::Fold);
    assert_eq!(
        renderer.host.panel().unwrap().rect().unwrap().width(),
        PANEL_WIDTH
    );
    check_between(&renderer, &unfolded, &in_unfolded);
    click(&mut renderer, PanelWidget::Fold);
    // The pointer off the frame, so that no button is lit under it.
    renderer.event(Event::PointerLeft).unwrap();
    let folded = settled(&mut renderer);
    assert_eq!(
        common::differing_pixels(&with_pane, &folded),
        0,
        "folded again"
    );

    // The pane's own pixels: many drawn, none outside it.
    renderer.host.close_tour();
    let panel_alone = settled(&mut renderer);
    assert!(renderer.host.panel().unwrap().tour_rect().is_none());
    let panel_rect = renderer.host.panel().unwrap().rect().unwrap();
    assert_eq!(
        panel_rect.width(),
        PANEL_WIDTH,
        "whole again without the pane"
    );
    let mut drawn = 0;
    for (x, y, p) in with_pane.enumerate_pixels() {
        if pane.contains(egui::pos2(x as f32 + 0.5, y as f32 + 0.5)) {
            drawn += usize::from(p.0 != [27, 27, 27]);
        }
    }
    let pane_pixels = (pane.width() * pane.height()) as usize;
    assert!(
        drawn > pane_pixels / 20,
        "only {drawn} of the pane's {pane_pixels} pixels are drawn"
    );
    // Without the pane the scene is whole under the panel, as before the tour.
    for (x, y, p) in panel_alone.enumerate_pixels() {
        if !panel_rect.contains(egui::pos2(x as f32 + 0.5, y as f32 + 0.5)) {
            assert_eq!(
                p,
                scene_alone.get_pixel(x, y),
                "pixel ({x}, {y}) without the pane"
            );
        }
    }

    // The close button, clicked as a front end gives a click: the pane goes.
    let mut renderer = tour_n(step);
    renderer.host.show_panel().unwrap();
    common::frame(&mut renderer);
    click(&mut renderer, PanelWidget::Tour(TourClick::Close));
    assert!(renderer.host.tour_step().is_none(), "the close button");
    renderer.event(Event::PointerLeft).unwrap();
    let closed = settled(&mut renderer);
    let d = common::frame_diff(&panel_alone, &closed);
    assert_eq!(d.differing(), 0, "closed: differs within {:?}", d.bbox);
}

// Fails if a bad `--tour` value is anything but one line on stderr naming it and a non-zero exit,
// in the window's path as headless (the value is read before a window or context is made, so this
// runs without a display).
#[test]
fn bad_tour_values_are_one_line_in_the_window_too() {
    for value in ["0", "19", "Results", ""] {
        let out = run(tutorial13().args(["--tour", value]));
        let line = assert_one_line_failure(&out, &format!("--tour {value:?}"));
        assert!(line.contains(&format!("--tour {value}")), "{line}");
    }
}

// Fails if keys pressed while a step's files are still coming in (the page fetches them) do not
// step on from the step asked last (two PageDowns must reach step 2, not step 1 twice), or if a
// step whose files come in after a later key's is shown over it (the last key's step must stay).
#[test]
fn keys_while_files_come_in_step_on_from_the_last_asked() {
    let mut renderer = common::renderer(&HeadlessOptions {
        scene: project_assets(),
        ..Default::default()
    });
    let mut fetches = Vec::new();
    for _ in 0..2 {
        for pressed in [true, false] {
            let key = Key::PageDown;
            let event = Event::Key {
                key,
                pressed,
                repeat: false,
                ctrl: false,
            };
            // The host's own event: its requests wait, as a page's fetch keeps them waiting.
            renderer.host.event(event).unwrap();
        }
    }
    while let Some(request) = renderer.host.next_request() {
        if let Request::Fetch { then, .. } = request {
            fetches.push(then);
        }
    }
    assert_eq!(fetches, [AfterFetch::Tour(0), AfterFetch::Tour(1)]);
    // The second step's files come in first, then the first's.
    for then in fetches.into_iter().rev() {
        renderer.host.fetched(then).unwrap();
    }
    assert_eq!(renderer.host.tour_step().map(Step::number), Some(2));
    let frame = common::frame(&mut renderer);
    assert_eq!(
        common::differing_pixels(&common::frame(&mut tour_n(&STEPS[1])), &frame),
        0,
        "step 2's frame"
    );
}

/// The tour at exercise `n`'s step, as `--tour exercise-N` with `shaders` as `--shaders`, the
/// panel shown.
fn at_exercise(n: u8, shaders: Option<std::path::PathBuf>) -> HeadlessRenderer {
    let step = STEPS
        .iter()
        .find(|s| s.name == format!("exercise-{n}"))
        .unwrap();
    let mut renderer = common::renderer(&HeadlessOptions {
        descriptor: step.state.descriptor().unwrap(),
        scene: SceneOptions {
            shaders,
            ..project_assets()
        },
        ..Default::default()
    });
    renderer.host.set_step_state(step).unwrap();
    renderer.host.show_panel().unwrap();
    renderer
}

/// Pixels of `frame` inside `rect` (pixels) that are black, the colour of "no difference" in the
/// heat map (egui's dark theme has none).
fn black_pixels_in(frame: &RgbImage, rect: egui::Rect) -> usize {
    frame
        .enumerate_pixels()
        .filter(|&(x, y, p)| {
            rect.contains(egui::pos2(x as f32 + 0.5, y as f32 + 0.5)) && p.0 == [0, 0, 0]
        })
        .count()
}

// Fails if F2 is not the host's key at an exercise step (no answer), if an unedited program is
// congratulated or told otherwise than the command line tells it (the line must be the verdict's
// own, naming the file to edit), if the check disturbs the scene on show (any pixel outside the
// pane changes: the check draws its frames in targets of its own), if the answer is not shown in
// the pane (its pixels unchanged), or if it outlives its step (PageDown must clear it). F2 at a
// step without an exercise answers nothing.
#[test]
fn f2_at_exercise_1_tells_an_unedited_program_it_is_not_done() {
    let mut renderer = at_exercise(1, None);
    let before = common::frame(&mut renderer);
    press(&mut renderer, Key::F(2));
    let answer = renderer.host.exercise_answer().expect("F2 answers").clone();
    let exercise = tutorial13::tour::exercise::exercise(1).unwrap();
    assert_eq!(answer.verdict, Some(Verdict::Untouched), "{}", answer.line);
    assert_eq!(answer.line, Verdict::Untouched.line(exercise));
    assert!(answer.line.contains("src/common/vboindexer.rs"));
    assert!(answer.heat_map.is_none());

    let after = common::frame(&mut renderer);
    let pane = renderer.host.panel().unwrap().tour_rect().unwrap();
    let d = common::frame_diff(&before, &after);
    let (x0, _, x1, _) = d.bbox.expect("the answer shows in the pane");
    assert!(
        x0 as f32 >= pane.left().floor() && x1 as f32 <= pane.right(),
        "the pane is {pane:?}, but pixels x {x0}..={x1} changed"
    );

    press(&mut renderer, Key::PageDown);
    assert!(renderer.host.exercise_answer().is_none(), "the next step");
    let mut elsewhere = tour_n(&STEPS[8]);
    press(&mut elsewhere, Key::F(2));
    assert!(elsewhere.host.exercise_answer().is_none());
}

// Fails if F2 at exercise 2 does not check the learner's shaders (a --shaders copy, as the command
// line's check reads them): done as asked, the answer must be "matches" with no heat map; with the
// eye direction left unnormalized it must count the pixels that differ (more than none, fewer than
// the frame) and show the compare view's heat map in the pane (black where nothing differs: the
// pane had no black pixel before, and has at least the map's black ones after), no wider than the
// pane.
#[test]
fn f2_at_exercise_2_checks_the_learners_shaders() {
    let done_dir = common::scratch("f2-done");
    crate::tour::shaders_with_colour(&done_dir, Some("normalize(EyeDirection_tangentspace)"));
    let mut done = at_exercise(2, Some(done_dir));
    common::frame(&mut done);
    press(&mut done, Key::F(2));
    let answer = done.host.exercise_answer().unwrap();
    assert_eq!(answer.verdict, Some(Verdict::Matches), "{}", answer.line);
    assert!(answer.line.starts_with("exercise 2: matches"));
    assert!(answer.heat_map.is_none());

    let wrong_dir = common::scratch("f2-wrong");
    crate::tour::shaders_with_colour(&wrong_dir, Some("EyeDirection_tangentspace"));
    let mut wrong = at_exercise(2, Some(wrong_dir));
    let before = common::frame(&mut wrong);
    let pane = wrong.host.panel().unwrap().tour_rect().unwrap();
    assert_eq!(black_pixels_in(&before, pane), 0);
    press(&mut wrong, Key::F(2));
    let answer = wrong.host.exercise_answer().unwrap().clone();
    let Some(Verdict::Differs(d)) = answer.verdict else {
        panic!("a wrong edit: {}", answer.line);
    };
    assert!(d.pixels > 0 && d.pixels < 1024 * 768, "{}", answer.line);
    assert!(answer.line.contains(&format!("{} pixels differ", d.pixels)));
    let map = answer.heat_map.expect("a heat map of where they differ");
    assert!(map.width() <= tutorial13::tour::exercise::HEAT_MAP_WIDTH);
    let map_black = map.pixels().filter(|p| p.0 == [0, 0, 0, 255]).count();
    let lit = map.pixels().count() - map_black;
    assert!(lit > 0, "the map shows where they differ");
    let after = common::frame(&mut wrong);
    let shown = black_pixels_in(&after, pane);
    assert!(
        shown >= map_black,
        "the pane shows {shown} black pixels; the heat map has {map_black}"
    );
}

/// Warnings logged, with the thread that logged them (each test runs on a thread of its own).
static WARNINGS: std::sync::Mutex<Vec<(std::thread::ThreadId, String)>> =
    std::sync::Mutex::new(Vec::new());

struct WarningLog;

impl log::Log for WarningLog {
    fn enabled(&self, metadata: &log::Metadata) -> bool {
        metadata.level() <= log::Level::Warn
    }

    fn log(&self, record: &log::Record) {
        if self.enabled(record.metadata()) {
            let thread = std::thread::current().id();
            let mut warnings = WARNINGS.lock().unwrap_or_else(|e| e.into_inner());
            warnings.push((thread, record.args().to_string()));
        }
    }

    fn flush(&self) {}
}

/// The warnings this thread logged that contain `text`, once the log is captured (the first call
/// installs the capture for the whole test process: no other test sets a logger).
fn warnings_here(text: &str) -> usize {
    static INSTALL: std::sync::Once = std::sync::Once::new();
    INSTALL.call_once(|| {
        if log::set_logger(&WarningLog).is_ok() {
            log::set_max_level(log::LevelFilter::Warn);
        }
    });
    let thread = std::thread::current().id();
    let warnings = WARNINGS.lock().unwrap_or_else(|e| e.into_inner());
    warnings
        .iter()
        .filter(|(t, w)| *t == thread && w.contains(text))
        .count()
}

// Fails if the core profile's fallback from the tutorial's immediate mode to the line shader is
// warned of again at every step of the tour with the lines on (each builds the scene again): from
// step 9 (Orthogonalization, L on) to step 12 (Debugging with the immediate mode) and back, the
// warning is logged once, at the first.
#[test]
fn the_line_shader_fallback_is_warned_of_once() {
    const FALLBACK: &str = "falling back to the core-profile line shader";
    let before = warnings_here(FALLBACK);
    assert_eq!(before, 0, "this thread has built no lines yet");
    let mut renderer = tour_n(&STEPS[8]);
    common::frame(&mut renderer);
    for key in [Key::PageDown; 3].into_iter().chain([Key::PageUp; 3]) {
        press(&mut renderer, key);
        common::frame(&mut renderer);
    }
    assert_eq!(renderer.host.tour_step().map(Step::number), Some(9));
    assert_eq!(warnings_here(FALLBACK), 1);
}

/// The panel's ms/frame row (pixels) in `step`'s scene, as a `--tour N` host lays it out: the one
/// part of the window as shown that is not the headless frame's (its figure is the window's
/// clock's; a headless frame has none). Where it is depends on the scene (the rows above it, its
/// name and description, are each scene's own).
fn figure_row(step: &'static Step) -> egui::Rect {
    let mut layout = tour_n(step);
    layout.host.show_panel().unwrap();
    common::frame(&mut layout);
    let panel = layout.host.panel().unwrap();
    let figure = panel.widget_rect(&PanelWidget::Figure).unwrap();
    egui::Rect::from_x_y_ranges(panel.rect().unwrap().x_range(), figure.y_range())
}

/// How many of `shown`'s pixels differ from `expected`'s, `row` left out.
fn differing_but(row: egui::Rect, shown: &RgbImage, expected: &RgbImage) -> usize {
    assert_eq!(shown.dimensions(), expected.dimensions());
    shown
        .enumerate_pixels()
        .filter(|&(x, y, p)| {
            let at = egui::pos2(x as f32 + 0.5, y as f32 + 0.5);
            !row.contains(at) && p != expected.get_pixel(x, y)
        })
        .count()
}

// Fails if PageDown and PageUp pressed in the real window (X key events under Xvfb, as a hand
// presses them) do not step the window's tour one step at a time through all 18 steps and back
// (its log must say "the tour, step N: <section>" once more at each step reached), or if a step so
// reached, on the way up or down, is not in that step's whole state to the pixel (switches,
// sliders, camera and scene: the window as shown, Ctrl+P, must be `--headless --tour N --panel`'s
// frame bit for bit, scene, panel and the tour's pane, but for the panel's ms/frame row). The
// pointer stays outside the window, so that nothing in it is hovered (headless has no pointer) and
// the sprite's light stays where the step puts it.
#[test]
fn the_window_steps_through_the_whole_tour_and_back() {
    if !common::reference_renderer_here("the_window_steps_through_the_whole_tour_and_back") {
        return;
    }
    let dir = common::scratch("window-walk");
    let headless: Vec<RgbImage> = STEPS
        .iter()
        .map(|step| {
            let n = step.number().to_string();
            let args = ["--tour", &n, "--panel"];
            common::headless_screenshot(&dir, &format!("tour-{n}.png"), &args)
        })
        .collect();
    let mut rows = std::collections::HashMap::new();
    for step in &STEPS {
        rows.entry(step.state.scene)
            .or_insert_with(|| figure_row(step));
    }

    let xvfb = Xvfb::start();
    // The screen's corner, outside the 1024×768 window, before the window opens: a pointer ever
    // over the pane shows its scroll bar until a later pass of the panel fades it out.
    xvfb.xdotool(&["mousemove", "1279", "1023"]);
    let (mut app, _window) = xvfb.open_window(&dir, &["--tour", "1"]);
    let mut reached = vec![0; STEPS.len()];
    let mut shots = 0;
    // The walk borrows the program: quit once it is done.
    {
        let mut walk = |key: Option<&str>, n: usize, way: &str| {
            if let Some(key) = key {
                xvfb.xdotool(&["key", key]);
            }
            let step = &STEPS[n - 1];
            reached[n - 1] += 1;
            app.wait_for_log(
                &format!("the tour, step {n}: {}", step.section),
                reached[n - 1],
            );
            // The third frame after the step, each Ctrl+P one. A new scene's panel has its sizes
            // from its first frame (Panel::run), but egui's fades run on the window's clock, which
            // headless's frozen frames do not have: with the first frame taken, 2 pixels of step
            // 18 differed once in CI.
            xvfb.xdotool(&["key", "ctrl+p", "ctrl+p"]);
            shots += 3;
            let shown = xvfb.screenshot_with(&dir, shots, "ctrl+p");
            assert_eq!(
                differing_but(rows[step.state.scene], &shown, &headless[n - 1]),
                0,
                "step {n} ({}) on the way {way}: pixels differ from --headless --tour {n} --panel \
                 (the window as shown: {})",
                step.section,
                dir.join(format!("tutorial13-{shots}.png")).display()
            );
        };
        walk(None, 1, "up");
        for n in 2..=STEPS.len() {
            walk(Some("Next"), n, "up");
        }
        for n in (1..STEPS.len()).rev() {
            walk(Some("Prior"), n, "down");
        }
    }
    xvfb.quit(&mut app);
}
