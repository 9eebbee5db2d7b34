//! The `cube` scene (article 003), headless through EGL on llvmpipe: normal mapping on and off, the
//! facing test that keeps highlights off faces turned away from the light, the emissive floor, a
//! golden image, and the scene's errors and shader reloads.
//!
//! The analytic checks use scratch asset folders with one-colour textures and a flat normal map, so
//! that a pixel's colour follows from the article's formula alone: emissive (0, 0.01, 0) + 0.09 ×
//! texel on a face the light does not reach.

use crate::common;

use std::path::PathBuf;

use crate::common::*;
use glam::{Mat4, Vec3};
use image::RgbImage;
use tutorial13::frontends::headless::{HeadlessOptions, HeadlessRenderer};
use tutorial13::gl::Profile;
use tutorial13::scenes::cube::{model_matrix, Cube, Face, FACES, HALF_SIZE};

/// FACES' order: front (+z), back, right (+x), left, top (+y), bottom.
const FRONT: Face = FACES[0];
const RIGHT: Face = FACES[2];
const TOP: Face = FACES[4];

/// The article's weights.
const EMISSIVE_GREEN: f32 = 0.01;
const AMBIENT: f32 = 0.09;

fn cube_options(assets: PathBuf) -> HeadlessOptions {
    let mut options = options(assets, Profile::Core);
    options.descriptor = tutorial13::scenes::descriptor::<tutorial13::scenes::cube::Cube>();
    options
}

/// A scratch asset folder whose cube textures are one colour each: `diffuse`, and a flat normal map
/// (128, 128, 255).
fn one_colour_assets(name: &str, diffuse: [u8; 3]) -> PathBuf {
    flat_scene_assets(name, "cube", 16, diffuse)
}

/// A point of `face` in world space: (a, b) in -1..1 along its U and V, through `model`.
fn face_point(model: Mat4, face: Face, a: f32, b: f32) -> Vec3 {
    model.transform_point3((face.normal + face.u * a + face.v * b) * HALF_SIZE)
}

/// The pixel a world point falls in, through the tutorial's start camera.
fn pixel_of(world: Vec3) -> (u32, u32) {
    let (x, y) = project(world);
    (x.floor() as u32, y.floor() as u32)
}

/// `n × n` points of `face` with a and b in -0.8..0.8 (clear of its edges), as (world point, pixel).
fn face_samples(model: Mat4, face: Face, n: u32) -> Vec<(Vec3, (u32, u32))> {
    let step = 1.6 / (n - 1) as f32;
    let mut samples = Vec::new();
    for i in 0..n {
        for j in 0..n {
            let p = face_point(model, face, -0.8 + step * i as f32, -0.8 + step * j as f32);
            samples.push((p, pixel_of(p)));
        }
    }
    samples
}

/// The article's colour where neither diffuse nor specular light arrives, in 8-bit levels (before
/// rounding): emissive green 0.01 plus 0.09 × the texel.
fn emissive_plus_ambient(texel: [u8; 3]) -> [f32; 3] {
    let emissive = [0.0, EMISSIVE_GREEN, 0.0];
    [0, 1, 2].map(|k| 255.0 * (emissive[k] + AMBIENT * f32::from(texel[k]) / 255.0))
}

/// Every sample pixel must be `expected` rounded to 8 bits. The one-colour textures are chosen so
/// that no channel lies within 0.04 of a rounding boundary (float error is below 0.001 level): the
/// comparison is exact.
fn assert_all_equal(
    frame: &RgbImage,
    samples: &[(Vec3, (u32, u32))],
    expected: [f32; 3],
    what: &str,
) {
    let want = expected.map(|c| c.round() as u8);
    for k in 0..3 {
        assert!(
            (expected[k] - expected[k].floor() - 0.5).abs() > 0.04,
            "{expected:?} too near a rounding boundary"
        );
    }
    let mut wrong = Vec::new();
    for &(_, (x, y)) in samples {
        let p = frame.get_pixel(x, y).0;
        if p != want {
            wrong.push(((x, y), p));
        }
    }
    println!(
        "{what}: {} of {} pixels equal {want:?} (exact value {expected:?})",
        samples.len() - wrong.len(),
        samples.len()
    );
    assert!(
        wrong.is_empty(),
        "{what}: expected {want:?}, got {:?}",
        &wrong[..wrong.len().min(8)]
    );
}

