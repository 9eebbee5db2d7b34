//! `common/vboindexer.cpp`: turn the triangle soup into an indexed mesh.
//!
//! The tutorial's `indexVBO_TBN` keeps a corner as a new vertex unless an earlier output vertex has
//! position, UV and normal each within 0.01 per component (`is_near`); then the corner reuses the
//! *first* such vertex and its tangent and bitangent are added to that vertex's (a sum, not an
//! average, and not normalized: the shader normalizes). It searches linearly, so it is quadratic.
//!
//! [`index_vbo_tbn`] gives the same result in expected linear time: output vertices are kept in a hash
//! grid keyed on their position (each registered in the cells its ±0.01 neighbourhood touches), and
//! a corner looks only in its own cell, taking the lowest matching index, as the linear search would.
//! [`index_vbo_tbn_linear`] is the straightforward port, kept as the reference the tests compare with.
//! [`index_vbo`] ports the plain `indexVBO` (exact matches through a map, no tangents).
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
        let capacity = corners / 4 + 16;
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
        let (t, b) = self.prepare(t, b);
        self.indices.push(index);
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
        let (t, b) = self.prepare(t, b);
        let index = self.mesh.vertices.len() as u32;
        self.mesh.vertices.push(corner.0);
        self.mesh.uvs.push(corner.1);
        self.mesh.normals.push(corner.2);
        if within_limit(t, b) {
            self.mesh.tangents.push(t);
            self.mesh.bitangents.push(b);
        } else {
            self.store_scaled(index, t, b);
        }
        self.indices.push(index);
        index
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

/// Side of a grid cell. A vertex's neighbourhood (± `MARGIN`) spans 0.0202 per axis, so it touches
/// one or two cells per axis (1.4 on average, about 2.7 cells in all). Measured on the benchmark
/// meshes: 0.05 beats 0.025 (more registrations) and 0.1 (longer buckets).
const CELL: f64 = 0.05;
/// A little more than `NEAR`: f32's `|a - b| < 0.01` holds only where the exact difference is below
/// 0.01 × (1 + 2⁻²⁴), so every near vertex lies strictly within this margin.
const MARGIN: f64 = 0.0101;
const NO_ENTRY: u32 = u32::MAX;

/// Cell coordinate along one axis. The float-to-int cast saturates, so huge values share the end
/// cells; that only adds candidates, never loses one, because the exact test decides. Cells are
/// centred on multiples of `CELL` (boundaries at odd multiples of `CELL / 2`), so that the values
/// files are full of (0, 1, 0.5) sit mid-cell and their neighbourhoods touch one cell, not two.
fn cell_of(x: f64) -> i64 {
    // floor() by truncation and a correction: the libm call is not inlined on baseline x86-64 and
    // was a tenth of the indexing time. Monotone in x, which is all the grid needs.
    let q = x * (1.0 / CELL) + 0.5;
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
    buckets: FxHashMap<u64, (u32, u32)>, // first, last entry of the bucket
    entries: Vec<(u32, u32)>,            // vertex, next entry of the same bucket
    fine: FxHashMap<(u64, u64), (u32, u32)>, // (position key, UV/normal key) → first, last entry
    fine_entries: Vec<(u32, u32)>,
}

impl Grid {
    /// Sized for the vertices `corners` corners are expected to make (see `Builder::new`), each
    /// registered in two or three cells.
    fn with_capacity(corners: usize) -> Self {
        let mut buckets = FxHashMap::default();
        buckets.reserve(corners / 2);
        Grid {
            buckets,
            entries: Vec::with_capacity(corners / 2),
            fine: FxHashMap::default(),
            fine_entries: Vec::new(),
        }
    }

