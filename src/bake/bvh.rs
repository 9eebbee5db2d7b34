//! A bounding volume hierarchy over HIGH's triangles, for the bake's rays: binned SAH, built on every
//! core near the root, leaves of at most four triangles, nodes in one array with each
//! node's children side by side. A bake's rays are short (from the cage to a little past LOW's
//! surface) and start near each other, so a plain stack traversal that visits the nearer child first
//! is what they need; see BENCHMARKS.md ("Baking") for why this is the project's own and not a crate.

use glam::{BVec3, Vec3, Vec4};

/// At most this many triangles in a leaf.
const LEAF_SIZE: usize = 4;
/// Centroid bins per axis for the SAH split.
const BINS: usize = 16;
/// Below this many triangles a subtree is built on the thread that reached it.
const PARALLEL_MIN: usize = 1 << 16;
/// A box within this fraction past the nearest hit so far is still searched ([`Lanes::enter`]).
const LIMIT_SLACK: f32 = 1e-5;
/// The deepest a node may be: the traversal's stack holds one more than this.
const MAX_DEPTH: usize = 120;

/// An axis-aligned box.
#[derive(Debug, Clone, Copy, PartialEq)]
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
        self.min = self.min.min(p);
        self.max = self.max.max(p);
    }

    fn join(&mut self, other: &Aabb) {
        self.min = self.min.min(other.min);
        self.max = self.max.max(other.max);
    }

    /// Half the surface area (the SAH's weights only compare).
    fn half_area(&self) -> f32 {
        let d = (self.max - self.min).max(Vec3::ZERO);
        d.x * d.y + d.y * d.z + d.z * d.x
    }
}

/// A node: an inner node's children are `first` and `first + 1`; a leaf holds `count` triangles
/// from `first` in [`Bvh::order`].
#[derive(Debug, Clone, Copy)]
struct Node {
    bounds: Aabb,
    first: u32,
    /// 0 for an inner node.
    count: u32,
}

/// A triangle as the ray test wants it: a corner and the two edges from it.
#[derive(Debug, Clone, Copy)]
struct Triangle {
    p0: Vec3,
    e1: Vec3,
    e2: Vec3,
}

/// The first triangle a ray meets: its index in the mesh and in the hierarchy's own order
/// ([`Bvh::order`]), the distance along the (unit) direction, and the barycentric weights of its
/// corners 1 and 2.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hit {
    pub triangle: u32,
    pub slot: u32,
    pub distance: f32,
    pub u: f32,
    pub v: f32,
}

/// The hierarchy, with the triangles copied in its leaves' order.
#[derive(Debug)]
pub struct Bvh {
    nodes: Vec<Node>,
    triangles: Vec<Triangle>,
    /// The mesh's index of each of `triangles`.
    order: Vec<u32>,
}

/// What the build sorts: a triangle's box, centre and index.
#[derive(Debug, Clone, Copy)]
struct Item {
    bounds: Aabb,
    centre: Vec3,
    index: u32,
}

impl Bvh {
    /// The hierarchy over `positions` (three per triangle). Triangles with a corner that is not
    /// finite are left out: no ray can meet them, and their boxes would poison their neighbours'.
    pub fn build(positions: &[Vec3], threads: usize) -> Bvh {
        let mut items: Vec<Item> = positions
            .chunks_exact(3)
            .enumerate()
            .filter(|(_, c)| c.iter().all(|p| p.is_finite()))
            .map(|(i, c)| {
                let mut bounds = Aabb::EMPTY;
                c.iter().for_each(|&p| bounds.grow(p));
                Item {
                    bounds,
                    centre: (bounds.min + bounds.max) * 0.5,
                    index: i as u32,
                }
            })
            .collect();
        let mut nodes = if items.is_empty() {
            Vec::new()
        } else {
            build_subtree(&mut items, 0, 0, threads.max(1))
        };
        nodes.shrink_to_fit();
        let order: Vec<u32> = items.iter().map(|item| item.index).collect();
        let triangles = order
            .iter()
            .map(|&i| {
                let c = &positions[3 * i as usize..3 * i as usize + 3];
                Triangle {
                    p0: c[0],
                    e1: c[1] - c[0],
                    e2: c[2] - c[0],
                }
            })
            .collect();
        Bvh {
            nodes,
            triangles,
            order,
        }
    }

    /// The mesh's index of each triangle in the hierarchy's order (the leaves' order): data a hit
    /// reads laid out in this order lies beside what its search read last.
    pub fn order(&self) -> &[u32] {
        &self.order
    }

