//! The browser page in a real browser: Chromium headless on SwiftShader's WebGL2, loading the page
//! `web/build.sh` wrote from the server `web/test.sh` starts (`TUTORIAL13_WEB_URL`). Each scene's
//! frame is compared with the native headless frame (SwiftShader rasterizes on its own, so "within
//! 8 levels on 90 % of the pixels", the share measured printed), the panel shows, a click on a
//! switch does what its key does, and the page's console holds no error.
//!
//! Without `TUTORIAL13_WEB_URL` these tests say they are skipped (the README's test command builds no
//! browser page); with `TUTORIAL13_REQUIRE_WEB=1` (web/test.sh) they fail instead.

use std::path::Path;
use std::process::Command;

use glam::{Vec2, Vec3};
use image::RgbImage;
use tutorial13::frontends::headless::{HeadlessOptions, HeadlessRenderer};
use tutorial13::frontends::keys::Arrow;
use tutorial13::frontends::page_contract::FROZEN_STEP_S;
use tutorial13::frontends::panel::PanelWidget;
use tutorial13::scenes::{self, SceneDescriptor, SCENES};

use crate::common::{self, frame, frame_diff};

/// The share of pixels that must be within [`TOLERANCE`] of the native frame.
const WITHIN: f64 = 0.90;
/// Levels (of 255, per channel) a pixel of the page may differ from the native one by.
const TOLERANCE: u8 = 8;

/// The page's address, or `None` (said) where the browser tests are not run.
fn page_url(test: &str) -> Option<String> {
    match std::env::var("TUTORIAL13_WEB_URL") {
        Ok(url) => Some(url),
        Err(_) if std::env::var_os("TUTORIAL13_REQUIRE_WEB").is_some() => {
            panic!("{test}: TUTORIAL13_REQUIRE_WEB is set but TUTORIAL13_WEB_URL is not")
        }
        Err(_) => {
            common::skip(
                test,
                "no TUTORIAL13_WEB_URL (the browser tests run with web/test.sh)",
            );
            None
        }
    }
}

/// What Chromium showed for `query`: the 1024×768 screenshot and the page's DOM once the frames
/// were drawn.
struct Loaded {
    shot: RgbImage,
    dom: String,
}

impl Loaded {
    /// The text of the element `id`.
    fn text(&self, id: &str) -> Option<String> {
        let start = self.dom.find(&format!("id=\"{id}\""))?;
        let rest = &self.dom[start..];
        let open = rest.find('>')? + 1;
        let close = rest.find("</")?;
        Some(rest[open..close].trim().to_owned())
    }

    /// The attribute `name` of the element `id`, as the DOM was dumped.
    fn attribute(&self, id: &str, name: &str) -> Option<String> {
        let start = self.dom.find(&format!("id=\"{id}\""))?;
        let tag = &self.dom[self.dom[..start].rfind('<')?..];
        let tag = &tag[..tag.find('>')?];
        let value = &tag[tag.find(&format!(" {name}=\""))? + name.len() + 3..];
        Some(value[..value.find('"')?].to_owned())
    }

    /// The camera of the page's last frame (`data-camera`): position, horizontal and vertical
    /// angle.
    fn camera(&self) -> (Vec3, f32, f32) {
        let text = self
            .attribute("canvas", "data-camera")
            .expect("data-camera");
        let numbers: Vec<f32> = text
            .split(' ')
            .map(|n| n.parse().expect("a number"))
            .collect();
        let [x, y, z, h, v] = numbers[..] else {
            panic!("data-camera={text}")
        };
        (Vec3::new(x, y, z), h, v)
    }

    /// The page's log lines saying which files it fetched for a scene.
    fn fetched(&self) -> Vec<String> {
        let log = self.text("console-log").unwrap_or_default();
        log.lines()
            .filter(|l| l.contains(": fetched "))
            .map(|l| l.split(" (").next().unwrap_or(l).to_owned())
            .collect()
    }

    /// The page's message and what reached the console as an error: nothing.
    fn check_clean(&self, what: &str) {
        let message = self.text("message");
        assert_eq!(message.as_deref(), Some(""), "{what}: the page's message");
        self.check_console(what);
    }

    /// What reached the console as an error: nothing.
    fn check_console(&self, what: &str) {
        let errors = self.text("console-errors");
        assert_eq!(errors.as_deref(), Some(""), "{what}: the console's errors");
    }
}

fn chromium(url: &str, action: &str, out: &Path, flags: &[&str]) -> Command {
    let binary = std::env::var("TUTORIAL13_CHROMIUM").unwrap_or_else(|_| "chromium".into());
    let mut command = Command::new(binary);
    command.args([
        "--headless=new",
        "--use-angle=swiftshader",
        "--enable-unsafe-swiftshader",
        "--no-sandbox",
        "--no-first-run",
        "--hide-scrollbars",
        "--window-size=1024,768",
        "--virtual-time-budget=20000",
        &format!("--user-data-dir={}", out.join("profile").display()),
        action,
    ]);
    command.args(flags).arg(url);
    command
}

/// Loads `query` (after `?`) in Chromium: a screenshot, then the DOM.
fn load(test: &str, base: &str, query: &str) -> Loaded {
    load_with(test, base, query, &[])
}

/// [`load`] with more of Chromium's flags.
fn load_with(test: &str, base: &str, query: &str, flags: &[&str]) -> Loaded {
    let out = common::scratch(&format!("{test}-{}", query.replace(['&', '=', ','], "_")));
    let url = format!("{base}/index.html?{query}");
    let png = out.join("page.png");
    let shot = common::run(&mut chromium(
        &url,
        &format!("--screenshot={}", png.display()),
        &out,
        flags,
    ));
    assert!(png.is_file(), "{url}: no screenshot: {shot:?}");
    let dumped = common::run(&mut chromium(&url, "--dump-dom", &out, flags));
    let dom = String::from_utf8_lossy(&dumped.stdout).into_owned();
    let shot = image::open(&png).expect("Chromium's PNG").into_rgb8();
    assert_eq!(
        shot.dimensions(),
        (1024, 768),
        "{url}: the screenshot's size"
    );
    Loaded { shot, dom }
}

/// What Chromium showed for `query` once the JavaScript `condition` came true, in real time
/// (web/page.py, through the DevTools protocol): for a page that waits on its bake's Web Worker,
/// whose work virtual time (as [`load`] runs) would not wait for.
fn load_when(test: &str, base: &str, query: &str, condition: &str) -> Loaded {
    let out = common::scratch(&format!("{test}-{}", query.replace(['&', '=', ','], "_")));
    let url = format!("{base}/index.html?{query}");
    let driven = common::run(
        Command::new("python3")
            .arg(common::manifest().join("web/page.py"))
            .args([&url, condition])
            .arg(&out),
    );
    assert!(
        driven.status.success(),
        "{url}: {}",
        common::text(&driven.stderr)
    );
    let shot = image::open(out.join("page.png"))
        .expect("the page's screenshot")
        .into_rgb8();
    let dom = std::fs::read_to_string(out.join("dom.html")).expect("the page's HTML");
    assert_eq!(
        shot.dimensions(),
        (1024, 768),
        "{url}: the screenshot's size"
    );
    Loaded { shot, dom }
}

/// The share of pixels of `page` within [`TOLERANCE`] of `native`.
fn share_within(page: &RgbImage, native: &RgbImage) -> f64 {
    let d = frame_diff(page, native);
    1.0 - d.over(TOLERANCE) as f64 / d.pixels() as f64
}

