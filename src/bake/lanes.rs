//! A packet's samples side by side: the normalizations of LOW's and HIGH's normals and the
//! shading's solve, t = (T B N)⁻¹ n normalized, for all its samples at once. Each component is in
//! an array of its own, one lane a sample, so that the divisions and square roots of several
//! samples run in one instruction (SSE2's four f32 or two f64 lanes; twice as many where the CPU
//! has AVX). The operations are glam's (`Vec3::normalize_or_zero`; `DMat3::determinant`,
//! `inverse`, `* DVec3` and `DVec3::normalize_or_zero`), in their order: every IEEE operation
//! here rounds the same in a vector lane as alone (and nothing is fused), so each lane's answer is
//! the scalar one, to the bit; the tests hold it to that.

use glam::{DVec3, Vec3};

use super::bvh::PACKET;

/// A packet's vectors, component by component.
pub(crate) struct Vec3Lanes {
    pub axes: [[f32; PACKET]; 3],
}

impl Vec3Lanes {
    pub fn new() -> Vec3Lanes {
        Vec3Lanes {
            axes: [[0.0; PACKET]; 3],
        }
    }

    pub fn set(&mut self, k: usize, v: Vec3) {
        for axis in 0..3 {
            self.axes[axis][k] = v[axis];
        }
    }

    pub fn get(&self, k: usize) -> Vec3 {
        let [x, y, z] = &self.axes;
        Vec3::new(x[k], y[k], z[k])
    }

    /// `Vec3::normalize_or_zero` of every lane.
    pub fn normalize_or_zero(&mut self) {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx") {
            // SAFETY: the CPU has AVX, which is all that `normalize_avx` is compiled for beyond
            // SSE2.
            return unsafe { normalize_avx(self) };
        }
        normalize_lanes(self)
    }
}

/// [`normalize_lanes`] compiled for AVX (eight f32 lanes an instruction).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
unsafe fn normalize_avx(v: &mut Vec3Lanes) {
    normalize_lanes(v)
}

#[inline(always)]
fn normalize_lanes(v: &mut Vec3Lanes) {
    let [x, y, z] = &mut v.axes;
    for k in 0..PACKET {
        let rcp = 1.0 / ((x[k] * x[k]) + (y[k] * y[k]) + (z[k] * z[k])).sqrt();
        let unit = rcp.is_finite() && rcp > 0.0;
        for a in [&mut x[k], &mut y[k], &mut z[k]] {
            *a = if unit { *a * rcp } else { 0.0 };
        }
    }
}

/// A packet's frames (columns T, B and N) and HIGH's normals, component by component.
pub(crate) struct FrameLanes {
    pub columns: [[[f64; PACKET]; 3]; 3],
    pub high: [[f64; PACKET]; 3],
}

impl FrameLanes {
    pub fn new() -> FrameLanes {
        FrameLanes {
            columns: [[[0.0; PACKET]; 3]; 3],
            high: [[0.0; PACKET]; 3],
        }
    }

    /// Lane `k`'s frame and HIGH's normal.
    #[cfg(test)]
    pub fn set(&mut self, k: usize, frame: &[DVec3; 3], high: Vec3) {
        for (column, c) in self.columns.iter_mut().zip(frame) {
            for axis in 0..3 {
                column[axis][k] = c[axis];
            }
        }
        self.set_high(k, high);
    }

    /// Lane `k`'s HIGH normal.
    pub fn set_high(&mut self, k: usize, high: Vec3) {
        for axis in 0..3 {
            self.high[axis][k] = high[axis] as f64;
        }
    }

    /// Lane `k`'s frame, its columns T, B, N.
    pub fn frame(&self, k: usize) -> [DVec3; 3] {
        self.columns.map(|[x, y, z]| DVec3::new(x[k], y[k], z[k]))
    }
}

