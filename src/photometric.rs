//! Photometric stereo, the tutorial's "make your own normal maps out of several photos", as
//! `tutorial13 photometric PHOTO... --light X,Y,Z ... -o NORMAL.png [--albedo ALBEDO.png]`.
//!
//! Three or more photos from one camera position, each lit by one distant light from a known
//! direction l (x to the photo's right, y up it, z out of the surface towards the camera; made unit
//! here, so every photo is taken as equally bright: same lamp, same distance, same exposure). A
//! matte (Lambertian) texel of albedo ρ and unit normal n shows, in linear light,
//! I = ρ · max(0, n·l). Where it is lit, I = lᵀg with g = ρn, so three or more photos give g by
//! least squares, g = (Σ l lᵀ)⁻¹ Σ l I, then n = g / |g| and ρ = |g|. The solve uses each photo's
//! luminance; each colour channel's albedo is that channel's g projected on n.
//!
//! A texel that is near black in a photo (its linear luminance below `shadow`: the light does not
//! reach it, and max(0, ·) hides how far) or saturated (a channel at 98 % of full scale or more: a
//! highlight, or clipped) is left out of that texel's solve. Which photos are kept is a bitmask per
//! texel, and the 3×3 inverse depends only on it: each mask's columns (Σ l lᵀ)⁻¹ l_k are computed
//! once, the first time a band of rows meets it, so a texel costs K multiply-adds.
//!
//! Lights that (nearly) share a plane cannot tell how far a normal leans out of it. The measure is
//! the light directions' root-mean-square angle to the plane that fits them best: the square root of
//! the smallest eigenvalue of (1/K) Σ l lᵀ is its sine. Below [`MIN_SPREAD_DEGREES`] the whole set
//! is refused; a texel whose own kept photos are below it (say, three neighbours of a ring of eight)
//! is solved no better than one with fewer than three, and both get the flat normal and are counted.

use std::path::{Path, PathBuf};

use glam::{DMat3, DVec3, Vec3, Vec4};
use rustc_hash::FxHashMap;

use crate::normalmap::{encode_normal, map_format, write_normal_map, Green};
use crate::photo::{Encoding, Photo, Samples, LUMINANCE};
use crate::{Error, Result};

/// Below this spread of the light directions out of one plane, they are refused as coplanar.
pub const MIN_SPREAD_DEGREES: f64 = 5.0;
/// A channel at this fraction of full scale or above is saturated.
pub const SATURATED: f64 = 0.98;
/// The default `--shadow`: linear luminance below which a texel counts as unlit (about sRGB 25/255).
pub const DEFAULT_SHADOW: f32 = 0.01;
/// Which photos a texel keeps is a 64-bit mask.
pub const MAX_PHOTOS: usize = 64;
/// Steps of the albedo encoder's table over linear light: fine enough (1.5e-5 each) that no step
/// holds two midpoints between 8-bit values (the closest, near black in sRGB, are 1 / (255 · 12.92)
/// = 3.0e-4 apart), so one comparison finishes the table's guess.
const COARSE: usize = 1 << 16;

/// How to read the photos and what to make.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PhotometricOptions {
    pub encoding: Encoding,
    pub green: Green,
    /// Linear luminance below which a photo's texel is left out as shadow.
    pub shadow: f32,
    /// Compute the albedo map too.
    pub albedo: bool,
    /// Bands of rows solved at once (1 = this thread only).
    pub threads: usize,
}

impl Default for PhotometricOptions {
    fn default() -> Self {
        PhotometricOptions {
            encoding: Encoding::Srgb,
            green: Green::Up,
            shadow: DEFAULT_SHADOW,
            albedo: false,
            threads: 1,
        }
    }
}

/// What the photos gave.
#[derive(Debug, Clone, PartialEq)]
pub struct Recovered {
    pub width: u32,
    pub height: u32,
    /// The normal map's texels, row 0 at the top.
    pub normals: Vec<[u8; 3]>,
    /// The albedo, encoded as the photos were (sRGB unless linear), if asked for.
    pub albedo: Option<Vec<[u8; 3]>>,
    /// Texels left flat: fewer than three photos kept, or their lights nearly coplanar.
    pub unsolved: usize,
}

