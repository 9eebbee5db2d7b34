//! A bounding volume hierarchy over HIGH's triangles, for the bake's rays: binned SAH, built on every
//! core near the root, leaves of at most four triangles, nodes in one array with each
//! node's children side by side. A bake's rays are short (from the cage to a little past LOW's
//! surface) and start near each other, so a plain stack traversal that visits the nearer child first
//! is what they need; see BENCHMARKS.md ("Baking") for why this is the project's own and not a crate.

use glam::{BVec3, Vec3, Vec4};

use std::sync::Mutex;

use crate::pipeline::{join, on_threads};

#[cfg(target_arch = "x86_64")]
mod wide;

/// At most this many triangles in a leaf.
const LEAF_SIZE: usize = 4;
/// Centroid bins per axis for the SAH split.
const BINS: usize = 16;
/// Below this many triangles a subtree is built on the thread that reached it.
const PARALLEL_MIN: usize = 1 << 16;

/// The triangles the build copies into the leaves' order at a time, by whichever thread is free.
const COPY_RUN: usize = 1 << 15;
/// A box within this fraction past the nearest hit so far is still searched ([`Lanes::enter`]).
const LIMIT_SLACK: f32 = 1e-5;
/// Below this cosine between a ray and a triangle's plane the ray counts as parallel to it.
const PARALLEL: f32 = 1e-6;
/// How much of its coordinates' size a box is grown by ([`Aabb::padded`]): 2⁻¹⁶, about 128
/// ulps.
const PAD: f32 = 1.0 / 65536.0;
/// The deepest a node may be: the traversal's stack holds one more than this.
const MAX_DEPTH: usize = 120;
/// The traversal's stack: a visit pops one child and pushes at most four.
const STACK: usize = 3 * MAX_DEPTH + 4;

/// An axis-aligned box.
#[derive(Debug, Clone, Copy, PartialEq, bytemuck::Zeroable)]
struct Aabb {
    min: Vec3,
    max: Vec3,
}

impl Aabb {
    const EMPTY: Aabb = Aabb {
        min: Vec3::splat(f32::INFINITY),
        max: Vec3::splat(f32::NEG_INFINITY),
    };

    fn grow(&mut self, p: Vec3) {
        self.min = lower(self.min, p);
        self.max = higher(self.max, p);
    }

    fn join(&mut self, other: &Aabb) {
        self.min = lower(self.min, other.min);
        self.max = higher(self.max, other.max);
    }

    /// The box grown by [`PAD`] of its coordinates' size on each side: the triangle test rounds
    /// too, and takes a ray that starts on a triangle's corner (a cage on HIGH) as meeting it at
    /// 0 even where the rounded origin lies a few ulps outside the triangle's box, which the
    /// slab test's slack (relative to the distances, 0 there) does not cover.
    fn padded(&self) -> Aabb {
        let pad = self.min.abs().max(self.max.abs()) * PAD;
        Aabb {
            min: self.min - pad,
            max: self.max + pad,
        }
    }

    /// Half the surface area (the SAH's weights only compare).
    fn half_area(&self) -> f32 {
        let d = (self.max - self.min).max(Vec3::ZERO);
        d.x * d.y + d.y * d.z + d.z * d.x
    }
}

/// Each component of `b` where it is below `a`'s, else `a`'s (a NaN in `b` is passed over): one
/// compare and select, where `f32::min`'s rule for NaN costs more (on wasm32, several times more).
#[inline(always)]
fn lower(a: Vec3, b: Vec3) -> Vec3 {
    Vec3::select(b.cmplt(a), b, a)
}

/// Each component of `b` where it is above `a`'s, else `a`'s ([`lower`]).
#[inline(always)]
fn higher(a: Vec3, b: Vec3) -> Vec3 {
    Vec3::select(b.cmpgt(a), b, a)
}

/// A node as the build makes it: an inner node's children are `first` and `first + 1`; a leaf
/// holds `count` triangles from `first` in [`Bvh::order`].
#[derive(Debug, Clone, Copy)]
struct BuildNode {
    bounds: Aabb,
    first: u32,
    /// 0 for an inner node.
    count: u32,
}

/// An inner node as the rays read it: up to four children, their boxes side by side axis by axis
/// (so that one test of four lanes tests all four), in two cache lines. The binary tree the build
/// makes is collapsed into these: half as many levels, so half as many reads that wait on memory.
#[derive(Debug, Clone, Copy)]
#[repr(C, align(64))]
struct Node {
    min: [Vec4; 3],
    max: [Vec4; 3],
    /// Each child: an inner node's index, or a leaf's first triangle.
    child: [u32; 4],
    /// Each child leaf's number of triangles, [`INNER`] for an inner node; 0 for an unused
    /// slot (its box empty).
    count: [u32; 4],
}

impl Node {
    /// Child `k`'s box.
    fn bounds(&self, k: usize) -> Aabb {
        Aabb {
            min: Vec3::new(self.min[0][k], self.min[1][k], self.min[2][k]),
            max: Vec3::new(self.max[0][k], self.max[1][k], self.max[2][k]),
        }
    }
}

/// [`Node::count`] of a child that is an inner node.
const INNER: u32 = u32::MAX;

/// A triangle as the ray test wants it: a corner and the two edges from it, 40 bytes (what a
/// hit hands back is in [`Bvh::data`], read once a packet's walk is done: beside them, a leaf's
/// four triangles were twice as many cache lines for the tests to read).
#[derive(Debug, Clone, Copy, bytemuck::Zeroable)]
struct Triangle {
    p0: Vec3,
    e1: Vec3,
    e2: Vec3,
    /// The determinant at or below which a ray counts as parallel to the triangle's plane
    /// ([`Triangle::new`]).
    parallel: f32,
}

impl Triangle {
    fn new(c: &[Vec3]) -> Triangle {
        let (e1, e2) = (c[1] - c[0], c[2] - c[0]);
        Triangle {
            p0: c[0],
            e1,
            e2,
            // The determinant is d · (e2 × e1), |e1 × e2| cos of the angle between the (unit)
            // direction and the normal: for a ray within 10⁻⁶ rad of the plane (in it, but for
            // rounding) its rounding errors are as large as it, and the test's distance and
            // barycentrics are noise (a "hit" at 0 on a triangle far from the origin). Such a
            // ray meets the triangle's edge at most, as a neighbour's face meets it.
            parallel: (e1.cross(e2).length() * PARALLEL).max(f32::MIN_POSITIVE),
        }
    }
}

/// The first triangle a ray meets: its index in the mesh, the distance along the (unit) direction,
/// the barycentric weights of its corners 1 and 2, and the data it was built with
/// ([`Bvh::build_with`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hit {
    pub triangle: u32,
    pub distance: f32,
    pub u: f32,
    pub v: f32,
    pub data: [Vec3; 3],
}

/// The hierarchy, with the triangles copied in its leaves' order.
#[derive(Debug)]
pub struct Bvh {
    nodes: Vec<Node>,
    triangles: Vec<Triangle>,
    /// What each of `triangles` hands back in a hit ([`Bvh::build_with`]), in their order.
    data: Vec<[Vec3; 3]>,
    /// The mesh's index of each of `triangles`.
    order: Vec<u32>,
}

/// What the build sorts: a triangle's box, centre and index.
#[derive(Debug, Clone, Copy, bytemuck::Zeroable)]
struct Item {
    bounds: Aabb,
    centre: Vec3,
    index: u32,
}

impl Bvh {
    /// The hierarchy over `positions` (three per triangle). Triangles with a corner that is not
    /// finite are left out: no ray can meet them, and their boxes would poison their neighbours'.
    pub fn build(positions: &[Vec3], threads: usize) -> Bvh {
        Bvh::build_with(positions, |_| [Vec3::ZERO; 3], threads)
    }

