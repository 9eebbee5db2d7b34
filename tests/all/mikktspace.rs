//! The program's MikkTSpace (`pipeline::mikktspace`) against the `mikktspace` crate, to the bit, on
//! meshes built to reach each part of the algorithm: smooth grids, a cylinder's seam, mirrored UVs
//! (orientation groups), degenerate triangles, triangles without UV area, edges shared by three
//! triangles, zeros of both signs, directions exactly opposite at a vertex, and random soups from
//! a few values (heavy welding). Each on 1, 2 and 5 threads.

use glam::{Vec2, Vec3};
use proptest::prelude::*;
use rustc_hash::FxHashMap;
use tutorial13::common::objloader::TriangleSoup;
use tutorial13::common::vboindexer::{IndexedMesh, Indices};
use tutorial13::pipeline::mikktspace::{mikktspace_tangents, mikktspace_tangents_on};
use tutorial13::pipeline::obj_parse::load_obj_threaded;
use tutorial13::tangent_source::{mikktspace_mesh, welded_mesh};

use crate::common::{mesh_bit_difference, own_assets};
use crate::mikktspace_reference::{first_difference, reference_can_take, reference_tangents};

/// Panics naming `what` and the first differing corner unless every thread count gives the crate's
/// tangents to the bit.
fn assert_as_the_crate(what: &str, soup: &TriangleSoup) {
    assert!(
        reference_can_take(soup),
        "{what}: not a mesh the crate can take"
    );
    let reference = reference_tangents(soup).expect("the crate refused the mesh");
    for threads in [1, 2, 5] {
        let ours = mikktspace_tangents_on(soup, threads).unwrap();
        if let Some(difference) = first_difference(&ours, &reference) {
            panic!("{what}, {threads} threads: {difference}");
        }
    }
}

/// Splitmix64, for meshes that are the same every run.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// In [-1, 1).
    fn unit(&mut self) -> f32 {
        (self.next() >> 40) as f32 / (1u64 << 23) as f32 - 1.0
    }
}

#[derive(Default)]
struct Builder {
    soup: TriangleSoup,
}

impl Builder {
    fn corner(&mut self, p: Vec3, uv: Vec2, n: Vec3) {
        self.soup.vertices.push(p);
        self.soup.uvs.push(uv);
        self.soup.normals.push(n);
    }
    fn triangle(&mut self, corners: [(Vec3, Vec2, Vec3); 3]) {
        for (p, uv, n) in corners {
            self.corner(p, uv, n);
        }
    }
}

/// A height field of `w` × `h` quads, split along alternating diagonals, its normals from the
/// slopes; `uv` maps a grid point (in 0..1) to its UV.
fn grid(w: usize, h: usize, seed: u64, uv: impl Fn(f32, f32) -> Vec2) -> TriangleSoup {
    let mut rng = Rng(seed);
    let heights: Vec<f32> = (0..(w + 1) * (h + 1)).map(|_| 0.2 * rng.unit()).collect();
    let at = |i: usize, j: usize| {
        let (x, y) = (i as f32 / w as f32, j as f32 / h as f32);
        let z = heights[j * (w + 1) + i];
        let hx = heights[j * (w + 1) + (i + 1).min(w)] - heights[j * (w + 1) + i.saturating_sub(1)];
        let hy = heights[(j + 1).min(h) * (w + 1) + i] - heights[j.saturating_sub(1) * (w + 1) + i];
        let n = Vec3::new(-hx, -hy, 0.1).normalize();
        (Vec3::new(x, y, z), uv(x, y), n)
    };
    let mut b = Builder::default();
    for j in 0..h {
        for i in 0..w {
            let (a, c, d, e) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            if (i + j) % 2 == 0 {
                b.triangle([a, c, d]);
                b.triangle([a, d, e]);
            } else {
                b.triangle([a, c, e]);
                b.triangle([c, d, e]);
            }
        }
    }
    b.soup
}

