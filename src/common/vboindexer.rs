//! `common/vboindexer.cpp`: turn the triangle soup into an indexed mesh.
//!
//! The tutorial's `indexVBO_TBN` keeps a corner as a new vertex unless an earlier output vertex has
//! position, UV and normal each within 0.01 per component (`is_near`); then the corner reuses the
//! *first* such vertex and its tangent and bitangent are added to that vertex's (a sum, not an
//! average, and not normalized: the shader normalizes). It searches linearly, so it is quadratic.
//!
//! [`index_vbo_tbn`] gives the same result in expected linear time, in two passes. First the
//! corners are numbered by their exact bits, as the plain [`index_vbo`] (and meshoptimizer's remap)
//! does: a corner equal to an earlier one to the bit gets that corner's vertex, which the search
//! would find again. Then, corner by corner in the tutorial's order, the search (once per distinct
//! corner), the index and the tangent sums. The search keeps output vertices in a hash grid keyed
//! on their position (each registered in the cells its ±0.01 neighbourhood touches); a corner looks
//! only in its own cell, taking the lowest matching index, as the linear search would.
//! [`index_vbo_tbn_linear`] is the straightforward port, kept as the reference the tests compare with.
//!
//! The two hash tables are written here rather than taken from a crate because their speed comes
//! from what a general map does not offer: a slot is loaded a few corners before it is needed
//! (with a prefetch), and a small table of recent keys answers most corners of a mesh from the
//! core's cache. Both are measured against meshoptimizer in `benches/first_frame.rs`.
//!
//! Where the port differs: indices are 16-bit only while every vertex fits (at most 65 535 of them),
//! else 32-bit; the original casts to `unsigned short` and silently wraps.

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

/// The tutorial's exercise as a switch.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct IndexOptions {
    /// Normalize each corner's tangent and bitangent before adding them up (exercise 1), so that
    /// large triangles no longer outweigh small ones. Off in the tutorial's code.
    pub normalize_before_sum: bool,
}

