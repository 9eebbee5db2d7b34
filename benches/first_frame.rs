//! The CPU half of a first frame, against the tool people index meshes with:
//! `cargo bench -p tutorial13-benches --bench first_frame`. Figures go to BENCHMARKS.md.
//!
//! * `indexing`: `index_vbo_hashed`, `index_vbo_tbn_hashed` and meshoptimizer's remap (`generate_vertex_remap`,
//!   `remap_vertex_buffer`, `remap_index_buffer`, on the same corners interleaved, as meshoptimizer
//!   reads them) on the same soups. Before timing, all three must give the same vertex count.
//! * `first-frame-1M`: the split of a 1M-triangle cylinder's first frame: OBJ text to soup (the
//!   project's parse on every core, and tobj's with the checks beside it), `compute_tangent_basis`,
//!   `index_vbo_tbn_hashed`.
//!
//! Criterion runs one benchmark's samples after another, so a neighbour on a shared machine can
//! land on one of them only. With `TUTORIAL13_ROUNDS=N` in the environment the bench instead times
//! the three indexers once each per round, N rounds, in turn, and prints each one's minimum and
//! median and the median of the per-round ratios to meshoptimizer.

mod common;

use std::path::Path;
use std::time::Instant;

use common::{charted_cylinder, cylinder, slow_group, spread_soup};
use criterion::Criterion;
use glam::Vec3;
use tutorial13::common::objloader::{self, TriangleSoup};
use tutorial13::common::tangentspace::{compute_tangent_basis, TangentBasis, TangentOptions};
use tutorial13::common::vboindexer::IndexOptions;
use tutorial13::pipeline::indexer::{index_vbo_hashed, index_vbo_tbn_hashed};
use tutorial13::pipeline::obj_parse::load_obj_bytes_threaded;

/// One corner as meshoptimizer reads it: the 32 bytes `indexVBO` compares.
#[repr(C)]
#[derive(Clone, Copy, Default)]
struct Corner {
    position: [f32; 3],
    uv: [f32; 2],
    normal: [f32; 3],
}

fn interleave(soup: &TriangleSoup) -> Vec<Corner> {
    (0..soup.vertices.len())
        .map(|i| Corner {
            position: soup.vertices[i].to_array(),
            uv: soup.uvs[i].to_array(),
            normal: soup.normals[i].to_array(),
        })
        .collect()
}

/// meshoptimizer's way from a soup to an indexed mesh: the vertices and the index buffer.
fn meshopt_remap(corners: &[Corner]) -> (Vec<Corner>, Vec<u32>) {
    let (count, remap) = meshopt::generate_vertex_remap(corners, None);
    let vertices = meshopt::remap_vertex_buffer(corners, count, &remap);
    let indices = meshopt::remap_index_buffer(None, corners.len(), &remap);
    (vertices, indices)
}

fn soup_of(text: &str) -> TriangleSoup {
    load_obj_bytes_threaded(text.as_bytes(), Path::new("generated.obj")).unwrap()
}

/// A soup to index, with its tangents and its corners for meshoptimizer.
struct Case {
    label: &'static str,
    soup: TriangleSoup,
    basis: TangentBasis,
    corners: Vec<Corner>,
}

fn cases() -> Vec<Case> {
    let soups = [
        ("cylinder/100k", soup_of(&cylinder(500, 100))),
        ("cylinder/1M", soup_of(&cylinder(1000, 500))),
        ("charted/1M", soup_of(&charted_cylinder(1000, 500))),
        ("one-cell/20k", spread_soup(Some(Vec3::ZERO))),
    ];
    soups
        .into_iter()
        .map(|(label, soup)| {
            let basis = compute_tangent_basis(&soup, TangentOptions::default());
            let corners = interleave(&soup);
            // The three must agree on the mesh before their times mean anything.
            let vertices = meshopt_remap(&corners).0.len();
            let plain = index_vbo_hashed(&soup).vertices.len();
            let tbn = index_vbo_tbn_hashed(&soup, &basis, IndexOptions::default())
                .vertices
                .len();
            assert_eq!((plain, tbn), (vertices, vertices), "{label}");
            eprintln!(
                "{label}: {} corners, {vertices} vertices from each indexer",
                corners.len()
            );
            Case {
                label,
                soup,
                basis,
                corners,
            }
        })
        .collect()
}

