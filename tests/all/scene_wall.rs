//! The `wall` scene (article 004): one stone wall lit in view space and in tangent space, headless.
//! The article says both give the same result; these tests measure how close they are, check the
//! lighting formula pixel by pixel against the article's numbers, and keep a golden image.

use crate::common;

use std::path::{Path, PathBuf};

use crate::common::{
    assert_matches_golden, drawn_pixels, flat_scene_assets, frame, frame_diff, own_assets,
    pixel_diff, renderer, H, W,
};
use glam::{Vec3, Vec4};
use image::RgbImage;
use tutorial13::common::controls::Controls;
use tutorial13::gl::Profile;
use tutorial13::scenes::wall::{LightingSpace, Wall, LIGHT_POSITION_WORLDSPACE};
use tutorial13::scenes::Scene;

fn options(
    assets: PathBuf,
    space: LightingSpace,
) -> tutorial13::frontends::headless::HeadlessOptions {
    let mut options = common::options(assets, Profile::Core);
    options.descriptor = tutorial13::scenes::descriptor::<Wall>();
    options
        .scene
        .start(tutorial13::scenes::wall::SPACE.to(space));
    options
}

fn render(assets: &Path, space: LightingSpace) -> RgbImage {
    frame(&mut renderer(&options(assets.to_path_buf(), space)))
}

/// A wall/ folder with a diffuse map of one colour and a flat normal map (128, 128, 255).
fn flat_assets(name: &str, diffuse: [u8; 3]) -> PathBuf {
    flat_scene_assets(name, "wall", 64, diffuse)
}

/// Renders the wall with `space`, from the tutorial's start camera or (`oblique`) from (3, 1.5, 3)
/// looking at the origin, where the view matrix turns the square's frame by tens of degrees.
fn render_from(assets: &Path, space: LightingSpace, oblique: bool) -> RgbImage {
    let mut r = renderer(&options(assets.to_path_buf(), space));
    if oblique {
        r.host.controls.position = Vec3::new(3.0, 1.5, 3.0);
        r.host.controls.horizontal_angle = 3.927;
        r.host.controls.vertical_angle = -0.3398;
    }
    frame(&mut r)
}

// Fails if the tangent-space program does not give the view-space program's frame (the article's
// claim) beyond float rounding, from the start camera and from an oblique one (from the start camera
// the view matrix is almost the identity, so only the oblique view shows a wrong TBN transpose).
// Measured: 22 and 11 pixels differing, by 1 level at most.
#[test]
fn view_and_tangent_space_give_the_same_wall() {
    for oblique in [false, true] {
        let view = render_from(&own_assets(), LightingSpace::View, oblique);
        let tangent = render_from(&own_assets(), LightingSpace::Tangent, oblique);
        let (differing, max, bbox) = pixel_diff(&view, &tangent);
        let square = drawn_pixels(&view);
        println!(
            "view vs tangent space (oblique camera: {oblique}): {differing} of {square} square \
             pixels differ, by at most {max} level(s), within {bbox:?}"
        );
        assert!(square > 50_000, "only {square} pixels of wall");
        assert!(max <= 1, "a difference of {max} levels");
        assert!(differing * 100 <= square, "{differing} pixels differ");
    }
}

// Fails if the normal map does not change the light (the three programs would be the same), or if a
// flat normal map does not give plain per-pixel lighting of the square in both spaces. A "flat" texel
// (128, 128, 255) expands to (1/255, 1/255, 1), a normal tilted 0.32° towards +x and +y, so most
// pixels move by a level: measured, 129 645 pixels differ, by 3 levels at most (in the specular
// highlight), 0.87 on average over the square's channels.
#[test]
fn a_flat_normal_map_is_plain_per_pixel_lighting() {
    let stones = render(&own_assets(), LightingSpace::View);
    let plain = render(&own_assets(), LightingSpace::NoNormalMap);
    let (differing, _, _) = pixel_diff(&stones, &plain);
    let square = drawn_pixels(&stones);
    println!("the stone normal map changes {differing} of {square} pixels");
    assert!(
        differing * 2 > square,
        "the normal map changes only {differing} pixels"
    );

    let flat = flat_assets("flat", [180, 160, 140]);
    let reference = render(&flat, LightingSpace::NoNormalMap);
    for space in [LightingSpace::View, LightingSpace::Tangent] {
        let lit = render(&flat, space);
        let d = frame_diff(&lit, &reference);
        let (differing, max) = (d.differing(), d.max());
        // The mean over the square's channels (the square's pixels counted on the stone wall).
        let mean = d.total as f64 / (square * 3) as f64;
        println!(
            "flat map, {} space vs no normal map: {differing} pixels differ, max {max}, mean \
             {mean:.3} levels over the square",
            space.name()
        );
        assert!(max <= 3, "{}: {max} levels", space.name());
        assert!(mean <= 1.0, "{}: mean {mean:.3} levels", space.name());
    }
}

