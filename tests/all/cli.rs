//! The binary's command line, run as a user runs it: its flags and messages (`--help`, with
//! docs/scenes.md for what the help leaves out), exit status 0 on success, 1 with one line on stderr
//! for an error, 2 for a usage error (clap's, or a flag of another scene).
//!
//! Headless tests need Mesa's EGL + llvmpipe (libegl1, libegl-mesa0, libgl1-mesa-dri); the window test
//! needs Xvfb and xdotool (Debian packages xvfb, xdotool), which CI installs. Every test works in its
//! own folder (`common::scratch`).

use std::path::Path;
use std::process::Output;
use std::time::Instant;

use image::RgbImage;
use tutorial13::gl::context::HeadlessContext;
use tutorial13::gl::Profile;

use crate::common;
use crate::common::{frame_diff, run, text, tutorial13};

use crate::common::xvfb::Xvfb;

/// The background the tutorial clears to: glClearColor(0.0, 0.0, 0.4, 0.0).
const CLEAR_RGB: [u8; 3] = [0, 0, 102];

// ---------------------------------------------------------------------------------------------------
// Helpers

/// Fails with the exit status and both streams unless the run exited 0.
pub(crate) fn assert_success(out: &Output, what: &str) {
    assert!(
        out.status.success(),
        "{what}: expected exit 0, got {:?}\nstdout:\n{}\nstderr:\n{}",
        out.status,
        text(&out.stdout),
        text(&out.stderr)
    );
    assert!(
        !text(&out.stderr).contains("panicked"),
        "{what}: a panic on stderr:\n{}",
        text(&out.stderr)
    );
}

/// Fails unless the run exited non-zero without a panic. Returns its stderr.
fn assert_failure_without_panic(out: &Output, what: &str) -> String {
    let stderr = text(&out.stderr);
    assert!(
        !out.status.success(),
        "{what}: expected a failure, got exit 0; stderr:\n{stderr}"
    );
    assert!(
        !stderr.contains("panicked"),
        "{what}: a panic instead of an error line:\n{stderr}"
    );
    stderr
}

/// The failure contract: non-zero exit, stderr exactly one line "tutorial13: <reason>", no panic.
/// Returns that line.
pub(crate) fn assert_one_line_failure(out: &Output, what: &str) -> String {
    let stderr = assert_failure_without_panic(out, what);
    let lines: Vec<&str> = stderr.lines().collect();
    assert_eq!(
        lines.len(),
        1,
        "{what}: stderr must be exactly one line, got {}:\n{stderr}",
        lines.len()
    );
    let line = lines[0];
    // The reason is said once: an I/O error is not repeated as its own cause.
    assert!(
        !line.contains("(os error 2): No such file"),
        "{what}: the reason is repeated: {line:?}"
    );
    assert!(
        line.starts_with("tutorial13: "),
        "{what}: the line must start with 'tutorial13: ': {line:?}"
    );
    line.to_string()
}

/// Copies every file of `from` into a new folder `to` (flat: assets/ and shaders/ have no subfolders).
fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap_or_else(|e| panic!("read {}: {e}", from.display()))
    {
        let entry = entry.unwrap();
        if entry.file_type().unwrap().is_file() {
            std::fs::copy(entry.path(), to.join(entry.file_name())).unwrap();
        }
    }
}

fn read_png(path: &Path) -> RgbImage {
    assert!(path.is_file(), "{} was not written", path.display());
    image::open(path)
        .unwrap_or_else(|e| panic!("{} is not a readable PNG: {e}", path.display()))
        .to_rgb8()
}

/// Renders one headless frame of the project's assets and returns it.
fn headless_frame(scratch: &Path, name: &str, extra: &[&str]) -> RgbImage {
    let shot = scratch.join(name);
    let out = run(tutorial13()
        .args(["--headless", "--frames", "1", "--screenshot"])
        .arg(&shot)
        .args(extra));
    assert_success(&out, &format!("headless {extra:?}"));
    read_png(&shot)
}

/// Fraction of pixels that are not the clear colour: the cylinder is on screen.
fn drawn_fraction(img: &RgbImage) -> f64 {
    let drawn = img.pixels().filter(|p| p.0 != CLEAR_RGB).count();
    drawn as f64 / img.pixels().len() as f64
}