// Fails if the article's flag does nothing on the lit faces (the normal map not sampled, or not
// perturbing the normal), if the key N does not toggle it or the status line does not say so, or if
// the start `--no-normal-map` gives (cube::NORMAL_MAPPING off) draws anything but what the key gives. Tolerance: at least half of
// the sampled pixels of the lit front and top faces must change, by at least 1.5 levels per channel on
// average (measured on llvmpipe: front 88 % and 3.8 levels, top 92 % and 5.0 levels; the
// stones' shoulders change by far more, their flat tops little).
#[test]
fn normal_mapping_off_and_on_differ_on_lit_faces() {
    let mut renderer = renderer(&cube_options(own_assets()));
    assert_eq!(renderer.host.scene.short_status(), "normal mapping on");
    let on = frame(&mut renderer);
    assert!(renderer.host.scene.key('N').unwrap(), "N is the cube's key");
    assert_eq!(renderer.host.scene.short_status(), "normal mapping off");
    let off = frame(&mut renderer);

    for (face, name) in [(FRONT, "front"), (TOP, "top")] {
        let samples = face_samples(model_matrix(), face, 41);
        let (mut changed, mut total_difference) = (0, 0u64);
        for &(_, (x, y)) in &samples {
            let (a, b) = (on.get_pixel(x, y).0, off.get_pixel(x, y).0);
            let difference: u64 = (0..3).map(|k| u64::from(a[k].abs_diff(b[k]))).sum();
            changed += usize::from(difference > 0);
            total_difference += difference;
        }
        let fraction = changed as f64 / samples.len() as f64;
        let mean = total_difference as f64 / (3 * samples.len()) as f64;
        println!(
            "{name} face: {changed} of {} sampled pixels differ ({:.0} %), mean difference {mean:.2} levels per channel",
            samples.len(),
            100.0 * fraction
        );
        assert!(
            fraction >= 0.5 && mean >= 1.5,
            "{name}: normal mapping changes too little"
        );
    }

    let mut flag_off = cube_options(own_assets());
    flag_off
        .scene
        .start(tutorial13::scenes::cube::NORMAL_MAPPING.to(false));
    let mut second = common::renderer(&flag_off);
    assert_eq!(second.host.scene.short_status(), "normal mapping off");
    assert!(
        frame(&mut second) == off,
        "--no-normal-map differs from pressing N"
    );
}

/// With normal mapping on, then off: [`assert_all_equal`] on the frame, then `also` on it.
fn assert_unlit_either_way(
    renderer: &mut HeadlessRenderer,
    samples: &[(Vec3, (u32, u32))],
    expected: [f32; 3],
    what: &str,
    also: impl Fn(&RgbImage),
) {
    for normal_mapping in [true, false] {
        renderer.scene_mut::<Cube>().normal_mapping = normal_mapping;
        let frame = frame(renderer);
        let what = format!("{what}, normal mapping {normal_mapping}");
        assert_all_equal(&frame, samples, expected, &what);
        also(&frame);
    }
}