/// The page's log line for the files it fetched for `scene`, without the byte count.
fn fetched_line(scene: &SceneDescriptor) -> String {
    format!(
        "scene {}: fetched {}",
        scene.name,
        scene.asset_files.join(", ")
    )
}

fn native_renderer(name: &str) -> HeadlessRenderer {
    common::renderer(&HeadlessOptions {
        descriptor: scenes::find(name).expect("a scene"),
        ..Default::default()
    })
}

// Fails if a scene's page frame (`frames=1`, panel off) is not the native headless frame within
// the tolerance, or the page shows a message or logs an error.
#[test]
fn each_scene_in_the_page_is_the_native_frame() {
    let Some(base) = page_url("web::each_scene_in_the_page_is_the_native_frame") else {
        return;
    };
    for scene in SCENES {
        let page = load(
            "scene",
            &base,
            &format!("scene={}&panel=off&frames=1", scene.name),
        );
        page.check_clean(scene.name);
        assert_eq!(
            page.fetched(),
            [fetched_line(scene)],
            "{}: the files fetched",
            scene.name
        );
        let native = frame(&mut native_renderer(scene.name));
        let share = share_within(&page.shot, &native);
        eprintln!(
            "web: {}: {:.2} % of pixels within {TOLERANCE} levels of the native frame",
            scene.name,
            share * 100.0
        );
        assert!(
            share >= WITHIN,
            "{}: {:.4} within {TOLERANCE}",
            scene.name,
            share
        );
    }
}

// Fails if the page without `panel=off` does not show the panel as the native headless `--panel`
// frame does.
#[test]
fn the_page_shows_the_panel() {
    let Some(base) = page_url("web::the_page_shows_the_panel") else {
        return;
    };
    let page = load("panel", &base, "scene=cylinder&frames=1");
    page.check_clean("panel");
    let mut renderer = native_renderer("cylinder");
    renderer.host.show_panel().expect("the panel");
    let native = frame(&mut renderer);
    let share = share_within(&page.shot, &native);
    eprintln!(
        "web: cylinder with the panel: {:.2} % of pixels within {TOLERANCE} levels",
        share * 100.0
    );
    assert!(
        share >= WITHIN,
        "with the panel: {share:.4} within {TOLERANCE}"
    );
    let without = frame(&mut native_renderer("cylinder"));
    assert!(
        share_within(&page.shot, &without) < share,
        "the page's frame is nearer the frame without the panel"
    );
}

// Fails if a click on the panel's L switch (at the centre the native panel draws it) does not
// change the frame as the L key does, or changes nothing.
#[test]
fn a_click_on_a_switch_does_what_its_key_does() {
    let Some(base) = page_url("web::a_click_on_a_switch_does_what_its_key_does") else {
        return;
    };
    let mut renderer = native_renderer("cylinder");
    renderer.host.show_panel().expect("the panel");
    frame(&mut renderer);
    let panel = renderer.host.panel().expect("the panel");
    let at = panel
        .widget_rect(&PanelWidget::Key('L'))
        .expect("the L switch")
        .center();
    let panel_right = panel.rect().expect("the panel's rectangle").max.x.ceil() as u32;
    let clicked = load("click", &base, &format!("frames=9&click={},{}", at.x, at.y));
    let pressed = load("key", &base, "frames=9&key=l");
    let untouched = load("none", &base, "frames=9");
    untouched.check_clean("none");
    // L on says, as natively, that the lines fall back to the line shader: the same line both ways.
    for (loaded, what) in [(&clicked, "click"), (&pressed, "key")] {
        loaded.check_console(what);
        let message = loaded.text("message").unwrap_or_default();
        assert!(
            message.contains("line shader"),
            "{what}: the page says {message}"
        );
    }
    assert_eq!(clicked.text("message"), pressed.text("message"));
    // The scene's part of the frame (the panel differs by the hovered switch).
    let scene_part = |image: &RgbImage| {
        image::imageops::crop_imm(image, panel_right, 0, 1024 - panel_right, 768).to_image()
    };
    let (clicked, pressed, untouched) = (
        scene_part(&clicked.shot),
        scene_part(&pressed.shot),
        scene_part(&untouched.shot),
    );
    assert_eq!(
        frame_diff(&clicked, &pressed).differing(),
        0,
        "the click and the key differ"
    );
    // The lines are thin: a few hundred pixels of the scene's part.
    let changed = frame_diff(&clicked, &untouched).differing();
    eprintln!("web: the click on L changed {changed} pixels of the scene, as the key did");
    assert!(changed > 100, "the click changed {changed} pixels");
}

// Fails if a dropped file that is no model or an OBJ without texture coordinates does not put the
// native program's one line on the page (the folder aside), if an MTL naming a missing map does
// not give its notice there too, or if any of them logs an error to the console.
#[test]
fn bad_drops_give_the_native_lines() {
    let Some(base) = page_url("web::bad_drops_give_the_native_lines") else {
        return;
    };
    let served =
        std::env::var("TUTORIAL13_WEB_DIR").expect("TUTORIAL13_WEB_DIR (web/test.sh sets it)");
    let drops = Path::new(&served).join("drops");
    std::fs::create_dir_all(&drops).expect("drops/ in the served folder");
    let triangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\n";
    let files = [
        ("notes.txt", "not a model\n".to_owned()),
        ("bare.obj", format!("{triangle}f 1//1 2//1 3//1\n")),
        (
            "lost.obj",
            format!("mtllib lost.mtl\n{triangle}vt 0 0\nvt 1 0\nvt 0 1\nusemtl m\nf 1/1/1 2/2/1 3/3/1\n"),
        ),
        ("lost.mtl", "newmtl m\nmap_Kd nothere.png\n".to_owned()),
    ];
    for (name, text) in &files {
        std::fs::write(drops.join(name), text).expect("a dropped file");
    }
    let in_page = |line: &str| line.replace(&format!("{}/", drops.display()), "dropped/");
    let mut renderer = native_renderer("cylinder");
    for name in ["notes.txt", "bare.obj"] {
        let native = match renderer.host.open_file(&drops.join(name)) {
            Err(e) => e.to_string(),
            Ok(()) => panic!("{name} opened natively"),
        };
        let page = load("drop", &base, &format!("frames=2&drop={name}"));
        page.check_console(name);
        assert_eq!(page.text("message"), Some(in_page(&native)), "{name}");
    }
    let native = common::run(
        common::tutorial13()
            .args(["--headless", "--model", "lost.obj", "--frames", "1"])
            .args(["--screenshot", "lost.png"])
            .current_dir(&drops),
    );
    // The page has no OS error codes: "No such file or directory", without " (os error 2)".
    let stderr = String::from_utf8_lossy(&native.stderr).replace(" (os error 2)", "");
    let page = load("drop", &base, "frames=2&drop=lost.obj,lost.mtl");
    page.check_console("lost.obj");
    let message = page.text("message").unwrap_or_default();
    assert!(message.contains("nothere.png"), "the page says: {message}");
    for line in message.lines() {
        let line = line.replace("dropped/", "");
        assert!(
            stderr.contains(&line),
            "{line:?} is not in the native {stderr:?}"
        );
    }
}

// Fails if a browser without WebGL2 gets a blank canvas instead of a line saying so, or an error
// in its console.
#[test]
fn no_webgl2_is_said_on_the_page() {
    let Some(base) = page_url("web::no_webgl2_is_said_on_the_page") else {
        return;
    };
    let page = load_with("no-webgl", &base, "frames=1", &["--disable-webgl"]);
    page.check_console("no WebGL2");
    let message = page.text("message").unwrap_or_default();
    assert!(
        message.contains("no WebGL2 context"),
        "the page says: {message}"
    );
}

