//! Photometric stereo's speed: `cargo bench -p tutorial13-benches --bench photometric`.
//! Figures go to BENCHMARKS.md.
//!
//! A capture as the public sets ship one: 96 linear 16-bit PNGs of 612×512, 96 lights of differing
//! brightness per channel. Reading the photos (decoding on every core) and solving them (the robust
//! default, and least squares) are timed apart, as a user waits for both.
//!
//! Four 2048² 8-bit sRGB photos of a bumpy surface (a sum of sines, some of it steep enough to be
//! in shadow under every light) with a varying albedo, lit from four directions 50°–60° above it.
//! `recover` is timed on photos already decoded, on one band of rows and on two; `run` is the whole
//! command: reading four PNGs, solving on every core, writing the normal map and the albedo as PNGs.

use std::path::PathBuf;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion};
use glam::Vec3;
use tutorial13::normalmap::Green;
use tutorial13::photometric::photo::{Encoding, Photo};
use tutorial13::photometric::{load_photos, recover, recover_calibrated, run};
use tutorial13::photometric::{Calibration, Job, PhotometricOptions, Solver};

#[path = "../tests/support/capture_rig.rs"]
mod capture_rig;

use capture_rig::rig;

const SIDE: u32 = 2048;

fn lights() -> [Vec3; 4] {
    [
        (1.0, 0.2, 1.4),
        (-0.3, 1.0, 1.6),
        (-1.0, -0.4, 1.4),
        (0.2, -1.0, 1.7),
    ]
    .map(Vec3::from)
}

/// The photo under `light`: albedo × max(0, n·l) in linear light, sRGB-encoded.
fn photo(light: Vec3) -> image::RgbImage {
    let l = light.normalize();
    image::RgbImage::from_fn(SIDE, SIDE, |x, y| {
        let (u, v) = (x as f32 / 37.0, y as f32 / 23.0);
        // Height 3 sin u sin v + sin 3u: its slopes, in texels of height per texel.
        let dx = (3.0 * u.cos() * v.sin() + 3.0 * (3.0 * u).cos()) / 37.0 * 12.0;
        let dy = 3.0 * u.sin() * v.cos() / 23.0 * 12.0;
        let n = Vec3::new(-dx, dy, 1.0).normalize();
        let albedo = [
            0.5 + 0.3 * (u * 0.1).sin(),
            0.4,
            0.3 + 0.2 * (v * 0.07).cos(),
        ];
        image::Rgb(albedo.map(|a| {
            let lit = a * n.dot(l).max(0.0);
            (Encoding::Srgb.from_linear(lit) * 255.0).round() as u8
        }))
    })
}

fn photometric(c: &mut Criterion) {
    let images: Vec<image::RgbImage> = lights().into_iter().map(photo).collect();
    let photos: Vec<Photo> = images
        .iter()
        .map(|i| Photo::from_image(i.clone().into()))
        .collect();
    let mut group = c.benchmark_group("photometric 2048² × 4");
    group.sample_size(10).warm_up_time(Duration::from_secs(1));
    for threads in [1, 2] {
        for albedo in [false, true] {
            let options = PhotometricOptions {
                albedo,
                threads,
                ..Default::default()
            };
            let name = format!("recover, {threads} thread(s), albedo {albedo}");
            group.bench_function(name, |b| {
                b.iter(|| recover(&photos, &lights(), &options).unwrap())
            });
        }
    }
    let dir = std::env::temp_dir().join("tutorial13-bench-photometric");
    std::fs::create_dir_all(&dir).unwrap();
    let paths: Vec<PathBuf> = (0..images.len())
        .map(|i| dir.join(format!("photo{i}.png")))
        .collect();
    for (image, path) in images.iter().zip(&paths) {
        image.save(path).unwrap();
    }
    let light_args: Vec<String> = lights()
        .iter()
        .map(|l| format!("{},{},{}", l.x, l.y, l.z))
        .collect();
    let (normal, albedo) = (dir.join("normal.png"), dir.join("albedo.png"));
    let job = Job {
        photos: &paths,
        lights: &light_args,
        lights_file: None,
        intensities: &[],
        intensities_file: None,
        mask: None,
        output: &normal,
        solver: None,
        sixteen_bit: false,
        albedo: Some(&albedo),
        encoding: Encoding::Srgb,
        green: Green::Up,
        shadow: tutorial13::photometric::DEFAULT_SHADOW,
    };
    group.bench_function("run: read 4 PNGs, solve, write 2 PNGs", |b| {
        b.iter(|| run(&job).unwrap())
    });
    group.finish();
}

fn capture(c: &mut Criterion) {
    let (width, height) = (612, 512);
    let rig = rig();
    let dir = std::env::temp_dir().join("tutorial13-bench-photometric-96");
    std::fs::create_dir_all(&dir).unwrap();
    let paths: Vec<PathBuf> = (1..=rig.len())
        .map(|k| dir.join(format!("{k:03}.png")))
        .collect();
    for ((l, e), path) in rig.iter().zip(&paths) {
        // The bench's bumpy surface, with a white Blinn-Phong highlight, in linear light.
        let half = (*l + Vec3::Z).normalize();
        let photo = image::ImageBuffer::<image::Rgb<u16>, _>::from_fn(width, height, |x, y| {
            let (u, v) = (x as f32 / 37.0, y as f32 / 23.0);
            let dx = (3.0 * u.cos() * v.sin() + 3.0 * (3.0 * u).cos()) / 37.0 * 12.0;
            let dy = 3.0 * u.sin() * v.cos() / 23.0 * 12.0;
            let n = Vec3::new(-dx, dy, 1.0).normalize();
            let lit = n.dot(*l).max(0.0);
            let shine = if lit > 0.0 {
                0.3 * n.dot(half).max(0.0).powf(100.0)
            } else {
                0.0
            };
            let albedo = [0.5, 0.4, 0.3];
            image::Rgb([0, 1, 2].map(|c| {
                let value = e[c] * (albedo[c] * lit + shine);
                (value.clamp(0.0, 1.0) * 65535.0).round() as u16
            }))
        });
        photo.save(path).unwrap();
    }
    let lights: Vec<Vec3> = rig.iter().map(|(l, _)| *l).collect();
    let calibration = Calibration {
        intensities: Some(rig.iter().map(|(_, e)| *e).collect()),
        mask: None,
    };
    let mut group = c.benchmark_group("photometric 612×512 × 96");
    group.sample_size(10).warm_up_time(Duration::from_secs(1));
    group.bench_function("read 96 16-bit PNGs, 2 threads", |b| {
        b.iter(|| load_photos(&paths, 2).unwrap())
    });
    let photos = load_photos(&paths, 2).unwrap();
    for (solver, name) in [(Solver::Robust, "robust"), (Solver::LeastSquares, "lstsq")] {
        for threads in [1, 2] {
            let options = PhotometricOptions {
                solver: Some(solver),
                encoding: Encoding::Linear,
                threads,
                ..Default::default()
            };
            group.bench_function(format!("solve, {name}, {threads} thread(s)"), |b| {
                b.iter(|| recover_calibrated(&photos, &lights, &calibration, &options).unwrap())
            });
        }
    }
    group.finish();
}

criterion_group!(benches, photometric, capture);
criterion_main!(benches);
