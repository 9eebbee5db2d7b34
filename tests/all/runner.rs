//! The scene host as the one runner of every front end: the window's translation of winit's events
//! and the events headless rendering (and a test) gives the host do the same, the front ends' own
//! keys run from their table alone, and headless frames keep the same clock as the window's.

use std::path::Path;
use std::time::{Duration, Instant};

use glam::Vec2;
use tutorial13::frontends::events::{AfterFetch, Event, FrameTime, Request};
use tutorial13::frontends::headless::{HeadlessOptions, HeadlessRenderer};
use tutorial13::frontends::keys::{HostAction, HostKey, Key, HOST_KEYS};
use tutorial13::frontends::page_contract::FROZEN_STEP_S;
use tutorial13::frontends::page_input;
use tutorial13::frontends::panel::PanelWidget;
use tutorial13::frontends::window::input::{key, key_event, translate};
use tutorial13::scenes::{self, SceneOptions};
use tutorial13::tour::STEPS;
use winit::dpi::PhysicalPosition;
use winit::event::{
    DeviceId, ElementState, MouseButton, MouseScrollDelta, TouchPhase, WindowEvent,
};
use winit::keyboard::KeyCode;

use crate::common;

/// A renderer whose frames step as the page's `frames=N` do: deterministic, and (unlike headless's
/// frozen time) a click and the wheel reach the scene, as in a running window.
fn stepped(options: &HeadlessOptions) -> HeadlessRenderer {
    let mut renderer = common::renderer(options);
    renderer.host.set_time(FrameTime::Stepped(FROZEN_STEP_S));
    renderer
}

/// One thing a user does at the window, as winit gives it to the window.
enum Winit {
    Window(WindowEvent),
    /// A key pressed and released (`ctrl`: with Ctrl held). winit's `KeyEvent` cannot be built
    /// outside winit: the window's translation of its key code and state is `key_event`, which
    /// `translate` calls for a `KeyboardInput`.
    Key(KeyCode, bool),
    /// Raw mouse motion (winit's `DeviceEvent::MouseMotion`, which the window gives as `Look`).
    Motion(f64, f64),
}

/// Whether a step is followed by a frame, and whether that frame must differ from the one before.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Frame {
    None,
    Changed,
    Unchanged,
}

/// `what` as the window turns it into the host's events.
fn through_the_window(what: &Winit) -> Vec<Event> {
    match what {
        Winit::Window(event) => translate(event, false).into_iter().collect(),
        Winit::Key(code, ctrl) => [ElementState::Pressed, ElementState::Released]
            .into_iter()
            .filter_map(|state| key_event(*code, state, false, *ctrl))
            .collect(),
        Winit::Motion(dx, dy) => vec![Event::Look(*dx, *dy)],
    }
}

/// A key pressed and released, as any front end's host event.
fn press(key: Key, ctrl: bool) -> Vec<Event> {
    [true, false]
        .map(|pressed| Event::Key {
            key,
            pressed,
            repeat: false,
            ctrl,
        })
        .to_vec()
}

/// Every event of `events` given to `renderer`; what the host asked for.
fn give(renderer: &mut HeadlessRenderer, events: Vec<Event>) -> Vec<Request> {
    let mut asked = Vec::new();
    for event in events {
        asked.extend(renderer.event(event).expect("the event is taken"));
    }
    asked
}

