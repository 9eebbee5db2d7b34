//! Baking: the normals of a detailed model (HIGH) written into a simple model's (LOW's) UV layout, in
//! the tangent frame that will draw LOW. The tutorial's "How to create a normal map" ends with such a
//! map ("baked normals"); this is the tool that makes one.
//!
//! For every texel of LOW's layout (K × K positions in it), LOW's surface point and interpolated
//! normal are found; a ray starts on the cage (the point pushed out along that normal by the
//! extrusion) and goes back along the normal, up to the maximum distance; the first triangle of HIGH
//! it meets gives its interpolated normal there (its face normal where HIGH's file has none). That
//! normal is written in LOW's frame at the texel: the inverse of what the renderer does with the
//! frame, so that drawing LOW with the map in that frame gives HIGH's normal back. A ray that meets
//! nothing writes the flat normal. These are Blender's semantics (`cage_extrusion`,
//! `max_ray_distance`), so that the same settings give the same map. With a cage of its own
//! ([`cage`], Blender's `cage_object`) a ray starts at the cage's point and goes toward LOW's; with
//! parts matched by name ([`parts`]) a LOW part's rays meet only its HIGH part.
//!
//! The frames (a [`TangentSource`] with corner frames: every one but the per-pixel `derivative`):
//! * MikkTSpace (glTF's rule, Blender's bake): the renderer rebuilds n = t.x·T + t.y·B + t.z·N per
//!   pixel from the interpolated, unnormalized T and N, with B = sign · N × T; the bake solves that
//!   3 × 3 system for t.
//! * The tutorial's frame: `computeTangentBasis` + `indexVBO_TBN`, each vertex's summed T, B and N
//!   (normalized first with `--normalize-tbn`, as the article's text does). Its shader moves the light
//!   into that frame, l' = (T·l, B·l, N·l), and normalizes l' before lighting; the map that gives
//!   HIGH's normal back is t = (T B N)⁻¹ n, the same solve. Where T, B and N are not at right angles
//!   with equal lengths, normalizing l' after the frame stretched it changes the light's brightness
//!   by up to the frame's stretch σmax/σmin whatever the map holds: no map can be right there, and
//!   the bake measures by how much ([`Skew`]).

pub mod bvh;
pub mod cage;
mod lanes;
pub mod parts;
mod texels;

use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};

use glam::{DVec3, Vec3};

use crate::clock::Instant;
use crate::common::objloader::TriangleSoup;
use crate::mesh::{build_mesh, MeshOptions};
use crate::model::{load_model, MapOverrides, Model};
use crate::pipeline::{each_on_cores, join, runs_on_cores};
use crate::tangent_source::{stretch, TangentSource};
use crate::{Error, Result};
use bvh::PACKET;

pub use parts::Pairing;
pub use texels::{TexelState, UvLayout};

/// Why the bake has no map for [`TangentSource::Derivative`], the frame `bake --tangents` and
/// [`BakeFiles::load`] refuse: it has no corner frames to bake for.
pub const NO_PER_PIXEL_BAKE: &str = "the per-pixel frame is solved from screen-space derivatives \
    as each frame is drawn, so the bake has no corner frames for it (it follows the UVs as \
    MikkTSpace does: --tangents mikktspace)";

/// Where the map's vectors live.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum Space {
    /// In LOW's tangent frame at each texel.
    #[default]
    Tangent,
    /// In the model's own axes (the file's: placing only scales and moves).
    Object,
}

/// Everything the bake needs besides the two models. Distances are in LOW's file units.
#[derive(Debug, Clone, PartialEq)]
pub struct BakeSettings {
    pub width: u32,
    pub height: u32,
    /// K: K × K positions per texel.
    pub samples: u32,
    /// How far the cage is pushed out along LOW's normal.
    pub extrusion: f32,
    /// How far a ray goes from the cage.
    pub max_distance: f32,
    /// Texels filled around each island's edge.
    pub margin: u32,
    /// The frame the map is for: any source but [`TangentSource::Derivative`] ([`NO_PER_PIXEL_BAKE`]).
    pub tangents: TangentSource,
    /// The tutorial's frame with each vertex's T, B and N normalized (the article's text).
    pub normalize_tbn: bool,
    pub space: Space,
    pub threads: usize,
}

impl Default for BakeSettings {
    fn default() -> Self {
        BakeSettings {
            width: 1024,
            height: 1024,
            samples: 1,
            extrusion: 0.0,
            max_distance: 0.0,
            margin: 16,
            tangents: TangentSource::MikkTSpace,
            normalize_tbn: false,
            space: Space::Tangent,
            threads: std::thread::available_parallelism().map_or(1, |n| n.get()),
        }
    }
}

/// LOW's frame at each corner, as its renderer interpolates it.
#[derive(Debug, Clone, PartialEq)]
pub struct CornerFrames {
    pub tangents: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    pub bitangents: Bitangents,
}

/// How the renderer gets B.
#[derive(Debug, Clone, PartialEq)]
pub enum Bitangents {
    /// MikkTSpace's: sign · N × T per pixel, the sign per corner.
    Signs(Vec<f32>),
    /// Interpolated as given (the tutorial's vertex attribute).
    Given(Vec<Vec3>),
}

impl CornerFrames {
    /// MikkTSpace's tangents (xyz, w the sign) over `soup`'s normals.
    pub fn mikktspace(soup: &TriangleSoup, tangents: &[[f32; 4]]) -> Self {
        CornerFrames {
            tangents: tangents
                .iter()
                .map(|t| Vec3::new(t[0], t[1], t[2]))
                .collect(),
            normals: soup.normals.clone(),
            bitangents: Bitangents::Signs(tangents.iter().map(|t| t[3]).collect()),
        }
    }

    /// The tutorial's pipeline's vertices (what its renderer uploads) at each corner; each vector
    /// normalized first when `normalize` (the article's normalized TBN).
    pub fn tutorial(soup: &TriangleSoup, normalize: bool) -> Self {
        let mesh = build_mesh(soup, MeshOptions::default());
        let indices = mesh.indices.to_u32();
        let pick = |values: &[Vec3]| -> Vec<Vec3> {
            indices
                .iter()
                .map(|&i| {
                    let v = values[i as usize];
                    if normalize {
                        v.normalize_or_zero()
                    } else {
                        v
                    }
                })
                .collect()
        };
        CornerFrames {
            tangents: pick(&mesh.tangents),
            normals: pick(&mesh.normals),
            bitangents: Bitangents::Given(pick(&mesh.bitangents)),
        }
    }

