//! Photometric stereo, the tutorial's "make your own normal maps out of several photos", as
//! `tutorial13 photometric PHOTO... --light X,Y,Z ... -o NORMAL.png [--albedo ALBEDO.png]`.
//!
//! Three or more photos from one camera position, each lit by one distant light from a known
//! direction l (x to the photo's right, y up it, z out of the surface towards the camera; made unit
//! here) and of a known brightness per colour channel, which each photo is divided by in linear
//! light (all equal unless given: same lamp, same distance, same exposure). A matte (Lambertian)
//! texel of albedo ρ and unit normal n shows, in linear light,
//! I = ρ · max(0, n·l). Where it is lit, I = lᵀg with g = ρn, so three or more photos give g by
//! least squares, g = (Σ l lᵀ)⁻¹ Σ l I, then n = g / |g| and ρ = |g|. The solve uses each photo's
//! luminance; each colour channel's albedo is that channel's g projected on n.
//!
//! A texel that is near black in a photo (its linear luminance below `shadow`: the light does not
//! reach it, and max(0, ·) hides how far) or saturated (a channel at 98 % of full scale or more: a
//! highlight, or clipped) is left out of that texel's solve. Up to [`MASKED_PHOTOS`] photos, least
//! squares keeps a bitmask per texel of the photos it keeps, and the 3×3 inverse depends only on
//! it: each mask's columns (Σ l lᵀ)⁻¹ l_k are computed once, the first time a band of rows meets it,
//! so a texel costs K multiply-adds. Above, a texel accumulates and inverts its own normal
//! equations over its kept photos (a cache of masks would hold nearly one per texel).
//!
//! The robust solver ([`Solver::Robust`], the default from [`ROBUST_FROM`] photos) is trimmed least
//! squares: a texel's kept photos are ranked by luminance (its light's brightness divided out),
//! the [`ROBUST_DARKEST`] and [`ROBUST_BRIGHTEST`] fractions at the two ends are left out, and the
//! rest is solved through its own normal equations. Highlights are brighter, and shadows with
//! light bounced in darker, than Lambert's law allows; docs/tools.md says which methods this
//! follows and where it stops working.
//!
//! Lights that (nearly) share a plane cannot tell how far a normal leans out of it. The measure is
//! the light directions' root-mean-square angle to the plane that fits them best: the square root of
//! the smallest eigenvalue of (1/K) Σ l lᵀ is its sine. Below [`MIN_SPREAD_DEGREES`] the whole set
//! is refused; a texel whose own kept photos are below it (say, three neighbours of a ring of eight)
//! is solved no better than one with fewer than three, and both get the flat normal and are counted.

use std::path::{Path, PathBuf};

use glam::{DMat3, DVec3, Vec3, Vec4};
use rustc_hash::FxHashMap;

use crate::normalmap::{decode_image, encode_normal, encode_normal16, map_format};
use crate::normalmap::{write_normal_map, write_normal_map16, Green};
use crate::photo::{Encoding, Photo, Samples, LUMINANCE};
use crate::{Error, Result};

/// Below this spread of the light directions out of one plane, they are refused as coplanar.
pub const MIN_SPREAD_DEGREES: f64 = 5.0;
/// A channel at this fraction of full scale or above is saturated.
pub const SATURATED: f64 = 0.98;
/// The default `--shadow`: linear luminance below which a texel counts as unlit (about sRGB 25/255).
pub const DEFAULT_SHADOW: f32 = 0.01;
/// Up to this many photos, which ones a texel keeps is a 64-bit mask and least squares reuses each
/// mask's solve; above it every texel solves its own normal equations.
pub const MASKED_PHOTOS: usize = 64;
/// From this many photos on, the robust solver is the default.
pub const ROBUST_FROM: usize = 6;
/// The robust solver leaves out this fraction of a texel's kept photos at the dark end of their
/// ranking (shadows that are not black: light bounced in, a lamp not quite point-like; black ones
/// are below `shadow` already, and each photo left out costs accuracy)...
pub const ROBUST_DARKEST: f32 = 0.1;
/// ... and this fraction at the bright end (highlights).
pub const ROBUST_BRIGHTEST: f32 = 0.25;
/// Steps of the albedo encoder's table over linear light: fine enough (1.5e-5 each) that no step
/// holds two midpoints between 8-bit values (the closest, near black in sRGB, are 1 / (255 · 12.92)
/// = 3.0e-4 apart), so one comparison finishes the table's guess.
const COARSE: usize = 1 << 16;

/// How each texel's normal is fitted to its kept photos.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Solver {
    /// Least squares over every kept photo (the textbook method).
    #[value(name = "lstsq")]
    LeastSquares,
    /// Least squares over the kept photos left once the darkest and brightest fractions of them
    /// ([`ROBUST_DARKEST`], [`ROBUST_BRIGHTEST`]) are left out, ranked by brightness per texel.
    Robust,
}

/// How to read the photos and what to make.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PhotometricOptions {
    /// `None`: robust from [`ROBUST_FROM`] photos on, least squares below.
    pub solver: Option<Solver>,
    /// Also make the normal map with 16 bits per channel.
    pub sixteen_bit: bool,
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
            solver: None,
            sixteen_bit: false,
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
    /// The same with 16 bits per channel, if asked for.
    pub normals16: Option<Vec<[u16; 3]>>,
    /// The albedo, encoded as the photos were (sRGB unless linear), if asked for.
    pub albedo: Option<Vec<[u8; 3]>>,
    /// Texels left flat: fewer than three photos kept, or their lights nearly coplanar (texels
    /// outside the mask are not counted).
    pub unsolved: usize,
}

