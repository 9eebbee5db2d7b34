//! LOW's UV layout as texels: which triangle covers each sample position, with its barycentrics, in
//! bands of rows baked on every core; and the margin around the islands.

use std::sync::Mutex;

use glam::{DVec2, Vec3};

use super::{BakeStats, BakedMap, Sample, Skew, SKEW_LIMIT};
use crate::common::objloader::TriangleSoup;
use crate::pipeline::{in_runs, on_threads};

/// Rows of samples baked together (rows of texels: this over K, at least a tile's): small enough
/// that the bands share the cores evenly, and that a band's owners (17 bytes a sample, written by
/// the raster, then read back by the tiles) stay in a core's cache: 8 rows of texels at 4 × 4 were
/// 4.5 MB.
const BAND_SAMPLE_ROWS: usize = 8;
/// Samples a side of the tiles traced together: 2 × 2 texels' 4 × 4 rays, or 8 × 8 texels' one
/// ray each (a packet, [`super::bvh::PACKET`]). A texel's 4 × 4 alone made a packet of 16 rays
/// within one texel, whose walk down the hierarchy cost as much as one of sixteen texels'.
const TILE_SAMPLES: usize = 8;
/// No triangle owns a sample.
const NONE: u32 = u32::MAX;

/// What a texel of the baked map holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TexelState {
    /// Nothing of LOW: the flat normal.
    Empty,
    /// A sample of LOW's surface.
    Covered,
    /// Filled by the margin from its neighbours.
    Margin,
}

/// A triangle in sample coordinates (x right, y down the picture, one unit per sample), its
/// corners ordered so that its area is positive.
#[derive(Debug, Clone, Copy)]
struct PixelTriangle {
    corners: [DVec2; 3],
    /// Whether `corners` are the soup's corners 0, 2, 1 (else 0, 1, 2).
    swapped: bool,
    area: f64,
}

/// LOW's triangles laid on a `width × height` map sampled `samples × samples` times per texel.
#[derive(Debug)]
pub struct UvLayout {
    width: usize,
    height: usize,
    samples: usize,
    triangles: Vec<Option<PixelTriangle>>,
    /// Rows of texels a band: a row of tiles ([`BAND_SAMPLE_ROWS`] over K).
    band_rows: usize,
    /// Each band's triangles, in the soup's order.
    bands: Vec<Vec<u32>>,
}

impl UvLayout {
    /// The layout of `soup`'s UVs (V up: V = 1 is the picture's top row, as image files store it).
    pub fn new(soup: &TriangleSoup, width: u32, height: u32, samples: u32) -> UvLayout {
        let (width, height, samples) = (width as usize, height as usize, samples.max(1) as usize);
        let scale = DVec2::new((width * samples) as f64, (height * samples) as f64);
        let band_rows = (BAND_SAMPLE_ROWS / samples).max(1);
        let band_count = height.div_ceil(band_rows);
        let mut bands = vec![Vec::new(); band_count];
        let triangles: Vec<Option<PixelTriangle>> = soup
            .uvs
            .chunks_exact(3)
            .map(|uv| {
                let at = |k: usize| DVec2::new(uv[k].x as f64, 1.0 - uv[k].y as f64) * scale;
                let (a, b, c) = (at(0), at(1), at(2));
                let area = (b - a).perp_dot(c - a);
                // Zero area (or NaN UVs): the triangle covers nothing.
                if area == 0.0 || !area.is_finite() {
                    return None;
                }
                Some(if area > 0.0 {
                    PixelTriangle {
                        corners: [a, b, c],
                        swapped: false,
                        area,
                    }
                } else {
                    PixelTriangle {
                        corners: [a, c, b],
                        swapped: true,
                        area: -area,
                    }
                })
            })
            .collect();
        for (t, tri) in triangles.iter().enumerate() {
            let Some(tri) = tri else { continue };
            let Some((_, rows)) = sample_box(tri, width * samples, height * samples) else {
                continue;
            };
            let first = rows.start / samples / band_rows;
            let last = (rows.end - 1) / samples / band_rows;
            for band in &mut bands[first..=last] {
                band.push(t as u32);
            }
        }
        UvLayout {
            width,
            height,
            samples,
            triangles,
            band_rows,
            bands,
        }
    }

