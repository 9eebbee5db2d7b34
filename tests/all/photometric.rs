//! The photo tools. `tutorial13 photometric` (photometric stereo) on synthetic photos of the
//! project's own wall, shaded Lambertian from its normal and diffuse maps under known lights and
//! written as 8-bit PNGs and as sRGB JPEGs; photos with shadows and highlights in part of them; every
//! refusal. `normalmap --from-photo`'s one-photo guess, and what it cannot tell. Both outputs on the
//! wall scene, as docs/tools.md's picture (docs/photometric.png) shows them.

use std::path::{Path, PathBuf};

use glam::Vec3;
use image::RgbImage;
use tutorial13::normalmap::round_to_u8;
use tutorial13::photometric::photo::{Encoding, Photo};
use tutorial13::photometric::{recover, PhotometricOptions};

use crate::capture_rig::rig;
use crate::common::{files_under, headless_screenshot, hybrid_score, is_background};
use crate::common::{own_assets, run, scratch, text, tutorial13};

/// A surface the tests photograph: unit normals (x right, y up the picture, z out) and linear
/// albedo, row 0 at the top.
struct Surface {
    size: u32,
    normals: Vec<Vec3>,
    albedo: Vec<[f32; 3]>,
}

/// A normal map's texel as the unit normal it stands for (green up).
fn decode_normal(t: [u8; 3]) -> Vec3 {
    Vec3::from(t.map(|c| f32::from(c) / 127.5 - 1.0)).normalize()
}

fn read_rgb(path: &Path) -> RgbImage {
    image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .into_rgb8()
}

/// The project's own wall: assets/wall/normal.bmp and diffuse.bmp (256², green up, sRGB colours).
fn wall() -> Surface {
    let normal = read_rgb(&own_assets().join("wall/normal.bmp"));
    let diffuse = read_rgb(&own_assets().join("wall/diffuse.bmp"));
    Surface {
        size: normal.width(),
        normals: normal.pixels().map(|p| decode_normal(p.0)).collect(),
        albedo: diffuse
            .pixels()
            .map(|p| p.0.map(|c| Encoding::Srgb.to_linear(f32::from(c) / 255.0)))
            .collect(),
    }
}

/// The photo of `surface` under a distant light towards `light` (any length, intensity 1): linear
/// albedo × max(0, n·l), sRGB-encoded to 8 bits, as a camera would store it.
fn photograph(surface: &Surface, light: Vec3) -> RgbImage {
    let l = light.normalize();
    let texels = surface.normals.iter().zip(&surface.albedo);
    let bytes = texels
        .flat_map(|(n, a)| {
            let lit = n.dot(l).max(0.0);
            a.map(|c| round_to_u8(Encoding::Srgb.from_linear(c * lit) * 255.0))
        })
        .collect();
    RgbImage::from_raw(surface.size, surface.size, bytes).unwrap()
}

/// `k` lights at the elevations a photographer with a lamp would pick (50° and 60° above the
/// surface, alternately), in azimuths spread evenly around it from 30°: several have negative
/// components, so `--light -0.55,…` is parsed on the way.
fn lights(k: usize) -> Vec<Vec3> {
    (0..k)
        .map(|i| {
            let azimuth = (30.0 + 360.0 * i as f32 / k as f32).to_radians();
            let elevation = (if i % 2 == 0 { 50.0f32 } else { 60.0 }).to_radians();
            Vec3::new(
                elevation.cos() * azimuth.cos(),
                elevation.cos() * azimuth.sin(),
                elevation.sin(),
            )
        })
        .collect()
}

/// `--light X,Y,Z` for each light, in order.
fn light_args(lights: &[Vec3]) -> Vec<String> {
    lights
        .iter()
        .flat_map(|l| ["--light".into(), format!("{},{},{}", l.x, l.y, l.z)])
        .collect()
}

/// How the tests store a photo.
#[derive(Debug, Clone, Copy)]
enum Format {
    Png,
    /// JPEG at this quality (the `image` crate's encoder, 4:2:0 chroma, as phones store photos).
    Jpeg(u8),
}

/// Saves `photo` as `dir`/`stem` in `format`; returns the file's name.
fn save(photo: &RgbImage, dir: &Path, stem: &str, format: Format) -> String {
    match format {
        Format::Png => {
            let name = format!("{stem}.png");
            photo.save(dir.join(&name)).unwrap();
            name
        }
        Format::Jpeg(quality) => {
            let name = format!("{stem}.jpg");
            let file = std::fs::File::create(dir.join(&name)).unwrap();
            let mut encoder = image::codecs::jpeg::JpegEncoder::new_with_quality(file, quality);
            encoder.encode_image(photo).unwrap();
            name
        }
    }
}

/// Photographs `surface` under each light, `spoil` changing photo k first; saves the photos in
/// `dir` and returns the command's arguments: the photos, then each `--light`.
fn shoot(
    dir: &Path,
    surface: &Surface,
    lights: &[Vec3],
    format: Format,
    spoil: impl Fn(usize, &mut RgbImage),
) -> Vec<String> {
    let mut args: Vec<String> = lights
        .iter()
        .enumerate()
        .map(|(k, &l)| {
            let mut photo = photograph(surface, l);
            spoil(k, &mut photo);
            save(&photo, dir, &format!("photo{k}"), format)
        })
        .collect();
    args.extend(light_args(lights));
    args
}

/// Runs `tutorial13 photometric ARGS` in `dir`; fails unless it succeeds. Returns its stderr.
fn photometric(dir: &Path, args: &[String]) -> String {
    let out = run(tutorial13().arg("photometric").args(args).current_dir(dir));
    let stderr = text(&out.stderr);
    assert!(out.status.success(), "photometric {args:?}:\n{stderr}");
    stderr
}

/// The angle, in degrees, between each texel of the normal map at `path` and `truth`.
fn angles(path: &Path, truth: &Surface) -> Vec<f64> {
    let map = read_rgb(path);
    assert_eq!(map.dimensions(), (truth.size, truth.size));
    map.pixels()
        .zip(&truth.normals)
        .map(|(p, n)| {
            f64::from(
                decode_normal(p.0)
                    .dot(*n)
                    .clamp(-1.0, 1.0)
                    .acos()
                    .to_degrees(),
            )
        })
        .collect()
}

fn mean(values: impl IntoIterator<Item = f64>) -> f64 {
    let (sum, n) = values
        .into_iter()
        .fold((0.0, 0), |(sum, n), v| (sum + v, n + 1));
    sum / f64::from(n)
}

/// Mean absolute difference, in 8-bit levels, between the albedo at `path` and the wall's
/// diffuse.bmp (both sRGB-encoded).
fn albedo_error(path: &Path) -> f64 {
    let got = read_rgb(path);
    let want = read_rgb(&own_assets().join("wall/diffuse.bmp"));
    mean(
        got.as_raw()
            .iter()
            .zip(want.as_raw())
            .map(|(a, b)| f64::from(a.abs_diff(*b))),
    )
}

/// The texel count in the command's "N of M texels … flat normal" line, 0 without one; fails if
/// there is more than one such line.
fn flat_count(stderr: &str) -> usize {
    let lines: Vec<&str> = stderr
        .lines()
        .filter(|l| l.contains("flat normal"))
        .collect();
    assert!(lines.len() <= 1, "more than one count line:\n{stderr}");
    lines.first().map_or(0, |line| {
        let count = line
            .split(" of ")
            .next()
            .unwrap()
            .rsplit(' ')
            .next()
            .unwrap();
        count
            .parse()
            .unwrap_or_else(|_| panic!("no count in {line:?}"))
    })
}