/// One `--light X,Y,Z`: three finite numbers, not all zero (any length: only the direction counts).
pub fn parse_light(text: &str) -> Result<Vec3> {
    let bad = |why: &str| Error::Photometric(format!("--light {text}: {why}"));
    let numbers: Vec<f32> = text
        .split(',')
        .map(|n| n.trim().parse::<f32>())
        .collect::<std::result::Result<_, _>>()
        .map_err(|_| bad("not three numbers X,Y,Z (e.g. --light -1,0,1)"))?;
    let [x, y, z] = numbers[..] else {
        return Err(bad("not three numbers X,Y,Z (e.g. --light -1,0,1)"));
    };
    let light = Vec3::new(x, y, z);
    if !light.is_finite() || light == Vec3::ZERO {
        return Err(bad("not a direction (all zero, or not finite)"));
    }
    Ok(light)
}

/// The lights' root-mean-square angle, in degrees, to the plane that fits them best (0 when they
/// are coplanar or all the same).
pub fn light_spread_degrees(lights: &[DVec3]) -> f64 {
    let m = scatter(lights.iter()) * (1.0 / lights.len() as f64);
    smallest_eigenvalue(&m)
        .clamp(0.0, 1.0)
        .sqrt()
        .asin()
        .to_degrees()
}

/// Σ l lᵀ over `lights`.
fn scatter<'a>(lights: impl Iterator<Item = &'a DVec3>) -> DMat3 {
    lights.fold(DMat3::ZERO, |m, &l| {
        m + DMat3::from_cols(l * l.x, l * l.y, l * l.z)
    })
}

/// The smallest eigenvalue of a symmetric 3×3 matrix (the trigonometric closed form).
fn smallest_eigenvalue(m: &DMat3) -> f64 {
    let a = |r: usize, c: usize| m.col(c)[r];
    let off = a(0, 1).powi(2) + a(0, 2).powi(2) + a(1, 2).powi(2);
    let q = (a(0, 0) + a(1, 1) + a(2, 2)) / 3.0;
    let p2 = (a(0, 0) - q).powi(2) + (a(1, 1) - q).powi(2) + (a(2, 2) - q).powi(2) + 2.0 * off;
    if p2 <= 1e-30 {
        return q;
    }
    let p = (p2 / 6.0).sqrt();
    let b = (*m - DMat3::from_diagonal(DVec3::splat(q))) * (1.0 / p);
    let phi = (b.determinant() / 2.0).clamp(-1.0, 1.0).acos() / 3.0;
    q + 2.0 * p * (phi + 2.0 * std::f64::consts::FRAC_PI_3).cos()
}

/// Unit directions of `lights`, one per photo, refused if there are not `photos` of them or if they
/// are (nearly) coplanar.
fn unit_lights(lights: &[Vec3], photos: usize) -> Result<Vec<DVec3>> {
    if photos < 3 {
        return Err(Error::Photometric(format!(
            "photometric stereo needs at least three photos, each under its own light; got {photos}"
        )));
    }
    if photos > MAX_PHOTOS {
        return Err(Error::Photometric(format!(
            "{photos} photos: at most {MAX_PHOTOS} are read"
        )));
    }
    if lights.len() != photos {
        return Err(Error::Photometric(format!(
            "{photos} photos but {} --light directions: give one --light X,Y,Z per photo, in the \
             photos' order",
            lights.len()
        )));
    }
    let unit: Vec<DVec3> = lights.iter().map(|l| l.as_dvec3().normalize()).collect();
    let spread = light_spread_degrees(&unit);
    if spread < MIN_SPREAD_DEGREES {
        return Err(Error::Photometric(format!(
            "the --light directions are nearly coplanar (within {spread:.1}° of one plane, at least \
             {MIN_SPREAD_DEGREES}° needed): the photos cannot tell how far a normal leans out of \
             that plane; light some photos from higher or lower"
        )));
    }
    Ok(unit)
}