    /// The frame at barycentrics `b` of triangle `t`: the columns T, B, N.
    #[cfg(test)]
    fn at(&self, t: usize, b: [f32; 3]) -> [DVec3; 3] {
        let mix = |v: &[Vec3]| -> DVec3 {
            (0..3)
                .map(|i| v[3 * t + i].as_dvec3() * b[i] as f64)
                .sum::<DVec3>()
        };
        let tangent = mix(&self.tangents);
        let normal = mix(&self.normals);
        let bitangent = match &self.bitangents {
            Bitangents::Given(v) => mix(v),
            Bitangents::Signs(signs) => {
                let sign: f32 = (0..3).map(|i| signs[3 * t + i] * b[i]).sum();
                normal.cross(tangent) * if sign < 0.0 { -1.0 } else { 1.0 }
            }
        };
        [tangent, bitangent, normal]
    }

    /// [`CornerFrames::at`] of every sample of `chunk` (a packet's), into `columns` (column, axis,
    /// lane), to the bit. A packet's samples come in runs on one triangle (a texel's K × K, often
    /// its neighbours'): each run's corners are read once and mixed lane by lane, the same products
    /// summed in the same order from the same zero as `at`'s, which the compiler lays side by side.
    #[inline(always)]
    fn at_lanes(&self, chunk: &[(usize, [f32; 3])], columns: &mut [[[f64; PACKET]; 3]; 3]) {
        let mut weights = [[0.0f64; PACKET]; 3];
        for (k, (_, b)) in chunk.iter().enumerate() {
            for i in 0..3 {
                weights[i][k] = b[i] as f64;
            }
        }
        // `mix` of `at` for lanes `run` of one triangle's corners `v` (a function, so that it is
        // compiled into the packet's code and not called).
        #[inline(always)]
        fn mix(
            v: &[Vec3],
            run: std::ops::Range<usize>,
            weights: &[[f64; PACKET]; 3],
            out: &mut [[f64; PACKET]; 3],
        ) {
            for (axis, out) in out.iter_mut().enumerate() {
                let corner = [v[0][axis] as f64, v[1][axis] as f64, v[2][axis] as f64];
                for k in run.clone() {
                    let sum = 0.0 + corner[0] * weights[0][k];
                    out[k] = (sum + corner[1] * weights[1][k]) + corner[2] * weights[2][k];
                }
            }
        }
        for (t, std::ops::Range { start, end }) in runs_of_triangles(chunk) {
            let corners = 3 * t..3 * t + 3;
            let [tangent, bitangent, normal] = columns;
            mix(
                &self.tangents[corners.clone()],
                start..end,
                &weights,
                tangent,
            );
            mix(&self.normals[corners.clone()], start..end, &weights, normal);
            match &self.bitangents {
                Bitangents::Given(v) => mix(&v[corners], start..end, &weights, bitangent),
                Bitangents::Signs(signs) => {
                    let signs = &signs[corners];
                    for k in start..end {
                        let b = chunk[k].1;
                        let sign: f32 = (0..3).map(|i| signs[i] * b[i]).sum();
                        let flip = if sign < 0.0 { -1.0 } else { 1.0 };
                        // N × T as glam's `cross` writes it.
                        let (n, t) = (
                            [0, 1, 2].map(|a| normal[a][k]),
                            [0, 1, 2].map(|a| tangent[a][k]),
                        );
                        bitangent[0][k] = (n[1] * t[2] - t[1] * n[2]) * flip;
                        bitangent[1][k] = (n[2] * t[0] - t[2] * n[0]) * flip;
                        bitangent[2][k] = (n[0] * t[1] - t[0] * n[1]) * flip;
                    }
                }
            }
        }
    }
}

/// The runs of consecutive samples of `chunk` on one triangle: the triangle, the run.
#[inline(always)]
fn runs_of_triangles(
    chunk: &[(usize, [f32; 3])],
) -> impl Iterator<Item = (usize, std::ops::Range<usize>)> + '_ {
    let mut start = 0;
    std::iter::from_fn(move || {
        let &(t, _) = chunk.get(start)?;
        let mut end = start + 1;
        while end < chunk.len() && chunk[end].0 == t {
            end += 1;
        }
        let run = start..end;
        start = end;
        Some((t, run))
    })
}

/// How far the tutorial's frame is from one that lights right: its stretch σmax/σmin (1 for T, B
/// and N at right angles with equal lengths), over the covered texels.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Skew {
    /// Texels whose stretch is over [`SKEW_LIMIT`].
    pub skewed: usize,
    pub median: f64,
    pub max: f64,
}

/// A stretch above this changes the light by more than 5 % for some light direction.
pub const SKEW_LIMIT: f64 = 1.05;

/// What the bake did.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct BakeStats {
    /// Texels with at least one sample on LOW.
    pub covered: usize,
    /// Texels the margin filled.
    pub margin: usize,
    /// Rays cast (covered samples).
    pub rays: usize,
    /// Rays that met nothing within the maximum distance (flat normal written).
    pub missed: usize,
    /// Of those, rays that meet HIGH farther on (a longer `--max-distance` would reach it), within
    /// LOW's bounding radius of the cage.
    pub missed_beyond: usize,
    /// Of those, rays whose cage point has HIGH outside it (a larger `--extrusion` would enclose
    /// it), within LOW's bounding radius.
    pub missed_outside: usize,
    /// The farthest from the cage, along the rays, that those rays found HIGH (0 for none).
    pub beyond_by: f32,
    /// The farthest outside the cage that those rays found HIGH (0 for none).
    pub outside_by: f32,
    /// Texels where two triangles' UVs claim one sample (mirrored or overlapping islands).
    pub overlapping: usize,
    /// LOW's triangles with no area in UV space (they cover nothing).
    pub flat_uv_triangles: usize,
    /// Samples whose frame has no inverse (T, B and N in one plane): flat normal written.
    pub singular: usize,
    /// For the tutorial's frame.
    pub skew: Option<Skew>,
}