/// Where the ray through the centre of window pixel (x, y) meets the plane z = 0, through the
/// tutorial's start camera.
fn on_the_wall(x: u32, y: u32) -> Vec3 {
    let controls = Controls::default();
    let inverse = (controls.projection_matrix() * controls.view_matrix()).inverse();
    let ndc_x = (x as f32 + 0.5) / W as f32 * 2.0 - 1.0;
    let ndc_y = 1.0 - (y as f32 + 0.5) / H as f32 * 2.0;
    let point = |z: f32| {
        let p: Vec4 = inverse * Vec4::new(ndc_x, ndc_y, z, 1.0);
        p.truncate() / p.w
    };
    let (near, far) = (point(-1.0), point(1.0));
    let t = near.z / (near.z - far.z);
    near + (far - near) * t
}

/// The article's lighting at `p` on the square (normal +z) for a diffuse texel `texel` (0..1):
/// 50/d² × (max(n·l, 0) + 0.3 × max(v·r, 0)^5), times the texel, no ambient.
fn expected(p: Vec3, texel: Vec3) -> Vec3 {
    let camera = Vec3::new(0.0, 0.0, 5.0);
    let n = Vec3::Z;
    let to_light = LIGHT_POSITION_WORLDSPACE - p;
    let d2 = to_light.length_squared();
    let l = to_light.normalize();
    let to_camera = (camera - p).normalize();
    let r = 2.0 * n.dot(l) * n - l;
    let diffuse = n.dot(l).clamp(0.0, 1.0);
    let specular = to_camera.dot(r).clamp(0.0, 1.0).powf(5.0);
    texel * 50.0 / d2 * (diffuse + 0.3 * specular)
}

// Fails if the programs' lighting is not the article's formula with its numbers (light at (4, 0, 4),
// intensity 50, 1/d², reflectivity 0.3, exponent 5, no ambient): probed on a grid of pixels of a wall
// with a flat map and a dark uniform diffuse texel (so nothing saturates), each within 2 levels.
#[test]
fn the_lighting_follows_the_articles_formula() {
    let texel = [60u8, 50, 40];
    let flat = flat_assets("formula", texel);
    let texel = Vec3::new(60.0, 50.0, 40.0) / 255.0;
    for &space in <LightingSpace as clap::ValueEnum>::value_variants() {
        let image = render(&flat, space);
        let (mut probed, mut worst) = (0, 0.0f32);
        for y in (210..560).step_by(35) {
            for x in (335..690).step_by(35) {
                let p = on_the_wall(x, y);
                assert!(
                    p.x.abs() < 1.0 && p.y.abs() < 1.0,
                    "({x}, {y}) is off the wall: {p}"
                );
                let want = (expected(p, texel) * 255.0).clamp(Vec3::ZERO, Vec3::splat(255.0));
                let got = image.get_pixel(x, y).0.map(f32::from);
                for c in 0..3 {
                    worst = worst.max((want[c] - got[c]).abs());
                }
                probed += 1;
            }
        }
        println!(
            "{} space: {probed} pixels, largest difference from the formula {worst:.2} levels",
            space.name()
        );
        assert!(worst <= 2.0, "{}: {worst} levels off", space.name());
    }
}

// Fails if the S key does not step view → tangent → none → view, the status does not say which, or
// the drawn frame does not follow the switch.
#[test]
fn the_space_key_steps_through_the_programs() {
    let mut r = renderer(&options(own_assets(), LightingSpace::View));
    let view = frame(&mut r);
    let wall = r.scene_mut::<Wall>();
    assert!(
        wall.status().starts_with("lighting space view |"),
        "{}",
        wall.status()
    );
    assert!(wall.key('s').unwrap());
    assert_eq!(wall.space, LightingSpace::Tangent);
    assert!(
        wall.status().starts_with("lighting space tangent |"),
        "{}",
        wall.status()
    );
    let tangent = frame(&mut r);
    assert!(pixel_diff(&view, &tangent).1 <= 1);
    let wall = r.scene_mut::<Wall>();
    assert!(wall.key('S').unwrap());
    assert!(
        wall.status().starts_with("lighting space none |"),
        "{}",
        wall.status()
    );
    let none = frame(&mut r);
    assert!(pixel_diff(&view, &none).1 > 10);
    let wall = r.scene_mut::<Wall>();
    assert!(wall.key('S').unwrap());
    assert_eq!(wall.space, LightingSpace::View);
    assert!(!wall.key('Q').unwrap());
    assert!(frame(&mut r) == view);
}

// Fails if the project's wall stops looking as committed (textures, lighting or camera changed).
#[test]
fn wall_matches_golden() {
    let image = render(&own_assets(), LightingSpace::View);
    assert_matches_golden(&image, "wall-view");
}