// Fails if the wall's normals, recovered from its photos under 3, 4 and 8 lights, stored as 8-bit
// PNGs and as JPEGs at quality 90, are further off on average than stated here, or the albedo is,
// by least squares (the default below six photos, `--solver lstsq` for eight) or, for eight, by the
// robust default. Measured (mean angle over all 65 536 texels; albedo as the mean difference from
// diffuse.bmp in 8-bit sRGB levels), least squares:
//   PNG:  3 lights 0.47° (albedo 0.02 levels), 4 lights 0.30° (0.004), 8 lights 0.17° (0.000);
//   JPEG: 3 lights 1.64° (0.79),               4 lights 1.40° (0.74),  8 lights 1.08° (0.66);
// robust, 8 lights: PNG 0.22° (0.007),                                    JPEG 1.17° (0.76):
// six photos of eight are left per texel, so noise counts more.
// Writing the normal map in 8 bits alone costs about 0.15° (the 8-light figure). With 3 lights,
// 172 texels at the stones' steep feet are lit in fewer than three photos: flat, and counted.
#[test]
fn the_walls_normals_and_albedo_come_back_from_its_photos() {
    let surface = wall();
    let (lstsq, robust) = (Some("lstsq"), Some("robust"));
    let cases = [
        (Format::Png, 3, None, 0.7, 0.1),
        (Format::Png, 4, None, 0.45, 0.05),
        (Format::Png, 8, lstsq, 0.3, 0.05),
        (Format::Png, 8, robust, 0.35, 0.05),
        (Format::Jpeg(90), 3, None, 2.2, 1.2),
        (Format::Jpeg(90), 4, None, 2.0, 1.1),
        (Format::Jpeg(90), 8, lstsq, 1.6, 1.0),
        (Format::Jpeg(90), 8, robust, 1.6, 1.0),
    ];
    for (format, k, solver, max_degrees, max_levels) in cases {
        let dir = scratch(&format!("wall-{k}-{format:?}-{solver:?}"));
        let mut args = shoot(&dir, &surface, &lights(k), format, |_, _| {});
        args.extend(["-o", "normal.png", "--albedo", "albedo.png"].map(String::from));
        if let Some(solver) = solver {
            args.extend(["--solver".into(), solver.into()]);
        }
        let stderr = photometric(&dir, &args);
        let degrees = mean(angles(&dir.join("normal.png"), &surface));
        let levels = albedo_error(&dir.join("albedo.png"));
        println!(
            "{k} lights, {format:?}, {solver:?}: mean {degrees:.3}°, albedo {levels:.3} levels"
        );
        assert!(
            degrees < max_degrees,
            "{k} lights, {format:?}: mean error {degrees:.3}° ≥ {max_degrees}°"
        );
        assert!(
            levels < max_levels,
            "{k} lights, {format:?}: albedo off by {levels:.3} levels on average ≥ {max_levels}"
        );
        // Only the 3-light sets leave texels with fewer than three lit photos.
        assert_eq!(flat_count(&stderr) > 0, k == 3, "{k} lights:\n{stderr}");
    }
}

// Fails if `--green down` does not store the same normals with green the other way: red and blue
// equal to the green-up map's and green = 255 − green-up's (each texel; the encoding rounds
// 127.5 · (1 ± y), which sum to 255 but where y = 0), on four photos of the wall.
#[test]
fn green_down_stores_the_same_normals_with_green_turned() {
    let surface = wall();
    let dir = scratch("photometric-green-down");
    let args = shoot(&dir, &surface, &lights(4), Format::Png, |_, _| {});
    let with = |extra: &[&str]| {
        let mut all = args.clone();
        all.extend(extra.iter().map(|s| s.to_string()));
        photometric(&dir, &all);
    };
    with(&["-o", "up.png"]);
    with(&["-o", "down.png", "--green", "down"]);
    let (up, down) = (
        read_rgb(&dir.join("up.png")),
        read_rgb(&dir.join("down.png")),
    );
    assert_eq!(up.dimensions(), down.dimensions());
    let (mut tilted, mut flats) = (0, 0);
    for (u, d) in up.pixels().zip(down.pixels()) {
        assert_eq!((u[0], u[2]), (d[0], d[2]), "red or blue changed");
        // y = 0 exactly (a flat texel) is the one tie that matters: 127.5 rounds to 128 both ways.
        let flat = u[1] == 128 && d[1] == 128;
        assert!(
            flat || u16::from(u[1]) + u16::from(d[1]) == 255,
            "green {} and {}",
            u[1],
            d[1]
        );
        flats += usize::from(flat);
        tilted += usize::from(u[1].abs_diff(128) > 8);
    }
    // The wall's relief tilts many texels up or down: a map of flat normals would pass the above.
    println!("{tilted} texels lean up or down, {flats} flat");
    assert!(tilted > 1000, "only {tilted} texels lean up or down");
}

// Fails if a shadow (black) or a highlight (saturated) over part of one photo spoils the texels
// under it when three other photos remain, or if with only three photos the shadowed texels are not
// given the flat normal and counted in the one line, or if the rest of the texels suffer for it.
// A 96×64 block of photo 0 is black (a cast shadow), a 64×96 block of photo 1 white (a highlight).
// Measured: under the shadow 0.47°, under the highlight 0.53° (four photos); outside the blocks
// 0.49° (three photos).
#[test]
fn shadows_and_highlights_in_part_of_a_photo_leave_the_rest() {
    let surface = wall();
    let (shadow, highlight) = ((20, 30, 96, 64), (150, 100, 64, 96));
    let inside = |(x0, y0, w, h): (u32, u32, u32, u32), i: usize| {
        let (x, y) = (i as u32 % surface.size, i as u32 / surface.size);
        (x0..x0 + w).contains(&x) && (y0..y0 + h).contains(&y)
    };
    let spoil = |k: usize, photo: &mut RgbImage| {
        for (x, y, p) in photo.enumerate_pixels_mut() {
            let i = (y * surface.size + x) as usize;
            if k == 0 && inside(shadow, i) {
                p.0 = [0; 3];
            }
            if k == 1 && inside(highlight, i) {
                p.0 = [255; 3];
            }
        }
    };
    // Four photos: every spoiled texel still has three, but for the few at the stones' steep feet
    // that one of those three misses as well (9; unspoiled, none is flat).
    let dir = scratch("spoiled-4");
    let mut args = shoot(&dir, &surface, &lights(4), Format::Png, spoil);
    args.extend(["-o", "normal.png"].map(String::from));
    let stderr = photometric(&dir, &args);
    assert!(flat_count(&stderr) < 20, "{stderr}");
    let errors = angles(&dir.join("normal.png"), &surface);
    for (what, block) in [("shadow", shadow), ("highlight", highlight)] {
        let under = mean(
            (0..errors.len())
                .filter(|&i| inside(block, i))
                .map(|i| errors[i]),
        );
        println!("4 photos, under the {what}: mean {under:.3}°");
        assert!(under < 0.7, "under the {what}: mean error {under:.3}°");
    }
    // Three photos: the shadowed block is left flat and counted, the rest is as good as unspoiled.
    let dir = scratch("spoiled-3");
    let mut args = shoot(&dir, &surface, &lights(3), Format::Png, spoil);
    args.extend(["-o", "normal.png"].map(String::from));
    let stderr = photometric(&dir, &args);
    let blocks = (96 * 64 + 64 * 96) as usize;
    let flat = flat_count(&stderr);
    // The blocks, plus the texels that are flat anyway (172 at the stones' feet, a few of them inside).
    assert!(
        (blocks..blocks + 172).contains(&flat),
        "{flat} flat:\n{stderr}"
    );
    let map = read_rgb(&dir.join("normal.png"));
    for i in (0..map.as_raw().len() / 3).filter(|&i| inside(shadow, i)) {
        let p = map.get_pixel(i as u32 % surface.size, i as u32 / surface.size);
        assert_eq!(p.0, [128, 128, 255], "texel {i} under the shadow");
    }
    let errors = angles(&dir.join("normal.png"), &surface);
    let outside = |i: &usize| !inside(shadow, *i) && !inside(highlight, *i);
    let rest = mean((0..errors.len()).filter(outside).map(|i| errors[i]));
    println!("3 photos, outside the blocks: mean {rest:.3}°");
    assert!(rest < 0.7, "outside the blocks: mean error {rest:.3}°");
}

