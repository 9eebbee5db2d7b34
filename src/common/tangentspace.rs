//! `common/tangentspace.cpp`: one tangent and bitangent per triangle corner.
//!
//! Per triangle, the tutorial solves `deltaPos = deltaU * T + deltaV * B` for the two edges. Per
//! corner it then makes T perpendicular to the corner's normal (Gram-Schmidt) and flips T where
//! `dot(cross(n, t), b) < 0` (mirrored UVs). The bitangent is left as solved, not normalized.
//!
//! Where the port differs: a triangle whose UV determinant is zero or not finite (two corners sharing
//! a UV, or UVs on a line) has no frame to solve for; the original then divides by zero and writes
//! NaN/inf tangents. Here each corner of such a triangle gets a finite orthonormal frame instead (see
//! [`fallback_frame`]); the same fallback catches a corner whose Gram-Schmidt result is not finite
//! (tangent parallel to the normal).

use glam::{Vec2, Vec3};

use crate::common::objloader::TriangleSoup;

/// The steps of the per-corner pass, as switches: the tutorial asks its reader to try without them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TangentOptions {
    /// `t = normalize(t - n * dot(n, t))`.
    pub gram_schmidt: bool,
    /// `if dot(cross(n, t), b) < 0 { t = -t }`.
    pub handedness: bool,
}

impl Default for TangentOptions {
    /// The tutorial's code: both steps on.
    fn default() -> Self {
        TangentOptions {
            gram_schmidt: true,
            handedness: true,
        }
    }
}

/// `computeTangentBasis`'s two output vectors, one entry per corner of the soup.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TangentBasis {
    pub tangents: Vec<Vec3>,
    pub bitangents: Vec<Vec3>,
}

/// The tutorial's `computeTangentBasis` over a triangle soup.
pub fn compute_tangent_basis(soup: &TriangleSoup, options: TangentOptions) -> TangentBasis {
    compute_tangent_basis_slices(&soup.vertices, &soup.uvs, &soup.normals, options)
}

/// [`compute_tangent_basis`] on the three corner arrays (lengths equal and a multiple of 3).
pub fn compute_tangent_basis_slices(
    vertices: &[Vec3],
    uvs: &[Vec2],
    normals: &[Vec3],
    options: TangentOptions,
) -> TangentBasis {
    assert!(
        vertices.len() == uvs.len() && vertices.len() == normals.len() && vertices.len() % 3 == 0,
        "compute_tangent_basis needs equal corner arrays, three corners per triangle"
    );
    let n = vertices.len();
    let mut basis = TangentBasis {
        tangents: Vec::with_capacity(n),
        bitangents: Vec::with_capacity(n),
    };
    for ((v, uv), nrm) in vertices
        .chunks_exact(3)
        .zip(uvs.chunks_exact(3))
        .zip(normals.chunks_exact(3))
    {
        // #region solve
        let delta_pos1 = v[1] - v[0];
        let delta_pos2 = v[2] - v[0];
        let delta_uv1 = uv[1] - uv[0];
        let delta_uv2 = uv[2] - uv[0];
        let det = delta_uv1.x * delta_uv2.y - delta_uv1.y * delta_uv2.x;
        let r = 1.0 / det;
        let tangent = (delta_pos1 * delta_uv2.y - delta_pos2 * delta_uv1.y) * r;
        let bitangent = (delta_pos2 * delta_uv1.x - delta_pos1 * delta_uv2.x) * r;
        // #endregion solve
        let solved = det != 0.0 && det.is_finite() && tangent.is_finite() && bitangent.is_finite();
        for &normal in nrm {
            let frame = if solved {
                orthogonalize_corner(normal, tangent, bitangent, options)
            } else {
                None
            };
            let (t, b) = frame.unwrap_or_else(|| fallback_frame(normal, delta_pos1, delta_pos2));
            basis.tangents.push(t);
            basis.bitangents.push(b);
        }
    }
    basis
}

/// The tutorial's per-corner pass ("Going further": Gram-Schmidt, then handedness). `None` when the
/// result would not be finite.
fn orthogonalize_corner(
    n: Vec3,
    mut t: Vec3,
    b: Vec3,
    options: TangentOptions,
) -> Option<(Vec3, Vec3)> {
    if options.gram_schmidt {
        t = gram_schmidt(n, t);
    }
    // #region handedness
    if options.handedness {
        let mut side = n.cross(t).dot(b);
        if side.is_nan() {
            // Vectors near f32::MAX overflow the products (inf - inf): the sign is that of the same
            // test on copies scaled towards 1.
            side = unit_scaled(n).cross(unit_scaled(t)).dot(unit_scaled(b));
        }
        if side < 0.0 {
            t = -t;
        }
    }
    // #endregion handedness
    t.is_finite().then_some((t, b))
}

