//! The packet's leaf tests eight lanes at a time, for CPUs with AVX2 ([`super::Bvh::first_hits`]
//! asks for them where the CPU has it): two groups of four rays side by side, so that a leaf's
//! box and triangles take half as many steps. Each lane goes through the operations of
//! [`Lanes::group_entry`] and [`Lanes::intersect`] in their order, with no fused multiply-add, so
//! every distance and barycentric is the four-lane code's to the bit; the hits the pairs keep
//! are the same too (of hits at one distance, the lowest index, whatever the order).
//!
//! A pair is tested where either of its groups enters the leaf's box. The other group's rays
//! are then tested too, which changes nothing: a ray that meets a triangle within its reach
//! enters every (padded) box around it, so each such hit is one its own group would have found.

use std::arch::x86_64::*;

use super::{Aabb, Lanes, Triangle, LIMIT_SLACK};

/// Groups `2p` and `2p + 1` of a component (`[Vec4; G]`) as one vector of eight lanes.
///
/// # Safety
/// `2p + 1 < G`, and the CPU has AVX.
#[inline(always)]
unsafe fn pair<const G: usize>(v: &[glam::Vec4; G], p: usize) -> __m256 {
    debug_assert!(2 * p + 1 < G);
    // SAFETY: glam's Vec4 is four f32 in order, and the array's groups 2p and 2p + 1 are side
    // by side: 32 bytes in bounds.
    unsafe { _mm256_loadu_ps(v.as_ptr().add(2 * p).cast()) }
}

/// |x|, as glam's `abs` (the sign bit cleared).
#[inline(always)]
unsafe fn abs(x: __m256) -> __m256 {
    unsafe { _mm256_andnot_ps(_mm256_set1_ps(-0.0), x) }
}

/// [`Lanes::groups_entering`], two groups at a time.
///
/// # Safety
/// The CPU has AVX2, and `G` is even.
#[target_feature(enable = "avx2")]
#[inline]
pub(super) unsafe fn groups_entering<const G: usize>(lanes: &Lanes<G>, bounds: &Aabb) -> u32 {
    debug_assert!(G % 2 == 0);
    let mut groups = 0;
    for p in 0..G / 2 {
        let mut near = _mm256_setzero_ps();
        let mut far = _mm256_set1_ps(f32::INFINITY);
        for axis in 0..3 {
            // SAFETY: p < G / 2, and the CPU has AVX2.
            let (o, i) = unsafe { (pair(&lanes.origin[axis], p), pair(&lanes.inverse[axis], p)) };
            let t0 = _mm256_mul_ps(_mm256_sub_ps(_mm256_set1_ps(bounds.min[axis]), o), i);
            let t1 = _mm256_mul_ps(_mm256_sub_ps(_mm256_set1_ps(bounds.max[axis]), o), i);
            let along = _mm256_or_ps(
                _mm256_cmp_ps::<_CMP_UNORD_Q>(t0, t0),
                _mm256_cmp_ps::<_CMP_UNORD_Q>(t1, t1),
            );
            let low = _mm256_blendv_ps(
                _mm256_min_ps(t0, t1),
                _mm256_set1_ps(f32::NEG_INFINITY),
                along,
            );
            let high =
                _mm256_blendv_ps(_mm256_max_ps(t0, t1), _mm256_set1_ps(f32::INFINITY), along);
            near = _mm256_max_ps(near, low);
            far = _mm256_min_ps(far, high);
        }
        let far = _mm256_max_ps(far, _mm256_set1_ps(-f32::MAX));
        // SAFETY: as above.
        let reach = unsafe { pair(&lanes.reach, p) };
        // SAFETY: the CPU has AVX2.
        let slack = _mm256_mul_ps(unsafe { abs(far) }, _mm256_set1_ps(LIMIT_SLACK));
        let far = _mm256_min_ps(_mm256_add_ps(far, slack), reach);
        let entry = _mm256_blendv_ps(
            _mm256_set1_ps(f32::INFINITY),
            near,
            _mm256_cmp_ps::<_CMP_LE_OQ>(near, far),
        );
        let entered = _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LT_OQ>(
            entry,
            _mm256_set1_ps(f32::INFINITY),
        )) as u32;
        groups |= (u32::from(entered & 0xF != 0) | u32::from(entered >> 4 != 0) << 1) << (2 * p);
    }
    groups
}