// Fails if the window's translation of winit's events (a pointer, a click, raw motion, keys with
// and without Ctrl, a loss of focus, a wheel) does not give the host what headless rendering's own
// events give it: each step must ask the same of the front end (a grab on the click, a screenshot
// with the panel on Ctrl+P, a release on Tab, the next scene's files on Enter, quit on Esc) and the
// frames after the mouse look, L, the pointer once released, R, Enter and the sprite's cursor and
// wheel must be the same to the bit, each differing from the one before but the one after the
// released pointer's motion (which turns nothing). The page's names for the same keys and the wheel
// must be the same keys and notches.
#[test]
fn the_windows_events_and_headless_events_run_the_host_alike() {
    let cylinder = scenes::default_scene();
    let sprite = scenes::next(cylinder);
    let device_id = DeviceId::dummy();
    let moved = |x: f64, y: f64| {
        Winit::Window(WindowEvent::CursorMoved {
            device_id,
            position: PhysicalPosition::new(x, y),
        })
    };
    let button = |state| {
        Winit::Window(WindowEvent::MouseInput {
            device_id,
            state,
            button: MouseButton::Left,
        })
    };
    let wheel = Winit::Window(WindowEvent::MouseWheel {
        device_id,
        delta: MouseScrollDelta::LineDelta(0.0, 2.0),
        phase: TouchPhase::Moved,
    });
    // Each step: the window's event, the host's event as headless gives it, what the host must ask
    // for, and whether a frame is drawn after it, changed from the one before or not.
    let steps: Vec<(Winit, Vec<Event>, Vec<Request>, Frame)> = vec![
        (
            moved(500.0, 380.0),
            vec![Event::PointerMoved(Vec2::new(500.0, 380.0))],
            vec![],
            Frame::None,
        ),
        (
            button(ElementState::Pressed),
            vec![Event::Button { pressed: true }],
            vec![Request::GrabCursor(true)],
            Frame::None,
        ),
        (
            button(ElementState::Released),
            vec![Event::Button { pressed: false }],
            vec![],
            Frame::None,
        ),
        (
            Winit::Motion(40.0, -10.0),
            vec![Event::Look(40.0, -10.0)],
            vec![],
            Frame::Changed,
        ),
        (
            Winit::Key(KeyCode::KeyL, false),
            press(Key::Char('L'), false),
            vec![],
            Frame::Changed,
        ),
        (
            Winit::Key(KeyCode::KeyP, true),
            press(Key::Char('P'), true),
            vec![Request::Screenshot { with_panel: true }],
            Frame::None,
        ),
        (
            Winit::Key(KeyCode::Tab, false),
            press(Key::Tab, false),
            vec![Request::GrabCursor(false)],
            Frame::None,
        ),
        // Released: neither raw motion nor the pointer turns the camera.
        (
            Winit::Motion(40.0, 0.0),
            vec![Event::Look(40.0, 0.0)],
            vec![],
            Frame::None,
        ),
        (
            moved(700.0, 420.0),
            vec![Event::PointerMoved(Vec2::new(700.0, 420.0))],
            vec![],
            Frame::None,
        ),
        (
            moved(760.0, 450.0),
            vec![Event::PointerMoved(Vec2::new(760.0, 450.0))],
            vec![],
            Frame::Unchanged,
        ),
        (
            Winit::Key(KeyCode::KeyR, false),
            press(Key::Char('R'), false),
            vec![],
            Frame::Changed,
        ),
        (
            Winit::Window(WindowEvent::Focused(false)),
            vec![Event::Focused(false)],
            vec![],
            Frame::None,
        ),
        (
            Winit::Key(KeyCode::Enter, false),
            press(Key::Enter, false),
            vec![
                Request::Fetch {
                    scene: sprite,
                    then: AfterFetch::Switch {
                        from: cylinder,
                        to: sprite,
                    },
                },
                Request::NewScene(sprite),
            ],
            Frame::Changed,
        ),
        (
            moved(600.0, 300.0),
            vec![Event::PointerMoved(Vec2::new(600.0, 300.0))],
            vec![],
            Frame::Changed,
        ),
        (
            wheel,
            vec![Event::Wheel(Vec2::new(0.0, 2.0))],
            vec![],
            Frame::Changed,
        ),
        (
            Winit::Key(KeyCode::Escape, false),
            press(Key::Esc, false),
            vec![Request::Quit],
            Frame::None,
        ),
    ];
    // One renderer at a time: each has its own context, current from when it is made.
    type Step = (Winit, Vec<Event>, Vec<Request>, Frame);
    let run = |events_of: &dyn Fn(&Step) -> Vec<Event>| {
        let mut renderer = stepped(&HeadlessOptions::default());
        let mut frames = vec![(common::frame(&mut renderer), Frame::None)];
        let mut asked = Vec::new();
        for step in &steps {
            asked.push(give(&mut renderer, events_of(step)));
            if step.3 != Frame::None {
                frames.push((common::frame(&mut renderer), step.3));
            }
        }
        (asked, frames)
    };
    let (window_asked, window_frames) = run(&|(winit, events, ..)| {
        let translated = through_the_window(winit);
        assert_eq!(&translated, events, "the window's translation");
        translated
    });
    let (headless_asked, headless_frames) = run(&|(_, events, ..)| events.clone());
    for (n, (_, _, expected, _)) in steps.iter().enumerate() {
        assert_eq!(
            &window_asked[n], expected,
            "step {n}: what the window's events asked for"
        );
        assert_eq!(
            &headless_asked[n], expected,
            "step {n}: what headless events asked for"
        );
    }
    for (n, ((a, _), (b, change))) in window_frames.iter().zip(&headless_frames).enumerate() {
        assert!(
            a == b,
            "frame {n}: {} pixels differ",
            common::differing_pixels(a, b)
        );
        if n > 0 {
            let changed = *b != headless_frames[n - 1].0;
            assert_eq!(
                changed,
                *change == Frame::Changed,
                "frame {n}: changed {changed}"
            );
        }
    }
    // The page's names for the same keys, and its wheel.
    for (code, dom) in [
        (KeyCode::KeyL, "l"),
        (KeyCode::KeyP, "p"),
        (KeyCode::Tab, "Tab"),
        (KeyCode::KeyR, "r"),
        (KeyCode::Enter, "Enter"),
        (KeyCode::Escape, "Escape"),
        (KeyCode::F1, "F1"),
        (KeyCode::ArrowUp, "ArrowUp"),
    ] {
        assert_eq!(page_input::key(dom), key(code), "{dom}");
    }
    assert_eq!(
        page_input::wheel_notches(0.0, -200.0, 0),
        Vec2::new(0.0, 2.0)
    );
}

