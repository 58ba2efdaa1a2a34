//! A light's kind (`[[lights]]` `kind`): a point light shining every way, a
//! spot light (a point light shining into a cone, with glTF's
//! `KHR_lights_punctual` smooth falloff between its inner and outer cones)
//! or a directional light (parallel light from infinitely far, such as the
//! sun). The falloff is mirrored by `spot_factor` in shaders/shade.wgsl.

use glam::DVec3;

use super::normals::unit;
use super::schema::RawLight;
use super::validate::Validator;
use super::SceneError;

/// What `kind` names, before its keys are read.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LightShape {
    #[default]
    Point,
    Spot,
    Directional,
}

impl crate::choice::Choice for LightShape {
    const ALL: &'static [Self] = &[Self::Point, Self::Spot, Self::Directional];

    fn name(self) -> &'static str {
        match self {
            Self::Point => "point",
            Self::Spot => "spot",
            Self::Directional => "directional",
        }
    }

    fn help(self) -> &'static str {
        match self {
            Self::Point => "a point light shining every way",
            Self::Spot => "a point light shining into a cone about `direction`",
            Self::Directional => "parallel light travelling along `direction`, from infinitely far",
        }
    }
}

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

impl Validator<'_> {
    /// Light `i`'s `reference_distance`: a positive distance within the
    /// coordinates the GPU takes, for a point or spot light only.
    pub(super) fn reference_distance(
        &self,
        i: usize,
        l: &RawLight,
    ) -> Result<Option<f64>, SceneError> {
        let key = || format!("lights[{i}].reference_distance");
        let Some(d) = l.reference_distance else {
            return Ok(None);
        };
        if l.kind
            .as_ref()
            .is_some_and(|n| n.0 == LightShape::Directional)
        {
            return Err(self.error(
                &key(),
                "a directional light has no reference_distance (its diffuse is the irradiance it gives)",
            ));
        }
        let d = self.number(&key, d)?;
        if !(d > 0.0 && d <= super::validate::MAX_COORDINATE) {
            return Err(self.error(
                &key(),
                format!(
                    "must be greater than 0 and at most {:e}, got {d:?}",
                    super::validate::MAX_COORDINATE
                ),
            ));
        }
        Ok(Some(d))
    }

    /// Light `i`'s kind and its position (None for a directional light,
    /// which must not give one; point and spot lights must).
    pub(super) fn light_kind(
        &self,
        i: usize,
        l: &RawLight,
    ) -> Result<(LightKind, Option<DVec3>), SceneError> {
        let key = |k: &str| format!("lights[{i}].{k}");
        let shape = l.kind.as_ref().map_or(LightShape::Point, |n| n.0);
        let name = crate::choice::Choice::name(shape);
        // A key the kind does not read is an error, not silently ignored.
        let refuse = |k: &str, given: bool| -> Result<(), SceneError> {
            if given {
                return Err(self.error(&key(k), format!("a {name} light has no {k}")));
            }
            Ok(())
        };
        let direction = |v: Option<super::schema::Vec3>| -> Result<DVec3, SceneError> {
            let Some(v) = v else {
                return Err(self.error(
                    &format!("lights[{i}]"),
                    format!("missing field `direction`: a {name} light needs one"),
                ));
            };
            let d = self.vector(&|| key("direction"), v)?;
            unit(d).ok_or_else(|| {
                self.error(
                    &key("direction"),
                    format!("must not be zero, got {:?}", v.0),
                )
            })
        };
        let position = |p: Option<super::schema::Vec3>| -> Result<DVec3, SceneError> {
            let Some(p) = p else {
                return Err(self.error(
                    &format!("lights[{i}]"),
                    format!("missing field `position`: a {name} light needs one"),
                ));
            };
            self.position(&|| key("position"), p)
        };
        match shape {
            LightShape::Point => {
                refuse("direction", l.direction.is_some())?;
                refuse("inner_cone", l.inner_cone.is_some())?;
                refuse("outer_cone", l.outer_cone.is_some())?;
                Ok((LightKind::Point, Some(position(l.position)?)))
            }
            LightShape::Directional => {
                refuse("position", l.position.is_some())?;
                refuse("inner_cone", l.inner_cone.is_some())?;
                refuse("outer_cone", l.outer_cone.is_some())?;
                let direction = direction(l.direction)?;
                Ok((LightKind::Directional { direction }, None))
            }
            LightShape::Spot => {
                let p = position(l.position)?;
                let direction = direction(l.direction)?;
                let cone = |k: &str, x: Option<f64>, default: f64| -> Result<f64, SceneError> {
                    let degrees = self.number(&|| key(k), x.unwrap_or(default))?;
                    if !(0.0..=90.0).contains(&degrees) {
                        return Err(self.error(
                            &key(k),
                            format!("must be between 0 and 90 degrees, got {degrees:?}"),
                        ));
                    }
                    Ok(degrees)
                };
                let inner = cone("inner_cone", l.inner_cone, DEFAULT_INNER_CONE_DEGREES)?;
                let outer = cone("outer_cone", l.outer_cone, DEFAULT_OUTER_CONE_DEGREES)?;
                if inner >= outer {
                    let at = if l.inner_cone.is_some() {
                        "inner_cone"
                    } else {
                        "outer_cone"
                    };
                    return Err(self.error(
                        &key(at),
                        format!(
                            "inner_cone must be less than outer_cone, got {inner:?} and {outer:?}"
                        ),
                    ));
                }
                Ok((
                    LightKind::Spot {
                        direction,
                        inner_degrees: inner,
                        outer_degrees: outer,
                    },
                    Some(p),
                ))
            }
        }
    }
}

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

    #[test]
    fn light_shapes_round_trip_by_name() {
        crate::choice::assert_names_round_trip::<LightShape>();
    }
}