/// The package versions a lock file pins: `name version` (with its checksum, where it has one) for
/// each of its packages.
fn locked_packages(path: &Path) -> Vec<(String, String)> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    text.split("[[package]]")
        .skip(1)
        .map(|block| {
            let field = |key: &str| {
                block
                    .lines()
                    .find_map(|l| l.strip_prefix(&format!("{key} = \"")))
                    .and_then(|v| v.strip_suffix('"'))
                    .unwrap_or("")
                    .to_owned()
            };
            let name = format!("{} {}", field("name"), field("version"));
            (name, field("checksum"))
        })
        .collect()
}

// Fails if web/Cargo.lock pins a package (a version, or a checksum) that the root Cargo.lock does
// not: the page would be built with other versions than the native tests ran. web/ is its own
// package (its release profile is the page's), so it has its own lock. Fails too if that lock is
// not what cargo resolves for web/ now (web/build.sh builds with --locked and would refuse it).
#[test]
fn the_pages_lock_pins_the_root_locks_versions() {
    let root = locked_packages(&common::manifest().join("Cargo.lock"));
    let web = locked_packages(&common::manifest().join("web/Cargo.lock"));
    let not_in_root: Vec<String> = web
        .iter()
        .filter(|(name, _)| !name.starts_with("tutorial13-web "))
        .filter(|package| !root.contains(package))
        .map(|(name, checksum)| format!("{name} {checksum}"))
        .collect();
    assert!(
        not_in_root.is_empty(),
        "web/Cargo.lock pins packages the root Cargo.lock does not: {not_in_root:?}; make it the \
         root's again: cp Cargo.lock web/ && (cd web && cargo metadata --offline \
         --format-version 1 >/dev/null)"
    );
    // The page's lock is the one cargo resolves now: web/build.sh builds with --locked, so a
    // dependency added to the root's Cargo.toml must reach web/Cargo.lock too (CI once failed there).
    // `update -w` resolves from the registry's index alone (no sources fetched), as the root's
    // build left it; with --locked it refuses any change to the lock.
    let resolve = std::process::Command::new(env!("CARGO"))
        .args(["update", "-w", "--locked", "--offline"])
        .current_dir(common::manifest().join("web"))
        .output()
        .expect("cargo update runs");
    assert!(
        resolve.status.success(),
        "web/Cargo.lock is not what cargo resolves for web/ now (update it: cd web && cargo \
         metadata --offline --format-version 1 >/dev/null): {}",
        String::from_utf8_lossy(&resolve.stderr).trim()
    );
    // Every package the root resolves for the library and the page, the page's lock has too (the
    // root also has the test-only ones).
    for needed in ["tutorial13 ", "wasm-bindgen ", "glow ", "egui ", "gltf "] {
        assert!(
            web.iter().any(|(name, _)| name.starts_with(needed)),
            "web/Cargo.lock has no {needed}"
        );
    }
}

// Fails if the page without WEBGL_compressed_texture_s3tc (`s3tc=off`) does not say in its log
// that it decoded both DXT maps on the CPU, if its cylinder is not the native frame within the
// scenes' tolerance, or if it is more than 1 level off the page's frame with the driver's decoding
// (the page with S3TC must not say it decoded on the CPU).
#[test]
fn without_s3tc_the_page_decodes_dxt_on_the_cpu() {
    let Some(base) = page_url("web::without_s3tc_the_page_decodes_dxt_on_the_cpu") else {
        return;
    };
    let cpu = load("s3tc", &base, "scene=cylinder&panel=off&frames=1&s3tc=off");
    cpu.check_clean("s3tc=off");
    let log = cpu.text("console-log").unwrap_or_default();
    for map in ["diffuse.DDS", "specular.DDS"] {
        assert!(
            log.lines()
                .any(|l| l.starts_with(&format!("assets/{map}: DXT3 decoded on the CPU"))),
            "{map} is not said to be decoded on the CPU: {log}"
        );
    }
    let native = frame(&mut native_renderer("cylinder"));
    let share = share_within(&cpu.shot, &native);
    let driver = load("s3tc", &base, "scene=cylinder&panel=off&frames=1");
    let log = driver.text("console-log").unwrap_or_default();
    assert!(!log.contains("decoded on the CPU"), "with S3TC: {log}");
    let d = frame_diff(&cpu.shot, &driver.shot);
    eprintln!(
        "web: cylinder, DXT decoded on the CPU: {:.2} % of pixels within {TOLERANCE} levels of \
         the native frame ({:.2} % with the driver's); against the driver's: {} pixels differ, by \
         {} levels at most, {} by more than 1",
        share * 100.0,
        share_within(&driver.shot, &native) * 100.0,
        d.differing(),
        d.max(),
        d.over(1),
    );
    assert!(share >= WITHIN, "s3tc=off: {share:.4} within {TOLERANCE}");
    // The same blocks decoded by texpresso and by SwiftShader: 0 levels apart when measured; a
    // decoder may round the 1/3 and 2/3 colours otherwise, by a level.
    assert!(
        d.max() <= 1,
        "the CPU's decoding is {} levels off the driver's",
        d.max()
    );
}

/// The native cylinder after `input` went through the host as the page's `frames=N` takes it
/// (one step of [`FROZEN_STEP_S`] a frame, for `steps` frames), then drawn as `frames=1` draws.
fn native_after(
    scene: &str,
    steps: u32,
    input: impl FnOnce(&mut HeadlessRenderer),
) -> (RgbImage, HeadlessRenderer) {
    let mut renderer = native_renderer(scene);
    input(&mut renderer);
    for _ in 0..steps {
        renderer.host.frame_input(FROZEN_STEP_S, 0.0, false);
    }
    (frame(&mut renderer), renderer)
}

// Fails if a drag on the canvas does not turn the camera by the tutorial's mouse speed × the
// pixels dragged (to 1e-5 rad), if the frame is not the native frame after the same look input
// through the host (within the scenes' tolerance), or if it is not nearer that frame (pixels more
// than 2 levels off) than the frame without the drag.
#[test]
fn a_drag_looks_as_the_host_predicts() {
    let Some(base) = page_url("web::a_drag_looks_as_the_host_predicts") else {
        return;
    };
    let (from, to) = (Vec2::new(500.0, 380.0), Vec2::new(560.0, 400.0));
    let page = load(
        "drag",
        &base,
        &format!(
            "scene=cylinder&panel=off&frames=9&drag={},{},{},{}",
            from.x, from.y, to.x, to.y
        ),
    );
    page.check_clean("drag");
    let moved = to - from;
    let (native, renderer) = native_after("cylinder", 1, |r| {
        r.host.look((f64::from(moved.x), f64::from(moved.y)))
    });
    let c = &renderer.host.controls;
    let (position, h, v) = page.camera();
    eprintln!(
        "web: the drag by {moved}: the page's camera turned to {h}, {v} (the host's: {}, {})",
        c.horizontal_angle, c.vertical_angle
    );
    assert!(
        (h - c.horizontal_angle).abs() < 1e-5,
        "horizontal angle {h}"
    );
    assert!((v - c.vertical_angle).abs() < 1e-5, "vertical angle {v}");
    assert!(position.distance(c.position) < 1e-6, "moved to {position}");
    let share = share_within(&page.shot, &native);
    let still = frame(&mut native_renderer("cylinder"));
    let (near, unmoved) = (
        frame_diff(&page.shot, &native).over(2),
        frame_diff(&page.shot, &still).over(2),
    );
    eprintln!(
        "web: after the drag: {:.2} % of pixels within {TOLERANCE} levels of the native frame \
         after the same look; {near} pixels differ from it by more than 2 levels, {unmoved} from \
         the frame without the drag",
        share * 100.0,
    );
    assert!(
        share >= WITHIN,
        "after the drag: {share:.4} within {TOLERANCE}"
    );
    assert!(
        unmoved > near,
        "the frame is as near the one without the drag"
    );
}

