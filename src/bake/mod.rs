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
//! The frames ([`Tangents`]):
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
pub mod parts;
mod texels;

use std::path::Path;

use glam::{DMat3, DVec3, Vec3};

use crate::clock::Instant;
use crate::common::objloader::TriangleSoup;
use crate::mesh::{build_mesh, MeshOptions};
use crate::model::{load_model, MapOverrides, Model};
use crate::tangent_source::stretch;
use crate::{Error, Result};

pub use parts::Pairing;
pub use texels::{TexelState, UvLayout};

/// The frame the map is baked for.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum Tangents {
    /// MikkTSpace, computed from LOW (glTF's and Blender's convention)
    #[default]
    #[value(name = "mikktspace")]
    MikkTSpace,
    /// LOW's own TANGENTs (a glTF that has them; MikkTSpace's where a primitive has none)
    File,
    /// The tutorial's computeTangentBasis + indexVBO_TBN (summed, as its shader takes them)
    Tutorial,
}

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
    pub tangents: Tangents,
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
            tangents: Tangents::MikkTSpace,
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
    /// Of those, rays that meet HIGH farther on (a longer `--max-distance` would reach it).
    pub missed_beyond: usize,
    /// Of those, rays whose cage point has HIGH outside it (a larger `--extrusion` would enclose it).
    pub missed_outside: usize,
    /// Texels where two triangles' UVs claim one sample (mirrored or overlapping islands).
    pub overlapping: usize,
    /// LOW's triangles with no area in UV space (they cover nothing).
    pub flat_uv_triangles: usize,
    /// Samples whose frame has no inverse (T, B and N in one plane): flat normal written.
    pub singular: usize,
    /// For the tutorial's frame.
    pub skew: Option<Skew>,
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

/// The bake on soups already in one space: raster, rays and margin.
pub fn bake_soups(input: &BakeInput, settings: &BakeSettings) -> BakedMap {
    let clock = Instant::now();
    let targets = parts::Targets::build(input.high, input.pairing, settings.threads);
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
    };
    let mut map = layout.bake(settings.threads, |t, b| sampler.sample(t, b));
    log::info!(
        "bake: {} rays in {:.2} s",
        map.stats.rays,
        clock.elapsed().as_secs_f64()
    );
    let clock = Instant::now();
    map.stats.margin = texels::fill_margin(
        settings.width as usize,
        settings.height as usize,
        &mut map.normals,
        &mut map.states,
        settings.margin as usize,
    );
    log::info!(
        "bake: margin of {} in {:.2} s",
        settings.margin,
        clock.elapsed().as_secs_f64()
    );
    map
}

/// One sample's ray and its normal in the map's space.
struct Sampler<'a> {
    input: &'a BakeInput<'a>,
    targets: &'a parts::Targets<'a>,
    space: Space,
    measure_skew: bool,
}

/// What one sample gives.
pub(crate) struct Sample {
    pub normal: Vec3,
    pub missed: bool,
    pub missed_beyond: bool,
    pub missed_outside: bool,
    pub singular: bool,
    /// The frame's stretch, where it is measured.
    pub stretch: Option<f64>,
}

