//! The height-map tool (`tutorial13 normalmap`): flat stays flat, slopes give the normal the test
//! computes, edges wrap, the green convention flips, two-channel maps rebuild z, any size is kept.

use std::path::Path;

use tutorial13::normalmap::{normal_map, Green, HeightMap, Kernel, NormalMapOptions};

const KERNELS: [Kernel; 3] = [Kernel::Sobel, Kernel::Scharr, Kernel::Central];

fn map(width: u32, height: u32, f: impl Fn(u32, u32) -> f32) -> HeightMap {
    let values = (0..height)
        .flat_map(|row| (0..width).map(move |col| (col, row)))
        .map(|(col, row)| f(col, row))
        .collect();
    HeightMap {
        width,
        height,
        values,
    }
}

fn options(kernel: Kernel, strength: f32) -> NormalMapOptions {
    NormalMapOptions {
        strength,
        kernel,
        ..Default::default()
    }
}

/// The stored byte of a normal component, as the tool documents it.
fn encode(c: f32) -> u8 {
    (127.5 * (c + 1.0)).round() as u8
}

// Fails if a constant height (any grey) is not (128, 128, 255) everywhere, or if the output is not
// one texel per height texel for a size that is neither square nor a power of two.
#[test]
fn a_constant_height_is_flat_at_any_size() {
    for grey in [0.0, 0.5, 0.73, 1.0] {
        for kernel in KERNELS {
            let texels = normal_map(&map(37, 20, |_, _| grey), options(kernel, 8.0));
            assert_eq!(texels.len(), 37 * 20);
            assert!(
                texels.iter().all(|&t| t == [128, 128, 255]),
                "{grey} {kernel:?}"
            );
        }
    }
}

// Fails if a linear ramp does not give the constant tilted normal normalize(−s·slope, 0, 1) (to the
// right) or normalize(0, −s·slope, 1) (up the picture) with every kernel, or the wrong sign of green.
#[test]
fn a_linear_ramp_gives_the_computed_tilt() {
    let (slope, strength) = (1.0 / 64.0, 20.0);
    let tilt = strength * slope;
    let len = (tilt * tilt + 1.0f32).sqrt();
    let (across, up) = (encode(-tilt / len), encode(1.0 / len));
    for kernel in KERNELS {
        // Height grows to the right: x tilts left (red below 128).
        let right = normal_map(
            &map(64, 8, |c, _| c as f32 * slope),
            options(kernel, strength),
        );
        // Height grows up the picture (towards row 0): with green up, y tilts down.
        let upward = normal_map(
            &map(8, 64, |_, r| (63 - r) as f32 * slope),
            options(kernel, strength),
        );
        for i in [1usize, 20, 62] {
            assert_eq!(
                right[3 * 64 + i],
                [across, 128, up],
                "{kernel:?} column {i}"
            );
            assert_eq!(upward[i * 8 + 3], [128, across, up], "{kernel:?} row {i}");
        }
        assert!(across < 128);
    }
}

// Fails if the derivatives do not wrap: on a height that tiles (one sine period across the map),
// the step from the last column to the first must be no larger than any step inside the map.
#[test]
fn derivatives_wrap_so_tiling_maps_tile() {
    let w = 48;
    let height = map(w, 4, |c, _| {
        0.5 + 0.5 * (std::f32::consts::TAU * c as f32 / w as f32).sin()
    });
    for kernel in KERNELS {
        let texels = normal_map(&height, options(kernel, 30.0));
        let red = |c: u32| i32::from(texels[(w + c) as usize][0]);
        let inside = (0..w - 1)
            .map(|c| (red(c + 1) - red(c)).abs())
            .max()
            .unwrap();
        let across_edge = (red(0) - red(w - 1)).abs();
        assert!(
            across_edge <= inside,
            "{kernel:?}: edge step {across_edge} > {inside}"
        );
    }
}

// Fails if --green down is not the green-up map of the height flipped upside down, flipped back
// (within 1 level: the kernels sum the rows in the other order, which may round differently).
#[test]
fn green_down_is_green_up_mirrored() {
    let height = map(32, 24, |c, r| ((c * 7 + r * r * 3) % 17) as f32 / 16.0);
    let flipped = map(32, 24, |c, r| height.values[((23 - r) * 32 + c) as usize]);
    for kernel in KERNELS {
        let up = normal_map(&height, options(kernel, 6.0));
        let down = normal_map(
            &flipped,
            NormalMapOptions {
                green: Green::Down,
                ..options(kernel, 6.0)
            },
        );
        for r in 0..24 {
            for c in 0..32 {
                let (a, b) = (up[r * 32 + c], down[(23 - r) * 32 + c]);
                let close = a.iter().zip(b).all(|(x, y)| x.abs_diff(y) <= 1);
                assert!(close, "{kernel:?} ({c}, {r}): {a:?} vs {b:?}");
            }
        }
    }
}