fn assert_looks_like_the_scene(img: &RgbImage, what: &str) {
    let (w, h) = img.dimensions();
    for (x, y) in [(0, 0), (w - 1, 0), (0, h - 1), (w - 1, h - 1)] {
        assert_eq!(
            img.get_pixel(x, y).0,
            CLEAR_RGB,
            "{what}: corner ({x},{y}) is not the clear colour"
        );
    }
    let drawn = drawn_fraction(img);
    assert!(
        drawn > 0.05,
        "{what}: only {:.2}% of the pixels are not background: no cylinder?",
        drawn * 100.0
    );
}

// ---------------------------------------------------------------------------------------------------
// 1. The default headless screenshot

// Fails if headless EGL rendering, the default 1024x768 size, the PNG writer or the clear colour breaks.
#[test]
fn headless_screenshot_is_1024x768_with_the_clear_colour_in_the_corner() {
    let scratch = common::scratch("headless_default");
    let img = headless_frame(&scratch, "x.png", &[]);
    assert_eq!(img.dimensions(), (1024, 768));
    assert_eq!(img.get_pixel(0, 0).0, CLEAR_RGB, "top-left pixel");
    assert_looks_like_the_scene(&img, "default headless frame");
}

// ---------------------------------------------------------------------------------------------------
// 2. --size

// Fails if --size is ignored by the headless target or the screenshot.
#[test]
fn size_sets_the_screenshot_dimensions() {
    let scratch = common::scratch("size");
    let img = headless_frame(&scratch, "small.png", &["--size", "320x240"]);
    assert_eq!(img.dimensions(), (320, 240));
    assert_looks_like_the_scene(&img, "320x240 frame");
}

// Fails if a bad --size is accepted, panics, or is reported without naming the option.
#[test]
fn bad_size_is_a_usage_error_not_a_panic() {
    let scratch = common::scratch("bad_size");
    for bad in ["0x5", "abc", "5x0", "16385x16", "12x"] {
        let shot = scratch.join("never.png");
        let out = run(tutorial13()
            .args(["--headless", "--frames", "1", "--size", bad, "--screenshot"])
            .arg(&shot));
        let stderr = assert_failure_without_panic(&out, &format!("--size {bad}"));
        assert!(
            stderr.contains("--size"),
            "--size {bad}: the error does not name the option:\n{stderr}"
        );
        assert!(
            !shot.exists(),
            "--size {bad}: a screenshot was written anyway"
        );
    }
}

// ---------------------------------------------------------------------------------------------------
// 3. Bad assets and shaders: one line naming the file, no screenshot

/// Runs one headless frame with `flag` (--assets or --shaders) naming the broken `folder`, with a
/// screenshot asked for in `scratch`, and checks the failure contract and that no screenshot was
/// written. Returns the error line.
fn assert_refuses_folder(scratch: &Path, flag: &str, folder: &Path, what: &str) -> String {
    let shot = scratch.join("never.png");
    let out = run(tutorial13()
        .args(["--headless", "--frames", "1", flag])
        .arg(folder)
        .arg("--screenshot")
        .arg(&shot));
    let line = assert_one_line_failure(&out, what);
    assert!(
        !shot.exists(),
        "{what}: a screenshot was written despite the failure"
    );
    line
}

/// Copies the project's assets, lets `spoil` break the copy, runs headless on it and checks the
/// failure contract. Returns the error line.
fn run_on_spoiled_assets(test: &str, file: &str, spoil: impl FnOnce(&Path)) -> String {
    let scratch = common::scratch(test);
    let assets = scratch.join("assets");
    copy_dir(&common::manifest().join("assets"), &assets);
    spoil(&assets.join(file));
    let line = assert_refuses_folder(&scratch, "--assets", &assets, test);
    assert!(
        line.contains(file),
        "{test}: the error does not name {file}: {line:?}"
    );
    eprintln!("{test}: {line}");
    line
}

// Fails if a truncated normal.bmp panics, prints more than one line, or does not say which file (a
// missing one is taken from the crate's assets: tests/all/asset_fallback.rs).
#[test]
fn truncated_normal_bmp_is_one_line_naming_it() {
    run_on_spoiled_assets("truncated_normal", "normal.bmp", |p| {
        let bytes = std::fs::read(p).unwrap();
        std::fs::write(p, &bytes[..bytes.len() / 2]).unwrap();
    });
}