// Fails if a texel whose kept photos' lights are nearly coplanar is solved anyway (the decision
// documented in src/photometric/: it is left flat and counted, like one with fewer than three),
// or if the same texel with every photo kept is not solved. Three lights 4° above the surface (within
// 5° of its plane) and one overhead, a light grey surface tilted a little (so that the low lights all
// reach it); texel 1 is black in the overhead photo.
#[test]
fn texels_kept_only_under_nearly_coplanar_lights_are_left_flat() {
    let n = Vec3::new(0.04, 0.02, 1.0).normalize();
    let low = 4f32.to_radians();
    let mut lights: Vec<Vec3> = (0..3)
        .map(|i| {
            let a = (120.0 * i as f32).to_radians();
            Vec3::new(low.cos() * a.cos(), low.cos() * a.sin(), low.sin())
        })
        .collect();
    lights.push(Vec3::Z);
    let photos: Vec<Photo> = lights
        .iter()
        .enumerate()
        .map(|(k, l)| {
            // Albedo 0.8: white would saturate under the overhead light.
            let lit = |texel: u32| {
                if k == 3 && texel == 1 {
                    0.0
                } else {
                    0.8 * n.dot(*l).max(0.0)
                }
            };
            let image = RgbImage::from_fn(2, 1, |x, _| {
                image::Rgb([round_to_u8(Encoding::Srgb.from_linear(lit(x)) * 255.0); 3])
            });
            Photo::from_image(image.into())
        })
        .collect();
    let recovered = recover(&photos, &lights, &PhotometricOptions::default()).unwrap();
    assert_eq!(recovered.unsolved, 1);
    assert_eq!(recovered.normals[1], [128, 128, 255]);
    let solved = decode_normal(recovered.normals[0]);
    assert!(solved.angle_between(n).to_degrees() < 2.0, "{solved}");
}

// Fails if `round_to_u8`, which the normal and albedo maps are written with, is not
// `x.round().clamp(0.0, 255.0) as u8` to the bit: checked on every 13th float from −2 to 258 and on
// every value within 4 ulps of each half-way point.
#[test]
fn the_fast_rounding_is_rounding() {
    let reference = |x: f32| x.round().clamp(0.0, 255.0) as u8;
    let (from, to) = ((-2.0f32).to_bits(), 258.0f32.to_bits());
    // Negative floats have larger bit patterns: walk both halves.
    let negatives = ((-0.0f32).to_bits()..=from).step_by(13).map(f32::from_bits);
    let positives = (0..to).step_by(13).map(f32::from_bits);
    let halves = (0..=256).flat_map(|k| {
        let half = k as f32 + 0.5;
        (-4..=4).map(move |d| f32::from_bits((half.to_bits() as i32 + d) as u32))
    });
    for x in negatives
        .chain(positives)
        .chain(halves)
        .chain([f32::NAN, f32::INFINITY])
    {
        assert_eq!(round_to_u8(x), reference(x), "{x:e}");
    }
}

/// Runs `tutorial13 ARGS` in `dir` and checks the failure contract: non-zero exit, exactly one
/// stderr line `tutorial13: …` that contains `says`, no panic, and `dir` holding only `before`.
fn assert_refused(dir: &Path, args: &[String], says: &str, before: &[PathBuf]) {
    let out = run(tutorial13().args(args).current_dir(dir));
    let stderr = text(&out.stderr);
    assert!(!out.status.success(), "{args:?} succeeded:\n{stderr}");
    let lines: Vec<&str> = stderr.lines().collect();
    assert_eq!(lines.len(), 1, "{args:?}: not one line:\n{stderr}");
    assert!(
        lines[0].starts_with("tutorial13: ") && lines[0].contains(says),
        "{args:?}: {:?} does not say {says:?}",
        lines[0]
    );
    assert_eq!(files_under(dir), before, "{args:?} wrote a file");
}

// Fails if any bad input is not refused with one line saying why (naming the file where there is
// one), a non-zero exit and no file written: too few photos, a --light count that differs, lights
// (nearly) coplanar, a --light that is not X,Y,Z or not a direction, photos of different sizes, a
// photo that is not an image, is a JPEG cut short or is missing, an output named neither .png nor .bmp, an output into a
// missing folder, -o and --albedo the same file, a --shadow out of range.
#[test]
fn bad_input_is_one_line_and_writes_nothing() {
    let dir = scratch("refusals");
    let surface = wall();
    let three = shoot(&dir, &surface, &lights(3), Format::Png, |_, _| {});
    let (photos, lights3) = (&three[..3], &three[3..]);
    std::fs::write(dir.join("notes.png"), "not a photo").unwrap();
    // A JPEG cut short (zune-jpeg's message for it ends in a line break).
    let jpeg = save(
        &read_rgb(&dir.join("photo1.png")),
        &dir,
        "whole",
        Format::Jpeg(90),
    );
    let bytes = std::fs::read(dir.join(&jpeg)).unwrap();
    std::fs::write(dir.join("cut.jpg"), &bytes[..bytes.len() / 3]).unwrap();
    std::fs::remove_file(dir.join(jpeg)).unwrap();
    let small = image::imageops::resize(
        &read_rgb(&dir.join("photo2.png")),
        128,
        128,
        image::imageops::FilterType::Triangle,
    );
    small.save(dir.join("small.png")).unwrap();
    let before = files_under(&dir);
    let args = |photos: &[&str], lights: &[&str], rest: &[&str]| -> Vec<String> {
        let mut args = vec!["photometric".to_string()];
        args.extend(photos.iter().map(|s| s.to_string()));
        for l in lights {
            args.extend(["--light".to_string(), l.to_string()]);
        }
        args.extend(rest.iter().map(|s| s.to_string()));
        args
    };
    let ok_photos: Vec<&str> = photos.iter().map(String::as_str).collect();
    let ok_lights: Vec<&str> = lights3
        .iter()
        .skip(1)
        .step_by(2)
        .map(String::as_str)
        .collect();
    let out = ["-o", "normal.png"];
    let cases: Vec<(Vec<String>, &str)> = vec![
        (
            args(&ok_photos[..2], &ok_lights[..2], &out),
            "needs at least three photos, each under its own light; got 2",
        ),
        (
            args(&ok_photos, &ok_lights[..2], &out),
            "3 photos but 2 --light directions",
        ),
        (
            args(&ok_photos, &["1,0,0", "0,1,0", "-1,-1,0"], &out),
            "nearly coplanar (within 0.0° of one plane",
        ),
        (
            args(&ok_photos, &["0,0,1", "0.02,0,1", "0,-0.02,1"], &out),
            "nearly coplanar",
        ),
        (
            args(&ok_photos, &[ok_lights[0], "1,2", ok_lights[2]], &out),
            "--light 1,2: not three numbers X,Y,Z",
        ),
        (
            args(&ok_photos, &[ok_lights[0], "0,0,0", ok_lights[2]], &out),
            "--light 0,0,0: not a direction",
        ),
        (
            args(&[ok_photos[0], ok_photos[1], "small.png"], &ok_lights, &out),
            "small.png: 128×128, but photo0.png is 256×256",
        ),
        (
            args(&[ok_photos[0], "notes.png", ok_photos[2]], &ok_lights, &out),
            "notes.png: not a photo this program reads",
        ),
        (
            args(&[ok_photos[0], "cut.jpg", ok_photos[2]], &ok_lights, &out),
            "cut.jpg: not a photo this program reads",
        ),
        (
            args(
                &[ok_photos[0], "missing.png", ok_photos[2]],
                &ok_lights,
                &out,
            ),
            "missing.png: No such file",
        ),
        (
            args(&ok_photos, &ok_lights, &["-o", "normal.jpg"]),
            "normal.jpg: cannot write: name the output .bmp or .png",
        ),
        (
            args(
                &ok_photos,
                &ok_lights,
                &["-o", "normal.png", "--albedo", "no/albedo.png"],
            ),
            "--albedo no/albedo.png: no such folder no (create it first)",
        ),
        (
            args(
                &ok_photos,
                &ok_lights,
                &["-o", "same.png", "--albedo", "same.png"],
            ),
            "-o and --albedo name the same file",
        ),
        (
            args(
                &ok_photos,
                &ok_lights,
                &["-o", "normal.png", "--shadow", "1.5"],
            ),
            "--shadow 1.5: must be a linear luminance from 0 to below 1",
        ),
    ];
    for (args, says) in cases {
        assert_refused(&dir, &args, says, &before);
    }
}

