//! `common/controls.cpp`: the tutorial's first-person camera.
//!
//! The mouse turns the camera (0.005 rad per pixel of motion), the arrow keys move it (3 units per
//! second) along the view direction and the right vector. The projection's aspect is the tutorial's 4:3
//! until a front end gives the viewport's (the original keeps 4:3 whatever the window's shape, which
//! stretches a resized window; 1024×768 gives the same float, so the tutorial's frame is unchanged).
//! The angles use 3.14 where π would do, as the original.

use glam::camera::rh::view::look_at_mat4;
use glam::{Mat4, Vec3, Vec4};

/// The tutorial writes 3.14 for π (start angle, and the quarter turn of `right`); keeping its value
/// keeps its first frame.
#[allow(clippy::approx_constant)]
pub const TUTORIAL_PI: f32 = 3.14;

/// What the window saw since the last frame.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Input {
    /// Mouse motion in pixels, +x right and +y down (the tutorial re-centres the cursor each frame and
    /// reads the offset from the centre; raw motion gives the same numbers without warping).
    pub mouse_dx: f64,
    pub mouse_dy: f64,
    /// Arrow keys held.
    pub up: bool,
    pub down: bool,
    pub left: bool,
    pub right: bool,
}

/// The tutorial's globals of `controls.cpp`, in a struct.
#[derive(Debug, Clone, PartialEq)]
pub struct Controls {
    pub position: Vec3,
    /// Toward -Z at 3.14.
    pub horizontal_angle: f32,
    /// 0: look at the horizon.
    pub vertical_angle: f32,
    /// Degrees.
    pub initial_fov: f32,
    /// Units per second.
    pub speed: f32,
    /// Radians per pixel.
    pub mouse_speed: f32,
    /// Width / height of the projection; the tutorial's `4.0f / 3.0f` by default.
    pub aspect: f32,
    view_matrix: Mat4,
    projection_matrix: Mat4,
}

impl Default for Controls {
    fn default() -> Self {
        let mut controls = Controls {
            position: Vec3::new(0.0, 0.0, 5.0),
            horizontal_angle: TUTORIAL_PI,
            vertical_angle: 0.0,
            initial_fov: 45.0,
            speed: 3.0,
            mouse_speed: 0.005,
            aspect: 4.0 / 3.0,
            view_matrix: Mat4::IDENTITY,
            projection_matrix: Mat4::IDENTITY,
        };
        controls.compute_matrices_from_inputs(&Input::default(), 0.0);
        controls
    }
}

impl Controls {
    /// The tutorial's start camera with the projection's aspect from a viewport of `width × height`.
    pub fn for_viewport(width: u32, height: u32) -> Self {
        let mut controls = Controls::default();
        controls.set_viewport(width, height);
        controls.compute_matrices_from_inputs(&Input::default(), 0.0);
        controls
    }

    /// Makes the projection follow a viewport of `width × height` (nothing changes for an empty
    /// one, e.g. a minimized window). Takes effect at the next `compute_matrices_from_inputs`.
    pub fn set_viewport(&mut self, width: u32, height: u32) {
        if width > 0 && height > 0 {
            self.aspect = width as f32 / height as f32;
        }
    }

    /// Moves the camera back along its view direction until a sphere at `center` of `radius` fits
    /// the view (the narrower of the two fields of view), with a 5 % margin. Not the tutorial's:
    /// its start position is framed for its own cylinder only (a learner's model uses this).
    pub fn frame_sphere(&mut self, center: Vec3, radius: f32) {
        let half_fov_y = radians_as_glm(self.initial_fov) / 2.0;
        let half_fov_x = (half_fov_y.tan() * self.aspect).atan();
        let distance = 1.05 * radius / half_fov_y.min(half_fov_x).sin();
        self.position = center - self.direction() * distance;
        self.compute_matrices_from_inputs(&Input::default(), 0.0);
    }

    /// Spherical angles to a direction, as the tutorial's `direction` vector.
    pub fn direction(&self) -> Vec3 {
        let (h, v) = (self.horizontal_angle, self.vertical_angle);
        Vec3::new(v.cos() * h.sin(), v.sin(), v.cos() * h.cos())
    }