    /// [`Bvh::build`], with `data(t)` kept for triangle `t` and handed back in its hits (a
    /// bake's HIGH normals): in the leaves' order, so that it is read near where the search read
    /// the triangle, not from anywhere in a mesh-sized array.
    pub fn build_with(
        positions: &[Vec3],
        data: impl Fn(usize) -> [Vec3; 3] + Sync,
        threads: usize,
    ) -> Bvh {
        let threads = threads.max(1);
        let mut items = items_of(positions, threads);
        if items.is_empty() {
            return Bvh {
                nodes: Vec::new(),
                triangles: Vec::new(),
                data: Vec::new(),
                order: Vec::new(),
            };
        }
        let built = build_subtree(&mut items, 0, 0, threads);
        // The triangles copied in the leaves' order, in runs that the threads take in turn; the
        // first thread makes the four-wide nodes first (0.04 s for a 1.3M-triangle sculpt, which
        // the other spends on the copies).
        let mut triangles: Vec<Triangle> = bytemuck::zeroed_vec(items.len());
        let mut datas: Vec<[Vec3; 3]> = bytemuck::zeroed_vec(items.len());
        let mut order: Vec<u32> = bytemuck::zeroed_vec(items.len());
        let runs = (items.chunks(COPY_RUN)).zip(
            (triangles.chunks_mut(COPY_RUN))
                .zip(datas.chunks_mut(COPY_RUN))
                .zip(order.chunks_mut(COPY_RUN)),
        );
        let runs = Mutex::new(runs);
        let copy = || loop {
            let next = runs.lock().expect("no copy panics holding it").next();
            let Some((items, ((triangles, datas), order))) = next else {
                break;
            };
            let slots = triangles.iter_mut().zip(datas).zip(order);
            for (item, ((triangle, kept), index)) in items.iter().zip(slots) {
                let i = item.index as usize;
                *triangle = Triangle::new(&positions[3 * i..3 * i + 3]);
                *kept = data(i);
                *index = item.index;
            }
        };
        let nodes = match threads {
            1 => {
                copy();
                four_wide(&built)
            }
            _ => {
                let (nodes, ()) = join(
                    || {
                        let nodes = four_wide(&built);
                        copy();
                        nodes
                    },
                    copy,
                );
                nodes
            }
        };
        Bvh {
            nodes,
            triangles,
            data: datas,
            order,
        }
    }

    /// The number of inner nodes (for the log and the tests).
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// The nearest triangle that the ray from `origin` along the unit `direction` meets at a
    /// distance in `0..=max_distance`, from either side; of triangles at one distance (a shared
    /// edge), the lowest index.
    pub fn first_hit(&self, origin: Vec3, direction: Vec3, max_distance: f32) -> Option<Hit> {
        let ray = Ray {
            origin,
            direction,
            max_distance,
        };
        let mut hit = [None];
        self.first_hits(&[ray], &mut hit);
        hit[0]
    }

    /// [`Bvh::first_hit`] of each ray, into `hits`, [`PACKET`] rays at a time: rays that start near
    /// each other and point the same way (a texel's K × K, neighbouring texels') walk the
    /// hierarchy together, each box and triangle tested for all of them at once. Each ray's
    /// answer is the one it finds alone.
    pub fn first_hits(&self, rays: &[Ray], hits: &mut [Option<Hit>]) {
        assert_eq!(rays.len(), hits.len(), "a hit for each ray");
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU has AVX2, which is all that `first_hits_avx2` is compiled for
            // beyond SSE2.
            return unsafe { self.first_hits_avx2(rays, hits) };
        }
        self.first_hits_of::<false>(rays, hits)
    }

    /// [`Bvh::first_hits`] compiled for AVX2: the walk's four-lane operations in VEX's
    /// three-operand form (no copies of registers before each one), and a leaf's tests on eight
    /// lanes ([`wide`]). No fused multiply-add is enabled, so every lane rounds as before: the
    /// same hits to the bit.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,bmi1,popcnt")]
    unsafe fn first_hits_avx2(&self, rays: &[Ray], hits: &mut [Option<Hit>]) {
        self.first_hits_of::<true>(rays, hits)
    }

    /// [`Bvh::first_hits`], for whichever instruction set it is inlined into: with `WIDE`, two
    /// groups of four rays are tested at once (eight lanes, [`wide`]), which only code compiled
    /// for AVX2 may ask for.
    #[inline(always)]
    fn first_hits_of<const WIDE: bool>(&self, rays: &[Ray], hits: &mut [Option<Hit>]) {
        for (rays, hits) in rays.chunks(PACKET).zip(hits.chunks_mut(PACKET)) {
            match rays.len() {
                1..=4 => self.trace::<1, false>(rays, hits),
                // A packet of a texel's 4 × 4 among larger ones (a band's last).
                5..=16 => self.trace::<4, WIDE>(rays, hits),
                _ => self.trace::<{ PACKET / 4 }, WIDE>(rays, hits),
            };
        }
    }

    /// The first hits of up to `4 × G` rays walking the hierarchy together: a box is entered if
    /// any ray enters it (each against its own nearest hit so far), a leaf's triangles are
    /// tested for every ray. A box a ray would not have entered holds no nearer triangle for it,
    /// and its tests are its own: its answer is the one it finds alone.
    /// Returns the number of nodes and leaves visited (for the tests).
    #[inline(always)]
    fn trace<const G: usize, const WIDE: bool>(
        &self,
        rays: &[Ray],
        hits: &mut [Option<Hit>],
    ) -> usize {
        let mut lanes = Lanes::<G>::new(rays);
        let visits = match (self.nodes.is_empty(), Beam::of(&lanes)) {
            (true, _) => 0,
            (false, Some(beam)) => self.walk::<G, WIDE>(&mut lanes, &beam),
            (false, None) => self.walk::<G, WIDE>(&mut lanes, &EachRay),
        };
        lanes.hits(&self.data, hits);
        visits
    }

    /// The walk down the hierarchy, `test` telling where the rays enter a box (if they do).
    /// Returns the number of nodes and leaves visited.
    #[inline(always)]
    fn walk<const G: usize, const WIDE: bool>(
        &self,
        lanes: &mut Lanes<G>,
        test: &impl BoxTest,
    ) -> usize {
        let mut visits = 0;
        // Each entry: a child (its index or first triangle, and its count), and the nearest
        // distance at which a ray entered it (it is skipped if every ray has found a nearer hit
        // since). The root's children are tested first.
        // A leaf's entry has the groups of four rays of which some ray enters its box: only
        // those test its triangles (a packet of a few texels' rays meets a leaf with one texel's).
        let mut stack = [(0u32, INNER, 0f32, 0u32); STACK];
        let mut depth = 1;
        while depth > 0 {
            depth -= 1;
            let (child, count, entry, groups) = stack[depth];
            if entry > lanes.farthest_limit() {
                continue;
            }
            visits += 1;
            if count != INNER {
                let start = child as usize;
                for k in start..start + count as usize {
                    let (tri, index) = (&self.triangles[k], self.order[k]);
                    #[cfg(target_arch = "x86_64")]
                    if WIDE && G % 2 == 0 {
                        // SAFETY: only `first_hits_avx2` asks for WIDE, on a CPU with AVX2; the
                        // groups pair up.
                        unsafe { wide::intersect(lanes, tri, index, k as u32, groups) };
                        continue;
                    }
                    lanes.intersect(tri, index, k as u32, groups);
                }
                continue;
            }
            let node = &self.nodes[child as usize];
            let entries = test.enter(node, lanes);
            // The entered children, farthest first on the stack, so that the nearest is visited
            // first and its hits can cut the others off.
            let mut entered = [(0u32, 0u32, 0f32, 0u32); 4];
            let mut n = 0;
            for (k, ((&entry, &c), &count)) in
                entries.iter().zip(&node.child).zip(&node.count).enumerate()
            {
                if entry < f32::INFINITY && count != 0 {
                    let mut groups = u32::MAX;
                    if count == INNER {
                        prefetch(&self.nodes[c as usize]);
                    } else {
                        prefetch(&self.triangles[c as usize]);
                        groups = match G {
                            1 => 1,
                            #[cfg(target_arch = "x86_64")]
                            // SAFETY: only `first_hits_avx2` asks for WIDE, on a CPU with AVX2; the
                            // groups pair up.
                            _ if WIDE && G % 2 == 0 => unsafe {
                                wide::groups_entering(lanes, &node.bounds(k))
                            },
                            _ => lanes.groups_entering(&node.bounds(k)),
                        };
                        if groups == 0 {
                            continue;
                        }
                    }
                    // Insertion by entry, farthest first.
                    let mut at = n;
                    while at > 0 && entered[at - 1].2 < entry {
                        entered[at] = entered[at - 1];
                        at -= 1;
                    }
                    entered[at] = (c, count, entry, groups);
                    n += 1;
                }
            }
            stack[depth..depth + n].copy_from_slice(&entered[..n]);
            depth += n;
        }
        visits
    }
}

/// Asks for the cache line at `item` ahead of its read (nothing where there is no such hint).
#[inline(always)]
fn prefetch<T>(item: &T) {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: a prefetch reads nothing and cannot fault; the address is a live reference's.
    unsafe {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        _mm_prefetch::<_MM_HINT_T0>((item as *const T).cast());
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = item;
}

/// A ray for [`Bvh::first_hits`]: from `origin` along the unit `direction`, at most
/// `max_distance` far.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ray {
    pub origin: Vec3,
    pub direction: Vec3,
    pub max_distance: f32,
}

impl Ray {
    /// A ray that meets nothing (a negative limit).
    pub const IDLE: Ray = Ray {
        origin: Vec3::ZERO,
        direction: Vec3::X,
        max_distance: -1.0,
    };
}