/// The cylinder with its shaders read from a copy in `dir` (to break one), stepping, the panel shown
/// and laid out once.
fn cylinder_at_start(dir: &Path) -> HeadlessRenderer {
    let shaders = dir.join("shaders");
    std::fs::create_dir_all(&shaders).unwrap();
    for entry in std::fs::read_dir(common::manifest().join("shaders")).unwrap() {
        let path = entry.unwrap().path();
        std::fs::copy(&path, shaders.join(path.file_name().unwrap())).unwrap();
    }
    let mut renderer = stepped(&HeadlessOptions {
        scene: SceneOptions {
            shaders: Some(shaders),
            ..Default::default()
        },
        ..Default::default()
    });
    renderer.host.show_panel().unwrap();
    renderer.render().unwrap();
    renderer
}

// Fails if a row of HOST_KEYS pressed in the window's host does not run its action (R the camera
// back at the start, Tab the cursor released after a click grabbed it, Enter the next scene's files
// then the scene, F5 the shaders read again, P a screenshot, F1 the panel hidden, PageDown and
// PageUp the tour's first step once its files are in, Esc quit), or if
// the keys are dispatched from anywhere but the host's table: with a table of its own, a key added
// to it (F3) runs its action with no other line, and a key left out of it (Esc) does nothing.
#[test]
fn the_host_keys_run_from_their_table() {
    let dir = common::scratch("host-keys");
    for row in HOST_KEYS {
        let mut r = cylinder_at_start(&dir);
        let start = r.host.controls.clone();
        let asked = match row.action {
            HostAction::ResetCamera => {
                r.host.controls.position.z += 2.0;
                give(&mut r, press(row.key, false));
                assert_eq!(r.host.controls.position, start.position, "{}", row.key);
                continue;
            }
            HostAction::ReleaseCursor => {
                // A click on the frame, right of the panel, grabs the cursor first.
                let clicked = [true, false].map(|pressed| Event::Button { pressed });
                let mut events = vec![Event::PointerMoved(Vec2::new(800.0, 400.0))];
                events.extend(clicked);
                assert_eq!(give(&mut r, events), [Request::GrabCursor(true)]);
                give(&mut r, press(row.key, false))
            }
            HostAction::ReloadShaders => {
                let fragment = dir.join("shaders/NormalMapping.fragmentshader");
                let good = std::fs::read_to_string(&fragment).unwrap();
                std::fs::write(&fragment, good.replace("void main", "void main(")).unwrap();
                let reloaded = r.host.event(press(row.key, false)[0].clone());
                std::fs::write(&fragment, good).unwrap();
                assert!(reloaded.is_err(), "F5 did not read the broken shader");
                assert!(r.host.shader_error().is_some(), "no error line");
                continue;
            }
            HostAction::TogglePanel => {
                give(&mut r, press(row.key, false));
                assert!(!r.host.panel_shown(), "{} left the panel shown", row.key);
                continue;
            }
            // Away from the tour's exercise steps it checks nothing (the log says where it does).
            HostAction::CheckExercise => {
                assert_eq!(give(&mut r, press(row.key, false)), [], "{}", row.key);
                assert!(r.host.exercise_answer().is_none(), "{}", row.key);
                continue;
            }
            _ => give(&mut r, press(row.key, false)),
        };
        let expected = match row.action {
            HostAction::ReleaseCursor => vec![Request::GrabCursor(false)],
            HostAction::NextScene => {
                let (from, to) = (
                    scenes::default_scene(),
                    scenes::next(scenes::default_scene()),
                );
                let then = AfterFetch::Switch { from, to };
                vec![Request::Fetch { scene: to, then }, Request::NewScene(to)]
            }
            HostAction::Screenshot => vec![Request::Screenshot { with_panel: false }],
            // With no tour shown, either key starts it at its first step: the step's scene's
            // files, then the scene built again.
            HostAction::TourNext | HostAction::TourBack => {
                assert_eq!(
                    r.host.tour_step().map(|s| s.number()),
                    Some(1),
                    "{}",
                    row.key
                );
                let scene = scenes::find(STEPS[0].state.scene).unwrap();
                let then = AfterFetch::Tour(0);
                vec![Request::Fetch { scene, then }, Request::NewScene(scene)]
            }
            HostAction::Quit => vec![Request::Quit],
            HostAction::ResetCamera
            | HostAction::ReloadShaders
            | HostAction::TogglePanel
            | HostAction::CheckExercise => {
                unreachable!("checked above")
            }
        };
        assert_eq!(asked, expected, "{}", row.key);
    }

    // A table of the host's own: F3 added (a screenshot), Esc left out.
    let mut rows: Vec<HostKey> = HOST_KEYS
        .iter()
        .filter(|k| k.action != HostAction::Quit)
        .copied()
        .collect();
    rows.push(HostKey {
        key: Key::F(3),
        help: "save a screenshot",
        action: HostAction::Screenshot,
        look_only: false,
        on_page: false,
    });
    let mut r = cylinder_at_start(&dir);
    r.host.set_host_keys(Box::leak(rows.into_boxed_slice()));
    let asked = give(&mut r, press(Key::F(3), false));
    assert_eq!(asked, [Request::Screenshot { with_panel: false }], "F3");
    assert_eq!(give(&mut r, press(Key::Esc, false)), [], "Esc");
}