// Fails if a face turned away from the light gets any specular (the article's `facing` test
// missing), any diffuse (max(n·l, 0) missing), or loses its emissive or ambient term: every sampled
// pixel of it must equal emissive + ambient exactly, with normal mapping on and off. Two set-ups:
// the scene's own (the right face is turned away from its light), and one where the highlight would
// be strong without the facing test: the cube turned so that the right face is seen at a grazing
// angle, the light just behind that face's plane, nearly opposite the camera, so that the halfway
// vector lies close to the face's normal (the ungated highlight is computed here and printed; it
// must be large, or the set-up has stopped testing the gate). The shader interpolates per-vertex
// halfway vectors, which spreads the highlight less than the per-pixel estimate: with the facing test
// removed, 17 of the 441 samples gained up to 16 levels (measured on llvmpipe).
#[test]
fn faces_turned_away_from_the_light_have_no_specular() {
    let texel = [200, 160, 120];
    let expected = emissive_plus_ambient(texel);
    let mut renderer = renderer(&cube_options(one_colour_assets("away", texel)));

    // The scene's own light and placement.
    let samples = face_samples(model_matrix(), RIGHT, 21);
    assert_unlit_either_way(&mut renderer, &samples, expected, "right face", |frame| {
        // The light does reach the front face: it is brighter than emissive + ambient.
        let (_, (x, y)) = face_samples(model_matrix(), FRONT, 3)[4];
        let lit = frame.get_pixel(x, y).0;
        assert!(
            lit[0] as f32 > expected[0] + 30.0,
            "front face not lit: {lit:?}"
        );
    });

    // The grazing set-up.
    let model = Mat4::from_rotation_y(-20f32.to_radians());
    let light = Vec3::new(2.3, 0.0, -4.5);
    let eye = Vec3::new(0.0, 0.0, 5.0);
    let normal = model.transform_vector3(RIGHT.normal);
    let samples = face_samples(model, RIGHT, 21);
    let (mut highest_n_dot_l, mut ungated) = (f32::MIN, 0.0f32);
    for &(p, _) in &samples {
        let l = (light - p).normalize();
        let h = (l + (eye - p).normalize()).normalize();
        highest_n_dot_l = highest_n_dot_l.max(normal.dot(l));
        ungated = ungated.max(0.9 * 255.0 * normal.dot(h).max(0.0).powf(200.0));
    }
    println!(
        "grazing set-up: n·l at most {highest_n_dot_l:.3}; without the facing test the highlight \
         would add up to {ungated:.0} levels (× texel) by a per-pixel estimate"
    );
    assert!(highest_n_dot_l < -0.05 && ungated > 0.25 * 255.0);
    let xs = samples.iter().map(|s| s.1 .0);
    println!(
        "grazing set-up: the face spans columns {}..{}",
        xs.clone().min().unwrap(),
        xs.max().unwrap()
    );
    let cube = renderer.scene_mut::<Cube>();
    cube.model_matrix = model;
    cube.light.position_worldspace = light;
    assert_unlit_either_way(
        &mut renderer,
        &samples,
        expected,
        "grazing right face",
        |_| {},
    );
}

// Fails if the emissive term is missing or not the article's 0.01 green: with a texture that has
// no green at all, the only green on a face the light does not reach is the emissive floor, so every
// sampled pixel of the right face must have green exactly round(0.01 × 255) = 3, and red and blue
// exactly 0.09 × the texel's, rounded; and the face must stand out from the background.
#[test]
fn emissive_floor_shows_where_nothing_else_lights() {
    let texel = [40, 0, 80];
    let expected = emissive_plus_ambient(texel);
    let mut renderer = renderer(&cube_options(one_colour_assets("emissive", texel)));
    let frame = frame(&mut renderer);
    let samples = face_samples(model_matrix(), RIGHT, 21);
    assert_all_equal(
        &frame,
        &samples,
        expected,
        "right face, texel without green",
    );
    let floor = (EMISSIVE_GREEN * 255.0).round() as u8;
    for &(_, (x, y)) in &samples {
        let p = frame.get_pixel(x, y);
        assert!(p[1] >= floor && !is_background(p), "({x}, {y}) = {p:?}");
    }
    println!("emissive floor: green {floor} on the unlit face, where the texture has none");
}

// Fails if the scene's first frame changes: placement, light, textures, the shaders' lighting, or
// the tangent frame (a flipped tangent or bitangent lights the other side of every stone).
#[test]
fn cube_matches_golden() {
    let frame = render(&cube_options(own_assets()));
    assert_matches_golden(&frame, "cube");
}