// Fails if an arrow key held for frames 2 and 3 does not move the camera as the host moves it for
// two frames (`speed × FROZEN_STEP_S` a frame, to 1e-5), or if the frame is not the native frame
// after the same input (within the scenes' tolerance).
#[test]
fn an_arrow_key_moves_the_camera_as_the_host_predicts() {
    let Some(base) = page_url("web::an_arrow_key_moves_the_camera_as_the_host_predicts") else {
        return;
    };
    let start = native_renderer("cylinder").host.controls.clone();
    for (key, arrow) in [("ArrowUp", Arrow::Up), ("ArrowLeft", Arrow::Left)] {
        let page = load(
            "arrow",
            &base,
            &format!("scene=cylinder&panel=off&frames=9&key={key}"),
        );
        page.check_clean(key);
        let (position, h, v) = page.camera();
        assert_eq!((h, v), (start.horizontal_angle, start.vertical_angle));
        // The frames the key was held: keydown after frame 1, keyup after frame 3, so frames 2
        // and 3 (each frame is a timer task of its own, after which the page's script runs).
        let step = start.speed * FROZEN_STEP_S;
        let frames = (position.distance(start.position) / step).round() as u32;
        let (native, renderer) = native_after("cylinder", frames, |r| r.host.arrow(arrow, true));
        let predicted = renderer.host.controls.position;
        eprintln!(
            "web: {key} held {frames} frames: the page's camera at {position}, the host's at \
             {predicted}"
        );
        assert_eq!(frames, 2, "{key}: the camera moved {frames} frames' steps");
        assert!(
            position.distance(predicted) < 1e-5,
            "{key}: at {position}, not {predicted}"
        );
        let share = share_within(&page.shot, &native);
        eprintln!(
            "web: after {key}: {:.2} % of pixels within {TOLERANCE} levels",
            share * 100.0
        );
        assert!(share >= WITHIN, "{key}: {share:.4} within {TOLERANCE}");
    }
}

// Fails if 5 notches of the wheel (a DOM deltaY of -500) over the sprite do not raise its light as
// the host's scroll by 5 does: the page's frame must be the native frame with the cursor there and
// the 5 notches, within the scenes' tolerance, and nearer it (pixels more than 2 levels off) than
// the frames after 0, 4 or 6 notches.
#[test]
fn the_wheel_raises_the_sprites_light_as_the_host_predicts() {
    let Some(base) = page_url("web::the_wheel_raises_the_sprites_light_as_the_host_predicts")
    else {
        return;
    };
    let at = Vec2::new(300.0, 250.0);
    let page = load(
        "wheel",
        &base,
        &format!(
            "scene=sprite&panel=off&frames=9&wheel={},{},-500",
            at.x, at.y
        ),
    );
    page.check_clean("wheel");
    // The native frame with the cursor there after `notches`.
    let native = |notches: f32| {
        native_after("sprite", 0, |r| {
            r.host.cursor = Some(at);
            r.host.scroll(notches);
        })
        .0
    };
    let share = share_within(&page.shot, &native(5.0));
    // Pixels more than 2 levels off the native frame after 0, 4, 5 and 6 notches.
    let counts: Vec<usize> = [0.0, 4.0, 5.0, 6.0]
        .into_iter()
        .map(|n| frame_diff(&page.shot, &native(n)).over(2))
        .collect();
    eprintln!(
        "web: sprite after 5 notches of the wheel at {at}: {:.2} % of pixels within {TOLERANCE} \
         levels of the native frame; pixels more than 2 levels off the native frame after 0, 4, \
         5, 6 notches: {counts:?}",
        share * 100.0,
    );
    assert!(share >= WITHIN, "the wheel: {share:.4} within {TOLERANCE}");
    let nearest = (0..counts.len()).min_by_key(|&i| counts[i]);
    assert_eq!(
        nearest,
        Some(2),
        "nearest another number of notches: {counts:?}"
    );
}

/// A learner's textured cube as a modelling tool exports it (Blender 4's OBJ exporter: its header,
/// `o`, normals to 4 places, `s 0`, quads, and an MTL with its usual statements and `map_Bump -bm`),
/// turned so that three faces show, with a PNG diffuse and normal map and a JPEG specular map:
/// written into `dir`, the names returned (the model first).
fn modelling_tool_export(dir: &Path) -> Vec<&'static str> {
    let turn = glam::Quat::from_rotation_y(0.6) * glam::Quat::from_rotation_x(0.45);
    let mut obj =
        String::from("# Blender 4.2.3 LTS\n# www.blender.org\nmtllib crate.mtl\no Crate\n");
    // Each face: its normal and two edges along U and V (corners counter-clockwise from outside).
    let faces = [
        (Vec3::Z, Vec3::X, Vec3::Y),
        (Vec3::NEG_Z, Vec3::NEG_X, Vec3::Y),
        (Vec3::X, Vec3::NEG_Z, Vec3::Y),
        (Vec3::NEG_X, Vec3::Z, Vec3::Y),
        (Vec3::Y, Vec3::X, Vec3::NEG_Z),
        (Vec3::NEG_Y, Vec3::X, Vec3::Z),
    ];
    let mut normals = String::new();
    let mut quads = String::new();
    for (f, (n, u, v)) in faces.iter().enumerate() {
        for (du, dv) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
            let p = turn * (*n + *u * du + *v * dv);
            obj += &format!("v {:.6} {:.6} {:.6}\n", p.x, p.y, p.z);
        }
        let n = turn * *n;
        normals += &format!("vn {:.4} {:.4} {:.4}\n", n.x, n.y, n.z);
        let c = |i: usize| format!("{}/{}/{}", 4 * f + i + 1, i + 1, f + 1);
        quads += &format!("f {} {} {} {}\n", c(0), c(1), c(2), c(3));
    }
    obj += &normals;
    obj +=
        "vt 0.000000 0.000000\nvt 1.000000 0.000000\nvt 1.000000 1.000000\nvt 0.000000 1.000000\n";
    obj += "s 0\nusemtl Crate\n";
    obj += &quads;
    let mtl = "# Blender 4.2.3 LTS MTL File: 'crate.blend'\n# www.blender.org\n\nnewmtl Crate\n\
               Ns 250.000000\nKa 1.000000 1.000000 1.000000\nKd 0.800000 0.800000 0.800000\n\
               Ks 0.500000 0.500000 0.500000\nKe 0.000000 0.000000 0.000000\nNi 1.450000\n\
               d 1.000000\nillum 2\nmap_Kd crate_diffuse.png\n\
               map_Bump -bm 1.000000 crate_normal.png\nmap_Ks crate_specular.jpg\n";
    std::fs::write(dir.join("crate.obj"), obj).expect("crate.obj");
    std::fs::write(dir.join("crate.mtl"), mtl).expect("crate.mtl");
    let size = 256;
    // Planks: brown stripes with darker seams; the normal map raises a rivet in each corner and
    // grooves the seams; the specular map is bright on the rivets.
    let seam = |x: u32| x % 64 < 4;
    let rivet = |x: u32, y: u32| {
        let (dx, dy) = ((x % 128) as f32 - 24.0, (y % 128) as f32 - 24.0);
        (dx * dx + dy * dy).sqrt() < 10.0
    };
    let diffuse = RgbImage::from_fn(size, size, |x, y| {
        let wood = 120 + (y * 7 % 40) as u8;
        if seam(x) {
            image::Rgb([60, 40, 20])
        } else if rivet(x, y) {
            image::Rgb([150, 150, 160])
        } else {
            image::Rgb([wood, (u16::from(wood) * 2 / 3) as u8, 40])
        }
    });
    let normal = RgbImage::from_fn(size, size, |x, y| {
        let (dx, dy) = ((x % 128) as f32 - 24.0, (y % 128) as f32 - 24.0);
        let n = if rivet(x, y) {
            Vec3::new(dx / 12.0, -dy / 12.0, 1.0).normalize()
        } else if seam(x) {
            Vec3::new(if x % 64 < 2 { 0.7 } else { -0.7 }, 0.0, 0.7).normalize()
        } else {
            Vec3::Z
        };
        let byte = |c: f32| ((c * 0.5 + 0.5) * 255.0).round() as u8;
        image::Rgb([byte(n.x), byte(n.y), byte(n.z)])
    });
    let specular = image::GrayImage::from_fn(size, size, |x, y| {
        image::Luma([if rivet(x, y) { 230 } else { 40 }])
    });
    diffuse
        .save(dir.join("crate_diffuse.png"))
        .expect("the PNG");
    normal.save(dir.join("crate_normal.png")).expect("the PNG");
    specular
        .save(dir.join("crate_specular.jpg"))
        .expect("the JPEG");
    vec![
        "crate.obj",
        "crate.mtl",
        "crate_diffuse.png",
        "crate_normal.png",
        "crate_specular.jpg",
    ]
}