    /// The number of nodes (for the log and the tests).
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
        for (rays, hits) in rays.chunks(PACKET).zip(hits.chunks_mut(PACKET)) {
            match rays.len() {
                1..=4 => self.trace::<1>(rays, hits),
                _ => self.trace::<{ PACKET / 4 }>(rays, hits),
            }
        }
    }

    /// The first hits of up to `4 × G` rays walking the hierarchy together: a box is entered if
    /// any ray enters it (each against its own nearest hit so far), a leaf's triangles are
    /// tested for every ray. A box a ray would not have entered holds no nearer triangle for it,
    /// and its tests are its own: its answer is the one it finds alone.
    fn trace<const G: usize>(&self, rays: &[Ray], hits: &mut [Option<Hit>]) {
        let mut lanes = Lanes::<G>::new(rays);
        if !self.nodes.is_empty() {
            match Beam::around(rays) {
                Some(beam) => self.walk(&mut lanes, &beam),
                None => self.walk(&mut lanes, &EachRay),
            }
        }
        lanes.hits(hits);
    }

    /// The walk down the hierarchy, `test` telling where the rays enter a box (if they do).
    #[inline(always)]
    fn walk<const G: usize>(&self, lanes: &mut Lanes<G>, test: &impl BoxTest) {
        // Each entry: a node, and the nearest distance at which a ray entered it (it is skipped
        // if every ray has found a nearer hit since).
        let mut stack = [(0u32, 0f32); MAX_DEPTH + 2];
        let mut depth = 1;
        while depth > 0 {
            depth -= 1;
            let (index, entry) = stack[depth];
            if entry > lanes.farthest_limit() {
                continue;
            }
            let node = &self.nodes[index as usize];
            if node.count > 0 {
                let start = node.first as usize;
                for k in start..start + node.count as usize {
                    lanes.intersect(&self.triangles[k], self.order[k], k as u32);
                }
                continue;
            }
            let (a, b) = (node.first, node.first + 1);
            let ta = test.enter(&self.nodes[a as usize].bounds, lanes);
            let tb = test.enter(&self.nodes[b as usize].bounds, lanes);
            // The farther child goes on the stack first, so the nearer is visited first and its
            // hits can cut the farther one off.
            match (ta, tb) {
                (Some(ta), Some(tb)) => {
                    let (near, far) = if ta <= tb {
                        ((a, ta), (b, tb))
                    } else {
                        ((b, tb), (a, ta))
                    };
                    stack[depth] = far;
                    stack[depth + 1] = near;
                    depth += 2;
                }
                (Some(ta), None) => {
                    stack[depth] = (a, ta);
                    depth += 1;
                }
                (None, Some(tb)) => {
                    stack[depth] = (b, tb);
                    depth += 1;
                }
                (None, None) => {}
            }
        }
    }
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

/// Rays traced together by [`Bvh::first_hits`]: a texel's 4 × 4, or 4 × 4 texels' one each.
pub const PACKET: usize = 16;

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
    /// The mesh index of the triangle met at `nearest` (`u32::MAX`: none yet), and its slot.
    triangle: [[u32; 4]; G],
    slot: [[u32; 4]; G],
    u: [[f32; 4]; G],
    v: [[f32; 4]; G],
}

impl<const G: usize> Lanes<G> {
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
            entry = entry.min(Vec4::select(near.cmple(far), near, Vec4::INFINITY));
        }
        let entry = entry.min_element();
        (entry < f32::INFINITY).then_some(entry)
    }

    /// [`intersect`] on every lane, keeping each lane's nearest hit (of hits at one distance,
    /// the lowest mesh index, so that the order of the search cannot change the answer). The
    /// same operations in the same order as [`intersect`]'s (glam's `cross` and `dot` written
    /// out), so that each lane's distance and barycentrics are its, to the bit.
    #[inline(always)]
    fn intersect(&mut self, tri: &Triangle, index: u32, slot: u32) {
        let [ox, oy, oz] = &self.origin;
        let [dx, dy, dz] = &self.direction;
        let [p0x, p0y, p0z] = tri.p0.to_array().map(Vec4::splat);
        let [e1x, e1y, e1z] = tri.e1.to_array().map(Vec4::splat);
        let [e2x, e2y, e2z] = tri.e2.to_array().map(Vec4::splat);
        for g in 0..G {
            // p = direction × e2
            let px = dy[g] * e2z - e2y * dz[g];
            let py = dz[g] * e2x - e2z * dx[g];
            let pz = dx[g] * e2y - e2x * dy[g];
            let det = (e1x * px) + (e1y * py) + (e1z * pz);
            let inv = Vec4::ONE / det;
            // s = origin − p0, q = s × e1
            let (sx, sy, sz) = (ox[g] - p0x, oy[g] - p0y, oz[g] - p0z);
            let u = ((sx * px) + (sy * py) + (sz * pz)) * inv;
            let qx = sy * e1z - e1y * sz;
            let qy = sz * e1x - e1z * sx;
            let qz = sx * e1y - e1x * sy;
            let v = ((dx[g] * qx) + (dy[g] * qy) + (dz[g] * qz)) * inv;
            let t = ((e2x * qx) + (e2y * qy) + (e2z * qz)) * inv;
            let hit = det.abs().cmpgt(Vec4::splat(f32::MIN_POSITIVE))
                & det.abs().cmplt(Vec4::INFINITY)
                & u.cmpge(Vec4::ZERO)
                & u.cmple(Vec4::ONE)
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
                let (t, nearest) = (t[k], self.nearest[g][k]);
                if t < nearest || index < self.triangle[g][k] {
                    self.nearest[g][k] = t;
                    self.reach[g][k] = widened_limit(t);
                    self.triangle[g][k] = index;
                    self.slot[g][k] = slot;
                    self.u[g][k] = u[k];
                    self.v[g][k] = v[k];
                }
            }
        }
    }

    /// The first `count` lanes' hits.
    fn hits(&self, hits: &mut [Option<Hit>]) {
        for (l, hit) in hits.iter_mut().enumerate() {
            let (g, k) = (l / 4, l % 4);
            *hit = (self.triangle[g][k] != u32::MAX).then(|| Hit {
                triangle: self.triangle[g][k],
                slot: self.slot[g][k],
                distance: self.nearest[g][k],
                u: self.u[g][k],
                v: self.v[g][k],
            });
        }
    }
}

