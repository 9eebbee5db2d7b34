//! The compare view (`--compare A,B`, key K): two tangent sources in one frame, side by side or as a
//! heat map of their difference.

use crate::common::{
    cylinder_frame, cylinder_renderer, frame, options, own_assets, pixel_diff, renderer, W,
};
use image::RgbImage;
use tutorial13::debug::compare::{heat_colour, CompareMode};
use tutorial13::frontends::headless::HeadlessRenderer;
use tutorial13::gl::Profile;
use tutorial13::scenes::cylinder::{self, Comparing, Cylinder};
use tutorial13::scenes::Scene;
use tutorial13::scenes::SceneOptions;
use tutorial13::tangent_source::TangentSource;

fn alone(source: TangentSource) -> RgbImage {
    cylinder_frame(own_assets(), |o| {
        o.start(cylinder::TANGENTS.to(source));
    })
}

/// The cylinder started in the compare view of `sources`.
fn compare_renderer(
    sources: [TangentSource; 2],
    mode: CompareMode,
    split: f32,
) -> HeadlessRenderer {
    cylinder_renderer(own_assets(), |o| {
        o.start(cylinder::COMPARE.to(Comparing::pair(sources, mode)));
        o.start(cylinder::SPLIT.to(split));
    })
}

fn compared(sources: [TangentSource; 2], mode: CompareMode, split: f32) -> RgbImage {
    frame(&mut compare_renderer(sources, mode, split))
}

// Fails if either half of the split view is not, pixel for pixel, the frame its source draws alone
// (left of the split line the first source, right of it the second), or if the split line is not a
// white column where the split says. Checked for two pairs and two split positions.
#[test]
fn each_half_is_its_source_drawn_alone() {
    use TangentSource::*;
    for (sources, split) in [
        ([Tutorial, MikkTSpace], 0.5),
        ([MikkTSpace, Derivative], 0.45),
    ] {
        let view = compared(sources, CompareMode::Split, split);
        let (a, b) = (alone(sources[0]), alone(sources[1]));
        let column = (split * W as f32).round() as u32;
        let mut wrong = 0;
        for (x, y, p) in view.enumerate_pixels() {
            let want = match x.cmp(&column) {
                std::cmp::Ordering::Less => a.get_pixel(x, y),
                std::cmp::Ordering::Equal => &image::Rgb([255, 255, 255]),
                std::cmp::Ordering::Greater => b.get_pixel(x, y),
            };
            wrong += usize::from(p != want);
        }
        println!("{sources:?} split at column {column}: {wrong} pixels wrong");
        assert_eq!(wrong, 0, "{sources:?}");
        // The two sources do differ on both sides, so a view showing one source twice would fail.
        let (differing, _, bbox) = pixel_diff(&a, &b);
        assert!(
            differing > 1000,
            "{differing}: the sources are alike, the test proves nothing"
        );
        assert!(
            bbox.is_some_and(|(x0, _, x1, _)| x0 < column && x1 > column),
            "the sources differ on one side of the split only: {bbox:?}"
        );
    }
}

// Fails if the difference mode does not show the heat map of the two sources' own frames, or reports
// another largest difference than those frames have (read in the status line, as in the title).
// Checked at the window's size and at one that is no multiple of 4 (the heat pass colours blocks of
// 16 × 16 pixels where a pixel differs; a block clipped wrong at the frame's edge would show).
#[test]
fn the_heat_map_is_the_difference_of_the_sources_alone() {
    assert_heat_map_is_the_difference((W, crate::common::H));
    assert_heat_map_is_the_difference((1001, 749));
}

