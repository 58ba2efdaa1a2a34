//! A light's kind (`[[lights]]` `kind`): a point light shining every way, a
//! spot light (a point light shining into a cone, with glTF's
//! `KHR_lights_punctual` smooth falloff between its inner and outer cones)
//! or a directional light (parallel light from infinitely far, such as the
//! sun). The falloff is mirrored by `spot_factor` in shaders/shade.wgsl.

use glam::DVec3;

use super::light_shape::LightShape;

/// A light's kind and the keys only that kind has.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum LightKind {
    #[default]
    Point,
    /// Full strength up to `inner_degrees` off the unit axis `direction`
    /// (where it shines), none past `outer_degrees`, smooth between
    /// ([`spot_factor`]); 0 <= inner < outer <= 90.
    Spot {
        direction: DVec3,
        inner_degrees: f64,
        outer_degrees: f64,
    },
    /// Light travelling along the unit vector `direction`; the light's
    /// position means nothing.
    Directional { direction: DVec3 },
}

impl LightKind {
    /// The kind's name in a scene file.
    pub fn shape(&self) -> LightShape {
        match self {
            Self::Point => LightShape::Point,
            Self::Spot { .. } => LightShape::Spot,
            Self::Directional { .. } => LightShape::Directional,
        }
    }

    /// The unit direction a spot or directional light shines along.
    pub fn direction(&self) -> Option<DVec3> {
        match *self {
            Self::Point => None,
            Self::Spot { direction, .. } | Self::Directional { direction } => Some(direction),
        }
    }
}

/// The share of a spot light's intensity sent `cos_angle` (the cosine of
/// the angle off its axis) away, by glTF's `KHR_lights_punctual` falloff:
/// `t = clamp((cos_angle - cos_outer) / max(cos_inner - cos_outer, 0.001), 0, 1)`,
/// squared. 1 inside the inner cone, 0 outside the outer one.
pub fn spot_factor(cos_angle: f64, cos_inner: f64, cos_outer: f64) -> f64 {
    let scale = 1.0 / (cos_inner - cos_outer).max(0.001);
    let t = ((cos_angle - cos_outer) * scale).clamp(0.0, 1.0);
    t * t
}

/// The default cone of a spot light (glTF's defaults: inner 0, outer 45
/// degrees).
pub const DEFAULT_INNER_CONE_DEGREES: f64 = 0.0;
pub const DEFAULT_OUTER_CONE_DEGREES: f64 = 45.0;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_spot_falloff_is_full_inside_the_inner_cone_and_none_outside_the_outer() {
        let (ci, co) = (10f64.to_radians().cos(), 30f64.to_radians().cos());
        assert_eq!(spot_factor(1.0, ci, co), 1.0);
        assert_eq!(spot_factor(ci, ci, co), 1.0);
        assert_eq!(spot_factor(co, ci, co), 0.0);
        assert_eq!(spot_factor(45f64.to_radians().cos(), ci, co), 0.0);
        let middle = spot_factor((ci + co) / 2.0, ci, co);
        assert!((middle - 0.25).abs() < 1e-12, "{middle}");
    }
}
