//! A light as the kernel reads it ([`GpuLight`]), and the values of its kind.

use bytemuck::{Pod, Zeroable};

#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct GpuLight {
    pub position: [f32; 3],
    /// [`LIGHT_POINT`], [`LIGHT_SPOT`], [`LIGHT_DIRECTIONAL`], or
    /// [`LIGHT_EMITTER`]: an emissive object, `object`, whose radiance is
    /// `diffuse` (the path tracer samples it).
    pub kind: u32,
    pub ambient: [f32; 3],
    /// An emitter's GPU object id.
    pub object: u32,
    pub diffuse: [f32; 3],
    /// A spot light: the cosine of its outer cone's half-angle.
    pub cos_outer: f32,
    pub specular: [f32; 3],
    /// A spot light: 1 / max(cos inner - cos outer, 0.001), the falloff's
    /// slope (`scene::spot_factor`).
    pub spot_scale: f32,
    /// A spot light's axis, a directional light's travel: unit.
    pub direction: [f32; 3],
    /// A point or spot light: the path tracer's radiant intensity is
    /// `diffuse * path_scale` (`scene::Light::path_intensity_scale`).
    pub path_scale: f32,
    /// The path tracer's choice of a light by power
    /// ([`light_picks`](super::light_picks)): a scene light's probability;
    /// an emitter's, that of the emitters' block (any emitter), given that
    /// the choice passed the scene lights (the light tree picks among them).
    pub pick: f32,
    /// A scene light: the sum of the picks of the scene lights before it.
    pub cdf: f32,
    /// The probability that the choice passes this entry's block: a scene
    /// light's, that it falls on an emitter or the sky; an emitter's, that
    /// it falls on the sky, given that it passed the scene lights.
    pub beyond: f32,
    /// An emitter: its leaf in the light tree
    /// ([`light_tree`](super::light_tree)), or `light_tree::NO_LEAF`.
    pub leaf: u32,
}

/// `GpuLight::kind`: a point light of the scene's `[[lights]]`.
pub const LIGHT_POINT: u32 = 0;
/// `GpuLight::kind`: an object whose material emits. The lights buffer
/// holds the scene's lights first, then the emitters, then the light
/// tree's nodes (`light_tree::GpuLightNode::to_light`).
pub const LIGHT_EMITTER: u32 = 1;
/// `GpuLight::kind`: a spot light of the scene's `[[lights]]`.
pub const LIGHT_SPOT: u32 = 2;
/// `GpuLight::kind`: a directional light of the scene's `[[lights]]`.
pub const LIGHT_DIRECTIONAL: u32 = 3;
