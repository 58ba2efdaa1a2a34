//! What a glTF scene's nodes place besides meshes: the first perspective
//! camera and the `KHR_lights_punctual` lights (for a model opened on its
//! own), read in the node walk with the node's world transform.

use glam::{DMat4, DVec3};

use crate::scene::camera::Camera;
use crate::scene::light::Light;
use crate::scene::light_kind::LightKind;

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
    if !(forward.length() > 0.0
        && up.cross(forward).length() > 1e-12 * up.length() * forward.length())
    {
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

/// The `KHR_lights_punctual` light of node `index` placed by `world`: at the
/// node's origin, shining down its -Z axis (spot and directional). glTF's
/// photometric intensity is read one for one as kdray's radiometric units
/// (docs/scene-format.md): `diffuse` = `specular` = colour x intensity (cd
/// as W/sr for point and spot lights, lux as W/m^2 for directional ones),
/// `ambient` 0. `range` is ignored (the falloff stays 1 / d^2).
pub(super) fn punctual_light(
    light: &gltf::khr_lights_punctual::Light,
    index: usize,
    world: DMat4,
) -> Result<Light, String> {
    use gltf::khr_lights_punctual::Kind;
    let at = || format!("node {index} light {}", light.index());
    let colour = DVec3::from_array(light.color().map(f64::from)) * f64::from(light.intensity());
    if !(colour.is_finite() && colour.min_element() >= 0.0) {
        return Err(format!(
            "{}: colour x intensity must be finite and >= 0, got {colour}",
            at()
        ));
    }
    let direction = || {
        crate::scene::normals::unit(world.transform_vector3(DVec3::NEG_Z)).ok_or_else(|| {
            format!(
                "{}: the node transform collapses the light's direction",
                at()
            )
        })
    };
    let kind = match light.kind() {
        Kind::Point => LightKind::Point,
        Kind::Directional => LightKind::Directional {
            direction: direction()?,
        },
        Kind::Spot {
            inner_cone_angle,
            outer_cone_angle,
        } => {
            let (inner, outer) = (
                f64::from(inner_cone_angle).to_degrees(),
                f64::from(outer_cone_angle).to_degrees(),
            );
            // glTF: 0 <= inner < outer <= pi / 2.
            if !(inner >= 0.0 && inner < outer && outer <= 90.0) {
                return Err(format!(
                    "{}: the spot's cone angles must satisfy 0 <= innerConeAngle < outerConeAngle <= pi/2, got {inner_cone_angle} and {outer_cone_angle} rad",
                    at()
                ));
            }
            LightKind::Spot {
                direction: direction()?,
                inner_degrees: inner,
                outer_degrees: outer,
            }
        }
    };
    let position = match kind {
        LightKind::Directional { .. } => DVec3::ZERO,
        _ => world.transform_point3(DVec3::ZERO),
    };
    Ok(Light {
        position,
        ambient: DVec3::ZERO,
        diffuse: colour,
        specular: colour,
        kind,
        reference_distance: None,
    })
}
