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
//!
//! Its parts: `capture.rs` parses the lights and their brightnesses (flags and files),
//! `lights.rs` measures the lights' spread and checks a set, `stereo.rs` solves a band of rows,
//! `masks.rs` caches each mask's solve, `load.rs` reads the photos and the mask, and `run.rs`
//! is the command; `photo.rs` is a photo as both photo tools read it (this command and
//! `normalmap --from-photo`, whose one-photo guess of a height map it holds too). This file holds
//! the options, the results and the solve over bands of rows.

mod capture;
mod lights;
mod load;
mod masks;
pub mod photo;
mod run;
mod stereo;

use glam::Vec3;

pub use self::capture::{parse_intensities_file, parse_intensity, parse_light, parse_lights_file};
pub use self::lights::light_spread_degrees;
use self::lights::unit_lights;
pub use self::load::{load_photos, reserve_for_photos};
use self::photo::{Encoding, Photo, Samples};
pub use self::run::{run, Job};
use self::stereo::{Band, Stereo};
use crate::normalmap::Green;
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

#[cfg(test)]
mod tests {
    use super::*;

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
}
