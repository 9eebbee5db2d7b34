//! The `sprite` scene (article 001): a 2D normal-mapped rock lit by a point light with
//! constant-linear-quadratic falloff. Headless frames, measured against what the article describes;
//! each test prints the numbers it measured (`cargo test --release -- scene_sprite:: --nocapture`).

use std::path::{Path, PathBuf};

use glam::{DVec3, Vec2, Vec3};
use image::{Rgb, RgbImage};
use tutorial13::assets::encode_bmp;
use tutorial13::frontends::headless::{HeadlessOptions, HeadlessRenderer};
use tutorial13::scenes::sprite::assets::rock_height_map;
use tutorial13::scenes::sprite::{
    cursor_to_light, sprite_rect, Sprite, SpriteOptions, DEFAULT_LIGHT_Z, DIFFUSE_FILE,
    INDEPENDENT_FALLOFF, NORMAL_FILE, Z_MAX, Z_MIN,
};
use tutorial13::scenes::{SceneOptions, Setting};

use crate::common;
use crate::common::xvfb::{wait_for, Xvfb};
use crate::common::{assert_matches_golden, frame, own_assets, pixel_diff, scratch};

/// Side of the sprite's textures.
const TEXELS: u32 = 512;

/// The sprite with its light at `sprite`'s and its controls started by `starts`.
struct SpriteStart {
    sprite: SpriteOptions,
    starts: Vec<Setting<Sprite>>,
}

impl From<SpriteOptions> for SpriteStart {
    fn from(sprite: SpriteOptions) -> Self {
        SpriteStart {
            sprite,
            starts: Vec::new(),
        }
    }
}

fn sprite_options(
    assets: Option<PathBuf>,
    start: impl Into<SpriteStart>,
    size: (u32, u32),
) -> HeadlessOptions {
    let SpriteStart { sprite, starts } = start.into();
    HeadlessOptions {
        descriptor: tutorial13::scenes::descriptor::<Sprite>(),
        scene: SceneOptions {
            assets,
            ..Default::default()
        }
        .with(sprite)
        .starting(starts),
        width: size.0,
        height: size.1,
        ..Default::default()
    }
}

fn light_at(light: Vec3) -> SpriteOptions {
    SpriteOptions { light }
}

/// The light at `light`, the falloff resolution-independent or not.
fn light_and_falloff(light: Vec3, independent: bool) -> SpriteStart {
    SpriteStart {
        sprite: SpriteOptions { light },
        starts: vec![INDEPENDENT_FALLOFF.to(independent)],
    }
}

fn sprite_renderer(
    assets: Option<PathBuf>,
    start: impl Into<SpriteStart>,
    size: (u32, u32),
) -> HeadlessRenderer {
    common::renderer(&sprite_options(assets, start, size))
}

/// One frame of the project's own rock at 1024×768.
fn render_rock(start: impl Into<SpriteStart>) -> RgbImage {
    frame(&mut sprite_renderer(None, start, (1024, 768)))
}

fn luma(p: &Rgb<u8>) -> f64 {
    0.2126 * f64::from(p[0]) + 0.7152 * f64::from(p[1]) + 0.0722 * f64::from(p[2])
}

/// The sprite's pixels in image coordinates (top row first): left column, top row, side.
fn sprite_in_image(width: u32, height: u32) -> (u32, u32, u32) {
    let (x0, y0, side) = sprite_rect(width, height);
    (x0, height - y0 - side, side)
}

/// The light's x (0..1 across the window) over the centre of window pixel column `column`.
fn light_x(column: u32, width: u32) -> f32 {
    (column as f32 + 0.5) / width as f32
}

/// A folder with the sprite's two files: `diffuse` and `normals` as `TEXELS`² RGB, row 0 on top.
fn sprite_assets(name: &str, diffuse: &[[u8; 3]], normals: &[[u8; 3]]) -> PathBuf {
    let dir = scratch(name);
    std::fs::create_dir_all(dir.join("sprite")).unwrap();
    std::fs::write(dir.join(DIFFUSE_FILE), encode_bmp(diffuse, TEXELS).unwrap()).unwrap();
    std::fs::write(dir.join(NORMAL_FILE), encode_bmp(normals, TEXELS).unwrap()).unwrap();
    dir
}