/// Normals (and albedo) of the texels of `photos` (same size, all 8-bit or all 16-bit), lit by
/// `lights` in order. Errors: fewer than three photos, a light count that differs, coplanar lights.
pub fn recover(
    photos: &[Photo],
    lights: &[Vec3],
    options: &PhotometricOptions,
) -> Result<Recovered> {
    let lights = unit_lights(lights, photos.len())?;
    let (width, height) = (photos[0].width, photos[0].height);
    let texels = width as usize * height as usize;
    let bits = photos[0].bits();
    let samples = |p: &Photo| match &p.samples {
        Samples::Eight(v) => v.len(),
        Samples::Sixteen(v) => v.len(),
    };
    if photos
        .iter()
        .any(|p| (p.width, p.height, p.bits()) != (width, height, bits) || samples(p) != 3 * texels)
    {
        return Err(Error::Photometric(
            "photos of different sizes or bit depths (see load_photos)".into(),
        ));
    }
    let solver = Solver::new(&lights, bits, options);
    let mut normals = vec![[0u8; 3]; texels];
    let mut albedo = vec![[0u8; 3]; if options.albedo { texels } else { 0 }];
    // Whole rows per band; each band keeps its own cache of solves.
    let rows = (height as usize).div_ceil(options.threads.max(1)).max(1);
    let band = (rows * width as usize).max(1);
    let albedo_bands = albedo.chunks_mut(band).map(Some);
    let bands: Vec<_> = normals
        .chunks_mut(band)
        .zip(albedo_bands.chain(std::iter::repeat_with(|| None)))
        .enumerate()
        .collect();
    let unsolved = std::thread::scope(|scope| {
        let handles: Vec<_> = bands
            .into_iter()
            .map(|(i, (normals, albedo))| {
                let solver = &solver;
                let first = i * band;
                scope.spawn(move || match &photos[0].samples {
                    Samples::Eight(_) => solver.band(photos, eight, first, normals, albedo),
                    Samples::Sixteen(_) => solver.band(photos, sixteen, first, normals, albedo),
                })
            })
            .collect();
        handles
            .into_iter()
            .map(|h| h.join().expect("a band of rows panicked"))
            .sum()
    });
    Ok(Recovered {
        width,
        height,
        normals,
        albedo: options.albedo.then_some(albedo),
        unsolved,
    })
}

fn eight(photo: &Photo) -> &[u8] {
    match &photo.samples {
        Samples::Eight(v) => v,
        Samples::Sixteen(_) => unreachable!("checked: every photo has the first one's depth"),
    }
}

fn sixteen(photo: &Photo) -> &[u16] {
    match &photo.samples {
        Samples::Sixteen(v) => v,
        Samples::Eight(_) => unreachable!("checked: every photo has the first one's depth"),
    }
}

/// What every band of rows shares.
struct Solver<'a> {
    lights: &'a [DVec3],
    /// Stored value → linear light.
    table: Vec<f32>,
    /// Stored values from here up are saturated.
    saturated: usize,
    /// For the albedo's encoding: the midpoints between 8-bit values in linear light, and for
    /// each of `COARSE` equal steps of linear light the 8-bit value at its start.
    midpoints: Vec<f32>,
    coarse: Vec<u8>,
    options: &'a PhotometricOptions,
}

impl<'a> Solver<'a> {
    fn new(lights: &'a [DVec3], bits: u32, options: &'a PhotometricOptions) -> Self {
        let midpoints = options.encoding.midpoints();
        Solver {
            lights,
            table: options.encoding.table(bits),
            saturated: (SATURATED * f64::from((1u32 << bits) - 1)).ceil() as usize,
            coarse: (0..=COARSE)
                .map(|i| midpoints.partition_point(|&m| m <= i as f32 / COARSE as f32) as u8)
                .collect(),
            midpoints,
            options,
        }
    }

