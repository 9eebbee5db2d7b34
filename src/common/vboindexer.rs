//! `common/vboindexer.cpp`: turn the triangle soup into an indexed mesh.
//!
//! The tutorial's `indexVBO_TBN` keeps a corner as a new vertex unless an earlier output vertex has
//! position, UV and normal each within 0.01 per component (`is_near`); then the corner reuses the
//! *first* such vertex and its tangent and bitangent are added to that vertex's (a sum, not an
//! average, and not normalized: the shader normalizes). It searches linearly, so it is quadratic:
//! the tutorial's cylinder is indexed here, and a mesh above [`crate::mesh::PORTS_UP_TO_TRIANGLES`]
//! triangles by [`crate::pipeline::indexer`], which gives the same mesh to the bit in expected
//! linear time; the tests compare the two. `indexVBO` merges only corners equal to the
//! bit, through a `std::map`.
//!
//! Where the port differs: indices are 16-bit only while every vertex fits (at most 65 535 of them),
//! else 32-bit; the original casts to `unsigned short` and silently wraps. A vertex's tangent sums
//! are scaled by a power of two where they would overflow (`SUM_LIMIT`).

use std::collections::BTreeMap;

use glam::{Vec2, Vec3};
use rustc_hash::FxHashMap;

use crate::common::objloader::TriangleSoup;
use crate::common::tangentspace::TangentBasis;

/// The tutorial's tolerance: two attributes are "near" when every component differs by less.
pub const NEAR: f32 = 0.01;

/// An index buffer, 16-bit like the tutorial's when every vertex can be named in 16 bits.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Indices {
    U16(Vec<u16>),
    U32(Vec<u32>),
}

impl Indices {
    /// The narrowest buffer for `indices` over `vertex_count` vertices. 16 bits while
    /// `vertex_count <= 65535`, so that 0xFFFF (the primitive-restart index) is never a vertex.
    pub fn from_u32(indices: Vec<u32>, vertex_count: usize) -> Self {
        if vertex_count <= u16::MAX as usize {
            Indices::U16(indices.into_iter().map(|i| i as u16).collect())
        } else {
            Indices::U32(indices)
        }
    }