/// An open cylinder of `segments` × `rings` quads, U around it (the seam's corners repeat at
/// u = 0 and u = 1), radial normals.
fn cylinder(segments: usize, rings: usize) -> TriangleSoup {
    let at = |s: usize, r: usize| {
        let angle = std::f32::consts::TAU * s as f32 / segments as f32;
        let n = Vec3::new(angle.cos(), angle.sin(), 0.0);
        let p = n + Vec3::new(0.0, 0.0, r as f32 / rings as f32 * 2.0);
        (
            p,
            Vec2::new(s as f32 / segments as f32, -(r as f32) / rings as f32),
            n,
        )
    };
    let mut b = Builder::default();
    for r in 0..rings {
        for s in 0..segments {
            let (a, c, d, e) = (at(s, r), at(s + 1, r), at(s + 1, r + 1), at(s, r + 1));
            b.triangle([a, c, d]);
            b.triangle([a, d, e]);
        }
    }
    b.soup
}

/// A fan of `k` triangles around the origin (normal +z) whose UVs wind twice around (u + iv =
/// z²): opposite triangles have opposite directions, which MikkTSpace keeps apart.
fn double_winding_fan(k: usize, turn: f32) -> TriangleSoup {
    let n = Vec3::Z;
    let outer = |i: usize| {
        let angle = turn + std::f32::consts::TAU * i as f32 / k as f32;
        let p = Vec3::new(angle.cos(), angle.sin(), 0.0);
        let uv = Vec2::new((2.0 * angle).cos(), (2.0 * angle).sin());
        (p, uv, n)
    };
    let center = (Vec3::ZERO, Vec2::ZERO, n);
    let mut b = Builder::default();
    for i in 0..k {
        b.triangle([center, outer(i), outer((i + 1) % k)]);
    }
    b.soup
}

/// The same fan with exact values: eight triangles to the corners and edge midpoints of a square,
/// UVs at quarter turns, so that opposite triangles have dP/du exactly opposite (cosine −1).
fn exact_opposite_fan() -> TriangleSoup {
    let n = Vec3::Z;
    let points = [
        (1.0, 0.0),
        (1.0, 1.0),
        (0.0, 1.0),
        (-1.0, 1.0),
        (-1.0, 0.0),
        (-1.0, -1.0),
        (0.0, -1.0),
        (1.0, -1.0),
    ];
    let uvs = [(1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0)];
    let outer = |i: usize| {
        let (x, y) = points[i % 8];
        let (u, v) = uvs[i % 4];
        (Vec3::new(x, y, 0.0), Vec2::new(u, v), n)
    };
    let center = (Vec3::ZERO, Vec2::ZERO, n);
    let mut b = Builder::default();
    for i in 0..8 {
        b.triangle([center, outer(i), outer(i + 1)]);
    }
    b.soup
}

/// `soup` with extra triangles that reach the degenerate and flat paths: two equal positions
/// (sharing a vertex with the mesh, or with none), all three equal, UVs all equal (no area),
/// UVs on a line, and a triangle repeated in both windings (edges of three and four triangles).
fn with_troubles(mut soup: TriangleSoup, seed: u64) -> TriangleSoup {
    let mut rng = Rng(seed);
    let n = soup.vertices.len();
    let corner = |soup: &TriangleSoup, c: usize| (soup.vertices[c], soup.uvs[c], soup.normals[c]);
    let mut b = Builder::default();
    for k in 0..(n / 30).max(4) {
        let pick = |rng: &mut Rng| (rng.next() % n as u64) as usize;
        let (a, c, d) = (
            corner(&soup, pick(&mut rng)),
            corner(&soup, pick(&mut rng)),
            corner(&soup, pick(&mut rng)),
        );
        let f = (a.0, a.1 + Vec2::splat(0.25), a.2);
        match k % 6 {
            0 => b.triangle([a, a, c]),
            1 => b.triangle([a, c, (a.0, Vec2::new(9.0, 9.0), Vec3::X)]),
            2 => b.triangle([f, f, f]),
            3 => b.triangle([(a.0, a.1, a.2), (c.0, a.1, c.2), (d.0, a.1, d.2)]),
            4 => b.triangle([
                (a.0, a.1, a.2),
                (c.0, a.1 + Vec2::X, c.2),
                (d.0, a.1 + 2.0 * Vec2::X, d.2),
            ]),
            _ => {
                let t = 3 * (pick(&mut rng) / 3);
                let tri = [corner(&soup, t), corner(&soup, t + 1), corner(&soup, t + 2)];
                b.triangle(tri);
                b.triangle([tri[0], tri[2], tri[1]]);
            }
        }
    }
    // Interleaved with the mesh's own triangles, so that degenerate ones sit between good ones.
    let extra = b.soup;
    let mut out = Builder::default();
    let per = (soup.triangle_count() / extra.triangle_count().max(1)).max(1);
    for f in 0..soup.triangle_count().max(extra.triangle_count()) {
        if f < soup.triangle_count() {
            out.triangle([0, 1, 2].map(|i| corner(&soup, 3 * f + i)));
        }
        if f % per == 0 && f / per < extra.triangle_count() {
            out.triangle([0, 1, 2].map(|i| corner(&extra, 3 * (f / per) + i)));
        }
    }
    soup = out.soup;
    soup
}