/// Rays traced together by [`Bvh::first_hits`]: 2 × 2 texels' 4 × 4, or 8 × 8 texels' one each
/// (a walk down the hierarchy for 64 rays, where it was one for a texel's 16; a leaf's triangles
/// are tested only by the groups of four rays that enter its box).
pub const PACKET: usize = 64;

/// `4 × G` rays, one per lane, each component in vectors of four lanes (glam's `Vec4`: SSE on
/// x86-64, simd128 or plain floats on wasm32), so that a box's or a triangle's test runs on four
/// rays at once.
struct Lanes<const G: usize> {
    origin: [[Vec4; G]; 3],
    direction: [[Vec4; G]; 3],
    inverse: [[Vec4; G]; 3],
    /// The distance a hit must not pass: the nearest so far, or the ray's limit (negative for an
    /// idle lane, which nothing is within).
    nearest: [Vec4; G],
    /// `nearest` widened by [`LIMIT_SLACK`], as the boxes are tested against it.
    reach: [Vec4; G],
    /// The mesh index of the triangle met at `nearest` (`u32::MAX`: none yet), and where it is
    /// in [`Bvh::triangles`] (its data is read at that slot of [`Bvh::data`] once the walk is
    /// done, not copied at each nearer hit).
    triangle: [[u32; 4]; G],
    slot: [[u32; 4]; G],
    u: [[f32; 4]; G],
    v: [[f32; 4]; G],
}

impl<const G: usize> Lanes<G> {
    #[inline(always)]
    fn new(rays: &[Ray]) -> Self {
        debug_assert!(rays.len() <= 4 * G);
        let mut lanes = Lanes {
            origin: [[Vec4::ZERO; G]; 3],
            direction: [[Vec4::X; G]; 3],
            inverse: [[Vec4::ONE; G]; 3],
            nearest: [Vec4::splat(-1.0); G],
            reach: [Vec4::splat(-1.0); G],
            triangle: [[u32::MAX; 4]; G],
            slot: [[0; 4]; G],
            u: [[0.0; 4]; G],
            v: [[0.0; 4]; G],
        };
        for (l, ray) in rays.iter().enumerate() {
            // A ray that is not finite meets nothing: its lane stays idle.
            if !(ray.origin.is_finite() && ray.direction.is_finite()) {
                continue;
            }
            let (g, k) = (l / 4, l % 4);
            let inverse = ray.direction.recip();
            for axis in 0..3 {
                lanes.origin[axis][g][k] = ray.origin[axis];
                lanes.direction[axis][g][k] = ray.direction[axis];
                lanes.inverse[axis][g][k] = inverse[axis];
            }
            lanes.nearest[g][k] = ray.max_distance;
            lanes.reach[g][k] = widened_limit(ray.max_distance);
        }
        lanes
    }

    /// The largest distance any lane still searches to.
    #[inline(always)]
    fn farthest_limit(&self) -> f32 {
        let mut far = self.reach[0];
        for reach in &self.reach[1..] {
            far = far.max(*reach);
        }
        far.max_element()
    }

    /// The nearest distance at which a lane enters `bounds` within its reach, if any does: the
    /// slab test on every lane.
    ///
    /// A direction component of 0 gives infinite reciprocals: a slab the ray lies wholly outside
    /// then gives it no distance in it, and one it lies inside gives it all. 0 × ∞ is NaN: the ray
    /// runs in the plane of one of that slab's faces, so all of it is in the slab, its faces
    /// counted in as the triangle test counts its edges: that axis limits nothing.
    ///
    /// The limit is a hit's distance from the triangle test, and a box holding another triangle
    /// at that very distance may round its entry a few ulps past it: with a little slack such a box
    /// is still searched, so that which of two triangles at one distance was met first cannot
    /// change the answer. The box's own exit is widened as much (Ize's robust slab test widens it
    /// by 2γ₃): a ray that grazes a triangle's edge on the box's face must not be rounded out of
    /// the box. An exit of −∞ (a box wholly to one side of a ray with a component of 0) must stay
    /// negative: −∞ + ∞ · slack was NaN, which counted the box as entered, and every box on that
    /// side was visited.
    #[inline(always)]
    fn enter(&self, bounds: &Aabb) -> Option<f32> {
        let mut entry = Vec4::INFINITY;
        for g in 0..G {
            entry = entry.min(self.group_entry(g, bounds));
        }
        let entry = entry.min_element();
        (entry < f32::INFINITY).then_some(entry)
    }

    /// The groups of four lanes of which some lane enters `bounds` within its reach, as a mask
    /// (group g: bit g); the test of [`Lanes::enter`].
    #[inline(always)]
    fn groups_entering(&self, bounds: &Aabb) -> u32 {
        let mut groups = 0;
        for g in 0..G {
            let entered = self.group_entry(g, bounds).cmplt(Vec4::INFINITY).any();
            groups |= u32::from(entered) << g;
        }
        groups
    }

    /// Where each lane of group `g` enters `bounds` within its reach, ∞ where it does not
    /// ([`Lanes::enter`]).
    #[inline(always)]
    fn group_entry(&self, g: usize, bounds: &Aabb) -> Vec4 {
        let mut near = Vec4::ZERO;
        let mut far = Vec4::INFINITY;
        for axis in 0..3 {
            let (o, i) = (self.origin[axis][g], self.inverse[axis][g]);
            let t0 = (Vec4::splat(bounds.min[axis]) - o) * i;
            let t1 = (Vec4::splat(bounds.max[axis]) - o) * i;
            // 0 × ∞: the ray in the plane of one of the slab's faces.
            let along = t0.is_nan_mask() | t1.is_nan_mask();
            let low = Vec4::select(along, Vec4::NEG_INFINITY, t0.min(t1));
            let high = Vec4::select(along, Vec4::INFINITY, t0.max(t1));
            near = near.max(low);
            far = far.min(high);
        }
        // −∞ as −f32::MAX, which its widening keeps negative.
        let far = far.max(Vec4::splat(-f32::MAX));
        let far = (far + far.abs() * LIMIT_SLACK).min(self.reach[g]);
        Vec4::select(near.cmple(far), near, Vec4::INFINITY)
    }

    /// [`intersect`] on every lane, keeping each lane's nearest hit (of hits at one distance,
    /// the lowest mesh index, so that the order of the search cannot change the answer). The
    /// same operations in the same order as [`intersect`]'s (glam's `cross` and `dot` written
    /// out), so that each lane's distance and barycentrics are its, to the bit.
    /// Only the groups of four lanes in the mask `groups` (group g: bit g) are tested: the others
    /// enter no box around the triangle. `index` is the triangle's in the mesh, `slot` in
    /// [`Bvh::triangles`].
    #[inline(always)]
    fn intersect(&mut self, tri: &Triangle, index: u32, slot: u32, groups: u32) {
        let [p0x, p0y, p0z] = tri.p0.to_array().map(Vec4::splat);
        let [e1x, e1y, e1z] = tri.e1.to_array().map(Vec4::splat);
        let [e2x, e2y, e2z] = tri.e2.to_array().map(Vec4::splat);
        // The groups in the mask, lowest first (one step each, where a loop over every group
        // tested each bit).
        let mut remaining = groups & ((1u64 << G) - 1) as u32;
        while remaining != 0 {
            let g = remaining.trailing_zeros() as usize;
            remaining &= remaining - 1;
            let (o, d) = (&self.origin, &self.direction);
            let (ox, oy, oz) = (o[0][g], o[1][g], o[2][g]);
            let (dx, dy, dz) = (d[0][g], d[1][g], d[2][g]);
            // p = direction × e2
            let px = dy * e2z - e2y * dz;
            let py = dz * e2x - e2z * dx;
            let pz = dx * e2y - e2x * dy;
            let det = (e1x * px) + (e1y * py) + (e1z * pz);
            let inv = Vec4::ONE / det;
            // s = origin − p0
            let (sx, sy, sz) = (ox - p0x, oy - p0y, oz - p0z);
            let u = ((sx * px) + (sy * py) + (sz * pz)) * inv;
            let within_u = det.abs().cmpgt(Vec4::splat(tri.parallel))
                & det.abs().cmplt(Vec4::INFINITY)
                & u.cmpge(Vec4::ZERO)
                & u.cmple(Vec4::ONE);
            // Most triangles a packet tests lie beside all its rays: half the test tells.
            if !within_u.any() {
                continue;
            }
            // q = s × e1
            let qx = sy * e1z - e1y * sz;
            let qy = sz * e1x - e1z * sx;
            let qz = sx * e1y - e1x * sy;
            let v = ((dx * qx) + (dy * qy) + (dz * qz)) * inv;
            let t = ((e2x * qx) + (e2y * qy) + (e2z * qz)) * inv;
            let hit = within_u
                & !(v.cmplt(Vec4::ZERO) | (u + v).cmpgt(Vec4::ONE))
                & t.cmpge(Vec4::ZERO)
                & t.abs().cmplt(Vec4::INFINITY)
                & t.cmple(self.nearest[g]);
            // Hits within a lane's nearest are few (a handful a ray): each is kept lane by lane.
            let mask = hit.bitmask();
            if mask == 0 {
                continue;
            }
            for k in (0..4).filter(|k| mask & (1 << k) != 0) {
                self.keep(g, k, (t[k], u[k], v[k]), index, slot);
            }
        }
    }