// Fails if a learner's OBJ with its MTL and PNG/JPEG maps, dropped on the page (showing the wall)
// together, does not give the native `--model` frame within the scenes' tolerance, is still the
// cylinder, puts a line on the page or an error in its console, or if the page did not fetch the
// cylinder's files for it (and the wall's only before). A map the page did not get is caught by the line
// (the notice a missing map gives), not by the frame: with the JPEG left out the frame was still
// 99.78 % within 8 levels (4463 pixels more than 2 levels off, 2071 with it).
#[test]
fn a_dropped_model_with_its_maps_is_the_native_model_frame() {
    let Some(base) = page_url("web::a_dropped_model_with_its_maps_is_the_native_model_frame")
    else {
        return;
    };
    let served =
        std::env::var("TUTORIAL13_WEB_DIR").expect("TUTORIAL13_WEB_DIR (web/test.sh sets it)");
    let drops = Path::new(&served).join("drops");
    std::fs::create_dir_all(&drops).expect("drops/ in the served folder");
    let names = modelling_tool_export(&drops);
    let native = common::run(
        common::tutorial13()
            .args(["--headless", "--model", "crate.obj", "--frames", "1"])
            .args(["--screenshot", "crate.png"])
            .current_dir(&drops),
    );
    assert!(native.status.success(), "{}", common::text(&native.stderr));
    // What the native program warns of, as the page names the dropped files.
    let warned: Vec<String> = common::text(&native.stderr)
        .lines()
        .filter_map(|l| l.strip_prefix("[WARN ] "))
        .map(|l| format!("dropped/{l}"))
        .collect();
    let native = image::open(drops.join("crate.png"))
        .expect("the native frame")
        .into_rgb8();
    // The page starts on the wall, so that the cylinder's files (which a model opens with) are
    // fetched at the drop. The drop lands after frame 1; the files are fetched and read before it
    // opens, so the frame taken is a late one.
    let page = load(
        "model",
        &base,
        &format!("scene=wall&panel=off&frames=60&drop={}", names.join(",")),
    );
    // The page says what the native program warns of and nothing more: the one notice that the
    // tutorial's frame on this model is far from MikkTSpace's.
    assert_eq!(
        page.text("message").unwrap_or_default(),
        warned.join("\n"),
        "the dropped model: the page's message"
    );
    assert_eq!(warned.len(), 1, "{warned:?}");
    page.check_console("the dropped model");
    let [wall, cylinder] = ["wall", "cylinder"].map(|name| scenes::find(name).unwrap());
    assert_eq!(
        page.fetched(),
        [fetched_line(wall), fetched_line(cylinder)],
        "the files fetched"
    );
    let share = share_within(&page.shot, &native);
    let cylinder = frame(&mut native_renderer("cylinder"));
    let (near, from_cylinder) = (
        frame_diff(&page.shot, &native).over(2),
        frame_diff(&page.shot, &cylinder).over(2),
    );
    eprintln!(
        "web: the dropped crate (OBJ, MTL, PNG and JPEG maps): {:.2} % of pixels within \
         {TOLERANCE} levels of the native --model frame; {near} pixels differ from it by more \
         than 2 levels, {from_cylinder} from the cylinder's",
        share * 100.0
    );
    assert!(
        share >= WITHIN,
        "the dropped model: {share:.4} within {TOLERANCE}"
    );
    assert!(from_cylinder > near, "the page still shows the cylinder");
}

// Fails if the page fetches another scene's files at start (it must fetch only the cylinder's), if
// Enter does not fetch the next scene's files and then show it (the native sprite frame within the
// scenes' tolerance), or if anything goes to the page's message or the console's errors.
#[test]
fn enter_fetches_the_next_scenes_files_and_shows_it() {
    let Some(base) = page_url("web::enter_fetches_the_next_scenes_files_and_shows_it") else {
        return;
    };
    let page = load(
        "enter",
        &base,
        "scene=cylinder&panel=off&frames=40&key=Enter",
    );
    page.check_clean("Enter");
    let (cylinder, sprite) = (
        scenes::find("cylinder").unwrap(),
        scenes::find("sprite").unwrap(),
    );
    assert_eq!(
        page.fetched(),
        [fetched_line(cylinder), fetched_line(sprite)],
        "the files fetched"
    );
    let native = frame(&mut native_renderer("sprite"));
    let share = share_within(&page.shot, &native);
    eprintln!(
        "web: Enter from the cylinder: {:.2} % of pixels within {TOLERANCE} levels of the native \
         sprite frame",
        share * 100.0
    );
    assert!(
        share >= WITHIN,
        "after Enter: {share:.4} within {TOLERANCE}"
    );
}

// Fails if K pressed twice on the page (off → side by side → the difference) does not show the
// native heat map of the same two frames within the scenes' tolerance (the GPU passes' integer
// targets, the pixel-pack read of their numbers and its fence on WebGL2), or if the page shows a
// message or logs an error (a pass that WebGL2 refuses).
#[test]
fn k_twice_shows_the_native_heat_map() {
    let Some(base) = page_url("web::k_twice_shows_the_native_heat_map") else {
        return;
    };
    let page = load("heat", &base, "scene=cylinder&panel=off&frames=9&key=k,k");
    page.check_clean("the difference view");
    let mut renderer = native_renderer("cylinder");
    for _ in 0..2 {
        renderer.host.scene_key('K').expect("K");
    }
    let native = frame(&mut renderer);
    let lit = frame(&mut native_renderer("cylinder"));
    check_heat_map(&page, &native, &lit, "the difference view");
}

/// The page's frame must be the native heat map `heat` within the scenes' tolerance, and not the
/// lit frame `lit` (the view did not come on); the shares are printed under `what`.
fn check_heat_map(page: &Loaded, heat: &RgbImage, lit: &RgbImage, what: &str) {
    let (share, like_lit) = (
        share_within(&page.shot, heat),
        share_within(&page.shot, lit),
    );
    eprintln!(
        "web: {what}: {:.2} % of pixels within {TOLERANCE} levels of the native heat map ({:.2} % \
         of the lit frame)",
        share * 100.0,
        like_lit * 100.0
    );
    assert!(share >= WITHIN, "{share:.4} within {TOLERANCE}");
    assert!(like_lit < WITHIN, "the page shows the lit frame");
}