    pub fn len(&self) -> usize {
        match self {
            Indices::U16(v) => v.len(),
            Indices::U32(v) => v.len(),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The `i`-th index, widened.
    pub fn get(&self, i: usize) -> u32 {
        match self {
            Indices::U16(v) => v[i] as u32,
            Indices::U32(v) => v[i],
        }
    }

    /// Every index, widened, in order.
    pub fn to_u32(&self) -> Vec<u32> {
        match self {
            Indices::U16(v) => v.iter().map(|&i| i as u32).collect(),
            Indices::U32(v) => v.clone(),
        }
    }

    /// Bytes per index: 2 or 4.
    pub fn index_size(&self) -> usize {
        match self {
            Indices::U16(_) => 2,
            Indices::U32(_) => 4,
        }
    }
}

/// The five vertex attribute arrays and the index buffer the tutorial uploads.
#[derive(Debug, Clone, PartialEq)]
pub struct IndexedMesh {
    pub indices: Indices,
    pub vertices: Vec<Vec3>,
    pub uvs: Vec<Vec2>,
    pub normals: Vec<Vec3>,
    /// Sums of the merged corners' tangents (empty from [`index_vbo`]).
    pub tangents: Vec<Vec3>,
    pub bitangents: Vec<Vec3>,
}

impl IndexedMesh {
    /// No vertices and no indices, to be filled (its indices are 32-bit until [`Indices::from_u32`]
    /// narrows a finished list).
    pub fn empty() -> Self {
        IndexedMesh {
            indices: Indices::U32(Vec::new()),
            vertices: Vec::new(),
            uvs: Vec::new(),
            normals: Vec::new(),
            tangents: Vec::new(),
            bitangents: Vec::new(),
        }
    }
}

/// The tutorial's exercise as a switch.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct IndexOptions {
    /// Normalize each corner's tangent and bitangent before adding them up (exercise 1), so that
    /// large triangles no longer outweigh small ones. Off in the tutorial's code.
    pub normalize_before_sum: bool,
}

/// The tutorial's `is_near`, per component.
pub(crate) fn is_near(a: f32, b: f32) -> bool {
    (a - b).abs() < NEAR
}

fn is_near_vertex(a: (Vec3, Vec2, Vec3), b: (Vec3, Vec2, Vec3)) -> bool {
    is_near(a.0.x, b.0.x)
        && is_near(a.0.y, b.0.y)
        && is_near(a.0.z, b.0.z)
        && is_near(a.1.x, b.1.x)
        && is_near(a.1.y, b.1.y)
        && is_near(a.2.x, b.2.x)
        && is_near(a.2.y, b.2.y)
        && is_near(a.2.z, b.2.z)
}

/// Collects output vertices and the index buffer for this port and the fast indexer
/// ([`crate::pipeline::indexer`]), so that they differ only in how they find a similar vertex.
pub(crate) struct Builder {
    pub(crate) mesh: IndexedMesh,
    pub(crate) indices: Vec<u32>,
    options: IndexOptions,
    /// Vertices whose tangent and bitangent sums are stored scaled by 2^-e (see [`SUM_LIMIT`]),
    /// with the e of each. Empty for any mesh of sane size.
    scaled: FxHashMap<u32, [i32; 2]>,
}

/// Largest tangent or bitangent component an output vertex keeps. Each corner's vectors are finite,
/// but the bitangent is not normalized, so on a mesh with coordinates near f32::MAX the sums would
/// overflow to infinity (and the shader's normalize give NaN). Where a vertex's tangent or
/// bitangent sum would reach this limit, that sum (and every later corner added to it) is scaled
/// by a power of two: exact, direction-keeping, and inert below the limit, so ordinary meshes are
/// summed bit for bit as the tutorial does. Tangent and bitangent are scaled apart, so that the
/// smaller one is not pushed to underflow; at 2^40 and beyond, the other two vectors of the TBN
/// matrix are already below f32's precision beside it, so the lighting does not change either.
const SUM_LIMIT: f32 = (1u64 << 40) as f32;

/// glam's `normalize_or_zero`, except for vectors whose squared length overflows or underflows
/// f32 (components beyond about 1e19 or below 1e-19): those still have a direction, taken from a
/// copy scaled towards 1. Other vectors are normalized exactly as before.
fn normalize_or_zero(v: Vec3) -> Vec3 {
    let unit = v.normalize_or_zero();
    let m = v.abs().max_element();
    if unit == Vec3::ZERO && m > 0.0 && m.is_finite() {
        (v / m).normalize_or_zero()
    } else {
        unit
    }
}

/// `sum + add × 2^-e`, in f64, then halved until every component is under [`SUM_LIMIT`]; gives
/// the new sum and its e. A corner that is not finite keeps the tutorial's arithmetic (no scaling
/// can help it).
fn add_scaled(sum: Vec3, add: Vec3, e: i32) -> (Vec3, i32) {
    let mut total = sum.as_dvec3() + add.as_dvec3() * 2f64.powi(-e);
    let mut e = e;
    if total.is_finite() {
        while total.abs().max_element() >= SUM_LIMIT as f64 {
            total *= 0.5;
            e += 1;
        }
    }
    (total.as_vec3(), e)
}

/// Whether every component of `t` and `b` is below [`SUM_LIMIT`] in magnitude (false for NaN).
fn within_limit(t: Vec3, b: Vec3) -> bool {
    // Each vector on its own: glam's `max` of the two would drop a NaN beside a number.
    let limit = Vec3::splat(SUM_LIMIT);
    t.abs().cmplt(limit).all() && b.abs().cmplt(limit).all()
}

impl Builder {
    /// `corners`: how many corners will come. Vertex arrays start at a quarter of that (a closed
    /// mesh shares each vertex among about six corners) and grow if needed: reserving for every
    /// corner touches several times the memory, and fresh pages cost more than the indexing here.
    fn new(corners: usize, options: IndexOptions) -> Self {
        Self::with_capacity(corners / 4 + 16, corners, options)
    }

