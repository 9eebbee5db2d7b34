//! Combining normal maps: a detail normal map laid over a base normal map
//! (`tutorial13 normalmap --combine BASE DETAIL -o out.png`), by the methods Barré-Brisebois and
//! Hill compare in "Blending in Detail" (2012).
//!
//! Each method is a pure function of two unit tangent-space normals, the base's `n1 = (x1, y1, z1)`
//! and the detail's `n2 = (x2, y2, z2)`, both with z ≥ 0, returning a unit normal:
//!
//! - [`rnm`], reoriented normal mapping (the default): the detail rotated by the rotation that takes
//!   (0, 0, 1) to the base normal, i.e. the detail's relief laid on the base's tilted surface.
//! - [`whiteout`]: normalize(x1 + x2, y1 + y2, z1·z2).
//! - [`udn`]: normalize(x1 + x2, y1 + y2, z1), as whiteout with the detail's z taken as 1.
//! - [`linear`]: normalize(n1 + n2), the half-way vector: it flattens both.
//! - [`partial_derivatives`]: the slopes added, normalize(x1/z1 + x2/z2, y1/z1 + y2/z2, 1): the
//!   normal of the base's height plus the detail's, measured vertically.
//!
//! Texels are read as n = 2·c/max − 1 (max 255 or 65535), the y of `--green down` maps negated, a z
//! below 0 (blue under half) taken as 0, and normalized. The detail is tiled `detail_scale` times
//! (any positive number) across the base and sampled with bilinear filtering that wraps around its
//! edges; when `detail_scale` × the detail's size is the base's size, every sample falls on a texel
//! centre and is that texel. The result has the base's size.

use std::path::Path;

use crate::normalmap::{decode_image, encode_normal, encode_normal16, Green};
use crate::pipeline::runs_on_cores;
use crate::{Error, Result};

/// The normal of an untouched surface.
pub const FLAT: [f32; 3] = [0.0, 0.0, 1.0];

/// How the detail is laid over the base.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum Method {
    /// Reoriented normal mapping: the detail turned as the base is turned
    #[default]
    Rnm,
    /// Slopes added, the detail's z times the base's
    Whiteout,
    /// Slopes added, the base's z kept (flattens the detail)
    Udn,
    /// The two normals averaged (flattens both)
    Linear,
    /// Partial derivatives: the two heights added
    Pd,
}

/// `method` applied to the base normal `base` and the detail normal `detail`.
pub fn combine(method: Method, base: [f32; 3], detail: [f32; 3]) -> [f32; 3] {
    match method {
        Method::Rnm => rnm(base, detail),
        Method::Whiteout => whiteout(base, detail),
        Method::Udn => udn(base, detail),
        Method::Linear => linear(base, detail),
        Method::Pd => partial_derivatives(base, detail),
    }
}

/// Reoriented normal mapping: `detail` rotated by the shortest rotation that takes (0, 0, 1) to
/// `base`. With s = (0, 0, 1), k = s × base = (−y1, x1, 0) (its length the sine of the angle) and
/// c = s · base = z1 (its cosine), Rodrigues' formula is R v = c v + k × v + (k · v) k / (1 + c).
pub fn rnm(base: [f32; 3], detail: [f32; 3]) -> [f32; 3] {
    let [x1, y1, z1] = base;
    let [x2, y2, z2] = detail;
    let k = [-y1, x1, 0.0];
    let k_cross_v = [x1 * z2, y1 * z2, -(x1 * x2 + y1 * y2)];
    // 1 + c ≥ 1 for a base with z ≥ 0.
    let along_k = (x1 * y2 - y1 * x2) / (1.0 + z1);
    normalize([
        z1 * x2 + k_cross_v[0] + along_k * k[0],
        z1 * y2 + k_cross_v[1] + along_k * k[1],
        z1 * z2 + k_cross_v[2],
    ])
}

/// Whiteout blending: the x and y added, the z multiplied.
pub fn whiteout(base: [f32; 3], detail: [f32; 3]) -> [f32; 3] {
    normalize([
        base[0] + detail[0],
        base[1] + detail[1],
        base[2] * detail[2],
    ])
}

/// UDN blending: the x and y added, the base's z kept.
pub fn udn(base: [f32; 3], detail: [f32; 3]) -> [f32; 3] {
    normalize([base[0] + detail[0], base[1] + detail[1], base[2]])
}

