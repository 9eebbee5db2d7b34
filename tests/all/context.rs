//! Headless EGL contexts on Mesa's llvmpipe and the offscreen render target.
//! Needs libegl1, libegl-mesa0 and libgl1-mesa-dri; no GPU, no X server.

use glow::HasContext;
use tutorial13::gl::context::HeadlessContext;
use tutorial13::gl::image::write_png;
use tutorial13::gl::offscreen::OffscreenTarget;
use tutorial13::gl::{context_info, gl_errors, Profile};

use crate::common;

fn software(profile: Profile) -> HeadlessContext {
    HeadlessContext::new(profile, false).unwrap_or_else(|e| panic!("{profile} context: {e}"))
}

fn clear(ctx: &HeadlessContext, target: &OffscreenTarget, rgba: [f32; 4]) {
    target.bind();
    let gl = ctx.gl();
    unsafe {
        gl.clear_color(rgba[0], rgba[1], rgba[2], rgba[3]);
        gl.clear(glow::COLOR_BUFFER_BIT | glow::DEPTH_BUFFER_BIT);
    }
}

/// A software context of `profile`, described on stderr, and checked to be of that profile and of
/// GL 3.3 or later.
fn checked(profile: Profile) -> HeadlessContext {
    let ctx = software(profile);
    let info = ctx.info();
    eprintln!(
        "device: {}\ninfo: {info}\nGL_VERSION: {}",
        ctx.device(),
        info.version_string
    );
    assert!(info.version >= (3, 3), "{info}");
    assert_eq!(info.profile, profile);
    ctx
}

// Fails if EGL device selection, the surfaceless 3.3 core context or the read-back of version/profile breaks.
#[test]
fn core_context_on_llvmpipe() {
    let ctx = checked(Profile::Core);
    let info = ctx.info();
    if common::on_reference_renderer("core_context_on_llvmpipe", info) {
        assert!(info.renderer.contains("llvmpipe"), "{info}");
    }
    // The reusable reader sees the same context.
    assert_eq!(context_info(ctx.gl()).version, info.version);
    assert!(info.has_extension("GL_ARB_framebuffer_object") || info.version >= (3, 0));
    assert!(!ctx.get_proc_address(c"glClear").is_null());
    assert!(gl_errors(ctx.gl()).is_empty());
}

// Fails if the compatibility profile cannot be had, or the profile mask is read wrong.
#[test]
fn compat_context_is_compat() {
    let ctx = checked(Profile::Compat);
    // Legacy entry points the debug lines need are there.
    assert!(!ctx.get_proc_address(c"glBegin").is_null());
}

// Fails if the FBO's format, clear or read-back conversion (0.4 → 102) or pack state is wrong.
#[test]
fn offscreen_clear_reads_back_exactly() {
    let ctx = software(Profile::Core);
    let target = OffscreenTarget::new(ctx.gl(), 64, 48).unwrap();
    clear(&ctx, &target, [0.0, 0.0, 0.4, 0.0]);
    let image = target.read_rgba();
    assert_eq!(image.dimensions(), (64, 48));
    assert!(image.pixels().all(|p| p.0 == [0, 0, 102, 0]));
    assert_eq!(gl_errors(ctx.gl()), Vec::<u32>::new());
}

// Fails if read_rgba stops flipping rows (row 0 must be the top of the frame).
#[test]
fn read_back_is_top_row_first() {
    let ctx = software(Profile::Core);
    let target = OffscreenTarget::new(ctx.gl(), 64, 48).unwrap();
    assert!(!target.flipped_y());
    assert_top_row_first(&ctx, &target);
}

// Fails if a target stored like a window (GL_MESA_framebuffer_flip_y) reads back upside down: GL's
// coordinates keep their bottom-left origin whatever the storage, so read_rgba needs no change.
#[test]
fn window_oriented_target_reads_back_top_row_first() {
    let ctx = software(Profile::Core);
    let info = ctx.info();
    let target =
        OffscreenTarget::with_window_orientation(ctx.gl(), (64, 48), 0, ctx.extensions()).unwrap();
    // Flipped exactly when the context has the extension (Mesa 22.3 has it on desktop GL).
    assert_eq!(
        target.flipped_y(),
        info.has_extension("GL_MESA_framebuffer_flip_y"),
        "{info}"
    );
    assert_top_row_first(&ctx, &target);
}

