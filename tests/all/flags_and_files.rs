//! Flags that must be refused, files that must not be lost or written half-way, and the projection
//! that follows the viewport: nothing lost, nothing silently wrong. Runs the binary as a user does;
//! the headless runs need Mesa's EGL + llvmpipe.

use std::path::Path;
use std::process::Output;

use tutorial13::assets::make_assets;
use tutorial13::scenes::generate_assets;
use tutorial13::Error;

use crate::common;

/// The binary run with `args` in `dir`.
fn tutorial13(args: &[&str], dir: &Path) -> Output {
    common::run(common::tutorial13().args(args).current_dir(dir))
}

fn stderr(out: &Output) -> String {
    common::text(&out.stderr)
}

/// The error line the binary prints on failure (clap's or ours), with any log lines left out.
fn error_line(out: &Output) -> String {
    let text = stderr(out);
    let errors: Vec<&str> = text
        .lines()
        .filter(|l| l.starts_with("error:") || l.starts_with("tutorial13:"))
        .collect();
    assert_eq!(errors.len(), 1, "one error line expected:\n{text}");
    errors[0].to_string()
}

/// The refusal contract: exit 1 and one error line holding each of `needles`. Returns that line.
fn assert_refused(out: &Output, needles: &[&str]) -> String {
    assert_eq!(out.status.code(), Some(1), "{}", stderr(out));
    let line = error_line(out);
    for needle in needles {
        assert!(line.contains(needle), "{line}");
    }
    line
}

// Fails if --frames 0 or --bench 0 is accepted (they used to run and print nonsense figures), or if
// the refusal does not name the flag.
#[test]
fn zero_frames_and_zero_bench_are_refused() {
    let dir = common::scratch("zero");
    for (args, flag) in [
        (&["--headless", "--frames", "0"][..], "--frames"),
        (&["--bench", "0"][..], "--bench"),
    ] {
        let out = tutorial13(args, &dir);
        assert!(!out.status.success(), "{args:?} was accepted");
        assert!(error_line(&out).contains(flag), "{}", stderr(&out));
    }
}

// Fails if a screenshot into a folder that does not exist is found out only after rendering (the
// context is made and the frame drawn first, so the log says "OpenGL"), if the error does not name
// the folder, or if the folder is created behind the user's back.
#[test]
fn a_screenshot_into_a_missing_folder_is_refused_before_rendering() {
    let dir = common::scratch("screenshot-folder");
    let out = tutorial13(&["--headless", "--screenshot", "shots/frame.png"], &dir);
    assert_refused(
        &out,
        &["--screenshot shots/frame.png: no such folder shots"],
    );
    assert!(
        !stderr(&out).contains("OpenGL"),
        "rendered first: {}",
        stderr(&out)
    );
    assert!(!dir.join("shots").exists());
}

// Fails if a mistyped --shaders or --assets folder is ignored or reported without its name.
#[test]
fn missing_folders_are_refused_by_name() {
    let dir = common::scratch("folders");
    std::fs::write(dir.join("a-file"), "x").unwrap();
    for (args, expected) in [
        (
            &["--headless", "--shaders", "no-such-dir"][..],
            "--shaders no-such-dir: no such folder",
        ),
        (
            &["--headless", "--assets", "a-file"][..],
            "--assets a-file: not a folder",
        ),
    ] {
        assert_refused(&tutorial13(args, &dir), &[expected]);
    }
}

// Fails if a screenshot's bytes are not the format its extension names (PNG, BMP, TGA decode to the
// same pixels), or if .jpg is accepted, written, or refused only after rendering.
#[test]
fn screenshots_are_written_in_the_format_their_extension_names() {
    let dir = common::scratch("screenshots");
    let mut frames = Vec::new();
    for name in ["frame.png", "frame.bmp", "frame.TGA"] {
        let out = tutorial13(
            &["--headless", "--size", "64x48", "--screenshot", name],
            &dir,
        );
        assert!(out.status.success(), "{name}: {}", stderr(&out));
        let format = image::ImageFormat::from_path(name).unwrap();
        let bytes = std::fs::read(dir.join(name)).unwrap();
        assert_eq!(
            image::guess_format(&bytes).ok().or(Some(format)),
            Some(format)
        );
        let decoded = image::load_from_memory_with_format(&bytes, format)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        frames.push(decoded.into_rgb8());
    }
    assert!(
        frames.windows(2).all(|w| w[0] == w[1]),
        "formats differ in pixels"
    );
    let out = tutorial13(&["--headless", "--screenshot", "frame.jpg"], &dir);
    assert_refused(&out, &["frame.jpg", ".png"]);
    assert!(
        !stderr(&out).contains("OpenGL"),
        "refused only after a context was made"
    );
    let left: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .flatten()
        .map(|e| e.file_name())
        .collect();
    assert_eq!(
        left.len(),
        3,
        "a .jpg (or a temporary file) was left: {left:?}"
    );
}