/// Linear blending: the sum (the half-way vector).
pub fn linear(base: [f32; 3], detail: [f32; 3]) -> [f32; 3] {
    normalize([
        base[0] + detail[0],
        base[1] + detail[1],
        base[2] + detail[2],
    ])
}

/// Partial derivatives: each normal's slopes (x/z, y/z) added, as (x1/z1 + x2/z2, y1/z1 + y2/z2, 1);
/// computed multiplied through by z1·z2, which gives the same direction and no division by zero.
pub fn partial_derivatives(base: [f32; 3], detail: [f32; 3]) -> [f32; 3] {
    let [x1, y1, z1] = base;
    let [x2, y2, z2] = detail;
    normalize([x1 * z2 + x2 * z1, y1 * z2 + y2 * z1, z1 * z2])
}

/// `v` scaled to unit length; [`FLAT`] for a zero or non-finite vector.
fn normalize(v: [f32; 3]) -> [f32; 3] {
    let len2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
    if !(len2 > 1e-24 && len2.is_finite()) {
        return FLAT;
    }
    let inv = 1.0 / len2.sqrt();
    v.map(|c| c * inv)
}

/// `v` with y negated for `Green::Down`: the same on the way in and on the way out.
fn green_up(v: [f32; 3], green: Green) -> [f32; 3] {
    match green {
        Green::Up => v,
        Green::Down => [v[0], -v[1], v[2]],
    }
}

/// A 16-bit texel (an 8-bit one times 257) as a unit normal, green up: 2·c/65535 − 1 per
/// component, z below 0 taken as 0.
pub fn decode_texel(texel: [u16; 3], green: Green) -> [f32; 3] {
    let [x, y, z] = texel.map(|c| 2.0 * f32::from(c) / 65535.0 - 1.0);
    normalize(green_up([x, y, z.max(0.0)], green))
}

/// A normal map as unit normals, green up, row 0 at the top.
#[derive(Debug, Clone, PartialEq)]
pub struct NormalMap {
    pub width: u32,
    pub height: u32,
    pub normals: Vec<[f32; 3]>,
}

impl NormalMap {
    /// Reads an RGB(A) normal map, PNG, BMP, TGA or JPEG, 8 or 16 bits, stored with `green`.
    pub fn load(path: &Path, green: Green) -> Result<Self> {
        let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
        Self::from_bytes(&bytes, path, green)
    }

    /// [`NormalMap::load`] on bytes already read; `path` names them in errors. A grey-scale image
    /// (a height map given by mistake) and a map whose blue is 0 everywhere (a two-channel map)
    /// are refused.
    pub fn from_bytes(bytes: &[u8], path: &Path, green: Green) -> Result<Self> {
        let bad = |reason: &str| Error::Image {
            path: path.to_path_buf(),
            reason: reason.into(),
        };
        let image = decode_image(bytes, path, "a normal map")?;
        if !image.color().has_color() {
            return Err(bad("a grey-scale image, not a normal map (a height map? \
                 `tutorial13 normalmap HEIGHT -o OUT` makes its normal map)"));
        }
        let rgb = image.into_rgb16();
        if rgb.pixels().all(|p| p.0[2] == 0) {
            return Err(bad(
                "blue is 0 in every texel: a two-channel map, which --combine does not read",
            ));
        }
        let (width, height) = rgb.dimensions();
        let normals = rgb.pixels().map(|p| decode_texel(p.0, green)).collect();
        Ok(NormalMap {
            width,
            height,
            normals,
        })
    }

    /// The normal at (`x`, `y`) in texels (texel centres at whole numbers, row 0 at the top),
    /// interpolated bilinearly between the four nearest texels, wrapping around the edges.
    pub fn sample_wrapped(&self, x: f64, y: f64) -> [f32; 3] {
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = ((x - x0) as f32, (y - y0) as f32);
        let wrap = |i: f64, n: u32| (i as i64).rem_euclid(i64::from(n)) as usize;
        let (c0, c1) = (wrap(x0, self.width), wrap(x0 + 1.0, self.width));
        let (r0, r1) = (wrap(y0, self.height), wrap(y0 + 1.0, self.height));
        let at = |c: usize, r: usize| self.normals[r * self.width as usize + c];
        let mut sum = [0.0; 3];
        for (n, weight) in [
            (at(c0, r0), (1.0 - fx) * (1.0 - fy)),
            (at(c1, r0), fx * (1.0 - fy)),
            (at(c0, r1), (1.0 - fx) * fy),
            (at(c1, r1), fx * fy),
        ] {
            for (s, c) in sum.iter_mut().zip(n) {
                *s += weight * c;
            }
        }
        normalize(sum)
    }
}