/// Paints the bottom-left quadrant (in GL's coordinates) red on black and checks that it comes back
/// as the bottom-left of the image, whose row 0 is the top.
fn assert_top_row_first(ctx: &HeadlessContext, target: &OffscreenTarget) {
    let (w, h) = (target.width(), target.height());
    clear(ctx, target, [0.0, 0.0, 0.0, 1.0]);
    let gl = ctx.gl();
    unsafe {
        // GL's window coordinates start at the bottom-left: paint that quadrant red.
        gl.enable(glow::SCISSOR_TEST);
        gl.scissor(0, 0, w as i32 / 2, h as i32 / 2);
        gl.clear_color(1.0, 0.0, 0.0, 1.0);
        gl.clear(glow::COLOR_BUFFER_BIT);
        gl.disable(glow::SCISSOR_TEST);
    }
    let image = target.read_rgba();
    for (x, y, p) in image.enumerate_pixels() {
        let red = x < w / 2 && y >= h / 2;
        let expected = if red {
            [255, 0, 0, 255]
        } else {
            [0, 0, 0, 255]
        };
        assert_eq!(p.0, expected, "pixel ({x}, {y})");
    }
    assert!(gl_errors(gl).is_empty());
}

// Fails if contexts leak across threads (e.g. a shared current context) or creation is not thread-safe.
#[test]
fn contexts_on_several_threads_at_once() {
    /// Clears a small target to `green` and checks every pixel, without panicking so that the other
    /// thread is never left waiting at the barrier.
    fn draw(ctx: &HeadlessContext, green: f32) -> Result<(), String> {
        let target = OffscreenTarget::new(ctx.gl(), 16, 16).map_err(|e| e.to_string())?;
        clear(ctx, &target, [0.0, green, 0.0, 1.0]);
        let expected = [0, (green * 255.0).round() as u8, 0, 255];
        match target.read_rgba().pixels().find(|p| p.0 != expected) {
            Some(p) => Err(format!("read {:?}, expected {expected:?}", p.0)),
            None if !gl_errors(ctx.gl()).is_empty() => Err("GL errors".into()),
            None => Ok(()),
        }
    }
    let barrier = std::sync::Arc::new(std::sync::Barrier::new(2));
    let threads: Vec<_> = [0.2f32, 0.8]
        .into_iter()
        .map(|green| {
            let barrier = barrier.clone();
            std::thread::spawn(move || {
                let made = HeadlessContext::new(Profile::Core, false);
                // Both contexts exist (current on their own threads) from here on...
                barrier.wait();
                let outcome = match &made {
                    Ok(ctx) => draw(ctx, green),
                    Err(e) => Err(e.to_string()),
                };
                // ...until both have drawn.
                barrier.wait();
                drop(made);
                outcome
            })
        })
        .collect();
    for t in threads {
        t.join().unwrap().unwrap();
    }
}

// Fails if a zero-sized or oversized target is accepted instead of being an Err.
#[test]
fn offscreen_target_rejects_bad_sizes() {
    let ctx = software(Profile::Core);
    for (w, h) in [(0, 10), (10, 0), (1 << 30, 1)] {
        let err = OffscreenTarget::new(ctx.gl(), w, h).unwrap_err();
        assert!(err.to_string().contains("offscreen target"), "{err}");
    }
    assert!(gl_errors(ctx.gl()).is_empty());
}

// Fails if the PNG encoder, the colour type or the atomic rename loses or changes pixels.
#[test]
fn write_png_round_trip() {
    let dir = common::scratch("round-trip");
    let path = dir.join("frame.png");
    let image = image::RgbaImage::from_fn(7, 5, |x, y| {
        image::Rgba([x as u8 * 30, y as u8 * 50, 7, 200])
    });
    write_png(&path, &image).unwrap();
    // Overwriting an existing file works too.
    write_png(&path, &image).unwrap();
    let back = image::open(&path).unwrap().into_rgba8();
    assert_eq!(back, image);
    let names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names, ["frame.png"], "no temporary file is left");
}

// Fails if a missing folder panics, gives an error without the path, or leaves a file behind.
#[test]
fn write_png_into_missing_folder_is_an_error() {
    let dir = common::scratch("missing");
    let path = dir.join("no-such-folder").join("frame.png");
    let err = write_png(&path, &image::RgbaImage::new(2, 2)).unwrap_err();
    assert_eq!(err.path(), Some(path.as_path()));
    assert!(
        err.to_string().contains(&path.display().to_string()),
        "{err}"
    );
    assert!(!path.exists());
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0);
}

// Fails if a failed rename (target is a folder) leaves the temporary file behind.
#[test]
fn write_png_failure_leaves_nothing_behind() {
    let dir = common::scratch("onto-folder");
    let path = dir.join("frame.png");
    std::fs::create_dir(&path).unwrap();
    let err = write_png(&path, &image::RgbaImage::new(2, 2)).unwrap_err();
    assert_eq!(err.path(), Some(path.as_path()));
    assert!(path.is_dir());
    let names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names, ["frame.png"]);
}
