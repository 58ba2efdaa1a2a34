//! What a glTF scene's nodes place besides meshes: the first perspective
//! camera (for a model opened on its own), read in the node walk with the
//! node's world transform.

use glam::{DMat4, DVec3};

use crate::scene::Camera;

/// The camera of node `index` placed by `world`: the eye at the node's
/// origin, looking down its -Z axis with +Y up (glTF's camera convention),
/// the vertical field of view `yfov` (radians) in degrees. The node's scale
/// moves no ray: only the directions of its axes are kept. None for an
/// orthographic camera (kdray's camera is a pinhole; the caller warns).
pub(super) fn perspective_camera(
    camera: &gltf::Camera,
    index: usize,
    world: DMat4,
) -> Result<Option<Camera>, String> {
    let gltf::camera::Projection::Perspective(p) = camera.projection() else {
        return Ok(None);
    };
    let at = || format!("node {index} camera {}", camera.index());
    let vfov_degrees = f64::from(p.yfov()).to_degrees();
    if !(vfov_degrees > 0.0 && vfov_degrees < 180.0) {
        return Err(format!(
            "{}: yfov {} rad is not between 0 and pi",
            at(),
            p.yfov()
        ));
    }
    let position = world.transform_point3(DVec3::ZERO);
    let forward = world.transform_vector3(DVec3::NEG_Z);
    let up = world.transform_vector3(DVec3::Y);
    // A zero scale collapses the axes; a shear may fold +Y onto -Z.
    if !(forward.length() > 0.0 && up.cross(forward).length() > 1e-12 * up.length() * forward.length()) {
        return Err(format!(
            "{}: the node transform collapses the camera's view or up direction",
            at()
        ));
    }
    let forward = forward.normalize();
    Ok(Some(Camera {
        position,
        // One unit ahead, scaled to the eye's magnitude so that the two
        // points differ in f64 however far the camera is from the origin.
        look_at: position + forward * position.length().max(1.0),
        up: up.normalize(),
        vfov_degrees,
    }))
}
