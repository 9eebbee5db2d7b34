//! The CPU pipeline's speed: `cargo bench -p tutorial13-benches --bench pipeline`. Figures go to BENCHMARKS.md.
//!
//! Meshes are generated open cylinders (the tutorial's shape) scaled so that neighbouring vertices
//! stay more than 0.01 apart: the tutorial's indexer would otherwise merge them, and the mesh would
//! no longer be the size it says.

use std::path::{Path, PathBuf};

mod common;
#[path = "../tests/support/mikktspace_reference.rs"]
mod mikktspace_reference;

use common::{cylinder, spread_soup, ten_samples};
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use glam::Vec3;
use tutorial13::common::objloader::TriangleSoup;
use tutorial13::common::tangentspace::{compute_tangent_basis, TangentOptions};
use tutorial13::common::vboindexer::{self, IndexOptions};
use tutorial13::mesh::{build_mesh, MeshOptions};
use tutorial13::pipeline::indexer::index_vbo_tbn_hashed;
use tutorial13::pipeline::obj_parse::load_obj_threaded;
use tutorial13::tangent_source::TangentSource;

fn write_obj(name: &str, segments: u32, rings: u32) -> PathBuf {
    let dir = std::env::temp_dir().join("tutorial13-bench");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, cylinder(segments, rings)).unwrap();
    path
}

/// The soup of a generated cylinder's OBJ file, as a learner's file is read.
fn cylinder_soup(label: &str, segments: u32, rings: u32) -> TriangleSoup {
    soup_of(&write_obj(
        &format!("cylinder-{label}.obj"),
        segments,
        rings,
    ))
}

fn soup_of(path: &Path) -> TriangleSoup {
    load_obj_threaded(path).unwrap()
}

/// load_obj_threaded + compute_tangent_basis + index_vbo_tbn_hashed, from the file on disk.
fn whole_pipeline(c: &mut Criterion) {
    let mut group = ten_samples(c, "pipeline", 1.0);
    for (label, segments, rings) in [("10k", 100, 50), ("100k", 500, 100), ("1M", 1000, 500)] {
        let path = write_obj(&format!("cylinder-{label}.obj"), segments, rings);
        group.bench_function(BenchmarkId::new("obj+tangents+index", label), |b| {
            b.iter(|| build_mesh(&soup_of(&path), MeshOptions::default()))
        });
    }
    group.finish();
}

/// The grid indexer against the tutorial's linear search, on the same soup: the ratio is the figure.
fn indexers(c: &mut Criterion) {
    let mut group = ten_samples(c, "index_vbo_tbn_hashed", 0.5);
    for (label, segments, rings) in [("20k", 100, 100), ("60k", 300, 100)] {
        let soup = cylinder_soup(label, segments, rings);
        let basis = compute_tangent_basis(&soup, TangentOptions::default());
        group.bench_function(BenchmarkId::new("grid", label), |b| {
            b.iter(|| index_vbo_tbn_hashed(&soup, &basis, IndexOptions::default()))
        });
        group.bench_function(BenchmarkId::new("linear", label), |b| {
            b.iter(|| vboindexer::index_vbo_tbn(&soup, &basis, IndexOptions::default()))
        });
    }
    group.finish();
}

/// The worst case of the position grid (every vertex in one cell) against a mesh of the same size
/// whose positions are all distinct: the split is meant to keep it within 10× of that.
fn one_cell(c: &mut Criterion) {
    let mut group = ten_samples(c, "one_cell", 0.5);
    for (label, position) in [
        ("distinct-positions/20k", None),
        ("one-position-mid-cell/20k", Some(Vec3::ZERO)),
        ("one-position-cell-corner/20k", Some(Vec3::splat(0.025))),
    ] {
        let soup = spread_soup(position);
        let basis = compute_tangent_basis(&soup, TangentOptions::default());
        group.bench_function(label, |b| {
            b.iter(|| index_vbo_tbn_hashed(&soup, &basis, IndexOptions::default()))
        });
    }
    group.finish();
}

/// The tangent sources of `--tangents` on the same soups: the tutorial's (computeTangentBasis, then
/// indexVBO_TBN summing them) against MikkTSpace's (the program's, then an exact weld), both
/// from the soup in memory to an indexed mesh with tangents; and MikkTSpace's tangents alone, the
/// program's against the `mikktspace` crate's (the same numbers to the bit). The per-pixel frame has no CPU cost
/// beyond `index_vbo`; its GPU cost is measured with `--bench` (BENCHMARKS.md).
fn tangent_sources(c: &mut Criterion) {
    let mut group = ten_samples(c, "tangent-sources", 1.0);
    for (label, segments, rings) in [("100k", 500, 100), ("1M", 1000, 500)] {
        let soup = cylinder_soup(label, segments, rings);
        group.bench_function(format!("tutorial/{label}"), |b| {
            b.iter(|| {
                TangentSource::Tutorial
                    .mesh(&soup, MeshOptions::default())
                    .unwrap()
            })
        });
        group.bench_function(format!("mikktspace/{label}"), |b| {
            b.iter(|| {
                TangentSource::MikkTSpace
                    .mesh(&soup, MeshOptions::default())
                    .unwrap()
            })
        });
        group.bench_function(format!("mikktspace-tangents/{label}"), |b| {
            b.iter(|| tutorial13::pipeline::mikktspace::mikktspace_tangents(&soup).unwrap())
        });
        group.bench_function(format!("mikktspace-crate-tangents/{label}"), |b| {
            b.iter(|| mikktspace_reference::reference_tangents(&soup).unwrap())
        });
    }
    group.finish();
}

/// Where the ports of `common/` stop and their fast twins in `pipeline/` take over (the program's
/// `mesh::PORTS_UP_TO`): the tutorial's quadratic `indexVBO_TBN` against the hash grid, and tobj's
/// `loadOBJ` against the parse on every core, on cylinders of growing size from the tutorial's 64
/// triangles (the same OBJ layout, written to disk as a learner's file is).
fn ports_or_twins(c: &mut Criterion) {
    let mut group = ten_samples(c, "ports-or-twins", 0.3);
    group.measurement_time(std::time::Duration::from_secs(1));
    for (segments, rings) in [(32, 1), (64, 2), (64, 8), (128, 16), (128, 40), (256, 32)] {
        let triangles = segments * rings * 2;
        let path = write_obj(&format!("cylinder-{triangles}.obj"), segments, rings);
        let soup = soup_of(&path);
        let basis = compute_tangent_basis(&soup, TangentOptions::default());
        group.bench_function(format!("index_vbo_tbn/{triangles}"), |b| {
            b.iter(|| vboindexer::index_vbo_tbn(&soup, &basis, IndexOptions::default()))
        });
        group.bench_function(format!("index_vbo_tbn_hashed/{triangles}"), |b| {
            b.iter(|| index_vbo_tbn_hashed(&soup, &basis, IndexOptions::default()))
        });
        group.bench_function(format!("load_obj/{triangles}"), |b| {
            b.iter(|| tutorial13::common::objloader::load_obj(&path).unwrap())
        });
        group.bench_function(format!("load_obj_threaded/{triangles}"), |b| {
            b.iter(|| load_obj_threaded(&path).unwrap())
        });
    }
    group.finish();
}

criterion_group!(
    benches,
    whole_pipeline,
    indexers,
    one_cell,
    tangent_sources,
    ports_or_twins
);
criterion_main!(benches);