/// A named run of one indexer on one case.
type Run<'a> = (&'static str, Box<dyn Fn() + 'a>);

/// The three indexers, by name, on one case (meshoptimizer first: the ratios' denominator).
fn indexers(case: &Case) -> [Run<'_>; 3] {
    [
        (
            "meshopt-remap",
            Box::new(|| drop(std::hint::black_box(meshopt_remap(&case.corners)))),
        ),
        (
            "index_vbo_hashed",
            Box::new(|| drop(std::hint::black_box(index_vbo_hashed(&case.soup)))),
        ),
        (
            "index_vbo_tbn_hashed",
            Box::new(|| {
                let options = IndexOptions::default();
                drop(std::hint::black_box(index_vbo_tbn_hashed(
                    &case.soup,
                    &case.basis,
                    options,
                )))
            }),
        ),
    ]
}

fn indexing(c: &mut Criterion, cases: &[Case]) {
    let mut group = slow_group(c, "indexing", 1.0, 4.0);
    for case in cases {
        for (name, run) in indexers(case) {
            group.bench_function(format!("{name}/{}", case.label), |b| b.iter(&run));
        }
    }
    group.finish();
}

fn first_frame(c: &mut Criterion) {
    let text = cylinder(1000, 500);
    let soup = soup_of(&text);
    let basis = compute_tangent_basis(&soup, TangentOptions::default());
    let mut group = slow_group(c, "first-frame-1M", 1.0, 8.0);
    group.bench_function("obj", |b| b.iter(|| soup_of(&text)));
    let path = Path::new("generated.obj");
    group.bench_function("obj-tobj", |b| {
        b.iter(|| objloader::load_obj_bytes(text.as_bytes(), path).unwrap())
    });
    group.bench_function("tangents", |b| {
        b.iter(|| compute_tangent_basis(&soup, TangentOptions::default()))
    });
    group.bench_function("index_vbo_tbn_hashed", |b| {
        b.iter(|| index_vbo_tbn_hashed(&soup, &basis, IndexOptions::default()))
    });
    group.finish();
}

/// `TUTORIAL13_ROUNDS=N`: the three indexers in turn, once per round (see the module docs).
fn rounds(cases: &[Case], rounds: usize) {
    for case in cases {
        let runs = indexers(case);
        let mut times = vec![Vec::new(); runs.len()];
        for round in 0..rounds {
            // Each round starts with another indexer, so none always runs right after the same one.
            for k in 0..runs.len() {
                let i = (round + k) % runs.len();
                let start = Instant::now();
                (runs[i].1)();
                times[i].push(start.elapsed().as_secs_f64() * 1e3);
            }
        }
        let median = |v: &[f64]| {
            let mut v = v.to_vec();
            v.sort_by(f64::total_cmp);
            v[v.len() / 2]
        };
        for (i, (name, _)) in runs.iter().enumerate() {
            let ratios: Vec<f64> = (0..rounds).map(|r| times[i][r] / times[0][r]).collect();
            let min = times[i].iter().copied().fold(f64::INFINITY, f64::min);
            println!(
                "{:<28} min {min:8.2} ms  median {:8.2} ms  median ratio to meshopt {:.2}",
                format!("{name}/{}", case.label),
                median(&times[i]),
                median(&ratios),
            );
        }
    }
}

fn main() {
    let cases = cases();
    if let Ok(n) = std::env::var("TUTORIAL13_ROUNDS") {
        rounds(
            &cases,
            n.parse().expect("TUTORIAL13_ROUNDS: a number of rounds"),
        );
        return;
    }
    let mut c = Criterion::default().configure_from_args();
    indexing(&mut c, &cases);
    first_frame(&mut c);
    c.final_summary();
}