/// The page's bake ended with a map.
fn assert_bake_done(page: &Loaded) {
    assert_eq!(
        page.attribute("bake", "data-state").as_deref(),
        Some("done")
    );
}

/// `tutorial13 bake HIGH LOW -o native_normal.png --size 256` in `dir`, the map the page's bake
/// must equal; fails with its stderr if the command fails.
fn native_bake(dir: &Path, high: &str, low: &str) {
    native_bake_to(dir, high, low, "native_normal.png", &[]);
}

/// `tutorial13 bake HIGH LOW -o OUT --size 256 ARGS…` in `dir`.
fn native_bake_to(dir: &Path, high: &str, low: &str, out: &str, args: &[&str]) {
    let native = common::run(
        common::tutorial13()
            .args(["bake", high, low, "-o", out, "--size", "256"])
            .args(args)
            .current_dir(dir),
    );
    assert!(native.status.success(), "{}", common::text(&native.stderr));
}

/// A bake's pair as artists hand it over, written into `dir`: HIGH a sculpt exported without UVs
/// (`f v//vn`, as ZBrush and Blender's sculpt exports write it), a bumpy sphere of `segments` ×
/// `segments / 2`; LOW a 32 × 16 UV sphere with its MTL and a PNG diffuse map. The files of each,
/// model first.
fn bake_pair(dir: &Path, segments: u32) -> (Vec<&'static str>, Vec<&'static str>) {
    let relief = tutorial13::assets::obj_text::bumps(0.02, 6.0);
    let sculpt = common::without_uvs(&tutorial13::assets::obj_text::sphere_obj_text(
        segments,
        segments / 2,
        &relief,
        false,
    ));
    std::fs::write(dir.join("sculpt.obj"), sculpt).expect("sculpt.obj");
    let round = tutorial13::assets::obj_text::round;
    let low = tutorial13::assets::obj_text::sphere_obj_text(32, 16, &round, false);
    let low = format!("mtllib low.mtl\nusemtl skin\n{low}");
    std::fs::write(dir.join("low.obj"), low).expect("low.obj");
    let mtl = "newmtl skin\nKd 0.8 0.8 0.8\nmap_Kd low_diffuse.png\n";
    std::fs::write(dir.join("low.mtl"), mtl).expect("low.mtl");
    let diffuse = RgbImage::from_fn(64, 64, |x, y| {
        let tile = (x / 8 + y / 8) % 2 == 0;
        image::Rgb(if tile { [180, 120, 90] } else { [150, 100, 80] })
    });
    diffuse.save(dir.join("low_diffuse.png")).expect("the PNG");
    (
        vec!["sculpt.obj"],
        vec!["low.obj", "low.mtl", "low_diffuse.png"],
    )
}

/// The page's query that drops the files `high` and `low` (in drops/) on the bake's slots, sets the
/// bake's controls to `set` (`ID:V,…`) and bakes, with `more` (further `&` parameters).
fn bake_query(high: &[&str], low: &[&str], set: &str, more: &str) -> String {
    format!(
        "scene=cylinder&panel=off&frames=100000&bake-high={}&bake-low={}&bake-set={set}{more}",
        high.join(","),
        low.join(",")
    )
}

/// drops/ in the served folder, made if missing.
fn served_drops() -> std::path::PathBuf {
    let served =
        std::env::var("TUTORIAL13_WEB_DIR").expect("TUTORIAL13_WEB_DIR (web/test.sh sets it)");
    let drops = Path::new(&served).join("drops");
    std::fs::create_dir_all(&drops).expect("drops/ in the served folder");
    drops
}

/// The map the page baked, from its `#bake-map` (in hex, which the page's test script fills).
fn baked_map(page: &Loaded) -> Option<Vec<u8>> {
    let text = page.text("bake-map")?;
    let byte = |i: usize| u8::from_str_radix(&text[i..i + 2], 16).expect("#bake-map is hex");
    Some((0..text.len()).step_by(2).map(byte).collect())
}

/// The page's bake ended (with its map in `#bake-map` and `after` frames drawn since), or failed,
/// or the page shows a line (an error or a notice): the condition [`load_when`] waits for.
fn bake_settled(after: u32) -> String {
    format!(
        "(bake => bake.dataset.state == 'failed' \
         || document.getElementById('message').className != '' \
         || (bake.dataset.state == 'done' && document.getElementById('bake-map') \
             && Number(document.getElementById('canvas').dataset.frames) \
                >= Number(bake.dataset.framesDuring.split(' ')[1]) + {after}))\
         (document.getElementById('bake'))"
    )
}

/// [`bake_settled`] for a test that takes the frame the map is drawn in.
const BAKE_SETTLED_AFTER: u32 = 10;

// Fails if a sculpt without UVs and a LOW with its MTL and map, dropped on the page's bake slots
// and baked at 256² in the page's worker, do not give the very map `tutorial13 bake` writes at the
// same settings (decoded texel by texel: to the bit; the PNG bytes too, the same encoder), if the
// page drew no frame while the worker baked (`data-frames-during`: its frames at the start and at
// the end; a bake on the page's thread draws none), if the map is not drawn on LOW at once (the
// frame must be the native `--model low.obj --normal-map map --tangents mikktspace` frame within
// the scenes' tolerance, and nearer it than LOW without the map), or if the page shows a line or
// logs an error.
#[test]
fn the_page_bakes_the_native_map_and_draws_it_on_low() {
    let Some(base) = page_url("web::the_page_bakes_the_native_map_and_draws_it_on_low") else {
        return;
    };
    let drops = served_drops();
    let (high, low) = bake_pair(&drops, 192);
    native_bake(&drops, high[0], low[0]);
    let query = bake_query(&high, &low, "bake-size:256", "");
    let page = load_when("bake", &base, &query, &bake_settled(BAKE_SETTLED_AFTER));
    page.check_clean("the bake");
    assert_bake_done(&page);
    let map = baked_map(&page).expect("the page's map (#bake-map)");
    let native_bytes = std::fs::read(drops.join("native_normal.png")).expect("the native map");
    let (ours, theirs) = (
        image::load_from_memory(&map)
            .expect("the page's PNG")
            .into_rgb8(),
        image::open(drops.join("native_normal.png"))
            .unwrap()
            .into_rgb8(),
    );
    assert_eq!(ours.dimensions(), (256, 256));
    let d = frame_diff(&ours, &theirs);
    let during = page
        .attribute("bake", "data-frames-during")
        .unwrap_or_default();
    let frames: Vec<u32> = during.split(' ').filter_map(|f| f.parse().ok()).collect();
    eprintln!(
        "web: the page's bake (256², a 192 × 96 sculpt onto a 32 × 16 sphere): {} texels differ \
         from the native map (by {} levels at most); its PNG is {} the native file; the page drew \
         frames {during} while it baked",
        d.differing(),
        d.max(),
        if map == native_bytes {
            "byte for byte"
        } else {
            "not byte for byte"
        }
    );
    assert_eq!(d.differing(), 0, "the page's map is not the native one");
    assert_eq!(map, native_bytes, "the same texels, another PNG");
    assert!(
        matches!(frames[..], [start, end] if end > start),
        "no frame was drawn while the worker baked: {during}"
    );
    // The map on LOW, in the frame it was baked for.
    let with_map = common::headless_screenshot(
        &drops,
        "with_map.png",
        &[
            "--model",
            "low.obj",
            "--normal-map",
            "native_normal.png",
            "--tangents",
            "mikktspace",
        ],
    );
    let without = common::headless_screenshot(
        &drops,
        "without.png",
        &["--model", "low.obj", "--tangents", "mikktspace"],
    );
    let share = share_within(&page.shot, &with_map);
    let (near, flat) = (
        frame_diff(&page.shot, &with_map).over(2),
        frame_diff(&page.shot, &without).over(2),
    );
    eprintln!(
        "web: the baked map drawn on LOW: {:.2} % of pixels within {TOLERANCE} levels of the \
         native frame; {near} pixels differ from it by more than 2 levels, {flat} from LOW \
         without the map",
        share * 100.0
    );
    assert!(
        share >= WITHIN,
        "LOW with the map: {share:.4} within {TOLERANCE}"
    );
    assert!(
        flat > near,
        "the page's LOW is as near the frame without the map"
    );
}

