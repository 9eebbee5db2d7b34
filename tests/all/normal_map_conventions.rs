//! Normal-map conventions (article 002), as switches of the cylinder's debugging program: green up or
//! down, the plain `2c − 1` expansion or the exact `c × 255/127 − 128/127`, and two-channel maps with z
//! rebuilt. Each is checked against a map changed the way the convention says.

use std::path::PathBuf;

use crate::common::{
    compare_drawn, cylinder_frame, flat_white_assets, is_background, options, own_assets,
    pixel_diff, renderer, scratch,
};
use image::RgbImage;
use tutorial13::assets::encode_bmp;
use tutorial13::debug::views::NormalMapConvention;
use tutorial13::gl::Profile;
use tutorial13::scenes::cylinder::{self, Cylinder};
use tutorial13::scenes::Scene;

fn render(assets: PathBuf, convention: NormalMapConvention, view: &str) -> RgbImage {
    cylinder_frame(assets, |o| {
        let settings = cylinder::convention(convention).into_iter();
        for setting in settings.chain(cylinder::view(view.parse().unwrap())) {
            o.start(setting);
        }
    })
}

/// The project's assets with its normal map's texels changed by `change`.
fn assets_with_normal_map(name: &str, change: impl Fn([u8; 3]) -> [u8; 3]) -> PathBuf {
    let dir = scratch(name);
    for file in ["cylinder.obj", "diffuse.DDS", "specular.DDS"] {
        std::fs::copy(own_assets().join(file), dir.join(file)).unwrap();
    }
    let map = image::open(own_assets().join("normal.bmp"))
        .unwrap()
        .into_rgb8();
    let texels: Vec<[u8; 3]> = map.pixels().map(|p| change(p.0)).collect();
    std::fs::write(
        dir.join("normal.bmp"),
        encode_bmp(&texels, map.width()).unwrap(),
    )
    .unwrap();
    dir
}

/// The project's cylinder and textures with a normal map of one texel value everywhere.
fn assets_with_constant_normal_map(name: &str, texel: [u8; 3]) -> PathBuf {
    assets_with_normal_map(name, move |_| texel)
}

// Fails if --green down does not read a map whose green was inverted (255 − g) as the original map is
// read with green up. On a map of one tilted texel, mipmaps are exact, so the two frames may differ
// only by float rounding (bound: 1 level). On the project's brick map, the mipmaps of the inverted
// bytes round half-way averages the other way (255 − round(a) ≠ round(255 − a)), and a byte of a
// coarse level moves the normal by 2/255: measured, 116 438 pixels differ, mean 1.46 levels, max 12
// in the highlights, against a mean of 21.4 when the inverted map is read green up.
#[test]
fn green_down_reads_an_inverted_green_as_green_up_reads_the_original() {
    let down = NormalMapConvention {
        green_down: true,
        ..Default::default()
    };
    let tilted = assets_with_constant_normal_map("tilted", [150, 90, 230]);
    let inverted = assets_with_constant_normal_map("tilted-inverted", [150, 165, 230]);
    let up = render(tilted, NormalMapConvention::default(), "lit");
    let flipped = render(inverted.clone(), down, "lit");
    let (differing, max, _) = pixel_diff(&up, &flipped);
    println!(
        "one tilted texel, green down on the inverted byte vs up: {differing} pixels, max {max}"
    );
    assert!(max <= 1, "{differing} pixels, max {max}");
    let (_, _, mean) = compare_drawn(
        &up,
        &render(inverted, NormalMapConvention::default(), "lit"),
    );
    assert!(mean > 1.0, "the green channel changes nothing? mean {mean}");

    let up = render(own_assets(), NormalMapConvention::default(), "lit");
    let inverted = assets_with_normal_map("green-inverted", |[r, g, b]| [r, 255 - g, b]);
    let flipped = render(inverted.clone(), down, "lit");
    let (differing, max, mean) = compare_drawn(&up, &flipped);
    let wrong = render(inverted, NormalMapConvention::default(), "lit");
    let (_, _, wrong_mean) = compare_drawn(&up, &wrong);
    println!(
        "brick map, green down on the inverted map vs up: {differing} pixels, max {max}, mean \
         {mean:.4}; read green up instead: mean {wrong_mean:.2}"
    );
    assert!(
        mean < 2.0 && max <= 16,
        "{differing} pixels, max {max}, mean {mean}"
    );
    assert!(wrong_mean > 4.0 * mean, "{wrong_mean} against {mean}");
}

