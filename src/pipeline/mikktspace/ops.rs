//! The float operations the reference's result depends on, spelled out in its order.

use glam::Vec3;

/// The dot product, summed in the order x, y, z.
pub(super) fn dot(a: Vec3, b: Vec3) -> f32 {
    a.x * b.x + a.y * b.y + a.z * b.z
}

/// The reference's "not zero": above the smallest normal f32.
pub(super) fn not_zero(x: f32) -> bool {
    x.abs() > f32::MIN_POSITIVE
}

/// Some component of `v` not zero.
fn any_not_zero(v: Vec3) -> bool {
    not_zero(v.x) || not_zero(v.y) || not_zero(v.z)
}

/// `v` scaled by the reciprocal of its length (not divided: the reference multiplies).
fn normalize(v: Vec3) -> Vec3 {
    let scale = 1.0 / dot(v, v).sqrt();
    Vec3::new(scale * v.x, scale * v.y, scale * v.z)
}

/// `v` normalized unless it is (nearly) zero.
pub(super) fn normalize_if_not_zero(v: Vec3) -> Vec3 {
    if any_not_zero(v) {
        normalize(v)
    } else {
        v
    }
}

/// `v` with its component along the unit normal `n` taken away, then normalized unless zero.
pub(super) fn on_plane(v: Vec3, n: Vec3) -> Vec3 {
    let along = dot(n, v);
    normalize_if_not_zero(Vec3::new(
        v.x - along * n.x,
        v.y - along * n.y,
        v.z - along * n.z,
    ))
}