    /// Room for `capacity` vertices and `corners` indices.
    pub(crate) fn with_capacity(capacity: usize, corners: usize, options: IndexOptions) -> Self {
        Builder {
            mesh: IndexedMesh {
                indices: Indices::U16(Vec::new()),
                vertices: Vec::with_capacity(capacity),
                uvs: Vec::with_capacity(capacity),
                normals: Vec::with_capacity(capacity),
                tangents: Vec::with_capacity(capacity),
                bitangents: Vec::with_capacity(capacity),
            },
            indices: Vec::with_capacity(corners),
            options,
            scaled: FxHashMap::default(),
        }
    }

    fn prepare(&self, t: Vec3, b: Vec3) -> (Vec3, Vec3) {
        if self.options.normalize_before_sum {
            (normalize_or_zero(t), normalize_or_zero(b))
        } else {
            (t, b)
        }
    }

    /// A corner that reuses vertex `index`: "average" (sum) its tangents in.
    fn reuse(&mut self, index: u32, t: Vec3, b: Vec3) {
        self.indices.push(index);
        self.add_sums(index, t, b);
    }

    /// Adds a corner's tangents to vertex `index`'s sums.
    #[inline]
    pub(crate) fn add_sums(&mut self, index: u32, t: Vec3, b: Vec3) {
        let (t, b) = self.prepare(t, b);
        let i = index as usize;
        let (sum_t, sum_b) = (self.mesh.tangents[i] + t, self.mesh.bitangents[i] + b);
        if within_limit(sum_t, sum_b)
            && (self.scaled.is_empty() || !self.scaled.contains_key(&index))
        {
            self.mesh.tangents[i] = sum_t;
            self.mesh.bitangents[i] = sum_b;
        } else {
            self.store_scaled(index, t, b);
        }
    }

    /// The slow path of [`SUM_LIMIT`]: adds `t` and `b` to vertex `index`'s sums (or starts them),
    /// each at its scale.
    fn store_scaled(&mut self, index: u32, t: Vec3, b: Vec3) {
        let i = index as usize;
        let [et, eb] = self.scaled.get(&index).copied().unwrap_or([0, 0]);
        if i == self.mesh.tangents.len() {
            self.mesh.tangents.push(Vec3::ZERO);
            self.mesh.bitangents.push(Vec3::ZERO);
        }
        let (sum_t, et) = add_scaled(self.mesh.tangents[i], t, et);
        let (sum_b, eb) = add_scaled(self.mesh.bitangents[i], b, eb);
        self.mesh.tangents[i] = sum_t;
        self.mesh.bitangents[i] = sum_b;
        if et > 0 || eb > 0 {
            self.scaled.insert(index, [et, eb]);
        }
    }

    /// A corner that becomes a new vertex.
    fn push(&mut self, corner: (Vec3, Vec2, Vec3), t: Vec3, b: Vec3) {
        let index = self.add_vertex(corner);
        self.start_sums(index, t, b);
        self.indices.push(index);
    }

    /// A new vertex's position, UV and normal; returns its index. Its sums come later.
    pub(crate) fn add_vertex(&mut self, corner: (Vec3, Vec2, Vec3)) -> u32 {
        self.mesh.vertices.push(corner.0);
        self.mesh.uvs.push(corner.1);
        self.mesh.normals.push(corner.2);
        self.mesh.vertices.len() as u32 - 1
    }

    /// The corner that made vertex `index` (the next one without sums): its tangents start the
    /// sums.
    #[inline]
    pub(crate) fn start_sums(&mut self, index: u32, t: Vec3, b: Vec3) {
        let (t, b) = self.prepare(t, b);
        if within_limit(t, b) {
            self.mesh.tangents.push(t);
            self.mesh.bitangents.push(b);
        } else {
            self.store_scaled(index, t, b);
        }
    }

