//! `common/vboindexer.cpp`: turn the triangle soup into an indexed mesh.
//!
//! The tutorial's `indexVBO_TBN` keeps a corner as a new vertex unless an earlier output vertex has
//! position, UV and normal each within 0.01 per component (`is_near`); then the corner reuses the
//! *first* such vertex and its tangent and bitangent are added to that vertex's (a sum, not an
//! average, and not normalized: the shader normalizes). It searches linearly, so it is quadratic:
//! the program indexes with [`crate::pipeline::indexer`], which gives the same mesh to the bit in
//! expected linear time, and the tests compare the two. `indexVBO` merges only corners equal to the
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
    let m = t.abs().max(b.abs());
    m.x < SUM_LIMIT && m.y < SUM_LIMIT && m.z < SUM_LIMIT
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

    /// A corner that becomes a new vertex; returns its index.
    fn push(&mut self, corner: (Vec3, Vec2, Vec3), t: Vec3, b: Vec3) -> u32 {
        let index = self.add_vertex(corner);
        self.start_sums(index, t, b);
        self.indices.push(index);
        index
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
            None => {
                out.push(c, t, b);
            }
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
}
