//! The CPU pipeline end to end: load_obj_threaded → compute_tangent_basis → index_vbo_tbn, on the tutorial's
//! own cylinder, on large generated meshes, and on random soups against the linear-search reference.

use std::path::Path;

use glam::{Vec2, Vec3};
use proptest::prelude::*;
use tutorial13::assets::obj_text::{charted_cylinder_obj_text, grid_cylinder_obj_text};
use tutorial13::common::objloader::TriangleSoup;
use tutorial13::common::tangentspace::{compute_tangent_basis, TangentBasis, TangentOptions};
use tutorial13::common::vboindexer::{self, IndexOptions, Indices};
use tutorial13::gl::Profile;
use tutorial13::mesh::{
    build_mesh, BuiltBy, Code, MeshOptions, PORTS_UP_TO_OBJ_BYTES, PORTS_UP_TO_TRIANGLES,
};
use tutorial13::pipeline::indexer::{index_vbo_hashed, index_vbo_tbn_hashed};
use tutorial13::pipeline::obj_parse::{load_obj_bytes_threaded, load_obj_threaded};
use tutorial13::scenes::cylinder::tutorial13::load_mesh;
use tutorial13::scenes::cylinder::Cylinder;

use crate::common;

// Fails if loading, V negation or the 0.01 merging differ from the original, which turns the
// tutorial's 64 triangles (192 corners) into 66 vertices with 16-bit indices.
#[test]
fn tutorial_cylinder_indexes_to_66_vertices() {
    let Some(original) = common::original_assets("tutorial_cylinder_indexes_to_66_vertices") else {
        return;
    };
    let soup = load_obj_threaded(&original.join("cylinder.obj")).unwrap();
    assert_eq!(soup.triangle_count(), 64);
    assert_eq!(soup.vertices.len(), 192);
    // V is negated: the file's V runs from about 0 to 1.
    assert!(soup.uvs.iter().all(|uv| (-1.0001..=0.0001).contains(&uv.y)));
    let (mesh, _) = load_mesh(&original.join("cylinder.obj"), MeshOptions::default()).unwrap();
    assert_eq!(mesh.vertices.len(), 66);
    assert_eq!(mesh.indices.len(), 192);
    assert!(matches!(mesh.indices, Indices::U16(_)));
    let basis = compute_tangent_basis(&soup, TangentOptions::default());
    let reference = vboindexer::index_vbo_tbn(&soup, &basis, IndexOptions::default());
    assert_eq!(mesh, reference);
    // The fast twin, which a larger model gets, gives the same mesh to the bit.
    let twin = index_vbo_tbn_hashed(&soup, &basis, IndexOptions::default());
    assert_eq!(twin, reference);
    // Every summed tangent points around the cylinder (perpendicular to the axis and the normal).
    for (t, n) in mesh.tangents.iter().zip(&mesh.normals) {
        let t = t.normalize();
        assert!(t.y.abs() < 1e-3 && t.dot(*n).abs() < 1e-3, "{t} {n}");
    }
}

// Fails if the generated cylinder's winding, seam or normals are off: every face's geometric normal
// must agree with its corners' normals, and the seam must cost exactly one extra column of vertices.
#[test]
fn generated_cylinder_is_outward_and_seamed() {
    let (segments, rings) = (32, 4);
    let text = grid_cylinder_obj_text(segments, rings, 1.0, 2.0, 2.3);
    let soup = load_obj_bytes_threaded(text.as_bytes(), Path::new("generated.obj")).unwrap();
    assert_eq!(soup.triangle_count(), (2 * segments * rings) as usize);
    for tri in 0..soup.triangle_count() {
        let v = &soup.vertices[3 * tri..3 * tri + 3];
        let face_normal = (v[1] - v[0]).cross(v[2] - v[0]);
        for n in &soup.normals[3 * tri..3 * tri + 3] {
            assert!(face_normal.dot(*n) > 0.0, "triangle {tri} faces inwards");
        }
    }
    let mesh = build_mesh(&soup, MeshOptions::default());
    assert_eq!(mesh.vertices.len(), ((segments + 1) * (rings + 1)) as usize);
}