/// What a capture says beside the photos and light directions: each light's brightness per colour
/// channel (all 1 if `None`) and which texels are the object (all if `None`).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Calibration {
    /// One linear RGB brightness per photo, each above zero; each photo is divided by its own.
    pub intensities: Option<Vec<[f32; 3]>>,
    /// One flag per texel, row 0 at the top: outside, the flat normal and albedo 0.
    pub mask: Option<Vec<bool>>,
}

/// One `--light X,Y,Z`: three finite numbers, not all zero (any length: only the direction counts).
pub fn parse_light(text: &str) -> Result<Vec3> {
    direction(text.split(',')).map_err(|not| {
        let why = match not {
            NotALight::Numbers => "not three numbers X,Y,Z (e.g. --light -1,0,1)",
            NotALight::Direction => "not a direction (all zero, or not finite)",
        };
        Error::Photometric(format!("--light {text}: {why}"))
    })
}

/// Why a light's text is not a direction.
enum NotALight {
    Numbers,
    Direction,
}

/// Three finite numbers, not all zero, as a direction.
fn direction<'a>(numbers: impl Iterator<Item = &'a str>) -> std::result::Result<Vec3, NotALight> {
    let numbers: Vec<f32> = numbers
        .map(|n| n.trim().parse::<f32>())
        .collect::<std::result::Result<_, _>>()
        .map_err(|_| NotALight::Numbers)?;
    let [x, y, z] = numbers[..] else {
        return Err(NotALight::Numbers);
    };
    let light = Vec3::new(x, y, z);
    if !light.is_finite() || light == Vec3::ZERO {
        return Err(NotALight::Direction);
    }
    Ok(light)
}

/// One `--intensity R,G,B` (or one value for all three): finite numbers above zero.
pub fn parse_intensity(text: &str) -> Result<[f32; 3]> {
    intensity(text.split(','))
        .map_err(|why| Error::Photometric(format!("--intensity {text}: {why}")))
}

/// Three numbers, or one for all three, each finite and above zero; else why not.
fn intensity<'a>(numbers: impl Iterator<Item = &'a str>) -> std::result::Result<[f32; 3], String> {
    let numbers: Vec<f32> = numbers
        .map(|n| n.trim().parse::<f32>())
        .collect::<std::result::Result<_, _>>()
        .map_err(|_| "not three numbers R G B (or one for all three)".to_string())?;
    let rgb = match numbers[..] {
        [v] => [v; 3],
        [r, g, b] => [r, g, b],
        _ => return Err("not three numbers R G B (or one for all three)".into()),
    };
    if rgb.iter().any(|c| !c.is_finite() || *c <= 0.0) {
        return Err("each brightness must be a finite number above zero".into());
    }
    Ok(rgb)
}

/// The lines of a capture's text file that hold values: blank lines and `#` comments left out,
/// with their line numbers (from 1).
fn value_lines(text: &str) -> impl Iterator<Item = (usize, &str)> {
    text.lines()
        .enumerate()
        .map(|(i, line)| (i + 1, line.split('#').next().unwrap_or("").trim()))
        .filter(|(_, line)| !line.is_empty())
}

/// A light-directions file (`--lights`): one `x y z` per photo and line, in the photos' order.
pub fn parse_lights_file(text: &str, path: &Path) -> Result<Vec<Vec3>> {
    value_lines(text)
        .map(|(n, line)| {
            direction(line.split_whitespace()).map_err(|not| {
                let why = match not {
                    NotALight::Numbers => "not three numbers x y z",
                    NotALight::Direction => "not a direction (all zero, or not finite)",
                };
                Error::Photometric(format!("{}: line {n}: {why}", path.display()))
            })
        })
        .collect()
}

