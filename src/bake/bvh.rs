//! A bounding volume hierarchy over HIGH's triangles, for the bake's rays: binned SAH, built on every
//! core near the root, leaves of at most four triangles, nodes in one array with each
//! node's children side by side. A bake's rays are short (from the cage to a little past LOW's
//! surface) and start near each other, so a plain stack traversal that visits the nearer child first
//! is what they need; see BENCHMARKS.md ("Baking") for why this is the project's own and not a crate.

use glam::Vec3;

/// At most this many triangles in a leaf.
const LEAF_SIZE: usize = 4;
/// Centroid bins per axis for the SAH split.
const BINS: usize = 16;
/// Below this many triangles a subtree is built on the thread that reached it.
const PARALLEL_MIN: usize = 1 << 16;
/// A box within this fraction past the nearest hit so far is still searched ([`enter`]).
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

/// The first triangle a ray meets: its index in the mesh, the distance along the (unit) direction,
/// and the barycentric weights of its corners 1 and 2.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hit {
    pub triangle: u32,
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

    /// The number of nodes (for the log and the tests).
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// The nearest triangle that the ray from `origin` along the unit `direction` meets at a
    /// distance in `0..=max_distance`, from either side.
    pub fn first_hit(&self, origin: Vec3, direction: Vec3, max_distance: f32) -> Option<Hit> {
        if self.nodes.is_empty() || !(origin.is_finite() && direction.is_finite()) {
            return None;
        }
        let inverse = direction.recip();
        let mut best: Option<Hit> = None;
        let mut nearest = max_distance;
        let mut stack = [0u32; MAX_DEPTH + 2];
        let mut depth = 1;
        while depth > 0 {
            depth -= 1;
            let node = &self.nodes[stack[depth] as usize];
            if node.count > 0 {
                let start = node.first as usize;
                for k in start..start + node.count as usize {
                    if let Some((t, u, v)) = intersect(&self.triangles[k], origin, direction) {
                        // Of hits at one distance (a shared edge) the lowest triangle index
                        // wins, so that the order of the search cannot change the answer.
                        let wins = match best {
                            None => t <= nearest,
                            Some(b) => t < nearest || (t == nearest && self.order[k] < b.triangle),
                        };
                        if wins {
                            nearest = t;
                            best = Some(Hit {
                                triangle: self.order[k],
                                distance: t,
                                u,
                                v,
                            });
                        }
                    }
                }
                continue;
            }
            let (a, b) = (node.first as usize, node.first as usize + 1);
            let ta = enter(&self.nodes[a].bounds, origin, inverse, nearest);
            let tb = enter(&self.nodes[b].bounds, origin, inverse, nearest);
            // The farther child goes on the stack first, so the nearer is visited first and its
            // hit can cut the farther one off.
            match (ta, tb) {
                (Some(ta), Some(tb)) => {
                    let (near, far) = if ta <= tb { (a, b) } else { (b, a) };
                    stack[depth] = far as u32;
                    stack[depth + 1] = near as u32;
                    depth += 2;
                }
                (Some(_), None) => {
                    stack[depth] = a as u32;
                    depth += 1;
                }
                (None, Some(_)) => {
                    stack[depth] = b as u32;
                    depth += 1;
                }
                (None, None) => {}
            }
        }
        best
    }
}

/// Where the ray enters `bounds` within `0..=limit`, if it does (the slab test; a direction
/// component of 0 gives infinite reciprocals, which the min/max handle).
fn enter(bounds: &Aabb, origin: Vec3, inverse: Vec3, limit: f32) -> Option<f32> {
    let t0 = (bounds.min - origin) * inverse;
    let t1 = (bounds.max - origin) * inverse;
    // 0 × ∞ is NaN: the ray runs in the plane of one of that slab's faces (a direction component
    // of 0, the origin on the face), so all of it is in the slab, its faces counted in as the
    // triangle test counts its edges: that axis limits nothing. (Left to min/max, the NaN would
    // give way to the other face's ±∞ on both sides, and the box would be missed.)
    let along = t0.is_nan_mask() | t1.is_nan_mask();
    let near = Vec3::select(along, Vec3::NEG_INFINITY, t0.min(t1));
    let far = Vec3::select(along, Vec3::INFINITY, t0.max(t1));
    let near = near.max_element().max(0.0);
    // The limit is a hit's distance from the triangle test, and a box holding another triangle at
    // that very distance may round its entry a few ulps past it: with a little slack such a box is
    // still searched, so that which of two triangles at one distance was met first cannot change
    // the answer.
    // The box's own exit is widened as much (Ize's robust slab test widens it by 2γ₃): a ray that
    // grazes a triangle's edge on the box's face must not be rounded out of the box.
    // A box wholly to one side of a ray with a direction component of 0 has far = −∞ there: it is
    // passed as it is (−∞ + ∞·slack would be NaN, which `min` replaces by the limit, and every
    // box on that side would be entered).
    let far = far.min_element();
    let far = if far.is_finite() {
        far + far.abs() * LIMIT_SLACK
    } else {
        far
    };
    let far = far.min(limit + limit * LIMIT_SLACK);
    (near <= far).then_some(near)
}

/// Möller and Trumbore's test, from either side: the distance and the barycentrics of corners 1
/// and 2, or `None` for a miss, a ray in the triangle's plane or a degenerate triangle.
#[inline]
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
            assert_eq!(
                enter(&beside, origin, direction.recip(), 10.0),
                None,
                "{direction}"
            );
        }
        // The same box in the ray's way is entered.
        let across = Aabb {
            min: Vec3::new(-1.0, -1.0, -3.0),
            max: Vec3::new(1.0, 1.0, -2.0),
        };
        assert_eq!(enter(&across, origin, (-Vec3::Z).recip(), 10.0), Some(4.0));
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
