//! The light directions' geometry: how far they spread out of one plane (the smallest eigenvalue of
//! their scatter), and the check that a set is one per photo and spread enough.

use glam::{DMat3, DVec3, Vec3};

use super::MIN_SPREAD_DEGREES;
use crate::{Error, Result};

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
pub(super) fn scatter<'a>(lights: impl Iterator<Item = &'a DVec3>) -> DMat3 {
    lights.fold(DMat3::ZERO, |m, &l| {
        m + DMat3::from_cols(l * l.x, l * l.y, l * l.z)
    })
}

/// The smallest eigenvalue of a symmetric 3×3 matrix (the trigonometric closed form).
pub(super) fn smallest_eigenvalue(m: &DMat3) -> f64 {
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
pub(super) fn nearly_coplanar(spread_degrees: f64) -> bool {
    spread_degrees < MIN_SPREAD_DEGREES
}

/// [`nearly_coplanar`] from the smallest eigenvalue of the lights' mean scatter (1/K) Σ l lᵀ, the
/// squared sine of their spread, without the arcsine (it is asked once per texel).
pub(super) fn nearly_coplanar_scatter(smallest_eigenvalue: f64) -> bool {
    let sine = MIN_SPREAD_DEGREES.to_radians().sin();
    smallest_eigenvalue < sine * sine
}

/// Unit directions of `lights`, one per photo, refused if there are not `photos` of them or if they
/// are (nearly) coplanar.
pub(super) fn unit_lights(lights: &[Vec3], photos: usize) -> Result<Vec<DVec3>> {
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

#[cfg(test)]
pub(super) mod tests {
    use super::*;

    pub(in crate::photometric) fn ring(elevation_degrees: f64, k: usize) -> Vec<DVec3> {
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
}
