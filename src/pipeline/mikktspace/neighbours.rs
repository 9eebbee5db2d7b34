//! Step 4, the neighbours across shared edges, paired as the reference's sorted edge list pairs
//! them (its quicksort redone only where its order shows).

use super::numbering::Numbering;
use super::NONE;
use crate::common::objloader::TriangleSoup;

/// Per good triangle and edge (corner i to i + 1), the triangle across it, or [`NONE`].
///
/// The reference sorts the edges by their lower vertex number, then by the higher, then by
/// triangle, and pairs each unpaired edge with the first later unpaired one going the other way
/// among the equal edges that follow it. Its sorts skip the last run of each pass: the edges of
/// the highest lower vertex stay in the order its quicksort left them ([`last_run`]), pairing only
/// with equal edges next to them. All the others are bucketed here by their lower vertex, then
/// by the other (a stable sort keeps the triangle order).
pub(super) fn neighbours(corners: &[[u32; 3]], mut numbers: Numbers) -> Vec<u32> {
    let edge_count = corners.len() * 3;
    let mut across = vec![NONE; edge_count];
    let last = last_run(corners, &mut numbers);
    let mut in_last = vec![false; edge_count];
    for &edge in &last {
        in_last[edge as usize] = true;
    }
    pair_last_run(corners, &last, &mut numbers, &mut across);
    let vertex_count = numbers.numbering.kept.len();
    pair_by_buckets(corners, vertex_count, &in_last, &mut across);
    across
}

/// The vertices edge `edge` (3 t + e) goes between: triangle t's corner e, then corner e + 1.
fn ends(corners: &[[u32; 3]], edge: u32) -> (u32, u32) {
    let (t, e) = ((edge / 3) as usize, (edge % 3) as usize);
    (corners[t][e], corners[t][(e + 1) % 3])
}

/// Pairs each unpaired edge of `run` with the first later unpaired one going the other way.
fn pair(corners: &[[u32; 3]], run: &[u32], across: &mut [u32]) {
    for (i, &a) in run.iter().enumerate() {
        if across[a as usize] != NONE {
            continue;
        }
        let (a0, a1) = ends(corners, a);
        let partner = run[i + 1..]
            .iter()
            .find(|&&b| across[b as usize] == NONE && ends(corners, b) == (a1, a0));
        if let Some(&b) = partner {
            across[a as usize] = b / 3;
            across[b as usize] = a / 3;
        }
    }
}

/// Pairs the last run's edges (`last`, in the reference's order): stretches of equal edges as they
/// lie, each but the final one by triangle.
fn pair_last_run(corners: &[[u32; 3]], last: &[u32], numbers: &mut Numbers, across: &mut [u32]) {
    let upper: Vec<u32> = last
        .iter()
        .map(|&edge| upper_number(corners, numbers, edge))
        .collect();
    let mut stretches = Vec::new();
    let mut from = 0;
    for k in 1..=last.len() {
        if k == last.len() || upper[k] != upper[from] {
            stretches.push(&last[from..k]);
            from = k;
        }
    }
    let final_stretch = stretches.pop();
    for stretch in stretches {
        let mut sorted = stretch.to_vec();
        sorted.sort_unstable();
        pair(corners, &sorted, across);
    }
    if let Some(stretch) = final_stretch {
        pair(corners, stretch, across);
    }
}

/// Pairs the edges outside the last run: bucketed by their lower vertex, each bucket sorted by the
/// other vertex (stably: in triangle order), each run of equal edges paired.
fn pair_by_buckets(
    corners: &[[u32; 3]],
    vertex_count: usize,
    in_last: &[bool],
    across: &mut [u32],
) {
    let low = |edge: u32| {
        let (a, b) = ends(corners, edge);
        a.min(b)
    };
    let high = |edge: u32| {
        let (a, b) = ends(corners, edge);
        a.max(b)
    };
    let edge_count = corners.len() * 3;
    let mut start = vec![0u32; vertex_count + 1];
    for edge in 0..edge_count as u32 {
        start[low(edge) as usize + 1] += 1;
    }
    for v in 0..vertex_count {
        start[v + 1] += start[v];
    }
    let mut fill = start.clone();
    let mut edges = vec![0u32; edge_count];
    for edge in 0..edge_count as u32 {
        let slot = &mut fill[low(edge) as usize];
        edges[*slot as usize] = edge;
        *slot += 1;
    }
    for v in 0..vertex_count {
        let bucket = &mut edges[start[v] as usize..start[v + 1] as usize];
        if bucket.len() < 2 {
            continue;
        }
        bucket.sort_by_key(|&edge| high(edge));
        for run in bucket.chunk_by(|&a, &b| high(a) == high(b)) {
            if !in_last[run[0] as usize] {
                pair(corners, run, across);
            }
        }
    }
}

/// [`Numbering`] with what it reads.
pub(super) struct Numbers<'a> {
    pub(super) numbering: Numbering,
    pub(super) soup: &'a TriangleSoup,
    pub(super) of_corner: &'a [u32],
}

impl Numbers<'_> {
    /// Vertex `class`'s number.
    fn number(&mut self, class: u32) -> u32 {
        self.numbering.number(self.soup, self.of_corner, class)
    }
}

/// The lower of the numbers of edge `edge`'s vertices, exactly.
fn lower_number(corners: &[[u32; 3]], numbers: &mut Numbers, edge: u32) -> u32 {
    let (a, b) = ends(corners, edge);
    numbers.number(a).min(numbers.number(b))
}