/// `detail` tiled `detail_scale` times (a positive number) across `base` and laid over it by
/// `method`: unit normals, green up, `base`'s size.
pub fn combine_maps(
    base: &NormalMap,
    detail: &NormalMap,
    method: Method,
    detail_scale: f64,
) -> Vec<[f32; 3]> {
    // Detail texels per base texel; exactly 1 when the tiles cover the base texel for texel.
    let kx = detail_scale * f64::from(detail.width) / f64::from(base.width);
    let ky = detail_scale * f64::from(detail.height) / f64::from(base.height);
    let mut out = Vec::with_capacity(base.normals.len());
    for row in 0..base.height as usize {
        let y = (row as f64 + 0.5) * ky - 0.5;
        for col in 0..base.width as usize {
            let x = (col as f64 + 0.5) * kx - 0.5;
            let n1 = base.normals[row * base.width as usize + col];
            out.push(combine(method, n1, detail.sample_wrapped(x, y)));
        }
    }
    out
}

/// Unit normals (green up; arrays or `Vec3`s) as 8-bit texels stored with `green`: the packing
/// `--combine` and the bake write.
pub fn texels8<N: Copy + Into<[f32; 3]> + Sync>(normals: &[N], green: Green) -> Vec<[u8; 3]> {
    // A run per core: a 2048² bake's 4M texels took 0.02 s on one.
    let runs = runs_on_cores(normals, |run| {
        (run.iter())
            .map(|&n| encode_normal(green_up(n.into(), green)))
            .collect::<Vec<_>>()
    });
    runs.concat()
}