    /// Lane `k` of group `g` met triangle `index` (at `slot`) within its nearest, at distance,
    /// u and v `hit`: kept if nearer than what it holds, or at the same distance with a lower
    /// index.
    #[inline(always)]
    fn keep(&mut self, g: usize, k: usize, hit: (f32, f32, f32), index: u32, slot: u32) {
        let (t, u, v) = hit;
        if t < self.nearest[g][k] || index < self.triangle[g][k] {
            self.nearest[g][k] = t;
            self.reach[g][k] = widened_limit(t);
            self.triangle[g][k] = index;
            self.slot[g][k] = slot;
            self.u[g][k] = u;
            self.v[g][k] = v;
        }
    }

    /// The first `count` lanes' hits, each with its triangle's data from `data`.
    #[inline(always)]
    fn hits(&self, data: &[[Vec3; 3]], hits: &mut [Option<Hit>]) {
        for (l, hit) in hits.iter_mut().enumerate() {
            let (g, k) = (l / 4, l % 4);
            *hit = (self.triangle[g][k] != u32::MAX).then(|| Hit {
                triangle: self.triangle[g][k],
                distance: self.nearest[g][k],
                u: self.u[g][k],
                v: self.v[g][k],
                data: data[self.slot[g][k] as usize],
            });
        }
    }
}

/// Where a packet's rays enter each of a node's children's boxes: no later than any of them,
/// and ∞ where none does.
trait BoxTest {
    fn enter<const G: usize>(&self, node: &Node, lanes: &Lanes<G>) -> [f32; 4];
}

/// Each ray tested on its own ([`Lanes::enter`]).
struct EachRay;

impl BoxTest for EachRay {
    #[inline(always)]
    fn enter<const G: usize>(&self, node: &Node, lanes: &Lanes<G>) -> [f32; 4] {
        std::array::from_fn(|k| match node.count[k] {
            0 => f32::INFINITY,
            _ => lanes.enter(&node.bounds(k)).unwrap_or(f32::INFINITY),
        })
    }
}

/// Rays that start near each other and point the same way, as one beam: the box around their
/// origins and, per axis, the range of their directions' reciprocals. A box the beam misses is
/// missed by every ray in it, so one test for the packet stands for its rays' tests (Wald,
/// Boulos and Shirley's interval-arithmetic test for coherent packets, as Embree's packets do).
#[derive(Debug, Clone, Copy)]
struct Beam {
    axes: [BeamAxis; 3],
}

/// One axis of a [`Beam`].
#[derive(Debug, Clone, Copy)]
enum BeamAxis {
    /// Every ray's direction is 0 along it: each stays at its origin's coordinate, `low..=high`.
    Still { low: f32, high: f32 },
    /// Every ray's direction has one sign along it: origins `low..=high`, reciprocals
    /// `inverse_low..=inverse_high` (all finite).
    Moving {
        low: f32,
        high: f32,
        inverse_low: f32,
        inverse_high: f32,
        positive: bool,
    },
}

impl Beam {
    /// The beam of `lanes`' rays (those with something to meet: a finite ray, a limit of 0 or
    /// more; the others are idle), if each axis is still or of one sign for all of them; `None`
    /// where some axis is not (the rays are then tested one by one), or no ray is active. Read
    /// from the lanes four rays at a time (the reciprocals are theirs).
    #[inline(always)]
    fn of<const G: usize>(lanes: &Lanes<G>) -> Option<Beam> {
        let (mut low, mut high) = ([Vec4::INFINITY; 3], [Vec4::NEG_INFINITY; 3]);
        let (mut inverse_low, mut inverse_high) = ([Vec4::INFINITY; 3], [Vec4::NEG_INFINITY; 3]);
        let no = glam::BVec4A::splat(false);
        let (mut still, mut positive, mut negative) = ([no; 3], [no; 3], [no; 3]);
        let mut any = no;
        for g in 0..G {
            // An idle lane's limit is negative (or NaN: nothing is within it either).
            let active = lanes.nearest[g].cmpge(Vec4::ZERO);
            any |= active;
            for axis in 0..3 {
                let (o, i, d) = (
                    lanes.origin[axis][g],
                    lanes.inverse[axis][g],
                    lanes.direction[axis][g],
                );
                low[axis] = low[axis].min(Vec4::select(active, o, Vec4::INFINITY));
                high[axis] = high[axis].max(Vec4::select(active, o, Vec4::NEG_INFINITY));
                inverse_low[axis] = inverse_low[axis].min(Vec4::select(active, i, Vec4::INFINITY));
                inverse_high[axis] =
                    inverse_high[axis].max(Vec4::select(active, i, Vec4::NEG_INFINITY));
                still[axis] |= active & d.cmpeq(Vec4::ZERO);
                positive[axis] |= active & d.cmpgt(Vec4::ZERO);
                negative[axis] |= active & d.cmplt(Vec4::ZERO);
            }
        }
        if !any.any() {
            return None;
        }
        let across = |v: [Vec4; 3], f: fn(Vec4) -> f32| Vec3::new(f(v[0]), f(v[1]), f(v[2]));
        let (low, high) = (
            across(low, Vec4::min_element),
            across(high, Vec4::max_element),
        );
        let inverse_low = across(inverse_low, Vec4::min_element);
        let inverse_high = across(inverse_high, Vec4::max_element);
        let across = |v: [glam::BVec4A; 3]| BVec3::new(v[0].any(), v[1].any(), v[2].any());
        let (still, positive, negative) = (across(still), across(positive), across(negative));
        let mut axes = [BeamAxis::Still {
            low: 0.0,
            high: 0.0,
        }; 3];
        for (axis, slot) in axes.iter_mut().enumerate() {
            // Finite and not 0 (a direction far from unit length), so that no product is NaN.
            let finite = inverse_low[axis].is_finite()
                && inverse_high[axis].is_finite()
                && inverse_low[axis] != 0.0
                && inverse_high[axis] != 0.0;
            *slot = match (still.test(axis), positive.test(axis), negative.test(axis)) {
                (_, false, false) => BeamAxis::Still {
                    low: low[axis],
                    high: high[axis],
                },
                (false, true, false) | (false, false, true) if finite => BeamAxis::Moving {
                    low: low[axis],
                    high: high[axis],
                    inverse_low: inverse_low[axis],
                    inverse_high: inverse_high[axis],
                    positive: positive.test(axis),
                },
                _ => return None,
            };
        }
        Some(Beam { axes })
    }

    /// The beam of `rays` (at most [`PACKET`]), as [`Bvh::first_hits`] makes it.
    #[cfg(test)]
    fn around(rays: &[Ray]) -> Option<Beam> {
        Beam::of(&Lanes::<{ PACKET / 4 }>::new(rays))
    }
}

impl BoxTest for Beam {
    /// Where the beam may enter each child's box within the lanes' reach: no later than any of
    /// its rays does, and ∞ only if none of them does; the four boxes at once. Each bound is the
    /// extreme of the products (face − origin) × reciprocal over the ranges, at their corners;
    /// both ends are widened by the slack of [`Lanes::enter`].
    #[inline(always)]
    fn enter<const G: usize>(&self, node: &Node, lanes: &Lanes<G>) -> [f32; 4] {
        let mut near = Vec4::ZERO;
        let mut far = Vec4::INFINITY;
        let mut inside = glam::BVec4A::splat(true);
        for (axis, beam) in self.axes.iter().enumerate() {
            let (min, max) = (node.min[axis], node.max[axis]);
            match *beam {
                BeamAxis::Still { low, high } => {
                    inside &= max.cmpge(Vec4::splat(low)) & min.cmple(Vec4::splat(high));
                }
                BeamAxis::Moving {
                    low,
                    high,
                    inverse_low,
                    inverse_high,
                    positive,
                } => {
                    // Entered through the face the rays come to first, left through the other.
                    // The smallest entry comes from the origin nearest that face, the largest
                    // exit from the one farthest from the other; which reciprocal gives the
                    // extreme depends on the sign of the difference.
                    let (to_entry, to_exit) = if positive {
                        (min - Vec4::splat(high), max - Vec4::splat(low))
                    } else {
                        (max - Vec4::splat(low), min - Vec4::splat(high))
                    };
                    let (low_inverse, high_inverse) =
                        (Vec4::splat(inverse_low), Vec4::splat(inverse_high));
                    let entry = to_entry
                        * Vec4::select(to_entry.cmpge(Vec4::ZERO), low_inverse, high_inverse);
                    let exit = to_exit
                        * Vec4::select(to_exit.cmpge(Vec4::ZERO), high_inverse, low_inverse);
                    near = near.max(entry);
                    far = far.min(exit);
                }
            }
        }
        let near = near - near.abs() * LIMIT_SLACK;
        let far = far.max(Vec4::splat(-f32::MAX));
        let far = (far + far.abs() * LIMIT_SLACK).min(Vec4::splat(lanes.farthest_limit()));
        let entered = inside & near.cmple(far);
        Vec4::select(entered, near.max(Vec4::ZERO), Vec4::INFINITY).to_array()
    }
}