    /// Solves the texels from `first` on, as many as `normals` holds; returns how many were left flat.
    fn band<T: Copy + Into<usize>>(
        &self,
        photos: &[Photo],
        samples: fn(&Photo) -> &[T],
        first: usize,
        normals: &mut [[u8; 3]],
        mut albedo: Option<&mut [[u8; 3]]>,
    ) -> usize {
        let planes: Vec<&[T]> = photos.iter().map(samples).collect();
        let mut solves = Solves::new(self.lights);
        // Per photo, the current texel in linear light: red, green, blue, luminance.
        let mut light = vec![Vec4::ZERO; planes.len()];
        let luminance = Vec4::from((Vec3::from(LUMINANCE), 0.0));
        let mut unsolved = 0;
        let y_sign = match self.options.green {
            Green::Up => 1.0,
            Green::Down => -1.0,
        };
        for (i, texel) in normals.iter_mut().enumerate() {
            let at = 3 * (first + i);
            let mut mask = 0u64;
            for (k, plane) in planes.iter().enumerate() {
                let codes: [usize; 3] =
                    [plane[at].into(), plane[at + 1].into(), plane[at + 2].into()];
                let rgb = Vec4::new(
                    self.table[codes[0]],
                    self.table[codes[1]],
                    self.table[codes[2]],
                    0.0,
                );
                let y = rgb.dot(luminance);
                light[k] = Vec4::new(rgb.x, rgb.y, rgb.z, y);
                if y >= self.options.shadow && codes[0].max(codes[1]).max(codes[2]) < self.saturated
                {
                    mask |= 1 << k;
                }
            }
            // g for all four channels at once: row r of the 3×4 matrix Σ_k p_k ⊗ light_k.
            let solved = solves.get(mask).and_then(|columns| {
                let mut g = [Vec4::ZERO; 3];
                for (p, v) in columns.iter().zip(&light) {
                    (0..3).for_each(|r| g[r] += p[r] * *v);
                }
                let n = Vec3::new(g[0].w, g[1].w, g[2].w).try_normalize()?;
                // Each channel's g projected on n.
                Some((n, g[0] * n.x + g[1] * n.y + g[2] * n.z))
            });
            let (n, rho) = solved.unwrap_or_else(|| {
                unsolved += 1;
                (Vec3::Z, Vec4::NAN)
            });
            *texel = encode_normal([n.x, y_sign * n.y, n.z]);
            if let Some(albedo) = albedo.as_deref_mut() {
                let rho = if rho.is_nan() {
                    flat_albedo(self.lights, mask, &light)
                } else {
                    rho
                };
                albedo[i] = [self.encode(rho.x), self.encode(rho.y), self.encode(rho.z)];
            }
        }
        unsolved
    }

    /// Linear light as the albedo map's 8-bit value (round(from_linear(l) · 255), without a `powf`):
    /// the table's value at the start of `l`'s step, plus one if `l` is past the one midpoint the
    /// step may hold.
    fn encode(&self, l: f32) -> u8 {
        let code = self.coarse[(l.clamp(0.0, 1.0) * COARSE as f32) as usize];
        let past = self
            .midpoints
            .get(usize::from(code))
            .is_some_and(|&m| m <= l);
        code + u8::from(past)
    }
}

/// A texel left flat still gets a colour: the albedo that best explains its kept photos (all of
/// them if none is kept) with the normal (0, 0, 1), Σ I·l_z / Σ l_z² over the lights above it.
fn flat_albedo(lights: &[DVec3], mask: u64, seen: &[Vec4]) -> Vec4 {
    let mask = if mask == 0 { u64::MAX } else { mask };
    let (mut sum, mut weight) = (Vec4::ZERO, 0f32);
    for (k, light) in lights.iter().enumerate() {
        let s = light.z.max(0.0) as f32;
        if mask & (1 << k) != 0 && s > 0.0 {
            sum += seen[k] * s;
            weight += s * s;
        }
    }
    if weight > 0.0 {
        sum / weight
    } else {
        Vec4::ZERO
    }
}

/// Each mask's solve, computed the first time it is met: for every photo k, the column
/// (Σ l lᵀ)⁻¹ l_k of the photos in the mask (zero for the others), or `None` for fewer than three
/// photos or lights within [`MIN_SPREAD_DEGREES`] of one plane.
struct Solves<'a> {
    lights: &'a [DVec3],
    index: FxHashMap<u64, usize>,
    solves: Vec<Option<Vec<[f32; 3]>>>,
    /// Neighbouring texels mostly keep the same photos.
    last: Option<(u64, usize)>,
}

impl<'a> Solves<'a> {
    fn new(lights: &'a [DVec3]) -> Self {
        Solves {
            lights,
            index: FxHashMap::default(),
            solves: Vec::new(),
            last: None,
        }
    }