    /// LOW's triangles with no area in UV space.
    pub fn flat_triangles(&self) -> usize {
        self.triangles.iter().filter(|t| t.is_none()).count()
    }

    /// Every covered sample through `sample` (a batch of triangle indices and barycentrics of
    /// their corners in, a [`Sample`] for each out), on `threads` threads, averaged per texel. Where two triangles claim a sample, the later one in
    /// the soup keeps it.
    pub(crate) fn bake(
        &self,
        threads: usize,
        sample: impl Fn(&[(usize, [f32; 3])], &mut Vec<Sample>) + Sync,
    ) -> BakedMap {
        let texels = self.width * self.height;
        let mut normals = vec![Vec3::Z; texels];
        let mut states = vec![TexelState::Empty; texels];
        let work: Vec<_> = normals
            .chunks_mut(self.band_rows * self.width)
            .zip(states.chunks_mut(self.band_rows * self.width))
            .enumerate()
            .collect();
        let work = Mutex::new(work.into_iter());
        let results = Mutex::new((BakeStats::default(), Vec::<f32>::new()));
        let sample = &sample;
        // Each worker takes the next band until none is left: the first on this thread. Its
        // per-sample buffers are its own, kept from band to band.
        on_threads(vec![(); threads.max(1)], |()| {
            let mut owners = Owners::default();
            loop {
                let next = work.lock().expect("no worker panics holding it").next();
                let Some((band, (normals, states))) = next else {
                    break;
                };
                let (stats, stretches) = self.bake_band(band, normals, states, &mut owners, sample);
                let mut all = results.lock().expect("no worker panics holding it");
                all.0 += &stats;
                all.1.extend(stretches);
            }
        });
        let (mut stats, mut stretches) = results.into_inner().expect("workers are done");
        stats.flat_uv_triangles = self.flat_triangles();
        if !stretches.is_empty() {
            stretches.sort_unstable_by(f32::total_cmp);
            stats.skew = Some(Skew {
                skewed: stretches.iter().filter(|&&s| s as f64 > SKEW_LIMIT).count(),
                median: stretches[stretches.len() / 2] as f64,
                max: *stretches.last().expect("not empty") as f64,
            });
        }
        BakedMap {
            width: self.width as u32,
            height: self.height as u32,
            normals,
            states,
            stats,
        }
    }