// Fails if a bake with LOW's slot left empty, a file that is no model dropped on a slot, or a LOW
// without UVs does not put one line on the page (for the UV-less LOW, the native command's own
// line, LOW named as the page keeps it), if any of them gives a map, or logs an error.
#[test]
fn bad_bakes_give_one_line() {
    let Some(base) = page_url("web::bad_bakes_give_one_line") else {
        return;
    };
    let drops = served_drops();
    let (high, _) = bake_pair(&drops, 64);
    std::fs::write(drops.join("notes.txt"), "not a model\n").expect("notes.txt");
    let bare = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\n";
    std::fs::write(drops.join("bare.obj"), bare).expect("bare.obj");
    let native = common::run(
        common::tutorial13()
            .args(["bake", high[0], "bare.obj", "-o", "bare_normal.png"])
            .current_dir(&drops),
    );
    assert!(!native.status.success(), "a LOW without UVs baked natively");
    let native = common::text(&native.stderr);
    let native = native.trim().trim_start_matches("tutorial13: ");
    let cases = [
        (
            format!("bake-high={}", high[0]),
            "bake: drop LOW's files on their slots first (a bake needs both models)".to_string(),
        ),
        (
            "bake-high=notes.txt&bake-start=off".into(),
            "bake: notes.txt is no model (drop an .obj, .gltf or .glb model on HIGH, with its \
             .mtl and maps)"
                .into(),
        ),
        (
            format!("bake-high={}&bake-low=bare.obj", high[0]),
            native.replace("bare.obj", "low/bare.obj"),
        ),
    ];
    for (bake, line) in cases {
        let page = load_when(
            "bad-bake",
            &base,
            &format!("frames=100000&{bake}"),
            &bake_settled(BAKE_SETTLED_AFTER),
        );
        page.check_console(&bake);
        assert_eq!(page.text("message"), Some(line), "{bake}");
        assert!(page.text("bake-map").is_none(), "{bake}: a map came");
        assert_ne!(
            page.attribute("bake", "data-state").as_deref(),
            Some("done")
        );
    }
}

// Fails if Cancel, clicked as the rays start on a bake that takes the worker about a second (1024²),
// does not end it so that the next bake (256²) is the panel's: the states must go running,
// cancelled, running, done, and the map be the native 256² one (with Cancel only showing
// "cancelled", the first bake's 1024² map came); or if anything puts a line on the page or an
// error in the console.
#[test]
fn cancel_ends_the_bake() {
    let Some(base) = page_url("web::cancel_ends_the_bake") else {
        return;
    };
    let drops = served_drops();
    let (high, low) = bake_pair(&drops, 192);
    native_bake(&drops, high[0], low[0]);
    let query = bake_query(
        &high,
        &low,
        "bake-size:1024",
        "&bake-cancel&bake-again=bake-size:256",
    );
    let page = load_when("cancel", &base, &query, &bake_settled(BAKE_SETTLED_AFTER));
    page.check_clean("cancel");
    let map = baked_map(&page).expect("the second bake's map");
    let map = image::load_from_memory(&map)
        .expect("the page's PNG")
        .into_rgb8();
    eprintln!(
        "web: Cancel, then a bake again: the panel went {:?}; the map is {:?}",
        page.text("bake-states").unwrap_or_default(),
        map.dimensions()
    );
    assert_eq!(
        map.dimensions(),
        (256, 256),
        "the cancelled bake's map came"
    );
    assert_eq!(
        page.text("bake-states").as_deref(),
        Some("running cancelled running done")
    );
    let native = image::open(drops.join("native_normal.png"))
        .unwrap()
        .into_rgb8();
    assert_eq!(
        frame_diff(&map, &native).differing(),
        0,
        "not the native map"
    );
}

/// The page's budget for its module, gzipped (4 MB).
const WASM_BUDGET_GZIPPED: usize = 4_000_000;

// Fails if the page's module (the .wasm web/build.sh wrote, which the bake's worker loads too),
// compressed as a server sends it (`gzip -9`), is over 4 MB.
#[test]
fn the_pages_module_is_within_its_budget() {
    let Some(_) = page_url("web::the_pages_module_is_within_its_budget") else {
        return;
    };
    let served =
        std::env::var("TUTORIAL13_WEB_DIR").expect("TUTORIAL13_WEB_DIR (web/test.sh sets it)");
    let module = Path::new(&served).join("tutorial13_bg.wasm");
    let raw = std::fs::metadata(&module).expect("the page's module").len();
    let gzip = common::run(Command::new("gzip").arg("-9").arg("-c").arg(&module));
    assert!(gzip.status.success(), "gzip -9 runs");
    let gzipped = gzip.stdout.len();
    eprintln!("web: the page's module: {raw} bytes, gzip -9 {gzipped} bytes");
    assert!(
        gzipped <= WASM_BUDGET_GZIPPED,
        "{gzipped} bytes gzipped, over the budget of {WASM_BUDGET_GZIPPED}"
    );
}

// Fails if a pair of binary glTF files as an exporter writes them (HIGH a bumpy sphere without a UV
// layout, LOW a 32 × 16 UV sphere), baked in the page at 2 × 2 rays a texel, is not the map
// `tutorial13 bake` writes from the very same two files at the same settings, byte for byte (the
// page's glTF reader, its sample pattern and its encoder are the command's), or if the page shows a
// line or logs an error.
#[test]
fn the_page_bakes_a_gltf_pair_as_the_command_does() {
    let Some(base) = page_url("web::the_page_bakes_a_gltf_pair_as_the_command_does") else {
        return;
    };
    let drops = served_drops();
    let relief = tutorial13::assets::obj_text::bumps(0.02, 6.0);
    let high_obj = tutorial13::assets::obj_text::sphere_obj_text(96, 48, &relief, false);
    let round = tutorial13::assets::obj_text::round;
    let low_obj = tutorial13::assets::obj_text::sphere_obj_text(32, 16, &round, false);
    for (obj, glb, uvs) in [
        (&high_obj, "gltf_high.glb", false),
        (&low_obj, "gltf_low.glb", true),
    ] {
        let path = drops.join(glb).with_extension("obj");
        std::fs::write(&path, obj).expect("the OBJ to convert");
        let bytes = crate::bake::obj_as_glb(&path, uvs, None);
        std::fs::write(drops.join(glb), bytes).expect("the .glb");
    }
    let (high, low) = ("gltf_high.glb", "gltf_low.glb");
    native_bake_to(&drops, high, low, "native_gltf.png", &["--samples", "2"]);
    let query = bake_query(&[high], &[low], "bake-size:256,bake-samples:2", "");
    let page = load_when(
        "bake-gltf",
        &base,
        &query,
        &bake_settled(BAKE_SETTLED_AFTER),
    );
    page.check_clean("the glTF bake");
    assert_bake_done(&page);
    let map = baked_map(&page).expect("the page's map (#bake-map)");
    let native = std::fs::read(drops.join("native_gltf.png")).expect("the native map");
    let d = frame_diff(
        &image::load_from_memory(&map)
            .expect("the page's PNG")
            .into_rgb8(),
        &image::load_from_memory(&native).unwrap().into_rgb8(),
    );
    eprintln!(
        "web: the page's bake of a glTF pair (256², 2 × 2 rays): {} texels differ from the \
         command's map (by {} levels at most)",
        d.differing(),
        d.max()
    );
    assert!(
        d.differing() == 0 && map == native,
        "the page's map is not the command's"
    );
}