    fn get(&mut self, mask: u64) -> Option<&[[f32; 3]]> {
        let slot = match self.last {
            Some((last, slot)) if last == mask => slot,
            _ => {
                let slot = match self.index.get(&mask) {
                    Some(&slot) => slot,
                    None => {
                        self.solves.push(solve(self.lights, mask));
                        self.index.insert(mask, self.solves.len() - 1);
                        self.solves.len() - 1
                    }
                };
                self.last = Some((mask, slot));
                slot
            }
        };
        self.solves[slot].as_deref()
    }
}

fn solve(lights: &[DVec3], mask: u64) -> Option<Vec<[f32; 3]>> {
    let kept: Vec<DVec3> = (0..lights.len())
        .filter(|k| mask & (1 << k) != 0)
        .map(|k| lights[k])
        .collect();
    if kept.len() < 3 || light_spread_degrees(&kept) < MIN_SPREAD_DEGREES {
        return None;
    }
    let inverse = scatter(kept.iter()).inverse();
    let columns = (0..lights.len()).map(|k| {
        if mask & (1 << k) != 0 {
            (inverse * lights[k]).as_vec3().to_array()
        } else {
            [0.0; 3]
        }
    });
    Some(columns.collect())
}

/// `tutorial13 photometric`, as the command line gives it.
#[derive(Debug, Clone)]
pub struct Job<'a> {
    pub photos: &'a [PathBuf],
    /// The `--light` texts, one per photo.
    pub lights: &'a [String],
    pub output: &'a Path,
    pub albedo: Option<&'a Path>,
    pub encoding: Encoding,
    pub green: Green,
    pub shadow: f32,
}

/// Checks everything that can be checked before reading a photo (counts, lights, `--shadow`, the
/// outputs' names and folders), reads the photos and solves on every core, then writes the normal map
/// and the albedo. On any error nothing is written (a normal map already written is removed if the
/// albedo then cannot be).
pub fn run(job: &Job) -> Result<Recovered> {
    let lights = job
        .lights
        .iter()
        .map(|l| parse_light(l))
        .collect::<Result<Vec<_>>>()?;
    unit_lights(&lights, job.photos.len())?;
    if !(0.0..1.0).contains(&job.shadow) {
        return Err(Error::Photometric(format!(
            "--shadow {}: must be a linear luminance from 0 to below 1",
            job.shadow
        )));
    }
    for path in std::iter::once(job.output).chain(job.albedo) {
        map_format(path)?;
        let folder = path.parent().filter(|f| !f.as_os_str().is_empty());
        if let Some(folder) = folder.filter(|f| !f.is_dir()) {
            return Err(Error::Write {
                path: path.to_path_buf(),
                reason: format!("no such folder {} (create it first)", folder.display()),
            });
        }
    }
    if job.albedo == Some(job.output) {
        return Err(Error::Photometric(format!(
            "-o and --albedo name the same file, {}",
            job.output.display()
        )));
    }
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let photos = load_photos(job.photos, threads)?;
    let options = PhotometricOptions {
        encoding: job.encoding,
        green: job.green,
        shadow: job.shadow,
        albedo: job.albedo.is_some(),
        threads,
    };
    let recovered = recover(&photos, &lights, &options)?;
    let (w, h) = (recovered.width, recovered.height);
    write_normal_map(job.output, &recovered.normals, w, h)?;
    if let (Some(path), Some(albedo)) = (job.albedo, &recovered.albedo) {
        if let Err(e) = write_normal_map(path, albedo, w, h) {
            let _ = std::fs::remove_file(job.output);
            return Err(e);
        }
    }
    Ok(recovered)
}