// Fails if a truncated DDS is read past its end (panic), accepted, or reported without its name.
#[test]
fn truncated_diffuse_dds_is_one_line_naming_it() {
    run_on_spoiled_assets("truncated_dds", "diffuse.DDS", |p| {
        let bytes = std::fs::read(p).unwrap();
        assert!(bytes.len() > 200, "diffuse.DDS is already tiny");
        std::fs::write(p, &bytes[..200]).unwrap();
    });
}

// Fails if out-of-range or malformed OBJ faces panic (index out of bounds) or pass unnoticed.
#[test]
fn garbage_obj_faces_are_one_line_naming_the_file() {
    run_on_spoiled_assets("garbage_obj", "cylinder.obj", |p| {
        let garbage =
            "v 0 0 0\nvt 0 0\nvn 0 0 1\nf 1/1/1 2/2/2 banana\nf 7/7/7 8/8/8 9/9/9\nf -5/x/1\n";
        std::fs::write(p, garbage).unwrap();
    });
}

// Fails if a shader compile error panics, loses the driver's log, or does not name the shader file.
#[test]
fn vertex_shader_syntax_error_is_one_line_with_the_driver_log() {
    let scratch = common::scratch("bad_shader");
    let shaders = scratch.join("shaders");
    copy_dir(&common::manifest().join("shaders"), &shaders);
    let file = "NormalMapping.vertexshader";
    let path = shaders.join(file);
    let source = std::fs::read_to_string(&path).unwrap();
    let (version, rest) = source.split_once('\n').expect("a #version line");
    assert!(
        version.starts_with("#version"),
        "{file} does not start with #version"
    );
    std::fs::write(&path, format!("{version}\nthis is not GLSL (;\n{rest}")).unwrap();

    let line = assert_refuses_folder(&scratch, "--shaders", &shaders, "broken vertex shader");
    eprintln!("bad_shader: {line}");
    let (_, after_name) = line
        .split_once(file)
        .unwrap_or_else(|| panic!("the error does not name {file}: {line:?}"));
    assert!(
        after_name.to_lowercase().contains("error"),
        "the driver's compile log is missing after the file name: {line:?}"
    );
}

// ---------------------------------------------------------------------------------------------------
// 4. --help

// Fails if --help stops exiting 0, drops any flag of the contract (every scene's flags included), or
// opens with another line than the program's own (a doc comment on a flattened Args struct once took
// its place).
#[test]
fn help_lists_every_flag() {
    let help = help_text(&["--help"], None);
    assert!(
        help.starts_with("opengl-tutorial.org's Tutorial 13 (Normal Mapping), ported to Rust\n"),
        "--help opens with {:?}",
        help.lines().next()
    );
    for needle in ["make-assets", "normalmap", "photometric", "docs/keys.md"] {
        assert!(
            help.contains(needle),
            "--help does not mention {needle:?}:\n{help}"
        );
    }
    for flag in [
        "--assets",
        "--shaders",
        "--headless",
        "--frames",
        "--screenshot",
        "--size",
        "--profile",
        "--debug-lines",
        "--bench",
        "--prefer-hardware",
    ] {
        assert!(help.contains(flag), "--help does not list {flag}:\n{help}");
    }
    assert!(
        help.contains("core") && help.contains("compat"),
        "--help does not list the profiles:\n{help}"
    );
}

/// `tutorial13 ARGS` (which asks for help) with stdout a pipe and `COLUMNS` set to `columns` (or
/// unset): its stdout, after checking it exited 0.
fn help_text(args: &[&str], columns: Option<usize>) -> String {
    let mut command = tutorial13();
    command.args(args).env_remove("COLUMNS");
    if let Some(columns) = columns {
        command.env("COLUMNS", columns.to_string());
    }
    let out = run(&mut command);
    assert_success(&out, &format!("{args:?} at COLUMNS={columns:?}"));
    text(&out.stdout)
}

/// `text` with every run of white space one space: a row wrapped onto two lines reads as one.
fn words(text: &str) -> String {
    text.split_whitespace().collect::<Vec<_>>().join(" ")
}