/// The tutorial's `is_near`, per component.
fn is_near(a: f32, b: f32) -> bool {
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

/// Collects output vertices and the index buffer for both indexers, so that they differ only in how
/// they find a similar vertex.
struct Builder {
    mesh: IndexedMesh,
    indices: Vec<u32>,
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
    fn with_capacity(capacity: usize, corners: usize, options: IndexOptions) -> Self {
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

    fn vertex(&self, i: usize) -> (Vec3, Vec2, Vec3) {
        (
            self.mesh.vertices[i],
            self.mesh.uvs[i],
            self.mesh.normals[i],
        )
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
    fn add_sums(&mut self, index: u32, t: Vec3, b: Vec3) {
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
    fn add_vertex(&mut self, corner: (Vec3, Vec2, Vec3)) -> u32 {
        self.mesh.vertices.push(corner.0);
        self.mesh.uvs.push(corner.1);
        self.mesh.normals.push(corner.2);
        self.mesh.vertices.len() as u32 - 1
    }

    /// The corner that made vertex `index` (the next one without sums): its tangents start the
    /// sums.
    #[inline]
    fn start_sums(&mut self, index: u32, t: Vec3, b: Vec3) {
        let (t, b) = self.prepare(t, b);
        if within_limit(t, b) {
            self.mesh.tangents.push(t);
            self.mesh.bitangents.push(b);
        } else {
            self.store_scaled(index, t, b);
        }
    }

    fn finish(mut self) -> IndexedMesh {
        self.mesh.indices = Indices::from_u32(self.indices, self.mesh.vertices.len());
        self.mesh
    }
}

fn check_lengths(soup: &TriangleSoup, basis: &TangentBasis) {
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

fn corner(soup: &TriangleSoup, i: usize) -> (Vec3, Vec2, Vec3) {
    (soup.vertices[i], soup.uvs[i], soup.normals[i])
}

/// A corner's eight floats as bits, two to a word: what the tutorial's `indexVBO` compares with
/// `memcmp` (position, UV, normal).
type Key = [u64; 4];

fn key_of(soup: &TriangleSoup, i: usize) -> Key {
    let (p, uv, n) = (soup.vertices[i], soup.uvs[i], soup.normals[i]);
    let pair = |a: f32, b: f32| a.to_bits() as u64 | (b.to_bits() as u64) << 32;
    [
        pair(p.x, p.y),
        pair(p.z, uv.x),
        pair(uv.y, n.x),
        pair(n.y, n.z),
    ]
}

/// 64 bits from a key: four independent products (no chain of dependent multiplies), folded and
/// multiplied once more so that every key bit reaches the high bits, which pick the slot.
fn hash_key(key: &Key) -> u64 {
    const K: [u64; 5] = [
        0x9E37_79B9_7F4A_7C15,
        0xC2B2_AE3D_27D4_EB4F,
        0x1656_67B1_9E37_79F9,
        0xD6E8_FEB8_6659_FD93,
        0xFF51_AFD7_ED55_8CCD,
    ];
    let h = key[0].wrapping_mul(K[0])
        ^ key[1].wrapping_mul(K[1])
        ^ key[2].wrapping_mul(K[2])
        ^ key[3].wrapping_mul(K[3]);
    (h ^ h >> 32).wrapping_mul(K[4])
}

/// Asks the CPU to start loading `x`'s cache line, so that a lookup a few corners later does not
/// wait for memory. Changes no result.
#[inline(always)]
fn prefetch<T>(x: &T) {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: a prefetch only warms the cache; the pointer comes from a live reference.
    unsafe {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        _mm_prefetch::<_MM_HINT_T0>((x as *const T).cast());
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = x;
}

/// How many corners ahead the indexers start loading the slots a corner will read: enough to
/// cover a trip to memory.
const AHEAD: usize = 16;

/// Corners seen so far, by their exact bits, each numbered in the order it first came. What
/// meshoptimizer's remap does, sized the same way: an open-addressing table hashed once per
/// corner, reserved up front, at most two thirds full (doubling when needed). A slot holds the
/// key's number plus one (0: free) and 32 bits of its hash, so that a probe reads the key itself
/// (from the soup, at the corner where it first came) only when those agree.
struct Weld<'a> {
    soup: &'a TriangleSoup,
    slots: Vec<(u32, u32)>,
    /// The corner where each key first came.
    first: Vec<u32>,
    /// The same (number, hash bits) pairs for the keys seen last, one per other bits of the hash
    /// (a direct-mapped cache): a mesh's corners mostly repeat a vertex of the last few hundred, and
    /// this small table stays in the core's cache where the big one's random slots do not.
    recent: Vec<(u32, u32)>,
}

/// Slots of [`Weld::recent`]: 128 KiB.
const RECENT: usize = 1 << 14;

/// Which slot of [`Weld::recent`] a hash goes in: bits that neither the big table's slot (the
/// high bits) nor the stored hash bits (the low 32) use.
fn recent_slot(hash: u64) -> usize {
    (hash >> 32) as usize & (RECENT - 1)
}

impl<'a> Weld<'a> {
    /// For about `expected` distinct keys.
    fn with_capacity(soup: &'a TriangleSoup, expected: usize) -> Self {
        Weld {
            soup,
            slots: vec![(0, 0); (expected + expected / 3).next_power_of_two().max(64)],
            first: Vec::with_capacity(expected),
            recent: vec![(0, 0); RECENT],
        }
    }

    /// The slot a hash starts probing at: its high bits (the best mixed).
    fn home(&self, hash: u64) -> usize {
        (hash >> (64 - self.slots.len().trailing_zeros())) as usize
    }

    /// Starts loading what [`Weld::number`] will read for `hash`: its slot in the big table, unless
    /// the small one seems to hold the key already (most corners of a mesh).
    fn prefetch(&self, hash: u64) {
        let (id, tag) = self.recent[recent_slot(hash)];
        if id == 0 || tag != hash as u32 {
            prefetch(&self.slots[self.home(hash)]);
        }
    }

    /// Whether key number `id` + 1 is `key`. (Word by word in registers: comparing the arrays
    /// went through the stack and stalled on every lookup.)
    fn is(&self, id: u32, key: &Key) -> bool {
        let other = key_of(self.soup, self.first[id as usize - 1] as usize);
        (other[0] ^ key[0]) | (other[1] ^ key[1]) | (other[2] ^ key[2]) | (other[3] ^ key[3]) == 0
    }

    /// The number of corner `i`, whose key and hash are given (a new one if the key is new).
    fn number(&mut self, i: usize, key: &Key, hash: u64) -> u32 {
        let tag = hash as u32;
        let recent = recent_slot(hash);
        let (id, recent_tag) = self.recent[recent];
        if id != 0 && recent_tag == tag && self.is(id, key) {
            return id - 1;
        }
        let mask = self.slots.len() - 1;
        let mut slot = self.home(hash);
        loop {
            let (id, slot_tag) = self.slots[slot];
            if id == 0 {
                break;
            }
            if slot_tag == tag && self.is(id, key) {
                self.recent[recent] = (id, tag);
                return id - 1;
            }
            slot = (slot + 1) & mask;
        }
        self.first.push(i as u32);
        let id = self.first.len() as u32;
        self.slots[slot] = (id, tag);
        self.recent[recent] = (id, tag);
        if 3 * self.first.len() > 2 * self.slots.len() {
            self.grow();
        }
        id - 1
    }

    /// A number of its own for corner `i`, never looked up (a corner that merges with nothing).
    fn number_unlisted(&mut self, i: usize) -> u32 {
        self.first.push(i as u32);
        self.first.len() as u32 - 1
    }

    fn grow(&mut self) {
        self.slots = vec![(0, 0); 2 * self.slots.len()];
        let mask = self.slots.len() - 1;
        // `recent` names keys, not slots: it stays right.
        for (id, &i) in self.first.iter().enumerate() {
            let hash = hash_key(&key_of(self.soup, i as usize));
            let mut slot = self.home(hash);
            while self.slots[slot].0 != 0 {
                slot = (slot + 1) & mask;
            }
            self.slots[slot] = (id as u32 + 1, hash as u32);
        }
    }
}

/// Numbers each corner's exact bits (position, UV, normal) in the order they first come: gives the
/// number of every corner, and for each number the corner where it first came. With
/// `finite_only`, a corner with a non-finite component gets a number of its own, as
/// `index_vbo_tbn` merges it with nothing.
fn weld(soup: &TriangleSoup, finite_only: bool) -> (Vec<u32>, Vec<u32>) {
    let n = soup.vertices.len();
    // A closed mesh shares each vertex among about six corners.
    let mut weld = Weld::with_capacity(soup, n / 4);
    let mut numbers = Vec::with_capacity(n);
    let mut ahead = Ahead::new(soup);
    for i in 0..n {
        let (key, hash, next) = ahead.step(soup, i);
        if let Some(next) = next {
            weld.prefetch(next);
        }
        let listed = !finite_only
            || soup.vertices[i].is_finite()
                && soup.uvs[i].is_finite()
                && soup.normals[i].is_finite();
        numbers.push(if listed {
            weld.number(i, &key, hash)
        } else {
            weld.number_unlisted(i)
        });
    }
    (numbers, weld.first)
}

/// The keys and hashes of the next [`AHEAD`] corners, so that what they will read can be loaded
/// early.
struct Ahead {
    keys: [(Key, u64); AHEAD],
}

impl Ahead {
    fn new(soup: &TriangleSoup) -> Self {
        let mut keys = [([0; 4], 0); AHEAD];
        for (i, slot) in keys.iter_mut().enumerate().take(soup.vertices.len()) {
            let key = key_of(soup, i);
            *slot = (key, hash_key(&key));
        }
        Ahead { keys }
    }

    /// Corner `i`'s key and hash (the corners must come in order), and the hash of the corner
    /// [`AHEAD`] further on, if there is one.
    fn step(&mut self, soup: &TriangleSoup, i: usize) -> (Key, u64, Option<u64>) {
        let (key, hash) = self.keys[i % AHEAD];
        let next = i + AHEAD;
        if next >= soup.vertices.len() {
            return (key, hash, None);
        }
        let next_key = key_of(soup, next);
        let next_hash = hash_key(&next_key);
        self.keys[i % AHEAD] = (next_key, next_hash);
        (key, hash, Some(next_hash))
    }
}

/// The straightforward port of `indexVBO_TBN` with `getSimilarVertexIndex`: for each corner, scan the
/// output vertices from the first and take the first near one. Quadratic; the tests' reference.
pub fn index_vbo_tbn_linear(
    soup: &TriangleSoup,
    basis: &TangentBasis,
    options: IndexOptions,
) -> IndexedMesh {
    check_lengths(soup, basis);
    let mut out = Builder::new(soup.vertices.len(), options);
    for i in 0..soup.vertices.len() {
        let c = corner(soup, i);
        let (t, b) = (basis.tangents[i], basis.bitangents[i]);
        let found = (0..out.mesh.vertices.len()).find(|&j| is_near_vertex(c, out.vertex(j)));
        match found {
            Some(j) => out.reuse(j as u32, t, b),
            None => {
                out.push(c, t, b);
            }
        }
    }
    out.finish()
}

/// Smallest side of a position cell (see [`cell_side`]). A vertex's neighbourhood (± `MARGIN`)
/// spans 0.0202 per axis, so it touches one or two cells per axis.
const MIN_CELL: f64 = 0.05;
/// Side of a UV-and-normal cell in a split position cell (see [`Grid`]): there the lists are
/// walked by every corner that searches, so they are kept short.
const FINE_CELL: f64 = 0.05;
/// A little more than `NEAR`: f32's `|a - b| < 0.01` holds only where the exact difference is below
/// 0.01 × (1 + 2⁻²⁴), so every near vertex lies strictly within this margin.
const MARGIN: f64 = 0.0101;
const NO_ENTRY: u32 = u32::MAX;

/// Side of the position cells for `soup`: the 0.05 × 2^k nearest to twice its typical edge (the
/// median edge of up to about 1000 triangles spread over the soup), at least 0.05. A cell then
/// holds a handful of vertices at any scale: measured on the benchmark meshes, a 1M-triangle
/// cylinder with edges of 0.05 to 0.08 indexes fastest in cells of 0.1 (0.05 makes four times the
/// cells, 0.2 lists twice as long), and the 0.02-spaced soup of the one-cell benchmark in cells of
/// 0.05 (0.1 lists overflow [`SPLIT`]). (When every corner searched the grid, not only a key's
/// first, 0.05 was best on the benchmark meshes.) The side changes which vertices are looked at,
/// never which is found.
fn cell_side(soup: &TriangleSoup) -> f64 {
    let triangles = soup.vertices.len() / 3;
    let mut edges: Vec<f32> = (0..triangles)
        .step_by((triangles / 1024).max(1))
        .flat_map(|t| {
            let v = &soup.vertices[3 * t..3 * t + 3];
            [
                v[0].distance(v[1]),
                v[1].distance(v[2]),
                v[2].distance(v[0]),
            ]
        })
        .filter(|e| e.is_finite())
        .collect();
    if edges.is_empty() {
        return MIN_CELL;
    }
    let middle = edges.len() / 2;
    let median = *edges.select_nth_unstable_by(middle, f32::total_cmp).1 as f64;
    let k = (2.0 * median / MIN_CELL).log2().round().clamp(0.0, 60.0);
    MIN_CELL * k.exp2()
}

/// Cell coordinate along one axis, for cells of side `1 / inverse_side`. The float-to-int cast
/// saturates, so huge values share the end cells; that only adds candidates, never loses one,
/// because the exact test decides. Cells are centred on multiples of the side (boundaries at odd
/// multiples of half of it), so that 0 sits mid-cell, and with a side of 0.05 or 0.1 so do the
/// other values files are full of (1, 0.5): their neighbourhoods touch one cell, not two.
fn cell_of(x: f64, inverse_side: f64) -> i64 {
    // floor() by truncation and a correction: the libm call is not inlined on baseline x86-64 and
    // was a tenth of the indexing time. Monotone in x, which is all the grid needs.
    let q = x * inverse_side + 0.5;
    let t = q as i64;
    if (t as f64) > q {
        t.saturating_sub(1)
    } else {
        t
    }
}

/// One key for three cell coordinates. Distinct cells may share a key (21 bits each, wrapping); that
/// too only adds candidates.
fn cell_key(x: i64, y: i64, z: i64) -> u64 {
    const MASK: u64 = (1 << 21) - 1;
    (x as u64 & MASK) | (y as u64 & MASK) << 21 | (z as u64 & MASK) << 42
}

/// A position cell whose search walked past this many vertices is split by UV and normal (see
/// [`Grid`]). Ordinary meshes never get there: a cell holds a handful of vertices.
const SPLIT: u32 = 32;
/// `Bucket::first` of a position cell that has been split: its vertices live in `Grid::fine`.
const SPLIT_BUCKET: u32 = u32::MAX - 1;

/// The five non-position components of a corner: UV, then normal.
fn rest_of(uv: Vec2, normal: Vec3) -> [f64; 5] {
    [uv.x, uv.y, normal.x, normal.y, normal.z].map(|x| x as f64)
}

/// One key for five cell coordinates, 12 bits each, wrapping (collisions only add candidates).
fn fine_key(cells: [i64; 5]) -> u64 {
    cells
        .iter()
        .fold(0u64, |key, &c| key << 12 | (c as u64 & 0xFFF))
}

/// What [`Grid::find`] found.
#[derive(Default)]
struct Found {
    /// The lowest near vertex.
    vertex: Option<u32>,
    /// The key of the corner's position cell if its list was long enough to split.
    split: Option<u64>,
    /// How many vertices were looked at.
    steps: u32,
}

/// The position cells' lists: cell key → (first, last) entry, an open-addressing table sized up
/// front for the vertices expected and kept under three quarters full, so that a cell is found in
/// one or two neighbouring slots, and so that the slot a corner will need can be loaded ahead
/// ([`Cells::prefetch`]).
struct Cells {
    /// Cell key with [`TAKEN`] set (0: free slot), first entry, last entry.
    slots: Vec<(u64, u32, u32)>,
    len: usize,
}

/// Marks a used slot of [`Cells`]: cell keys use the low 63 bits only.
const TAKEN: u64 = 1 << 63;

impl Cells {
    fn with_capacity(cells: usize) -> Self {
        Cells {
            slots: vec![(0, 0, 0); (cells + cells / 3).next_power_of_two().max(64)],
            len: 0,
        }
    }

    fn home(&self, key: u64) -> usize {
        let hash = (key ^ key >> 29).wrapping_mul(0x9E37_79B9_7F4A_7C15);
        (hash >> (64 - self.slots.len().trailing_zeros())) as usize
    }

    /// The slot holding `key`, or the free one where it would go.
    fn slot(&self, key: u64) -> usize {
        let mask = self.slots.len() - 1;
        let mut slot = self.home(key);
        while self.slots[slot].0 != 0 && self.slots[slot].0 != key | TAKEN {
            slot = (slot + 1) & mask;
        }
        slot
    }

    fn prefetch(&self, key: u64) {
        prefetch(&self.slots[self.home(key)]);
    }

    fn get(&self, key: u64) -> Option<(u32, u32)> {
        let (k, first, last) = self.slots[self.slot(key)];
        (k != 0).then_some((first, last))
    }

    /// The (first, last) pair of `key`, made `default` if the cell has none yet.
    fn get_or_insert(&mut self, key: u64, default: (u32, u32)) -> (&mut u32, &mut u32) {
        let mut slot = self.slot(key);
        if self.slots[slot].0 == 0 {
            if 4 * (self.len + 1) > 3 * self.slots.len() {
                self.grow();
                slot = self.slot(key);
            }
            self.slots[slot] = (key | TAKEN, default.0, default.1);
            self.len += 1;
        }
        let (_, first, last) = &mut self.slots[slot];
        (first, last)
    }

    fn grow(&mut self) {
        let bigger = vec![(0, 0, 0); 2 * self.slots.len()];
        let old = std::mem::replace(&mut self.slots, bigger);
        for entry in old.into_iter().filter(|e| e.0 != 0) {
            let slot = self.slot(entry.0 & !TAKEN);
            self.slots[slot] = entry;
        }
    }
}

/// Output vertices bucketed by position cell. A vertex is registered in every cell its ±0.01
/// neighbourhood touches (one to eight), so a corner looks in its own cell only: corners outnumber
/// vertices about six to one in a typical mesh, so the probing is done on the cheaper side. Each
/// bucket is a list threaded through `entries`, in increasing vertex order, so the first near vertex
/// found is the lowest near one, as the linear search would find.
///
/// Many vertices in one position cell (a file whose corners share a position but not their UVs)
/// would make that list long and the search quadratic. So a cell whose search walks past [`SPLIT`]
/// vertices is split: its vertices, and any registered there later, go to `fine`, keyed on the cell
/// and on the cell of their UV and normal (registered, the same way, in every such cell their ±0.01
/// neighbourhood touches), again in increasing vertex order. A corner in a split cell looks in the
/// one list for its own UV-and-normal cell, which holds every vertex near it.
struct Grid {
    /// 1 / the side of a position cell.
    inverse_side: f64,
    buckets: Cells,
    entries: Vec<(u32, u32)>, // vertex, next entry of the same bucket
    fine: FxHashMap<(u64, u64), (u32, u32)>, // (position key, UV/normal key) → first, last entry
    fine_entries: Vec<(u32, u32)>,
}

impl Grid {
    /// Cells of side `side`, sized for up to `vertices` vertices, each registered in one to three
    /// cells.
    fn new(side: f64, vertices: usize) -> Self {
        Grid {
            inverse_side: 1.0 / side,
            buckets: Cells::with_capacity(vertices / 2),
            entries: Vec::with_capacity(3 * vertices),
            fine: FxHashMap::default(),
            fine_entries: Vec::new(),
        }
    }

    /// The cells a vertex at `p` is registered in: every cell of the box lo..=hi.
    fn neighbourhood(&self, p: Vec3) -> ([i64; 3], [i64; 3]) {
        let p = p.to_array().map(|x| x as f64);
        (
            p.map(|x| cell_of(x - MARGIN, self.inverse_side)),
            p.map(|x| cell_of(x + MARGIN, self.inverse_side)),
        )
    }

    /// Starts loading the slots that a corner at `p` will read ([`Grid::find`]) and, if it becomes
    /// a vertex, write ([`Grid::insert`]).
    fn prefetch(&self, p: Vec3) {
        let (lo, hi) = self.neighbourhood(p);
        for x in lo[0]..=hi[0] {
            for y in lo[1]..=hi[1] {
                for z in lo[2]..=hi[2] {
                    self.buckets.prefetch(cell_key(x, y, z));
                }
            }
        }
    }

    /// Registers output vertex `index` (which must be the newest) of `out`.
    fn insert(&mut self, index: u32, out: &IndexedMesh) {
        let (lo, hi) = self.neighbourhood(out.vertices[index as usize]);
        for x in lo[0]..=hi[0] {
            for y in lo[1]..=hi[1] {
                for z in lo[2]..=hi[2] {
                    let key = cell_key(x, y, z);
                    let entry = self.entries.len() as u32;
                    // One probe per registration: finds or makes the bucket.
                    let (_, last) = self.buckets.get_or_insert(key, (entry, NO_ENTRY));
                    if *last == SPLIT_BUCKET {
                        self.insert_fine(key, index, out);
                        continue;
                    }
                    if *last != NO_ENTRY {
                        self.entries[*last as usize].1 = entry;
                    }
                    *last = entry;
                    self.entries.push((index, NO_ENTRY));
                }
            }
        }
    }

    /// Registers vertex `index` of `out` in the split position cell `key`.
    fn insert_fine(&mut self, key: u64, index: u32, out: &IndexedMesh) {
        let j = index as usize;
        let rest = rest_of(out.uvs[j], out.normals[j]);
        let lo = rest.map(|x| cell_of(x - MARGIN, 1.0 / FINE_CELL));
        let hi = rest.map(|x| cell_of(x + MARGIN, 1.0 / FINE_CELL));
        // Every cell of the box lo..=hi (one to 32), as an odometer.
        let mut cells = lo;
        loop {
            let entry = self.fine_entries.len() as u32;
            self.fine_entries.push((index, NO_ENTRY));
            let (_, last) = self
                .fine
                .entry((key, fine_key(cells)))
                .or_insert((entry, NO_ENTRY));
            if *last != NO_ENTRY {
                self.fine_entries[*last as usize].1 = entry;
            }
            *last = entry;
            let mut axis = 0;
            while axis < 5 && cells[axis] == hi[axis] {
                cells[axis] = lo[axis];
                axis += 1;
            }
            if axis == 5 {
                break;
            }
            cells[axis] += 1;
        }
    }

    /// Splits position cell `key` (see [`Grid`]): its vertices move to `fine`, in order.
    fn split(&mut self, key: u64, out: &IndexedMesh) {
        let Some((mut entry, last)) = self.buckets.get(key) else {
            return;
        };
        if last == SPLIT_BUCKET {
            return;
        }
        while entry != NO_ENTRY {
            let (vertex, next) = self.entries[entry as usize];
            self.insert_fine(key, vertex, out);
            entry = next;
        }
        let (first, last) = self
            .buckets
            .get_or_insert(key, (SPLIT_BUCKET, SPLIT_BUCKET));
        (*first, *last) = (SPLIT_BUCKET, SPLIT_BUCKET);
    }

    /// The lowest output vertex near a corner, and whether the position cell's list was long
    /// enough to be worth splitting (then also the cell's key).
    /// Also gives how many vertices were looked at.
    fn find(&self, (p, uv, n): (Vec3, Vec2, Vec3), out: &IndexedMesh) -> Found {
        let key = cell_key(
            cell_of(p.x as f64, self.inverse_side),
            cell_of(p.y as f64, self.inverse_side),
            cell_of(p.z as f64, self.inverse_side),
        );
        let Some((first, last)) = self.buckets.get(key) else {
            return Found::default();
        };
        let (mut entry, entries) = if last == SPLIT_BUCKET {
            let fine = fine_key(rest_of(uv, n).map(|x| cell_of(x, 1.0 / FINE_CELL)));
            match self.fine.get(&(key, fine)) {
                Some(&(first, _)) => (first, &self.fine_entries),
                None => return Found::default(),
            }
        } else {
            (first, &self.entries)
        };
        let mut steps = 0;
        while entry != NO_ENTRY {
            let (vertex, next) = entries[entry as usize];
            let j = vertex as usize;
            // The tutorial's is_near on all eight components, read in place.
            let (q, quv, qn) = (out.vertices[j], out.uvs[j], out.normals[j]);
            if is_near(p.x, q.x)
                && is_near(p.y, q.y)
                && is_near(p.z, q.z)
                && is_near(uv.x, quv.x)
                && is_near(uv.y, quv.y)
                && is_near(n.x, qn.x)
                && is_near(n.y, qn.y)
                && is_near(n.z, qn.z)
            {
                break;
            }
            entry = next;
            steps += 1;
        }
        let found = (entry != NO_ENTRY).then(|| entries[entry as usize].0);
        let long = steps > SPLIT && last != SPLIT_BUCKET;
        Found {
            vertex: found,
            split: long.then_some(key),
            steps,
        }
    }
}

/// `indexVBO_TBN` with the tutorial's exact semantics, in expected linear time (see the module docs).
pub fn index_vbo_tbn(
    soup: &TriangleSoup,
    basis: &TangentBasis,
    options: IndexOptions,
) -> IndexedMesh {
    index_with_grid(soup, basis, options).0
}

/// How many numbers ahead [`index_with_grid`] starts loading the cells of their first corners.
const GRID_AHEAD: usize = 8;

/// [`index_vbo_tbn`], also giving how many candidate vertices the searches looked at in all.
///
/// In two passes over the corners, each with a small working set: number them by their exact bits
/// ([`weld`]); then, corner by corner, search the grid at each number's first corner (a corner
/// equal to an earlier one to the bit gets that corner's vertex: any near vertex with a lower index
/// existed back then, and would have been found), write the index and sum the tangents, as the
/// tutorial does.
fn index_with_grid(
    soup: &TriangleSoup,
    basis: &TangentBasis,
    options: IndexOptions,
) -> (IndexedMesh, u64) {
    check_lengths(soup, basis);
    let (mut numbers, mut first) = weld(soup, true);
    // At most one vertex per number; the index buffer will be `numbers`.
    let mut out = Builder::with_capacity(first.len(), 0, options);
    let mut grid = Grid::new(cell_side(soup), first.len());
    let mut steps = 0u64;
    // Numbers below `searched` have their vertex, which replaces their first corner in `first`.
    let mut searched = 0;
    for (i, index) in numbers.iter_mut().enumerate() {
        let number = *index as usize;
        // Numbers come in the order of their first corners: this is number `searched`'s.
        if number == searched {
            if let Some(&next) = first.get(number + GRID_AHEAD) {
                grid.prefetch(soup.vertices[next as usize]);
            }
            let corner = corner(soup, i);
            // A non-finite component is never near anything (NaN and inf - inf compare false), so
            // such a corner is always new and never found again: [`weld`] numbered it alone.
            let finite = corner.0.is_finite() && corner.1.is_finite() && corner.2.is_finite();
            first[number] = if finite {
                let found = grid.find(corner, &out.mesh);
                steps += found.steps as u64;
                if let Some(key) = found.split {
                    grid.split(key, &out.mesh);
                }
                match found.vertex {
                    Some(j) => j,
                    None => {
                        let j = out.add_vertex(corner);
                        grid.insert(j, &out.mesh);
                        j
                    }
                }
            } else {
                out.add_vertex(corner)
            };
            searched += 1;
        }
        let j = first[number];
        let (t, b) = (basis.tangents[i], basis.bitangents[i]);
        // Vertices are numbered in the order of the corners that made them.
        if j as usize == out.mesh.tangents.len() {
            out.start_sums(j, t, b);
        } else {
            out.add_sums(j, t, b);
        }
        // The corner's number becomes its vertex: the index buffer, in place.
        *index = j;
    }
    out.indices = numbers;
    (out.finish(), steps)
}

/// The plain `indexVBO`: corners merge only when position, UV and normal are bit-for-bit equal (the
/// original compares `PackedVertex` with `memcmp` in a `std::map`). No tangents.
pub fn index_vbo(soup: &TriangleSoup) -> IndexedMesh {
    let n = soup.vertices.len();
    assert!(soup.uvs.len() == n && soup.normals.len() == n);
    let (numbers, first) = weld(soup, false);
    // The vertices are the distinct corners, in the order they first came.
    IndexedMesh {
        indices: Indices::from_u32(numbers, first.len()),
        vertices: first.iter().map(|&i| soup.vertices[i as usize]).collect(),
        uvs: first.iter().map(|&i| soup.uvs[i as usize]).collect(),
        normals: first.iter().map(|&i| soup.normals[i as usize]).collect(),
        tangents: Vec::new(),
        bitangents: Vec::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn soup_of(positions: &[Vec3]) -> (TriangleSoup, TangentBasis) {
        let n = positions.len();
        let soup = TriangleSoup {
            vertices: positions.to_vec(),
            uvs: vec![Vec2::ZERO; n],
            normals: vec![Vec3::Z; n],
        };
        let basis = TangentBasis {
            tangents: (0..n).map(|i| Vec3::new(i as f32, 1.0, 0.0)).collect(),
            bitangents: vec![Vec3::Y; n],
        };
        (soup, basis)
    }

    // Fails if "near" is not strict per-component < 0.01, or if a merged vertex keeps its own
    // tangent instead of the sum.
    #[test]
    fn near_corners_merge_and_sum() {
        let (soup, basis) = soup_of(&[
            Vec3::ZERO,
            Vec3::new(0.009, 0.0, 0.0), // near the first
            Vec3::new(0.011, 0.0, 0.0), // not near the first, near the second: new vertex
        ]);
        for mesh in [
            index_vbo_tbn(&soup, &basis, IndexOptions::default()),
            index_vbo_tbn_linear(&soup, &basis, IndexOptions::default()),
        ] {
            assert_eq!(mesh.indices, Indices::U16(vec![0, 0, 1]));
            assert_eq!(mesh.vertices, vec![Vec3::ZERO, Vec3::new(0.011, 0.0, 0.0)]);
            assert_eq!(mesh.tangents[0], Vec3::new(1.0, 2.0, 0.0));
            assert_eq!(mesh.bitangents[0], Vec3::new(0.0, 2.0, 0.0));
        }
    }

    // Fails if the fast indexer takes any near vertex rather than the first, as the linear search does.
    #[test]
    fn first_near_vertex_wins_across_cells() {
        // Vertices 0 and 1 are 0.015 apart (both kept); the corner at 0.0075 is near both and
        // straddles a cell boundary: it must pick vertex 0.
        let base = 0.025 * 7.0 - 0.0075;
        let (soup, basis) = soup_of(&[
            Vec3::new(base + 0.015, 0.0, 0.0),
            Vec3::new(base, 0.0, 0.0),
            Vec3::new(base + 0.0075, 0.0, 0.0),
        ]);
        let fast = index_vbo_tbn(&soup, &basis, IndexOptions::default());
        assert_eq!(fast.indices.to_u32(), vec![0, 1, 0]);
        assert_eq!(
            fast,
            index_vbo_tbn_linear(&soup, &basis, IndexOptions::default())
        );
    }

    // Fails if NaN corners are merged with each other or anything else (the original never does).
    #[test]
    fn non_finite_corners_never_merge() {
        let (soup, basis) = soup_of(&[
            Vec3::NAN,
            Vec3::NAN,
            Vec3::ZERO,
            Vec3::INFINITY,
            Vec3::INFINITY,
            Vec3::ZERO,
        ]);
        let fast = index_vbo_tbn(&soup, &basis, IndexOptions::default());
        assert_eq!(fast.indices.to_u32(), vec![0, 1, 2, 3, 4, 2]);
    }

    // Fails if the exercise switch does not normalize each corner before summing.
    #[test]
    fn normalize_before_sum() {
        let (soup, basis) = soup_of(&[Vec3::ZERO, Vec3::ZERO, Vec3::ZERO]);
        let options = IndexOptions {
            normalize_before_sum: true,
        };
        let mesh = index_vbo_tbn(&soup, &basis, options);
        let expected =
            Vec3::Y + Vec3::new(1.0, 1.0, 0.0).normalize() + Vec3::new(2.0, 1.0, 0.0).normalize();
        assert!((mesh.tangents[0] - expected).length() < 1e-6);
        assert_eq!(mesh.bitangents[0], Vec3::new(0.0, 3.0, 0.0));
    }

    // Fails if the plain indexer merges anything but bit-identical corners.
    #[test]
    fn index_vbo_merges_exact_duplicates_only() {
        let (soup, _) = soup_of(&[Vec3::ZERO, Vec3::new(0.001, 0.0, 0.0), Vec3::ZERO]);
        let mesh = index_vbo(&soup);
        assert_eq!(mesh.indices.to_u32(), vec![0, 1, 0]);
        assert!(mesh.tangents.is_empty());
    }

    // Fails if thousands of vertices sharing one position (distinct UVs) stay in one list that
    // every corner walks: the quadratic case of issue 8. After the split, lists stay short.
    #[test]
    fn one_position_cell_is_split() {
        for position in [Vec3::ZERO, Vec3::splat(0.025)] {
            let n = 3000;
            let (mut soup, basis) = soup_of(&vec![position; n]);
            soup.uvs = (0..n)
                .map(|i| Vec2::new(0.02 * (i % 50) as f32, 0.02 * (i / 50) as f32))
                .collect();
            let (mesh, steps) = index_with_grid(&soup, &basis, IndexOptions::default());
            assert_eq!(mesh.vertices.len(), n);
            // Unsplit, every corner walks every earlier vertex: n²/2 = 4.5 million steps.
            assert!(steps < 20 * n as u64, "{position}: {steps} steps");
        }
    }

    // Fails if the position cells are not sized to the mesh: twice the typical edge, rounded to
    // 0.05 × 2^k, at least 0.05 (also for a soup of one point, or of edges too long for f32).
    #[test]
    fn cell_side_follows_the_edges() {
        // Right triangles along x, legs `edge` long (so the median edge is `edge`).
        let strip = |edge: f32| {
            let positions: Vec<Vec3> = (0..300)
                .map(|i| {
                    let corner = [Vec3::ZERO, Vec3::X, Vec3::Y][i % 3];
                    (corner + Vec3::X * (i / 3) as f32) * edge
                })
                .collect();
            soup_of(&positions).0
        };
        assert_eq!(cell_side(&strip(0.06)), 0.1);
        assert_eq!(cell_side(&strip(0.02)), 0.05);
        assert_eq!(cell_side(&strip(0.5)), 0.8);
        assert_eq!(cell_side(&soup_of(&[Vec3::ONE; 30]).0), 0.05);
        assert_eq!(cell_side(&strip(3e38)), 0.05);
        assert_eq!(cell_side(&soup_of(&[]).0), 0.05);
    }

    // Fails if the index width rule is off by one at the 16-bit limit.
    #[test]
    fn index_width_threshold() {
        assert_eq!(Indices::from_u32(vec![65534], 65535).index_size(), 2);
        assert_eq!(Indices::from_u32(vec![65535], 65536).index_size(), 4);
    }
}