// Fails if the one-photo guess does not make a raised, albedo-flat dome lit from the front (bright
// on top, darker down its sides) into a normal map whose slopes lean outwards on every side: red above
// 128 on the right flank and below on the left, green above 128 on the upper flank and below on the
// lower (green up). Or if --radius is accepted without --from-photo.
#[test]
fn from_photo_turns_a_lit_dome_into_outward_slopes() {
    let dir = scratch("from-photo-dome");
    save(&dome_photo(1.0), &dir, "dome", Format::Png);
    let normal = from_photo(&dir, "dome.png", "normal.png");
    let (c, r) = (64u32, 20u32);
    let flanks = [
        ((c + r, c), 0, true),
        ((c - r, c), 0, false),
        ((c, c - r), 1, true),
        ((c, c + r), 1, false),
    ];
    for ((x, y), channel, above) in flanks {
        let v = normal.get_pixel(x, y)[channel];
        assert_eq!(v > 128, above, "({x}, {y}) channel {channel}: {v}");
        assert!(
            v.abs_diff(128) >= 8,
            "({x}, {y}) channel {channel}: only {v}"
        );
    }
    let out = run(tutorial13()
        .args(["normalmap", "dome.png", "-o", "x.png", "--radius", "8"])
        .current_dir(&dir));
    assert!(
        !out.status.success(),
        "--radius without --from-photo was accepted"
    );
    assert!(!dir.join("x.png").exists());
}

// The limitation docs/tools.md states, as a test: an engraved dome (the same shape, sunk) lit from the
// front photographs exactly as the raised one does, so the guess gives the same normal map for both,
// though their true slopes point opposite ways. Fails if the two photos or the two maps differ.
#[test]
fn from_photo_cannot_tell_raised_from_engraved() {
    let dir = scratch("from-photo-engraved");
    let (raised, engraved) = (dome_photo(1.0), dome_photo(-1.0));
    assert_eq!(raised, engraved, "a frontal light shows n_z only");
    save(&raised, &dir, "raised", Format::Png);
    save(&engraved, &dir, "engraved", Format::Png);
    let raised = from_photo(&dir, "raised.png", "raised-normal.png");
    let engraved = from_photo(&dir, "engraved.png", "engraved-normal.png");
    assert_eq!(raised, engraved);
}

// Fails if a photo of one colour does not give the flat map (128, 128, 255) everywhere, whatever
// the radius, including radii wider than the photo (the blur wraps around it several times).
#[test]
fn from_photo_of_one_colour_is_flat_at_any_radius() {
    let dir = scratch("from-photo-flat");
    save(
        &RgbImage::from_pixel(37, 20, image::Rgb([180, 120, 60])),
        &dir,
        "plain",
        Format::Png,
    );
    for radius in ["1", "16", "50", "4096"] {
        let args = [
            "normalmap",
            "--from-photo",
            "plain.png",
            "-o",
            "flat.png",
            "--radius",
            radius,
        ];
        let out = run(tutorial13().args(args).current_dir(&dir));
        assert!(out.status.success(), "{}", text(&out.stderr));
        let map = read_rgb(&dir.join("flat.png"));
        assert_eq!(map.dimensions(), (37, 20));
        assert!(
            map.pixels().all(|p| p.0 == [128, 128, 255]),
            "--radius {radius}"
        );
    }
}

// What --radius does, predicted: a photo whose linear brightness is 0.5 + 0.2·sin(2πx/64) (stripes
// 64 texels wide, constant down the picture) becomes heights of the stripes minus their blur. Three
// box blurs of 2R + 1 texels scale a sinusoid of period 64 by A³, A = Σ_{|j|≤R} cos(2πj/64) / (2R + 1),
// so the heights keep an amplitude of 0.2·(1 − A³): 0.2 · 0.0096 at R = 1 (the stripes are wider
// than the radius, so they count as lighting and go), 0.2 · 1.0000 at R = 32 (they count as relief).
// Fails if the heights' amplitude is off that by more than 3 % at either radius (the photo is a
// 16-bit PNG, so quantisation costs about 0.1 %), or if the binary's map for either radius is not
// bit for bit the library's map of those heights (--radius ignored or read wrong).
#[test]
fn from_photo_radius_decides_which_widths_are_relief() {
    use tutorial13::normalmap::{normal_map, Green, Kernel, NormalMapOptions};
    use tutorial13::photometric::photo::height_from_photo;

    let dir = scratch("from-photo-radius");
    let period = 64.0f64;
    let photo = image::ImageBuffer::from_fn(128, 8, |x, _| {
        let linear = 0.5 + 0.2 * (std::f64::consts::TAU * (x as f64 + 0.5) / period).sin();
        let stored = Encoding::Srgb.from_linear(linear as f32);
        image::Luma([(f64::from(stored) * 65535.0).round() as u16])
    });
    photo.save(dir.join("stripes.png")).unwrap();
    let loaded = Photo::load(&dir.join("stripes.png")).unwrap();
    for radius in [1u32, 32] {
        let a = (-(radius as i32)..=radius as i32)
            .map(|j| (std::f64::consts::TAU * f64::from(j) / period).cos())
            .sum::<f64>()
            / f64::from(2 * radius + 1);
        let predicted = 0.2 * (1.0 - a.powi(3));
        let heights = height_from_photo(&loaded, radius);
        let (low, high) = heights
            .values
            .iter()
            .fold((f32::MAX, f32::MIN), |(l, h), &v| (l.min(v), h.max(v)));
        let amplitude = f64::from(high - low) / 2.0;
        println!("--radius {radius}: amplitude {amplitude:.6}, predicted {predicted:.6}");
        assert!(
            (amplitude / predicted - 1.0).abs() < 0.03,
            "--radius {radius}: heights' amplitude {amplitude:.6}, predicted {predicted:.6}"
        );

        let out = format!("r{radius}.png");
        let args = ["normalmap", "--from-photo", "stripes.png", "-o", &out];
        let radius_text = radius.to_string();
        let ran = run(tutorial13()
            .args(args)
            .args(["--strength", "40", "--radius", &radius_text])
            .current_dir(&dir));
        assert!(ran.status.success(), "{}", text(&ran.stderr));
        let options = NormalMapOptions {
            strength: 40.0,
            kernel: Kernel::Sobel,
            green: Green::Up,
            two_channel: false,
        };
        let expected: Vec<u8> = normal_map(&heights, options).concat();
        assert!(
            read_rgb(&dir.join(&out)).into_raw() == expected,
            "--radius {radius}: the binary's map is not the library's for these heights"
        );
    }
}