/// A committed texture of the rock as RGB texels, picture row 0 (top) first.
fn own_texture(file: &str) -> Vec<[u8; 3]> {
    let path = own_assets().join(file);
    let image = image::open(&path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .into_rgb8();
    image.pixels().map(|p| p.0).collect()
}

/// White texels and a flat normal map (128, 128, 255): the frame is then the light's intensity.
fn flat_white_assets(name: &str) -> PathBuf {
    let n = (TEXELS * TEXELS) as usize;
    sprite_assets(name, &vec![[255; 3]; n], &vec![[128, 128, 255]; n])
}

/// The two set-ups the brightness tests measure, each with its own bound: the project's rock (`None`: the
/// scene's own assets) and [`flat_white_assets`] in a scratch folder `name`.
fn rock_and_flat_white<T>(
    name: &str,
    rock: T,
    flat_white: T,
) -> [(&'static str, Option<PathBuf>, T); 2] {
    let flat = flat_white_assets(name);
    [("rock", None, rock), ("flat white", Some(flat), flat_white)]
}

// Fails if the brightest part of the sprite does not follow the light: the column (row) of the
// largest mean brightness over the sprite must lie near the light's column (row) for the light over
// the sprite's left edge, centre and right edge (bottom, centre, top), and move the same way. With
// white texels and a flat normal map the peak is analytic: within 2 px (the flat texel's normal
// leans 0.3° towards +x and +y). On the rock, the rims facing the light catch it unevenly: within
// 48 px, under the 58-px height of the light (z 0.075 of 768). A light whose x or y went the wrong
// way (GL's y up against the image's y down) misses by hundreds of pixels.
#[test]
fn brightest_region_follows_the_light() {
    let (w, h) = (1024, 768);
    let (left, top, side) = sprite_in_image(w, h);
    let z = DEFAULT_LIGHT_Z;
    for (what, assets, tolerance) in rock_and_flat_white("brightest", 48, 2) {
        let render = |light: Vec3| {
            frame(&mut sprite_renderer(
                assets.clone(),
                light_at(light),
                (w, h),
            ))
        };
        for columns in [true, false] {
            let (line, targets) = if columns {
                ("column", [left, left + side / 2, left + side - 1])
            } else {
                ("row", [top + side - 1, top + side / 2, top])
            };
            let mut peaks = Vec::new();
            for target in targets {
                let light = if columns {
                    Vec3::new(light_x(target, w), 0.5, z)
                } else {
                    // Light y runs up the window (0 = bottom row), image rows run down.
                    Vec3::new(0.5, 1.0 - (target as f32 + 0.5) / h as f32, z)
                };
                let peak = brightest_line(&render(light), columns);
                println!(
                    "{what}: light ({:.4}, {:.4}) over {line} {target}: brightest {line} {peak}",
                    light.x, light.y
                );
                assert!(
                    peak.abs_diff(target) <= tolerance,
                    "{what}: light over {line} {target}, brightest {peak}"
                );
                peaks.push(peak);
            }
            if columns {
                assert!(peaks.windows(2).all(|p| p[0] < p[1]), "{what}: {peaks:?}");
            }
        }
    }
}

/// The sprite's column (`columns`) or row whose pixels add up to the most brightness, in image
/// coordinates.
fn brightest_line(frame: &RgbImage, columns: bool) -> u32 {
    let (left, top, side) = sprite_in_image(frame.width(), frame.height());
    let sums: Vec<f64> = (0..side)
        .map(|i| {
            (0..side)
                .map(|j| {
                    let (x, y) = if columns { (i, j) } else { (j, i) };
                    luma(frame.get_pixel(left + x, top + y))
                })
                .sum::<f64>()
        })
        .collect();
    (if columns { left } else { top }) + argmax(&sums) as u32
}

fn argmax(values: &[f64]) -> usize {
    values
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.total_cmp(b.1))
        .map(|(i, _)| i)
        .unwrap()
}

/// Mean and coefficient of variation (standard deviation / mean) of the sprite's brightness.
fn contrast(frame: &RgbImage) -> (f64, f64) {
    let (left, top, side) = sprite_in_image(frame.width(), frame.height());
    let values: Vec<f64> = (top..top + side)
        .flat_map(|y| (left..left + side).map(move |x| (x, y)))
        .map(|(x, y)| luma(frame.get_pixel(x, y)))
        .collect();
    let mean = values.iter().sum::<f64>() / values.len() as f64;
    let variance = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / values.len() as f64;
    (mean, variance.sqrt() / mean)
}

// Fails if raising the light does not flatten the image: the coefficient of variation of the
// sprite's brightness (standard deviation / mean) must fall at each step of z = 0.075, 0.15, 0.3,
// 0.6. On white texels with a flat normal map (the light's pool alone) by at least 20 % each time
// (measured 31 %, 54 % and 74 %); on the rock by at least 5 % (its own texture keeps its contrast
// at any height, so the steps shrink: measured 18 %, 17 % and 10 %).
#[test]
fn a_higher_light_gives_a_flatter_image() {
    for (what, assets, factor) in rock_and_flat_white("flatter", 0.95, 0.8) {
        let mut last: Option<f64> = None;
        for z in [0.075, 0.15, 0.3, 0.6] {
            let light = light_at(Vec3::new(0.5, 0.5, z));
            let (mean, cv) = contrast(&frame(&mut sprite_renderer(
                assets.clone(),
                light,
                (1024, 768),
            )));
            println!("{what}: z {z}: mean brightness {mean:.2}, coefficient of variation {cv:.4}");
            if let Some(previous) = last {
                assert!(
                    cv < factor * previous,
                    "{what}: z {z}: {cv:.4} not below {factor:.3} × {previous:.4}"
                );
            }
            last = Some(cv);
        }
    }
}

/// What the article's shader gives, in 0..255 per channel, for a white texel with a flat
/// (128, 128, 255) normal at window pixel (`column`, `row` from the top), computed here in f64.
/// `pixels_per_unit`: `None` for the article's falloff in window heights, else the
/// resolution-independent one.
fn expected(
    column: u32,
    row: u32,
    size: (u32, u32),
    light: Vec3,
    pixels_per_unit: Option<f64>,
) -> [f64; 3] {
    let (w, h) = (f64::from(size.0), f64::from(size.1));
    // gl_FragCoord: pixel centres, y up.
    let fragment = (f64::from(column) + 0.5, h - f64::from(row) - 0.5);
    let light = light.as_dvec3();
    let direction = match pixels_per_unit {
        None => DVec3::new(
            (light.x - fragment.0 / w) * w / h,
            light.y - fragment.1 / h,
            light.z,
        ),
        Some(unit) => DVec3::new(
            (light.x * w - fragment.0) / unit,
            (light.y * h - fragment.1) / unit,
            light.z,
        ),
    };
    let distance = direction.length();
    let c = 128.0 / 255.0 * 2.0 - 1.0;
    let n = DVec3::new(c, c, 1.0).normalize();
    let lambert = n.dot(direction.normalize()).max(0.0);
    let attenuation = 1.0 / (0.4 + 3.0 * distance + 20.0 * distance * distance);
    let light_color = [1.0, 0.8, 0.6]; // intensity 1
    let ambient = [0.6 * 0.2, 0.6 * 0.2, 1.0 * 0.2];
    std::array::from_fn(|k| {
        let intensity = ambient[k] + light_color[k] * lambert * attenuation;
        (intensity * 255.0).clamp(0.0, 255.0)
    })
}

// Fails if a pixel's brightness does not follow the article's formula: intensity = ambient +
// light colour × max(N·L, 0) × 1 / (0.4 + 3 d + 20 d²), with the light vector from the fragment's
// position normalized to the window, x stretched by the aspect ratio, d taken before normalizing
// (or, with the resolution-independent falloff, pixel offsets over 768 of the sprite's pixels).
// White texels and a flat normal map make the expected value analytic. Tolerance: 1 level of 255
// (the frame's 8-bit rounding plus the GPU's single-precision maths), checked on a ring of probes
// from under the light to the sprite's edge, in two window sizes (4:3 and 16:9, where the aspect
// correction matters) and both falloff modes.
#[test]
fn brightness_follows_the_attenuation_formula() {
    let assets = flat_white_assets("attenuation");
    let mut worst = 0.0f64;
    for size in [(1024, 768), (1280, 720)] {
        let (left, top, side) = sprite_in_image(size.0, size.1);
        let (cx, cy) = (left + side / 2, top + side / 2);
        let light = Vec3::new(0.5, 0.5, DEFAULT_LIGHT_Z);
        for independent in [false, true] {
            let sprite = light_and_falloff(light, independent);
            let frame = frame(&mut sprite_renderer(Some(assets.clone()), sprite, size));
            let unit = independent.then_some(768.0 * f64::from(side) / f64::from(TEXELS));
            let offsets = [0i32, 3, 10, 25, 50, 100, 170, 255];
            let mut probes = Vec::new();
            for &d in &offsets {
                probes.extend([(d, 0), (-d, 0), (0, d), (0, -d), (d * 7 / 10, -d * 7 / 10)]);
            }
            for (dx, dy) in probes {
                let (x, y) = ((cx as i32 + dx) as u32, (cy as i32 + dy) as u32);
                let want = expected(x, y, size, light, unit);
                let got = frame.get_pixel(x, y).0;
                for k in 0..3 {
                    let error = (f64::from(got[k]) - want[k]).abs();
                    worst = worst.max(error);
                    assert!(
                        error <= 1.0,
                        "{size:?} independent {independent}: pixel ({x}, {y}) channel {k}: {} \
                         against the formula's {:.3}",
                        got[k],
                        want[k]
                    );
                }
            }
            let edge = frame.get_pixel(cx + 255, cy).0;
            println!(
                "{size:?} independent {independent}: centre {:?}, 255 px right {edge:?}",
                frame.get_pixel(cx, cy).0
            );
        }
    }
    println!("largest difference from the formula: {worst:.3} of 255");
}

// Fails if the green-flip switch (key Y) is not the same as a normal map whose green channel is
// inverted in the file: the flipped frame and the frame of the inverted file must agree within 1
// level per channel (the file stores 255 − g where the shader computes 1 − g/255; both are exact in
// 8 bits, so bit for bit is expected). Fails too if the switch changes nothing (then the flipped
// file's frame would differ from it).
#[test]
fn green_flip_equals_an_inverted_green_channel() {
    let diffuse = own_texture(DIFFUSE_FILE);
    let inverted: Vec<[u8; 3]> = own_texture(NORMAL_FILE)
        .iter()
        .map(|&[r, g, b]| [r, 255 - g, b])
        .collect();
    let assets = sprite_assets("green-inverted", &diffuse, &inverted);
    let light = light_at(Vec3::new(0.45, 0.55, DEFAULT_LIGHT_Z));

    let mut renderer = sprite_renderer(None, light, (1024, 768));
    let as_made = frame(&mut renderer);
    assert!(renderer.host.scene.key('Y').unwrap(), "Y is the flip key");
    assert!(renderer.scene_ref::<Sprite>().flip_green);
    assert!(
        renderer.host.scene.status().contains("green flipped on"),
        "{}",
        renderer.host.scene.status()
    );
    let flipped = frame(&mut renderer);
    let from_file = frame(&mut sprite_renderer(Some(assets), light, (1024, 768)));

    let (differing, max, _) = pixel_diff(&flipped, &from_file);
    println!("flip switch vs inverted file: {differing} pixels differ, by at most {max}");
    assert!(max <= 1, "{differing} pixels differ by up to {max}");
    let (changed, changed_max, _) = pixel_diff(&as_made, &flipped);
    println!("flip switch vs as made: {changed} pixels differ, by at most {changed_max}");
    assert!(
        changed > 10_000 && changed_max > 20,
        "the switch changes too little"
    );
}

/// The sprite's pixels of `frame`.
fn sprite_crop(frame: &RgbImage) -> RgbImage {
    let (left, top, side) = sprite_in_image(frame.width(), frame.height());
    image::imageops::crop_imm(frame, left, top, side, side).to_image()
}

// Fails if the resolution-independent falloff (key I) does not keep the lit sprite the same in
// windows of other sizes, or if the article's falloff does not change with the window (the
// dependence the article warns about). The light sits over the same pixel of the sprite (drawn at
// its own size in all three windows). Tolerance for "the same": every channel within 1 level (the
// light's position goes through x / width × width in single precision). Also fails if the two
// modes disagree by more than 1 level at 1024×768, where they are meant to be equal.
#[test]
fn independent_falloff_does_not_change_with_the_window() {
    let sizes = [(1024, 768), (1600, 1000), (800, 600)];
    let crops = |independent: bool| -> Vec<RgbImage> {
        sizes
            .iter()
            .map(|&(w, h)| {
                let (x0, y0, side) = sprite_rect(w, h);
                assert_eq!(side, TEXELS, "{w}x{h}: the sprite is drawn at its own size");
                // Over sprite pixel (180, 300) from its lower-left corner.
                let light = Vec3::new(
                    (x0 as f32 + 180.5) / w as f32,
                    (y0 as f32 + 300.5) / h as f32,
                    DEFAULT_LIGHT_Z,
                );
                let sprite = light_and_falloff(light, independent);
                sprite_crop(&frame(&mut sprite_renderer(None, sprite, (w, h))))
            })
            .collect()
    };
    let independent = crops(true);
    let article = crops(false);
    for (i, size) in sizes.iter().enumerate().skip(1) {
        let (n, max, _) = pixel_diff(&independent[0], &independent[i]);
        println!("independent, 1024x768 vs {size:?}: {n} pixels differ, by at most {max}");
        assert!(max <= 1, "{size:?}: {n} pixels differ by up to {max}");
        let (n, max, _) = pixel_diff(&article[0], &article[i]);
        println!("article, 1024x768 vs {size:?}: {n} pixels differ, by at most {max}");
        assert!(
            n > 50_000 && max > 20,
            "{size:?}: the article's falloff did not change"
        );
    }
    let (n, max, _) = pixel_diff(&article[0], &independent[0]);
    println!("1024x768, article vs independent: {n} pixels differ, by at most {max}");
    assert!(max <= 1, "{n} pixels differ by up to {max}");
}

// Fails if the picture is not upright: with a flat normal map and the light high above, the sprite is
// its colour map times a smooth intensity, so its brightness must correlate with the colour map as an
// image viewer shows it (row 0 on top) far better than with the map upside down. Measured: Pearson
// correlation above 0.9 upright, below 0.3 flipped.
#[test]
fn the_rock_is_upright() {
    let diffuse = own_texture(DIFFUSE_FILE);
    let flat = vec![[128, 128, 255]; diffuse.len()];
    let assets = sprite_assets("upright", &diffuse, &flat);
    let light = light_at(Vec3::new(0.5, 0.5, Z_MAX));
    let crop = sprite_crop(&frame(&mut sprite_renderer(
        Some(assets),
        light,
        (1024, 768),
    )));
    let rendered: Vec<f64> = crop.pixels().map(luma).collect();
    let n = TEXELS as usize;
    let upright: Vec<f64> = diffuse.iter().map(|&p| luma(&Rgb(p))).collect();
    let flipped: Vec<f64> = (0..n * n)
        .map(|i| upright[(n - 1 - i / n) * n + i % n])
        .collect();
    let (up, down) = (pearson(&rendered, &upright), pearson(&rendered, &flipped));
    println!("correlation with the colour map: upright {up:.4}, upside down {down:.4}");
    assert!(
        up > 0.9 && down < 0.3,
        "upright {up:.4}, upside down {down:.4}"
    );
}

fn pearson(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len() as f64;
    let (ma, mb) = (a.iter().sum::<f64>() / n, b.iter().sum::<f64>() / n);
    let (mut ab, mut aa, mut bb) = (0.0, 0.0, 0.0);
    for (x, y) in a.iter().zip(b) {
        ab += (x - ma) * (y - mb);
        aa += (x - ma) * (x - ma);
        bb += (y - mb) * (y - mb);
    }
    ab / (aa * bb).sqrt()
}

// Fails if the light does not start where --light puts it, takes the cursor before the cursor has
// moved (a window opening under the pointer would throw a --light away), does not follow the cursor
// once it moves (pixel centre, y flipped to the article's y up), or stays on a cursor that left.
// Fails too if the wheel does not move the light by 0.01 a notch within 0.005..=1, or a click does
// not put it back at the article's 0.075, or the status line does not show the light.
#[test]
fn the_light_follows_the_cursor_wheel_and_click() {
    let start = Vec3::new(0.2, 0.7, 0.1);
    let mut renderer = sprite_renderer(None, light_at(start), (1024, 768));
    let first = frame(&mut renderer);
    assert_eq!(renderer.scene_ref::<Sprite>().light, start);
    assert!(renderer
        .host
        .scene
        .status()
        .contains("light (0.200, 0.700, 0.100)"));

    let pointer = Vec2::new(700.0, 200.0);
    renderer.host.cursor = Some(pointer);
    for _ in 0..2 {
        assert_eq!(
            frame(&mut renderer),
            first,
            "the light moved before the cursor did"
        );
    }
    let moved = Vec2::new(701.0, 200.0);
    renderer.host.cursor = Some(moved);
    frame(&mut renderer);
    let sprite = renderer.scene_ref::<Sprite>();
    assert!(sprite.following());
    let expected = cursor_to_light(moved, (1024, 768));
    assert_eq!(sprite.light, expected.extend(start.z));
    assert!(expected.abs_diff_eq(Vec2::new(701.5 / 1024.0, 567.5 / 768.0), 1e-6));
    assert!(renderer.host.scene.status().contains("on the mouse"));

    renderer.host.cursor = None;
    frame(&mut renderer);
    assert_eq!(
        renderer.scene_ref::<Sprite>().light,
        expected.extend(start.z)
    );

    renderer.host.scene.scroll(3.0);
    let z = renderer.scene_ref::<Sprite>().light.z;
    println!("z after 3 notches up from 0.1: {z}");
    assert!((z - 0.13).abs() < 1e-6, "{z}");
    renderer.host.scene.scroll(-1000.0);
    assert_eq!(renderer.scene_ref::<Sprite>().light.z, Z_MIN);
    renderer.host.scene.scroll(f32::NAN);
    assert_eq!(renderer.scene_ref::<Sprite>().light.z, Z_MIN);
    renderer.host.scene.scroll(1000.0);
    assert_eq!(renderer.scene_ref::<Sprite>().light.z, Z_MAX);
    renderer.host.scene.click();
    assert_eq!(renderer.scene_ref::<Sprite>().light.z, DEFAULT_LIGHT_Z);
    assert!(
        renderer.host.scene.status().contains(", 0.075)"),
        "{}",
        renderer.host.scene.status()
    );
}

// Fails if the committed normal map is not the rock's height field in the "green up" convention
// the scene relies on: red must grow where the height falls to the right (n.x = −∂h/∂x) and green
// where it falls up the picture (n.y = −∂h/∂y, y up), which shows as a strong correlation (measured
// above 0.9; a flipped channel gives about −0.9) between each channel and the height's slope.
#[test]
fn the_normal_map_is_the_rocks_relief_green_up() {
    let n = TEXELS as usize;
    let height = rock_height_map(TEXELS);
    let normals = own_texture(NORMAL_FILE);
    let at = |col: usize, row: usize| height[(row % n) * n + col % n];
    let (mut red, mut green, mut falls_right, mut falls_up) = (vec![], vec![], vec![], vec![]);
    for row in 0..n {
        for col in 0..n {
            let [r, g, _] = normals[row * n + col];
            red.push(f64::from(r));
            green.push(f64::from(g));
            // Central differences; row 0 is the top, so "up the picture" is row − 1.
            falls_right.push(f64::from(at(col + n - 1, row) - at(col + 1, row)));
            falls_up.push(f64::from(at(col, row + 1) - at(col, row + n - 1)));
        }
    }
    let (x, y) = (pearson(&red, &falls_right), pearson(&green, &falls_up));
    println!("correlation: red with −∂h/∂x {x:.4}, green with −∂h/∂y (y up) {y:.4}");
    assert!(x > 0.9 && y > 0.9, "red {x:.4}, green {y:.4}");
}

// Fails if a bad --light panics or is accepted: anything but three finite numbers, or a height that
// is not above the sprite, must end the program with one line naming --light and a non-zero status.
#[test]
fn a_bad_light_flag_is_refused() {
    for bad in [
        "0.5,0.5",
        "0.5,0.5,0",
        "0.5,0.5,-1",
        "a,0.5,0.1",
        "0.5,nan,0.1",
        "0.5,0.5,0.1,1",
    ] {
        let out = common::run(common::tutorial13().args([
            "--headless",
            "--scene",
            "sprite",
            "--light",
            bad,
        ]));
        let stderr = String::from_utf8_lossy(&out.stderr);
        println!("--light {bad}: {}", stderr.lines().next().unwrap_or(""));
        assert_eq!(out.status.code(), Some(2), "--light {bad}: {stderr}");
        assert!(
            stderr.contains("--light") && !stderr.contains("panicked"),
            "{stderr}"
        );
    }
}

// Fails if the first frame changes: the rock in the middle of the window, lit from the upper left of
// its centre by a warm, small pool of light (the default light (0.4, 0.6, 0.075)), bluish-dark
// elsewhere from the ambient term.
#[test]
fn first_frame_matches_golden() {
    let frame = render_rock(SpriteOptions::default());
    assert_matches_golden(&frame, "sprite");
}

// ---------------------------------------------------------------------------------------------
// The window, driven through a private Xvfb with xdotool (as tests/window_input.rs does).

/// The headless frame of the sprite scene with these extra arguments, as the binary writes it.
fn headless_shot(dir: &Path, name: &str, args: &[&str]) -> RgbImage {
    common::headless_screenshot(dir, name, &[&["--scene", "sprite"], args].concat())
}

/// `--light` for a light the window computed: f32's shortest round-trip text parses back to the
/// same floats.
fn light_arg(light: Vec3) -> String {
    format!("{},{},{}", light.x, light.y, light.z)
}

// Fails if the window's frame differs from the headless one (before the mouse moves: the default
// light, bit for bit), if moving the mouse over the window does not bring the light to the pixel
// under it (the title must say so, and the frame then equal the headless frame with that --light,
// bit for bit), if the wheel does not raise it by whole notches of 0.01 (the title shows the
// light), if a click does not put it back at 0.075, or if Y does not flip the green channel as
// --green down does.
#[test]
fn the_window_light_follows_the_mouse() {
    if !common::reference_renderer_here("the_window_light_follows_the_mouse") {
        return;
    }
    let dir = scratch("window");
    let xvfb = Xvfb::start();
    let (mut app, window) = xvfb.open_window(&dir, &["--scene", "sprite"]);
    let mut shots = 0;
    let mut shot = || {
        shots += 1;
        xvfb.screenshot(&dir, shots)
    };
    let title = || xvfb.title(&window);

    let first = shot();
    assert!(
        first == headless_shot(&dir, "default.png", &[]),
        "the window's first frame is not the headless one"
    );

    // The light takes the cursor once it has seen it move between two frames: moved until it does,
    // then to `pointer`, where the title must show it before the screenshot.
    xvfb.move_pointer_until(
        &window,
        &[(560, 280), (600, 300)],
        "the light on the mouse",
        |t| t.contains("on the mouse"),
    );
    let pointer = Vec2::new(600.0, 300.0);
    xvfb.xdotool(&["mousemove", "--window", &window, "600", "300"]);
    let light = cursor_to_light(pointer, (1024, 768)).extend(DEFAULT_LIGHT_Z);
    let in_title = format!(
        "light ({:.3}, {:.3}, {:.3}) on the mouse",
        light.x, light.y, light.z
    );
    xvfb.wait_for_title(&window, &in_title, |t| t.contains(&in_title));
    let moved = shot();
    let expected = headless_shot(&dir, "moved.png", &["--light", &light_arg(light)]);
    let (n, max, _) = pixel_diff(&moved, &expected);
    println!(
        "light on the mouse at {pointer}: {n} pixels differ from --light {}, by at most {max}",
        light_arg(light)
    );
    assert!(n == 0, "{n} pixels differ, by up to {max}");
    assert!(title().contains("on the mouse"), "{}", title());

    // The wheel away from the user (button 4) raises the light. winit counts an XTEST wheel
    // click's press and its release as a notch each (a real wheel's clicks come as one scroll
    // motion), so one click here raises it by 0.02: the test asks for whole notches of 0.01 above.
    let light_z = |title: &str| -> Option<f32> {
        let inside = title.split("light (").nth(1)?.split(')').next()?;
        inside.split(", ").nth(2)?.parse().ok()
    };
    xvfb.xdotool(&["click", "4"]);
    let raised = wait_for("the title: the light raised", || {
        light_z(&title()).filter(|&z| z > DEFAULT_LIGHT_Z + 0.005)
    });
    let notches = (raised - DEFAULT_LIGHT_Z) / 0.01;
    println!("one wheel click: z {raised} ({notches} notches)");
    assert!(
        (notches - notches.round()).abs() < 0.01,
        "z {raised} is not 0.075 + whole notches"
    );
    xvfb.xdotool(&["click", "1"]);
    xvfb.wait_for_title(&window, "the light back at 0.075", |t| {
        t.contains(", 0.075) on the mouse")
    });
    assert!(shot() == moved, "a click did not put the light back");

    xvfb.xdotool(&["key", "y"]);
    xvfb.wait_for_title(&window, "green flipped on", |t| {
        t.contains("green flipped on")
    });
    let flipped = shot();
    let expected = headless_shot(
        &dir,
        "flipped.png",
        &["--light", &light_arg(light), "--green", "down"],
    );
    assert!(flipped == expected, "Y in the window is not --green down");

    xvfb.quit(&mut app);
}
