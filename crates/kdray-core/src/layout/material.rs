//! A material as the kernel reads it ([`GpuMaterial`]), and the values of its
//! alpha mode, model and texture-coordinate slots.

use bytemuck::{Pod, Zeroable};

#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct GpuMaterial {
    pub ambient: [f32; 3],
    pub shininess: f32,
    pub diffuse: [f32; 3],
    pub reflection: f32,
    pub specular: [f32; 3],
    /// 0 opaque .. 1 clear; read only by the glass variant of the kernel.
    pub transmission: f32,
    /// Index of refraction of the inside (the outside is 1).
    pub ior: f32,
    /// Its base-colour texture in the `textures` buffer, or
    /// [`GpuMaterial::NO_TEXTURE`].
    pub texture: u32,
    /// glTF's metallic and perceptual roughness, read by the path tracer
    /// where `model` is [`MODEL_METAL_ROUGH`].
    pub metallic: f32,
    pub roughness: f32,
    /// Emitted radiance (the path tracer's lights).
    pub emission: [f32; 3],
    /// [`MODEL_LAMBERTIAN`] or [`MODEL_METAL_ROUGH`]: how the path tracer
    /// reads `diffuse`.
    pub model: u32,
    /// The path tracer's maps in the `textures` buffer, each or
    /// [`GpuMaterial::NO_TEXTURE`]: metallic-roughness (blue, green),
    /// emissive, and the tangent-space normal map with its x-y scale.
    pub metal_rough_texture: u32,
    pub emissive_texture: u32,
    pub normal_texture: u32,
    pub normal_scale: f32,
    /// [`ALPHA_OPAQUE`], [`ALPHA_MASK`] or [`ALPHA_BLEND`]: whether the
    /// walks' alpha test (shaders/alpha.wgsl) reads this material.
    pub alpha_mode: u32,
    /// Alpha below this is a hole (MASK; BLEND outside the path tracer).
    pub alpha_cutoff: f32,
    /// The constant alpha, times the base-colour texture's where textured.
    pub alpha_factor: f32,
    /// The Whitted integrator's occlusion map (red darkens the ambient
    /// term), or [`GpuMaterial::NO_TEXTURE`], and its strength in [0, 1].
    pub occlusion_texture: u32,
    pub occlusion_strength: f32,
    /// The slots ([`UV_SLOT_BASE`] ...) that read the second channel of
    /// texture coordinates.
    pub uv_channels: u32,
    /// 1: an emitting triangle emits from both sides; 0: its front only.
    pub two_sided: u32,
    /// The path tracer: the dielectric's perceptual roughness (GGX alpha =
    /// roughness^2); 0: smooth glass.
    pub transmission_roughness: f32,
    /// The path tracer: the absorption coefficient per scene unit of the
    /// medium inside a transmissive object (0: clear).
    pub absorption: [f32; 3],
    /// The path tracer: 1: the dielectric is thin-walled (air on both
    /// sides: transmitted light leaves unbent); 0: it bounds a volume.
    pub thin_walled: u32,
}

impl GpuMaterial {
    /// `texture` of a material without one.
    pub const NO_TEXTURE: u32 = u32::MAX;
}

/// `GpuMaterial::alpha_mode`: alpha ignored, the surface everywhere.
pub const ALPHA_OPAQUE: u32 = 0;
/// `GpuMaterial::alpha_mode`: alpha below `alpha_cutoff` is a hole.
pub const ALPHA_MASK: u32 = 1;
/// `GpuMaterial::alpha_mode`: a ray passes with probability 1 - alpha in
/// the path tracer; elsewhere as [`ALPHA_MASK`].
pub const ALPHA_BLEND: u32 = 2;

/// `GpuMaterial::model`: `diffuse` is a Lambertian albedo.
pub const MODEL_LAMBERTIAN: u32 = 0;
/// `GpuMaterial::model`: glTF 2.0's metal/rough BRDF with base colour `diffuse`.
pub const MODEL_METAL_ROUGH: u32 = 1;

/// `GpuMaterial::uv_channels`'s slots, defined beside
/// [`crate::scene::MaterialMaps::second_uv`].
pub use crate::scene::{
    UV_SLOT_BASE, UV_SLOT_EMISSIVE, UV_SLOT_METAL_ROUGH, UV_SLOT_NORMAL, UV_SLOT_OCCLUSION,
};