/// Where a packet's rays enter a box, if any does: no later than any of them.
trait BoxTest {
    fn enter<const G: usize>(&self, bounds: &Aabb, lanes: &Lanes<G>) -> Option<f32>;
}

/// Each ray tested on its own ([`Lanes::enter`]).
struct EachRay;

impl BoxTest for EachRay {
    #[inline(always)]
    fn enter<const G: usize>(&self, bounds: &Aabb, lanes: &Lanes<G>) -> Option<f32> {
        lanes.enter(bounds)
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
    /// The beam of `rays` (the finite ones: the others are idle), if each axis is still or of
    /// one sign for all of them; `None` where some axis is not (the rays are then tested one
    /// by one), or no ray is finite.
    fn around(rays: &[Ray]) -> Option<Beam> {
        let mut low = Vec3::INFINITY;
        let mut high = Vec3::NEG_INFINITY;
        let mut inverse_low = Vec3::INFINITY;
        let mut inverse_high = Vec3::NEG_INFINITY;
        let (mut still, mut positive, mut negative) = (BVec3::FALSE, BVec3::FALSE, BVec3::FALSE);
        let mut any = false;
        for ray in rays {
            if !(ray.origin.is_finite() && ray.direction.is_finite()) {
                continue;
            }
            any = true;
            let inverse = ray.direction.recip();
            low = low.min(ray.origin);
            high = high.max(ray.origin);
            inverse_low = inverse_low.min(inverse);
            inverse_high = inverse_high.max(inverse);
            still |= ray.direction.cmpeq(Vec3::ZERO);
            positive |= ray.direction.cmpgt(Vec3::ZERO);
            negative |= ray.direction.cmplt(Vec3::ZERO);
        }
        if !any {
            return None;
        }
        let mut axes = [BeamAxis::Still {
            low: 0.0,
            high: 0.0,
        }; 3];
        for (axis, slot) in axes.iter_mut().enumerate() {
            let finite = inverse_low[axis].is_finite() && inverse_high[axis].is_finite();
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
}

impl BoxTest for Beam {
    /// Where the beam may enter `bounds` within the lanes' reach: no later than any of its rays
    /// does, and `None` only if none of them does. Each bound is the extreme of the products
    /// (face − origin) × reciprocal over the ranges, at their corners; both ends are widened
    /// by the slack of [`Lanes::enter`].
    #[inline(always)]
    fn enter<const G: usize>(&self, bounds: &Aabb, lanes: &Lanes<G>) -> Option<f32> {
        let mut near = 0f32;
        let mut far = f32::INFINITY;
        for (axis, beam) in self.axes.iter().enumerate() {
            let (min, max) = (bounds.min[axis], bounds.max[axis]);
            match *beam {
                BeamAxis::Still { low, high } => {
                    if max < low || min > high {
                        return None;
                    }
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
                        (min - high, max - low)
                    } else {
                        (max - low, min - high)
                    };
                    let entry = to_entry
                        * if to_entry >= 0.0 {
                            inverse_low
                        } else {
                            inverse_high
                        };
                    let exit = to_exit
                        * if to_exit >= 0.0 {
                            inverse_high
                        } else {
                            inverse_low
                        };
                    near = if entry > near { entry } else { near };
                    far = if exit < far { exit } else { far };
                }
            }
        }
        let near = near - near.abs() * LIMIT_SLACK;
        let far = far.max(-f32::MAX);
        let far = (far + far.abs() * LIMIT_SLACK).min(lanes.farthest_limit());
        (near <= far).then_some(near.max(0.0))
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
    if det.abs() <= f32::MIN_POSITIVE || !det.is_finite() {
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

/// The subtree over `items` (reordered into its leaves' order), its root first; child and leaf
/// indices count from its root, its leaves' from `base` items; `depth` is its root's.
fn build_subtree(items: &mut [Item], base: usize, depth: usize, threads: usize) -> Vec<Node> {
    let mut nodes = Vec::with_capacity(2 * items.len() / LEAF_SIZE + 1);
    nodes.push(Node {
        bounds: Aabb::EMPTY,
        first: 0,
        count: 0,
    });
    build_node(&mut nodes, 0, items, base, depth, threads);
    nodes
}

/// Fills `nodes[at]` for `items` and appends its descendants.
fn build_node(
    nodes: &mut Vec<Node>,
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
    let leaf = Node {
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
    nodes[at] = Node {
        bounds,
        first: first as u32,
        count: 0,
    };
    let placeholder = Node {
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
        let right_nodes = std::thread::scope(|scope| {
            let job = scope.spawn(|| build_subtree(right, base + middle, depth + 1, right_threads));
            build_node(nodes, first, left, base, depth + 1, threads - right_threads);
            job.join()
                .unwrap_or_else(|panic| std::panic::resume_unwind(panic))
        });
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
fn moved(node: Node, offset: u32) -> Node {
    match node.count {
        0 => Node {
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

    /// Every triangle tested: the reference the hierarchy must equal.
    fn brute_force(positions: &[Vec3], origin: Vec3, direction: Vec3, max: f32) -> Option<Hit> {
        let mut best: Option<Hit> = None;
        for (i, c) in positions.chunks_exact(3).enumerate() {
            let tri = Triangle {
                p0: c[0],
                e1: c[1] - c[0],
                e2: c[2] - c[0],
            };
            if let Some((t, u, v)) = intersect(&tri, origin, direction) {
                if t <= max && best.is_none_or(|b| t < b.distance) {
                    best = Some(Hit {
                        triangle: i as u32,
                        slot: u32::MAX,
                        distance: t,
                        u,
                        v,
                    });
                }
            }
        }
        best
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

    /// Fails if the traversal skips a subtree it should enter, orders children wrongly (a farther
    /// hit wins), or a parallel build's subtree lands at the wrong offset (threads 1 and 4
    /// differ).
    #[test]
    fn the_hierarchy_finds_what_testing_every_triangle_finds() {
        let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
        // Enough triangles that the build goes parallel (PARALLEL_MIN) on 4 threads.
        let positions = random_soup(70_000, &mut rng);
        for threads in [1, 4] {
            let bvh = Bvh::build(&positions, threads);
            assert!(bvh.node_count() > 1);
            let mut hits = 0;
            for _ in 0..300 {
                let origin = rng.vec() * 1.5;
                let direction = rng.vec().normalize();
                let max = 0.5 + rng.next();
                let expected = brute_force(&positions, origin, direction, max);
                let found = bvh.first_hit(origin, direction, max);
                assert_eq!(
                    found.map(|h| h.distance),
                    expected.map(|h| h.distance),
                    "threads {threads}, ray from {origin} along {direction}"
                );
                hits += usize::from(found.is_some());
            }
            assert!(hits > 100, "only {hits} rays hit: the test is too easy");
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
            let origin = Vec3::new(x, y, 1.0);
            let expected = brute_force(&positions, origin, -Vec3::Z, 2.0);
            assert!(expected.is_some(), "({x}, {y}): the test is wrong");
            let found = bvh.first_hit(origin, -Vec3::Z, 2.0);
            assert_eq!(
                found.map(|h| h.distance),
                expected.map(|h| h.distance),
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

    /// Fails if a ray with a direction component of 0 enters a box lying wholly to one side of it
    /// in that axis (its far distance −∞, widened to NaN and then replaced by the limit: the
    /// traversal then visited every box on that side, 66 s for a 1024² bake of a cube).
    #[test]
    fn a_ray_along_an_axis_enters_no_box_beside_it() {
        let beside = Aabb {
            min: Vec3::new(-3.0, -1.0, -1.0),
            max: Vec3::new(-2.0, 1.0, 1.0),
        };
        let origin = Vec3::new(0.0, 0.0, 2.0);
        for direction in [-Vec3::Z, Vec3::Z, Vec3::Y, -Vec3::Y] {
            assert_eq!(enter(&beside, origin, direction, 10.0), None, "{direction}");
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
