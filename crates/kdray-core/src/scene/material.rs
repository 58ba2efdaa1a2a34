//! A material: the Phong terms and glass of the Whitted integrator, the
//! physically based part the path tracer reads, and the texture maps.

use glam::DVec3;

use super::alpha::Alpha;

/// A Phong material that may be glass. `T` is how it holds its texture:
/// a scene's material, an index into [`Scene::textures`](super::Scene::textures) (the default); a
/// mesh file's ([`MeshMaterial`](super::mesh::MeshMaterial)), the decoded image.
#[derive(Debug, Clone, PartialEq)]
pub struct Material<T = u32> {
    /// The name in the scene file, or `mesh-file.obj:mtl-name` for MTL
    /// materials (in a mesh file's material, the file's name for it).
    pub name: String,
    pub ambient: DVec3,
    pub diffuse: DVec3,
    pub specular: DVec3,
    /// >= 0; the Blinn-Phong exponent is shininess / 4.
    pub shininess: f64,
    /// 0 = opaque .. 1 = perfect mirror.
    pub reflection: f64,
    /// 0 = opaque .. 1 = clear: the share of the light that is not mirrored
    /// which passes through the surface (refracted, with Fresnel reflection).
    pub transmission: f64,
    /// Index of refraction, > 0, of the object's inside (outside is 1).
    pub ior: f64,
    /// Its base-colour texture, which multiplies `diffuse` and `ambient` on
    /// its textured triangles.
    pub texture: Option<T>,
    /// What the path tracer reads beyond the keys above.
    pub physical: Physical,
    /// The path tracer's other texture maps (glTF's).
    pub maps: MaterialMaps<T>,
    /// Where the surface is there at all (glTF's alphaMode; [`Alpha`]).
    pub alpha: Alpha,
}

/// A glTF material's texture maps beside its base colour, read on textured
/// triangles (the occlusion map by the Whitted integrator, the normal map by
/// both, the others by the path tracer) (docs/scene-format.md, "glTF materials");
/// `T` as [`Material`]'s texture.
#[derive(Debug, Clone, PartialEq)]
pub struct MaterialMaps<T = u32> {
    /// metallicRoughnessTexture: its blue channel scales `metallic`, its
    /// green `roughness` (linear values).
    pub metal_rough: Option<T>,
    /// emissiveTexture: multiplies the emission (sRGB-encoded colours).
    pub emissive: Option<T>,
    /// normalTexture: a tangent-space normal (linear, 2 * texel - 1), its x
    /// and y scaled by `normal_scale`.
    pub normal: Option<T>,
    pub normal_scale: f64,
    /// occlusionTexture: its red channel (linear) darkens the Whitted
    /// integrator's ambient term, by `occlusion_strength` in [0, 1].
    pub occlusion: Option<T>,
    pub occlusion_strength: f64,
    /// The slots ([`UV_SLOT_BASE`] ...) that read a
    /// triangle's second channel of texture coordinates
    /// ([`Scene::triangle_second_uvs`](super::Scene::triangle_second_uvs)); 0: all read the first.
    pub second_uv: u32,
}

/// [`MaterialMaps::second_uv`] (and the kernel's `GpuMaterial::uv_channels`):
/// the texture slots that read a triangle's second channel of texture
/// coordinates; the others read the first.
pub const UV_SLOT_BASE: u32 = 1;
pub const UV_SLOT_METAL_ROUGH: u32 = 2;
pub const UV_SLOT_NORMAL: u32 = 4;
pub const UV_SLOT_EMISSIVE: u32 = 8;
pub const UV_SLOT_OCCLUSION: u32 = 16;

impl<T> MaterialMaps<T> {
    /// No maps.
    pub const NONE: MaterialMaps<T> = MaterialMaps {
        metal_rough: None,
        emissive: None,
        normal: None,
        normal_scale: 1.0,
        occlusion: None,
        occlusion_strength: 1.0,
        second_uv: 0,
    };