/// `soup` with every zero in some corners turned to −0 (pseudo-randomly, corner by corner):
/// corners that the crate welds (−0 == +0) but whose bits differ.
fn with_negative_zeros(mut soup: TriangleSoup, seed: u64) -> TriangleSoup {
    let mut rng = Rng(seed);
    let flip = |x: &mut f32, rng: &mut Rng| {
        if *x == 0.0 && rng.next() % 2 == 0 {
            *x = -0.0;
        }
    };
    for c in 0..soup.vertices.len() {
        let p: &mut [f32; 3] = soup.vertices[c].as_mut();
        let n: &mut [f32; 3] = soup.normals[c].as_mut();
        let uv: &mut [f32; 2] = soup.uvs[c].as_mut();
        for x in p.iter_mut().chain(n.iter_mut()).chain(uv.iter_mut()) {
            flip(x, &mut rng);
        }
    }
    soup
}

/// A flat grid at z = 0 with normals (0, 0, 1) and zeros in many UVs: the floats whose signs
/// [`with_negative_zeros`] flips.
fn flat_grid(w: usize, h: usize) -> TriangleSoup {
    let mut soup = grid(w, h, 1, |x, y| Vec2::new(x.min(0.5) - 0.5, y));
    for p in &mut soup.vertices {
        p.z = 0.0;
    }
    for n in &mut soup.normals {
        *n = Vec3::Z;
    }
    soup
}

/// The meshes made to reach each part of MikkTSpace, and the tutorial's cylinder, with their names.
fn named_meshes() -> Vec<(String, TriangleSoup)> {
    let mut meshes: Vec<(String, TriangleSoup)> = vec![
        ("grid 8x8".into(), grid(8, 8, 1, Vec2::new)),
        (
            "grid 40x30, rotated UVs".into(),
            grid(40, 30, 2, |x, y| {
                Vec2::new(0.6 * x - 0.8 * y, 0.8 * x + 0.6 * y)
            }),
        ),
        // Mirrored: U folds at x = 0.5, so the two halves have opposite orientations.
        (
            "grid 20x20, mirrored U".into(),
            grid(20, 20, 3, |x, y| Vec2::new(0.5 - (x - 0.5).abs(), y)),
        ),
        (
            "grid 16x16, mirrored V in stripes".into(),
            grid(16, 16, 4, |x, y| {
                Vec2::new(x, if (y * 4.0) as i32 % 2 == 0 { y } else { -y })
            }),
        ),
        (
            "grid 12x12, UVs squashed to a line".into(),
            grid(12, 12, 5, |x, _| Vec2::new(x, 0.0)),
        ),
        ("cylinder 24x6".into(), cylinder(24, 6)),
        ("cylinder 3x1".into(), cylinder(3, 1)),
        ("double-winding fan 6".into(), double_winding_fan(6, 0.0)),
        ("double-winding fan 8".into(), double_winding_fan(8, 0.3)),
        ("exact opposite fan".into(), exact_opposite_fan()),
        ("flat grid 10x10".into(), flat_grid(10, 10)),
    ];
    for seed in 0..6 {
        meshes.push((
            format!("grid 9x7 with troubles {seed}"),
            with_troubles(grid(9, 7, seed, Vec2::new), seed),
        ));
        meshes.push((
            format!("cylinder 16x4 with troubles {seed}"),
            with_troubles(cylinder(16, 4), seed),
        ));
        meshes.push((
            format!("flat grid with −0s {seed}"),
            with_negative_zeros(flat_grid(8, 8), seed),
        ));
        meshes.push((
            format!("mirrored grid with troubles and −0s {seed}"),
            with_negative_zeros(
                with_troubles(
                    grid(10, 10, seed, |x, y| Vec2::new((x - 0.5).abs(), y - 0.5)),
                    seed,
                ),
                seed + 100,
            ),
        ));
    }
    let tutorial = load_obj_threaded(&own_assets().join("cylinder.obj")).unwrap();
    meshes.push(("the tutorial's cylinder".into(), tutorial));
    meshes
}