    /// One band: its triangles rasterized into per-sample owners, then each owned sample baked.
    /// Returns the band's counts and each covered texel's frame stretch (where measured).
    fn bake_band(
        &self,
        band: usize,
        normals: &mut [Vec3],
        states: &mut [TexelState],
        owners: &mut Owners,
        sample: &(impl Fn(&[(usize, [f32; 3])], &mut Vec<Sample>) + Sync),
    ) -> (BakeStats, Vec<f32>) {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU has AVX2, which is all that `bake_band_avx2` is compiled for
            // beyond SSE2.
            return unsafe { self.bake_band_avx2(band, normals, states, owners, sample) };
        }
        self.bake_band_of(band, normals, states, owners, sample)
    }

    /// [`UvLayout::bake_band`] compiled for AVX2 (no fused multiply-add: every barycentric and
    /// average rounds as before).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,bmi1,popcnt")]
    unsafe fn bake_band_avx2(
        &self,
        band: usize,
        normals: &mut [Vec3],
        states: &mut [TexelState],
        owners: &mut Owners,
        sample: &(impl Fn(&[(usize, [f32; 3])], &mut Vec<Sample>) + Sync),
    ) -> (BakeStats, Vec<f32>) {
        self.bake_band_of(band, normals, states, owners, sample)
    }

    /// [`UvLayout::bake_band`], for whichever instruction set it is inlined into.
    #[inline(always)]
    fn bake_band_of(
        &self,
        band: usize,
        normals: &mut [Vec3],
        states: &mut [TexelState],
        owners: &mut Owners,
        sample: &(impl Fn(&[(usize, [f32; 3])], &mut Vec<Sample>) + Sync),
    ) -> (BakeStats, Vec<f32>) {
        let (w, k) = (self.width, self.samples);
        let rows = normals.len() / w;
        let first_sample_row = band * self.band_rows * k;
        let sample_rows = first_sample_row..first_sample_row + rows * k;
        let per_row = w * k;
        let count = rows * k * per_row;
        let Owners {
            owner,
            weights,
            claims,
        } = owners;
        owner.clear();
        owner.resize(count, NONE);
        claims.clear();
        claims.resize(count, 0);
        // Read only where a triangle owns the sample, which writes it first.
        weights.resize(count, [0.0; 3]);
        for &t in &self.bands[band] {
            let tri = self.triangles[t as usize].expect("only triangles with area are in bands");
            let Some((xs, ys)) = sample_box(&tri, w * k, self.height * k) else {
                continue;
            };
            let ys = ys.start.max(sample_rows.start)..ys.end.min(sample_rows.end);
            for sy in ys {
                for sx in row_span(&tri, sy as f64 + 0.5, xs.clone()) {
                    let p = DVec2::new(sx as f64 + 0.5, sy as f64 + 0.5);
                    let Some(b) = barycentrics(&tri, p) else {
                        continue;
                    };
                    let at = (sy - sample_rows.start) * per_row + sx;
                    owner[at] = t;
                    weights[at] = b;
                    claims[at] = claims[at].saturating_add(1);
                }
            }
        }
        let mut stats = BakeStats::default();
        let mut stretches = Vec::new();
        // The samples are traced a tile of texels at a time, whose rays start side by side: 2 × 2
        // texels' 4 × 4, or 8 × 8 texels' at K = 1 (see `Bvh::first_hits`).
        let tile = (TILE_SAMPLES / k).max(1);
        let mut batch = Vec::new();
        let mut found = Vec::new();
        for tile_row in (0..rows).step_by(tile) {
            for tile_x in (0..w).step_by(tile) {
                let texels = (tile_row..(tile_row + tile).min(rows))
                    .flat_map(|row| (tile_x..(tile_x + tile).min(w)).map(move |x| (row, x)));
                batch.clear();
                for (row, x) in texels.clone() {
                    for j in 0..k {
                        for i in 0..k {
                            let at = (row * k + j) * per_row + x * k + i;
                            if owner[at] != NONE {
                                batch.push((owner[at] as usize, weights[at]));
                            }
                        }
                    }
                }
                found.clear();
                sample(&batch, &mut found);
                let mut found = found.iter();
                for (row, x) in texels {
                    let mut sum = Vec3::ZERO;
                    let mut first: Option<Vec3> = None;
                    let mut stretch = None;
                    let mut overlapping = false;
                    for j in 0..k {
                        for i in 0..k {
                            let at = (row * k + j) * per_row + x * k + i;
                            if owner[at] == NONE {
                                continue;
                            }
                            overlapping |= claims[at] > 1;
                            let s = found.next().expect("a sample for each position");
                            stats.add_sample(s);
                            stretch = stretch.or(s.stretch);
                            first.get_or_insert(s.normal);
                            sum += s.normal;
                        }
                    }
                    let Some(first) = first else { continue };
                    let texel = row * w + x;
                    // Samples that cancel (a fold) keep the first one's direction.
                    normals[texel] = sum.try_normalize().unwrap_or(first);
                    states[texel] = TexelState::Covered;
                    stats.covered += 1;
                    stats.overlapping += usize::from(overlapping);
                    if let Some(s) = stretch {
                        stretches.push(s.min(f32::MAX as f64) as f32);
                    }
                }
            }
        }
        (stats, stretches)
    }
}

/// Each bake thread's per-sample buffers for a band: which triangle owns each sample (the last
/// to claim it), its barycentrics there, and how many triangles claimed it.
#[derive(Default)]
struct Owners {
    owner: Vec<u32>,
    weights: Vec<[f32; 3]>,
    claims: Vec<u8>,
}