// Fails if headless frames do not tick the host's clock (the panel would show "– ms/frame" for
// ever), if the figure is not drawn where the panel's figure is, or if a frozen frame shows it (a
// frozen frame, a screenshot's or a test's, would then change once a second of frames had passed:
// two runs, or a slow run and a fast one, would differ). Once the clock has its first figure, the
// frozen frame must still equal the first frame bit for bit; with the time running, the next frame
// must differ from it only inside the figure's label (and the pixel around it a glyph's edge may
// reach).
#[test]
fn headless_panel_shows_its_ms_per_frame() {
    let mut r = common::renderer(&HeadlessOptions::default());
    r.host.show_panel().unwrap();
    let first = common::frame(&mut r);
    let label = r
        .host
        .panel()
        .and_then(|p| p.widget_rect(&PanelWidget::Figure))
        .expect("the panel shows the figure's label");
    let deadline = Instant::now() + Duration::from_secs(30);
    while r.host.clock.ms_per_frame().is_none() {
        assert!(
            Instant::now() < deadline,
            "no ms/frame figure after {} headless frames in 30 s",
            r.host.frames_drawn()
        );
        r.render().unwrap();
    }
    let ms = r.host.clock.ms_per_frame().unwrap();
    assert!(
        common::frame(&mut r) == first,
        "a frozen frame shows the wall clock's figure"
    );
    r.host.set_time(FrameTime::Running);
    let shown = common::frame(&mut r);
    // The label as drawn now, with the figure: wider than the dash it replaces. A glyph's
    // antialiased edge may reach a pixel past the rectangle egui lays the text out in.
    let now = r
        .host
        .panel()
        .unwrap()
        .widget_rect(&PanelWidget::Figure)
        .unwrap();
    let label = label.union(now).expand(1.0);
    let mut inside = 0;
    for (x, y, p) in shown.enumerate_pixels() {
        if first.get_pixel(x, y) != p {
            let at = egui::pos2(x as f32 + 0.5, y as f32 + 0.5);
            assert!(
                label.contains(at),
                "({x}, {y}) differs outside the label {label:?}"
            );
            inside += 1;
        }
    }
    eprintln!(
        "runner: headless panel after {} frames: {ms:.3} ms/frame, {inside} pixels of its label",
        r.host.frames_drawn()
    );
    assert!(inside > 0, "the figure's label did not change");
}