// Fails if --help is no longer wrapped to the width it is given when stdout is not a terminal
// (COLUMNS, else 100; wider terminals get 100), the closing lists included, or if it grows past a few
// screens (241 lines up to 520 columns before it wrapped and left the scenes' key tables out).
#[test]
fn help_fits_the_width_it_is_given() {
    // (--help, -h, --scene sprite --help): 215, 130 and 116 lines at 100 columns, 238, 161 and 126
    // at 80 (143 for the sprite with the tour's PageDown, PageUp and F2); each scene's key table would
    // add 12 to 20.
    for (columns, width, most_lines) in [
        (None, 100, [235, 150, 130]),
        (Some(80), 80, [260, 180, 143]),
        (Some(100), 100, [235, 150, 130]),
        (Some(200), 100, [235, 150, 130]),
    ] {
        let asks = [&["--help"][..], &["-h"], &["--scene", "sprite", "--help"]];
        for (args, most_lines) in asks.into_iter().zip(most_lines) {
            let help = help_text(args, columns);
            let lines = help.lines().count();
            println!("{args:?} at COLUMNS={columns:?}: {lines} lines");
            for line in help.lines() {
                assert!(
                    line.chars().count() <= width,
                    "{args:?} at COLUMNS={columns:?}: a line of {} columns, over {width}:\n{line}",
                    line.chars().count()
                );
            }
            assert!(
                lines <= most_lines,
                "{args:?} at COLUMNS={columns:?}: {lines} lines, over {most_lines}"
            );
        }
    }
}

// Fails if `--scene NAME --help` does not end with that scene's keys as the window prints them
// (tutorial13::frontends::keys::key_list), shows another scene's keys or flags, or drops a flag the scene
// reads; or if the window's own keys (the arrow keys, Esc) are no longer listed there.
#[test]
fn scene_help_lists_that_scenes_keys_and_flags_only() {
    use tutorial13::frontends::keys::key_list;
    use tutorial13::scenes::{cylinder::Cylinder, descriptor, sprite::Sprite};
    let help = help_text(&["--scene", "sprite", "--help"], None);
    let (help_words, sprite_keys) = (words(&help), key_list(descriptor::<Sprite>()));
    for row in sprite_keys.lines() {
        assert!(
            help_words.contains(&words(row)),
            "--scene sprite --help lacks the key row {row:?}:\n{help}"
        );
    }
    for row in key_list(descriptor::<Cylinder>()).lines() {
        if !sprite_keys.contains(row) {
            assert!(
                !help_words.contains(&words(row)),
                "--scene sprite --help shows the cylinder's key row {row:?}:\n{help}"
            );
        }
    }
    for flag in ["--green", "--light", "--headless", "--scene"] {
        assert!(help.contains(flag), "--scene sprite --help lacks {flag}");
    }
    for flag in ["--debug-lines", "--space", "Scene cylinder"] {
        assert!(!help.contains(flag), "--scene sprite --help shows {flag}");
    }
    let cylinder = words(&help_text(&["--help", "--scene=cylinder"], None));
    for needle in ["arrow keys", "Esc", "--debug-lines"] {
        assert!(
            cylinder.contains(needle),
            "--scene cylinder --help does not mention {needle:?}:\n{cylinder}"
        );
    }
    // Plain --help keeps no scene's key table.
    let plain = words(&help_text(&["--help"], None));
    assert!(!plain.contains("Keys (window"), "{plain}");
}

// Fails if a flag of another scene is ignored again (exit 0 and a frame drawn without it), if the
// error does not name the scene the flag belongs to, or if anything is written: the cases a new user
// hit, run as the binary.
#[test]
fn a_flag_of_another_scene_stops_the_program_before_rendering() {
    let scratch = common::scratch("other_scene_flag");
    let shot = scratch.join("frame.png");
    for (args, flag, owner) in [
        (
            &["--scene", "sprite", "--light-power", "2"][..],
            "--light-power",
            "scenes cylinder, cube and wall",
        ),
        (
            &["--scene", "wall", "--model", "a.obj"][..],
            "--model",
            "scene cylinder",
        ),
        (&["--space", "tangent"][..], "--space", "scene wall"),
        (
            &["--scene", "wall", "--view", "normal"][..],
            "--view",
            "scene cylinder",
        ),
        (
            &["--scene", "sprite", "--debug-lines"][..],
            "--debug-lines",
            "scene cylinder",
        ),
        (
            &["--scene", "cube", "--green", "down"][..],
            "--green",
            "scenes cylinder and sprite",
        ),
    ] {
        let out = run(tutorial13()
            .args(args)
            .args(["--headless", "--screenshot"])
            .arg(&shot));
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let err = text(&out.stderr);
        assert!(
            err.contains(&format!("{flag} is an option of {owner}, not of scene")),
            "{args:?}: {err}"
        );
        assert!(!shot.exists(), "{args:?}: a frame was written");
    }
}