/// Each lane's solve: its normalized t (0 where it has no length), and whether the frame has an
/// inverse (its columns span some volume relative to their lengths).
pub(crate) struct Solved {
    pub normal: [[f64; PACKET]; 3],
    pub invertible: [bool; PACKET],
}

impl Solved {
    pub fn new() -> Solved {
        Solved {
            normal: [[0.0; PACKET]; 3],
            invertible: [false; PACKET],
        }
    }
}

/// The solve of every lane of `lanes` into `out` (the lanes past a packet's samples too: their
/// zeros give no inverse).
pub(crate) fn solve(lanes: &FrameLanes, out: &mut Solved) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx") {
        // SAFETY: the CPU has AVX, which is all that `solve_avx` is compiled for beyond SSE2.
        return unsafe { solve_avx(lanes, out) };
    }
    solve_lanes(lanes, out)
}

/// [`solve_lanes`] compiled for AVX (four f64 lanes an instruction; AVX has no fused
/// multiply-add, so nothing rounds differently).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
unsafe fn solve_avx(lanes: &FrameLanes, out: &mut Solved) {
    solve_lanes(lanes, out)
}

#[inline(always)]
fn solve_lanes(lanes: &FrameLanes, out: &mut Solved) {
    let [x, y, z] = &lanes.columns;
    let n = &lanes.high;
    // Written out as glam writes each step (see the module's description), lane by lane.
    let cross = |a: [f64; 3], b: [f64; 3]| {
        [
            a[1] * b[2] - b[1] * a[2],
            a[2] * b[0] - b[2] * a[0],
            a[0] * b[1] - b[0] * a[1],
        ]
    };
    let dot = |a: [f64; 3], b: [f64; 3]| (a[0] * b[0]) + (a[1] * b[1]) + (a[2] * b[2]);
    for k in 0..PACKET {
        let x = [x[0][k], x[1][k], x[2][k]];
        let y = [y[0][k], y[1][k], y[2][k]];
        let z = [z[0][k], z[1][k], z[2][k]];
        let n = [n[0][k], n[1][k], n[2][k]];
        // The rows of the inverse, before the division by the determinant.
        let rows = [cross(y, z), cross(z, x), cross(x, y)];
        let det = dot(x, rows[0]);
        let scale = 1.0 * dot(x, x).sqrt() * dot(y, y).sqrt() * dot(z, z).sqrt();
        out.invertible[k] = det.abs() > 1e-9 * scale && det.is_finite();
        let inverse = 1.0 / det;
        let t = rows.map(|r| {
            ((r[0] * inverse) * n[0]) + ((r[1] * inverse) * n[1]) + ((r[2] * inverse) * n[2])
        });
        let rcp = 1.0 / dot(t, t).sqrt();
        let unit = rcp.is_finite() && rcp > 0.0;
        for (out, t) in out.normal.iter_mut().zip(t) {
            out[k] = if unit { t * rcp } else { 0.0 };
        }
    }
}

#[cfg(test)]
mod tests {
    use glam::DMat3;

    use super::*;
    use crate::bake::xorshift;

    /// Fails if a lane's normalization differs from glam's in a bit: random vectors of every
    /// size, zeros, ones too long to square, NaN and infinities among them.
    #[test]
    fn each_lane_is_glams_normalization_to_the_bit() {
        let mut bits = xorshift(0x9e37_79b9_7f4a_7c15);
        let mut next = move || (bits() >> 40) as f32 / (1u32 << 24) as f32 * 2.0 - 1.0;
        let special = [0.0, -0.0, 1e-30, 1e-45, 1e20, 3e38, f32::INFINITY, f32::NAN];
        let mut zero = 0;
        for round in 0..2000 {
            let mut lanes = Vec3Lanes::new();
            let mut vectors = [Vec3::ZERO; PACKET];
            for (k, v) in vectors.iter_mut().enumerate() {
                *v = Vec3::new(next(), next(), next()) * 10f32.powi((round + k) as i32 % 13 - 6);
                if (round + k) % 5 == 0 {
                    v[k % 3] = special[(round + k) / 5 % special.len()];
                }
                lanes.set(k, *v);
            }
            let mut each = Vec3Lanes { axes: lanes.axes };
            lanes.normalize_or_zero();
            normalize_lanes(&mut each);
            for (k, v) in vectors.iter().enumerate() {
                let want = v.normalize_or_zero().to_array().map(f32::to_bits);
                assert_eq!(
                    lanes.get(k).to_array().map(f32::to_bits),
                    want,
                    "lane {k}: {v}"
                );
                assert_eq!(
                    each.get(k).to_array().map(f32::to_bits),
                    want,
                    "lane {k}: {v}"
                );
                zero += usize::from(want == [0; 3]);
            }
        }
        // Both kinds of lane were met.
        assert!(zero > 1000, "{zero} without a direction");
    }