// Fails if a two-channel map keeps blue, or if z rebuilt as sqrt(1 − x² − y²) from its red and green
// is more than 2 levels from the three-channel map's blue.
#[test]
fn two_channel_maps_rebuild_z() {
    let height = map(32, 32, |c, r| ((c * 5 + r * 11) % 13) as f32 / 12.0);
    let three = normal_map(&height, options(Kernel::Sobel, 4.0));
    let two = normal_map(
        &height,
        NormalMapOptions {
            two_channel: true,
            ..options(Kernel::Sobel, 4.0)
        },
    );
    for (t3, t2) in three.iter().zip(&two) {
        assert_eq!((t2[0], t2[1], t2[2]), (t3[0], t3[1], 0));
        let decode = |b: u8| f32::from(b) / 127.5 - 1.0;
        let (x, y) = (decode(t2[0]), decode(t2[1]));
        let z = (1.0 - x * x - y * y).max(0.0).sqrt();
        assert!(encode(z).abs_diff(t3[2]) <= 2, "{t3:?} rebuilt z {z}");
    }
}

// Fails if the command does not read a PNG height map and write a BMP of the same size that the
// tutorial's BMP loader accepts, or accepts an output format it cannot write.
#[test]
fn the_command_keeps_the_size_and_writes_a_loadable_bmp() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("normalmap-command");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let grey = image::GrayImage::from_fn(37, 20, |c, r| image::Luma([((c * 3 + r) % 256) as u8]));
    grey.save(dir.join("height.png")).unwrap();
    let run = |args: &[&str]| {
        crate::common::run(crate::common::tutorial13().args(args).current_dir(&dir))
    };
    let out = run(&[
        "normalmap",
        "height.png",
        "-o",
        "normal.bmp",
        "--strength",
        "3",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let bytes = std::fs::read(dir.join("normal.bmp")).unwrap();
    let bmp = tutorial13::common::texture::read_bmp_bytes(&bytes, &dir.join("normal.bmp")).unwrap();
    assert_eq!((bmp.width, bmp.height), (37, 20));
    assert_eq!(bmp.bgr.len(), 37 * 20 * 3);
    let out = run(&["normalmap", "height.png", "-o", "normal.jpg"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(!dir.join("normal.jpg").exists());
}

// Fails if a negative strength given with a space (`--strength -8`, the way every other value is
// given) is refused as an unknown argument, or if it does not turn the relief inside out: the map
// of -8 must be the map of +8 with x and y negated (red and green mirrored about 128, within one
// level of rounding), blue unchanged.
#[test]
fn a_negative_strength_parses_with_a_space_and_inverts_the_relief() {
    let dir = crate::common::scratch("negative-strength");
    let bump = image::GrayImage::from_fn(32, 32, |c, r| {
        let d = ((c as f32 - 16.0).powi(2) + (r as f32 - 16.0).powi(2)).sqrt();
        image::Luma([(255.0 * (1.0 - d / 16.0).max(0.0)) as u8])
    });
    bump.save(dir.join("bump.png")).unwrap();
    let make = |strength: &str, out: &str| {
        let args = ["normalmap", "bump.png", "-o", out, "--strength", strength];
        let run = crate::common::run(crate::common::tutorial13().args(args).current_dir(&dir));
        assert!(
            run.status.success(),
            "--strength {strength}: {}",
            String::from_utf8_lossy(&run.stderr)
        );
        image::open(dir.join(out)).unwrap().into_rgb8()
    };
    let (raised, engraved) = (make("8", "raised.png"), make("-8", "engraved.png"));
    let mut tilted = 0;
    for (up, down) in raised.pixels().zip(engraved.pixels()) {
        for c in 0..2 {
            let mirrored = 255 - i32::from(up[c]) + 1;
            assert!(
                (i32::from(down[c]) - mirrored).abs() <= 1,
                "{up:?} vs {down:?}"
            );
        }
        assert_eq!(up[2], down[2], "{up:?} vs {down:?}");
        tilted += usize::from(up[0] != 128 || up[1] != 128);
    }
    assert!(
        tilted > 100,
        "only {tilted} tilted texels: is the bump there?"
    );
}

// Fails if a TGA height map (a format with no signature to recognise it by) is refused, or reads
// other heights than the same picture as a PNG; or if --invert is not the map of the negated height.
#[test]
fn tga_heights_read_like_png_and_invert_negates() {
    let dir = crate::common::scratch("tga");
    let picture = image::GrayImage::from_fn(32, 24, |x, y| image::Luma([(x * 7 + y * 3) as u8]));
    picture.save(dir.join("h.png")).unwrap();
    image::DynamicImage::ImageLuma8(picture.clone())
        .to_rgb8()
        .save(dir.join("h.tga"))
        .unwrap();
    let load = |name: &str| HeightMap::load(&dir.join(name)).unwrap();
    assert_eq!(load("h.png"), load("h.tga"));
    let run = |args: &[&str]| {
        let out = crate::common::run(crate::common::tutorial13().args(args).current_dir(&dir));
        assert!(out.status.success(), "{}", crate::common::text(&out.stderr));
    };
    run(&["normalmap", "h.png", "--invert", "-o", "inverted.png"]);
    run(&[
        "normalmap",
        "h.png",
        "--strength",
        "-8",
        "-o",
        "negated.png",
    ]);
    let read = |name: &str| std::fs::read(dir.join(name)).unwrap();
    assert_eq!(read("inverted.png"), read("negated.png"));
}
