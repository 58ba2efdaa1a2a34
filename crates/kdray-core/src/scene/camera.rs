//! The scene's camera (`[camera]`): where it is, what it looks at, and its
//! vertical field of view.

use glam::DVec3;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    pub position: DVec3,
    pub look_at: DVec3,
    pub up: DVec3,
    /// Vertical field of view in degrees, in (0, 180).
    pub vfov_degrees: f64,
}