/// [`Lanes::intersect`], two groups at a time: the pairs of which either group is in `groups`.
///
/// # Safety
/// The CPU has AVX2, and `G` is even.
#[target_feature(enable = "avx2")]
#[inline]
pub(super) unsafe fn intersect<const G: usize>(
    lanes: &mut Lanes<G>,
    tri: &Triangle,
    index: u32,
    slot: u32,
    groups: u32,
) {
    let splat = |v: glam::Vec3| v.to_array().map(|c| _mm256_set1_ps(c));
    let [p0x, p0y, p0z] = splat(tri.p0);
    let [e1x, e1y, e1z] = splat(tri.e1);
    let [e2x, e2y, e2z] = splat(tri.e2);
    let (zero, one) = (_mm256_setzero_ps(), _mm256_set1_ps(1.0));
    let infinity = _mm256_set1_ps(f32::INFINITY);
    // A pair's bit where either of its groups' is set.
    let groups = groups & ((1u64 << G) - 1) as u32;
    let mut pairs = (groups | groups >> 1) & 0x5555_5555;
    while pairs != 0 {
        let p = pairs.trailing_zeros() as usize / 2;
        pairs &= pairs - 1;
        // SAFETY: p < G / 2 (the mask's bits are below G), and the CPU has AVX2.
        let [ox, oy, oz, dx, dy, dz] = unsafe {
            [
                pair(&lanes.origin[0], p),
                pair(&lanes.origin[1], p),
                pair(&lanes.origin[2], p),
                pair(&lanes.direction[0], p),
                pair(&lanes.direction[1], p),
                pair(&lanes.direction[2], p),
            ]
        };
        let (mul, add, sub) = (_mm256_mul_ps, _mm256_add_ps, _mm256_sub_ps);
        // p = direction × e2
        let px = sub(mul(dy, e2z), mul(e2y, dz));
        let py = sub(mul(dz, e2x), mul(e2z, dx));
        let pz = sub(mul(dx, e2y), mul(e2x, dy));
        let det = add(add(mul(e1x, px), mul(e1y, py)), mul(e1z, pz));
        let inv = _mm256_div_ps(one, det);
        // s = origin − p0
        let (sx, sy, sz) = (sub(ox, p0x), sub(oy, p0y), sub(oz, p0z));
        let u = mul(add(add(mul(sx, px), mul(sy, py)), mul(sz, pz)), inv);
        // SAFETY: the CPU has AVX2.
        let det_abs = unsafe { abs(det) };
        let within_u = _mm256_and_ps(
            _mm256_and_ps(
                _mm256_cmp_ps::<_CMP_GT_OQ>(det_abs, _mm256_set1_ps(tri.parallel)),
                _mm256_cmp_ps::<_CMP_LT_OQ>(det_abs, infinity),
            ),
            _mm256_and_ps(
                _mm256_cmp_ps::<_CMP_GE_OQ>(u, zero),
                _mm256_cmp_ps::<_CMP_LE_OQ>(u, one),
            ),
        );
        if _mm256_movemask_ps(within_u) == 0 {
            continue;
        }
        // q = s × e1
        let qx = sub(mul(sy, e1z), mul(e1y, sz));
        let qy = sub(mul(sz, e1x), mul(e1z, sx));
        let qz = sub(mul(sx, e1y), mul(e1x, sy));
        let v = mul(add(add(mul(dx, qx), mul(dy, qy)), mul(dz, qz)), inv);
        let t = mul(add(add(mul(e2x, qx), mul(e2y, qy)), mul(e2z, qz)), inv);
        // SAFETY: as above.
        let nearest = unsafe { pair(&lanes.nearest, p) };
        let outside = _mm256_or_ps(
            _mm256_cmp_ps::<_CMP_LT_OQ>(v, zero),
            _mm256_cmp_ps::<_CMP_GT_OQ>(add(u, v), one),
        );
        // SAFETY: as above.
        let t_abs = unsafe { abs(t) };
        let hit = _mm256_and_ps(
            _mm256_andnot_ps(outside, within_u),
            _mm256_and_ps(
                _mm256_and_ps(
                    _mm256_cmp_ps::<_CMP_GE_OQ>(t, zero),
                    _mm256_cmp_ps::<_CMP_LT_OQ>(t_abs, infinity),
                ),
                _mm256_cmp_ps::<_CMP_LE_OQ>(t, nearest),
            ),
        );
        let mask = _mm256_movemask_ps(hit) as u32;
        if mask == 0 {
            continue;
        }
        let (mut ts, mut us, mut vs) = ([0f32; 8], [0f32; 8], [0f32; 8]);
        // SAFETY: each array is eight f32; unaligned stores.
        unsafe {
            _mm256_storeu_ps(ts.as_mut_ptr(), t);
            _mm256_storeu_ps(us.as_mut_ptr(), u);
            _mm256_storeu_ps(vs.as_mut_ptr(), v);
        }
        let mut lanes_hit = mask;
        while lanes_hit != 0 {
            let l = lanes_hit.trailing_zeros() as usize;
            lanes_hit &= lanes_hit - 1;
            lanes.keep(2 * p + l / 4, l % 4, (ts[l], us[l], vs[l]), index, slot);
        }
    }
}
