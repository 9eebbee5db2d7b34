//! Many vertices in one position cell. The grid then splits the cell by UV and
//! normal; the result must stay exactly the linear search's (first near vertex, same sums).

use glam::{Vec2, Vec3};
use proptest::prelude::*;
use tutorial13::common::objloader::TriangleSoup;
use tutorial13::common::tangentspace::{compute_tangent_basis, TangentBasis, TangentOptions};
use tutorial13::common::vboindexer::{self, IndexOptions};
use tutorial13::pipeline::indexer::index_vbo_tbn_hashed;

use crate::common::{indexers_match_references, mesh_bit_difference};

fn basis_for(n: usize) -> TangentBasis {
    TangentBasis {
        tangents: (0..n).map(|i| Vec3::new(i as f32, 1.0, -0.5)).collect(),
        bitangents: (0..n)
            .map(|i| Vec3::new(0.25, i as f32 * 0.5, 1.0))
            .collect(),
    }
}

// Fails if a cell holding thousands of vertices (one position, UVs 0.02 apart, every third corner
// repeating an earlier UV within the tolerance) indexes differently from the linear search, to the bit.
#[test]
fn one_position_many_uvs_matches_linear() {
    for position in [
        Vec3::ZERO,
        Vec3::splat(0.025),
        Vec3::new(-0.0249, 7.5, 0.075),
    ] {
        let n = 3000;
        let uv = |i: usize| {
            let k = if i % 3 == 2 { i / 2 } else { i };
            let jitter = if i % 3 == 2 { 0.0099 } else { 0.0 };
            Vec2::new(0.02 * (k % 40) as f32 + jitter, 0.02 * (k / 40) as f32)
        };
        let soup = TriangleSoup {
            vertices: vec![position; n],
            uvs: (0..n).map(uv).collect(),
            normals: (0..n)
                .map(|i| if i % 7 == 0 { Vec3::Y } else { Vec3::Z })
                .collect(),
        };
        let basis = basis_for(n);
        let fast = index_vbo_tbn_hashed(&soup, &basis, IndexOptions::default());
        let reference = vboindexer::index_vbo_tbn(&soup, &basis, IndexOptions::default());
        assert!(fast.vertices.len() > 1000, "{}", fast.vertices.len());
        if let Some(difference) = mesh_bit_difference(&fast, &reference) {
            panic!("at {position}: {difference}");
        }
    }
}

/// Corners that mostly share a position (or sit within the tolerance of it, across cell
/// boundaries), with UVs and normals from a small lattice plus offsets around the 0.01 tolerance:
/// far more than 32 vertices per cell, with ties.
fn crowded_soup() -> impl Strategy<Value = (TriangleSoup, TangentBasis)> {
    let offset = prop_oneof![
        3 => Just(0.0f32),
        1 => prop::sample::select(vec![
            0.0049f32, -0.0049, 0.0099, -0.0099, 0.01, -0.01, 0.0101, -0.0101, 0.02, 0.025,
        ]),
    ];
    let corner = (
        prop::array::uniform3(offset.clone()),
        (0usize..10, 0usize..10),
        prop::array::uniform2(offset.clone()),
        0usize..3,
        offset,
    );
    let centre = prop::sample::select(vec![
        Vec3::ZERO,
        Vec3::splat(0.025),
        Vec3::new(0.0249, -0.025, 1.0),
        Vec3::new(3.1, -2.2, 0.5),
    ]);
    (
        centre,
        prop::collection::vec(prop::collection::vec(corner, 3), 20..150),
    )
        .prop_map(|(centre, triangles)| {
            let mut soup = TriangleSoup::default();
            for (dp, (u, v), duv, normal, dn) in triangles.into_iter().flatten() {
                soup.vertices.push(centre + Vec3::from(dp));
                soup.uvs
                    .push(Vec2::new(u as f32 * 0.015, v as f32 * 0.015) + Vec2::from(duv));
                let n = [Vec3::Z, Vec3::Y, Vec3::new(0.6, 0.0, 0.8)][normal];
                soup.normals.push(n + Vec3::splat(dn));
            }
            let basis = compute_tangent_basis(&soup, TangentOptions::default());
            (soup, basis)
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    // Fails if splitting a crowded cell ever changes which vertex a corner picks, or the sums.
    #[test]
    fn crowded_cells_match_linear((soup, basis) in crowded_soup(), normalize in any::<bool>()) {
        indexers_match_references(&soup, &basis, normalize)?;
    }
}