/// The higher of the numbers of edge `edge`'s vertices.
fn upper_number(corners: &[[u32; 3]], numbers: &mut Numbers, edge: u32) -> u32 {
    let (a, b) = ends(corners, edge);
    numbers.number(a).max(numbers.number(b))
}

/// The edges whose lower vertex number is the highest of all, in the order the reference's
/// quicksort on that number leaves them (in edge order where no order could pair them otherwise).
///
/// The quicksort is the reference's (its pivot from a seeded rotation), run only on the parts
/// that hold those edges: a part whose pivot is below the highest number leaves them all to its
/// right. An edge's number is kept as bounds until a comparison needs it exactly.
pub(super) fn last_run(corners: &[[u32; 3]], numbers: &mut Numbers) -> Vec<u32> {
    let bounds = std::mem::take(&mut numbers.numbering.bounds);
    let bound = |edge: u32| {
        let (a, b) = ends(corners, edge);
        let ((la, ha), (lb, hb)) = (bounds[a as usize], bounds[b as usize]);
        (la.min(lb), ha.min(hb))
    };
    let edge_count = corners.len() as u32 * 3;
    let Some(floor) = (0..edge_count).map(|e| bound(e).0).max() else {
        return Vec::new();
    };
    let candidates: Vec<(u32, u32)> = (0..edge_count)
        .filter(|&e| bound(e).1 >= floor)
        .map(|e| (e, lower_number(corners, numbers, e)))
        .collect();
    let top = candidates.iter().map(|&(_, n)| n).max().unwrap_or(0);
    // Their order only decides which of them are paired when some two join the same two vertices
    // (a stretch) beside a third: with at most two, or no two alike, every order pairs them the
    // same, and the quicksort (most of a first frame's neighbour step) need not be run.
    let last: Vec<u32> = candidates
        .iter()
        .filter(|&&(_, n)| n == top)
        .map(|&(e, _)| e)
        .collect();
    let count = last.len();
    if count <= 2 || !some_two_alike(corners, numbers, &last) {
        return last;
    }
    let mut keys: Vec<(u32, u32, u32)> = (0..edge_count)
        .map(|e| {
            let (lo, hi) = bound(e);
            (lo, hi, e)
        })
        .collect();
    quicksort_towards(&mut keys, top, |e| lower_number(corners, numbers, e));
    keys[keys.len() - count..]
        .iter()
        .map(|&(_, _, e)| e)
        .collect()
}

/// Whether some two of the last run's edges join the same two vertices.
fn some_two_alike(corners: &[[u32; 3]], numbers: &mut Numbers, last: &[u32]) -> bool {
    // All share their lower vertex (numbered `top`): two alike share the upper one too.
    let mut uppers: Vec<u32> = last
        .iter()
        .map(|&e| upper_number(corners, numbers, e))
        .collect();
    uppers.sort_unstable();
    uppers.dedup();
    uppers.len() != last.len()
}

/// The reference's quicksort of `keys` (an edge's number's lower and upper bound, the edge) by
/// the edges' numbers, run only on the parts that can hold the number `top`; `exact` gives an
/// edge's number.
fn quicksort_towards(keys: &mut [(u32, u32, u32)], top: u32, mut exact: impl FnMut(u32) -> u32) {
    // The key of entry `i`, exactly (and from then on without bounds).
    let mut resolve = |keys: &mut [(u32, u32, u32)], i: isize| {
        let entry = &mut keys[i as usize];
        if entry.0 != entry.1 {
            let n = exact(entry.2);
            *entry = (n, n, entry.2);
        }
        entry.0
    };
    let mut parts = vec![(0isize, keys.len() as isize - 1, 39_871_946u32)];
    while let Some((left, right, seed)) = parts.pop() {
        let size = right - left + 1;
        if size < 2 {
            continue;
        }
        if size == 2 {
            if resolve(keys, left) > resolve(keys, right) {
                keys.swap(left as usize, right as usize);
            }
            continue;
        }
        let seed = next_seed(seed);
        let pivot = resolve(keys, left + (seed % size as u32) as isize);
        let (il, ir) = partition(keys, left, right, pivot, &mut resolve);
        if left < ir && pivot == top {
            parts.push((left, ir, seed));
        }
        if il < right {
            parts.push((il, right, seed));
        }
    }
}

/// The reference's next pivot seed: `seed` plus itself rotated by its low five bits, plus 3.
fn next_seed(seed: u32) -> u32 {
    let turn = seed & 31;
    seed.wrapping_add(seed.rotate_left(turn) | seed.rotate_right(32u32.wrapping_sub(turn)))
        .wrapping_add(3)
}

/// The reference's partition of `keys[left..=right]` around `pivot`: where the two sides' scans
/// stopped (the left part ends at the second, the right one starts at the first).
fn partition(
    keys: &mut [(u32, u32, u32)],
    left: isize,
    right: isize,
    pivot: u32,
    resolve: &mut impl FnMut(&mut [(u32, u32, u32)], isize) -> u32,
) -> (isize, isize) {
    let (mut il, mut ir) = (left, right);
    loop {
        // Below the pivot: certain from the bounds, else worked out.
        while keys[il as usize].1 < pivot
            || keys[il as usize].0 < pivot && resolve(keys, il) < pivot
        {
            il += 1;
        }
        while keys[ir as usize].0 > pivot
            || keys[ir as usize].1 > pivot && resolve(keys, ir) > pivot
        {
            ir -= 1;
        }
        if il <= ir {
            keys.swap(il as usize, ir as usize);
            il += 1;
            ir -= 1;
        }
        if il > ir {
            break;
        }
    }
    (il, ir)
}