/// A light-intensities file (`--intensities`): one `r g b` (or one value) per photo and line.
pub fn parse_intensities_file(text: &str, path: &Path) -> Result<Vec<[f32; 3]>> {
    value_lines(text)
        .map(|(n, line)| {
            intensity(line.split_whitespace())
                .map_err(|why| Error::Photometric(format!("{}: line {n}: {why}", path.display())))
        })
        .collect()
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

/// Whether lights of this spread (see [`light_spread_degrees`]) are refused as coplanar: below
/// [`MIN_SPREAD_DEGREES`]; exactly that much is enough.
fn nearly_coplanar(spread_degrees: f64) -> bool {
    spread_degrees < MIN_SPREAD_DEGREES
}

/// [`nearly_coplanar`] from the smallest eigenvalue of the lights' mean scatter (1/K) Σ l lᵀ, the
/// squared sine of their spread, without the arcsine (it is asked once per texel).
fn nearly_coplanar_scatter(smallest_eigenvalue: f64) -> bool {
    let sine = MIN_SPREAD_DEGREES.to_radians().sin();
    smallest_eigenvalue < sine * sine
}

/// Unit directions of `lights`, one per photo, refused if there are not `photos` of them or if they
/// are (nearly) coplanar.
fn unit_lights(lights: &[Vec3], photos: usize) -> Result<Vec<DVec3>> {
    if photos < 3 {
        return Err(Error::Photometric(format!(
            "photometric stereo needs at least three photos, each under its own light; got {photos}"
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
    if nearly_coplanar(spread) {
        return Err(Error::Photometric(format!(
            "the --light directions are nearly coplanar (within {spread:.1}° of one plane, at least \
             {MIN_SPREAD_DEGREES}° needed): the photos cannot tell how far a normal leans out of \
             that plane; light some photos from higher or lower"
        )));
    }
    Ok(unit)
}

/// Normals (and albedo) of the texels of `photos` (same size, all 8-bit or all 16-bit), lit by
/// `lights` in order, every light equally bright. Errors: fewer than three photos, a light count
/// that differs, coplanar lights.
pub fn recover(
    photos: &[Photo],
    lights: &[Vec3],
    options: &PhotometricOptions,
) -> Result<Recovered> {
    recover_calibrated(photos, lights, &Calibration::default(), options)
}

/// [`recover`] with each light's brightness and a mask (see [`Calibration`]). Errors as
/// [`recover`]'s, and an intensity count or a mask size that differs.
pub fn recover_calibrated(
    photos: &[Photo],
    lights: &[Vec3],
    calibration: &Calibration,
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
    if let Some(intensities) = &calibration.intensities {
        if intensities.len() != photos.len() {
            return Err(Error::Photometric(format!(
                "{} photos but {} intensities",
                photos.len(),
                intensities.len()
            )));
        }
    }
    if calibration.mask.as_ref().is_some_and(|m| m.len() != texels) {
        return Err(Error::Photometric(format!(
            "a mask that is not {width}×{height}, the photos' size"
        )));
    }
    let stereo = Stereo::new(&lights, calibration, bits, options);
    let mut normals = vec![[0u8; 3]; texels];
    let mut normals16 = vec![[0u16; 3]; if options.sixteen_bit { texels } else { 0 }];
    let mut albedo = vec![[0u8; 3]; if options.albedo { texels } else { 0 }];
    let band = band_texels(width, height, options.threads);
    let bands: Vec<_> = normals
        .chunks_mut(band)
        .zip(optional_bands(&mut normals16, band))
        .zip(optional_bands(&mut albedo, band))
        .enumerate()
        .collect();
    let unsolved = std::thread::scope(|scope| {
        let handles: Vec<_> = bands
            .into_iter()
            .map(|(i, ((normals, normals16), albedo))| {
                let stereo = &stereo;
                let out = Band {
                    first: i * band,
                    normals,
                    normals16,
                    albedo,
                };
                scope.spawn(move || match &photos[0].samples {
                    Samples::Eight(_) => stereo.band(photos, eight, out),
                    Samples::Sixteen(_) => stereo.band(photos, sixteen, out),
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
        normals16: options.sixteen_bit.then_some(normals16),
        albedo: options.albedo.then_some(albedo),
        unsolved,
    })
}

/// How many texels each band of rows solved at once holds: whole rows, as many as make `threads`
/// bands (fewer if there are fewer rows), and at least one texel. Each band keeps its own cache of
/// solves.
fn band_texels(width: u32, height: u32, threads: usize) -> usize {
    let rows = (height as usize).div_ceil(threads.max(1)).max(1);
    (rows * width as usize).max(1)
}

/// `texels` cut in bands of `band`, or (when it is empty: not asked for) `None` for every band.
fn optional_bands<T>(texels: &mut [T], band: usize) -> impl Iterator<Item = Option<&mut [T]>> {
    texels
        .chunks_mut(band)
        .map(Some)
        .chain(std::iter::repeat_with(|| None))
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

/// How a texel's normal is fitted.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Method {
    /// Least squares through each mask's cached solve (up to [`MASKED_PHOTOS`] photos).
    Masks,
    /// Least squares through the texel's own normal equations.
    PerTexel,
    /// The texel's own normal equations over its middle-ranked kept photos.
    Robust,
}

/// One band of rows to fill: its first texel's index and its share of each output.
struct Band<'o> {
    first: usize,
    normals: &'o mut [[u8; 3]],
    normals16: Option<&'o mut [[u16; 3]]>,
    albedo: Option<&'o mut [[u8; 3]]>,
}

/// What every band of rows shares.
struct Stereo<'a> {
    lights: &'a [DVec3],
    /// The same in single precision, for the per-texel normal equations.
    lights32: Vec<Vec3>,
    /// Per photo, what each linear channel is multiplied by: one over its light's brightness (0 for
    /// the luminance slot, made after).
    gains: Vec<Vec4>,
    mask: Option<&'a [bool]>,
    method: Method,
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

impl<'a> Stereo<'a> {
    fn new(
        lights: &'a [DVec3],
        calibration: &'a Calibration,
        bits: u32,
        options: &'a PhotometricOptions,
    ) -> Self {
        let midpoints = options.encoding.midpoints();
        let default = if lights.len() >= ROBUST_FROM {
            Solver::Robust
        } else {
            Solver::LeastSquares
        };
        let method = match options.solver.unwrap_or(default) {
            Solver::LeastSquares if lights.len() <= MASKED_PHOTOS => Method::Masks,
            Solver::LeastSquares => Method::PerTexel,
            Solver::Robust => Method::Robust,
        };
        let gains = (0..lights.len()).map(|k| match &calibration.intensities {
            Some(rgb) => Vec4::from((Vec3::ONE / Vec3::from(rgb[k]), 0.0)),
            None => Vec4::new(1.0, 1.0, 1.0, 0.0),
        });
        Stereo {
            lights,
            lights32: lights.iter().map(|l| l.as_vec3()).collect(),
            gains: gains.collect(),
            mask: calibration.mask.as_deref(),
            method,
            table: options.encoding.table(bits),
            saturated: (SATURATED * f64::from((1u32 << bits) - 1)).ceil() as usize,
            coarse: (0..=COARSE)
                .map(|i| midpoints.partition_point(|&m| m <= i as f32 / COARSE as f32) as u8)
                .collect(),
            midpoints,
            options,
        }
    }

    /// Solves the texels of `out`; returns how many were left flat.
    fn band<T: Copy + Into<usize>>(
        &self,
        photos: &[Photo],
        samples: fn(&Photo) -> &[T],
        mut out: Band,
    ) -> usize {
        let planes: Vec<&[T]> = photos.iter().map(samples).collect();
        let mut solves = Solves::new(self.lights);
        // Per photo, the current texel in linear light over its light's brightness: red, green,
        // blue, luminance.
        let mut light = vec![Vec4::ZERO; planes.len()];
        // The photos the texel keeps, in order.
        let mut kept: Vec<u32> = Vec::with_capacity(planes.len());
        let luminance = Vec4::from((Vec3::from(LUMINANCE), 0.0));
        let mut unsolved = 0;
        let y_sign = match self.options.green {
            Green::Up => 1.0,
            Green::Down => -1.0,
        };
        for i in 0..out.normals.len() {
            let texel = out.first + i;
            if self.mask.is_some_and(|m| !m[texel]) {
                out.normals[i] = encode_normal([0.0, 0.0, 1.0]);
                if let Some(n16) = out.normals16.as_deref_mut() {
                    n16[i] = encode_normal16([0.0, 0.0, 1.0]);
                }
                if let Some(albedo) = out.albedo.as_deref_mut() {
                    albedo[i] = [0; 3];
                }
                continue;
            }
            let at = 3 * texel;
            let mut mask = 0u64;
            kept.clear();
            for (k, plane) in planes.iter().enumerate() {
                let codes: [usize; 3] =
                    [plane[at].into(), plane[at + 1].into(), plane[at + 2].into()];
                let rgb = Vec4::new(
                    self.table[codes[0]],
                    self.table[codes[1]],
                    self.table[codes[2]],
                    0.0,
                );
                // Shadow is judged on what the camera saw, before the light's brightness is
                // divided out (a dim light's photo is no less exposed for it).
                let seen = rgb.dot(luminance);
                let rgb = rgb * self.gains[k];
                light[k] = Vec4::new(rgb.x, rgb.y, rgb.z, rgb.dot(luminance));
                if self.keeps(seen, codes) {
                    if self.method == Method::Masks {
                        mask |= 1 << k;
                    }
                    kept.push(k as u32);
                }
            }
            let solved = match self.method {
                // g for all four channels at once: row r of the 3×4 matrix Σ_k p_k ⊗ light_k.
                Method::Masks => solves.get(mask).and_then(|columns| {
                    let mut g = [Vec4::ZERO; 3];
                    for (p, v) in columns.iter().zip(&light) {
                        (0..3).for_each(|r| g[r] += p[r] * *v);
                    }
                    normal_and_albedo(g)
                }),
                Method::PerTexel => self.fit(&kept, &light),
                Method::Robust => {
                    let middle = middle_ranked(&mut kept, &light);
                    self.fit(middle, &light)
                }
            };
            let (n, rho) = solved.unwrap_or_else(|| {
                unsolved += 1;
                (Vec3::Z, Vec4::NAN)
            });
            let n = [n.x, y_sign * n.y, n.z];
            out.normals[i] = encode_normal(n);
            if let Some(n16) = out.normals16.as_deref_mut() {
                n16[i] = encode_normal16(n);
            }
            if let Some(albedo) = out.albedo.as_deref_mut() {
                let rho = if rho.is_nan() {
                    flat_albedo(self.lights, &kept, &light)
                } else {
                    rho
                };
                albedo[i] = [self.encode(rho.x), self.encode(rho.y), self.encode(rho.z)];
            }
        }
        unsolved
    }

    /// Whether a photo's texel takes part in its solve: lit (its luminance as the camera saw it at
    /// `shadow` or above) and no channel's stored value saturated.
    fn keeps(&self, seen: f32, codes: [usize; 3]) -> bool {
        seen >= self.options.shadow && codes[0].max(codes[1]).max(codes[2]) < self.saturated
    }

    /// Least squares over the photos `kept`, through their own normal equations
    /// (Σ l lᵀ) g = Σ l I; `None` for fewer than three or lights within [`MIN_SPREAD_DEGREES`] of
    /// one plane.
    fn fit(&self, kept: &[u32], light: &[Vec4]) -> Option<(Vec3, Vec4)> {
        if kept.len() < 3 {
            return None;
        }
        let (mut a, mut b) = ([Vec3::ZERO; 3], [Vec4::ZERO; 3]);
        for &k in kept {
            let (l, v) = (self.lights32[k as usize], light[k as usize]);
            (0..3).for_each(|r| {
                a[r] += l * l[r];
                b[r] += v * l[r];
            });
        }
        let a = DMat3::from_cols(a[0].as_dvec3(), a[1].as_dvec3(), a[2].as_dvec3());
        if nearly_coplanar_scatter(smallest_eigenvalue(&(a * (1.0 / kept.len() as f64)))) {
            return None;
        }
        let inverse = a.inverse().as_mat3();
        let mut g = [Vec4::ZERO; 3];
        for (r, g) in g.iter_mut().enumerate() {
            *g = (0..3).map(|c| b[c] * inverse.col(c)[r]).sum();
        }
        normal_and_albedo(g)
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

/// n = g / |g| and each channel's albedo, g projected on n, from g for the four channels (row r
/// of the 3×4 matrix); `None` where g is zero.
fn normal_and_albedo(g: [Vec4; 3]) -> Option<(Vec3, Vec4)> {
    let n = Vec3::new(g[0].w, g[1].w, g[2].w).try_normalize()?;
    Some((n, g[0] * n.x + g[1] * n.y + g[2] * n.z))
}

/// The middle of `kept` ranked by luminance: without the [`ROBUST_DARKEST`] and
/// [`ROBUST_BRIGHTEST`] fractions at either end (rounded down). Reorders `kept`.
fn middle_ranked<'k>(kept: &'k mut [u32], light: &[Vec4]) -> &'k [u32] {
    let n = kept.len();
    let dark = (n as f32 * ROBUST_DARKEST) as usize;
    let bright = (n as f32 * ROBUST_BRIGHTEST) as usize;
    let by_luminance = |a: &u32, b: &u32| light[*a as usize].w.total_cmp(&light[*b as usize].w);
    // Partial sorts: the darkest before `dark`, then the brightest after the middle.
    if dark > 0 {
        kept.select_nth_unstable_by(dark, by_luminance);
    }
    let middle = n - dark - bright;
    if bright > 0 {
        kept[dark..].select_nth_unstable_by(middle, by_luminance);
    }
    &kept[dark..dark + middle]
}

/// A texel left flat still gets a colour: the albedo that best explains its kept photos (all of
/// them if none is kept) with the normal (0, 0, 1), Σ I·l_z / Σ l_z² over the lights above it.
fn flat_albedo(lights: &[DVec3], kept: &[u32], seen: &[Vec4]) -> Vec4 {
    let (mut sum, mut weight) = (Vec4::ZERO, 0f32);
    let mut add = |k: usize| {
        let s = lights[k].z.max(0.0) as f32;
        if s > 0.0 {
            sum += seen[k] * s;
            weight += s * s;
        }
    };
    if kept.is_empty() {
        (0..lights.len()).for_each(&mut add);
    } else {
        kept.iter().for_each(|&k| add(k as usize));
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
    if kept.len() < 3 || nearly_coplanar(light_spread_degrees(&kept)) {
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
    /// The `--light` texts, one per photo (or none, with `lights_file`).
    pub lights: &'a [String],
    /// `--lights FILE`: one `x y z` per photo and line.
    pub lights_file: Option<&'a Path>,
    /// The `--intensity` texts, one per photo (or none).
    pub intensities: &'a [String],
    /// `--intensities FILE`: one `r g b` per photo and line.
    pub intensities_file: Option<&'a Path>,
    /// `--mask FILE`: nonzero inside.
    pub mask: Option<&'a Path>,
    pub output: &'a Path,
    pub albedo: Option<&'a Path>,
    pub solver: Option<Solver>,
    /// Write the normal map with 16 bits per channel (PNG).
    pub sixteen_bit: bool,
    pub encoding: Encoding,
    pub green: Green,
    pub shadow: f32,
}

/// Reads a capture's text file as UTF-8; errors name it.
fn read_text(path: &Path) -> Result<String> {
    let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    String::from_utf8(bytes)
        .map_err(|_| Error::Photometric(format!("{}: not UTF-8 text", path.display())))
}

/// `values`, one per photo, checked against the photo count; `source` names where they came from
/// and `what` they are.
fn one_per_photo<T>(values: Vec<T>, photos: usize, source: &str, what: &str) -> Result<Vec<T>> {
    if values.len() != photos {
        return Err(Error::Photometric(format!(
            "{source}: {} {what} for {photos} photos: give one per photo, in the photos' order",
            values.len()
        )));
    }
    Ok(values)
}

/// Checks everything that can be checked before reading a photo (counts, lights, intensities,
/// `--shadow`, the outputs' names and folders), reads the photos and the mask and solves on every
/// core, then writes the normal map and the albedo. On any error nothing is written (a normal map
/// already written is removed if the albedo then cannot be).
pub fn run(job: &Job) -> Result<Recovered> {
    let count = job.photos.len();
    let lights = match job.lights_file {
        Some(path) => one_per_photo(
            parse_lights_file(&read_text(path)?, path)?,
            count,
            &path.display().to_string(),
            "directions",
        )?,
        None => job
            .lights
            .iter()
            .map(|l| parse_light(l))
            .collect::<Result<Vec<_>>>()?,
    };
    unit_lights(&lights, count)?;
    let intensities = match job.intensities_file {
        Some(path) => Some(one_per_photo(
            parse_intensities_file(&read_text(path)?, path)?,
            count,
            &path.display().to_string(),
            "intensities",
        )?),
        None if job.intensities.is_empty() => None,
        None => Some(one_per_photo(
            job.intensities
                .iter()
                .map(|i| parse_intensity(i))
                .collect::<Result<Vec<_>>>()?,
            count,
            "--intensity",
            "brightnesses",
        )?),
    };
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
    if job.sixteen_bit && map_format(job.output)? != image::ImageFormat::Png {
        return Err(Error::Write {
            path: job.output.to_path_buf(),
            reason: "--depth 16 writes PNG only: name the output .png".into(),
        });
    }
    if job.albedo == Some(job.output) {
        return Err(Error::Photometric(format!(
            "-o and --albedo name the same file, {}",
            job.output.display()
        )));
    }
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let photos = load_photos(job.photos, threads)?;
    let mask = job
        .mask
        .map(|path| load_mask(path, &photos[0], &job.photos[0]))
        .transpose()?;
    let options = PhotometricOptions {
        solver: job.solver,
        sixteen_bit: job.sixteen_bit,
        encoding: job.encoding,
        green: job.green,
        shadow: job.shadow,
        albedo: job.albedo.is_some(),
        threads,
    };
    let calibration = Calibration { intensities, mask };
    let recovered = recover_calibrated(&photos, &lights, &calibration, &options)?;
    let (w, h) = (recovered.width, recovered.height);
    match &recovered.normals16 {
        Some(normals) => write_normal_map16(job.output, normals, w, h)?,
        None => write_normal_map(job.output, &recovered.normals, w, h)?,
    }
    if let (Some(path), Some(albedo)) = (job.albedo, &recovered.albedo) {
        if let Err(e) = write_normal_map(path, albedo, w, h) {
            let _ = std::fs::remove_file(job.output);
            return Err(e);
        }
    }
    Ok(recovered)
}

/// The mask at `path`: a texel is inside where any channel is nonzero. It must be the size of the
/// photos (`first`, read from `first_path`).
fn load_mask(path: &Path, first: &Photo, first_path: &Path) -> Result<Vec<bool>> {
    let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    let image = decode_image(&bytes, path, "a mask")?;
    if (image.width(), image.height()) != (first.width, first.height) {
        return Err(Error::Image {
            path: path.to_path_buf(),
            reason: format!(
                "a {}×{} mask, but {} is {}×{}: the mask must be the photos' size",
                image.width(),
                image.height(),
                first_path.display(),
                first.width,
                first.height
            ),
        });
    }
    let rgb = image.into_rgb16();
    Ok(rgb.pixels().map(|p| p.0 != [0; 3]).collect())
}

/// Checks that `count` photos of `width`×`height`, `bytes` per channel, can be held at once:
/// computes their size and asks the allocator for it before anything is decoded (and gives it
/// back), so that a set too large is refused with the figure instead of aborting half-way.
pub fn reserve_for_photos(count: usize, width: u32, height: u32, bytes: usize) -> Result<()> {
    let need = count as u128 * u128::from(width) * u128::from(height) * 3 * bytes as u128;
    let fits = usize::try_from(need)
        .ok()
        .filter(|&n| n <= isize::MAX as usize)
        .is_some_and(|n| Vec::<u8>::new().try_reserve_exact(n).is_ok());
    if !fits {
        return Err(Error::Photometric(format!(
            "{count} photos of {width}×{height} need {need} bytes ({:.1} GiB) to be held at once, \
             more than this machine can allocate: use fewer photos or crop them",
            need as f64 / f64::from(1u32 << 30)
        )));
    }
    Ok(())
}

/// Reads every photo, `threads` at a time (decoding is a third of the command's time); all must
/// be the first one's size, and the first error in the photos' order is the one reported. If any
/// is deeper than 8 bits, all are widened to 16.
pub fn load_photos(paths: &[PathBuf], threads: usize) -> Result<Vec<Photo>> {
    // The first photo's header gives the set's size (if it has none, its load says why).
    // Without the decoder's limits: the header's size is what is checked here.
    let header = image::ImageReader::open(&paths[0])
        .ok()
        .and_then(|r| r.with_guessed_format().ok())
        .and_then(|mut r| {
            r.no_limits();
            image::ImageDecoder::dimensions(&r.into_decoder().ok()?).into()
        });
    if let Some((width, height)) = header {
        // 16 bits per channel: what any photo deeper than 8 makes of all of them.
        reserve_for_photos(paths.len(), width, height, 2)?;
    }
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

    // Fails if the closed form does not give the smallest eigenvalue of a matrix whose eigenvalues
    // are distinct and whose eigenvectors lie off the axes: M = R diag(d) Rᵀ for rotations R and
    // known d (the rings and axes above have zero off-diagonal terms or two equal eigenvalues, on
    // which a wrong sum of the off-diagonal squares or a wrong angle can still come out right).
    #[test]
    fn the_smallest_eigenvalue_of_a_rotated_diagonal_matrix_is_its_smallest_entry() {
        let spectra = [
            [0.1, 0.5, 0.9],
            [2.0, 0.03, 1.1],
            [0.7, 0.69, 0.2],
            [1e-4, 3.0, 1.5],
        ];
        for (i, d) in spectra.iter().enumerate() {
            for j in 0..5 {
                let axis = DVec3::new(1.0 + i as f64, 2.0 - j as f64, 0.5 + j as f64).normalize();
                let r = DMat3::from_axis_angle(axis, 0.4 + 0.7 * j as f64);
                let m = r * DMat3::from_diagonal(DVec3::from(*d)) * r.transpose();
                let smallest = d.iter().copied().fold(f64::INFINITY, f64::min);
                let got = smallest_eigenvalue(&m);
                assert!((got - smallest).abs() < 1e-9, "{d:?} turned {j}: {got}");
            }
        }
    }

    // Fails if exactly the least spread allowed is refused (the error asks for "at least" it), or
    // if less is not.
    #[test]
    fn exactly_the_least_spread_is_enough() {
        assert!(!nearly_coplanar(MIN_SPREAD_DEGREES));
        assert!(nearly_coplanar(MIN_SPREAD_DEGREES - 1e-9));
        assert!(!nearly_coplanar(90.0));
    }

    // Fails if the per-texel check of the spread (its eigenvalue against sin² 5°) does not draw the
    // line where `nearly_coplanar` does: exactly sin² 5° is enough, less is refused, and sin² 6° is
    // well clear.
    #[test]
    fn the_per_texel_spread_check_is_the_sets() {
        let sine_squared = |degrees: f64| degrees.to_radians().sin().powi(2);
        assert!(!nearly_coplanar_scatter(sine_squared(MIN_SPREAD_DEGREES)));
        assert!(nearly_coplanar_scatter(
            sine_squared(MIN_SPREAD_DEGREES) - 1e-12
        ));
        assert!(!nearly_coplanar_scatter(sine_squared(6.0)));
        assert!(!nearly_coplanar_scatter(1.0 / 3.0));
    }

    // Fails if a photo's texel is kept or left out on the wrong side of either line: a luminance of
    // exactly `shadow` is lit, just below is not; for 8 bits the first saturated value is
    // ceil(0.98 · 255) = 250, for 16 bits ceil(0.98 · 65535) = 64225, in any channel.
    #[test]
    fn a_texel_is_kept_from_the_shadow_line_up_to_below_saturation() {
        let options = PhotometricOptions::default();
        let calibration = Calibration::default();
        for (bits, first_saturated) in [(8, 250), (16, 64225)] {
            let stereo = Stereo::new(&[], &calibration, bits, &options);
            let shadow = options.shadow;
            let below = first_saturated - 1;
            assert!(stereo.keeps(shadow, [below, 0, 0]));
            assert!(stereo.keeps(1.0, [0, below, below]));
            assert!(!stereo.keeps(shadow - 1e-6, [100, 100, 100]));
            for c in 0..3 {
                let mut codes = [10; 3];
                codes[c] = first_saturated;
                assert!(!stereo.keeps(1.0, codes), "{bits} bits, channel {c}");
            }
        }
    }

    // Fails if the per-texel fit (the robust solver's, and least squares' above 64 photos) refuses
    // exactly three photos, or solves three whose lights are nearly coplanar: three lights 30° up
    // recover a tilted normal and its albedo, the same three 3° up are refused, and so are two.
    #[test]
    fn the_per_texel_fit_solves_three_photos_unless_coplanar() {
        let options = PhotometricOptions::default();
        let calibration = Calibration::default();
        let n = DVec3::new(0.2, -0.3, 1.0).normalize();
        let albedo = 0.6;
        for (elevation, solved) in [(30.0, true), (3.0, false)] {
            let lights = ring(elevation, 3);
            let stereo = Stereo::new(&lights, &calibration, 8, &options);
            let seen: Vec<Vec4> = lights
                .iter()
                .map(|l| Vec4::splat((albedo * n.dot(*l)) as f32))
                .collect();
            // Lambert's law without its max(0, ·): 30° up, every light reaches the texel.
            assert!(!solved || seen.iter().all(|v| v.w > 0.0));
            let fit = stereo.fit(&[0, 1, 2], &seen);
            assert_eq!(fit.is_some(), solved, "{elevation}°");
            if let Some((normal, rho)) = fit {
                assert!((normal.as_dvec3() - n).length() < 1e-5, "{normal}");
                assert!((rho - Vec4::splat(albedo as f32)).length() < 1e-5, "{rho}");
            }
            assert_eq!(stereo.fit(&[0, 1], &seen), None);
        }
    }

    // Fails if the rows are not shared out in whole rows, one band per thread (a band that is not a
    // multiple of the width, or one thread per texel, gives the same normals, so only this sees it).
    #[test]
    fn bands_are_whole_rows_one_per_thread() {
        assert_eq!(band_texels(7, 10, 1), 70);
        assert_eq!(band_texels(7, 10, 3), 28);
        assert_eq!(band_texels(7, 10, 16), 7);
        assert_eq!(band_texels(7, 10, 0), 70);
        assert_eq!(band_texels(0, 0, 4), 1);
    }

    // Fails if photos of different bit depths but the same size (or a photo whose samples are not
    // 3 × width × height) reach the solver: each must be refused, not read as the first one's depth.
    #[test]
    fn photos_must_share_size_depth_and_sample_count() {
        let lights = [Vec3::Z, Vec3::X + Vec3::Z, Vec3::Y + Vec3::Z];
        let eight = |n: usize| Photo {
            width: 2,
            height: 2,
            samples: Samples::Eight(vec![128; n]),
        };
        let sixteen = Photo {
            width: 2,
            height: 2,
            samples: Samples::Sixteen(vec![30000; 12]),
        };
        let options = PhotometricOptions::default();
        recover(&[eight(12), eight(12), eight(12)], &lights, &options).unwrap();
        for photos in [
            [eight(12), sixteen.clone(), eight(12)],
            [eight(12), eight(12), eight(9)],
        ] {
            let error = recover(&photos, &lights, &options).unwrap_err();
            assert!(
                error.to_string().contains("different sizes or bit depths"),
                "{error}"
            );
        }
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
            let calibration = Calibration::default();
            let solver = Stereo::new(&[], &calibration, 8, &options);
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

    /// 16×16 photos (16-bit, linear) of a surface with varying normals and a grey albedo under
    /// `lights`, Lambertian but for up to ±5 % of noise (so that every photo left out or added
    /// changes the fit); some texels are in shadow in some photos.
    fn photos_of_a_bumpy_patch(lights: &[DVec3]) -> Vec<Photo> {
        lights
            .iter()
            .enumerate()
            .map(|(k, l)| {
                let image = image::ImageBuffer::from_fn(16, 16, |x, y| {
                    let (u, v) = (x as f64 / 3.0, y as f64 / 5.0);
                    let n = DVec3::new(0.6 * u.sin(), 0.5 * v.cos(), 1.0).normalize();
                    let noise = ((k as u32 * 7919 + x * 104_729 + y * 1_299_709) % 101) as f64;
                    let lit = 0.7 * n.dot(*l).max(0.0) * (0.95 + 0.001 * noise);
                    image::Rgb([(lit * 65535.0).round() as u16; 3])
                });
                Photo::from_image(image.into())
            })
            .collect()
    }

    // Fails if least squares through each texel's own normal equations (what sets of more than 64
    // photos use) does not give the normals of the cached solve per mask (what smaller sets use),
    // to within one 16-bit step: the same 8 photos are solved both ways.
    #[test]
    fn per_texel_least_squares_is_the_masks_least_squares() {
        let lights = ring(40.0, 8);
        let photos = photos_of_a_bumpy_patch(&lights);
        let options = PhotometricOptions {
            encoding: Encoding::Linear,
            solver: Some(Solver::LeastSquares),
            ..Default::default()
        };
        let calibration = Calibration::default();
        let solve = |method| {
            let mut stereo = Stereo::new(&lights, &calibration, 16, &options);
            stereo.method = method;
            let (mut normals, mut normals16) = (vec![[0; 3]; 256], vec![[0; 3]; 256]);
            let band = Band {
                first: 0,
                normals: &mut normals,
                normals16: Some(&mut normals16),
                albedo: None,
            };
            let unsolved = stereo.band(&photos, sixteen, band);
            (normals16, unsolved)
        };
        let (masks, per_texel) = (solve(Method::Masks), solve(Method::PerTexel));
        assert_eq!(masks.1, per_texel.1);
        for (a, b) in masks.0.iter().zip(&per_texel.0) {
            assert!((0..3).all(|c| a[c].abs_diff(b[c]) <= 1), "{a:?} {b:?}");
        }
    }

    // Fails if the robust solver's ranking does not leave out the darkest tenth and the brightest
    // quarter: of twenty photos, luminances 0 to 19 in a shuffled order, 2 to 14 are kept.
    #[test]
    fn the_middle_ranked_photos_are_kept() {
        let order: Vec<u32> = (0..20).map(|i| i * 7 % 20).collect();
        let light: Vec<Vec4> = order
            .iter()
            .map(|&y| Vec4::new(0.0, 0.0, 0.0, y as f32))
            .collect();
        let mut kept: Vec<u32> = (0..20).collect();
        let mut middle: Vec<u32> = middle_ranked(&mut kept, &light)
            .iter()
            .map(|&k| order[k as usize])
            .collect();
        middle.sort();
        assert_eq!(middle, (2..15).collect::<Vec<u32>>());
        // Fewer than four kept (the robust solver's sets in shadow): a tenth and a quarter of them
        // round down to none, and all are kept in their order (so that the fit sums them as least
        // squares does, to the bit); four leave out the brightest only.
        let light: Vec<Vec4> = (0..4).map(|y| Vec4::new(0.0, 0.0, 0.0, y as f32)).collect();
        let mut kept = vec![2, 1, 0];
        assert_eq!(middle_ranked(&mut kept, &light), [2, 1, 0]);
        let mut kept = vec![3, 2, 1, 0];
        let mut middle = middle_ranked(&mut kept, &light).to_vec();
        middle.sort();
        assert_eq!(middle, [0, 1, 2]);
    }

    // Fails if a set too large to hold is not refused before anything is decoded, with the bytes it
    // would need named (96 photos of 4 294 967 295² at 16 bits: far past any address space).
    #[test]
    fn a_set_too_large_to_hold_is_refused_with_its_size() {
        let error = reserve_for_photos(96, u32::MAX, u32::MAX, 2).unwrap_err();
        let need = 96u128 * u128::from(u32::MAX).pow(2) * 6;
        assert!(
            error.to_string().contains(&format!("need {need} bytes")),
            "{error}"
        );
        reserve_for_photos(96, 612, 512, 2).unwrap();
    }

    // Fails if the capture files' parsers do not skip blank lines and comments, take one value as
    // all three channels, or do not name the file and line of a bad value.
    #[test]
    fn capture_files_parse_as_sets_ship_them() {
        let path = Path::new("l.txt");
        let lights = parse_lights_file("# x y z\n\n0 0 1\n1 0 1 # right\n", path).unwrap();
        assert_eq!(lights, [Vec3::Z, Vec3::new(1.0, 0.0, 1.0)]);
        let rgb = parse_intensities_file("0.5 1 2\n\n3\n", path).unwrap();
        assert_eq!(rgb, [[0.5, 1.0, 2.0], [3.0; 3]]);
        let error = parse_intensities_file("1\n1 nan 1\n", path).unwrap_err();
        assert!(error.to_string().starts_with("l.txt: line 2: "), "{error}");
        let error = parse_lights_file("0 0 0\n", path).unwrap_err();
        assert!(
            error
                .to_string()
                .starts_with("l.txt: line 1: not a direction"),
            "{error}"
        );
    }
}
