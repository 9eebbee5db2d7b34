//! Combining normal maps (`tutorial13 normalmap --combine BASE DETAIL`): the output has the base's
//! size, a flat detail gives the base back, the detail tiles, `--green down` reads and writes y
//! negated, bad inputs are one line and nothing written, and the height-map flags are refused.
//! The methods' maths is tested in src/combine.rs.

use std::path::Path;

use image::RgbImage;

use crate::common::{files_under, run, scratch, text, tutorial13};

/// A normal map whose normals lean up to about 50° in every direction, varying texel by texel.
fn bumpy(width: u32, height: u32, seed: u32) -> RgbImage {
    RgbImage::from_fn(width, height, |c, r| {
        let angle = (c * 7 + r * 13 + seed) as f32 * 0.37;
        let lean = 0.9 * (((c * 3 + r * 5 + seed) % 11) as f32 / 10.0);
        let (x, y) = (lean * angle.cos(), lean * angle.sin());
        let n = [x, y, 1.0];
        let len = (x * x + y * y + 1.0).sqrt();
        image::Rgb(tutorial13::normalmap::encode_normal(n.map(|v| v / len)))
    })
}

/// Every channel of every texel within one level.
fn within_a_level(a: &RgbImage, b: &RgbImage) -> Result<(), String> {
    if a.dimensions() != b.dimensions() {
        return Err(format!("{:?} vs {:?}", a.dimensions(), b.dimensions()));
    }
    for ((x, y, p), q) in a.enumerate_pixels().zip(b.pixels()) {
        if p.0.iter().zip(q.0).any(|(u, v)| u.abs_diff(v) > 1) {
            return Err(format!("({x}, {y}): {:?} vs {:?}", p.0, q.0));
        }
    }
    Ok(())
}

/// Runs the binary in `dir`, asserting it succeeds.
fn ok(dir: &Path, args: &[&str]) {
    let out = run(tutorial13().args(args).current_dir(dir));
    assert!(out.status.success(), "{args:?}: {}", text(&out.stderr));
}

// Fails if the output does not have the base's size (a 37×20 base under a 16×16 detail scaled by
// 3: not a whole number of tiles), or if a flat detail (128, 128, 255) does not give the base back
// within one level with each method that allows it (all but linear), as PNG, as BMP, or as a
// 16-bit PNG (--depth 16, compared at 8 bits).
#[test]
fn a_flat_detail_gives_the_base_back_at_its_size() {
    let dir = scratch("flat-detail");
    let base = bumpy(37, 20, 0);
    base.save(dir.join("base.png")).unwrap();
    RgbImage::from_pixel(16, 16, image::Rgb([128, 128, 255]))
        .save(dir.join("flat.png"))
        .unwrap();
    let combine = ["normalmap", "--combine", "base.png", "flat.png"];
    for method in ["rnm", "whiteout", "udn", "pd"] {
        let out = format!("{method}.png");
        let args = ["--method", method, "--detail-scale", "3", "-o", &out];
        ok(&dir, &[&combine[..], &args].concat());
        let combined = image::open(dir.join(&out)).unwrap().into_rgb8();
        within_a_level(&combined, &base).unwrap_or_else(|e| panic!("{method}: {e}"));
    }
    ok(&dir, &[&combine[..], &["-o", "default.bmp"]].concat());
    let bmp = image::open(dir.join("default.bmp")).unwrap().into_rgb8();
    within_a_level(&bmp, &base).unwrap_or_else(|e| panic!("bmp: {e}"));
    ok(
        &dir,
        &[&combine[..], &["--depth", "16", "-o", "deep.png"]].concat(),
    );
    let deep = image::open(dir.join("deep.png")).unwrap();
    assert_eq!(deep.color(), image::ColorType::Rgb16);
    let deep = deep.into_rgb16();
    let eight = RgbImage::from_fn(37, 20, |x, y| {
        image::Rgb(
            deep.get_pixel(x, y)
                .0
                .map(|c| (f32::from(c) / 257.0).round() as u8),
        )
    });
    within_a_level(&eight, &base).unwrap_or_else(|e| panic!("16-bit: {e}"));
}

// Fails if a detail is not repeated --detail-scale times across the base: an 8×8 detail over a flat
// 32×32 base at scale 4 must come out as the detail tiled 4 × 4, texel for texel (within a level).
#[test]
fn the_detail_tiles_across_the_base() {
    let dir = scratch("tiles");
    let detail = bumpy(8, 8, 3);
    detail.save(dir.join("detail.png")).unwrap();
    RgbImage::from_pixel(32, 32, image::Rgb([128, 128, 255]))
        .save(dir.join("flat.png"))
        .unwrap();
    let args = ["normalmap", "--combine", "flat.png", "detail.png"];
    ok(
        &dir,
        &[&args[..], &["--detail-scale", "4", "-o", "out.png"]].concat(),
    );
    let out = image::open(dir.join("out.png")).unwrap().into_rgb8();
    let tiled = RgbImage::from_fn(32, 32, |x, y| *detail.get_pixel(x % 8, y % 8));
    within_a_level(&out, &tiled).unwrap();
}