/// The columns of `columns` in the sample row whose centres lie at `y` that can hold a sample
/// of `tri`: those between where the row crosses its edges, a column wider on each side than
/// that crossing (computed with rounding, far below a column) says. The test of each sample
/// ([`barycentrics`]) decides; this only spares it the bounding box's empty corners.
#[inline(always)]
fn row_span(
    tri: &PixelTriangle,
    y: f64,
    columns: std::ops::Range<usize>,
) -> std::ops::Range<usize> {
    let (mut low, mut high) = (columns.start as f64, columns.end as f64);
    let [a, b, c] = tri.corners;
    for (from, to) in [(b, c), (c, a), (a, b)] {
        let edge = to - from;
        // A level edge bounds no column: its side is the whole row's.
        if edge.y == 0.0 {
            continue;
        }
        // The centre x + ½ where the edge's weight is 0; inside is to its left where the edge
        // goes down the picture (y grows), to its right where it goes up.
        let cross = from.x + edge.x * (y - from.y) / edge.y - 0.5;
        if edge.y > 0.0 {
            high = high.min(cross.floor() + 2.0);
        } else {
            low = low.max(cross.ceil() - 1.0);
        }
    }
    // A NaN crossing (an edge too steep for f64) is passed over by `min` and `max`.
    match low < high {
        true => low as usize..high as usize,
        false => 0..0,
    }
}

/// The sample columns and rows whose centres (x + ½, y + ½) can fall in `tri`, clipped to the map.
#[inline(always)]
fn sample_box(
    tri: &PixelTriangle,
    columns: usize,
    rows: usize,
) -> Option<(std::ops::Range<usize>, std::ops::Range<usize>)> {
    let min = tri.corners[0].min(tri.corners[1]).min(tri.corners[2]);
    let max = tri.corners[0].max(tri.corners[1]).max(tri.corners[2]);
    let range = |low: f64, high: f64, size: usize| {
        let start = (low - 0.5).ceil().max(0.0);
        let end = ((high - 0.5).floor() + 1.0).min(size as f64);
        (start < end).then_some(start as usize..end as usize)
    };
    Some((range(min.x, max.x, columns)?, range(min.y, max.y, rows)?))
}

/// The barycentrics (in the soup's corner order) of `p` if it is inside `tri`. A point on an edge
/// belongs to one of the two triangles that share it: the edge's own triangle when the edge is a
/// "top" or "left" one, as GL rasterizes, so that no sample is counted twice on a shared edge.
#[inline(always)]
fn barycentrics(tri: &PixelTriangle, p: DVec2) -> Option<[f32; 3]> {
    let [a, b, c] = tri.corners;
    let weight = |from: DVec2, to: DVec2| {
        let edge = to - from;
        let w = edge.perp_dot(p - from);
        // With y down and positive area the inside is w > 0; on the edge (w = 0) take the point
        // only for edges going one way, which the neighbour's copy of the edge does not.
        let owns_edge = edge.y > 0.0 || (edge.y == 0.0 && edge.x < 0.0);
        (w > 0.0 || (w == 0.0 && owns_edge)).then_some(w)
    };
    // Each corner's weight is the edge opposite it.
    let wa = weight(b, c)?;
    let wb = weight(c, a)?;
    let wc = weight(a, b)?;
    let w = [wa, wb, wc].map(|w| (w / tri.area) as f32);
    // Put back in the soup's order as whole values (stored one by one through the order, they
    // were read back as one, a stall on every sample).
    Some(match tri.swapped {
        false => w,
        true => [w[0], w[2], w[1]],
    })
}

