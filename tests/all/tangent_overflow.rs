//! Tangent and bitangent sums of a mesh near f32's range stay finite and usable.

use std::path::Path;

use glam::{Vec2, Vec3};
use tutorial13::common::objloader::TriangleSoup;
use tutorial13::common::tangentspace::TangentBasis;
use tutorial13::common::vboindexer::{self, IndexOptions};
use tutorial13::mesh::{build_mesh, MeshOptions};
use tutorial13::pipeline::indexer::index_vbo_tbn_hashed;
use tutorial13::pipeline::obj_parse::load_obj_bytes_threaded;

/// Every output tangent and bitangent is finite, not zero, and small enough for the shader's
/// products and squares.
fn assert_usable(t: Vec3, b: Vec3) {
    for v in [t, b] {
        assert!(v.is_finite(), "{t} {b}");
        assert!(v != Vec3::ZERO, "{t} {b}");
        assert!(v.abs().max_element() <= (1u64 << 40) as f32, "{t} {b}");
        let n = v.normalize();
        assert!(n.is_finite() && n.is_normalized(), "{v}");
    }
}

// Fails if two corners whose bitangents are finite but near f32::MAX sum to infinity (the
// shader's normalize then gives NaN): a mesh of one triangle repeated.
#[test]
fn huge_mesh_gives_finite_tbn() {
    let obj = "v 0 0 0\nv 3e38 0 0\nv 0 3e38 0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\n\
               f 1/1/1 2/2/1 3/3/1\nf 1/1/1 2/2/1 3/3/1\nf 1/1/1 2/2/1 3/3/1\n";
    let soup = load_obj_bytes_threaded(obj.as_bytes(), Path::new("huge.obj")).unwrap();
    for normalize_before_sum in [false, true] {
        let options = MeshOptions {
            indexing: IndexOptions {
                normalize_before_sum,
            },
            ..Default::default()
        };
        let mesh = build_mesh(&soup, options);
        assert_eq!(mesh.vertices.len(), 3);
        for (t, b) in mesh.tangents.iter().zip(&mesh.bitangents) {
            assert_usable(*t, *b);
            // V is negated on load, so the bitangent points along -y, and the handedness step
            // turns the tangent to -x.
            assert!(t.normalize().abs_diff_eq(-Vec3::X, 1e-6), "{t}");
            assert!(b.normalize().abs_diff_eq(-Vec3::Y, 1e-6), "{b}");
        }
    }
}

fn one_vertex_soup(bitangents: &[Vec3], tangents: &[Vec3]) -> (TriangleSoup, TangentBasis) {
    let n = bitangents.len();
    let soup = TriangleSoup {
        vertices: vec![Vec3::ONE; n],
        uvs: vec![Vec2::ZERO; n],
        normals: vec![Vec3::Z; n],
    };
    let basis = TangentBasis {
        tangents: tangents.to_vec(),
        bitangents: bitangents.to_vec(),
    };
    (soup, basis)
}

// Fails if the scaling loses the weighting of corners added after a vertex was scaled (each
// must count with its own magnitude), drags the small tangent sum down with the huge bitangent
// sum (to underflow), or if the two indexers part ways.
#[test]
fn scaled_sums_keep_their_direction() {
    let big = 3e38f32;
    let (soup, basis) = one_vertex_soup(
        &[
            Vec3::new(0.0, big, 0.0),
            Vec3::new(0.0, big, 0.0),
            Vec3::new(big, 0.0, 0.0),
            Vec3::new(0.0, 0.0, 1.0), // far below the rest: vanishes, as in any float sum
            Vec3::new(0.0, -big, 0.0),
            Vec3::new(big, 0.0, 0.0),
        ],
        &[Vec3::X; 6],
    );
    let mesh = index_vbo_tbn_hashed(&soup, &basis, IndexOptions::default());
    assert_eq!(
        mesh,
        vboindexer::index_vbo_tbn(&soup, &basis, IndexOptions::default())
    );
    assert_eq!(mesh.vertices.len(), 1);
    let (t, b) = (mesh.tangents[0], mesh.bitangents[0]);
    assert_usable(t, b);
    // The sum is (2, 1, 0) × 3e38: scaled, but the same direction.
    assert!(
        b.normalize()
            .abs_diff_eq(Vec3::new(2.0, 1.0, 0.0).normalize(), 1e-6),
        "{b}"
    );
    // The tangent sum (6 × X) is far below the limit: scaled apart from the bitangent, it is
    // exactly the tutorial's sum.
    assert_eq!(t, Vec3::X * 6.0);
}