impl BakeStats {
    /// Counts one sample.
    #[inline(always)]
    pub(crate) fn add_sample(&mut self, sample: &Sample) {
        self.rays += 1;
        self.missed += usize::from(sample.missed);
        self.singular += usize::from(sample.singular);
        if let Some(d) = sample.beyond {
            self.missed_beyond += 1;
            self.beyond_by = self.beyond_by.max(d);
        }
        if let Some(d) = sample.outside {
            self.missed_outside += 1;
            self.outside_by = self.outside_by.max(d);
        }
    }
}

/// Two parts' counts together (bands of one bake): counts add, distances take the larger. Every
/// field is named, so a new one does not compile until it is summed here.
impl std::ops::AddAssign<&BakeStats> for BakeStats {
    fn add_assign(&mut self, other: &BakeStats) {
        let BakeStats {
            covered,
            margin,
            rays,
            missed,
            missed_beyond,
            missed_outside,
            beyond_by,
            outside_by,
            overlapping,
            flat_uv_triangles,
            singular,
            skew,
        } = other;
        self.covered += covered;
        self.margin += margin;
        self.rays += rays;
        self.missed += missed;
        self.missed_beyond += missed_beyond;
        self.missed_outside += missed_outside;
        self.beyond_by = self.beyond_by.max(*beyond_by);
        self.outside_by = self.outside_by.max(*outside_by);
        self.overlapping += overlapping;
        self.flat_uv_triangles += flat_uv_triangles;
        self.singular += singular;
        // A median does not add: the whole bake's is measured once its texels are all in (a
        // band's is `None`).
        self.skew = self.skew.or(*skew);
    }
}

/// A baked map: unit vectors, row 0 at the top (V = 1), y up the picture.
#[derive(Debug, Clone)]
pub struct BakedMap {
    pub width: u32,
    pub height: u32,
    pub normals: Vec<Vec3>,
    pub states: Vec<TexelState>,
    pub stats: BakeStats,
}

/// Both models in one space, and LOW's frames.
pub struct BakeInput<'a> {
    pub low: &'a TriangleSoup,
    pub frames: &'a CornerFrames,
    pub high: &'a TriangleSoup,
    /// HIGH's file has no normals: its face normals are taken.
    pub high_face_normals: bool,
    /// In this space's units.
    pub extrusion: f32,
    pub max_distance: f32,
    /// A cage ([`cage::cage_corners`]): a point per LOW corner, in this space. Each ray starts at
    /// the cage's point and goes toward LOW's (`extrusion` is not used).
    pub cage: Option<&'a [Vec3]>,
    /// Parts matched by name: a LOW triangle's rays meet only its pair's HIGH triangles.
    pub pairing: Option<&'a Pairing>,
}

/// Each HIGH triangle's corner normals (its face normal first, with `high_face_normals`), kept in
/// the hierarchy beside the triangle: a hit reads them beside the triangle its search read last,
/// not from anywhere in the mesh's tens of megabytes.
fn high_normals<'a>(input: &'a BakeInput) -> impl Fn(usize) -> [Vec3; 3] + Sync + 'a {
    let high = input.high;
    move |t: usize| {
        let corners = 3 * t..3 * t + 3;
        if input.high_face_normals {
            let p = &high.vertices[corners];
            [(p[1] - p[0]).cross(p[2] - p[0]), Vec3::ZERO, Vec3::ZERO]
        } else {
            let n = &high.normals[corners];
            [n[0], n[1], n[2]]
        }
    }
}

/// Told what a bake is doing, for a progress bar (the page's): the stage in words, and the share of
/// it done (the rays' share against LOW's UV area, so about; overlapping islands end it early).
pub type BakeProgress<'a> = &'a (dyn Fn(&str, f32) + Sync);

/// Samples between two calls of a [`BakeProgress`].
const PROGRESS_SAMPLES: usize = 4096;

/// The bake on soups already in one space: raster, rays and margin.
pub fn bake_soups(input: &BakeInput, settings: &BakeSettings) -> BakedMap {
    bake_soups_with(input, settings, None)
}

/// [`bake_soups`], telling `progress` how far it is.
pub fn bake_soups_with(
    input: &BakeInput,
    settings: &BakeSettings,
    progress: Option<BakeProgress>,
) -> BakedMap {
    let tell = |stage: &str, share: f32| {
        if let Some(progress) = progress {
            progress(stage, share);
        }
    };
    tell("building the BVH", 0.0);
    let clock = Instant::now();
    let targets = parts::Targets::build(
        input.high,
        input.pairing,
        settings.threads,
        high_normals(input),
    );
    log::info!(
        "bake: BVH over {} triangles ({} nodes) in {:.2} s",
        input.high.triangle_count(),
        targets.node_count(),
        clock.elapsed().as_secs_f64()
    );
    let clock = Instant::now();
    let layout = UvLayout::new(input.low, settings.width, settings.height, settings.samples);
    let sampler = Sampler {
        input,
        targets: &targets,
        space: settings.space,
        measure_skew: matches!(input.frames.bitangents, Bitangents::Given(_)),
        reach: Reach::of(input),
    };
    tell("tracing rays", 0.0);
    let (done, expected) = (AtomicUsize::new(0), uv_samples(input.low, settings));
    let mut map = layout.bake(settings.threads, |batch, out| {
        if let Some(progress) = progress {
            let before = done.fetch_add(batch.len(), Ordering::Relaxed);
            // Told once each PROGRESS_SAMPLES samples, whatever the batches' sizes.
            if before / PROGRESS_SAMPLES != (before + batch.len()) / PROGRESS_SAMPLES {
                let share = (before + batch.len()) as f64 / expected;
                progress("tracing rays", share.min(1.0) as f32);
            }
        }
        sampler.samples(batch, out)
    });
    log::info!(
        "bake: {} rays in {:.2} s",
        map.stats.rays,
        clock.elapsed().as_secs_f64()
    );
    tell("filling the margin", 1.0);
    let clock = Instant::now();
    map.stats.margin = texels::fill_margin(
        settings.width as usize,
        settings.height as usize,
        &mut map.normals,
        &mut map.states,
        settings.margin as usize,
        settings.threads,
    );
    log::info!(
        "bake: margin of {} in {:.2} s",
        settings.margin,
        clock.elapsed().as_secs_f64()
    );
    map
}