    /// The tutorial's `right` vector: horizontal, a quarter turn from the direction.
    pub fn right(&self) -> Vec3 {
        let h = self.horizontal_angle - TUTORIAL_PI / 2.0;
        Vec3::new(h.sin(), 0.0, h.cos())
    }

    /// One frame of `computeMatricesFromInputs`: turn, move, then rebuild both matrices.
    pub fn compute_matrices_from_inputs(&mut self, input: &Input, delta_time: f32) {
        // The original adds mouseSpeed * (centre - cursor): moving right lowers the angle, which
        // turns the view to the right.
        self.horizontal_angle -= self.mouse_speed * input.mouse_dx as f32;
        self.vertical_angle -= self.mouse_speed * input.mouse_dy as f32;

        let direction = self.direction();
        let right = self.right();
        let up = right.cross(direction);

        let step = delta_time * self.speed;
        if input.up {
            self.position += direction * step;
        }
        if input.down {
            self.position -= direction * step;
        }
        if input.right {
            self.position += right * step;
        }
        if input.left {
            self.position -= right * step;
        }

        // The original's 4.0f / 3.0f, or the viewport's aspect (1024 / 768 is the same float).
        self.projection_matrix =
            perspective_as_glm(radians_as_glm(self.initial_fov), self.aspect, 0.1, 100.0);
        self.view_matrix = look_at_mat4(self.position, self.position + direction, up);
    }

    pub fn view_matrix(&self) -> Mat4 {
        self.view_matrix
    }

    pub fn projection_matrix(&self) -> Mat4 {
        self.projection_matrix
    }
}

/// `glm::radians` for a float: degrees times GLM's constant rounded to f32.
pub fn radians_as_glm(degrees: f32) -> f32 {
    #[allow(clippy::excessive_precision)]
    const GLM_DEGREES_TO_RADIANS: f32 = 0.01745329251994329576923690768489;
    degrees * GLM_DEGREES_TO_RADIANS
}