// Fails if sums below the limit are touched: they must be exactly the tutorial's f32 sums.
#[test]
fn ordinary_sums_are_untouched() {
    let bs = [
        Vec3::new(0.1, 2.5, -3.0),
        Vec3::new(1e6, -7.0, 0.25),
        Vec3::new(3.0, 1e-3, 5e8),
    ];
    let ts = [Vec3::X, Vec3::Y, Vec3::new(0.6, 0.8, 0.0)];
    let (soup, basis) = one_vertex_soup(&bs, &ts);
    let mesh = index_vbo_tbn_hashed(&soup, &basis, IndexOptions::default());
    assert_eq!(mesh.bitangents[0], bs[0] + bs[1] + bs[2]);
    assert_eq!(mesh.tangents[0], ts[0] + ts[1] + ts[2]);
}

// Fails if a corner tangent near f32::MAX normalizes to zero (its squared length overflows) or a
// huge bitangent makes the handedness test NaN: every corner gets a unit tangent along the solve.
#[test]
fn huge_corner_tangents_normalize() {
    use tutorial13::common::tangentspace::{compute_tangent_basis, TangentOptions};
    let soup = TriangleSoup {
        vertices: vec![
            Vec3::ZERO,
            Vec3::new(3e38, 0.0, 0.0),
            Vec3::new(0.0, 3e38, 0.0),
        ],
        uvs: vec![Vec2::ZERO, Vec2::X, Vec2::NEG_Y],
        normals: vec![Vec3::Z, Vec3::new(0.0, 0.6, 0.8), Vec3::Z],
    };
    let basis = compute_tangent_basis(&soup, TangentOptions::default());
    for (i, (t, b)) in basis.tangents.iter().zip(&basis.bitangents).enumerate() {
        assert!(t.is_normalized(), "corner {i}: {t}");
        assert!(
            t.dot(soup.normals[i].normalize()).abs() < 1e-6,
            "corner {i}: {t}"
        );
        assert!(b.is_finite(), "corner {i}: {b}");
        // Right-handed after the handedness step, whatever the magnitudes.
        let side = soup.normals[i].cross(*t).dot(*b / 3e38);
        assert!(side > 0.0, "corner {i}: {t} {b}");
    }
}

// Fails if a corner normal with a huge component (found by the fuzzer: `vn -0.866 1e38 0.5`, and
// `vn 4294967297 0 1`) makes Gram-Schmidt's result overflow its squared length and normalize to
// zero: the tangent must be unit length, or the corner must get the unit fallback frame.
#[test]
fn huge_normals_still_give_unit_tangents() {
    use tutorial13::common::tangentspace::{compute_tangent_basis, TangentOptions};
    for normal in [
        Vec3::new(-0.866, 1e38, 0.5),
        Vec3::new(4294967297.0, 0.0, 1.0),
        Vec3::new(3e38, 3e38, 3e38),
    ] {
        let soup = TriangleSoup {
            vertices: vec![Vec3::ZERO, Vec3::X, Vec3::Z],
            uvs: vec![Vec2::ZERO, Vec2::X, Vec2::Y],
            normals: vec![normal; 3],
        };
        let basis = compute_tangent_basis(&soup, TangentOptions::default());
        for (t, b) in basis.tangents.iter().zip(&basis.bitangents) {
            assert!((t.length() - 1.0).abs() < 1e-3, "{normal}: {t}");
            assert!(b.is_finite(), "{normal}: {b}");
        }
    }
}