// Fails if F twice then K twice, pressed once the page has baked a map and drawn it on LOW, do not
// show the compare view's heat map of where the tutorial's frame reads that map otherwise than the
// MikkTSpace frame it was baked for, as the native program draws it with `--tangents tutorial
// --compare tutorial,mikktspace --compare-difference` (F steps MikkTSpace, the source a baked LOW is
// drawn with, to the per-pixel frame, then to the tutorial's; K compares the source drawn with the
// next F would pick), within the scenes' tolerance and not the lit frame; or if the page shows a
// line or logs an error.
#[test]
fn k_compares_on_the_baked_low() {
    let Some(base) = page_url("web::k_compares_on_the_baked_low") else {
        return;
    };
    let drops = served_drops();
    let (high, low) = bake_pair(&drops, 96);
    native_bake_to(&drops, high[0], low[0], "native_for_k.png", &[]);
    let query = bake_query(&high, &low, "bake-size:256", "&bake-keys=f,f,k,k");
    // The four keys are down and up again by the sixteenth frame after the bake.
    let page = load_when("bake-k", &base, &query, &bake_settled(24));
    page.check_clean("F and K after the bake");
    assert_bake_done(&page);
    let mut args = vec!["--model", "low.obj", "--normal-map", "native_for_k.png"];
    args.extend(["--tangents", "tutorial"]);
    let lit = common::headless_screenshot(&drops, "k_lit.png", &args);
    args.extend(["--compare", "tutorial,mikktspace", "--compare-difference"]);
    let heat = common::headless_screenshot(&drops, "k_heat.png", &args);
    check_heat_map(&page, &heat, &lit, "F, F, K, K on the baked LOW");
}

/// A native renderer at the tour's step `n` (from 1), as `--headless --tour N` puts it there.
fn native_at_step(n: usize) -> HeadlessRenderer {
    let step = &tutorial13::tour::STEPS[n - 1];
    let mut renderer = native_renderer(step.state.scene);
    renderer
        .host
        .set_step_state(step)
        .expect("the step's state");
    renderer
}

/// The native frame of the tour's step `n` (from 1) as `--headless --tour N` draws it, with the
/// panel and the pane where `panel`.
fn native_tour_frame(n: usize, panel: bool) -> RgbImage {
    let mut renderer = native_at_step(n);
    if panel {
        renderer.host.show_panel().expect("the panel");
    }
    frame(&mut renderer)
}

/// The native host's state line ([`tutorial13::frontends::host::SceneHost::state_line`]) at the
/// tour's step `n` (from 1).
fn native_step_state(n: usize) -> String {
    native_at_step(n).host.state_line()
}

/// Checks the states the page went through on the walk 1 → 18 → 10 (`data-states`, one line per
/// change): one step at a time, up to the last step and down to 10 (the sprite's step 18 may be
/// passed over: a PageUp pressed while its files come in steps on from 18 asked, as it should), and
/// each state the native host's at that step, switches, sliders, scene and camera.
fn check_walk_states(page: &Loaded) {
    let states = page
        .attribute("canvas", "data-states")
        .expect("data-states")
        .replace("&quot;", "\"")
        .replace("&amp;", "&");
    let states: Vec<&str> = states.lines().collect();
    let step_of = |line: &str| -> usize {
        let number = line.strip_prefix("step ").and_then(|l| l.split(' ').next());
        number
            .and_then(|n| n.parse().ok())
            .unwrap_or_else(|| panic!("a state outside the tour: {line}"))
    };
    let steps: Vec<usize> = states.iter().map(|l| step_of(l)).collect();
    let top = *steps.iter().max().unwrap_or(&0);
    let walked: Vec<usize> = (1..=top).chain((10..top).rev()).collect();
    assert!(
        steps == walked && top >= STEPS_BEFORE_THE_SPRITE,
        "the page's steps, one per change: {steps:?}"
    );
    let mut native = std::collections::HashMap::new();
    for (line, n) in states.iter().zip(&steps) {
        let expected = native.entry(*n).or_insert_with(|| native_step_state(*n));
        assert_eq!(
            line, expected,
            "the page's state at step {n} is not --tour {n}'s"
        );
    }
    eprintln!(
        "web: the walk went through {} states, each --tour N's (steps {steps:?})",
        states.len()
    );
}

/// The tour's steps on the cylinder, before its last, the sprite's.
const STEPS_BEFORE_THE_SPRITE: usize = 17;

// Fails if the page's `?tour=N` is not the native `--tour N` frame (the step's scene and state, the
// pane drawn by the panel), if PageDown and PageUp on the page do not step through the whole tour
// (its last step, the sprite, fetched on the way) and back to the state of the step they land on
// (step 10's switch, not the colour view an earlier step set), if any state the page passes through
// on the way is not its step's native state (switches, sliders, scene, camera), or if a bad
// `?tour=` is anything but the one line on the page naming it.
#[test]
fn the_tour_in_the_page_steps_forward_and_back() {
    let Some(base) = page_url("web::the_tour_in_the_page_steps_forward_and_back") else {
        return;
    };
    let page = load("tour", &base, "tour=4&frames=1");
    page.check_clean("tour=4");
    let share = share_within(&page.shot, &native_tour_frame(4, true));
    eprintln!("web: tour=4 with its pane: {:.2} % within", share * 100.0);
    assert!(share >= WITHIN, "tour=4: {share:.4} within {TOLERANCE}");

    // 1 → 18 and back to 10: 17 PageDowns, then 8 PageUps, four frames apart, then frames to spare.
    let keys: Vec<&str> = std::iter::repeat_n("PageDown", 17)
        .chain(std::iter::repeat_n("PageUp", 8))
        .collect();
    let query = format!(
        "tour=1&panel=off&frames={}&key={}",
        4 * keys.len() + 40,
        keys.join(",")
    );
    let page = load("tour-walk", &base, &query);
    page.check_clean("the walk");
    let sprite = scenes::find("sprite").unwrap();
    assert!(
        page.fetched().contains(&fetched_line(sprite)),
        "the last step's scene was not fetched: {:?}",
        page.fetched()
    );
    check_walk_states(&page);
    // A tour key shows the panel F1 (or `panel=off`) hid: the pane is the panel's.
    let share = share_within(&page.shot, &native_tour_frame(10, true));
    eprintln!(
        "web: the walk back to step 10: {:.2} % within",
        share * 100.0
    );
    assert!(share >= WITHIN, "the walk: {share:.4} within {TOLERANCE}");

    let page = load("tour-bad", &base, "tour=19&frames=1");
    let message = page.text("message").unwrap_or_default();
    assert_eq!(message.lines().count(), 1, "{message}");
    assert!(message.starts_with("tour=19: "), "{message}");
}