    /// Whether any map is given.
    pub fn any(&self) -> bool {
        self.metal_rough.is_some()
            || self.emissive.is_some()
            || self.normal.is_some()
            || self.occlusion.is_some()
    }

    /// The same maps, each texture mapped by `f`.
    pub fn map<U>(&self, mut f: impl FnMut(&T) -> U) -> MaterialMaps<U> {
        MaterialMaps {
            metal_rough: self.metal_rough.as_ref().map(&mut f),
            emissive: self.emissive.as_ref().map(&mut f),
            normal: self.normal.as_ref().map(&mut f),
            normal_scale: self.normal_scale,
            occlusion: self.occlusion.as_ref().map(&mut f),
            occlusion_strength: self.occlusion_strength,
            second_uv: self.second_uv,
        }
    }
}

/// A material's physically based part, read by the path tracer: glTF 2.0's
/// metal/rough BRDF where it has one, and emission.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Physical {
    /// Some: glTF's metal/rough BRDF, whose base colour is the material's
    /// `diffuse`; None: `diffuse` is a Lambertian albedo.
    pub metal_rough: Option<MetalRough>,
    /// Emitted radiance, per channel, >= 0 (zero: not a light). A sphere
    /// emits outward, a triangle on its front side (the side its corners
    /// wind counter-clockwise seen from), or on both with `two_sided`.
    pub emission: DVec3,
    /// A triangle emits from both sides (glTF's `doubleSided`).
    pub two_sided: bool,
    /// The medium inside a transmissive object (glTF's
    /// `KHR_materials_volume`), None: clear.
    pub volume: Option<Volume>,
    /// The perceptual roughness of the transmission, in [0, 1]: 0 is smooth
    /// glass, more a frosted one (GGX microfacets that refract, alpha =
    /// roughness^2).
    pub transmission_roughness: f64,
    /// The transmissive surface has air on both sides (glTF's
    /// thin-walled transmission, without a volume): light passes it
    /// unbent and no medium is entered.
    pub thin_walled: bool,
}

/// An absorbing medium (Beer-Lambert): white light that travels
/// `attenuation_distance` inside it turns `attenuation_color`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Volume {
    /// Components in [0, 1].
    pub attenuation_color: DVec3,
    /// In scene units, > 0 (infinite: no absorption).
    pub attenuation_distance: f64,
}

impl Volume {
    /// The largest absorption coefficient, standing for an infinite one (a
    /// colour component of 0): finite, so that a path of length 0 keeps
    /// its light, and large enough that any other length loses it in f32.
    pub const MAX_ABSORPTION: f64 = 1e30;

    /// The absorption coefficient per scene unit of each channel,
    /// `-ln(colour) / distance`: the light left after a length `t` inside
    /// is `exp(-coefficient t)`.
    pub fn absorption(&self) -> DVec3 {
        let coefficient = |c: f64| {
            if c >= 1.0 || !self.attenuation_distance.is_finite() {
                0.0
            } else if c <= 0.0 {
                Self::MAX_ABSORPTION
            } else {
                (-c.ln() / self.attenuation_distance).min(Self::MAX_ABSORPTION)
            }
        };
        let c = self.attenuation_color;
        DVec3::new(coefficient(c.x), coefficient(c.y), coefficient(c.z))
    }
}

impl Physical {
    /// A Lambertian surface that emits nothing.
    pub const LAMBERTIAN: Physical = Physical {
        metal_rough: None,
        emission: DVec3::ZERO,
        two_sided: false,
        volume: None,
        transmission_roughness: 0.0,
        thin_walled: false,
    };
}

impl Default for Physical {
    fn default() -> Self {
        Self::LAMBERTIAN
    }
}

/// glTF 2.0's metallic-roughness parameters, each in [0, 1].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MetalRough {
    pub metallic: f64,
    /// Perceptual roughness: the GGX width is alpha = roughness^2.
    pub roughness: f64,
}

impl Material {
    /// `ior` where a file gives none: common glass.
    pub const DEFAULT_IOR: f64 = 1.5;
}