/// Unit normals (green up; arrays or `Vec3`s) as 16-bit texels stored with `green`.
pub fn texels16<N: Copy + Into<[f32; 3]>>(normals: &[N], green: Green) -> Vec<[u16; 3]> {
    normals
        .iter()
        .map(|&n| encode_normal16(green_up(n.into(), green)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    const METHODS: [Method; 5] = [
        Method::Rnm,
        Method::Whiteout,
        Method::Udn,
        Method::Linear,
        Method::Pd,
    ];

    /// Fails if a map's texels, encoded a run per core, are not each normal's own texel, in order.
    #[test]
    fn a_large_maps_texels_are_each_normals_own() {
        let mut next = crate::bake::xorshift(0x7e4e15);
        let normals: Vec<[f32; 3]> = (0..150_001)
            .map(|_| [0, 1, 2].map(|_| (next() >> 40) as f32 / (1u64 << 23) as f32 - 1.0))
            .collect();
        for green in [Green::Up, Green::Down] {
            let one_pass: Vec<[u8; 3]> = (normals.iter())
                .map(|&n| encode_normal(green_up(n, green)))
                .collect();
            assert!(texels8(&normals, green) == one_pass, "{green:?}");
        }
    }

    /// An 8-bit texel as the tool reads it.
    fn decode8(texel: [u8; 3]) -> [f32; 3] {
        decode_texel(texel.map(|c| u16::from(c) * 257), Green::Up)
    }

    /// The angle between two vectors in degrees, in f64 (acos of f32 loses small angles).
    fn degrees(a: [f32; 3], b: [f32; 3]) -> f64 {
        let [a, b] = [a, b].map(|v| v.map(f64::from));
        let cross = [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ];
        let sine = cross.iter().map(|c| c * c).sum::<f64>().sqrt();
        let cosine: f64 = a.iter().zip(&b).map(|(x, y)| x * y).sum();
        sine.atan2(cosine).to_degrees()
    }

    /// Texels of unit normals leaning up to about 65° every way, as a map would store them.
    fn texels() -> Vec<[u8; 3]> {
        let mut texels = Vec::new();
        for r in (0..=255u8).step_by(5) {
            for g in (0..=255u8).step_by(5) {
                let (x, y) = (f32::from(r) / 127.5 - 1.0, f32::from(g) / 127.5 - 1.0);
                if x * x + y * y < 0.83 {
                    texels.push(encode_normal(normalize([
                        x,
                        y,
                        (1.0 - x * x - y * y).sqrt(),
                    ])));
                }
            }
        }
        assert!(texels.len() > 1500);
        texels
    }

    // (a) Fails if a flat detail (0, 0, 1) does not give the base back within one 8-bit level with
    // RNM, whiteout, UDN or partial derivatives, or a flat base the detail back with RNM, whiteout or
    // partial derivatives; or if the two exceptions stop being exceptions. Linear is the half-way
    // vector, normalize(n + (0, 0, 1)): it halves every tilt, as base or as detail. UDN keeps the
    // base's z, so a flat base gives normalize(x2, y2, 1): the detail's tilt flattened (a 45° detail
    // comes out at 35°); as detail, flat adds nothing to x and y and the base is kept.
    #[test]
    fn a_flat_map_gives_the_other_back_where_the_method_allows() {
        let within_a_level =
            |a: [u8; 3], b: [u8; 3]| a.iter().zip(b).all(|(x, y)| x.abs_diff(y) <= 1);
        for method in METHODS {
            let (mut base_kept, mut detail_kept) = (true, true);
            for &texel in &texels() {
                let n = decode8(texel);
                base_kept &= within_a_level(encode_normal(combine(method, n, FLAT)), texel);
                detail_kept &= within_a_level(encode_normal(combine(method, FLAT, n)), texel);
            }
            let (expect_base, expect_detail) = match method {
                Method::Rnm | Method::Whiteout | Method::Pd => (true, true),
                Method::Udn => (true, false),
                Method::Linear => (false, false),
            };
            assert_eq!(base_kept, expect_base, "{method:?}: flat detail");
            assert_eq!(detail_kept, expect_detail, "{method:?}: flat base");
        }
        // The exceptions, as the comment above says: halved, and 45° flattened to 35.3°.
        let tilted = normalize([1.0, 0.0, 1.0]);
        assert!((degrees(linear(tilted, FLAT), FLAT) - 22.5).abs() < 1e-3);
        let flattened = degrees(udn(FLAT, tilted), FLAT);
        assert!((flattened - 0.5f64.sqrt().atan().to_degrees()).abs() < 1e-3);
    }

    // Fails if RNM is not a rotation taking (0, 0, 1) to the base: the result must be unit length,
    // keep the detail's angle to (0, 0, 1) as its angle to the base, and turn the detail by the
    // base's tilt in the plane of the tilt (a detail leaning as the base does leans twice as far).
    #[test]
    fn rnm_turns_the_detail_as_the_base_is_turned() {
        for &b in texels().iter().step_by(7) {
            for &d in texels().iter().step_by(11) {
                let (base, detail) = (decode8(b), decode8(d));
                let r = rnm(base, detail);
                let len = r.iter().map(|c| c * c).sum::<f32>().sqrt();
                assert!((len - 1.0).abs() < 1e-5, "{b:?} {d:?}: length {len}");
                let (kept, had) = (degrees(r, base), degrees(detail, FLAT));
                assert!((kept - had).abs() < 0.01, "{b:?} {d:?}: {kept}° vs {had}°");
            }
        }
        let at = |deg: f32| [deg.to_radians().sin(), 0.0, deg.to_radians().cos()];
        assert!(degrees(rnm(at(30.0), at(20.0)), at(50.0)) < 1e-4);
        let across = rnm(
            at(30.0),
            [0.0, 20f32.to_radians().sin(), 20f32.to_radians().cos()],
        );
        assert!(across[1] > 0.3 && (degrees(across, at(30.0)) - 20.0).abs() < 1e-3);
    }

    // (b) The detail's relief on a slope, with an exact answer. The base is the plane z = a·x, whose
    // normal is nb = normalize(−a, 0, 1); the detail is the relief h(u, v) = A sin(ωu) cos(ωv), whose
    // normal map holds normalize(−h_u, −h_v, 1). What a tangent-space detail map means is a relief
    // measured in the frame of the surface it lies on: along that surface (u along
    // t = normalize(1, 0, a), v along b = (0, 1, 0), the texture laid on the slope unstretched) and
    // out of it along nb. So the reference is the surface S(u, v) = u·t + v·b + h(u, v)·nb and its
    // normal S_u × S_v, computed from the partial derivatives of S (not from any rotation). RNM
    // claims exactly this (the rotation taking (0, 0, 1) to nb takes the detail's frame
    // (x, y, (0, 0, 1)) to (t, b, nb)), so with exact inputs it should be exact, and with 8-bit
    // inputs off by their rounding alone; every other method errs by the slope. The other reading,
    // heights added vertically (z = a·x + h(x, y): the relief not turned with the slope, stretched
    // along it), is what partial derivatives compute exactly: it is measured too. Fails if RNM is
    // not exact (within 0.01°) against the first reference with exact inputs and the closest with
    // 8-bit ones, or partial derivatives the same against the second. The figures are printed
    // (`cargo test --release --lib combine -- --nocapture`); docs/tools.md lists them.
    #[test]
    fn detail_on_a_slope_rnm_is_closest_to_the_relief_laid_on_it() {
        let cross = |p: [f32; 3], q: [f32; 3]| {
            [
                p[1] * q[2] - p[2] * q[1],
                p[2] * q[0] - p[0] * q[2],
                p[0] * q[1] - p[1] * q[0],
            ]
        };
        // Detail slopes up to 0.8 (39°), sampled on a 48 × 48 grid over one period.
        let (amplitude_times_omega, steps) = (0.8f32, 48);
        let best = |errors: [f64; 5]| {
            let least = errors.iter().copied().fold(f64::INFINITY, f64::min);
            METHODS[errors.iter().position(|&e| e == least).unwrap()]
        };
        println!(
            "mean angle error (°), exact inputs | 8-bit inputs: laid on the slope, heights added"
        );
        for a in [0.25f32, 0.5, 1.0] {
            let nb = normalize([-a, 0.0, 1.0]);
            let t = normalize([1.0, 0.0, a]);
            let b = [0.0, 1.0, 0.0];
            // Per input precision (exact, 8-bit): the mean errors against each reference.
            let mut laid = [[0.0f64; 5]; 2];
            let mut added = [[0.0f64; 5]; 2];
            for i in 0..steps {
                for j in 0..steps {
                    let phase = |k: usize| std::f32::consts::TAU * k as f32 / steps as f32;
                    let (wu, wv) = (phase(i), phase(j));
                    let h_u = amplitude_times_omega * wu.cos() * wv.cos();
                    let h_v = -amplitude_times_omega * wu.sin() * wv.sin();
                    let detail = normalize([-h_u, -h_v, 1.0]);
                    let s_u = [t[0] + h_u * nb[0], t[1] + h_u * nb[1], t[2] + h_u * nb[2]];
                    let s_v = [b[0] + h_v * nb[0], b[1] + h_v * nb[1], b[2] + h_v * nb[2]];
                    let on_slope = normalize(cross(s_u, s_v));
                    let heights = normalize(cross([1.0, 0.0, a + h_u], [0.0, 1.0, h_v]));
                    let inputs = [
                        (nb, detail),
                        (decode8(encode_normal(nb)), decode8(encode_normal(detail))),
                    ];
                    for (p, (base, detail)) in inputs.into_iter().enumerate() {
                        for (k, &method) in METHODS.iter().enumerate() {
                            let n = combine(method, base, detail);
                            laid[p][k] += degrees(n, on_slope);
                            added[p][k] += degrees(n, heights);
                        }
                    }
                }
            }
            let count = (steps * steps) as f64;
            let laid = laid.map(|errors| errors.map(|e| e / count));
            let added = added.map(|errors| errors.map(|e| e / count));
            for (k, method) in METHODS.iter().enumerate() {
                println!(
                    "slope {a} ({:.1}°) {method:?}: {:.2}, {:.2} | {:.2}, {:.2}",
                    a.atan().to_degrees(),
                    laid[0][k],
                    added[0][k],
                    laid[1][k],
                    added[1][k]
                );
            }
            assert!(laid[0][0] < 0.01, "slope {a}: RNM {laid:?}");
            assert!(
                added[0][4] < 0.01,
                "slope {a}: partial derivatives {added:?}"
            );
            for p in 0..2 {
                assert_eq!(best(laid[p]), Method::Rnm, "slope {a}: {laid:?}");
                assert_eq!(best(added[p]), Method::Pd, "slope {a}: {added:?}");
            }
        }
    }

    // Fails if samples do not fall on texel centres at whole coordinates, do not wrap past either
    // edge, or are not the normalized bilinear mix between texels; or if tiling a detail whose
    // tiles cover the base texel for texel is not that detail repeated.
    #[test]
    fn the_detail_is_sampled_bilinearly_and_wraps() {
        let (a, b) = (normalize([0.6, 0.0, 0.8]), normalize([-0.6, 0.0, 0.8]));
        let detail = NormalMap {
            width: 2,
            height: 1,
            normals: vec![a, b],
        };
        assert_eq!(detail.sample_wrapped(0.0, 0.0), a);
        assert_eq!(detail.sample_wrapped(1.0, 7.0), b);
        assert_eq!(detail.sample_wrapped(-1.0, -3.0), b);
        assert_eq!(detail.sample_wrapped(4.0, 0.0), a);
        // Half-way between a and b either way round: straight up.
        for x in [0.5, 1.5, -0.5] {
            assert!(degrees(detail.sample_wrapped(x, 0.25), FLAT) < 1e-4, "{x}");
        }
        let mix = normalize([0.75 * a[0] + 0.25 * b[0], 0.0, 0.75 * a[2] + 0.25 * b[2]]);
        assert!(degrees(detail.sample_wrapped(0.25, 0.0), mix) < 1e-4);
        assert!(degrees(detail.sample_wrapped(-1.75, 0.6), mix) < 1e-4);
        let base = NormalMap {
            width: 6,
            height: 2,
            normals: vec![FLAT; 12],
        };
        let tiled = combine_maps(&base, &detail, Method::Rnm, 3.0);
        for (i, n) in tiled.iter().enumerate() {
            let expected = if i % 2 == 0 { a } else { b };
            assert!(degrees(*n, expected) < 1e-4, "texel {i}: {n:?}");
        }
    }

    // Fails if 8-bit and 16-bit texels are not read as 2·c/max − 1 (normalized), if green down is
    // not y negated on the way in and on the way out, if a z below 0 is not read as 0, or if a
    // grey-scale image or a two-channel map (blue 0 everywhere) is accepted.
    #[test]
    fn texels_decode_as_the_green_convention_says() {
        let encoded = |image: image::DynamicImage| {
            let mut bytes = std::io::Cursor::new(Vec::new());
            image.write_to(&mut bytes, image::ImageFormat::Png).unwrap();
            bytes.into_inner()
        };
        let rgb8 = image::RgbImage::from_raw(2, 1, vec![255, 128, 128, 0, 200, 60]).unwrap();
        let rgb16 = image::ImageBuffer::<image::Rgb<u16>, _>::from_raw(
            2,
            1,
            vec![65535, 32896, 32896, 0, 51400, 15420],
        )
        .unwrap();
        for bytes in [
            encoded(image::DynamicImage::ImageRgb8(rgb8)),
            encoded(image::DynamicImage::ImageRgb16(rgb16)),
        ] {
            let path = Path::new("n.png");
            let up = NormalMap::from_bytes(&bytes, path, Green::Up).unwrap();
            let down = NormalMap::from_bytes(&bytes, path, Green::Down).unwrap();
            assert_eq!((up.width, up.height), (2, 1));
            let c = |v: f32| 2.0 * v / 255.0 - 1.0;
            let expected = normalize([c(255.0), c(128.0), c(128.0)]);
            assert!(
                degrees(up.normals[0], expected) < 1e-3,
                "{:?}",
                up.normals[0]
            );
            // Blue 60 is below the surface: z 0.
            let expected = normalize([-1.0, c(200.0), 0.0]);
            assert!(
                degrees(up.normals[1], expected) < 1e-3,
                "{:?}",
                up.normals[1]
            );
            for (u, d) in up.normals.iter().zip(&down.normals) {
                assert_eq!([u[0], -u[1], u[2]], *d);
            }
            assert_eq!(
                texels8(&down.normals, Green::Down),
                texels8(&up.normals, Green::Up)
            );
            let n = [normalize([0.3, 0.4, 0.8])];
            let (t_up, t_down) = (texels8(&n, Green::Up)[0], texels8(&n, Green::Down)[0]);
            assert!((i32::from(t_up[1]) + i32::from(t_down[1]) - 255).abs() <= 1);
            let (w_up, w_down) = (texels16(&n, Green::Up)[0], texels16(&n, Green::Down)[0]);
            assert!(w_up[1] > 32768 && w_down[1] < 32768);
        }
        let grey = encoded(image::DynamicImage::ImageLuma8(
            image::GrayImage::from_raw(1, 1, vec![9]).unwrap(),
        ));
        let error = NormalMap::from_bytes(&grey, Path::new("g.png"), Green::Up).unwrap_err();
        assert!(
            error.to_string().starts_with("g.png: a grey-scale image"),
            "{error}"
        );
        let two = encoded(image::DynamicImage::ImageRgb8(
            image::RgbImage::from_raw(1, 1, vec![9, 200, 0]).unwrap(),
        ));
        let error = NormalMap::from_bytes(&two, Path::new("t.png"), Green::Up).unwrap_err();
        assert!(error.to_string().contains("two-channel"), "{error}");
    }
}
