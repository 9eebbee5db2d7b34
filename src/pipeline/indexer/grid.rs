//! The hash grid [`index_vbo_tbn_hashed`](super::index_vbo_tbn_hashed) searches for the first near vertex.

use glam::{Vec2, Vec3};
use rustc_hash::FxHashMap;

use crate::common::objloader::TriangleSoup;
use crate::common::vboindexer::{is_near, IndexedMesh};

use super::prefetch;

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
pub(super) fn cell_side(soup: &TriangleSoup) -> f64 {
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
pub(super) struct Found {
    /// The lowest near vertex.
    pub(super) vertex: Option<u32>,
    /// The key of the corner's position cell if its list was long enough to split.
    pub(super) split: Option<u64>,
    /// How many vertices were looked at.
    pub(super) steps: u32,
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
pub(super) struct Grid {
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
    pub(super) fn new(side: f64, vertices: usize) -> Self {
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
    pub(super) fn prefetch(&self, p: Vec3) {
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
    pub(super) fn insert(&mut self, index: u32, out: &IndexedMesh) {
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
    pub(super) fn split(&mut self, key: u64, out: &IndexedMesh) {
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
    pub(super) fn find(&self, (p, uv, n): (Vec3, Vec2, Vec3), out: &IndexedMesh) -> Found {
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