    pub(crate) fn finish(mut self) -> IndexedMesh {
        self.mesh.indices = Indices::from_u32(self.indices, self.mesh.vertices.len());
        self.mesh
    }
}

pub(crate) fn check_lengths(soup: &TriangleSoup, basis: &TangentBasis) {
    let n = soup.vertices.len();
    assert!(
        soup.uvs.len() == n
            && soup.normals.len() == n
            && basis.tangents.len() == n
            && basis.bitangents.len() == n,
        "index_vbo_tbn needs one UV, normal, tangent and bitangent per corner"
    );
    assert!(
        n <= u32::MAX as usize,
        "more corners than 32-bit indices can name"
    );
}

pub(crate) fn corner(soup: &TriangleSoup, i: usize) -> (Vec3, Vec2, Vec3) {
    (soup.vertices[i], soup.uvs[i], soup.normals[i])
}

/// The tutorial's `getSimilarVertexIndex`: the first output vertex near `corner`, searched from the
/// first.
fn get_similar_vertex_index(corner: (Vec3, Vec2, Vec3), out: &IndexedMesh) -> Option<u32> {
    (0..out.vertices.len())
        .find(|&j| is_near_vertex(corner, (out.vertices[j], out.uvs[j], out.normals[j])))
        .map(|j| j as u32)
}

/// The tutorial's `indexVBO_TBN`: for each corner, the first near output vertex gets the corner's
/// tangents added to its sums; a corner near none becomes a new vertex.
pub fn index_vbo_tbn(
    soup: &TriangleSoup,
    basis: &TangentBasis,
    options: IndexOptions,
) -> IndexedMesh {
    check_lengths(soup, basis);
    let mut out = Builder::new(soup.vertices.len(), options);
    for i in 0..soup.vertices.len() {
        let c = corner(soup, i);
        let (t, b) = (basis.tangents[i], basis.bitangents[i]);
        match get_similar_vertex_index(c, &out.mesh) {
            Some(j) => out.reuse(j, t, b),
            None => out.push(c, t, b),
        }
    }
    out.finish()
}

/// The tutorial's `indexVBO`, as written: a map from each corner's bytes (`memcmp` order, the
/// `PackedVertex` of `getSimilarVertexIndex_fast`) to the first vertex made from it. No tangents.
pub fn index_vbo(soup: &TriangleSoup) -> IndexedMesh {
    let mut mesh = IndexedMesh::empty();
    let mut map = BTreeMap::new();
    let mut indices = Vec::new();
    for i in 0..soup.vertices.len() {
        let (p, uv, n) = corner(soup, i);
        let bytes: [u8; 32] = bytemuck::cast([p.x, p.y, p.z, uv.x, uv.y, n.x, n.y, n.z]);
        let index = *map.entry(bytes).or_insert_with(|| {
            mesh.vertices.push(p);
            mesh.uvs.push(uv);
            mesh.normals.push(n);
            mesh.vertices.len() as u32 - 1
        });
        indices.push(index);
    }
    mesh.indices = Indices::from_u32(indices, mesh.vertices.len());
    mesh
}

#[cfg(test)]
mod tests {
    use super::*;

    // Fails if the index width rule is off by one at the 16-bit limit.
    #[test]
    fn index_width_threshold() {
        assert_eq!(Indices::from_u32(vec![65534], 65535).index_size(), 2);
        assert_eq!(Indices::from_u32(vec![65535], 65536).index_size(), 4);
    }

    // Fails if either width loses or reorders an index, or if len, is_empty, get or to_u32 answer
    // for anything but the buffer's own indices.
    #[test]
    fn both_widths_hold_their_indices() {
        for (indices, size) in [
            (Indices::from_u32(vec![2, 0, 1, 7], 8), 2),
            (Indices::from_u32(vec![2, 0, 1, 70_000], 70_001), 4),
        ] {
            assert_eq!(indices.index_size(), size);
            assert_eq!(indices.len(), 4);
            assert!(!indices.is_empty());
            let got: Vec<u32> = (0..4).map(|i| indices.get(i)).collect();
            assert_eq!(got, indices.to_u32());
            assert_eq!(got[..3], [2, 0, 1]);
        }
        assert!(Indices::from_u32(Vec::new(), 0).is_empty());
        assert_eq!(Indices::from_u32(Vec::new(), 0).len(), 0);
    }