/// About how many samples LOW's UV layout covers (the UV triangles' area, overlaps counted twice).
fn uv_samples(low: &TriangleSoup, settings: &BakeSettings) -> f64 {
    let area: f64 = (low.uvs.chunks_exact(3))
        .map(|uv| ((uv[1] - uv[0]).perp_dot(uv[2] - uv[0]) as f64 / 2.0).abs())
        .filter(|a| a.is_finite())
        .sum();
    let samples =
        (settings.width * settings.samples) as f64 * (settings.height * settings.samples) as f64;
    (area * samples).max(1.0)
}

/// Xorshift64 from `seed` (not 0): the bake's tests' random numbers, the same on every run.
#[cfg(test)]
pub(crate) fn xorshift(mut seed: u64) -> impl FnMut() -> u64 {
    move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        seed
    }
}

/// Each sample's ray, and its normal in the map's space.
struct Sampler<'a> {
    input: &'a BakeInput<'a>,
    targets: &'a parts::Targets<'a>,
    space: Space,
    measure_skew: bool,
    reach: Reach,
}

/// What one sample gives.
pub(crate) struct Sample {
    pub normal: Vec3,
    pub missed: bool,
    /// A missed ray: how far from the cage HIGH lies along it (a longer `--max-distance` reaches
    /// it), if it does within [`Reach::look`].
    pub beyond: Option<f32>,
    /// A missed ray: how far outside the cage HIGH lies (a larger `--extrusion` encloses it), if
    /// it does within [`Reach::look`].
    pub outside: Option<f32>,
    pub singular: bool,
    /// The frame's stretch, where it is measured.
    pub stretch: Option<f64>,
}

impl Sample {
    /// The flat normal, nothing missed (for the texels' own tests).
    #[cfg(test)]
    pub(crate) fn flat() -> Sample {
        Sample {
            normal: Vec3::Z,
            missed: false,
            beyond: None,
            outside: None,
            singular: false,
            stretch: None,
        }
    }
}

/// A thread's arrays for a packet, kept from packet to packet: made anew for each, they were 13 KB
/// of zeros every 64 rays. Every lane a packet reads is written first: its rays' hits, its samples'
/// frames, HIGH's normal where a ray met it, every lane of the solve.
struct PacketLanes {
    hits: [Option<bvh::Hit>; PACKET],
    frames: lanes::FrameLanes,
    solved: lanes::Solved,
}

thread_local! {
    static PACKET_LANES: std::cell::RefCell<PacketLanes> = std::cell::RefCell::new(PacketLanes {
        hits: [None; PACKET],
        frames: lanes::FrameLanes::new(),
        solved: lanes::Solved::new(),
    });
}

/// What [`Sampler::shade`] gives the samples of a packet: the first as many as it shaded.
struct Shaded {
    normal: [Vec3; bvh::PACKET],
    singular: [bool; bvh::PACKET],
    /// The frame's stretch, where it is measured.
    stretch: [Option<f64>; bvh::PACKET],
}

/// How far the rays go, bounded by where the models are: no setting makes a ray longer than the
/// models are wide, so that none can make a small bake slow.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Reach {
    /// How far out along LOW's normal a ray starts.
    pub extrusion: f32,
    /// How far it goes.
    pub max_distance: f32,
    /// How far a missed ray looks for HIGH on either side of the cage: LOW's bounding radius.
    pub look: f32,
}

impl Reach {
    /// The input's distances, bounded: a cage pushed out farther than the diagonal D of the box
    /// around both models is put at D (every ray from there meets what it met from farther out,
    /// but the sums of a distance of 1e30 keep nothing of the models' size), and a ray goes no
    /// farther than the cage's distance plus D (past that it has left the box). Bakes with
    /// distances within the models' size are unchanged.
    pub fn of(input: &BakeInput) -> Reach {
        type Box3 = (Vec3, Vec3);
        let union = |(min, max): Box3, (lo, hi): Box3| (min.min(lo), max.max(hi));
        let bounds = |points: &[Vec3]| -> Box3 {
            (points.iter())
                .filter(|p| p.is_finite())
                .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |b, p| {
                    union(b, (*p, *p))
                })
        };
        let low = bounds(&input.low.vertices);
        // HIGH's a run per core (a minimum or a maximum is the same in any order); a cage's
        // points too: its rays start there.
        let high = runs_on_cores(&input.high.vertices, bounds);
        let cage = bounds(input.cage.unwrap_or_default());
        let both = high.into_iter().chain([cage]).fold(low, union);
        // Generous, so that rounding cannot cut a ray that reaches a triangle.
        let width = (both.1 - both.0).max(Vec3::ZERO).length() * 1.01 + f32::MIN_POSITIVE;
        let extrusion = input.extrusion.min(width);
        // LOW's bounding radius as its placing measures it: from its box's centre.
        let centre = (low.0 + low.1) * 0.5;
        let radius = input
            .low
            .vertices
            .iter()
            .filter(|p| p.is_finite())
            .map(|p| p.distance(centre))
            .fold(0.0, f32::max);
        Reach {
            extrusion,
            max_distance: input.max_distance.min(extrusion + width),
            look: radius,
        }
    }
}