    /// The scalar solve the shading did before the lanes: glam's own calls.
    fn scalar(frame: &[DVec3; 3], n: Vec3) -> (bool, DVec3) {
        let matrix = DMat3::from_cols(frame[0], frame[1], frame[2]);
        let det = matrix.determinant();
        let scale = frame.iter().map(|c| c.length()).product::<f64>();
        if !(det.abs() > 1e-9 * scale && det.is_finite()) {
            return (false, DVec3::ZERO);
        }
        (true, (matrix.inverse() * n.as_dvec3()).normalize_or_zero())
    }

    /// Fails if any lane differs from the scalar solve in a bit, or in whether the frame has an
    /// inverse: frames from random columns (some near one plane, some with a zero or huge
    /// column), the special values among them.
    #[test]
    fn each_lane_is_the_scalar_solve_to_the_bit() {
        let mut bits = xorshift(0x2545_f491_4f6c_dd1d);
        let mut next = move || (bits() >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0;
        let special = [0.0, -0.0, 1e-300, 1e300, f64::INFINITY, f64::NAN, 1.0];
        let (mut compared, mut singular) = (0, 0);
        for round in 0..400 {
            let mut lanes = FrameLanes::new();
            let mut cases = Vec::new();
            for k in 0..PACKET {
                let mut v = || DVec3::new(next(), next(), next());
                let mut frame = [v(), v(), v()];
                match (round + k) % 9 {
                    // Nearly one plane: N almost in T and B's plane.
                    0 => frame[2] = frame[0] * 0.5 + frame[1] * 0.25 + v() * 1e-12,
                    1 => frame[1] = DVec3::ZERO,
                    2 => frame[0][k % 3] = special[(round + k) % special.len()],
                    3 => frame[2] *= 1e200,
                    _ => {}
                }
                let n = Vec3::new(next() as f32, next() as f32, next() as f32);
                let n = if k % 11 == 0 { Vec3::ZERO } else { n };
                lanes.set(k, &frame, n);
                cases.push((frame, n));
            }
            let (mut solved, mut each) = (Solved::new(), Solved::new());
            solve(&lanes, &mut solved);
            solve_lanes(&lanes, &mut each);
            for (k, (frame, n)) in cases.iter().enumerate() {
                let (invertible, t) = scalar(frame, *n);
                assert_eq!(solved.invertible[k], invertible, "lane {k} of {frame:?}");
                assert_eq!(each.invertible[k], invertible, "lane {k} of {frame:?}");
                singular += usize::from(!invertible);
                if !invertible {
                    continue;
                }
                for axis in 0..3 {
                    let bits =
                        [solved.normal[axis][k], each.normal[axis][k], t[axis]].map(f64::to_bits);
                    assert!(
                        bits[0] == bits[2] && bits[1] == bits[2],
                        "lane {k} {frame:?} {n}: {bits:?}"
                    );
                }
                compared += 1;
            }
        }
        // Both kinds of lane were met.
        assert!(
            compared > 10_000 && singular > 3_000,
            "{compared} solved, {singular} singular"
        );
    }
}