/// A 128² photo of a grey dome of radius 40 texels and height `sign` · 20 in the middle of a flat
/// surface, lit from the camera (the light along z): brightness n_z, albedo 0.5.
fn dome_photo(sign: f32) -> RgbImage {
    RgbImage::from_fn(128, 128, |x, y| {
        let (dx, dy) = (x as f32 + 0.5 - 64.0, 64.0 - (y as f32 + 0.5));
        let d2 = dx * dx + dy * dy;
        // Height sign · 20 · (1 − d²/40²): slope −sign · 40 · (dx, dy) / 40².
        let slope = if d2 < 1600.0 {
            sign * 40.0 / 1600.0
        } else {
            0.0
        };
        let n = Vec3::new(slope * dx, slope * dy, 1.0).normalize();
        image::Rgb([round_to_u8(Encoding::Srgb.from_linear(0.5 * n.z) * 255.0); 3])
    })
}

/// `tutorial13 normalmap --from-photo PHOTO -o OUT --strength 40` in `dir`; the map it wrote.
fn from_photo(dir: &Path, photo: &str, out: &str) -> RgbImage {
    let args = [
        "normalmap",
        "--from-photo",
        photo,
        "-o",
        out,
        "--strength",
        "40",
    ];
    let run = run(tutorial13().args(args).current_dir(dir));
    assert!(run.status.success(), "{}", text(&run.stderr));
    read_rgb(&dir.join(out))
}

/// The wall scene's frame (512×384, `--scene wall --assets DIR`), drawn by the binary.
fn wall_frame(assets: &Path) -> RgbImage {
    let assets = assets.to_str().unwrap();
    let args = ["--scene", "wall", "--assets", assets, "--size", "512x384"];
    headless_screenshot(assets.as_ref(), "frame.png", &args)
}

/// A folder `name`/wall/ holding the wall's own diffuse.bmp and normal.bmp, with `change` applied.
#[track_caller]
fn wall_assets(name: &str, change: impl FnOnce(&Path)) -> PathBuf {
    let dir = scratch(name);
    std::fs::create_dir_all(dir.join("wall")).unwrap();
    for file in ["diffuse.bmp", "normal.bmp"] {
        std::fs::copy(
            own_assets().join("wall").join(file),
            dir.join("wall").join(file),
        )
        .unwrap();
    }
    change(&dir.join("wall"));
    dir
}

// Fails if either tool's output, written where the wall scene reads its maps (--assets DIR:
// wall/normal.bmp, wall/diffuse.bmp), does not render, or if the photometric maps (normal and albedo
// from four photos) draw a wall less like the one drawn from its own maps than stated (hybrid
// similarity, 1 = identical; measured 0.992), or if the one-photo guess does not land between the
// flat wall and the photometric one (measured 0.420: its joints come out raised; a flat normal map
// gives 0.396, the photometric maps 0.992), or if it draws nearly the flat wall.
// It also makes docs/tools.md's picture, docs/photometric.png: first row the four photos, second the
// recovered normal map and the wall drawn with its own maps, with the photometric maps and with the
// guess from its diffuse map. The picture must match bit for bit on the reference renderer
// (similarity ≥ 0.95 elsewhere), or with TUTORIAL13_UPDATE_DOCS=1 it is rewritten.
#[test]
fn both_outputs_light_the_wall_as_the_readme_shows() {
    let surface = wall();
    let photos_dir = scratch("readme-photos");
    let mut args = shoot(&photos_dir, &surface, &lights(4), Format::Png, |_, _| {});
    let photos: Vec<RgbImage> = args[..4]
        .iter()
        .map(|p| read_rgb(&photos_dir.join(p)))
        .collect();
    let measured = wall_assets("readme-photometric", |wall| {
        let (normal, diffuse) = (wall.join("normal.bmp"), wall.join("diffuse.bmp"));
        args.extend(["-o".into(), normal.display().to_string()]);
        args.extend(["--albedo".into(), diffuse.display().to_string()]);
        photometric(&photos_dir, &args);
    });
    let guessed = wall_assets("readme-from-photo", |wall| {
        let diffuse = own_assets().join("wall/diffuse.bmp");
        let out = run(tutorial13()
            .args(["normalmap", "--from-photo"])
            .arg(diffuse)
            .arg("-o")
            .arg(wall.join("normal.bmp")));
        assert!(out.status.success(), "{}", text(&out.stderr));
    });
    let flat = wall_assets("readme-flat", |wall| {
        let flat = tutorial13::assets::encode_bmp(&vec![[128, 128, 255]; 256 * 256], 256).unwrap();
        std::fs::write(wall.join("normal.bmp"), flat).unwrap();
    });
    let own = wall_frame(&wall_assets("readme-own", |_| {}));
    // Compared and shown on the wall's square only (the background would make any two alike).
    let on_wall: Vec<(u32, u32)> = own
        .enumerate_pixels()
        .filter(|(_, _, p)| !is_background(p))
        .map(|(x, y, _)| (x, y))
        .collect();
    let (x0, y0) = on_wall
        .iter()
        .fold((u32::MAX, u32::MAX), |(a, b), &(x, y)| (a.min(x), b.min(y)));
    let (x1, y1) = on_wall
        .iter()
        .fold((0, 0), |(a, b), &(x, y)| (a.max(x), b.max(y)));
    let square = |frame: RgbImage| {
        image::imageops::crop_imm(&frame, x0, y0, x1 + 1 - x0, y1 + 1 - y0).to_image()
    };
    let own = square(own);
    let [measured_frame, guessed_frame, flat_frame] =
        [&measured, &guessed, &flat].map(|assets| square(wall_frame(assets)));
    let score = |frame: &RgbImage, name: &str| {
        hybrid_score(&own, frame, &format!("photometric-wall-{name}"), 0.0)
    };
    let measured_score = score(&measured_frame, "photometric");
    let guessed_score = score(&guessed_frame, "from-photo");
    let flat_score = score(&flat_frame, "flat");
    println!(
        "similarity to the wall drawn with its own maps: photometric {measured_score:.4}, one \
         photo {guessed_score:.4}, flat normals {flat_score:.4}"
    );
    assert!(
        measured_score > 0.99,
        "photometric maps: {measured_score:.4}"
    );
    assert!(
        flat_score < guessed_score && guessed_score < measured_score,
        "the one-photo guess {guessed_score:.4} is not between the flat wall {flat_score:.4} and \
         the photometric one {measured_score:.4}"
    );
    let guess_against_flat = hybrid_score(&flat_frame, &guessed_frame, "photometric-guess", 0.0);
    assert!(
        guess_against_flat < 0.8,
        "the one-photo guess draws nearly the flat wall: {guess_against_flat:.4}"
    );

    let tile = |image: &RgbImage| {
        image::imageops::resize(image, 128, 128, image::imageops::FilterType::Triangle)
    };
    let normal = read_rgb(&measured.join("wall/normal.bmp"));
    let tiles = photos
        .iter()
        .chain([&normal, &own, &measured_frame, &guessed_frame]);
    let mut picture = RgbImage::new(512, 256);
    for (i, image) in tiles.enumerate() {
        let (x, y) = (128 * (i as i64 % 4), 128 * (i as i64 / 4));
        image::imageops::replace(&mut picture, &tile(image), x, y);
    }
    crate::common::check_docs_picture(&picture, "docs/photometric.png", "photometric");
}