fn assert_heat_map_is_the_difference((width, height): (u32, u32)) {
    let sources = [TangentSource::Tutorial, TangentSource::MikkTSpace];
    let at_size = |set: &dyn Fn(&mut SceneOptions)| {
        let mut options = options(own_assets(), Profile::Core);
        (options.width, options.height) = (width, height);
        set(&mut options.scene);
        renderer(&options)
    };
    let mut r = at_size(&|o| {
        o.start(cylinder::COMPARE.to(Comparing::pair(sources, CompareMode::Difference)));
        o.start(cylinder::SPLIT.to(0.5));
    });
    let view = frame(&mut r);
    let [a, b] = sources.map(|source| {
        frame(&mut at_size(&|o| {
            o.start(cylinder::TANGENTS.to(source));
        }))
    });
    // Without the view's own function: each pixel's largest channel difference, and the colours the
    // ramp must give it (black where the sources agree, white at the largest difference, a dark
    // red of at least 96 for the smallest).
    let deltas: Vec<u8> = a
        .pixels()
        .zip(b.pixels())
        .map(|(p, q)| (0..3).map(|c| p[c].abs_diff(q[c])).max().unwrap())
        .collect();
    let max = *deltas.iter().max().unwrap();
    let smallest = *deltas.iter().filter(|&&d| d > 0).min().unwrap();
    let expected = |d: u8| {
        match d {
            0 => [0, 0, 0],
            d if d == max => [255, 255, 255],
            d if d == smallest && (d as f32) / (max as f32) < 0.34 => {
                let red = (((d as f32 / max as f32) + 0.5) / 0.84 * 255.0) as u8;
                [red.max(96), 0, 0]
            }
            _ => return None,
        }
        .into()
    };
    let mut checked = [0usize; 3];
    for (i, p) in view.pixels().enumerate() {
        let d = deltas[i];
        if let Some(colour) = expected(d) {
            assert_eq!(p.0, colour, "pixel {i}: difference {d} of at most {max}");
            checked[usize::from(d > 0) + usize::from(d == max)] += 1;
        }
    }
    let drawn = view.pixels().filter(|p| p.0 != [0, 0, 0]).count();
    let differing_sources = deltas.iter().filter(|&&d| d > 0).count();
    println!(
        "{width} × {height}: checked {checked:?} pixels (same, smallest, largest); largest {max}, \
         smallest {smallest}"
    );
    assert_eq!(drawn, differing_sources, "pixels lit in the heat map");
    assert!(checked.iter().all(|&n| n > 0), "{checked:?}");
    // Every pixel: the ramp's colour for its difference, relative to the largest.
    let heat = RgbImage::from_fn(view.width(), view.height(), |x, y| {
        let [r, g, b, _] = heat_colour(deltas[(y * view.width() + x) as usize], max);
        image::Rgb([r, g, b])
    });
    let difference = (differing_sources, max);
    let (differing, _, _) = pixel_diff(&view, &heat);
    let status = r.scene_ref::<Cylinder>().status();
    println!("{status}");
    assert_eq!(differing, 0, "the heat map is not the sources' difference");
    assert!(max > 0 && differing_sources > 1000, "{difference:?}");
    assert!(
        status.ends_with(&format!(
            "compare tutorial - mikktspace: {differing_sources} pixels differ, max {max} levels"
        )),
        "{status}"
    );
}

// Fails if K does not step off → split → difference → off, A and D do not move the split line, or
// the frame after the view is turned off is not the plain frame again.
#[test]
fn keys_drive_the_compare_view() {
    let mut r = renderer(&options(own_assets(), Profile::Core));
    let plain = frame(&mut r);
    let cylinder = r.scene_mut::<Cylinder>();
    assert!(cylinder.compare_view().is_none());
    cylinder.key('K').unwrap();
    assert_eq!(cylinder.compare_view().unwrap().mode, CompareMode::Split);
    cylinder.key('D').unwrap();
    cylinder.key('D').unwrap();
    cylinder.key('A').unwrap();
    assert!((cylinder.compare_view().unwrap().split - 0.55).abs() < 1e-6);
    assert!(cylinder
        .status()
        .ends_with("compare tutorial | mikktspace at 55 %"));
    let split = frame(&mut r);
    assert_ne!(split, plain);
    let cylinder = r.scene_mut::<Cylinder>();
    cylinder.key('K').unwrap();
    assert_eq!(
        cylinder.compare_view().unwrap().mode,
        CompareMode::Difference
    );
    frame(&mut r);
    let cylinder = r.scene_mut::<Cylinder>();
    cylinder.key('K').unwrap();
    assert!(cylinder.compare_view().is_none());
    assert!(frame(&mut r) == plain);
}