// ---------------------------------------------------------------------------------------------------
// 5. No display

// Fails if the window path without a display panics, hangs, or does not point the user to --headless.
#[test]
fn no_display_fails_pointing_to_headless() {
    let scratch = common::scratch("no_display");
    let shot = scratch.join("never.png");
    let out = run(tutorial13()
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .args(["--frames", "1", "--screenshot"])
        .arg(&shot));
    let line = assert_one_line_failure(&out, "window without a display");
    assert!(
        line.contains("--headless"),
        "the error does not mention --headless: {line:?}"
    );
    assert!(!shot.exists(), "a screenshot was written without a display");
}

// ---------------------------------------------------------------------------------------------------
// 6. The real window under Xvfb

// Fails if the winit/glutin window cannot open on X11, --frames/--screenshot do not work in the window,
// or the window's frame is not the headless one, pixel for pixel (on the reference Mesa, see below).
#[test]
fn window_under_xvfb_matches_headless() {
    window_matches_headless(&[], "xvfb");
}

// Fails if the window's compatibility-profile context (GLX or EGL on X11) cannot draw the tutorial's
// immediate-mode debug lines, or draws them differently from the headless context.
#[test]
fn window_compat_profile_with_debug_lines_matches_headless() {
    let window = window_matches_headless(&["--profile", "compat", "--debug-lines"], "xvfb-compat");
    // The bitangents hang below the bottom rim as pure green lines.
    let green = window.pixels().filter(|p| p.0 == [0, 255, 0]).count();
    assert!(
        green > 100,
        "{green} green pixels: no debug lines in the window"
    );
}

// Fails if --msaa 4 does not make the window and the headless target multisampled (each must blend
// the debug lines' edges: far fewer pure-green pixels than without), or if the window's screenshot is
// not the headless frame bit for bit (on the reference renderer). The window's frame is resolved before
// it is read: read directly, Mesa gave 2006 pixels that the window does not show (xwd capture).
#[test]
fn msaa_window_matches_headless_and_blends_the_lines() {
    let lines = ["--profile", "compat", "--debug-lines"];
    let msaa = [&lines[..], &["--msaa", "4"]].concat();
    // A display may offer no multisampled config at all (Mesa 25.0.7 from bookworm-backports under
    // Xvfb offers [0]): the window then says so and exits 1, which is its contract, not a failure
    // of this test (the reference renderer, which CI requires, offers 4).
    let xvfb = Xvfb::start();
    let probe = run(tutorial13()
        .env("DISPLAY", &xvfb.display)
        .env_remove("WAYLAND_DISPLAY")
        .args(&msaa)
        .args(["--frames", "1"]));
    drop(xvfb);
    let stderr = text(&probe.stderr);
    if let Some(line) = stderr
        .lines()
        .find(|l| l.contains("no framebuffer configuration with 4 samples"))
    {
        let test = "msaa_window_matches_headless_and_blends_the_lines";
        return common::skip_off_reference(test, line);
    }
    let window = window_matches_headless(&msaa, "xvfb-msaa");
    let plain = headless_frame(&common::scratch("msaa"), "plain.png", &lines);
    let green = |img: &RgbImage| img.pixels().filter(|p| p.0 == [0, 255, 0]).count();
    let (g_plain, g_msaa) = (green(&plain), green(&window));
    let d = frame_diff(&window, &plain);
    println!(
        "--msaa 4 against none: {} pixels differ; pure-green line pixels {g_plain} -> {g_msaa}",
        d.differing()
    );
    assert!(d.differing() > 1000, "{} pixels differ", d.differing());
    assert!(
        g_msaa * 2 < g_plain,
        "{g_msaa} of {g_plain}: the lines are not blended"
    );
}