/// Grows the covered texels outward by `margin` rings (8 neighbours: each ring is the texels at
/// that Chebyshev distance), each new texel the normalized mean of its filled neighbours. Returns
/// how many texels it filled.
pub fn fill_margin(
    width: usize,
    height: usize,
    normals: &mut [Vec3],
    states: &mut [TexelState],
    margin: usize,
    threads: usize,
) -> usize {
    let around = |i: usize| neighbours(i, i % width, i / width, width, height);
    // The covered texels beside an empty one: each run walks its texels along the rows.
    let mut frontier: Vec<usize> = {
        let states = &*states;
        in_runs(states.len(), threads, |run| {
            let (mut x, mut y) = (run.start % width, run.start / width);
            let mut frontier = Vec::new();
            for i in run {
                if states[i] == TexelState::Covered
                    && neighbours(i, x, y, width, height).any(|n| states[n] == TexelState::Empty)
                {
                    frontier.push(i);
                }
                x += 1;
                if x == width {
                    (x, y) = (0, y + 1);
                }
            }
            frontier
        })
    };
    let mut queued = vec![false; states.len()];
    let mut filled = 0;
    for _ in 0..margin {
        let mut ring = Vec::new();
        for &f in &frontier {
            for n in around(f) {
                if states[n] == TexelState::Empty && !queued[n] {
                    queued[n] = true;
                    ring.push(n);
                }
            }
        }
        if ring.is_empty() {
            break;
        }
        // Every value of the ring is computed from the rings before it, then written.
        let values = {
            let (states, normals, around, ring) = (&*states, &*normals, &around, &ring);
            in_runs(ring.len(), threads, |run| {
                (ring[run].iter())
                    .map(|&i| {
                        let sum: Vec3 = around(i)
                            .filter(|&n| states[n] != TexelState::Empty)
                            .map(|n| normals[n])
                            .sum();
                        sum.try_normalize().unwrap_or(Vec3::Z)
                    })
                    .collect()
            })
        };
        for (&i, v) in ring.iter().zip(values) {
            normals[i] = v;
            states[i] = TexelState::Margin;
        }
        filled += ring.len();
        frontier = ring;
    }
    filled
}