    // Fails if `is_near` is not "differs by less than 0.01": 0.01 apart is not near (a `<=`
    // would be), 0.005 apart is, and so are equal values.
    #[test]
    fn is_near_is_strictly_within_the_tutorials_tolerance() {
        assert!(is_near(1.0, 1.0));
        assert!(is_near(1.0, 1.005));
        assert!(is_near(-3.0, -2.995));
        assert!(!is_near(0.0, NEAR));
        assert!(!is_near(1.0, 2.0));
    }

    fn a_corner() -> (Vec3, Vec2, Vec3) {
        (
            Vec3::new(1.0, 2.0, 3.0),
            Vec2::new(0.25, 0.75),
            Vec3::new(0.0, 0.6, 0.8),
        )
    }

    // Fails if any one of the eight components is left out of the comparison: a corner differing
    // from another in that component alone must not be near it.
    #[test]
    fn is_near_vertex_needs_every_component_near() {
        let a = a_corner();
        assert!(is_near_vertex(a, a));
        for k in 0..8 {
            let mut c = [a.0.x, a.0.y, a.0.z, a.1.x, a.1.y, a.2.x, a.2.y, a.2.z];
            c[k] += 0.5;
            let b = (
                Vec3::new(c[0], c[1], c[2]),
                Vec2::new(c[3], c[4]),
                Vec3::new(c[5], c[6], c[7]),
            );
            assert!(!is_near_vertex(a, b), "component {k} is not compared");
        }
    }

    // Fails if ordinary vectors are not normalized exactly as glam does (the tutorial's sums must
    // not move by an ulp), or if the vectors whose squared length overflows or underflows lose
    // their direction, or if zero, infinite or NaN vectors give anything but zero.
    #[test]
    fn normalize_or_zero_keeps_glams_result_and_rescues_extremes() {
        let mut x = 0x2545_f491u32;
        for _ in 0..1000 {
            let mut next = || {
                x ^= x << 13;
                x ^= x >> 17;
                x ^= x << 5;
                (x as f32 / u32::MAX as f32) * 20.0 - 10.0
            };
            let v = Vec3::new(next(), next(), next());
            assert_eq!(normalize_or_zero(v), v.normalize_or_zero(), "{v}");
        }
        assert_eq!(normalize_or_zero(Vec3::new(1e-30, 0.0, 0.0)), Vec3::X);
        assert_eq!(normalize_or_zero(Vec3::new(0.0, -3e30, 0.0)), Vec3::NEG_Y);
        let diagonal = normalize_or_zero(Vec3::new(1e30, 1e30, 0.0));
        assert!((diagonal - Vec3::new(1.0, 1.0, 0.0).normalize()).length() < 1e-6);
        for zero in [
            Vec3::ZERO,
            Vec3::new(f32::INFINITY, 0.0, 0.0),
            Vec3::new(f32::NAN, 1.0, 0.0),
        ] {
            assert_eq!(normalize_or_zero(zero), Vec3::ZERO, "{zero}");
        }
    }

    // Fails if `add_scaled` does not add `add × 2^-e`, or does not halve a total at or beyond the
    // limit until it is under it (counting the halvings in e).
    #[test]
    fn add_scaled_adds_at_the_sums_scale_and_halves_past_the_limit() {
        let sum = Vec3::new(1.0, 2.0, 3.0);
        let add = Vec3::new(4.0, 6.0, -8.0);
        assert_eq!(add_scaled(sum, add, 0), (Vec3::new(5.0, 8.0, -5.0), 0));
        assert_eq!(add_scaled(sum, add, 1), (Vec3::new(3.0, 5.0, -1.0), 1));
        let limit = SUM_LIMIT;
        // 2^40 exactly is at the limit: halved once.
        assert_eq!(
            add_scaled(Vec3::ZERO, Vec3::new(0.0, -limit, 1.0), 0),
            (Vec3::new(0.0, -limit / 2.0, 0.5), 1)
        );
        assert_eq!(
            add_scaled(Vec3::ZERO, Vec3::new(3.0 * limit, 0.0, 0.0), 0),
            (Vec3::new(0.75 * limit, 0.0, 0.0), 2)
        );
    }

