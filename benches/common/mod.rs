//! The meshes both CPU benches (`pipeline`, `first_frame`) run on.
#![allow(dead_code)] // each bench uses a different subset

use std::time::Duration;

use criterion::Criterion;
use glam::{Vec2, Vec3};
use tutorial13::assets::obj_text::{charted_cylinder_obj_text, grid_cylinder_obj_text};
use tutorial13::common::objloader::TriangleSoup;

/// `segments × rings × 2` triangles, about 0.06 apart around and 0.05 along the axis (so that no two
/// vertices are within the tutorial's 0.01 and the mesh indexes to `(segments + 1) × (rings + 1)`).
pub fn cylinder(segments: u32, rings: u32) -> String {
    grid_cylinder_obj_text(
        segments,
        rings,
        segments as f32 / 100.0,
        rings as f32 / 20.0,
        2.3,
    )
}

/// The same cylinder cut into UV charts of 25 × 25 quads: a seam (positions repeated with other UVs)
/// along every chart border, faces chart by chart, as a modelling tool exports a mesh.
pub fn charted_cylinder(segments: u32, rings: u32) -> String {
    charted_cylinder_obj_text(
        segments,
        rings,
        segments as f32 / 100.0,
        rings as f32 / 20.0,
        25,
    )
}

/// 20k triangles whose 60k corners all stay distinct vertices: UVs on a 0.02 grid (never within
/// 0.01 of each other), positions either all at `at` (one grid cell) or on the same 0.02 grid.
pub fn spread_soup(one_position: Option<Vec3>) -> TriangleSoup {
    let corners = 60_000;
    let grid = |i: usize| Vec2::new(0.02 * (i % 250) as f32, 0.02 * (i / 250) as f32);
    TriangleSoup {
        vertices: (0..corners)
            .map(|i| one_position.unwrap_or_else(|| grid(i).extend(0.0)))
            .collect(),
        uvs: (0..corners).map(grid).collect(),
        normals: vec![Vec3::Z; corners],
    }
}

/// A group of ten flat samples (each a whole run of a slow case), after `warm_up` seconds, measured
/// for `measure` seconds.
pub fn slow_group<'a>(c: &'a mut Criterion, name: &str, warm_up: f64, measure: f64) -> Group<'a> {
    let mut group = ten_samples(c, name, warm_up);
    group
        .sampling_mode(criterion::SamplingMode::Flat)
        .measurement_time(Duration::from_secs_f64(measure));
    group
}

/// A group of ten samples after `warm_up` seconds (criterion's default is a hundred).
pub fn ten_samples<'a>(c: &'a mut Criterion, name: &str, warm_up: f64) -> Group<'a> {
    let mut group = c.benchmark_group(name);
    group
        .sample_size(10)
        .warm_up_time(Duration::from_secs_f64(warm_up));
    group
}

type Group<'a> = criterion::BenchmarkGroup<'a, criterion::measurement::WallTime>;