// Fails if a sample count the driver does not have is accepted (or panics) instead of one line
// naming --msaa, or if an out-of-range value is not a usage error.
#[test]
fn msaa_beyond_the_driver_is_one_line() {
    let scratch = common::scratch("msaa-too-many");
    let shot = scratch.join("never.png");
    let out = run(tutorial13()
        .args(["--headless", "--msaa", "32", "--screenshot"])
        .arg(&shot));
    let line = assert_one_line_failure(&out, "--msaa 32");
    assert!(line.contains("32 samples"), "{line}");
    assert!(!shot.exists());
    let out = run(tutorial13().args(["--headless", "--msaa", "33"]));
    assert_eq!(out.status.code(), Some(2), "usage error expected");
}

// Fails if `--bench-panel K` does not time K frames in each state in a real window and print both
// figures and their ratio, or if `--headless` with it is not refused (it measures the window;
// headless has --bench).
#[test]
fn bench_panel_times_the_window_with_and_without_the_panel() {
    let xvfb = Xvfb::start();
    let out = run(tutorial13()
        .env("DISPLAY", &xvfb.display)
        .env_remove("WAYLAND_DISPLAY")
        .args(["--bench-panel", "6"]));
    drop(xvfb);
    assert_success(&out, "--bench-panel 6 under Xvfb");
    let stdout = text(&out.stdout);
    let line = stdout
        .lines()
        .find(|l| l.starts_with("6 frames each"))
        .unwrap_or_else(|| panic!("no result line in {stdout}"));
    let ratio: f64 = line
        .rsplit_once("shown/hidden ")
        .and_then(|(_, r)| r.split(' ').next()?.parse().ok())
        .unwrap_or_else(|| panic!("no ratio in {line}"));
    assert!(ratio.is_finite() && ratio > 0.0, "{line}");
    let out = run(tutorial13().args(["--bench-panel", "5", "--headless"]));
    assert_eq!(out.status.code(), Some(2), "usage error expected");
}

/// 3 frames in a real window under a private Xvfb with `extra` flags: the last frame (checked to
/// look like the scene) and the program's stderr.
fn window_frame(scratch: &Path, extra: &[&str]) -> (RgbImage, Vec<u8>) {
    let xvfb = Xvfb::start();
    let window_shot = scratch.join("w.png");
    let out = run(tutorial13()
        .env("DISPLAY", &xvfb.display)
        .env_remove("WAYLAND_DISPLAY")
        .args(extra)
        .args(["--frames", "3", "--screenshot"])
        .arg(&window_shot));
    drop(xvfb);
    assert_success(&out, "window under Xvfb");
    let window = read_png(&window_shot);
    assert_eq!(window.dimensions(), (1024, 768), "window screenshot size");
    assert_looks_like_the_scene(&window, "window frame");
    (window, out.stderr)
}

/// Renders 3 frames in a real window under Xvfb and headless with the same `extra` flags, compares
/// the two screenshots, and returns the window's.
fn window_matches_headless(extra: &[&str], name: &str) -> RgbImage {
    let scratch = common::scratch(name);
    let started = Instant::now();
    let (window, out_window_stderr) = window_frame(&scratch, extra);
    let window_time = started.elapsed();

    let headless_shot = scratch.join("h.png");
    let out = run(tutorial13()
        .args(extra)
        .args(["--headless", "--frames", "3", "--screenshot"])
        .arg(&headless_shot));
    assert_success(&out, "headless, 3 frames");
    let headless = read_png(&headless_shot);

    // Mesa keeps window buffers top row first and llvmpipe rasterizes them y-flipped; the headless
    // target is stored the same way (GL_MESA_framebuffer_flip_y), so on the renderer this was measured
    // on the two frames are the same frame, pixel for pixel, debug lines included.
    let d = frame_diff(&window, &headless);
    eprintln!(
        "window vs headless: max channel difference {}, {} of {} pixels differ, {} by more than 2, \
         all within {:?} (window run {window_time:?})",
        d.max(), d.differing(), d.pixels(), d.over(2), d.bbox
    );
    let window_log = text(&out_window_stderr);
    let not_reference = reference_renderer_skip_reason(extra).or_else(|| {
        (!window_log.contains(common::REFERENCE_RENDERER)).then(|| {
            format!(
                "the window's context is not on {}...): {window_log:?}",
                common::REFERENCE_RENDERER
            )
        })
    });
    match not_reference {
        None => assert_eq!(
            d.differing(),
            0,
            "window and headless frames differ in {} of {} pixels (max {}, all within {:?})",
            d.differing(),
            d.pixels(),
            d.max(),
            d.bbox
        ),
        Some(reason) => {
            // Elsewhere only a coarse check: a wrong texture, camera or size fails by far.
            common::skip_off_reference(
                &format!("window vs headless bit for bit ({name})"),
                &reason,
            );
            assert!(
                d.over(2) as f64 <= d.pixels() as f64 * 0.001,
                "window and headless frames differ: {} of {} pixels by more than 2 (max {})",
                d.over(2),
                d.pixels(),
                d.max()
            );
        }
    }
    window
}