// Fails if any named mesh's tangents differ from the crate's in one bit, on 1, 2 or 5 threads.
#[test]
fn named_meshes_as_the_crate() {
    let meshes = named_meshes();
    for (name, soup) in &meshes {
        assert_as_the_crate(name, soup);
    }
    println!(
        "{} meshes as the crate, on 1, 2 and 5 threads",
        meshes.len()
    );
}

// Fails if the opposite-directions path (sub-groups that differ from corner to corner) is never
// reached by the named meshes: the corners at the fan's centre must not all share one tangent.
#[test]
fn opposite_directions_split_a_group() {
    for soup in [double_winding_fan(6, 0.0), exact_opposite_fan()] {
        let t = mikktspace_tangents(&soup).unwrap();
        let centre: Vec<[f32; 4]> = (0..soup.triangle_count()).map(|f| t[3 * f]).collect();
        let distinct = centre.iter().filter(|a| **a != centre[0]).count();
        println!("fan centre tangents: {centre:?}");
        assert!(
            distinct > 0,
            "every corner at the centre has {:?}",
            centre[0]
        );
    }
}

// Fails if a mesh with every triangle degenerate (the crate reads past its arrays there) does not
// get the fallback frame everywhere, or if an empty or non-finite soup is not refused.
#[test]
fn all_degenerate_empty_and_non_finite() {
    let mut b = Builder::default();
    let corner = (Vec3::ONE, Vec2::ZERO, Vec3::Z);
    b.triangle([corner, corner, (Vec3::ZERO, Vec2::ONE, Vec3::Z)]);
    b.triangle([corner; 3]);
    let t = mikktspace_tangents(&b.soup).unwrap();
    assert!(t.iter().all(|t| *t == [1.0, 0.0, 0.0, -1.0]), "{t:?}");
    assert!(mikktspace_tangents(&TriangleSoup::default()).is_err());
    let mut soup = grid(2, 2, 0, Vec2::new);
    soup.normals[4].y = f32::NAN;
    assert!(mikktspace_tangents(&soup).is_err());
}

/// A soup of `triangles` triangles whose corners are drawn from a few positions, normals and UVs
/// (zeros of both signs among them): many corners weld, many triangles are degenerate or flat,
/// edges are shared by many triangles.
fn palette_soup(picks: &[(u8, u8, u8)], values: &[f32]) -> TriangleSoup {
    let value = |k: usize| values[k % values.len()];
    let mut b = Builder::default();
    for &(p, n, uv) in picks {
        let (p, n, uv) = (p as usize, n as usize, uv as usize);
        let position = Vec3::new(value(p), value(p / 3 + 1), value(p / 5 + 2));
        let normal = Vec3::new(value(n + 3), value(n / 2 + 4), 1.0).normalize();
        let uv = Vec2::new(value(uv + 5), value(uv / 3 + 6));
        b.corner(position, uv, normal);
    }
    let whole = b.soup.vertices.len() / 3 * 3;
    b.soup.vertices.truncate(whole);
    b.soup.normals.truncate(whole);
    b.soup.uvs.truncate(whole);
    b.soup
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 400, ..ProptestConfig::default() })]

    // Fails if a random soup of few distinct values gets other tangents than the crate's.
    #[test]
    fn random_palette_soups_as_the_crate(
        picks in proptest::collection::vec((0u8..12, 0u8..4, 0u8..8), 3..120),
        values in proptest::collection::vec(prop_oneof![
            Just(0.0f32), Just(-0.0f32), Just(1.0f32), Just(-1.0f32), Just(0.5f32), -4.0f32..4.0,
        ], 8..16),
    ) {
        let soup = palette_soup(&picks, &values);
        prop_assume!(reference_can_take(&soup));
        let reference = reference_tangents(&soup).unwrap();
        for threads in [1, 3] {
            let ours = mikktspace_tangents_on(&soup, threads).unwrap();
            prop_assert!(first_difference(&ours, &reference).is_none(), "{threads} threads: {:?}", first_difference(&ours, &reference));
        }
    }

    // Fails if a jittered grid with troubles (random sizes, UV maps and seeds) differs from the crate.
    #[test]
    fn random_grids_as_the_crate(w in 1usize..12, h in 1usize..12, seed in 0u64..1000, fold in 0.0f32..1.0) {
        let soup = with_negative_zeros(
            with_troubles(grid(w, h, seed, |x, y| Vec2::new((x - fold).abs(), y * (1.0 - fold))), seed),
            seed,
        );
        prop_assume!(reference_can_take(&soup));
        let reference = reference_tangents(&soup).unwrap();
        let ours = mikktspace_tangents_on(&soup, 2).unwrap();
        prop_assert!(first_difference(&ours, &reference).is_none(), "{:?}", first_difference(&ours, &reference));
    }
}

