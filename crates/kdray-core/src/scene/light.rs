//! A light of the scene (`[[lights]]`): its position, colours and kind.

use glam::DVec3;

use super::light_kind::LightKind;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Light {
    /// Where a point or spot light is (a directional light's: zero, unused).
    pub position: DVec3,
    pub ambient: DVec3,
    pub diffuse: DVec3,
    pub specular: DVec3,
    pub kind: LightKind,
    /// A point or spot light's `reference_distance`: where the path tracer
    /// lights a white Lambertian surface facing it as brightly as the
    /// Whitted integrator (which has no falloff) does, its radiant
    /// intensity being `pi * diffuse * d^2` ([`Light::path_intensity_scale`]).
    /// None: `diffuse` is its radiant intensity.
    pub reference_distance: Option<f64>,
}

impl Light {
    /// What the path tracer multiplies a point or spot light's `diffuse`
    /// by to get its radiant intensity (W/sr): `pi * d^2` with a
    /// `reference_distance` d, else 1.
    pub fn path_intensity_scale(&self) -> f64 {
        self.reference_distance
            .map_or(1.0, |d| std::f64::consts::PI * d * d)
    }
}