/// A box within this of a ray's limit is still searched ([`Lanes::enter`]).
#[inline]
fn widened_limit(limit: f32) -> f32 {
    limit + limit * LIMIT_SLACK
}

/// Möller and Trumbore's test, from either side (one ray: the tests' reference for
/// [`Lanes::intersect`]): the distance and the barycentrics of corners 1
/// and 2, or `None` for a miss, a ray in the triangle's plane or a degenerate triangle.
#[cfg(test)]
fn intersect(tri: &Triangle, origin: Vec3, direction: Vec3) -> Option<(f32, f32, f32)> {
    let p = direction.cross(tri.e2);
    let det = tri.e1.dot(p);
    // A zero-area triangle, or a ray along its plane: nothing to meet (and no division by zero).
    if det.abs() <= tri.parallel || !det.is_finite() {
        return None;
    }
    let inv = 1.0 / det;
    let s = origin - tri.p0;
    let u = s.dot(p) * inv;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let q = s.cross(tri.e1);
    let v = direction.dot(q) * inv;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    let t = tri.e2.dot(q) * inv;
    (t >= 0.0 && t.is_finite()).then_some((t, u, v))
}

/// The build's binary tree as the rays read it: each node with up to four children, made by
/// opening the largest (by surface) of a node's inner children until there are four; the root
/// first. A root that is a leaf becomes a node with that one child.
fn four_wide(built: &[BuildNode]) -> Vec<Node> {
    let mut nodes = Vec::with_capacity(built.len() / 3 + 1);
    if built[0].count > 0 {
        nodes.push(node_of(built, &[0], |_| {
            unreachable!("a leaf has no inner child")
        }));
        return nodes;
    }
    // Each entry: a binary inner node and the index its four-wide node gets.
    let mut pending = vec![(0usize, 0u32)];
    nodes.push(empty_node());
    while let Some((at, index)) = pending.pop() {
        let mut children = vec![built[at].first as usize, built[at].first as usize + 1];
        while children.len() < 4 {
            let largest = children
                .iter()
                .enumerate()
                .filter(|(_, &c)| built[c].count == 0)
                .max_by(|a, b| {
                    let area = |c: usize| built[c].bounds.half_area();
                    area(*a.1).total_cmp(&area(*b.1))
                });
            let Some((k, &c)) = largest else { break };
            children.swap_remove(k);
            children.extend([built[c].first as usize, built[c].first as usize + 1]);
        }
        let node = node_of(built, &children, |c| {
            let index = nodes.len() as u32;
            nodes.push(empty_node());
            pending.push((c, index));
            index
        });
        nodes[index as usize] = node;
    }
    nodes
}

/// A four-wide node with no children.
fn empty_node() -> Node {
    Node {
        min: [Vec4::INFINITY; 3],
        max: [Vec4::NEG_INFINITY; 3],
        child: [0; 4],
        count: [0; 4],
    }
}

/// The four-wide node over the binary tree's `children` (at most four), `inner(c)` giving the
/// index of the four-wide node made for an inner child `c`.
fn node_of(built: &[BuildNode], children: &[usize], mut inner: impl FnMut(usize) -> u32) -> Node {
    let mut node = empty_node();
    for (k, &c) in children.iter().enumerate() {
        let b = built[c];
        let bounds = b.bounds.padded();
        for axis in 0..3 {
            node.min[axis][k] = bounds.min[axis];
            node.max[axis][k] = bounds.max[axis];
        }
        (node.child[k], node.count[k]) = match b.count {
            0 => (inner(c), INNER),
            n => (b.first, n),
        };
    }
    node
}

/// The build's items of the triangles of `positions` whose corners are all finite (no ray can
/// meet the others, and their boxes would poison their neighbours'), in order. Made in runs on
/// `threads` threads into an array the system zeroed, each thread faulting in its own pages; a
/// mesh with a triangle left out is made again in one pass.
fn items_of(positions: &[Vec3], threads: usize) -> Vec<Item> {
    let item = |(i, c): (usize, &[Vec3])| {
        let mut bounds = Aabb::EMPTY;
        c.iter().for_each(|&p| bounds.grow(p));
        Item {
            bounds,
            centre: (bounds.min + bounds.max) * 0.5,
            index: i as u32,
        }
    };
    let finite = |c: &[Vec3]| c.iter().all(|p| p.is_finite());
    let count = positions.len() / 3;
    let mut items: Vec<Item> = bytemuck::zeroed_vec(count);
    let run = count.div_ceil(threads).max(1);
    let jobs: Vec<_> = items.chunks_mut(run).enumerate().collect();
    let all_finite = on_threads(jobs, |(k, items)| {
        let triangles = positions[3 * k * run..].chunks_exact(3);
        let mut all_finite = true;
        for (j, (out, c)) in items.iter_mut().zip(triangles).enumerate() {
            all_finite &= finite(c);
            *out = item((k * run + j, c));
        }
        all_finite
    });
    if all_finite.into_iter().all(|f| f) {
        return items;
    }
    let triangles = positions.chunks_exact(3).enumerate();
    triangles.filter(|(_, c)| finite(c)).map(item).collect()
}

/// The subtree over `items` (reordered into its leaves' order), its root first; child and leaf
/// indices count from its root, its leaves' from `base` items; `depth` is its root's.
fn build_subtree(items: &mut [Item], base: usize, depth: usize, threads: usize) -> Vec<BuildNode> {
    let mut nodes = Vec::with_capacity(2 * items.len() / LEAF_SIZE + 1);
    nodes.push(BuildNode {
        bounds: Aabb::EMPTY,
        first: 0,
        count: 0,
    });
    build_node(&mut nodes, 0, items, base, depth, threads);
    nodes
}

/// Fills `nodes[at]` for `items` and appends its descendants.
fn build_node(
    nodes: &mut Vec<BuildNode>,
    at: usize,
    items: &mut [Item],
    base: usize,
    depth: usize,
    threads: usize,
) {
    let mut bounds = Aabb::EMPTY;
    let mut centres = Aabb::EMPTY;
    for item in items.iter() {
        bounds.join(&item.bounds);
        centres.grow(item.centre);
    }
    let leaf = BuildNode {
        bounds,
        first: base as u32,
        count: items.len() as u32,
    };
    // Past MAX_DEPTH a leaf takes what is left, so that the traversal's stack cannot overflow.
    if items.len() <= LEAF_SIZE || depth >= MAX_DEPTH {
        nodes[at] = leaf;
        return;
    }
    let middle = sah_split(items, &centres);
    let first = nodes.len();
    nodes[at] = BuildNode {
        bounds,
        first: first as u32,
        count: 0,
    };
    let placeholder = BuildNode {
        bounds: Aabb::EMPTY,
        first: 0,
        count: 0,
    };
    nodes.push(placeholder);
    nodes.push(placeholder);
    let parallel = threads > 1 && items.len() >= PARALLEL_MIN;
    let (left, right) = items.split_at_mut(middle);
    if parallel {
        // The right half is built on a thread of its own into a list of its own, then appended
        // with its indices moved to where it lands.
        let right_threads = threads / 2;
        let ((), right_nodes) = join(
            || build_node(nodes, first, left, base, depth + 1, threads - right_threads),
            || build_subtree(right, base + middle, depth + 1, right_threads),
        );
        let offset = nodes.len() as u32 - 1;
        nodes[first + 1] = moved(right_nodes[0], offset);
        nodes.extend(right_nodes[1..].iter().map(|&n| moved(n, offset)));
    } else {
        build_node(nodes, first, left, base, depth + 1, 1);
        build_node(nodes, first + 1, right, base + middle, depth + 1, 1);
    }
}

/// A node of a subtree built on its own, with its children's index moved by `offset` (a subtree's
/// node k lands at `offset + k`, its root excepted, which takes its parent's reserved slot).
fn moved(node: BuildNode, offset: u32) -> BuildNode {
    match node.count {
        0 => BuildNode {
            first: node.first + offset,
            ..node
        },
        _ => node,
    }
}