// Fails if a two-channel map (blue 0, as `tutorial13 normalmap --two-channel` writes) read with z
// rebuilt does not draw the three-channel map it came from. On one texel the only difference is the
// stored z's rounding (bound: 1 level). On the brick map the mipmaps differ in kind: averaging x and y
// and rebuilding z gives a steeper normal than averaging all three, so minified grazing areas move:
// measured, 24 528 pixels differ, mean 0.14 levels, max 49; bound: mean under 0.2.
#[test]
fn a_two_channel_map_draws_the_three_channel_frame() {
    let rebuilt = NormalMapConvention {
        two_channel: true,
        ..Default::default()
    };
    // A texel whose blue holds the unit-length z of its red and green, rounded to a byte.
    let (r, g) = (150u8, 90u8);
    let (x, y) = (r as f32 / 255.0 * 2.0 - 1.0, g as f32 / 255.0 * 2.0 - 1.0);
    let z = (1.0 - x * x - y * y).sqrt();
    let b = ((z + 1.0) / 2.0 * 255.0).round() as u8;
    let three = render(
        assets_with_constant_normal_map("three", [r, g, b]),
        NormalMapConvention::default(),
        "lit",
    );
    let two = render(
        assets_with_constant_normal_map("two", [r, g, 0]),
        rebuilt,
        "lit",
    );
    let (differing, max, _) = pixel_diff(&three, &two);
    println!("one texel ({r}, {g}, {b}), two channels vs three: {differing} pixels, max {max}");
    assert!(max <= 1, "{differing} pixels, max {max}");

    let three = render(own_assets(), NormalMapConvention::default(), "lit");
    let two_channel = assets_with_normal_map("two-channel", |[r, g, _]| [r, g, 0]);
    let two = render(two_channel.clone(), rebuilt, "lit");
    let (differing, max, mean) = compare_drawn(&three, &two);
    println!("brick map, two channels, z rebuilt, vs three: {differing} pixels, max {max}, mean {mean:.4}");
    assert!(mean < 0.2, "{differing} pixels, max {max}, mean {mean}");
    // Read as three channels, blue 0 is z = -1: nothing like it.
    let (_, _, mean) = compare_drawn(
        &three,
        &render(two_channel, NormalMapConvention::default(), "lit"),
    );
    assert!(
        mean > 5.0,
        "blue 0 read as z = -1 changes nothing? mean {mean}"
    );
}

// Fails if the exact expansion does not read the flat texel (128, 128, 255) as exactly (0, 0, 1), or if
// the plain one does not show its 1/255 tilt: the raw texture-normal view is (0, 0, 255) on every
// cylinder pixel with the exact expansion and (1, 1, 255) with 2c − 1.
#[test]
fn exact_expansion_reads_128_as_zero() {
    let flat = flat_white_assets("flat-expansion");
    let exact = NormalMapConvention {
        exact_expansion: true,
        ..Default::default()
    };
    for (convention, want) in [
        (exact, [0, 0, 255]),
        (NormalMapConvention::default(), [1, 1, 255]),
    ] {
        let view = render(flat.clone(), convention, "normal");
        let cylinder: Vec<_> = view.pixels().filter(|p| !is_background(p)).collect();
        assert!(cylinder.len() > 100_000, "{}", cylinder.len());
        let wrong = cylinder.iter().filter(|p| p.0 != want).count();
        assert_eq!(wrong, 0, "{convention}: {wrong} pixels are not {want:?}");
    }
}

// Fails if the keys Y, E and Z do not switch the conventions, or the title's status does not say so.
#[test]
fn keys_switch_the_conventions() {
    let mut r = renderer(&options(own_assets(), Profile::Core));
    let scene = r.scene_mut::<Cylinder>();
    assert!(scene
        .status()
        .contains("green down (DirectX) off | exact expansion off | two channels off"));
    for key in ['Y', 'E', 'Z'] {
        assert!(scene.key(key).unwrap());
    }
    assert_eq!(
        scene.switches.convention,
        NormalMapConvention {
            green_down: true,
            exact_expansion: true,
            two_channel: true
        }
    );
    assert!(scene
        .status()
        .contains("green down (DirectX) on | exact expansion on | two channels on"));
}
