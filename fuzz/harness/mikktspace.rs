//! The `mikktspace` target: the program's MikkTSpace against the `mikktspace` crate.

use std::path::Path;

use glam::Vec3;

use tutorial13::common::objloader::TriangleSoup;
use tutorial13::pipeline::mikktspace::mikktspace_tangents_on;

use super::Outcome;
use crate::mikktspace_reference::{first_difference, reference_can_take, reference_tangents};

/// The `mikktspace` target's check (see [`Target::Mikktspace`](super::Target::Mikktspace)).
pub(super) fn check(input: &[u8], _path: &Path) -> Result<Outcome, String> {
    check_mikktspace(input)
}

/// A `mikktspace` input's triangles are cut to this many: the crate's search for degenerate
/// triangles' corners takes time quadratic in the mesh.
const MIKKTSPACE_MAX_TRIANGLES: usize = 2000;

/// A `mikktspace` input as a soup: its first 16 bytes are 16 values (byte b is `b as i8` / 16, and
/// 0x80 is −0), then 3 bytes make a corner, each choosing values by its nibbles: the position
/// (low, high, and bits 2–5), the normal (low, high, bits 1–4; not unit, which MikkTSpace allows)
/// and the UV (low, high).
pub fn mikktspace_soup(input: &[u8]) -> TriangleSoup {
    let value = |k: usize| match input.get(k).copied().unwrap_or(0) {
        0x80 => -0.0,
        b => (b as i8) as f32 / 16.0,
    };
    let v: Vec<f32> = (0..16).map(value).collect();
    let pick = |b: u8, shift: u32| v[(b >> shift) as usize & 15];
    let mut soup = TriangleSoup::default();
    let corners = input.get(16..).unwrap_or(&[]).chunks_exact(3);
    let count = (corners.len() / 3).min(MIKKTSPACE_MAX_TRIANGLES) * 3;
    for c in corners.take(count) {
        let (p, n, uv) = (c[0], c[1], c[2]);
        soup.vertices
            .push(Vec3::new(pick(p, 0), pick(p, 4), pick(p, 2)));
        soup.normals
            .push(Vec3::new(pick(n, 0), pick(n, 4), pick(n, 1)));
        soup.uvs.push(glam::Vec2::new(pick(uv, 0), pick(uv, 4)));
    }
    soup
}

/// The `mikktspace` target's check (see [`Target::Mikktspace`]).
fn check_mikktspace(input: &[u8]) -> Result<Outcome, String> {
    let soup = mikktspace_soup(input);
    if soup.vertices.is_empty() {
        return Ok(Outcome::Rejected("no triangle".into()));
    }
    let ours = mikktspace_tangents_on(&soup, 1).map_err(|e| format!("refused: {e}"))?;
    let threads = mikktspace_tangents_on(&soup, 3).map_err(|e| format!("refused: {e}"))?;
    if let Some(difference) = first_difference(&threads, &ours) {
        return Err(format!("3 threads against 1: {difference}"));
    }
    if reference_can_take(&soup) {
        let reference = reference_tangents(&soup).ok_or("the crate refused the mesh")?;
        if let Some(difference) = first_difference(&ours, &reference) {
            return Err(format!("against the crate: {difference}"));
        }
    } else if let Some(t) = ours.iter().find(|t| **t != [1.0, 0.0, 0.0, -1.0]) {
        return Err(format!("every triangle degenerate, yet a tangent {t:?}"));
    }
    Ok(Outcome::Loaded)
}