impl Sampler<'_> {
    fn sample(&self, t: usize, b: [f32; 3]) -> Sample {
        let low = self.input.low;
        let mix = |v: &[Vec3]| -> Vec3 { (0..3).map(|i| v[3 * t + i] * b[i]).sum() };
        let position = mix(&low.vertices);
        let normal = mix(&low.normals).normalize_or_zero();
        let (origin, direction) = match self.input.cage {
            None => (position + normal * self.input.extrusion, -normal),
            Some(cage) => {
                let origin = mix(cage);
                // Where the cage touches LOW the ray goes in along LOW's normal.
                let direction = (position - origin).try_normalize().unwrap_or(-normal);
                (origin, direction)
            }
        };
        let max_distance = self.input.max_distance;
        // A LOW part without a partner meets nothing and is not a miss: it is said once.
        let paired = self.targets.paired(t);
        let hit = self.targets.first_hit(t, origin, direction, max_distance);
        let missed = hit.is_none() && paired;
        // Where a missed ray's HIGH is: past its end, or outside the cage.
        let look = |direction: Vec3, bounded: bool| {
            missed
                && bounded
                && direction != Vec3::ZERO
                && self
                    .targets
                    .first_hit(t, origin, direction, f32::INFINITY)
                    .is_some()
        };
        let high_normal = hit.map(|hit| self.high_normal(hit));
        let mut sample = Sample {
            normal: Vec3::Z,
            missed,
            missed_beyond: look(direction, max_distance < f32::INFINITY),
            missed_outside: look(-direction, true),
            singular: false,
            stretch: None,
        };
        if self.space == Space::Object {
            // A miss keeps LOW's own normal: the object-space map's "flat"; so does a hit where
            // HIGH's normal has no direction (a file normal of 0, or one too long to square in
            // f32), which the tangent-space map writes flat too.
            sample.normal = match high_normal.filter(|n| *n != Vec3::ZERO) {
                Some(n) => n,
                None if normal == Vec3::ZERO => Vec3::Z,
                None => normal,
            };
            return sample;
        }
        let frame = self.input.frames.at(t, b);
        if self.measure_skew {
            sample.stretch = Some(stretch(&frame));
        }
        match high_normal {
            None => {}
            Some(n) => {
                let matrix = DMat3::from_cols(frame[0], frame[1], frame[2]);
                let det = matrix.determinant();
                let scale = frame.iter().map(|c| c.length()).product::<f64>();
                // A frame whose columns span no volume (relative to their lengths) has no inverse.
                if det.abs() > 1e-9 * scale && det.is_finite() {
                    let t = (matrix.inverse() * n.as_dvec3()).normalize_or_zero();
                    if t != DVec3::ZERO {
                        sample.normal = t.as_vec3();
                    }
                } else {
                    sample.singular = true;
                }
            }
        }
        sample
    }

    /// HIGH's normal where the ray met it: interpolated, or the face's.
    fn high_normal(&self, hit: bvh::Hit) -> Vec3 {
        let high = self.input.high;
        let t = hit.triangle as usize;
        let corners = 3 * t..3 * t + 3;
        let n = if self.input.high_face_normals {
            let p = &high.vertices[corners];
            (p[1] - p[0]).cross(p[2] - p[0])
        } else {
            let n = &high.normals[corners];
            n[0] * (1.0 - hit.u - hit.v) + n[1] * hit.u + n[2] * hit.v
        };
        n.normalize_or_zero()
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
    /// Reads HIGH and LOW (anything `--model` reads) and computes LOW's frame for `settings`.
    pub fn load(high_path: &Path, low_path: &Path, settings: &BakeSettings) -> Result<BakeFiles> {
        let clock = Instant::now();
        let (high, low) = std::thread::scope(|scope| {
            let high = scope.spawn(|| crate::model::load_shape(high_path));
            let low = load_model(low_path, &MapOverrides::default());
            let high = high
                .join()
                .unwrap_or_else(|panic| std::panic::resume_unwind(panic));
            (high, low)
        });
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
        for p in &mut high_soup.vertices {
            *p = low.placement.to_world(high.placement.to_file(*p));
        }
        let frames = match settings.tangents {
            Tangents::MikkTSpace => CornerFrames::mikktspace(
                &low.soup,
                &crate::tangent_source::mikktspace_tangents(&low.soup)?,
            ),
            Tangents::File => {
                let file = low.file_tangents.as_ref().ok_or_else(|| Error::Bake {
                    path: low_path.to_path_buf(),
                    reason: "--tangents file: the file has no TANGENT (a glTF exported with \
                             tangents has them); --tangents mikktspace computes the same \
                             convention"
                        .into(),
                })?;
                CornerFrames::mikktspace(&low.soup, &file.complete(&low.soup)?)
            }
            Tangents::Tutorial => CornerFrames::tutorial(&low.soup, settings.normalize_tbn),
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
        let map = bake_soups(&input, settings);
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