/// `glm::perspective` (right-handed, clip depth −1..1, what the tutorial's GLM 0.9.9 uses) with GLM's
/// operations in GLM's order, so that every element rounds as in the C++ original: 1/(aspect·tan(fovy/2)),
/// 1/tan(fovy/2), −(far+near)/(far−near), −(2·far·near)/(far−near). glam's `perspective` gives the same
/// matrix up to the last bit of a few elements (it multiplies by reciprocals in another order), which
/// moves a few edge pixels of the frame.
pub fn perspective_as_glm(fovy: f32, aspect: f32, z_near: f32, z_far: f32) -> Mat4 {
    let tan_half_fovy = (fovy / 2.0).tan();
    Mat4::from_cols(
        Vec4::new(1.0 / (aspect * tan_half_fovy), 0.0, 0.0, 0.0),
        Vec4::new(0.0, 1.0 / tan_half_fovy, 0.0, 0.0),
        Vec4::new(0.0, 0.0, -(z_far + z_near) / (z_far - z_near), -1.0),
        Vec4::new(0.0, 0.0, -(2.0 * z_far * z_near) / (z_far - z_near), 0.0),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: Mat4, b: Mat4, eps: f32) -> bool {
        a.abs_diff_eq(b, eps)
    }

    // Fails if the start position, angles or look-at convention differ from the tutorial's: the first
    // view looks from (0, 0, 5) toward -Z. 3.14 is 0.0016 rad short of π, which tilts the rotation by
    // that much and moves the origin sideways by 5 × 0.0016 = 0.008: hence the 1e-2 tolerance.
    #[test]
    fn initial_view_looks_down_minus_z() {
        let c = Controls::default();
        let expected = look_at_mat4(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::Y);
        assert!(
            close(c.view_matrix(), expected, 1e-2),
            "{}",
            c.view_matrix()
        );
        let d = c.direction();
        assert!(
            (0.0015..0.0017).contains(&d.x) && d.y == 0.0 && d.z < -0.99999,
            "{d}"
        );
        // The world origin lands 5 units in front of the camera.
        let origin = c.view_matrix().transform_point3(Vec3::ZERO);
        assert!(
            (origin - Vec3::new(0.0, 0.0, -5.0)).length() < 1e-2,
            "{origin}"
        );
    }

    // Fails if the projection is not the tutorial's 45°, 4:3, near 0.1, far 100 GL matrix.
    #[test]
    fn projection_is_45_degrees_4_by_3() {
        let p = Controls::default().projection_matrix();
        let f = 1.0 / (22.5f32.to_radians()).tan();
        assert!((p.y_axis.y - f).abs() < 1e-5);
        assert!((p.x_axis.x - f * 0.75).abs() < 1e-5);
        // A point on the near plane maps to NDC z = -1, on the far plane to +1.
        let near = p.project_point3(Vec3::new(0.0, 0.0, -0.1));
        let far = p.project_point3(Vec3::new(0.0, 0.0, -100.0));
        assert!((near.z + 1.0).abs() < 1e-5 && (far.z - 1.0).abs() < 1e-4);
    }

    // Fails if a viewport's aspect does not reach the projection, or if 1024×768 does not give the
    // tutorial's 4:3 matrix bit for bit (its first frame depends on it).
    #[test]
    fn projection_follows_the_viewport() {
        let tutorial = Controls::default().projection_matrix();
        assert_eq!(
            Controls::for_viewport(1024, 768).projection_matrix(),
            tutorial
        );
        assert_eq!(
            Controls::for_viewport(640, 480).projection_matrix(),
            tutorial
        );
        let wide = Controls::for_viewport(1920, 1080).projection_matrix();
        assert_eq!(wide.y_axis.y, tutorial.y_axis.y);
        assert!((wide.x_axis.x * 16.0 / 9.0 - wide.y_axis.y).abs() < 1e-6);
        // A minimized window (0 × 0) keeps the last aspect instead of dividing by zero.
        let mut c = Controls::for_viewport(1920, 1080);
        c.set_viewport(0, 0);
        c.compute_matrices_from_inputs(&Input::default(), 0.0);
        assert_eq!(c.projection_matrix(), wide);
    }

    // Fails if a viewport with one side 0 (a window minimized on one axis) changes the aspect to 0
    // or infinity: only a viewport with both sides above 0 is taken.
    #[test]
    fn a_viewport_empty_on_either_side_keeps_the_aspect() {
        for (width, height) in [(0, 768), (1024, 0), (0, 0)] {
            let mut c = Controls::default();
            c.set_viewport(width, height);
            assert_eq!(c.aspect, 4.0 / 3.0, "{width}×{height}");
        }
    }

    // Fails if `direction` is not the tutorial's spherical formula away from the start angles (at
    // the start, cos v = 1 and a term's product with it cannot be told from a quotient), or if the
    // view matrix does not look from the camera along it with `right` to the right: a camera turned
    // and moved off every axis must see its own position at the origin, position + direction at
    // (0, 0, -1) and `right` along +X (to 0.0008 rad).
    #[test]
    fn the_view_looks_along_direction_from_anywhere() {
        let (h, v) = (0.5f64, 0.3f64);
        let c = Controls {
            horizontal_angle: h as f32,
            vertical_angle: v as f32,
            ..Controls::default()
        };
        let expected = Vec3::new(
            (v.cos() * h.sin()) as f32,
            v.sin() as f32,
            (v.cos() * h.cos()) as f32,
        );
        assert!(
            (c.direction() - expected).length() < 1e-6,
            "{}",
            c.direction()
        );

        let mut c = Controls::default();
        let input = Input {
            mouse_dx: 60.0,
            mouse_dy: -35.0,
            up: true,
            left: true,
            ..Default::default()
        };
        c.compute_matrices_from_inputs(&input, 0.7);
        let view = c.view_matrix();
        assert!(
            c.position.x.abs() > 0.3 && c.position.y.abs() > 0.3,
            "{}",
            c.position
        );
        assert!(view.transform_point3(c.position).length() < 1e-5);
        let ahead = view.transform_point3(c.position + c.direction());
        assert!((ahead - Vec3::NEG_Z).length() < 1e-5, "{ahead}");
        // `right` turns by 3.14 / 2, not π / 2, so it is 0.0008 rad off the view's exact +X.
        let right = view.transform_vector3(c.right());
        assert!((right - Vec3::X).length() < 1e-3, "{right}");
    }

    // Fails if `frame_sphere` does not put the camera back along its view direction at
    // 1.05 r / sin(half the narrower field of view) from the centre, by an independent f64
    // computation: at 4:3 the vertical half-angle is 22.5°; at 1:2 the horizontal one,
    // atan(tan 22.5° / 2) = 11.7°, is the narrower.
    #[test]
    fn frame_sphere_fits_the_narrower_field_of_view() {
        let half_y = 22.5f64.to_radians();
        for (width, height, half) in [(1024, 768, half_y), (400, 800, (half_y.tan() * 0.5).atan())]
        {
            let mut c = Controls::for_viewport(width, height);
            let center = Vec3::new(1.0, 2.0, 3.0);
            c.frame_sphere(center, 2.0);
            let distance = 1.05 * 2.0 / half.sin();
            let back = center - c.position;
            assert!(
                (f64::from(back.length()) - distance).abs() < 1e-4,
                "{width}×{height}: {} for {distance}",
                back.length()
            );
            assert!((back.normalize() - c.direction()).length() < 1e-6);
            // The view matrix follows: the centre straight ahead at that distance.
            let seen = c.view_matrix().transform_point3(center);
            assert!(
                (seen - Vec3::new(0.0, 0.0, -distance as f32)).length() < 1e-4,
                "{seen}"
            );
        }
    }

    // Fails if the projection in GLM's order is not glam's perspective matrix up to rounding (the
    // orders differ only in the last bits, which is the point of keeping GLM's).
    #[test]
    fn glm_order_projection_is_glams_up_to_rounding() {
        let ours = perspective_as_glm(radians_as_glm(45.0), 4.0 / 3.0, 0.1, 100.0);
        let glams =
            glam::camera::rh::proj::opengl::perspective(45f32.to_radians(), 4.0 / 3.0, 0.1, 100.0);
        assert!(close(ours, glams, 1e-5), "{ours} {glams}");
        assert!((radians_as_glm(45.0) - 45f32.to_radians()).abs() < 1e-7);
    }

    // Fails if the mouse does not turn by mouse_speed × pixels with the original's signs.
    #[test]
    fn mouse_turns_by_the_tutorials_formula() {
        let mut c = Controls::default();
        let input = Input {
            mouse_dx: 100.0,
            mouse_dy: -40.0,
            ..Default::default()
        };
        c.compute_matrices_from_inputs(&input, 0.016);
        assert!((c.horizontal_angle - (TUTORIAL_PI - 0.5)).abs() < 1e-6);
        assert!((c.vertical_angle - 0.2).abs() < 1e-6);
        // Mouse up (negative dy) looks up; position does not move without keys.
        assert!(c.direction().y > 0.19);
        assert_eq!(c.position, Vec3::new(0.0, 0.0, 5.0));
    }

    // Fails if the arrow keys do not move 3 units per second along direction and right.
    #[test]
    fn arrow_keys_move_along_direction_and_right() {
        let mut c = Controls::default();
        let forward = Input {
            up: true,
            ..Default::default()
        };
        let direction = c.direction();
        c.compute_matrices_from_inputs(&forward, 0.5);
        assert!((c.position - (Vec3::new(0.0, 0.0, 5.0) + direction * 1.5)).length() < 1e-6);
        let start = c.position;
        let right = c.right();
        let strafe = Input {
            right: true,
            ..Default::default()
        };
        c.compute_matrices_from_inputs(&strafe, 1.0);
        assert!((c.position - (start + right * 3.0)).length() < 1e-6);
        // Looking toward -Z, "right" is +X.
        assert!((right - Vec3::X).length() < 1e-2, "{right}");
        let both = Input {
            left: true,
            right: true,
            up: true,
            down: true,
            ..Default::default()
        };
        let before = c.position;
        c.compute_matrices_from_inputs(&both, 1.0);
        assert!((c.position - before).length() < 1e-5);
    }
}