    // Fails if any component of either vector is not held to the limit (each is tried at exactly
    // 2^40, which is not within, and just under it, which is), or if NaN counts as within.
    #[test]
    fn within_limit_checks_all_six_components() {
        let under = SUM_LIMIT - 65536.0;
        assert!(within_limit(Vec3::splat(under), Vec3::splat(-under)));
        assert!(within_limit(Vec3::ZERO, Vec3::new(1.0, -2.0, 3.0)));
        for k in 0..6 {
            let mut c = [1.0f32; 6];
            c[k] = SUM_LIMIT;
            let (t, b) = (Vec3::from_slice(&c[..3]), Vec3::from_slice(&c[3..]));
            assert!(!within_limit(t, b), "component {k} at the limit");
            assert!(!within_limit(-t, -b), "component {k} at minus the limit");
            c[k] = f32::NAN;
            let (t, b) = (Vec3::from_slice(&c[..3]), Vec3::from_slice(&c[3..]));
            assert!(!within_limit(t, b), "component {k} NaN");
        }
    }

    /// A soup of the given corners, each with its tangent and bitangent.
    fn soup(corners: &[((Vec3, Vec2, Vec3), Vec3, Vec3)]) -> (TriangleSoup, TangentBasis) {
        (
            TriangleSoup {
                vertices: corners.iter().map(|c| c.0 .0).collect(),
                uvs: corners.iter().map(|c| c.0 .1).collect(),
                normals: corners.iter().map(|c| c.0 .2).collect(),
            },
            TangentBasis {
                tangents: corners.iter().map(|c| c.1).collect(),
                bitangents: corners.iter().map(|c| c.2).collect(),
            },
        )
    }

    // Fails if a corner near an earlier vertex is not merged into the *first* such vertex with its
    // tangent and bitangent added (not subtracted, multiplied or dropped), if a corner near none
    // is not a new vertex with its own attributes and the next index, or if exercise 1's switch
    // does not normalize each corner's vectors before the sum.
    #[test]
    fn index_vbo_tbn_merges_near_corners_into_the_first_and_sums_their_tangents() {
        let a = a_corner();
        let b = (Vec3::new(5.0, 2.0, 3.0), a.1, a.2);
        let near_a = (a.0 + Vec3::splat(0.004), a.1, a.2);
        let (x, y, z) = (Vec3::X, Vec3::Y, Vec3::Z);
        let (s, t) = soup(&[
            (a, 2.0 * x, y),
            (b, y, z),
            (near_a, 3.0 * y, 4.0 * z),
            (b, z, x),
            (a, x, x),
        ]);
        let mesh = index_vbo_tbn(&s, &t, IndexOptions::default());
        assert_eq!(mesh.indices.to_u32(), [0, 1, 0, 1, 0]);
        assert_eq!(mesh.vertices, [a.0, b.0]);
        assert_eq!(mesh.uvs, [a.1, b.1]);
        assert_eq!(mesh.normals, [a.2, b.2]);
        assert_eq!(mesh.tangents, [3.0 * x + 3.0 * y, y + z]);
        assert_eq!(mesh.bitangents, [y + 4.0 * z + x, z + x]);

        let normalized = index_vbo_tbn(
            &s,
            &t,
            IndexOptions {
                normalize_before_sum: true,
            },
        );
        assert_eq!(normalized.indices, mesh.indices);
        assert_eq!(normalized.tangents, [2.0 * x + y, y + z]);
        assert_eq!(normalized.bitangents, [y + z + x, z + x]);
    }

    fn at(p: f32) -> (Vec3, Vec2, Vec3) {
        (Vec3::splat(p), Vec2::ZERO, Vec3::Z)
    }

