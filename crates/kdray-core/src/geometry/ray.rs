//! A ray, the stand-ins for infinity and for parallel in its arithmetic,
//! and where a secondary ray starts off a surface.

use glam::Vec3;

/// Stand-in for infinity: WGSL implementations may assume no inf or NaN.
pub const T_INFINITY: f32 = 3.0e38;
/// Direction components smaller than this count as parallel to an axis
/// plane, so no division can overflow.
pub const PARALLEL_EPSILON: f32 = 1e-20;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ray {
    pub origin: Vec3,
    /// Unit length.
    pub dir: Vec3,
}

/// Distance to move a secondary ray's origin off the surface along N.
///
/// 1e-4 of the hit point's magnitude (at least 1e-4 scene units), and never
/// less than 2^-22 of the largest coordinate the intersection test worked
/// with: a sphere of radius 9000 centred 9000 away computes |o - c|^2 - r^2
/// with an absolute error of ~16 units^2, i.e. ~1e-3 units of distance, far
/// more than 1e-4. Scaling with the object (not the scene's extent) keeps
/// small objects' contact shadows tight while big ones show no acne.
pub fn spawn_offset(hit_point: Vec3, object_magnitude: f32) -> f32 {
    (1e-4 * hit_point.abs().max_element().max(1.0)).max(object_magnitude * (1.0 / 4_194_304.0))
}