/// The binned SAH's best split of `items` (partitioned in place), as the size of the left part.
/// Where every centre is at one point, or every centre falls on one side, the items are split in
/// halves by count (a leaf of that many would make its rays slow).
fn sah_split(items: &mut [Item], centres: &Aabb) -> usize {
    let extent = centres.max - centres.min;
    let axis = if extent.x >= extent.y && extent.x >= extent.z {
        0
    } else if extent.y >= extent.z {
        1
    } else {
        2
    };
    let (low, size) = (centres.min[axis], extent[axis]);
    // Every centre at one point (or a NaN extent): no plane separates them.
    if size.is_nan() || size <= 0.0 {
        return items.len() / 2;
    }
    let scale = BINS as f32 / size;
    let bin_of = |item: &Item| (((item.centre[axis] - low) * scale) as usize).min(BINS - 1);
    let mut bins = [(Aabb::EMPTY, 0usize); BINS];
    for item in items.iter() {
        let bin = &mut bins[bin_of(item)];
        bin.0.join(&item.bounds);
        bin.1 += 1;
    }
    // Costs of each split between bins k and k + 1, from the left and the right sweeps.
    let mut left_cost = [0.0f32; BINS];
    let (mut b, mut n) = (Aabb::EMPTY, 0);
    for k in 0..BINS - 1 {
        b.join(&bins[k].0);
        n += bins[k].1;
        left_cost[k] = b.half_area() * n as f32;
    }
    let (mut b, mut n) = (Aabb::EMPTY, 0);
    let mut best = (f32::INFINITY, 0);
    for k in (0..BINS - 1).rev() {
        b.join(&bins[k + 1].0);
        n += bins[k + 1].1;
        let cost = left_cost[k] + b.half_area() * n as f32;
        if cost < best.0 {
            best = (cost, k);
        }
    }
    let mut middle = 0;
    for i in 0..items.len() {
        if bin_of(&items[i]) <= best.1 {
            items.swap(i, middle);
            middle += 1;
        }
    }
    if middle == 0 || middle == items.len() {
        middle = items.len() / 2;
    }
    middle
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// Fails if a box's bounds, grown by [`lower`] and [`higher`], are not `f32::min`'s and
    /// `f32::max`'s where neither side is NaN (the boxes the build makes from finite corners), or
    /// if a NaN grown in replaces a bound.
    #[test]
    fn a_boxs_bounds_grow_as_min_and_max_do() {
        let values = [
            -2.5,
            -1.0,
            -0.0,
            0.0,
            1e-30,
            1.0,
            3.0,
            f32::INFINITY,
            f32::NEG_INFINITY,
        ];
        for &a in &values {
            for &b in &values {
                let (x, y) = (Vec3::new(a, b, a), Vec3::new(b, a, 1.0));
                let (low, high) = (lower(x, y), higher(x, y));
                for axis in 0..3 {
                    // ±0 compare equal; either sign bounds the same slab.
                    assert_eq!(low[axis], x[axis].min(y[axis]), "lower({x}, {y})");
                    assert_eq!(high[axis], x[axis].max(y[axis]), "higher({x}, {y})");
                }
            }
        }
        let kept = Vec3::new(1.0, 2.0, 3.0);
        let nan = Vec3::new(f32::NAN, 0.0, 5.0);
        assert_eq!(lower(kept, nan), Vec3::new(1.0, 0.0, 3.0));
        assert_eq!(higher(kept, nan), Vec3::new(1.0, 2.0, 5.0));
    }

    /// Every triangle tested: the reference the hierarchy must equal, to the bit (the nearest,
    /// of hits at one distance the lowest index).
    fn brute_force(positions: &[Vec3], ray: &Ray) -> Option<Hit> {
        let mut best: Option<Hit> = None;
        if !(ray.origin.is_finite() && ray.direction.is_finite()) {
            return None;
        }
        for (i, c) in positions.chunks_exact(3).enumerate() {
            if !c.iter().all(|p| p.is_finite()) {
                continue;
            }
            let tri = Triangle::new(c);
            if let Some((t, u, v)) = intersect(&tri, ray.origin, ray.direction) {
                if t <= ray.max_distance && best.is_none_or(|b| t < b.distance) {
                    best = Some(Hit {
                        triangle: i as u32,
                        distance: t,
                        u,
                        v,
                        data: [Vec3::ZERO; 3],
                    });
                }
            }
        }
        best
    }

    /// `rays` traced as packets against the hierarchy and one by one against every triangle:
    /// the first difference, if any. The packets are traced four lanes at a time, and eight
    /// where the CPU has AVX2 (`first_hits` takes that path there): each must find what testing
    /// every triangle finds.
    fn differences(bvh: &Bvh, positions: &[Vec3], rays: &[Ray]) -> Option<String> {
        let mut traced = Vec::new();
        let mut hits = vec![None; rays.len()];
        bvh.first_hits_of::<false>(rays, &mut hits);
        traced.push(("four lanes", hits));
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            let mut hits = vec![None; rays.len()];
            // SAFETY: the CPU has AVX2.
            unsafe { bvh.first_hits_avx2(rays, &mut hits) };
            traced.push(("eight lanes", hits));
        }
        traced.iter().find_map(|(lanes, hits)| {
            rays.iter().zip(hits).find_map(|(ray, hit)| {
                let expected = brute_force(positions, ray);
                (*hit != expected)
                    .then(|| format!("{ray:?} ({lanes}): found {hit:?}, expected {expected:?}"))
            })
        })
    }

    /// A tiny deterministic generator (xorshift), so the tests need no crate.
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> f32 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            (self.0 >> 40) as f32 / (1u64 << 24) as f32
        }
        fn vec(&mut self) -> Vec3 {
            Vec3::new(self.next(), self.next(), self.next()) * 2.0 - 1.0
        }
    }

    fn random_soup(count: usize, rng: &mut Rng) -> Vec<Vec3> {
        (0..count)
            .flat_map(|_| {
                let c = rng.vec();
                let (a, b) = (rng.vec() * 0.1, rng.vec() * 0.1);
                [c, c + a, c + b]
            })
            .collect()
    }

    /// A hard-surface model: a cube of side 2, each face a `grid` × `grid` grid of quads (two
    /// triangles each) with bumps pushed out along the face's normal (0 on the cube's edges, so
    /// the faces meet, and 0 on every fourth grid line, so that some triangles lie in the
    /// cube's own planes), turned by `turn`.
    fn bumpy_cube(grid: usize, turn: glam::Quat) -> Vec<Vec3> {
        let faces = [
            (Vec3::X, Vec3::NEG_Z, Vec3::Y),
            (Vec3::NEG_X, Vec3::Z, Vec3::Y),
            (Vec3::Y, Vec3::X, Vec3::NEG_Z),
            (Vec3::NEG_Y, Vec3::X, Vec3::Z),
            (Vec3::Z, Vec3::X, Vec3::Y),
            (Vec3::NEG_Z, Vec3::NEG_X, Vec3::Y),
        ];
        let mut positions = Vec::new();
        for (n, a, b) in faces {
            let point = |i: usize, j: usize| {
                let (s, t) = (i as f32 / grid as f32, j as f32 / grid as f32);
                let bump = |i: usize, x: f32| match i % 4 {
                    0 => 0.0,
                    _ => (std::f32::consts::PI * 3.0 * x).sin().powi(2),
                };
                let h = 0.05 * bump(i, s) * bump(j, t);
                turn * (n * (1.0 + h) + a * (2.0 * s - 1.0) + b * (2.0 * t - 1.0))
            };
            for j in 0..grid {
                for i in 0..grid {
                    let [p, q, r, w] = [
                        point(i, j),
                        point(i + 1, j),
                        point(i + 1, j + 1),
                        point(i, j + 1),
                    ];
                    positions.extend([p, q, r, p, r, w]);
                }
            }
        }
        positions
    }

    /// The cube's three turns: none (every face along an axis), about two axes (the faces on X
    /// keep a zero component), about three.
    fn turns() -> [glam::Quat; 3] {
        [
            glam::Quat::IDENTITY,
            glam::Quat::from_rotation_y(0.5) * glam::Quat::from_rotation_x(0.35),
            glam::Quat::from_rotation_z(0.26)
                * glam::Quat::from_rotation_y(0.5)
                * glam::Quat::from_rotation_x(0.35),
        ]
    }

    /// Fails if the build leaves a finite triangle out of the leaves or puts one in twice, keeps
    /// one that is not finite, copies a triangle other than the one its index names (its corners
    /// or its data), or puts it in a leaf whose box does not hold it: on one thread and on four
    /// (the items and the copies made in runs), and with triangles that are not finite (the items
    /// made again in one pass).
    #[test]
    fn every_finite_triangle_is_copied_once_into_a_leaf_that_holds_it() {
        let mut rng = Rng(0x2545_F491_4F6C_DD1D);
        let soup = random_soup(70_000, &mut rng);
        let data = |t: usize| [Vec3::splat(t as f32), Vec3::X * (t % 7) as f32, Vec3::Y];
        for (threads, poisoned) in [(1, false), (4, false), (1, true), (4, true)] {
            let mut positions = soup.clone();
            if poisoned {
                positions[3 * 12_345 + 1].y = f32::NAN;
                positions[3 * 60_000] = Vec3::INFINITY;
            }
            let bvh = Bvh::build_with(&positions, data, threads);
            let mut seen = vec![0; positions.len() / 3];
            for node in &bvh.nodes {
                for k in 0..4 {
                    let (first, count) = (node.child[k] as usize, node.count[k]);
                    if count == INNER || count == 0 {
                        continue;
                    }
                    let bounds = node.bounds(k);
                    for at in first..first + count as usize {
                        let t = bvh.order[at] as usize;
                        seen[t] += 1;
                        let corners = &positions[3 * t..3 * t + 3];
                        let expected = Triangle::new(corners);
                        let copy = &bvh.triangles[at];
                        assert_eq!(format!("{copy:?}"), format!("{expected:?}"), "triangle {t}");
                        assert_eq!(bvh.data[at], data(t), "triangle {t}'s data");
                        for p in corners {
                            let inside = p.cmpge(bounds.min).all() && p.cmple(bounds.max).all();
                            assert!(inside, "triangle {t} outside its leaf's box");
                        }
                    }
                }
            }
            for (t, &count) in seen.iter().enumerate() {
                let finite = positions[3 * t..3 * t + 3].iter().all(|p| p.is_finite());
                assert_eq!(
                    count,
                    usize::from(finite),
                    "triangle {t}, threads {threads}"
                );
            }
        }
    }

    /// Fails if the traversal skips a subtree it should enter, orders children wrongly (a farther
    /// hit wins), a parallel build's subtree lands at the wrong offset (threads 1 and 4 differ),
    /// or a packet's rays (pointing every way: each tested on its own; pointing one way: the
    /// beam) find other hits than each alone.
    #[test]
    fn the_hierarchy_finds_what_testing_every_triangle_finds() {
        let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
        // Enough triangles that the build goes parallel (PARALLEL_MIN) on 4 threads.
        let positions = random_soup(70_000, &mut rng);
        for threads in [1, 4] {
            let bvh = Bvh::build(&positions, threads);
            assert!(bvh.node_count() > 1);
            let mut rays = Vec::new();
            for _ in 0..20 {
                // Sixteen rays every way, then sixteen side by side along one direction.
                for _ in 0..16 {
                    rays.push(Ray {
                        origin: rng.vec() * 1.5,
                        direction: rng.vec().normalize(),
                        max_distance: 0.5 + rng.next(),
                    });
                }
                let (origin, direction) = (rng.vec() * 1.5, rng.vec().normalize());
                for _ in 0..16 {
                    rays.push(Ray {
                        origin: origin + rng.vec() * 0.01,
                        direction: (direction + rng.vec() * 0.01).normalize(),
                        max_distance: 1.5,
                    });
                }
            }
            assert_eq!(
                differences(&bvh, &positions, &rays),
                None,
                "threads {threads}"
            );
            let hits = rays
                .iter()
                .filter(|r| {
                    bvh.first_hit(r.origin, r.direction, r.max_distance)
                        .is_some()
                })
                .count();
            assert!(hits > 150, "only {hits} rays hit: the test is too easy");
        }
    }

    /// What a ray of a proptest case is: where it starts and which way it goes.
    #[derive(Debug, Clone)]
    struct Case {
        /// A grid point of the cube (exact, so on its edges and faces), its centre, or anywhere.
        origin: (u8, u8, u8, Vec3),
        /// Along an axis, in an axis plane, in a face's plane (grazing), or anywhere.
        direction: (u8, u8, Vec3),
        max: f32,
    }

    fn case() -> impl Strategy<Value = Case> {
        let unit =
            || (-1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0).prop_map(|(x, y, z)| Vec3::new(x, y, z));
        (
            (0u8..4, 0u8..13, 0u8..13, unit()),
            (0u8..4, 0u8..6, unit()),
            prop_oneof![Just(f32::INFINITY), 0.01f32..4.0],
        )
            .prop_map(|(origin, direction, max)| Case {
                origin,
                direction,
                max,
            })
    }

    /// The ray of `case` on the cube `grid` × `grid` turned by `turn`.
    fn ray_of(case: &Case, grid: usize, turn: glam::Quat) -> Ray {
        let axes = [
            Vec3::X,
            Vec3::Y,
            Vec3::Z,
            Vec3::NEG_X,
            Vec3::NEG_Y,
            Vec3::NEG_Z,
        ];
        let (kind, i, j, anywhere) = case.origin;
        let on_grid = |i: u8| -1.0 + 2.0 * (i as usize % (grid + 1)) as f32 / grid as f32;
        let origin = match kind {
            // On a face's grid (a vertex, or on an edge of two triangles), or just off it.
            0 => Vec3::new(on_grid(i), on_grid(j), 1.0),
            1 => Vec3::new(on_grid(i), 1.0 + 0.5 * anywhere.z.abs(), on_grid(j)),
            2 => anywhere * 0.9,
            _ => anywhere * 2.5,
        };
        let (kind, axis, anywhere) = case.direction;
        let direction = match kind {
            0 => axes[axis as usize],
            // One component 0.
            1 => (axes[axis as usize] + axes[(axis as usize + 1) % 6] * anywhere.x).normalize(),
            // In the plane of the face z = 1 (grazing it and the triangles lying in it).
            2 => Vec3::new(anywhere.x, anywhere.y, 0.0).normalize(),
            _ => anywhere.normalize(),
        };
        Ray {
            origin: turn * origin,
            direction: turn * direction,
            max_distance: case.max,
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 96, ..ProptestConfig::default() })]

        /// Fails if a ray along an axis, from inside the cube's boxes or on its grid lines, or
        /// grazing a face (lying in its plane), finds another hit through the hierarchy than
        /// testing every triangle finds: a box test that drops a box such a ray is in (its
        /// slab's NaN, its exit rounded below its entry), or a packet that enters fewer boxes
        /// than its rays would one by one. Each case is traced alone, then as a packet of sixteen
        /// rays along one direction from origins side by side (the beam), as a fan of directions
        /// spread about it (a beam where each axis keeps its sign), then with rays going every
        /// way (each ray's own test).
        #[test]
        fn rays_along_axes_from_inside_and_grazing_find_what_every_triangle_finds(
            turn in 0usize..3,
            cases in proptest::collection::vec(case(), 16),
            step in 0.0f32..0.05,
            spread in 0.0f32..0.5,
        ) {
            const GRID: usize = 12;
            let turn = turns()[turn];
            let positions = bumpy_cube(GRID, turn);
            let bvh = Bvh::build(&positions, 1);
            let alone: Vec<Ray> = cases.iter().map(|c| ray_of(c, GRID, turn)).collect();
            let first = alone[0];
            let side_by_side: Vec<Ray> = (0..16)
                .map(|k| Ray {
                    origin: first.origin + turn * Vec3::new(k as f32 * step, (k / 4) as f32 * step, 0.0),
                    ..first
                })
                .collect();
            // A fan: origins side by side, directions spread about the first's.
            let fan: Vec<Ray> = side_by_side
                .iter()
                .zip(&cases)
                .map(|(ray, case)| Ray {
                    direction: (ray.direction + case.origin.3 * spread).normalize_or(ray.direction),
                    ..*ray
                })
                .collect();
            for ray in &alone {
                prop_assert_eq!(differences(&bvh, &positions, &[*ray]), None);
            }
            prop_assert_eq!(differences(&bvh, &positions, &side_by_side), None);
            prop_assert_eq!(differences(&bvh, &positions, &fan), None);
            prop_assert_eq!(differences(&bvh, &positions, &alone), None);
        }
    }

    /// The nodes and leaves that `rays` visit.
    fn visits(bvh: &Bvh, rays: &[Ray]) -> usize {
        let mut hits = vec![None; rays.len()];
        match rays.len() {
            1..=4 => bvh.trace::<1, false>(rays, &mut hits),
            _ => bvh.trace::<{ PACKET / 4 }, false>(rays, &mut hits),
        }
    }

    /// Fails if rays along an axis visit the boxes beside them (a box wholly to one side of a
    /// ray with a direction component of 0 counted as entered: −∞ widened by ∞ · slack was NaN,
    /// which the limit replaced; every box on that side was visited, and a 1024² bake of a
    /// hard-surface cube took 66 s). A ray down onto a face of a 43,200-triangle cube visits
    /// about one path down the tree (here at most 40 nodes and leaves, a packet of sixteen at
    /// most 80), alone (each ray's own test), as a beam, and as sixteen rays with directions
    /// of both signs along X (each ray's own test).
    #[test]
    fn rays_along_an_axis_visit_only_the_boxes_they_pass() {
        let positions = bumpy_cube(60, glam::Quat::IDENTITY);
        let bvh = Bvh::build(&positions, 1);
        let down = |x: f32, y: f32, tilt: f32| Ray {
            origin: Vec3::new(x, y, 1.2),
            direction: Vec3::new(tilt, 0.0, -1.0).normalize(),
            max_distance: 0.3,
        };
        for (x, y) in [(0.013, 0.5), (-0.41, -0.77), (0.5, 0.5)] {
            let alone = visits(&bvh, &[down(x, y, 0.0)]);
            assert!(alone <= 40, "({x}, {y}) alone: {alone} visits");
            let beam: Vec<Ray> = (0..16)
                .map(|k| down(x + k as f32 * 0.002, y, 0.0))
                .collect();
            assert!(Beam::around(&beam).is_some());
            let packet = visits(&bvh, &beam);
            assert!(packet <= 80, "({x}, {y}) beam: {packet} visits");
            let both_ways: Vec<Ray> = (0..16)
                .map(|k| {
                    down(
                        x + k as f32 * 0.002,
                        y,
                        if k % 2 == 0 { 1e-3 } else { -1e-3 },
                    )
                })
                .collect();
            assert!(Beam::around(&both_ways).is_none());
            let each = visits(&bvh, &both_ways);
            assert!(each <= 80, "({x}, {y}) each ray: {each} visits");
            assert_eq!(differences(&bvh, &positions, &beam), None);
            assert_eq!(differences(&bvh, &positions, &both_ways), None);
        }
    }
    /// Fails if the test accepts hits behind the origin or beyond the limit, or refuses a triangle
    /// seen from behind (a bake's cage may be inside the high-poly model).
    #[test]
    fn a_ray_meets_a_triangle_from_either_side_within_its_limit() {
        let tri = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let bvh = Bvh::build(&tri, 1);
        let at = Vec3::new(0.25, 0.25, 0.0);
        let down = bvh.first_hit(at + Vec3::Z, -Vec3::Z, 2.0).unwrap();
        assert_eq!((down.distance, down.u, down.v), (1.0, 0.25, 0.25));
        let up = bvh.first_hit(at - Vec3::Z, Vec3::Z, 2.0).unwrap();
        assert_eq!(up.distance, 1.0);
        assert!(bvh.first_hit(at + Vec3::Z, -Vec3::Z, 0.99).is_none());
        assert!(bvh.first_hit(at + Vec3::Z, Vec3::Z, 2.0).is_none());
        assert!(bvh
            .first_hit(Vec3::new(0.75, 0.75, 1.0), -Vec3::Z, 2.0)
            .is_none());
    }

    /// Fails if a degenerate or non-finite triangle produces a hit or a non-finite distance.
    #[test]
    fn degenerate_and_non_finite_triangles_are_never_hit() {
        let positions = [
            // A line (zero area).
            Vec3::ZERO,
            Vec3::X,
            Vec3::X * 2.0,
            // A point.
            Vec3::ONE,
            Vec3::ONE,
            Vec3::ONE,
            // A NaN corner.
            Vec3::new(f32::NAN, 0.0, 0.0),
            Vec3::Y,
            Vec3::Z,
            // Infinite.
            Vec3::splat(f32::INFINITY),
            Vec3::Y,
            Vec3::Z,
        ];
        let bvh = Bvh::build(&positions, 2);
        for origin in [Vec3::new(0.5, 0.0, 1.0), Vec3::new(1.0, 1.0, 2.0)] {
            for direction in [-Vec3::Z, Vec3::X, Vec3::new(0.0, -1.0, -1.0).normalize()] {
                assert_eq!(bvh.first_hit(origin, direction, 10.0), None);
            }
        }
        assert_eq!(bvh.first_hit(Vec3::NAN, -Vec3::Z, 10.0), None);
    }

    /// Fails if a ray that runs in the plane of a box's face (an axis-aligned ray, as a flat LOW's
    /// normal gives, on a grid line of HIGH) misses the box, and so the triangles whose edges it
    /// meets: found by the `bake` fuzz target (fuzz/regressions/bake/).
    #[test]
    fn a_ray_along_a_box_face_meets_the_triangles_there() {
        // A 4 × 4 grid of unit squares in z = 0, two triangles each: the tree's boxes have their
        // faces on the grid lines.
        let positions: Vec<Vec3> = (0..16)
            .flat_map(|i| {
                let (x, y) = ((i % 4) as f32, (i / 4) as f32);
                let [a, b, c, d] = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
                    .map(|(dx, dy)| Vec3::new(x + dx, y + dy, 0.0));
                [a, b, c, a, c, d]
            })
            .collect();
        let bvh = Bvh::build(&positions, 1);
        assert!(bvh.node_count() > 1);
        for (x, y) in [
            (1.0, 0.5),
            (2.5, 2.0),
            (0.0, 0.5),
            (3.5, 4.0),
            (2.0, 3.0),
            (0.25, 0.0),
        ] {
            let ray = Ray {
                origin: Vec3::new(x, y, 1.0),
                direction: -Vec3::Z,
                max_distance: 2.0,
            };
            assert!(
                brute_force(&positions, &ray).is_some(),
                "({x}, {y}): the test is wrong"
            );
            assert_eq!(differences(&bvh, &positions, &[ray]), None, "({x}, {y})");
            // As a beam of sixteen such rays too.
            assert_eq!(
                differences(&bvh, &positions, &[ray; 16]),
                None,
                "({x}, {y})"
            );
        }
    }

    /// One ray's entry into `bounds`.
    fn enter(bounds: &Aabb, origin: Vec3, direction: Vec3, limit: f32) -> Option<f32> {
        let ray = Ray {
            origin,
            direction,
            max_distance: limit,
        };
        Lanes::<1>::new(&[ray]).enter(bounds)
    }

    /// A node whose first child is `bounds`.
    fn node_around(bounds: &Aabb) -> Node {
        let mut node = empty_node();
        for axis in 0..3 {
            node.min[axis][0] = bounds.min[axis];
            node.max[axis][0] = bounds.max[axis];
        }
        node.count[0] = 1;
        node
    }

    /// Fails if a ray with a direction component of 0 enters a box lying wholly to one side of it
    /// in that axis (its far distance −∞, widened to NaN and then replaced by the limit: the
    /// traversal then visited every box on that side, 66 s for a 1024² bake of a cube), tested
    /// on its own or as a beam.
    #[test]
    fn a_ray_along_an_axis_enters_no_box_beside_it() {
        let beside = Aabb {
            min: Vec3::new(-3.0, -1.0, -1.0),
            max: Vec3::new(-2.0, 1.0, 1.0),
        };
        let origin = Vec3::new(0.0, 0.0, 2.0);
        let beam = |direction: Vec3| {
            let ray = Ray {
                origin,
                direction,
                max_distance: 10.0,
            };
            let lanes = Lanes::<1>::new(&[ray]);
            Beam::around(&[ray])
                .expect("one ray is a beam")
                .enter(&node_around(&beside), &lanes)[0]
        };
        for direction in [-Vec3::Z, Vec3::Z, Vec3::Y, -Vec3::Y] {
            assert_eq!(enter(&beside, origin, direction, 10.0), None, "{direction}");
            assert_eq!(beam(direction), f32::INFINITY, "{direction}");
        }
        // The same box in the ray's way is entered.
        let across = Aabb {
            min: Vec3::new(-1.0, -1.0, -3.0),
            max: Vec3::new(1.0, 1.0, -2.0),
        };
        assert_eq!(enter(&across, origin, -Vec3::Z, 10.0), Some(4.0));
    }

    /// Fails if triangles whose centres coincide make the build recurse forever or lose some.
    #[test]
    fn triangles_at_one_centre_are_all_kept() {
        let positions: Vec<Vec3> = (0..100)
            .flat_map(|i| {
                let s = 1.0 + i as f32 * 0.01;
                [
                    Vec3::new(-s, -s, 0.0),
                    Vec3::new(s, -s, 0.0),
                    Vec3::new(0.0, s, 0.0),
                ]
            })
            .collect();
        let bvh = Bvh::build(&positions, 1);
        let mut order = bvh.order.clone();
        order.sort_unstable();
        assert_eq!(order, (0..100).collect::<Vec<u32>>());
    }
}