// Fails if indices stay 16-bit past 65 535 vertices (the original wraps) or if any corner ends up
// naming a vertex with other attributes.
#[test]
fn more_than_65535_vertices_use_32_bit_indices_and_lose_nothing() {
    // Radius 40 and height 40 keep neighbouring vertices more than 0.01 apart, so none merge.
    let (segments, rings) = (400, 200);
    let text = grid_cylinder_obj_text(segments, rings, 40.0, 40.0, 8.0);
    let soup = load_obj_bytes_threaded(text.as_bytes(), Path::new("big.obj")).unwrap();
    let mesh = build_mesh(&soup, MeshOptions::default());
    let expected_vertices = ((segments + 1) * (rings + 1)) as usize;
    assert!(expected_vertices > 65_535);
    assert_eq!(mesh.vertices.len(), expected_vertices);
    let Indices::U32(indices) = &mesh.indices else {
        panic!("{} vertices with 16-bit indices", mesh.vertices.len());
    };
    assert_eq!(indices.len(), soup.vertices.len());
    for (corner, &index) in indices.iter().enumerate() {
        let i = index as usize;
        assert_eq!(mesh.vertices[i], soup.vertices[corner]);
        assert_eq!(mesh.uvs[i], soup.uvs[corner]);
        assert_eq!(mesh.normals[i], soup.normals[corner]);
    }
    // Corners equal bit for bit, so the plain indexer agrees on every index.
    assert_eq!(index_vbo_hashed(&soup).indices, mesh.indices);
}

/// What built the cylinder scene's mesh, and its first frame, on `assets` with `code` forced (or by
/// size), or with `model`.
fn built_by_and_frame(
    assets: &Path,
    model: Option<&Path>,
    code: Option<Code>,
) -> (Option<BuiltBy>, image::RgbImage) {
    let mut options = common::options(assets.to_path_buf(), Profile::Core);
    let cylinder = common::cylinder_files(&mut options);
    cylinder.code = code;
    cylinder.model = model.map(Path::to_path_buf);
    let mut renderer = common::renderer(&options);
    let built_by = renderer.scene_ref::<Cylinder>().tutorial.built_by;
    (built_by, common::frame(&mut renderer))
}

// Fails if the tutorial's cylinder (the project's and the tutorial's own, 64 triangles each) is not
// read and indexed by the ports in src/common/ that the reading guide and the tour show (the
// program ran the fast twins before: it would report FastTwins), if a mesh above the stated size
// is not handed to the twins (a learner's model would wait on the quadratic search: FastTwins
// expected for an OBJ above PORTS_UP_TO_OBJ_BYTES with more than PORTS_UP_TO_TRIANGLES
// triangles, and for a model's indexing), or if the twins draw one pixel otherwise than the ports
// on the same cylinder.
#[test]
fn the_tutorials_cylinder_runs_the_ports_and_larger_meshes_the_twins() {
    let ports = BuiltBy {
        load_obj: Some(Code::Ports),
        index_vbo_tbn: Code::Ports,
    };
    let own = common::own_assets();
    let (built_by, by_size) = built_by_and_frame(&own, None, None);
    assert_eq!(built_by, Some(ports));
    let (built_by, twins) = built_by_and_frame(&own, None, Some(Code::FastTwins));
    assert_eq!(
        built_by,
        Some(BuiltBy {
            load_obj: Some(Code::FastTwins),
            index_vbo_tbn: Code::FastTwins,
        })
    );
    assert_eq!(common::differing_pixels(&by_size, &twins), 0);
    if let Some(original) = common::original_assets("the_tutorials_cylinder_runs_the_ports") {
        assert_eq!(built_by_and_frame(&original, None, None).0, Some(ports));
    }

    // 64 × 36 × 2 = 4 608 triangles, about 300 KiB of OBJ: both above the ports' sizes.
    let text = grid_cylinder_obj_text(64, 36, 1.0, 2.0, 2.0);
    assert!(text.len() as u64 > PORTS_UP_TO_OBJ_BYTES && 64 * 36 * 2 > PORTS_UP_TO_TRIANGLES);
    let big = common::flat_assets("twins", &text, [200; 4], [40; 4]);
    let twins = BuiltBy {
        load_obj: Some(Code::FastTwins),
        index_vbo_tbn: Code::FastTwins,
    };
    assert_eq!(built_by_and_frame(&big, None, None).0, Some(twins));
    let model = big.join("cylinder.obj");
    let (built_by, _) = built_by_and_frame(&own, Some(&model), None);
    assert_eq!(
        built_by,
        Some(BuiltBy {
            load_obj: None,
            index_vbo_tbn: Code::FastTwins,
        })
    );
}