/// The weld of a tangent per corner as it was first written (a hash map of all twelve floats'
/// bits, vertices in the order of their first corner): what `tangent_source::welded_mesh` and
/// `tangent_source::mikktspace_mesh` must still give.
fn reference_weld(soup: &TriangleSoup, tangents: &[[f32; 4]]) -> IndexedMesh {
    let mut mesh = IndexedMesh::empty();
    let mut indices = Vec::new();
    let mut seen: FxHashMap<[u32; 12], u32> = FxHashMap::default();
    for (i, &[tx, ty, tz, w]) in tangents.iter().enumerate() {
        let (p, uv, n) = (soup.vertices[i], soup.uvs[i], soup.normals[i]);
        let t = Vec3::new(tx, ty, tz);
        let key = [p.x, p.y, p.z, uv.x, uv.y, n.x, n.y, n.z, tx, ty, tz, w].map(f32::to_bits);
        let index = *seen.entry(key).or_insert_with(|| {
            mesh.vertices.push(p);
            mesh.uvs.push(uv);
            mesh.normals.push(n);
            mesh.tangents.push(t);
            mesh.bitangents.push(w * n.cross(t));
            (mesh.vertices.len() - 1) as u32
        });
        indices.push(index);
    }
    mesh.indices = Indices::from_u32(indices, mesh.vertices.len());
    mesh
}

// Fails if MikkTSpace's mesh (welded from MikkTSpace's own numbering of the corners) is not the
// one the first weld, of all twelve floats, gives: same vertices in the same order, same indices.
#[test]
fn mikktspace_mesh_as_the_first_weld() {
    let meshes = named_meshes();
    for (name, soup) in &meshes {
        let reference = reference_weld(soup, &mikktspace_tangents(soup).unwrap());
        let ours = mikktspace_mesh(soup).unwrap();
        if let Some(difference) = mesh_bit_difference(&ours, &reference) {
            panic!("{name}: {difference}");
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200, ..ProptestConfig::default() })]

    // Fails if a soup of few values with tangents of few values (several per vertex, zeros of both
    // signs, NaNs) welds otherwise than the first weld did.
    #[test]
    fn welded_mesh_as_the_first_weld(
        picks in proptest::collection::vec((0u8..12, 0u8..4, 0u8..8), 3..120),
        values in proptest::collection::vec(prop_oneof![
            Just(0.0f32), Just(-0.0f32), Just(1.0f32), Just(f32::NAN), -4.0f32..4.0,
        ], 8..16),
        tangent_picks in proptest::collection::vec(0usize..6, 120),
    ) {
        let soup = palette_soup(&picks, &values);
        let tangents: Vec<[f32; 4]> = (0..soup.vertices.len())
            .map(|c| {
                let k = tangent_picks[c];
                [values[k], values[k + 1], 0.0, if k % 2 == 0 { 1.0 } else { -1.0 }]
            })
            .collect();
        let (ours, first) = (welded_mesh(&soup, &tangents), reference_weld(&soup, &tangents));
        let difference = mesh_bit_difference(&ours, &first);
        prop_assert!(difference.is_none(), "{:?}", difference);
    }
}