// Fails if make-assets replaces a file that differs (the learner's copy of the tutorial's own file)
// without --force, writes any file when it refuses, or does not replace with --force.
#[test]
fn make_assets_keeps_files_that_differ_unless_forced() {
    let dir = common::scratch("make-assets");
    let theirs = b"the learner's own normal map".to_vec();
    std::fs::write(dir.join("normal.bmp"), &theirs).unwrap();
    let files = generate_assets().unwrap();
    match make_assets(&dir, &files, false) {
        Err(Error::WouldOverwrite { paths }) => assert_eq!(paths, [dir.join("normal.bmp")]),
        other => panic!("expected a refusal, got {other:?}"),
    }
    assert_eq!(std::fs::read(dir.join("normal.bmp")).unwrap(), theirs);
    assert_eq!(
        std::fs::read_dir(&dir).unwrap().count(),
        1,
        "files written on refusal"
    );

    // The binary: one line naming the file, exit 1.
    assert_refused(
        &tutorial13(&["make-assets", "--out", "."], &dir),
        &["normal.bmp", "--force"],
    );

    let all: Vec<&str> = files.iter().map(|(name, _)| *name).collect();
    let written = make_assets(&dir, &files, true).unwrap();
    assert_eq!(written.replaced, [dir.join("normal.bmp")]);
    assert_eq!(written.created.len(), all.len() - 1);
    let again = make_assets(&dir, &files, false).unwrap();
    assert_eq!(again.unchanged.len(), all.len(), "{again:?}");
    let committed = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets");
    for name in &all {
        let ours = std::fs::read(dir.join(name)).unwrap();
        assert!(
            ours == std::fs::read(committed.join(name)).unwrap(),
            "{name} differs"
        );
    }
    let names = common::files_under(&dir);
    assert_eq!(names.len(), all.len(), "temporary files left: {names:?}");
}

// Fails if the key list is printed before a window failure (the error would follow a screen of
// help), or if the error shows winit's source path.
#[test]
fn a_window_failure_prints_its_error_alone() {
    let dir = common::scratch("no-display");
    let out = common::run(
        common::tutorial13()
            .args(["--frames", "1"])
            .current_dir(&dir)
            .env("DISPLAY", ":97")
            .env_remove("WAYLAND_DISPLAY"),
    );
    assert!(out.stdout.is_empty(), "{}", common::text(&out.stdout));
    let line = assert_refused(&out, &["no display", "--headless"]);
    assert!(!line.contains(".rs:"), "{line}");
}

/// The bounding box (x0, y0, x1, y1) of the pixels that are not the clear colour.
fn drawn_box(frame: &image::RgbImage) -> (u32, u32, u32, u32) {
    let mut b = (u32::MAX, u32::MAX, 0, 0);
    for (x, y, p) in frame.enumerate_pixels() {
        if p.0 != [0, 0, 102] {
            b = (b.0.min(x), b.1.min(y), b.2.max(x), b.3.max(y));
        }
    }
    b
}

// Fails if the projection keeps 4:3 on a wider viewport (the cylinder is then stretched 1.5× wide),
// i.e. if the cylinder's size in pixels changes with the viewport's width.
#[test]
fn a_wider_viewport_shows_more_without_stretching() {
    let dir = common::scratch("aspect");
    let mut boxes = Vec::new();
    for size in ["1024x768", "1536x768"] {
        let out = tutorial13(
            &["--headless", "--size", size, "--screenshot", "f.png"],
            &dir,
        );
        assert!(out.status.success(), "{}", stderr(&out));
        boxes.push(drawn_box(
            &image::open(dir.join("f.png")).unwrap().into_rgb8(),
        ));
    }
    let size = |b: (u32, u32, u32, u32)| (b.2 - b.0, b.3 - b.1);
    let ((w0, h0), (w1, h1)) = (size(boxes[0]), size(boxes[1]));
    assert!(w0 > 100 && h0 > 100, "nothing drawn: {boxes:?}");
    assert!(w0.abs_diff(w1) <= 2 && h0.abs_diff(h1) <= 2, "{boxes:?}");
    // Centred: the extra width is shared on both sides.
    let centre = |b: (u32, u32, u32, u32)| (b.0 + b.2) as f32 / 2.0;
    assert!(
        (centre(boxes[1]) - centre(boxes[0]) - 256.0).abs() <= 1.5,
        "{boxes:?}"
    );
}

// Fails if make-assets without --out writes into the folder it is run from (the program would not
// read them there) instead of the crate's assets/ (where, the committed files being what it makes,
// nothing changes and each is listed unchanged).
#[test]
fn make_assets_writes_where_the_program_reads() {
    let dir = common::scratch("make-assets-default");
    let out = tutorial13(&["make-assets"], &dir);
    assert!(out.status.success(), "{}", common::text(&out.stderr));
    assert_eq!(
        std::fs::read_dir(&dir).unwrap().count(),
        0,
        "wrote into the working folder"
    );
    let stdout = common::text(&out.stdout);
    let crate_assets = common::own_assets().join("cylinder.obj");
    assert!(
        stdout.contains(&crate_assets.display().to_string()),
        "{stdout}"
    );
    assert!(stdout.starts_with("unchanged: "), "{stdout}");
}

// Fails if --headless without --screenshot renders silently (a learner waits for a file that is
// never written) instead of saying what to add.
#[test]
fn headless_without_a_screenshot_says_what_is_missing() {
    let dir = common::scratch("headless-alone");
    let out = tutorial13(&["--headless"], &dir);
    let stderr = common::text(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(
        stderr.contains("wrote nothing: add --screenshot"),
        "{stderr}"
    );
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0);
}