impl Sampler<'_> {
    /// The rays of a packet's samples (LOW's triangle and barycentrics each) into `rays`, and
    /// LOW's normal at each into `normals`: from the cage point (LOW's point pushed out along the
    /// normal) back along the normal. The normals are normalized side by side ([`lanes`]).
    #[inline(always)]
    fn rays(
        &self,
        chunk: &[(usize, [f32; 3])],
        rays: &mut [bvh::Ray; bvh::PACKET],
        normals: &mut [Vec3; bvh::PACKET],
    ) {
        let low = self.input.low;
        // The corners' sum from 0, in order, as `Iterator::sum` adds (a closure over that sum
        // was a call for each point, outside the packet's compiled code).
        #[inline(always)]
        fn mix(v: &[Vec3], t: usize, b: [f32; 3]) -> Vec3 {
            let c = &v[3 * t..3 * t + 3];
            ((Vec3::ZERO + c[0] * b[0]) + c[1] * b[1]) + c[2] * b[2]
        }
        let mut positions = [Vec3::ZERO; bvh::PACKET];
        let mut unit = lanes::Vec3Lanes::new();
        for (k, &(t, b)) in chunk.iter().enumerate() {
            positions[k] = mix(&low.vertices, t, b);
            unit.set(k, mix(&low.normals, t, b));
        }
        unit.normalize_or_zero();
        for (k, &(t, b)) in chunk.iter().enumerate() {
            let (position, normal) = (positions[k], unit.get(k));
            let (origin, direction) = match self.input.cage {
                None => (position + normal * self.reach.extrusion, -normal),
                Some(cage) => {
                    let origin = mix(cage, t, b);
                    // Where the cage touches LOW the ray goes in along LOW's normal.
                    let direction = (position - origin).try_normalize().unwrap_or(-normal);
                    (origin, direction)
                }
            };
            rays[k] = bvh::Ray {
                origin,
                direction,
                max_distance: self.reach.max_distance,
            };
            normals[k] = normal;
        }
    }

    /// The samples of `batch` (LOW's triangle and barycentrics each), one for each into `out`:
    /// their rays traced [`bvh::PACKET`] at a time.
    fn samples(&self, batch: &[(usize, [f32; 3])], out: &mut Vec<Sample>) {
        PACKET_LANES.with_borrow_mut(|scratch| self.samples_with(batch, out, scratch));
    }

    /// [`Sampler::samples`] with this thread's lanes.
    fn samples_with(
        &self,
        batch: &[(usize, [f32; 3])],
        out: &mut Vec<Sample>,
        scratch: &mut PacketLanes,
    ) {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU has AVX2, which is all that `samples_avx2` is compiled for beyond
            // SSE2.
            return unsafe { self.samples_avx2(batch, out, scratch) };
        }
        self.samples_of(batch, out, scratch)
    }

    /// [`Sampler::samples_with`] compiled for AVX2 (as [`bvh::Bvh::first_hits`] is: no fused
    /// multiply-add, so every sample rounds as before).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,bmi1,popcnt")]
    unsafe fn samples_avx2(
        &self,
        batch: &[(usize, [f32; 3])],
        out: &mut Vec<Sample>,
        scratch: &mut PacketLanes,
    ) {
        self.samples_of(batch, out, scratch)
    }

    /// [`Sampler::samples_with`], for whichever instruction set it is inlined into.
    #[inline(always)]
    fn samples_of(
        &self,
        batch: &[(usize, [f32; 3])],
        out: &mut Vec<Sample>,
        scratch: &mut PacketLanes,
    ) {
        for chunk in batch.chunks(bvh::PACKET) {
            let n = chunk.len();
            let mut rays = [bvh::Ray::IDLE; bvh::PACKET];
            let mut normals = [Vec3::ZERO; bvh::PACKET];
            self.rays(chunk, &mut rays, &mut normals);
            let mut triangles = [0usize; bvh::PACKET];
            for (triangle, &(t, _)) in triangles.iter_mut().zip(chunk) {
                *triangle = t;
            }
            let triangles = &triangles[..n];
            let hits = &mut scratch.hits;
            self.targets
                .first_hits(triangles, &rays[..n], &mut hits[..n]);
            let (beyond, outside) = self.look(triangles, &rays[..n], &normals[..n], &hits[..n]);
            // HIGH's normals read for the whole packet first: each read may wait on memory, and
            // these waits overlap where the shading's long sums would not let them. They are
            // normalized side by side.
            let mut unit = lanes::Vec3Lanes::new();
            for (k, hit) in hits[..n].iter().enumerate() {
                if let Some(hit) = hit {
                    unit.set(k, self.high_normal(hit));
                }
            }
            unit.normalize_or_zero();
            let mut high = [None; bvh::PACKET];
            for (k, (high, hit)) in high.iter_mut().zip(&hits[..n]).enumerate() {
                *high = hit.map(|_| unit.get(k));
            }
            let shaded = self.shade(chunk, &normals[..n], &high[..n], scratch);
            // Each sample written once, whole (built field by field in place, its stores were
            // read back across their seams, a stall each); pushed in a loop here, where
            // `extend` was a call for each packet, outside the packet's compiled code.
            out.reserve(n);
            for k in 0..n {
                out.push(Sample {
                    normal: shaded.normal[k],
                    // A LOW part without a partner meets nothing and is not a miss: it is said
                    // once.
                    missed: high[k].is_none() && self.targets.paired(triangles[k]),
                    beyond: beyond[k],
                    outside: outside[k],
                    singular: shaded.singular[k],
                    stretch: shaded.stretch[k],
                });
            }
        }
    }

    /// Where the missed rays' HIGH is, within [`Reach::look`] of the cage: the distance along
    /// each ray past its end, and against it outside the cage. Traced as a packet of the missed
    /// rays, so that a miss costs about what a hit does.
    #[allow(clippy::type_complexity)]
    #[inline(always)]
    fn look(
        &self,
        triangles: &[usize],
        rays: &[bvh::Ray],
        normals: &[Vec3],
        hits: &[Option<bvh::Hit>],
    ) -> ([Option<f32>; bvh::PACKET], [Option<f32>; bvh::PACKET]) {
        let mut found = ([None; bvh::PACKET], [None; bvh::PACKET]);
        // The missed rays that had something to meet, packed at the front.
        let (mut missed, mut n) = ([0usize; bvh::PACKET], 0);
        for k in 0..rays.len() {
            if hits[k].is_none() && normals[k] != Vec3::ZERO && self.targets.paired(triangles[k]) {
                missed[n] = k;
                n += 1;
            }
        }
        if n == 0 {
            return found;
        }
        let missed = &missed[..n];
        let from: [usize; bvh::PACKET] =
            std::array::from_fn(|j| missed.get(j).map_or(0, |&k| triangles[k]));
        for (sign, into) in [(1.0, &mut found.0), (-1.0, &mut found.1)] {
            let mut looks = [bvh::Ray::IDLE; bvh::PACKET];
            for (look, &k) in looks.iter_mut().zip(missed) {
                *look = bvh::Ray {
                    origin: rays[k].origin,
                    direction: rays[k].direction * sign,
                    max_distance: self.reach.look,
                };
            }
            let mut hits = [None; bvh::PACKET];
            (self.targets).first_hits(&from[..n], &looks[..n], &mut hits[..n]);
            for (&k, hit) in missed.iter().zip(&hits[..n]) {
                into[k] = hit.map(|h| h.distance);
            }
        }
        found
    }

    /// The map's normal of each sample of `chunk` (at barycentrics `b` of LOW's triangle `t`
    /// each, LOW's normal there in `normals`), given HIGH's normal where each ray met HIGH
    /// (`None`: it met nothing). Each step is taken for the whole chunk before the next, so that
    /// one sample's long divisions and square roots overlap the others'.
    #[inline(always)]
    fn shade(
        &self,
        chunk: &[(usize, [f32; 3])],
        normals: &[Vec3],
        high: &[Option<Vec3>],
        scratch: &mut PacketLanes,
    ) -> Shaded {
        let mut shaded = Shaded {
            normal: [Vec3::Z; bvh::PACKET],
            singular: [false; bvh::PACKET],
            stretch: [None; bvh::PACKET],
        };
        if self.space == Space::Object {
            for ((out, high), normal) in shaded.normal.iter_mut().zip(high).zip(normals) {
                // A miss keeps LOW's own normal: the object-space map's "flat"; so does a hit
                // where HIGH's normal has no direction (a file normal of 0, or one too long to
                // square in f32), which the tangent-space map writes flat too.
                *out = match high.filter(|n| *n != Vec3::ZERO) {
                    Some(n) => n,
                    None if *normal == Vec3::ZERO => Vec3::Z,
                    None => *normal,
                };
            }
            return shaded;
        }
        // t = (T B N)⁻¹ n, where the frame has an inverse: the packet's solves side by side.
        let PacketLanes {
            frames: lanes,
            solved,
            ..
        } = scratch;
        self.input.frames.at_lanes(chunk, &mut lanes.columns);
        for (k, high) in high.iter().enumerate() {
            if self.measure_skew {
                shaded.stretch[k] = Some(stretch(&lanes.frame(k)));
            }
            if let Some(n) = high {
                lanes.set_high(k, *n);
            }
        }
        lanes::solve(lanes, solved);
        for (k, high) in high.iter().enumerate() {
            if high.is_none() {
                continue;
            }
            if !solved.invertible[k] {
                shaded.singular[k] = true;
                continue;
            }
            let [x, y, z] = &solved.normal;
            let t = DVec3::new(x[k], y[k], z[k]);
            if t != DVec3::ZERO {
                shaded.normal[k] = t.as_vec3();
            }
        }
        shaded
    }

    /// HIGH's normal where the ray met it, before it is normalized: interpolated, or the face's.
    #[inline(always)]
    fn high_normal(&self, hit: &bvh::Hit) -> Vec3 {
        let n = &hit.data;
        if self.input.high_face_normals {
            n[0]
        } else {
            n[0] * (1.0 - hit.u - hit.v) + n[1] * hit.u + n[2] * hit.v
        }
    }
}

