//! The lights of the photometric captures the tests and the bench make: included with `#[path]`
//! by tests/all and benches/photometric.rs, so that both photograph under the same rig.

use glam::Vec3;

/// 96 lights as capture rigs place them: directions up to 55° from the camera's axis (a sunflower
/// spiral), each with its own brightness per channel (from 0.5 to 1).
pub fn rig() -> Vec<(Vec3, [f32; 3])> {
    (0..96)
        .map(|i| {
            let polar = 55f32.to_radians() * ((i as f32 + 0.5) / 96.0).sqrt();
            let azimuth = i as f32 * 137.508f32.to_radians();
            let l = Vec3::new(
                polar.sin() * azimuth.cos(),
                polar.sin() * azimuth.sin(),
                polar.cos(),
            );
            let wobble = |m: usize| 0.5 + 0.5 * ((i * m) % 97) as f32 / 96.0;
            (l, [wobble(37), wobble(59), wobble(71)])
        })
        .collect()
}