    /// Registers output vertex `index` (which must be the newest) of `out`.
    fn insert(&mut self, index: u32, out: &IndexedMesh) {
        let p = out.vertices[index as usize].to_array().map(|x| x as f64);
        let lo = p.map(|x| cell_of(x - MARGIN));
        let hi = p.map(|x| cell_of(x + MARGIN));
        for x in lo[0]..=hi[0] {
            for y in lo[1]..=hi[1] {
                for z in lo[2]..=hi[2] {
                    let key = cell_key(x, y, z);
                    let entry = self.entries.len() as u32;
                    // One hash per registration: the entry API finds or makes the bucket.
                    let (_, last) = self.buckets.entry(key).or_insert((entry, NO_ENTRY));
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
        let lo = rest.map(|x| cell_of(x - MARGIN));
        let hi = rest.map(|x| cell_of(x + MARGIN));
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
        let Some(&(mut entry, last)) = self.buckets.get(&key) else {
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
        self.buckets.insert(key, (SPLIT_BUCKET, SPLIT_BUCKET));
    }

    /// The lowest output vertex near corner `i` of `soup`, and whether the position cell's list was
    /// long enough to be worth splitting (then also the cell's key).
    /// Also gives how many vertices were looked at.
    fn find(&self, soup: &TriangleSoup, i: usize, out: &IndexedMesh) -> Found {
        let p = soup.vertices[i];
        let key = cell_key(
            cell_of(p.x as f64),
            cell_of(p.y as f64),
            cell_of(p.z as f64),
        );
        let Some(&(first, last)) = self.buckets.get(&key) else {
            return Found::default();
        };
        let (uv, n) = (soup.uvs[i], soup.normals[i]);
        let (mut entry, entries) = if last == SPLIT_BUCKET {
            let fine = fine_key(rest_of(uv, n).map(cell_of));
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

/// [`index_vbo_tbn`], also giving how many candidate vertices the searches looked at in all.
fn index_with_grid(
    soup: &TriangleSoup,
    basis: &TangentBasis,
    options: IndexOptions,
) -> (IndexedMesh, u64) {
    check_lengths(soup, basis);
    let n = soup.vertices.len();
    let mut out = Builder::new(n, options);
    let mut grid = Grid::with_capacity(n);
    let mut steps = 0u64;
    for i in 0..n {
        let (t, b) = (basis.tangents[i], basis.bitangents[i]);
        // A non-finite component is never near anything (NaN and inf - inf compare false), so such
        // a corner is always new and never found again: keep it out of the grid. (Read in place:
        // copying the corner out first cost a store-forwarding stall per corner.)
        let finite =
            soup.vertices[i].is_finite() && soup.uvs[i].is_finite() && soup.normals[i].is_finite();
        if !finite {
            out.push(corner(soup, i), t, b);
            continue;
        }
        let found = grid.find(soup, i, &out.mesh);
        steps += found.steps as u64;
        if let Some(key) = found.split {
            grid.split(key, &out.mesh);
        }
        match found.vertex {
            Some(j) => out.reuse(j, t, b),
            None => {
                let index = out.push(corner(soup, i), t, b);
                grid.insert(index, &out.mesh);
            }
        }
    }
    (out.finish(), steps)
}

/// The plain `indexVBO`: corners merge only when position, UV and normal are bit-for-bit equal (the
/// original compares `PackedVertex` with `memcmp` in a `std::map`). No tangents.
pub fn index_vbo(soup: &TriangleSoup) -> IndexedMesh {
    let n = soup.vertices.len();
    assert!(soup.uvs.len() == n && soup.normals.len() == n);
    let mut out = Builder::new(n, IndexOptions::default());
    let mut seen: FxHashMap<[u32; 8], u32> = FxHashMap::default();
    for i in 0..n {
        let c = corner(soup, i);
        let key = [c.0.x, c.0.y, c.0.z, c.1.x, c.1.y, c.2.x, c.2.y, c.2.z].map(f32::to_bits);
        match seen.get(&key) {
            Some(&j) => out.indices.push(j),
            None => {
                let j = out.push(c, Vec3::ZERO, Vec3::ZERO);
                seen.insert(key, j);
            }
        }
    }
    out.mesh.tangents.clear();
    out.mesh.bitangents.clear();
    out.finish()
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

    // Fails if the index width rule is off by one at the 16-bit limit.
    #[test]
    fn index_width_threshold() {
        assert_eq!(Indices::from_u32(vec![65534], 65535).index_size(), 2);
        assert_eq!(Indices::from_u32(vec![65535], 65536).index_size(), 4);
    }
}