/// `normalize(t - n * dot(n, t))`. glam's normalize divides by the length, whose square overflows
/// f32 for components past about 1e19 (giving zero or NaN) and underflows below about 1e-19; such a
/// vector still has a direction, so it is normalized from a copy scaled towards 1 (and if the
/// products overflow, computed from a scaled copy of t). Ordinary tangents never reach that path,
/// so they are normalized exactly as the tutorial does. NaN here sends the corner to the fallback.
fn gram_schmidt(n: Vec3, t: Vec3) -> Vec3 {
    let v = t - n * n.dot(t);
    let unit = v.normalize();
    // is_normalized also catches tiny v, whose subnormal squares leave normalize 2 % off.
    if unit.is_finite() && unit.is_normalized() {
        return unit;
    }
    // v is linear in t: from a scaled copy of t it has the same direction, and may not overflow.
    let v = if v.is_finite() {
        v
    } else {
        let t = unit_scaled(t);
        t - n * n.dot(t)
    };
    unit_scaled(v).normalize()
}

/// `v` divided by its largest component's magnitude (unchanged if that is 0 or not finite).
fn unit_scaled(v: Vec3) -> Vec3 {
    let m = v.abs().max_element();
    if m > 0.0 && m.is_finite() {
        v / m
    } else {
        v
    }
}

/// The frame given where the UVs define none. Rule: the unit normal `n` is the corner's normal (the
/// triangle's face normal if that is zero or not finite, +Z if the triangle has no area); `t` is the
/// triangle's first edge made perpendicular to `n` (its second edge if the first is parallel to `n`,
/// any perpendicular if both are); `b = n × t`. So `t` and `b` are unit length, orthogonal to each
/// other and to `n`, right-handed, and the same for every switch setting.
pub fn fallback_frame(normal: Vec3, delta_pos1: Vec3, delta_pos2: Vec3) -> (Vec3, Vec3) {
    let n = direction(normal)
        .or_else(|| direction(delta_pos1.cross(delta_pos2)))
        .unwrap_or(Vec3::Z);
    let t = [delta_pos1, delta_pos2]
        .into_iter()
        .find_map(|edge| direction(edge - n * n.dot(edge)))
        .unwrap_or_else(|| n.any_orthonormal_vector());
    (t, n.cross(t))
}

