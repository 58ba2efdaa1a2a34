//! The camera's orthonormal basis: the one place that turns a camera's
//! position, look-at point and up vector into the frame that the kernel,
//! the CPU reference and the window's controls all use.

use glam::DVec3;

use super::camera::Camera;

/// A right-handed orthonormal frame: `forward` looks at the target, `right`
/// is `forward x up` normalised, and `up` is `right x forward` (the scene's
/// up vector made perpendicular to `forward`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraBasis {
    pub position: DVec3,
    pub forward: DVec3,
    pub right: DVec3,
    pub up: DVec3,
    /// tan(vfov / 2): the half-height of the image plane at distance 1.
    pub tan_half_vfov: f64,
}

impl Camera {
    /// The camera's frame. A validated camera has `look_at != position` and
    /// `up` not parallel to the view direction; for a camera that breaks
    /// those rules (a window's controls mid-move) the frame falls back to
    /// looking down -z with x to the right rather than producing NaNs.
    pub fn basis(&self) -> CameraBasis {
        let forward = (self.look_at - self.position).normalize_or(-DVec3::Z);
        let right = forward.cross(self.up).normalize_or(DVec3::X);
        CameraBasis {
            position: self.position,
            forward,
            right,
            up: right.cross(forward),
            tan_half_vfov: (self.vfov_degrees.to_radians() * 0.5).tan(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_camera_looking_down_minus_z_has_the_standard_frame() {
        let camera = Camera {
            position: DVec3::new(0.0, 0.0, 5.0),
            look_at: DVec3::ZERO,
            up: DVec3::new(0.0, 2.0, 0.0),
            vfov_degrees: 90.0,
        };
        let b = camera.basis();
        assert_eq!(b.forward, -DVec3::Z);
        assert_eq!(b.right, DVec3::X);
        assert_eq!(b.up, DVec3::Y);
        assert!((b.tan_half_vfov - 1.0).abs() < 1e-15);
    }

    /// An up vector that is not perpendicular to the view is straightened.
    #[test]
    fn the_frame_is_orthonormal_for_a_tilted_up_vector() {
        let camera = Camera {
            position: DVec3::new(1.0, 2.0, 3.0),
            look_at: DVec3::new(-2.0, 0.5, 0.0),
            up: DVec3::new(0.3, 1.0, 0.2),
            vfov_degrees: 40.0,
        };
        let b = camera.basis();
        for v in [b.forward, b.right, b.up] {
            assert!((v.length() - 1.0).abs() < 1e-12);
        }
        assert!(b.forward.dot(b.right).abs() < 1e-12);
        assert!(b.forward.dot(b.up).abs() < 1e-12);
        assert!(b.right.dot(b.up).abs() < 1e-12);
        // Right-handed, and up on the same side as the scene's up vector.
        assert!((b.right.cross(b.up) - -b.forward).length() < 1e-12);
        assert!(b.up.dot(camera.up) > 0.0);
    }

    #[test]
    fn a_degenerate_camera_gets_a_finite_frame() {
        let camera = Camera {
            position: DVec3::ONE,
            look_at: DVec3::ONE,
            up: DVec3::Y,
            vfov_degrees: 60.0,
        };
        let b = camera.basis();
        assert!(b.forward.is_finite() && b.right.is_finite() && b.up.is_finite());
    }
}