// Fails if a missing or malformed OBJ panics or returns an error without the file's name.
#[test]
fn bad_obj_files_name_the_file() {
    let missing = Path::new("/nonexistent/dir/cylinder.obj");
    let e = load_mesh(missing, MeshOptions::default()).unwrap_err();
    assert!(
        e.to_string().starts_with("/nonexistent/dir/cylinder.obj: "),
        "{e}"
    );
    let dir = common::scratch("no-normals");
    let bad = dir.join("no-normals.obj");
    std::fs::write(&bad, "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/1\n").unwrap();
    let e = load_mesh(&bad, MeshOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("no-normals.obj") && e.contains("normal"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}

// Fails if either indexer's output changes by one bit (vertex order, indices, tangent sums) from its
// reference (the tutorial's linear search, the tutorial's map) on meshes shaped like real ones: a
// cylinder whose vertices stay apart, one so dense that the 0.01 tolerance merges neighbours, one
// cut into UV charts (positions repeated with other UVs along every seam), and corners that differ
// only in the sign of a zero. Every speed-up of the indexers is checked against this.
#[test]
fn indexers_equal_references_bit_for_bit() {
    let meshes = [
        ("apart", grid_cylinder_obj_text(100, 40, 1.0, 2.0, 2.3)),
        // 700 segments of radius 1: neighbours 0.009 apart in position, 0.0014 in U and 0.009 in
        // the normal, so the tolerance merges them in chains.
        ("dense", grid_cylinder_obj_text(700, 6, 1.0, 0.03, 1.0)),
        ("charted", charted_cylinder_obj_text(120, 40, 1.2, 2.0, 7)),
    ];
    for (name, text) in meshes {
        let soup = load_obj_bytes_threaded(text.as_bytes(), Path::new(name)).unwrap();
        for options in [
            TangentOptions::default(),
            TangentOptions {
                gram_schmidt: false,
                ..TangentOptions::default()
            },
        ] {
            let basis = compute_tangent_basis(&soup, options);
            for normalize in [false, true] {
                if let Err(e) = common::indexers_match_references(&soup, &basis, normalize) {
                    panic!("{name}, {options:?}, normalize {normalize}: {e}");
                }
            }
        }
    }
    let merged = |text: &str| {
        let soup = load_obj_bytes_threaded(text.as_bytes(), Path::new("m")).unwrap();
        build_mesh(&soup, MeshOptions::default()).vertices.len()
    };
    // The dense cylinder really merges within the tolerance (7 × 701 corners' positions otherwise).
    assert!(merged(&grid_cylinder_obj_text(700, 6, 1.0, 0.03, 1.0)) < 7 * 500);
    // Signed zeros: 0.0 and -0.0 are near (one vertex for index_vbo_tbn) but not the same bytes (two
    // for index_vbo_hashed); a sum that starts at -0.0 stays -0.0 only if the first corner is stored, not added.
    let z = Vec3::new(0.0, -0.0, 0.0);
    let soup = TriangleSoup {
        vertices: vec![z, Vec3::ZERO, -z, z, -Vec3::ZERO, z],
        uvs: vec![Vec2::new(-0.0, 0.0); 6],
        normals: vec![Vec3::new(0.0, 0.0, -0.0); 6],
    };
    let basis = TangentBasis {
        tangents: vec![
            -Vec3::ZERO,
            Vec3::X,
            -Vec3::ZERO,
            -Vec3::ZERO,
            Vec3::ZERO,
            Vec3::Y,
        ],
        bitangents: vec![-Vec3::ZERO; 6],
    };
    for normalize in [false, true] {
        common::indexers_match_references(&soup, &basis, normalize).unwrap();
    }
}

// Fails if the charted cylinder (the benchmarks' mesh with seams) loses its seams or merges across
// them: each chart of 7 × 7 quads (fewer at the ends) keeps its own grid of vertices, so the
// border positions index to one vertex per chart they belong to.
#[test]
fn charted_cylinder_keeps_a_vertex_per_chart() {
    let (segments, rings, chart) = (50, 16, 7);
    let text = charted_cylinder_obj_text(segments, rings, 1.2, 2.0, chart);
    let soup = load_obj_bytes_threaded(text.as_bytes(), Path::new("charted.obj")).unwrap();
    assert_eq!(soup.triangle_count(), (2 * segments * rings) as usize);
    let side = |n: u32| (0..n.div_ceil(chart)).map(move |c| chart.min(n - c * chart) + 1);
    let expected: u32 = side(segments)
        .flat_map(|w| side(rings).map(move |h| w * h))
        .sum();
    let mesh = build_mesh(&soup, MeshOptions::default());
    assert_eq!(mesh.vertices.len(), expected as usize);
    assert_eq!(index_vbo_hashed(&soup).vertices.len(), expected as usize);
    assert!(expected > (segments + 1) * (rings + 1));
}

/// Offsets that stress the 0.01 test: zero half the time, else just inside or just outside the
/// tolerance, or far.
fn offset() -> impl Strategy<Value = f32> {
    prop_oneof![
        Just(0.0f32),
        prop::sample::select(vec![
            0.0001f32, -0.0001, 0.004, -0.004, 0.005, -0.005, 0.0099, -0.0099, 0.00999, -0.00999,
            0.01, -0.01, 0.0101, -0.0101, 0.015, -0.015, 0.02, -0.02,
        ]),
    ]
}

/// A corner: one of a few anchors (so that corners land near each other and near several earlier
/// vertices at once, making ties) plus a small offset on each of its eight components. Anchors are
/// arbitrary floats, so neighbourhoods straddle grid cells at every possible place.
fn soup_strategy() -> impl Strategy<Value = (TriangleSoup, TangentBasis)> {
    let anchors = prop::collection::vec(prop::array::uniform8(-1.0f32..1.0), 1..5);
    anchors.prop_flat_map(|anchors| {
        let count = anchors.len();
        let corner = (
            0..count,
            prop::array::uniform8(offset()),
            prop::array::uniform3(-2.0f32..2.0),
        );
        prop::collection::vec(prop::collection::vec(corner, 3), 1..80).prop_map(move |triangles| {
            let mut soup = TriangleSoup::default();
            let mut basis = TangentBasis::default();
            for (anchor, offsets, t) in triangles.into_iter().flatten() {
                let c: Vec<f32> = anchors[anchor]
                    .iter()
                    .zip(offsets)
                    .map(|(a, o)| a + o)
                    .collect();
                soup.vertices.push(Vec3::new(c[0], c[1], c[2]));
                soup.uvs.push(Vec2::new(c[3], c[4]));
                soup.normals.push(Vec3::new(c[5], c[6], c[7]));
                basis.tangents.push(Vec3::from(t));
                basis.bitangents.push(Vec3::new(t[1], t[2], t[0]) * 0.5);
            }
            (soup, basis)
        })
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(1000))]

    // Fails if the grid indexer ever picks another vertex than the linear search (ties included), or
    // sums tangents in another order: indices, vertices and sums must be identical to the bit.
    #[test]
    fn fast_indexer_equals_linear_reference((soup, basis) in soup_strategy(), normalize in any::<bool>()) {
        common::indexers_match_references(&soup, &basis, normalize)?;
    }
}
