//! The solve of one band of rows: each texel's photos read in linear light, the ones it keeps, its
//! fit (by mask, by its own normal equations, or robust), and its normal and albedo encoded.

use glam::{DMat3, DVec3, Vec3, Vec4};

use super::lights::{nearly_coplanar_scatter, smallest_eigenvalue};
use super::masks::Solves;
use super::{Calibration, PhotometricOptions, Solver, COARSE, MASKED_PHOTOS, ROBUST_FROM};
use super::{ROBUST_BRIGHTEST, ROBUST_DARKEST, SATURATED};
use crate::normalmap::{encode_normal, encode_normal16, Green};
use crate::photometric::photo::{Photo, LUMINANCE};

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
pub(super) struct Band<'o> {
    pub(super) first: usize,
    pub(super) normals: &'o mut [[u8; 3]],
    pub(super) normals16: Option<&'o mut [[u16; 3]]>,
    pub(super) albedo: Option<&'o mut [[u8; 3]]>,
}

impl Band<'_> {
    /// Texel `i` outside the mask: the flat normal, and albedo 0.
    fn outside(&mut self, i: usize) {
        self.normals[i] = encode_normal([0.0, 0.0, 1.0]);
        if let Some(n16) = self.normals16.as_deref_mut() {
            n16[i] = encode_normal16([0.0, 0.0, 1.0]);
        }
        if let Some(albedo) = self.albedo.as_deref_mut() {
            albedo[i] = [0; 3];
        }
    }
}

/// What every band of rows shares.
pub(super) struct Stereo<'a> {
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
    pub(super) fn new(
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
    pub(super) fn band<T: Copy + Into<usize>>(
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
        let mut unsolved = 0;
        for i in 0..out.normals.len() {
            let texel = out.first + i;
            if self.mask.is_some_and(|m| !m[texel]) {
                out.outside(i);
                continue;
            }
            let mask = self.read_texel(&planes, 3 * texel, &mut light, &mut kept);
            let solved = self.solve_texel(&mut solves, mask, &mut kept, &light);
            let solved = solved.unwrap_or_else(|| {
                unsolved += 1;
                (Vec3::Z, Vec4::NAN)
            });
            self.write(&mut out, i, solved, &kept, &light);
        }
        unsolved
    }

    /// Reads the texel at sample `at` of every photo into `light` (linear, over its light's
    /// brightness, with its luminance) and the photos it keeps into `kept`; returns their mask (0
    /// unless the method solves by mask).
    fn read_texel<T: Copy + Into<usize>>(
        &self,
        planes: &[&[T]],
        at: usize,
        light: &mut [Vec4],
        kept: &mut Vec<u32>,
    ) -> u64 {
        let luminance = Vec4::from((Vec3::from(LUMINANCE), 0.0));
        let mut mask = 0u64;
        kept.clear();
        for (k, plane) in planes.iter().enumerate() {
            let codes: [usize; 3] = [plane[at].into(), plane[at + 1].into(), plane[at + 2].into()];
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
        mask
    }

    /// The texel's normal and albedo by the method's fit; `None` where it is left flat (the robust
    /// fit reorders `kept`).
    fn solve_texel(
        &self,
        solves: &mut Solves,
        mask: u64,
        kept: &mut [u32],
        light: &[Vec4],
    ) -> Option<(Vec3, Vec4)> {
        match self.method {
            // g for all four channels at once: row r of the 3×4 matrix Σ_k p_k ⊗ light_k.
            Method::Masks => solves.get(mask).and_then(|columns| {
                let mut g = [Vec4::ZERO; 3];
                for (p, v) in columns.iter().zip(light) {
                    (0..3).for_each(|r| g[r] += p[r] * *v);
                }
                normal_and_albedo(g)
            }),
            Method::PerTexel => self.fit(kept, light),
            Method::Robust => {
                let middle = middle_ranked(kept, light);
                self.fit(middle, light)
            }
        }
    }

    /// Writes texel `i` of `out`: the normal `n` (its green as asked), and the albedo `rho`, or
    /// where it is NaN (the texel left flat) the flat one its kept photos give.
    fn write(
        &self,
        out: &mut Band,
        i: usize,
        (n, rho): (Vec3, Vec4),
        kept: &[u32],
        light: &[Vec4],
    ) {
        let y_sign = match self.options.green {
            Green::Up => 1.0,
            Green::Down => -1.0,
        };
        let n = [n.x, y_sign * n.y, n.z];
        out.normals[i] = encode_normal(n);
        if let Some(n16) = out.normals16.as_deref_mut() {
            n16[i] = encode_normal16(n);
        }
        if let Some(albedo) = out.albedo.as_deref_mut() {
            let rho = if rho.is_nan() {
                flat_albedo(self.lights, kept, light)
            } else {
                rho
            };
            albedo[i] = [self.encode(rho.x), self.encode(rho.y), self.encode(rho.z)];
        }
    }

    /// Whether a photo's texel takes part in its solve: lit (its luminance as the camera saw it at
    /// `shadow` or above) and no channel's stored value saturated.
    fn keeps(&self, seen: f32, codes: [usize; 3]) -> bool {
        seen >= self.options.shadow && codes[0].max(codes[1]).max(codes[2]) < self.saturated
    }

    /// Least squares over the photos `kept`, through their own normal equations
    /// (Σ l lᵀ) g = Σ l I; `None` for fewer than three or lights within
    /// [`MIN_SPREAD_DEGREES`](super::MIN_SPREAD_DEGREES) of one plane.
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

#[cfg(test)]
mod tests {
    use super::super::lights::tests::ring;
    use super::super::sixteen;
    use super::*;
    use crate::photometric::photo::Encoding;

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
}