/// The files' side of a bake: both models read, HIGH moved into LOW's placed space, LOW's frames.
pub struct BakeFiles {
    /// HIGH as read, its soup moved to `high_soup`.
    pub high: Model,
    pub low: Model,
    /// HIGH's positions in LOW's placed space.
    pub high_soup: TriangleSoup,
    pub frames: CornerFrames,
    /// Placed units per LOW file unit.
    pub scale: f32,
    /// The cage's corners in LOW's placed space ([`BakeFiles::load_cage`]).
    pub cage: Option<Vec<Vec3>>,
    /// LOW's parts paired with HIGH's ([`BakeFiles::match_names`]).
    pub pairing: Option<Pairing>,
}

impl BakeFiles {
    /// Reads HIGH and LOW (anything `--model` reads) and computes LOW's frame for `settings`;
    /// refuses the per-pixel frame first ([`NO_PER_PIXEL_BAKE`]).
    pub fn load(high_path: &Path, low_path: &Path, settings: &BakeSettings) -> Result<BakeFiles> {
        if !settings.tangents.has_vertex_tangents() {
            return Err(Error::Argument(format!(
                "--tangents derivative: {NO_PER_PIXEL_BAKE}"
            )));
        }
        let clock = Instant::now();
        // One thread (the browser has no other): one file after the other.
        let (high, low) = if settings.threads <= 1 {
            let high = crate::model::load_shape(high_path);
            (high, load_model(low_path, &MapOverrides::default()))
        } else {
            let (low, high) = join(
                || load_model(low_path, &MapOverrides::default()),
                || crate::model::load_shape(high_path),
            );
            (high, low)
        };
        let (mut high, low) = (high?, low?);
        // HIGH's notices say what was filled in (UVs, normals); LOW's maps do not matter here.
        for notice in &high.notices {
            log::info!("{notice}");
        }
        log::info!(
            "bake: read {} and {} in {:.2} s",
            high_path.display(),
            low_path.display(),
            clock.elapsed().as_secs_f64()
        );
        let clock = Instant::now();
        // Each model was placed on the tutorial's cylinder by its own bounding sphere: HIGH goes back
        // to its file's coordinates, then where LOW's placing puts them. The soup is moved out of
        // the model, not copied: HIGH's millions of corners are only read by the rays from here on.
        let mut high_soup = std::mem::take(&mut high.soup);
        each_on_cores(&mut high_soup.vertices, |p| {
            *p = low.placement.to_world(high.placement.to_file(*p));
        });
        let frames = match settings.tangents {
            TangentSource::MikkTSpace => CornerFrames::mikktspace(
                &low.soup,
                &crate::tangent_source::mikktspace_tangents(&low.soup)?,
            ),
            TangentSource::File => {
                let file = low.file_tangents.as_ref().ok_or_else(|| Error::Bake {
                    path: low_path.to_path_buf(),
                    reason: "--tangents file: the file has no TANGENT (a glTF exported with \
                             tangents has them); --tangents mikktspace computes the same \
                             convention"
                        .into(),
                })?;
                CornerFrames::mikktspace(&low.soup, &file.complete(&low.soup)?)
            }
            TangentSource::Tutorial => CornerFrames::tutorial(&low.soup, settings.normalize_tbn),
            TangentSource::Derivative => unreachable!("refused before the files are read"),
        };
        log::info!(
            "bake: LOW's frames in {:.2} s",
            clock.elapsed().as_secs_f64()
        );
        let scale = low.placement.scale();
        Ok(BakeFiles {
            high,
            low,
            high_soup,
            frames,
            scale,
            cage: None,
            pairing: None,
        })
    }