/// `None` when the headless context for `extra`'s profile is the renderer the bit-for-bit comparisons
/// were measured on; otherwise why they are skipped.
fn reference_renderer_skip_reason(extra: &[&str]) -> Option<String> {
    let profile = if extra.contains(&"compat") {
        Profile::Compat
    } else {
        Profile::Core
    };
    match HeadlessContext::new(profile, false) {
        Ok(context) => common::not_reference_renderer(context.info()),
        Err(e) => Some(format!("no headless {profile} context to ask: {e}")),
    }
}

// ---------------------------------------------------------------------------------------------------
// 7. --bench

/// The number right after the word `word` in `line` ("min 1.234 ms/frame" → 1.234).
fn number_after(line: &str, word: &str) -> f64 {
    let mut tokens = line.split_whitespace();
    tokens
        .find(|t| t.trim_matches(|c: char| !c.is_alphanumeric()) == word)
        .and_then(|_| tokens.next())
        .and_then(|t| {
            t.trim_matches(|c: char| !c.is_ascii_digit() && c != '.')
                .parse()
                .ok()
        })
        .unwrap_or_else(|| panic!("no number after {word:?} in {line:?}"))
}

// Fails if --bench does not run headless, or its last stdout line lacks min/median ms/frame figures.
#[test]
fn bench_prints_min_and_median() {
    let out = run(tutorial13().args(["--bench", "5", "--size", "256x192"]));
    assert_success(&out, "--bench 5");
    let stdout = text(&out.stdout);
    let last = stdout
        .lines()
        .last()
        .unwrap_or_else(|| panic!("--bench printed nothing"));
    eprintln!("bench: {last}");
    for word in ["min", "median", "ms/frame"] {
        assert!(
            last.contains(word),
            "the last line does not contain {word:?}: {last:?}"
        );
    }
    let (min, median) = (number_after(last, "min"), number_after(last, "median"));
    assert!(
        min > 0.0 && min <= median,
        "min {min} and median {median} out of order in {last:?}"
    );
}

// ---------------------------------------------------------------------------------------------------
// 8. --profile compat

// Fails if a compatibility-profile context cannot be made or draws the frame differently from core.
#[test]
fn compat_profile_draws_the_same_frame_as_core() {
    let scratch = common::scratch("compat");
    let core = headless_frame(&scratch, "core.png", &["--profile", "core"]);
    let compat = headless_frame(&scratch, "c.png", &["--profile", "compat"]);
    assert_eq!(compat.dimensions(), (1024, 768));
    let d = frame_diff(&core, &compat);
    eprintln!(
        "core vs compat: max difference {}, {} pixels differ",
        d.max(),
        d.differing()
    );
    // Same driver, same shaders, same state: the frames must be identical.
    assert_eq!(
        d.differing(),
        0,
        "compat differs from core in {} pixels (max {})",
        d.differing(),
        d.max()
    );
}

// ---------------------------------------------------------------------------------------------------
// 9. make-assets

// Fails if make-assets is not deterministic or the committed assets/ are stale relative to the generator.
#[test]
fn make_assets_reproduces_the_committed_assets() {
    let scratch = common::scratch("make_assets");
    let out_dir = scratch.join("generated");
    let started = Instant::now();
    let out = run(tutorial13().arg("make-assets").arg("--out").arg(&out_dir));
    eprintln!("make-assets took {:?}", started.elapsed());
    assert_success(&out, "make-assets");
    let files = tutorial13::scenes::generate_assets().unwrap();
    for file in files.iter().map(|(name, _)| *name) {
        let generated = std::fs::read(out_dir.join(file))
            .unwrap_or_else(|e| panic!("{file} not generated: {e}"));
        let committed = std::fs::read(common::manifest().join("assets").join(file)).unwrap();
        assert!(
            generated == committed,
            "{file}: generated ({} bytes) differs from assets/{file} ({} bytes)",
            generated.len(),
            committed.len()
        );
    }
}

