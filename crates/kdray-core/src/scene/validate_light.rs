//! `[[lights]]` checked entry by entry: each light's kind with the keys only
//! that kind has, its colours and its `reference_distance` (the rules of
//! docs/scene-format.md, `[[lights]]`).

use glam::DVec3;

use super::error::SceneError;
use super::integrator::Integrator;
use super::light::Light;
use super::light_kind::{LightKind, DEFAULT_INNER_CONE_DEGREES, DEFAULT_OUTER_CONE_DEGREES};
use super::light_shape::LightShape;
use super::normals::unit;
use super::render_settings::RenderSettings;
use super::schema::{RawLight, RawScene, Vec3};
use super::validate::{Validator, MAX_COORDINATE};

impl Validator<'_> {
    /// `[[lights]]`: at least one for the Whitted integrator.
    pub(super) fn lights(
        &self,
        raw: &RawScene,
        render: &RenderSettings,
    ) -> Result<Vec<Light>, SceneError> {
        if raw.lights.is_empty() && render.integrator == Integrator::Whitted {
            // Names the line of `lights = []` when there is one.
            return Err(self.error(
                "lights",
                "a scene needs at least one [[lights]] entry (the path tracer, integrator = \"path\", may do without)",
            ));
        }
        raw.lights
            .iter()
            .enumerate()
            .map(|(i, l)| {
                let key = |k: &str| format!("lights[{i}].{k}");
                let (kind, position) = self.light_kind(i, l)?;
                Ok(Light {
                    kind,
                    position: position.unwrap_or_default(),
                    ambient: self.colour(&|| key("ambient"), l.ambient)?,
                    diffuse: self.colour(&|| key("diffuse"), l.diffuse)?,
                    specular: self.colour(&|| key("specular"), l.specular)?,
                    reference_distance: self.reference_distance(i, l)?,
                })
            })
            .collect()
    }

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
        if !(d > 0.0 && d <= MAX_COORDINATE) {
            return Err(self.error(
                &key(),
                format!(
                    "must be greater than 0 and at most {:e}, got {d:?}",
                    MAX_COORDINATE
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
        let direction = |v: Option<Vec3>| -> Result<DVec3, SceneError> {
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
        let position = |p: Option<Vec3>| -> Result<DVec3, SceneError> {
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