    /// Reads a cage for LOW (anything `--model` reads, its UVs not used): LOW's faces in LOW's
    /// order, its corners moved ([`cage`]).
    pub fn load_cage(&mut self, path: &Path) -> Result<()> {
        let cage = crate::model::load_shape(path)?;
        let corners = cage::cage_corners(&cage, &self.low).map_err(|reason| Error::Bake {
            path: path.to_path_buf(),
            reason: format!("not a cage for LOW: {reason}"),
        })?;
        let (split, shared) = (
            cage::vertex_count(&cage.soup.vertices),
            cage::vertex_count(&self.low.soup.vertices),
        );
        if split > shared {
            log::info!(
                "{}: the cage has {split} vertices where LOW has {shared}: where it splits one of \
             LOW's vertices (a hard edge pushed apart) its rays leave a gap",
                path.display()
            );
        }
        self.cage = Some(corners);
        Ok(())
    }

    /// Pairs LOW's parts with HIGH's by name ([`parts`]): refused where no name pairs.
    pub fn match_names(&mut self) -> Result<&Pairing> {
        let clock = Instant::now();
        let read = crate::files::read;
        let high =
            crate::model::parts::part_names(&self.high, self.high_soup.triangle_count(), read)?;
        let low = crate::model::parts::part_names(&self.low, self.low.soup.triangle_count(), read)?;
        let pairing = Pairing::new(&low, &high);
        log::info!(
            "bake: parts named and paired in {:.2} s",
            clock.elapsed().as_secs_f64()
        );
        if pairing.pairs.is_empty() {
            let list = |names: &[String]| -> String {
                let quoted = |n: &String| match n.as_str() {
                    "" => "(unnamed)".to_string(),
                    n => format!("'{n}'"),
                };
                let shown: Vec<String> = names.iter().take(6).map(quoted).collect();
                let more = names.len().saturating_sub(6);
                match more {
                    0 => shown.join(", "),
                    _ => format!("{} and {more} more", shown.join(", ")),
                }
            };
            return Err(Error::Bake {
                path: self.low.path.clone(),
                reason: format!(
                    "--match-names: no part's name pairs with one of {} (LOW's parts: {}; \
                     HIGH's: {}); names pair without their suffixes _low/_lp and _high/_hp, case \
                     ignored",
                    self.high.path.display(),
                    list(&low.names),
                    list(&high.names)
                ),
            });
        }
        Ok(self.pairing.insert(pairing))
    }

    /// The bake, with `extrusion` and `max_distance` in LOW's file units.
    pub fn bake(&self, settings: &BakeSettings) -> Result<BakedMap> {
        self.bake_with(settings, None)
    }

    /// [`BakeFiles::bake`], telling `progress` how far it is.
    pub fn bake_with(
        &self,
        settings: &BakeSettings,
        progress: Option<BakeProgress>,
    ) -> Result<BakedMap> {
        // With a cage, no maximum distance is no bound (Blender's `max_ray_distance` 0).
        let max_distance = match self.cage.is_some() && settings.max_distance == 0.0 {
            true => f32::INFINITY,
            false => settings.max_distance * self.scale,
        };
        let input = BakeInput {
            low: &self.low.soup,
            frames: &self.frames,
            high: &self.high_soup,
            high_face_normals: self.high.normals_computed,
            extrusion: settings.extrusion * self.scale,
            max_distance,
            cage: self.cage.as_deref(),
            pairing: self.pairing.as_ref(),
        };
        let map = bake_soups_with(&input, settings, progress);
        if map.stats.covered == 0 {
            return Err(Error::Bake {
                path: self.low.path.clone(),
                reason: format!(
                    "no texel of the {}×{} map is covered: its triangles have no area in UV \
                     space, or lie outside 0..1 (a bake needs LOW's UV layout)",
                    settings.width, settings.height
                ),
            });
        }
        Ok(map)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Fails if a packet's frames mixed lane by lane are not `CornerFrames::at`'s, to the bit, for
    /// MikkTSpace's frames (signs, B = ±N × T) and the tutorial's (B mixed as given): packets of
    /// runs on one triangle and of single samples, weights of 0 and −0, signs of 0, corners of
    /// every size, and a packet shorter than [`PACKET`].
    #[test]
    fn a_packets_frames_in_lanes_are_each_samples_own() {
        let mut next = xorshift(0xf4a3e5);
        let mut value = move || {
            let r = next();
            let x = (r >> 40) as f32 / (1u64 << 24) as f32 * 2.0 - 1.0;
            match r % 16 {
                0 => 0.0,
                1 => -0.0,
                2 => x * 1e30,
                3 => x * 1e-30,
                _ => x,
            }
        };
        let triangles = 40;
        let mut corners = |n: usize| -> Vec<Vec3> {
            (0..3 * n)
                .map(|_| Vec3::new(value(), value(), value()))
                .collect()
        };
        let (tangents, normals, given) =
            (corners(triangles), corners(triangles), corners(triangles));
        let signs: Vec<f32> = (0..3 * triangles)
            .map(|k| [1.0, -1.0, 0.0, -0.0][k % 4])
            .collect();
        let frames = [
            CornerFrames {
                tangents: tangents.clone(),
                normals: normals.clone(),
                bitangents: Bitangents::Signs(signs),
            },
            CornerFrames {
                tangents,
                normals,
                bitangents: Bitangents::Given(given),
            },
        ];
        let mut pick = xorshift(0x5a3b1e);
        for packet in 0..400 {
            let length = if packet % 5 == 0 {
                1 + (pick() % PACKET as u64) as usize
            } else {
                PACKET
            };
            let mut chunk = Vec::new();
            while chunk.len() < length {
                let t = (pick() % triangles as u64) as usize;
                // Runs of a texel's sixteen, of one, or of a few.
                let run = [16, 1, 3, 64][(pick() % 4) as usize];
                for _ in 0..run.min(length - chunk.len()) {
                    let b = [0, 1, 2].map(|_| match pick() % 8 {
                        0 => 0.0,
                        1 => -0.0,
                        r => (r as f32 * 0.37).fract(),
                    });
                    chunk.push((t, b));
                }
            }
            for frames in &frames {
                let mut columns = [[[f64::NAN; PACKET]; 3]; 3];
                frames.at_lanes(&chunk, &mut columns);
                for (k, &(t, b)) in chunk.iter().enumerate() {
                    let lane = columns.map(|[x, y, z]| [x[k], y[k], z[k]].map(f64::to_bits));
                    let alone = frames.at(t, b).map(|c| c.to_array().map(f64::to_bits));
                    assert_eq!(
                        lane, alone,
                        "packet {packet}, lane {k}: triangle {t} at {b:?}"
                    );
                }
            }
        }
    }
}

#[cfg(test)]
mod packet_lanes {
    use super::*;
    use glam::Vec2;