/// `v` normalized, or `None` for a zero or non-finite `v`. A vector so small (or large) that its
/// squared length leaves f32's normal range is normalized from a copy scaled towards 1: directly,
/// its subnormal square made a fuzzed corner's tangent 0.92 long.
fn direction(v: Vec3) -> Option<Vec3> {
    match v.try_normalize() {
        Some(unit) if unit.is_normalized() => Some(unit),
        _ => unit_scaled(v).try_normalize(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn soup(vertices: [Vec3; 3], uvs: [Vec2; 3], normal: Vec3) -> TriangleSoup {
        TriangleSoup {
            vertices: vertices.to_vec(),
            uvs: uvs.to_vec(),
            normals: vec![normal; 3],
        }
    }

    fn right_triangle(uvs: [Vec2; 3]) -> TriangleSoup {
        soup([Vec3::ZERO, Vec3::X, Vec3::Y], uvs, Vec3::Z)
    }

    const AXIS_UVS: [Vec2; 3] = [Vec2::ZERO, Vec2::X, Vec2::Y];

    // Fails if the per-triangle solve is wrong: U along +x and V along +y must give T=+x, B=+y.
    #[test]
    fn axis_aligned_uvs_give_x_and_y() {
        let basis = compute_tangent_basis(&right_triangle(AXIS_UVS), TangentOptions::default());
        assert_eq!(basis.tangents, vec![Vec3::X; 3]);
        assert_eq!(basis.bitangents, vec![Vec3::Y; 3]);
    }

    // Fails if the solve does not scale with the UV density (B is left unnormalized, like the original).
    #[test]
    fn bitangent_is_not_normalized() {
        let uvs = [Vec2::ZERO, Vec2::new(2.0, 0.0), Vec2::new(0.0, 4.0)];
        let basis = compute_tangent_basis(&right_triangle(uvs), TangentOptions::default());
        assert_eq!(basis.tangents[0], Vec3::X); // normalized by Gram-Schmidt
        assert_eq!(basis.bitangents[0], Vec3::new(0.0, 0.25, 0.0));
    }

    // Fails if mirrored UVs (U running along -x) do not solve to T = -x, or if the handedness step
    // does not then flip T back so that (T, B, N) is right-handed, as the tutorial's code does.
    #[test]
    fn mirrored_uvs_flip_the_tangent() {
        let mirrored = right_triangle([Vec2::ZERO, Vec2::new(-1.0, 0.0), Vec2::Y]);
        let no_flip = TangentOptions {
            handedness: false,
            ..Default::default()
        };
        let solved = compute_tangent_basis(&mirrored, no_flip);
        assert_eq!(solved.tangents[0], -Vec3::X);
        assert_eq!(solved.bitangents[0], Vec3::Y);
        let fixed = compute_tangent_basis(&mirrored, TangentOptions::default());
        assert_eq!(fixed.tangents[0], Vec3::X);
        assert_eq!(fixed.bitangents[0], Vec3::Y);
        assert!(Vec3::Z.cross(fixed.tangents[0]).dot(fixed.bitangents[0]) > 0.0);
    }

    // Fails if Gram-Schmidt leaves any component of T along a tilted corner normal.
    #[test]
    fn gram_schmidt_makes_t_perpendicular_to_n() {
        let n = Vec3::new(0.3, -0.2, 1.0).normalize();
        let tri = soup([Vec3::ZERO, Vec3::X, Vec3::Y], AXIS_UVS, n);
        let basis = compute_tangent_basis(&tri, TangentOptions::default());
        for t in &basis.tangents {
            assert!(t.dot(n).abs() < 1e-6, "{t}");
            assert!((t.length() - 1.0).abs() < 1e-6);
        }
        let off = TangentOptions {
            gram_schmidt: false,
            ..Default::default()
        };
        let raw = compute_tangent_basis(&tri, off);
        assert_eq!(raw.tangents[0], Vec3::X);
        assert!(raw.tangents[0].dot(n).abs() > 0.1);
    }

    // Fails if a zero or non-finite UV determinant leaks NaN/inf or a non-orthonormal frame, for
    // every switch setting.
    #[test]
    fn degenerate_uvs_give_finite_unit_vectors() {
        let cases = [
            [Vec2::ZERO; 3],
            [Vec2::ZERO, Vec2::X, Vec2::new(2.0, 0.0)],
            [Vec2::ZERO, Vec2::X, Vec2::X],
            [Vec2::ZERO, Vec2::new(1e30, 0.0), Vec2::new(0.0, 1e30)],
        ];
        let n = Vec3::new(0.0, 0.6, 0.8);
        for uvs in cases {
            for (gram_schmidt, handedness) in [(true, true), (false, false), (true, false)] {
                let options = TangentOptions {
                    gram_schmidt,
                    handedness,
                };
                let tri = soup([Vec3::ZERO, Vec3::X, Vec3::Y], uvs, n);
                let basis = compute_tangent_basis(&tri, options);
                for (t, b) in basis.tangents.iter().zip(&basis.bitangents) {
                    assert!(t.is_finite() && b.is_finite(), "{uvs:?}: {t} {b}");
                    assert!((t.length() - 1.0).abs() < 1e-6 && (b.length() - 1.0).abs() < 1e-6);
                    assert!(
                        t.dot(n).abs() < 1e-6 && b.dot(n).abs() < 1e-6 && t.dot(*b).abs() < 1e-6
                    );
                }
            }
        }
    }

    // Fails if an edge so short (1e-23 off the normal) that its squared length is subnormal gives a
    // tangent that is not unit length (it was 0.92 long, found by the fuzzer).
    #[test]
    fn fallback_is_unit_for_tiny_edges() {
        let normal = Vec3::new(0.0, 1e-30, 0.0099);
        let (t, b) = fallback_frame(normal, Vec3::ZERO, Vec3::new(1e-30, 0.0, -483648.0));
        assert!(t.is_normalized() && b.is_normalized(), "{t} {b}");
    }

    // Fails if a triangle with no area, or a zero normal, reaches NaN in the fallback.
    #[test]
    fn fallback_survives_zero_area_and_zero_normal() {
        for (normal, e1, e2) in [
            (Vec3::ZERO, Vec3::ZERO, Vec3::ZERO),
            (Vec3::ZERO, Vec3::X, Vec3::Y),
            (Vec3::Y, Vec3::Y, Vec3::Y * 2.0),
            (Vec3::NAN, Vec3::X, Vec3::X),
        ] {
            let (t, b) = fallback_frame(normal, e1, e2);
            assert!(
                t.is_normalized() && b.is_normalized(),
                "{normal} {e1} {e2}: {t} {b}"
            );
            assert!(t.dot(b).abs() < 1e-6);
        }
    }

    // Fails if the solve reads an edge as a sum, not a difference, of two corners (positions or
    // UVs), or if either product of the UV determinant, the edge weights or `r = 1 / det` is
    // changed: a triangle away from the origin, UVs away from (0, 0), no UV component 0 or ±1, and
    // det = 4, with both per-corner steps off, gives exactly the solved T = (0.75, -0.5, 0) and
    // B = (1, 2, 0).
    #[test]
    fn offset_triangle_solves_to_the_exact_frame() {
        let p0 = Vec3::new(1.0, 2.0, 3.0);
        let uv0 = Vec2::new(0.5, 0.25);
        let tri = TriangleSoup {
            vertices: vec![
                p0,
                p0 + Vec3::new(2.0, 0.0, 0.0),
                p0 + Vec3::new(0.0, 4.0, 0.0),
            ],
            uvs: vec![uv0, uv0 + Vec2::new(2.0, 0.5), uv0 + Vec2::new(-2.0, 1.5)],
            normals: vec![Vec3::Z; 3],
        };
        let raw = TangentOptions {
            gram_schmidt: false,
            handedness: false,
        };
        let basis = compute_tangent_basis(&tri, raw);
        assert_eq!(basis.tangents, vec![Vec3::new(0.75, -0.5, 0.0); 3]);
        assert_eq!(basis.bitangents, vec![Vec3::new(1.0, 2.0, 0.0); 3]);
    }

    // Fails if the handedness step flips T when `dot(cross(n, t), b)` is exactly 0 (the tutorial
    // tests `< 0`): on a triangle with no area whose UVs still solve (T = +x, B = 2x, so the test
    // gives 0), T stays +x.
    #[test]
    fn handedness_leaves_a_zero_side_unflipped() {
        let flat = soup([Vec3::ZERO, Vec3::X, Vec3::X * 2.0], AXIS_UVS, Vec3::Z);
        let basis = compute_tangent_basis(&flat, TangentOptions::default());
        assert_eq!(basis.tangents, vec![Vec3::X; 3]);
        assert_eq!(basis.bitangents, vec![Vec3::X * 2.0; 3]);
    }

    // Fails if the fallback does not take the first edge minus its component along the normal: a
    // normal +z and a first edge (2, 0, 1) give t = +x exactly, and b = z × x = +y.
    #[test]
    fn fallback_takes_the_first_edge_off_the_normal() {
        let (t, b) = fallback_frame(Vec3::Z, Vec3::new(2.0, 0.0, 1.0), Vec3::new(0.0, 3.0, 0.0));
        assert_eq!((t, b), (Vec3::X, Vec3::Y));
    }

    // Fails if an ordinary vector is normalized from its copy scaled towards 1 rather than
    // directly: (2, 3, 6) normalizes directly to (2, 3, 6) / 7 as glam rounds it, which differs in
    // the last bit from normalizing (1/3, 1/2, 1).
    #[test]
    fn ordinary_directions_are_normalized_directly() {
        let v = Vec3::new(2.0, 3.0, 6.0);
        assert_ne!(v.normalize(), (v / 6.0).normalize());
        assert_eq!(direction(v), Some(v.normalize()));
    }

    // Fails if Gram-Schmidt keeps glam's normalize of a tangent whose squared length is subnormal
    // (edges 1e-22 long: 1e-44 is rounded to 7 × 2^-149, which leaves the "unit" vector 1 % long):
    // that tangent is normalized from a copy scaled towards 1 and is exactly +x.
    #[test]
    fn tiny_tangents_normalize_exactly() {
        let tiny = soup(
            [Vec3::ZERO, Vec3::X * 1e-22, Vec3::Y * 1e-22],
            AXIS_UVS,
            Vec3::Z,
        );
        assert!(!(Vec3::X * 1e-22).normalize().is_normalized());
        let basis = compute_tangent_basis(&tiny, TangentOptions::default());
        assert_eq!(basis.tangents, vec![Vec3::X; 3]);
    }

    // Fails if Gram-Schmidt of a tangent so large that `t - n * dot(n, t)` overflows is not taken
    // from the tangent scaled towards 1, in the same arithmetic: t = (3e38, 3e38, 0) against
    // n = (0.6, 0.8, 0) (dot 4.2e38, past f32::MAX) gives exactly the result for t = (1, 1, 0).
    #[test]
    fn overflowing_gram_schmidt_is_that_of_the_scaled_tangent() {
        let n = Vec3::new(0.6, 0.8, 0.0);
        let huge = Vec3::new(3e38, 3e38, 0.0);
        assert!(!(huge - n * n.dot(huge)).is_finite());
        let unit = gram_schmidt(n, Vec3::new(1.0, 1.0, 0.0));
        assert!(unit.is_normalized() && unit.dot(n).abs() < 1e-6, "{unit}");
        assert_eq!(gram_schmidt(n, huge), unit);
    }
}