// Fails if a cylinder flag whose switch the library tests is not wired to it: the binary's headless
// frame with the flag must equal bit for bit the frame of the same controls started in the library
// through their typed handles (and differ from the plain frame, so that the flag is seen doing
// something).
#[test]
fn each_cylinder_flag_draws_the_frame_of_its_option() {
    use glam::Vec3;
    use tutorial13::debug::compare::CompareMode;
    use tutorial13::scenes::cylinder::{self, Comparing, Cylinder};
    use tutorial13::scenes::Setting;
    use tutorial13::tangent_source::TangentSource;
    let dir = common::scratch("cylinder_flags");
    let pair = [TangentSource::Tutorial, TangentSource::MikkTSpace];
    let compare = |mode| cylinder::COMPARE.to(Comparing::pair(pair, mode));
    // Each flag, and the starts of the typed handles that must give its frame.
    let cases: [(&[&str], Vec<Setting<Cylinder>>); 17] = [
        (
            &["--no-gram-schmidt"],
            vec![cylinder::GRAM_SCHMIDT.to(false)],
        ),
        (&["--no-handedness"], vec![cylinder::HANDEDNESS.to(false)]),
        (
            &["--normalize-before-sum"],
            vec![cylinder::NORMALIZE_BEFORE_SUM.to(true)],
        ),
        (
            &["--no-specular-texture"],
            vec![cylinder::SPECULAR_TEXTURE.to(false)],
        ),
        (&["--normalize-tbn"], vec![cylinder::NORMALIZE_TBN.to(true)]),
        (
            &["--exact-expansion"],
            vec![cylinder::EXACT_EXPANSION.to(true)],
        ),
        (&["--two-channel"], vec![cylinder::TWO_CHANNEL.to(true)]),
        (&["--green", "down"], vec![cylinder::GREEN_DOWN.to(true)]),
        (
            &["--view", "normal01.y"],
            cylinder::view("normal01.y".parse().unwrap()).to_vec(),
        ),
        (
            &["--tangents", "mikktspace"],
            vec![cylinder::TANGENTS.to(TangentSource::MikkTSpace)],
        ),
        (&["--debug-lines"], vec![cylinder::LINES.to(true)]),
        (
            &["--compare", "tutorial,mikktspace", "--split", "0.3"],
            vec![compare(CompareMode::Split), cylinder::SPLIT.to(0.3)],
        ),
        (
            &["--compare", "tutorial,mikktspace", "--compare-difference"],
            vec![compare(CompareMode::Difference)],
        ),
        (
            &["--normal-strength", "2.5"],
            vec![cylinder::NORMAL_STRENGTH.to(2.5)],
        ),
        (
            &["--debug-lines", "--line-length", "0.25"],
            vec![cylinder::LINES.to(true), cylinder::TBN_LINE_LENGTH.to(0.25)],
        ),
        (
            &["--light", "1,2,3"],
            cylinder::light_at(Vec3::new(1.0, 2.0, 3.0)).to_vec(),
        ),
        (
            &["--light-power", "80"],
            vec![cylinder::LIGHT_POWER.to(80.0)],
        ),
    ];
    let plain = common::headless_screenshot(&dir, "plain.png", &[]);
    for (n, (args, settings)) in cases.into_iter().enumerate() {
        let flagged = common::headless_screenshot(&dir, &format!("{n}.png"), args);
        let mut options = tutorial13::frontends::headless::HeadlessOptions::default();
        options.scene = options.scene.starting(settings);
        let mut renderer = common::renderer(&options);
        let library = common::frame(&mut renderer);
        drop(renderer);
        assert!(flagged != plain, "{args:?} changed nothing");
        let (differing, max, _) = common::pixel_diff(&flagged, &library);
        assert_eq!(
            differing, 0,
            "{args:?}: differs from its option by up to {max}"
        );
    }
}