/// FNV-1a (64 bits) of the decoded RGB texels of the image at `path`: a record of its exact output
/// that does not depend on how the PNG encoder compresses.
fn texel_hash(path: &Path) -> u64 {
    read_rgb(path)
        .as_raw()
        .iter()
        .fold(0xcbf2_9ce4_8422_2325, |h, &b| {
            (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
        })
}

// Fails if least squares (the default up to five photos, `--solver lstsq` from six) writes any
// texel of the normal map or the albedo other than before the robust solver, intensities, masks
// and sets of more than 64 photos were added: the hashes were recorded from that version's binary
// on the wall's 8-bit PNG photos under 3, 4, 8 and 64 lights.
#[test]
fn least_squares_writes_what_it_wrote_before() {
    let surface = wall();
    let recorded: [(usize, u64, u64); 4] = [
        (3, 0x0bef_8383_4368_be06, 0x5f17_32ad_45cf_2656),
        (4, 0x4d04_2872_9e64_f6dd, 0x70f8_63f0_3afb_1dcd),
        (8, 0xa6fd_4d3a_400b_2695, 0x8af8_58ce_95f9_04fc),
        (64, 0x15d1_0e9a_6c7e_4af3, 0xc07b_2022_1635_2585),
    ];
    let mut wrong = Vec::new();
    for (k, normal_hash, albedo_hash) in recorded {
        let dir = scratch(&format!("lstsq-hash-{k}"));
        let mut args = shoot(&dir, &surface, &lights(k), Format::Png, |_, _| {});
        args.extend(["-o", "normal.png", "--albedo", "albedo.png"].map(String::from));
        if k >= 6 {
            args.extend(["--solver", "lstsq"].map(String::from));
        }
        photometric(&dir, &args);
        let got = (
            texel_hash(&dir.join("normal.png")),
            texel_hash(&dir.join("albedo.png")),
        );
        println!("{k} photos: normal {:#x}, albedo {:#x}", got.0, got.1);
        if got != (normal_hash, albedo_hash) {
            wrong.push(k);
        }
    }
    assert!(wrong.is_empty(), "other output with {wrong:?} photos");
}

/// A shiny scene the robust solver's tests photograph: true unit normals and linear albedo per
/// texel (x right, y up the picture, z towards the camera; row 0 at the top), the mask of what is
/// measured, and whether a texel's point sees a light (cast shadows).
struct Scene {
    size: u32,
    normals: Vec<Vec3>,
    albedo: Vec<[f32; 3]>,
    mask: Vec<bool>,
    /// The point each texel shows, in texels (z up out of the plane).
    points: Vec<Vec3>,
    /// Whether anything of the scene lies between `point` and the light towards `l`.
    occluded: fn(Vec3, Vec3) -> bool,
}

impl Scene {
    /// A scene of `texels`, each its normal, point, albedo and whether it is measured, in order.
    fn new(texels: Vec<(Vec3, Vec3, [f32; 3], bool)>, occluded: fn(Vec3, Vec3) -> bool) -> Scene {
        Scene {
            size: SIDE,
            normals: texels.iter().map(|t| t.0).collect(),
            points: texels.iter().map(|t| t.1).collect(),
            albedo: texels.iter().map(|t| t.2).collect(),
            mask: texels.iter().map(|t| t.3).collect(),
            occluded,
        }
    }
}

/// Side of the scenes' photos, in texels.
const SIDE: u32 = 96;
/// The sphere's centre (it rests on the plane z = 0) and radius.
const SPHERE: (f32, f32, f32) = (48.0, 48.0, 28.0);
/// Blinn-Phong's specular weight (white, as a dielectric's) and exponent.
const SHINE: (f32, f32) = (0.35, 100.0);

/// The texel centre (x, y up) of texel `i`.
fn texel_xy(i: usize) -> (f32, f32) {
    let (col, row) = ((i as u32 % SIDE) as f32, (i as u32 / SIDE) as f32);
    (col + 0.5, SIDE as f32 - row - 0.5)
}

/// A sphere resting on a plane, seen from above: the sphere shades itself (attached shadows) and
/// casts its shadow on the plane. Measured: the sphere and the plane around it within 1.6 radii.
fn sphere_on_plane() -> Scene {
    let (cx, cy, r) = SPHERE;
    let texels = (0..(SIDE * SIDE) as usize).map(|i| {
        let (x, y) = texel_xy(i);
        let d2 = (x - cx).powi(2) + (y - cy).powi(2);
        let measured = d2 < (1.6 * r).powi(2);
        if d2 < r * r {
            let z = (r * r - d2).sqrt();
            let n = Vec3::new(x - cx, y - cy, z) / r;
            (n, Vec3::new(x, y, r + z), [0.55, 0.35, 0.2], measured)
        } else {
            (Vec3::Z, Vec3::new(x, y, 0.0), [0.3, 0.4, 0.5], measured)
        }
    });
    fn occluded(p: Vec3, l: Vec3) -> bool {
        // Only the plane is shadowed by something else: does the ray p + t·l meet the sphere?
        let centre = Vec3::new(SPHERE.0, SPHERE.1, SPHERE.2);
        if p.z > 0.0 {
            return false;
        }
        let to = centre - p;
        let along = to.dot(l);
        along > 0.0 && to.length_squared() - along * along < SPHERE.2 * SPHERE.2
    }
    Scene::new(texels.collect(), occluded)
}

/// The bumpy surface's height, in texels: Gaussian bumps and dents of differing widths.
fn bump_height(x: f32, y: f32) -> (f32, Vec3) {
    const BUMPS: [(f32, f32, f32, f32); 6] = [
        (24.0, 26.0, 10.0, 7.0),
        (66.0, 30.0, -7.0, 9.0),
        (40.0, 62.0, 12.0, 8.0),
        (76.0, 72.0, 8.0, 5.0),
        (18.0, 78.0, -5.0, 6.0),
        (56.0, 48.0, 5.0, 4.0),
    ];
    let (mut h, mut dx, mut dy) = (0.0, 0.0, 0.0);
    for (bx, by, height, width) in BUMPS {
        let (u, v) = (x - bx, y - by);
        let e = height * (-(u * u + v * v) / (2.0 * width * width)).exp();
        h += e;
        dx -= e * u / (width * width);
        dy -= e * v / (width * width);
    }
    (h, Vec3::new(-dx, -dy, 1.0).normalize())
}

/// A height field of bumps and dents: attached shadows, and shadows the bumps cast on their
/// surroundings and on each other (found by marching along the ray over the height field).
/// Measured: all but a border of 2 texels.
fn bumpy() -> Scene {
    let border = |c: f32| !(2.0..SIDE as f32 - 2.0).contains(&c);
    let texels = (0..(SIDE * SIDE) as usize).map(|i| {
        let (x, y) = texel_xy(i);
        let (h, n) = bump_height(x, y);
        (
            n,
            Vec3::new(x, y, h),
            [0.5, 0.45, 0.35],
            !border(x) && !border(y),
        )
    });
    fn occluded(p: Vec3, l: Vec3) -> bool {
        // Half-texel steps along the ray's footprint, until it is above the highest bump.
        let step = 0.5 / l.truncate().length().max(1e-3);
        let mut t = step;
        loop {
            let q = p + l * t;
            if q.z > 13.0
                || !(0.0..SIDE as f32).contains(&q.x)
                || !(0.0..SIDE as f32).contains(&q.y)
            {
                return false;
            }
            if bump_height(q.x, q.y).0 > q.z + 0.05 {
                return true;
            }
            t += step;
        }
    }
    Scene::new(texels.collect(), occluded)
}

/// The photo of `scene` under a distant light towards `l` of brightness `e`: e × (albedo · n·l +
/// Blinn-Phong's white highlight), where lit, in linear light, stored as a 16-bit PNG as capture
/// sets ship their photos (clipped at full scale).
fn render(scene: &Scene, l: Vec3, e: [f32; 3]) -> image::ImageBuffer<image::Rgb<u16>, Vec<u16>> {
    let half = (l + Vec3::Z).normalize();
    let (shine, exponent) = SHINE;
    let samples = (0..scene.normals.len()).flat_map(|i| {
        let n = scene.normals[i];
        let lit = n.dot(l);
        let value = if lit <= 0.0 || (scene.occluded)(scene.points[i], l) {
            [0.0; 3]
        } else {
            let specular = shine * n.dot(half).max(0.0).powf(exponent);
            [0, 1, 2].map(|c| e[c] * (scene.albedo[i][c] * lit + specular))
        };
        value.map(|v| (v.clamp(0.0, 1.0) * 65535.0).round() as u16)
    });
    image::ImageBuffer::from_raw(scene.size, scene.size, samples.collect()).unwrap()
}

/// Writes `scene`'s capture into `dir` as public sets lay theirs out: 001.png … 096.png,
/// light_directions.txt and light_intensities.txt (one line per photo), mask.png. Returns the
/// photos' names.
fn capture(dir: &Path, scene: &Scene) -> Vec<String> {
    let (mut directions, mut intensities) = (String::new(), String::new());
    let mut names = Vec::new();
    for (k, (l, e)) in rig().into_iter().enumerate() {
        let name = format!("{:03}.png", k + 1);
        render(scene, l, e).save(dir.join(&name)).unwrap();
        directions += &format!("{} {} {}\n", l.x, l.y, l.z);
        intensities += &format!("{} {} {}\n", e[0], e[1], e[2]);
        names.push(name);
    }
    std::fs::write(dir.join("light_directions.txt"), directions).unwrap();
    std::fs::write(dir.join("light_intensities.txt"), intensities).unwrap();
    let mask = image::GrayImage::from_fn(scene.size, scene.size, |x, y| {
        image::Luma([if scene.mask[(y * scene.size + x) as usize] {
            255
        } else {
            0
        }])
    });
    mask.save(dir.join("mask.png")).unwrap();
    names
}

/// What every run on a capture is given besides its lights: its mask, linear photos, a 16-bit
/// normal map, and `-o` (the name follows).
const CAPTURE_OPTIONS: [&str; 6] = ["--mask", "mask.png", "--linear", "--depth", "16", "-o"];

/// Runs `photometric` on the capture in `dir` (its photos `names`, linear, its lights' files and
/// mask, a 16-bit normal map) with `extra` arguments; returns the mean angle, in degrees, between
/// the normal map and `scene`'s normals over its mask.
fn solve_capture(dir: &Path, scene: &Scene, names: &[String], extra: &[&str]) -> f64 {
    let mut args = names.to_vec();
    args.extend(["--lights", "light_directions.txt"].map(String::from));
    args.extend(CAPTURE_OPTIONS.map(String::from));
    args.push("normal.png".into());
    args.extend(extra.iter().map(|s| s.to_string()));
    photometric(dir, &args);
    let map = image::open(dir.join("normal.png")).unwrap();
    assert_eq!(
        map.color(),
        image::ColorType::Rgb16,
        "--depth 16 wrote no 16-bit PNG"
    );
    let map = map.into_rgb16();
    let decode = |p: [u16; 3]| Vec3::from(p.map(|c| f32::from(c) / 32767.5 - 1.0)).normalize();
    let errors = map.pixels().enumerate().filter_map(|(i, p)| {
        if !scene.mask[i] {
            assert_eq!(p.0, [32768, 32768, 65535], "texel {i} outside the mask");
            return None;
        }
        Some(f64::from(
            decode(p.0).angle_between(scene.normals[i]).to_degrees(),
        ))
    });
    mean(errors)
}

// Fails if photometric stereo does not take 96 16-bit photos with their light files and mask, or if,
// on a shiny sphere casting its shadow on a plane and on a shiny bumpy surface shadowing itself
// (Blinn-Phong highlights, 96 lights of differing RGB brightness), the robust default's mean error
// over the mask is above 1.5°, or least squares (`--solver lstsq`) is not worse than it by at least
// 2°, or the texels outside the mask are not the flat normal. Measured: sphere robust 0.28°, least
// squares 4.45°; bumps robust 0.41°, least squares 3.18°.
#[test]
fn the_robust_solver_sees_through_highlights_and_cast_shadows() {
    for (name, scene) in [("sphere", sphere_on_plane()), ("bumps", bumpy())] {
        let dir = scratch(&format!("shiny-{name}"));
        let names = capture(&dir, &scene);
        let calibrated = ["--intensities", "light_intensities.txt"];
        let robust = solve_capture(&dir, &scene, &names, &calibrated);
        let lstsq = solve_capture(
            &dir,
            &scene,
            &names,
            &[calibrated[0], calibrated[1], "--solver", "lstsq"],
        );
        println!("{name}: robust {robust:.3}°, least squares {lstsq:.3}°");
        assert!(robust <= 1.5, "{name}: robust mean error {robust:.3}°");
        assert!(
            lstsq >= robust + 2.0,
            "{name}: least squares {lstsq:.3}° is not worse than robust {robust:.3}°"
        );
    }
}

// Fails if the lights' brightnesses are not divided out: the same sphere solved as if every light
// were equally bright must be further off than stated, and each light's brightness given as
// `--intensity R,G,B` (and its direction as `--light`) must give the file's result exactly.
// Measured: with the intensities 0.28°, without 3.49° (more than 2° worse is asserted).
#[test]
fn each_lights_brightness_is_divided_out() {
    let scene = sphere_on_plane();
    let dir = scratch("shiny-intensities");
    let names = capture(&dir, &scene);
    let calibrated = solve_capture(
        &dir,
        &scene,
        &names,
        &["--intensities", "light_intensities.txt"],
    );
    let from_files = std::fs::read(dir.join("normal.png")).unwrap();
    let uncalibrated = solve_capture(&dir, &scene, &names, &[]);
    println!("with the intensities {calibrated:.3}°, without {uncalibrated:.3}°");
    assert!(
        uncalibrated > calibrated + 2.0,
        "ignoring the intensities costs only {:.3}°",
        uncalibrated - calibrated
    );
    // The same lights as flags instead of the files (the same numbers: `{}` prints the shortest text
    // that reads back as the same f32).
    let mut args = names.clone();
    for (l, e) in rig() {
        args.extend(["--light".into(), format!("{},{},{}", l.x, l.y, l.z)]);
        args.extend(["--intensity".into(), format!("{},{},{}", e[0], e[1], e[2])]);
    }
    args.extend(CAPTURE_OPTIONS.map(String::from));
    args.push("flags.png".into());
    photometric(&dir, &args);
    assert!(
        std::fs::read(dir.join("flags.png")).unwrap() == from_files,
        "--light and --intensity flags give another map than the files"
    );
}

// Fails if any bad capture input is not refused with one line saying why (naming the file where
// there is one), a non-zero exit and no file written: a lights file or an intensities file with
// another count than the photos, `--intensity` flags of another count, a zero brightness in a file, a
// negative one in a flag, a mask of another size, a lights file line that is not x y z, a lights
// file that is missing, `--depth 16` into a BMP. (Photos of different sizes: see
// bad_input_is_one_line_and_writes_nothing.)
#[test]
fn bad_capture_files_are_one_line_and_write_nothing() {
    let dir = scratch("capture-refusals");
    let surface = wall();
    let three = shoot(&dir, &surface, &lights(3), Format::Png, |_, _| {});
    let directions: String = lights(3)
        .iter()
        .map(|l| format!("{} {} {}\n", l.x, l.y, l.z))
        .collect();
    let two_lines: String = directions
        .lines()
        .take(2)
        .map(|l| l.to_string() + "\n")
        .collect();
    std::fs::write(dir.join("lights.txt"), &directions).unwrap();
    std::fs::write(dir.join("two-lights.txt"), two_lines).unwrap();
    std::fs::write(dir.join("bad-lights.txt"), "1 0\n0 1 1\n-1 0 1\n").unwrap();
    std::fs::write(dir.join("two-intensities.txt"), "1 1 1\n0.5 0.5 0.5\n").unwrap();
    std::fs::write(dir.join("zero.txt"), "1 1 1\n# dark\n0.8 0 0.8\n1\n").unwrap();
    RgbImage::new(128, 128)
        .save(dir.join("small-mask.png"))
        .unwrap();
    let before = files_under(&dir);
    let command = |rest: &[&str]| -> Vec<String> {
        let mut args = vec!["photometric".to_string()];
        args.extend(three[..3].iter().cloned());
        args.extend(rest.iter().map(|s| s.to_string()));
        args.extend(["-o", "normal.png"].map(String::from));
        args
    };
    let lit = |rest: &[&str]| command(&[&["--lights", "lights.txt"], rest].concat());
    let cases: Vec<(Vec<String>, &str)> = vec![
        (
            command(&["--lights", "two-lights.txt"]),
            "two-lights.txt: 2 directions for 3 photos",
        ),
        (
            lit(&["--intensities", "two-intensities.txt"]),
            "two-intensities.txt: 2 intensities for 3 photos",
        ),
        (
            lit(&["--intensity", "1", "--intensity", "1"]),
            "--intensity: 2 brightnesses for 3 photos",
        ),
        (
            lit(&["--intensities", "zero.txt"]),
            "zero.txt: line 3: each brightness must be a finite number above zero",
        ),
        (
            lit(&[
                "--intensity",
                "1",
                "--intensity",
                "-1,1,1",
                "--intensity",
                "1",
            ]),
            "--intensity -1,1,1: each brightness must be a finite number above zero",
        ),
        (
            lit(&["--mask", "small-mask.png"]),
            "small-mask.png: a 128×128 mask, but photo0.png is 256×256",
        ),
        (
            command(&["--lights", "bad-lights.txt"]),
            "bad-lights.txt: line 1: not three numbers x y z",
        ),
        (
            command(&["--lights", "missing.txt"]),
            "missing.txt: No such file",
        ),
        (
            {
                let mut args = lit(&["--depth", "16"]);
                *args.last_mut().unwrap() = "normal.bmp".into();
                args
            },
            "normal.bmp: cannot write: --depth 16 writes PNG only",
        ),
    ];
    for (args, says) in cases {
        assert_refused(&dir, &args, says, &before);
    }
}

/// A PNG that declares `width`×`height` 8-bit RGB texels and holds none: its signature, header, an
/// empty data chunk and its end, each chunk with its CRC.
fn png_header_only(width: u32, height: u32) -> Vec<u8> {
    let crc = |bytes: &[u8]| {
        !bytes.iter().fold(!0u32, |c, &b| {
            (0..8).fold(c ^ u32::from(b), |c, _| {
                (c >> 1) ^ (0xEDB8_8320 & 0u32.wrapping_sub(c & 1))
            })
        })
    };
    let mut png = b"\x89PNG\r\n\x1a\n".to_vec();
    let mut header = [width.to_be_bytes(), height.to_be_bytes()].concat();
    header.extend([8, 2, 0, 0, 0]);
    for (kind, data) in [(*b"IHDR", header), (*b"IDAT", vec![]), (*b"IEND", vec![])] {
        png.extend((data.len() as u32).to_be_bytes());
        let chunk = [&kind[..], &data].concat();
        png.extend(&chunk);
        png.extend(crc(&chunk).to_be_bytes());
    }
    png
}

// Fails if a set too large to hold in memory is not refused before its photos are decoded, in one
// line giving the bytes it would need, with nothing written: three photos whose headers declare
// 16 777 216 × 2 147 483 647 texels each (a PNG's tallest; rows short enough for the decoder to
// read the header), 6.5e17 bytes at 16 bits per channel: more than any 64-bit address space holds.
#[test]
fn a_set_too_large_for_memory_is_refused_with_its_size() {
    let dir = scratch("too-large");
    for k in 0..3 {
        std::fs::write(
            dir.join(format!("huge{k}.png")),
            png_header_only(1 << 24, i32::MAX as u32),
        )
        .unwrap();
    }
    let before = files_under(&dir);
    let mut args: Vec<String> = ["photometric", "huge0.png", "huge1.png", "huge2.png"]
        .map(String::from)
        .to_vec();
    args.extend(light_args(&lights(3)));
    args.extend(["-o", "normal.png"].map(String::from));
    let need = 3 * (1u128 << 24) * u128::from(i32::MAX as u32) * 6;
    let says = format!("3 photos of 16777216×2147483647 need {need} bytes");
    assert_refused(&dir, &args, &says, &before);
}

// Fails if a set of 8-bit photos is widened to 16 bits (twice the memory, for the same linear
// values), or if a set with one 16-bit photo is not widened whole (the solver reads every photo at
// the first one's depth): 8-bit stays 8-bit, and 8 + 16 + 8 becomes 16-bit with v × 257.
#[test]
fn load_photos_widens_a_set_only_if_one_is_deeper() {
    use tutorial13::photometric::load_photos;
    use tutorial13::photometric::photo::Samples;

    let dir = scratch("widen");
    let eight = image::RgbImage::from_fn(3, 2, |x, y| image::Rgb([x as u8 * 80, y as u8 * 200, 7]));
    let deep = image::ImageBuffer::<image::Rgb<u16>, _>::from_fn(3, 2, |x, _| {
        image::Rgb([x as u16 * 20000, 1, 65535])
    });
    eight.save(dir.join("a.png")).unwrap();
    eight.save(dir.join("b.png")).unwrap();
    deep.save(dir.join("deep.png")).unwrap();
    let paths = |names: &[&str]| names.iter().map(|n| dir.join(n)).collect::<Vec<_>>();

    let photos = load_photos(&paths(&["a.png", "b.png", "a.png"]), 2).unwrap();
    assert!(photos
        .iter()
        .all(|p| p.samples == Samples::Eight(eight.as_raw().clone())));

    let photos = load_photos(&paths(&["a.png", "deep.png", "b.png"]), 2).unwrap();
    let widened: Vec<u16> = eight.as_raw().iter().map(|&v| u16::from(v) * 257).collect();
    assert_eq!(photos[0].samples, Samples::Sixteen(widened.clone()));
    assert_eq!(photos[1].samples, Samples::Sixteen(deep.as_raw().clone()));
    assert_eq!(photos[2].samples, Samples::Sixteen(widened));
}