    /// A quad in z = 0 (UVs 0..1) as LOW, its frames with triangle 1's T along N where `singular`,
    /// and as HIGH a wavy sheet above it, over all of it or over its lower half only (V < 0.5: the
    /// map's lower rows, baked last, so that its first packets meet nothing).
    fn pair(singular: bool, half: bool) -> (TriangleSoup, CornerFrames, TriangleSoup) {
        let corners = [
            Vec2::ZERO,
            Vec2::X,
            Vec2::ONE,
            Vec2::ZERO,
            Vec2::ONE,
            Vec2::Y,
        ];
        let low = TriangleSoup {
            vertices: corners.iter().map(|c| c.extend(0.0)).collect(),
            uvs: corners.to_vec(),
            normals: vec![Vec3::Z; 6],
        };
        let mut frames = CornerFrames::tutorial(&low, false);
        if singular {
            frames.tangents[3..].fill(Vec3::Z);
        }
        let (columns, top) = (24, if half { 0.5 } else { 1.0 });
        let at = |i: usize, j: usize| {
            let (x, y) = (i as f32 / columns as f32, top * j as f32 / columns as f32);
            Vec3::new(x, y, 0.02 * (9.0 * x).sin() * (7.0 * y).cos())
        };
        let mut vertices = Vec::new();
        for j in 0..columns {
            for i in 0..columns {
                let quad = [at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)];
                vertices.extend([quad[0], quad[1], quad[2], quad[0], quad[2], quad[3]]);
            }
        }
        let high = TriangleSoup {
            uvs: vec![Vec2::ZERO; vertices.len()],
            normals: vec![Vec3::Z; vertices.len()],
            vertices,
        };
        (low, frames, high)
    }

    fn bake((low, frames, high): &(TriangleSoup, CornerFrames, TriangleSoup)) -> BakedMap {
        let input = BakeInput {
            low,
            frames,
            high,
            high_face_normals: true,
            extrusion: 0.1,
            max_distance: 0.2,
            cage: None,
            pairing: None,
        };
        let settings = BakeSettings {
            width: 24,
            height: 24,
            samples: 3,
            margin: 2,
            threads: 1,
            ..BakeSettings::default()
        };
        bake_soups(&input, &settings)
    }

    /// Fails if a packet reads a lane its thread's arrays kept from an earlier one (the arrays are
    /// not zeroed from packet to packet): a bake with misses and frames without an inverse gives
    /// the same map, to the bit, on a thread of its own and on a thread that baked another pair
    /// first, whose every ray met HIGH in an invertible frame.
    #[test]
    fn a_packet_reads_no_lane_an_earlier_one_left() {
        let (full, gaps) = (pair(false, false), pair(true, true));
        let alone = std::thread::scope(|s| s.spawn(|| bake(&gaps)).join().unwrap());
        let after = std::thread::scope(|s| {
            s.spawn(|| {
                assert_eq!(bake(&full).stats.missed, 0);
                bake(&gaps)
            })
            .join()
            .unwrap()
        });
        assert!(alone.stats.missed > 0 && alone.stats.singular > 0);
        let bits = |map: &BakedMap| -> Vec<[u32; 3]> {
            map.normals
                .iter()
                .map(|n| n.to_array().map(f32::to_bits))
                .collect()
        };
        assert!(bits(&after) == bits(&alone));
        assert_eq!(after.states, alone.states);
        assert_eq!(format!("{:?}", after.stats), format!("{:?}", alone.stats));
    }
}

#[cfg(test)]
mod found_by_fuzzing {
    use super::*;

    /// Fails if an object-space map holds a zero vector where the ray met HIGH at a normal with no
    /// direction (HIGH's file normals 0, or 1e38 long, whose square overflows f32): found by the
    /// `bake` fuzz target (fuzz/regressions/bake/); LOW's own normal is the right value there.
    #[test]
    fn an_object_space_texel_is_unit_where_high_has_no_normal() {
        let triangle = vec![Vec3::ZERO, Vec3::X, Vec3::Y];
        let low = TriangleSoup {
            vertices: triangle.clone(),
            uvs: vec![glam::Vec2::ZERO, glam::Vec2::X, glam::Vec2::Y],
            normals: vec![Vec3::Z; 3],
        };
        let frames = CornerFrames::tutorial(&low, false);
        for high_normals in [vec![Vec3::ZERO; 3], vec![Vec3::new(1e38, 1e38, 0.0); 3]] {
            let high = TriangleSoup {
                vertices: triangle.clone(),
                uvs: vec![glam::Vec2::ZERO; 3],
                normals: high_normals,
            };
            let input = BakeInput {
                low: &low,
                frames: &frames,
                high: &high,
                high_face_normals: false,
                extrusion: 0.1,
                max_distance: 0.2,
                cage: None,
                pairing: None,
            };
            let settings = BakeSettings {
                width: 8,
                height: 8,
                margin: 0,
                space: Space::Object,
                threads: 1,
                ..BakeSettings::default()
            };
            let map = bake_soups(&input, &settings);
            assert!(map.stats.covered > 0 && map.stats.missed == 0);
            // LOW's normal, +Z, on the covered texels; +Z on the others.
            let wrong = map.normals.iter().find(|n| **n != Vec3::Z);
            assert_eq!(wrong, None, "HIGH's normals {}", high.normals[0]);
        }
    }
}