// Fails if --green down does not negate y both on reading and on writing: the inputs stored green
// down (green mirrored) must give the green-up result stored green down. Every method treats x and y
// alike (mirroring both inputs mirrors the result), so negating on both sides or on neither passes;
// negating on one side only does not.
#[test]
fn green_down_negates_y_on_read_and_on_write() {
    let dir = scratch("green-down");
    let mirrored = |image: &RgbImage| {
        let mut image = image.clone();
        image.pixels_mut().for_each(|p| p.0[1] = 255 - p.0[1]);
        image
    };
    let (base, detail) = (bumpy(24, 24, 1), bumpy(12, 12, 5));
    base.save(dir.join("base.png")).unwrap();
    detail.save(dir.join("detail.png")).unwrap();
    mirrored(&base).save(dir.join("base-down.png")).unwrap();
    mirrored(&detail).save(dir.join("detail-down.png")).unwrap();
    ok(
        &dir,
        &[
            "normalmap",
            "--combine",
            "base.png",
            "detail.png",
            "-o",
            "up.png",
        ],
    );
    let down = ["normalmap", "--combine", "base-down.png", "detail-down.png"];
    ok(
        &dir,
        &[&down[..], &["--green", "down", "-o", "down.png"]].concat(),
    );
    let read = |name: &str| image::open(dir.join(name)).unwrap().into_rgb8();
    within_a_level(&read("down.png"), &mirrored(&read("up.png"))).unwrap();
    // Not vacuous: the result leans in y, so mirrored it is another map.
    assert!(within_a_level(&read("up.png"), &mirrored(&read("up.png"))).is_err());
}

// Fails if a bad input (a missing file, a file that is not an image, a grey-scale height map, a
// two-channel map, an output that is neither .png nor .bmp, a 16-bit .bmp, a scale that is not
// positive) does not exit 1 with one line on stderr naming the file (or the flag), or if anything
// is written.
#[test]
fn a_bad_input_is_one_line_and_nothing_is_written() {
    let dir = scratch("bad-input");
    bumpy(16, 16, 0).save(dir.join("base.png")).unwrap();
    bumpy(8, 8, 2).save(dir.join("detail.png")).unwrap();
    std::fs::write(dir.join("notes.png"), "not a picture\n").unwrap();
    image::GrayImage::from_fn(16, 16, |x, _| image::Luma([x as u8 * 16]))
        .save(dir.join("height.png"))
        .unwrap();
    RgbImage::from_fn(8, 8, |x, y| image::Rgb([x as u8 * 30, y as u8 * 30, 0]))
        .save(dir.join("two.png"))
        .unwrap();
    let before = files_under(&dir);
    let cases: [(&[&str], &str); 7] = [
        (
            &["missing.png", "detail.png", "-o", "out.png"],
            "missing.png",
        ),
        (&["base.png", "notes.png", "-o", "out.png"], "notes.png"),
        (&["height.png", "detail.png", "-o", "out.png"], "height.png"),
        (&["base.png", "two.png", "-o", "out.png"], "two.png"),
        (&["base.png", "detail.png", "-o", "out.jpg"], "out.jpg"),
        (
            &["base.png", "detail.png", "--depth", "16", "-o", "out.bmp"],
            "out.bmp",
        ),
        (
            &[
                "base.png",
                "detail.png",
                "--detail-scale",
                "0",
                "-o",
                "out.png",
            ],
            "--detail-scale",
        ),
    ];
    for (args, named) in cases {
        let out = run(tutorial13()
            .args(["normalmap", "--combine"])
            .args(args)
            .current_dir(&dir));
        let stderr = text(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{args:?}: {stderr}");
        assert_eq!(stderr.lines().count(), 1, "{args:?}: {stderr}");
        assert!(
            stderr.contains(named),
            "{args:?} does not name {named}: {stderr}"
        );
        assert_eq!(files_under(&dir), before, "{args:?} wrote a file");
    }
}

// Fails if --combine is accepted with a height map or a height-only flag, or a --combine flag
// without it, instead of being refused as a usage error (exit 2) before anything is read.
#[test]
fn combine_and_the_height_flags_exclude_each_other() {
    let dir = scratch("conflicts");
    let combine = ["normalmap", "--combine", "a.png", "b.png", "-o", "out.png"];
    let height = ["normalmap", "h.png", "-o", "out.png"];
    let cases: [&[&str]; 8] = [
        &[&combine[..], &["h.png"]].concat(),
        &[&combine[..], &["--strength", "2"]].concat(),
        &[&combine[..], &["--kernel", "central"]].concat(),
        &[&combine[..], &["--from-photo"]].concat(),
        &[&combine[..], &["--invert"]].concat(),
        &[&height[..], &["--method", "pd"]].concat(),
        &[&height[..], &["--detail-scale", "2"]].concat(),
        &["normalmap", "--combine", "a.png", "-o", "out.png"],
    ];
    for args in cases {
        let out = run(tutorial13().args(args).current_dir(&dir));
        assert_eq!(
            out.status.code(),
            Some(2),
            "{args:?}: {}",
            text(&out.stderr)
        );
    }
    assert!(files_under(&dir).is_empty());
}