// Fails if the cube's shoulders are lit from the wrong side: with the light up and to the left, the
// stones' upper-left shoulders on the front face must be brighter than their lower-right ones. On the
// texture, a stone's shoulder on its left has a normal leaning left (red below 128) and one on its
// top a normal leaning up (green above 128); the frame's pixels with normal mapping on are grouped by
// the normal map texel under them.
#[test]
fn shoulders_facing_the_light_are_brighter() {
    let normal_map = image::open(own_assets().join("cube/normal.bmp"))
        .unwrap()
        .into_rgb8();
    let mut renderer = renderer(&cube_options(own_assets()));
    let frame = frame(&mut renderer);
    let size = normal_map.width() as f32;
    let (mut towards, mut away) = (Vec::new(), Vec::new());
    let n = 81;
    for i in 0..n {
        for j in 0..n {
            let (u, v) = (
                0.05 + 0.9 * i as f32 / (n - 1) as f32,
                0.05 + 0.9 * j as f32 / (n - 1) as f32,
            );
            let p = face_point(model_matrix(), FRONT, 2.0 * u - 1.0, 2.0 * v - 1.0);
            let (x, y) = pixel_of(p);
            // Picture row 0 is the top of the face (V = 1).
            let texel = normal_map
                .get_pixel((u * size) as u32, ((1.0 - v) * size) as u32)
                .0;
            let luma = frame
                .get_pixel(x, y)
                .0
                .iter()
                .map(|&c| f64::from(c))
                .sum::<f64>();
            if texel[0] < 90 && texel[1] > 166 {
                towards.push(luma);
            } else if texel[0] > 166 && texel[1] < 90 {
                away.push(luma);
            }
        }
    }
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    println!(
        "front face: shoulders towards the light {:.1} ({} samples), away {:.1} ({} samples), summed levels",
        mean(&towards),
        towards.len(),
        mean(&away),
        away.len()
    );
    assert!(towards.len() > 20 && away.len() > 20);
    assert!(mean(&towards) > mean(&away) + 15.0);
}

// Fails if the cube's shaders are not reloaded from the --shaders folder, or if a broken one is
// accepted, not named, or changes the frame (the last good program must keep drawing).
#[test]
fn shader_reload_is_all_or_nothing() {
    let dir = scratch("shaders");
    for name in [
        "CubeBlinnPhong.vertexshader",
        "CubeBlinnPhong.fragmentshader",
    ] {
        let from = tutorial13::common::shader::crate_shader_dir().join(name);
        std::fs::copy(&from, dir.join(name)).unwrap();
    }
    let mut options = cube_options(own_assets());
    options.scene.shaders = Some(dir.clone());
    let mut renderer = renderer(&options);
    let first = frame(&mut renderer);
    assert!(renderer
        .host
        .scene
        .shader_files()
        .iter()
        .all(|p| p.starts_with(&dir)));

    let fragment = dir.join("CubeBlinnPhong.fragmentshader");
    let good = std::fs::read_to_string(&fragment).unwrap();
    std::fs::write(
        &fragment,
        good.replace("color.a = 1.0;", "color.a = 1.0 +;"),
    )
    .unwrap();
    let error = renderer
        .host
        .reload_shaders()
        .expect_err("a broken shader is refused")
        .to_string();
    assert!(error.contains("CubeBlinnPhong.fragmentshader"), "{error}");
    assert!(
        frame(&mut renderer) == first,
        "a refused reload changed the frame"
    );

    std::fs::write(
        &fragment,
        good.replace("color.a = 1.0;", "color = vec4(1.0);"),
    )
    .unwrap();
    renderer.host.reload_shaders().unwrap();
    let white = frame(&mut renderer);
    let (x, y) = pixel_of(face_point(model_matrix(), FRONT, 0.0, 0.0));
    assert_eq!(white.get_pixel(x, y).0, [255; 3], "the edit did not show");
}