/// Reads every photo, `threads` at a time (decoding is a third of the command's time); all must
/// be the first one's size, and the first error in the photos' order is the one reported. If any
/// is deeper than 8 bits, all are widened to 16.
pub fn load_photos(paths: &[PathBuf], threads: usize) -> Result<Vec<Photo>> {
    let per_thread = paths.len().div_ceil(threads.max(1)).max(1);
    let loaded: Vec<Result<Photo>> = std::thread::scope(|scope| {
        let handles: Vec<_> = paths
            .chunks(per_thread)
            .map(|chunk| scope.spawn(|| chunk.iter().map(|p| Photo::load(p)).collect::<Vec<_>>()))
            .collect();
        let joined = handles
            .into_iter()
            .map(|h| h.join().expect("a photo's decoder panicked"));
        joined.flatten().collect()
    });
    let mut photos = Vec::with_capacity(paths.len());
    for (path, photo) in paths.iter().zip(loaded) {
        let photo = photo?;
        if let Some(first) = photos.first().map(|p: &Photo| (p.width, p.height)) {
            if (photo.width, photo.height) != first {
                return Err(Error::Image {
                    path: path.clone(),
                    reason: format!(
                        "{}×{}, but {} is {}×{}: every photo must be the same size (one camera, \
                         not moved)",
                        photo.width,
                        photo.height,
                        paths[0].display(),
                        first.0,
                        first.1
                    ),
                });
            }
        }
        photos.push(photo);
    }
    if photos.iter().any(|p| p.bits() == 16) {
        photos = photos.into_iter().map(Photo::to_sixteen).collect();
    }
    Ok(photos)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ring(elevation_degrees: f64, k: usize) -> Vec<DVec3> {
        let e = elevation_degrees.to_radians();
        (0..k)
            .map(|i| {
                let a = std::f64::consts::TAU * i as f64 / k as f64 + 0.3;
                DVec3::new(e.cos() * a.cos(), e.cos() * a.sin(), e.sin())
            })
            .collect()
    }

    // Fails if the spread is not the lights' RMS angle to their best plane: a ring of lights at
    // elevation e is e from the surface's plane (for e up to 35.26°, where sin² e = cos² e / 2; above
    // it a vertical plane fits better), three perpendicular axes are asin(√⅓) from any plane, coplanar or equal lights 0.
    #[test]
    fn light_spread_is_the_angle_to_the_best_plane() {
        for e in [0.0, 3.0, 10.0, 30.0, 35.0] {
            let spread = light_spread_degrees(&ring(e, 5));
            assert!((spread - e).abs() < 1e-6, "{e}: {spread}");
        }
        let axes = [DVec3::X, DVec3::Y, DVec3::Z];
        let expected = (1.0f64 / 3.0).sqrt().asin().to_degrees();
        assert!((light_spread_degrees(&axes) - expected).abs() < 1e-9);
        let tilted = [
            DVec3::new(1.0, 1.0, 1.0),
            DVec3::new(1.0, -1.0, 0.0),
            DVec3::new(2.0, 0.0, 1.0),
        ];
        let tilted: Vec<DVec3> = tilted.iter().map(|l| l.normalize()).collect();
        assert!(light_spread_degrees(&tilted) < 1e-6);
        assert!(light_spread_degrees(&[DVec3::Z; 4]) < 1e-6);
    }

    // Fails if the albedo's 8-bit value is not round(from_linear(l) · 255) (computed in f64, so
    // that only values within float rounding of a midpoint may go either way) for sRGB and linear.
    #[test]
    fn the_albedo_encoder_rounds_as_the_curve_says() {
        for encoding in [Encoding::Srgb, Encoding::Linear] {
            let options = PhotometricOptions {
                encoding,
                ..Default::default()
            };
            let solver = Solver::new(&[], 8, &options);
            for i in 0..=200_000 {
                let l = i as f32 / 200_000.0;
                let exact = match encoding {
                    Encoding::Linear => f64::from(l),
                    Encoding::Srgb if l <= 0.003_130_8 => 12.92 * f64::from(l),
                    Encoding::Srgb => 1.055 * f64::from(l).powf(1.0 / 2.4) - 0.055,
                } * 255.0;
                let got = f64::from(solver.encode(l));
                let near_midpoint = (exact.fract() - 0.5).abs() < 1e-4;
                assert!(
                    got == exact.round() || near_midpoint && (got - exact).abs() <= 0.5 + 1e-4,
                    "{encoding:?} {l}: {got} for {exact}"
                );
            }
            assert_eq!((solver.encode(-1.0), solver.encode(2.0)), (0, 255));
        }
    }
}