    // Fails if a sum that reaches 2^40 is not halved (it is stored as the tutorial's plain sum),
    // if its scale is not remembered so that later corners, even small ones, are added at that
    // scale, or if the tangent's and the bitangent's scales are not kept apart (each scaled alone,
    // and both). The figures are exact: powers of two times small integers.
    #[test]
    fn sums_past_the_limit_are_halved_and_later_corners_added_at_their_scale() {
        let big = Vec3::new(1.5 * (1u64 << 39) as f32, 0.0, 0.0); // 0.75 of the limit
        let step = Vec3::new((1u64 << 38) as f32, 0.0, 0.0);
        let small = Vec3::Y;
        let e36 = (1u64 << 36) as f32;
        // Tangent alone: 0.75 + 0.75 = 1.5 × 2^40 → halved (e = 1); + 0.75 × 2^40 / 2 → 1.125 ×
        // 2^40 → halved (e = 2): 9 × 2^36; then 2^38 at e = 2 adds 2^36: 10 × 2^36 (a plain sum
        // would be 13 × 2^36).
        let corners = [
            (at(0.0), big, small),
            (at(0.0), big, small),
            (at(0.0), big, small),
        ];
        let mut all = corners.to_vec();
        all.push((at(0.0), step, small));
        let (s, t) = soup(&all);
        let mesh = index_vbo_tbn(&s, &t, IndexOptions::default());
        assert_eq!(mesh.tangents, [Vec3::new(10.0 * e36, 0.0, 0.0)]);
        assert_eq!(mesh.bitangents, [4.0 * small]);

        // The bitangent alone, the same figures.
        let swapped: Vec<_> = all.iter().map(|&(c, t, b)| (c, b, t)).collect();
        let (s, t) = soup(&swapped);
        let mesh = index_vbo_tbn(&s, &t, IndexOptions::default());
        assert_eq!(mesh.tangents, [4.0 * small]);
        assert_eq!(mesh.bitangents, [Vec3::new(10.0 * e36, 0.0, 0.0)]);

        // Both, and a first corner already past the limit: 2^41 → 2^39 (e = 2) for the tangent,
        // 0.75 × 2^40 for the bitangent; the second corner 0.75 × 2^40 each: the tangent
        // 2^39 + 0.75 × 2^38 → 44 × 2^34 (e = 2), the bitangent 1.5 × 2^40 → 0.75 × 2^40 (e = 1);
        // then 2^38 each: 44 × 2^34 + 2^36 = 48 × 2^34 and 0.75 × 2^40 + 2^37 = 56 × 2^34.
        let e34 = (1u64 << 34) as f32;
        let first = Vec3::new((1u64 << 41) as f32, 0.0, 0.0);
        let (s, t) = soup(&[
            (at(0.0), first, big),
            (at(0.0), big, big),
            (at(0.0), step, step),
        ]);
        let mesh = index_vbo_tbn(&s, &t, IndexOptions::default());
        assert_eq!(mesh.tangents, [Vec3::new(48.0 * e34, 0.0, 0.0)]);
        assert_eq!(mesh.bitangents, [Vec3::new(56.0 * e34, 0.0, 0.0)]);
    }

    // Fails if the lengths are not checked (the indexer would read past a short array).
    #[test]
    #[should_panic(expected = "one UV, normal, tangent and bitangent per corner")]
    fn index_vbo_tbn_refuses_a_basis_of_another_length() {
        let (s, mut t) = soup(&[(at(0.0), Vec3::X, Vec3::Y), (at(1.0), Vec3::X, Vec3::Y)]);
        t.bitangents.pop();
        index_vbo_tbn(&s, &t, IndexOptions::default());
    }

    // Fails if `index_vbo` merges anything but corners equal to the bit (0.004 apart is near for
    // `index_vbo_tbn`, not here), or numbers its vertices other than in order of first use.
    #[test]
    fn index_vbo_merges_only_equal_corners() {
        let a = a_corner();
        let near_a = (a.0 + Vec3::splat(0.004), a.1, a.2);
        let b = at(7.0);
        let (s, _) = soup(&[
            (b, Vec3::X, Vec3::Y),
            (a, Vec3::X, Vec3::Y),
            (near_a, Vec3::X, Vec3::Y),
            (a, Vec3::X, Vec3::Y),
            (b, Vec3::X, Vec3::Y),
        ]);
        let mesh = index_vbo(&s);
        assert_eq!(mesh.indices.to_u32(), [0, 1, 2, 1, 0]);
        assert_eq!(mesh.vertices, [b.0, a.0, near_a.0]);
        assert_eq!(mesh.uvs, [b.1, a.1, near_a.1]);
        assert_eq!(mesh.normals, [b.2, a.2, near_a.2]);
        assert!(mesh.tangents.is_empty() && mesh.bitangents.is_empty());
    }
}
