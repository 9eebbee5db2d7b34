//! The exact numbering both fast indexers start with: each corner's eight floats, by their bits.

use crate::common::objloader::TriangleSoup;

use super::prefetch;

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
/// [`index_vbo_tbn_hashed`](super::index_vbo_tbn_hashed) merges it with nothing.
pub(crate) fn weld(soup: &TriangleSoup, finite_only: bool) -> (Vec<u32>, Vec<u32>) {
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