/// The neighbours within the map of texel `i` at column `x` and row `y`, row by row (the order in
/// which the margin's sums add them). Built in an array: as a chain of closures over the nine
/// offsets, finding the frontier of a 2048² map took half the margin's time.
fn neighbours(
    i: usize,
    x: usize,
    y: usize,
    width: usize,
    height: usize,
) -> impl Iterator<Item = usize> {
    let mut found = [0; 8];
    let mut count = 0;
    if x > 0 && y > 0 && x + 1 < width && y + 1 < height {
        let (above, below) = (i - width, i + width);
        found = [
            above - 1,
            above,
            above + 1,
            i - 1,
            i + 1,
            below - 1,
            below,
            below + 1,
        ];
        count = 8;
    } else {
        for ny in y.saturating_sub(1)..(y + 2).min(height) {
            for nx in x.saturating_sub(1)..(x + 2).min(width) {
                if (nx, ny) != (x, y) {
                    found[count] = ny * width + nx;
                    count += 1;
                }
            }
        }
    }
    found.into_iter().take(count)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec2;

    fn soup(uvs: &[Vec2]) -> TriangleSoup {
        TriangleSoup {
            vertices: vec![Vec3::ZERO; uvs.len()],
            uvs: uvs.to_vec(),
            normals: vec![Vec3::Z; uvs.len()],
        }
    }

    fn flat(batch: &[(usize, [f32; 3])], out: &mut Vec<Sample>) {
        out.extend(batch.iter().map(|_| Sample::flat()));
    }

    /// Fails if a shared edge's samples are counted by both triangles or by neither (the fill
    /// rule), or if the square's texels are not all covered exactly once.
    #[test]
    fn two_triangles_of_a_square_cover_each_sample_once() {
        let (a, b, c, d) = (
            Vec2::new(0.1, 0.1),
            Vec2::new(0.9, 0.1),
            Vec2::new(0.9, 0.9),
            Vec2::new(0.1, 0.9),
        );
        // One wound each way in UV space: the rule must hold for both orientations.
        let layout = UvLayout::new(&soup(&[a, b, c, a, d, c]), 10, 10, 3);
        let map = layout.bake(2, flat);
        // Samples at (x + 1/6, 3/6, 5/6) in 0.1..0.9 of 10 texels: texels 1..=8 in each direction.
        assert_eq!(map.stats.covered, 64);
        assert_eq!(map.stats.rays, 64 * 9);
        assert_eq!(map.stats.overlapping, 0);
    }

    /// Fails if a texel's samples are not the ones its own test of every sample finds (which
    /// triangle owns each, last claimant first, at which barycentrics, summed in order), at 1 to
    /// 5 samples a side: a band's rows taken from another band, or rows of a band left out. The
    /// map's height is no multiple of any band's.
    #[test]
    fn each_texel_averages_the_samples_its_own_test_finds() {
        let mut bits = crate::bake::xorshift(0x7a3b_11c0_9e21_55d3);
        let mut next = move || (bits() >> 40) as f32 / (1u64 << 24) as f32;
        let uvs: Vec<Vec2> = (0..3 * 9)
            .map(|_| Vec2::new(next() * 1.2 - 0.1, next() * 1.2 - 0.1))
            .collect();
        let (w, h) = (13, 37);
        let normal = |t: usize, b: [f32; 3]| Vec3::new(t as f32 + 1.0, b[0], b[1] - b[2]);
        for k in 1..=5 {
            let layout = UvLayout::new(&soup(&uvs), w as u32, h as u32, k as u32);
            let map = layout.bake(2, |batch, out| {
                out.extend(batch.iter().map(|&(t, b)| Sample {
                    normal: normal(t, b),
                    ..Sample::flat()
                }))
            });
            for texel in 0..w * h {
                let (x, y) = (texel % w, texel / w);
                let mut found = Vec::new();
                for j in 0..k {
                    for i in 0..k {
                        let p = DVec2::new((x * k + i) as f64 + 0.5, (y * k + j) as f64 + 0.5);
                        let owner = (layout.triangles.iter().enumerate())
                            .rev()
                            .find_map(|(t, tri)| Some((t, barycentrics(tri.as_ref()?, p)?)));
                        found.extend(owner.map(|(t, b)| normal(t, b)));
                    }
                }
                let covered = map.states[texel] == TexelState::Covered;
                assert_eq!(covered, !found.is_empty(), "texel ({x}, {y}) at {k} × {k}");
                if let Some(&first) = found.first() {
                    let sum: Vec3 = found.iter().fold(Vec3::ZERO, |sum, n| sum + *n);
                    let expected = sum.try_normalize().unwrap_or(first);
                    assert_eq!(
                        map.normals[texel], expected,
                        "texel ({x}, {y}) at {k} × {k}"
                    );
                }
            }
        }
    }

    /// Fails if a row's span leaves out a sample the triangle owns (a span too narrow by
    /// rounding, or on the wrong side of an edge): every sample of the triangle's box is
    /// tested, on random triangles of every size and shape (slivers, level and upright edges,
    /// corners on sample centres, far outside the map), both windings.
    #[test]
    fn a_rows_span_holds_every_sample_of_the_triangle() {
        let mut bits = crate::bake::xorshift(0x1234_5678_9abc_def1);
        let mut next = move |scale: f64| (bits() >> 11) as f64 / (1u64 << 53) as f64 * scale;
        let (columns, rows) = (96, 80);
        let (mut inside, mut spared) = (0, 0);
        for round in 0..3000 {
            let mut corner = |k: usize| {
                let p = DVec2::new(next(110.0) - 7.0, next(94.0) - 7.0);
                // A round in three, each corner a fraction of the map in f32 UVs, scaled as
                // `UvLayout::new` scales them: edges through sample centres but for rounding
                // (the fill rule's ties).
                let mut fraction = |scale: f64| (next(12.0).floor() as f32 / 10.0) as f64 * scale;
                match (round + k) % 7 {
                    _ if round % 3 == 0 => {
                        DVec2::new(fraction(columns as f64), 1.0 - fraction(1.0) * rows as f64)
                    }
                    // On a sample centre, or on the row or column of another corner.
                    0 => p.floor() + 0.5,
                    1 => DVec2::new(p.x, 40.5),
                    2 => DVec2::new(33.5, p.y),
                    _ => p,
                }
            };
            let (a, b) = (corner(0), corner(1));
            // A sliver now and then: the third corner near the first two's line.
            let c = match round % 5 {
                0 => a + (b - a) * next(1.0) + DVec2::splat(next(1e-6)),
                _ => corner(2),
            };
            let area = (b - a).perp_dot(c - a);
            if area == 0.0 {
                continue;
            }
            let tri = match area > 0.0 {
                true => PixelTriangle {
                    corners: [a, b, c],
                    swapped: false,
                    area,
                },
                false => PixelTriangle {
                    corners: [a, c, b],
                    swapped: true,
                    area: -area,
                },
            };
            let Some((xs, ys)) = sample_box(&tri, columns, rows) else {
                continue;
            };
            for sy in ys {
                let span = row_span(&tri, sy as f64 + 0.5, xs.clone());
                for sx in xs.clone() {
                    let p = DVec2::new(sx as f64 + 0.5, sy as f64 + 0.5);
                    if barycentrics(&tri, p).is_some() {
                        assert!(span.contains(&sx), "{tri:?}: ({sx}, {sy}) outside {span:?}");
                        inside += 1;
                    } else {
                        spared += usize::from(!span.contains(&sx));
                    }
                }
            }
        }
        // The spans did spare the box's empty corners.
        assert!(
            inside > 100_000 && spared > inside / 2,
            "{inside} inside, {spared} spared"
        );
    }

    /// Fails if a sample claimed by two overlapping triangles is not counted as overlapping.
    #[test]
    fn overlapping_islands_are_counted() {
        let tri = [
            Vec2::new(0.0, 0.0),
            Vec2::new(1.0, 0.0),
            Vec2::new(0.0, 1.0),
        ];
        // The same UV triangle twice, wound the other way the second time (as a mirrored half's
        // copy is); the hypotenuse's 8 texel centres are on an edge its orientation owns.
        let mirrored: Vec<Vec2> = tri.iter().rev().copied().collect();
        let uvs: Vec<Vec2> = tri.iter().copied().chain(mirrored).collect();
        let map = UvLayout::new(&soup(&uvs), 8, 8, 1).bake(1, flat);
        assert_eq!(map.stats.covered, 36);
        assert_eq!(map.stats.overlapping, 36);
    }

    /// Fails if a texel's neighbours are not the texels around it inside the map, each once,
    /// row by row and left to right (the order the margin's sums take), on maps one texel wide
    /// or high, and at every border and corner.
    #[test]
    fn a_texels_neighbours_are_the_eight_around_it_in_order() {
        for (w, h) in [(1, 1), (1, 5), (5, 1), (2, 2), (3, 3), (7, 4), (4, 7)] {
            for i in 0..w * h {
                let (x, y) = ((i % w) as isize, (i / w) as isize);
                let mut around = Vec::new();
                for dy in -1..=1 {
                    for dx in -1..=1 {
                        let (nx, ny) = (x + dx, y + dy);
                        let inside = (0..w as isize).contains(&nx) && (0..h as isize).contains(&ny);
                        if (dx, dy) != (0, 0) && inside {
                            around.push(ny as usize * w + nx as usize);
                        }
                    }
                }
                let found: Vec<usize> = neighbours(i, i % w, i / w, w, h).collect();
                assert_eq!(found, around, "texel ({x}, {y}) of {w} × {h}");
            }
        }
    }

    /// Fails if the margin fills anything other than the texels within `margin` (Chebyshev) of
    /// the island, or writes over the island.
    #[test]
    fn the_margin_fills_exactly_its_rings() {
        let (w, h) = (40, 30);
        let mut states = vec![TexelState::Empty; w * h];
        let mut normals = vec![Vec3::Z; w * h];
        // An L-shaped island.
        let island = |x: usize, y: usize| {
            (10..20).contains(&x) && (8..12).contains(&y)
                || (10..13).contains(&x) && (8..20).contains(&y)
        };
        for y in 0..h {
            for x in 0..w {
                if island(x, y) {
                    states[y * w + x] = TexelState::Covered;
                    normals[y * w + x] = Vec3::X;
                }
            }
        }
        let filled = fill_margin(w, h, &mut normals, &mut states, 3, 2);
        let mut expected = 0;
        for y in 0..h {
            for x in 0..w {
                let distance = (0..h)
                    .flat_map(|iy| (0..w).map(move |ix| (ix, iy)))
                    .filter(|&(ix, iy)| island(ix, iy))
                    .map(|(ix, iy)| {
                        (ix as isize - x as isize)
                            .abs()
                            .max((iy as isize - y as isize).abs())
                    })
                    .min()
                    .unwrap();
                let state = states[y * w + x];
                match distance {
                    0 => assert_eq!(state, TexelState::Covered),
                    1..=3 => {
                        expected += 1;
                        assert_eq!(state, TexelState::Margin, "({x}, {y}) at {distance}");
                        assert_eq!(normals[y * w + x], Vec3::X);
                    }
                    _ => assert_eq!(state, TexelState::Empty, "({x}, {y}) at {distance}"),
                }
            }
        }
        assert_eq!(filled, expected);
    }
}
