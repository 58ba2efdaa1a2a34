//! Scenes: the validated, world-space description that everything downstream
//! consumes. This file holds the types; nothing here knows about the GPU or
//! the k-d tree. A scene file goes `input_file` (bytes) -> `load` (TOML or
//! JSON into the `schema`, its library errors worded by `document_errors`
//! with the lines of `source_map`) -> `validate` (every rule, into a
//! `Scene`) -> `mesh_placement` (each `[[meshes]]` entry read through
//! `mesh_file` by `obj` or `gltf` into a `mesh::Mesh`, then placed in the
//! world). `write` turns a `Scene` back into scene file text, and
//! `animation` gives the camera and lights at each frame of an
//! `[animation]`.
//!
//! Units: positions in scene units, angles in degrees in files and radians
//! nowhere in this module (the camera keeps `vfov_degrees`), colours linear.

mod alpha;
mod animation;
mod camera_basis;
mod document_errors;
pub mod environment;
mod error;
pub mod gltf;
mod input_file;
mod integrator;
mod light_kind;
mod light_shape;
mod load;
pub mod mesh;
pub mod mesh_file;
mod mesh_placement;
mod model_scene;
mod normals;
pub mod obj;
#[cfg(test)]
mod physical_keys_tests;
mod scene_format;
mod schema;
mod source_map;
pub mod tangents;
pub mod texture;
mod validate;
mod validate_animation;
mod validate_light;
mod warning;
mod write;

pub use alpha::{Alpha, AlphaMode};
pub use animation::{Animation, CameraKey, CameraPath, Frame, FramePath, LightKey, MAX_FRAMES};
pub use camera_basis::CameraBasis;
pub use environment::EnvironmentMap;
pub use error::SceneError;
pub use input_file::MAX_INPUT_BYTES;
pub use integrator::{Integrator, ToneMap};
pub use light_kind::{spot_factor, LightKind};
pub use light_shape::LightShape;
pub use load::{load_scene, load_scene_observed, load_scene_with, parse_scene, parse_scene_with};
pub use model_scene::{model_scene, model_scene_viewed, model_scene_with, ModelCamera};
pub use scene_format::SceneFormat;
pub use texture::{MinFilter, MipMode, Texture, TextureFilter, TextureWrap};
pub use validate::{check_samples, MAX_IMAGE_SIDE};
pub use warning::{print_warning, Warning};
pub use write::scene_text;

use glam::{DVec2, DVec3, DVec4};

/// A fully validated scene. All values are finite; materials are referred
/// to by index into `materials`.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    pub camera: Camera,
    pub render: RenderSettings,
    pub lights: Vec<Light>,
    pub materials: Vec<Material>,
    pub spheres: Vec<Sphere>,
    pub triangles: Vec<Triangle>,
    /// The vertex normals of the smooth-shaded triangles, which
    /// [`Triangle::normals`] indexes ([`Scene::normals_of`]).
    pub triangle_normals: Vec<[DVec3; 3]>,
    /// The texture coordinates of the textured triangles (a triangle whose
    /// material has a texture and whose file gives every corner one), which
    /// [`Triangle::uvs`] indexes ([`Scene::uvs_of`]); the convention of
    /// [`texture`].
    pub triangle_uvs: Vec<[DVec2; 3]>,
    /// glTF's `COLOR_0` at the corners (linear RGBA), beside
    /// `triangle_uvs` and indexed alike ([`Scene::colours_of`]): empty when
    /// no triangle has vertex colours, else one per entry of `triangle_uvs`
    /// (white where a triangle has none). A triangle with colours and no
    /// texture coordinates has zero coordinates there.
    pub triangle_colours: Vec<[DVec4; 3]>,
    /// The second channel of texture coordinates, which the texture slots
    /// in a material's [`MaterialMaps::second_uv`] read, beside
    /// `triangle_uvs` and indexed alike: empty when no material reads one,
    /// else one per entry (zero where a triangle has none).
    pub triangle_second_uvs: Vec<[DVec2; 3]>,
    /// The tangent frame of the normal-mapped triangles at the corners,
    /// beside `triangle_uvs` and indexed alike ([`Scene::tangents_of`]):
    /// xyz the tangent in world space, w = +-1 the sign of the bitangent
    /// `w * (n x t)`; glTF's `TANGENT` where the file gives it, else
    /// MikkTSpace's ([`tangents`]). Empty when no triangle has one; all
    /// zero (none) for the other entries.
    pub triangle_tangents: Vec<[DVec4; 3]>,
    /// The base-colour textures that [`Material::texture`] indexes.
    pub textures: Vec<Texture>,
    /// `[environment] image`: the sky as an image (escaping rays see it
    /// instead of `render.background`).
    pub environment: Option<EnvironmentMap>,
    /// The `[animation]`, if any: how the camera and lights change from
    /// frame to frame ([`Scene::frame`]); `camera` and `lights` are its
    /// frame 0 unless a key says otherwise.
    pub animation: Option<Animation>,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    pub position: DVec3,
    pub look_at: DVec3,
    pub up: DVec3,
    /// Vertical field of view in degrees, in (0, 180).
    pub vfov_degrees: f64,
}

/// What happens at a hit from which no light is visible.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ShadowMode {
    /// The hit still gets its ambient term and the path goes on.
    Ambient,
    /// The path ends and adds nothing (the seed's Algorithm 1).
    Seed,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RenderSettings {
    pub width: u32,
    pub height: u32,
    /// The seed's ind_ref: a path stops once its weight falls below this.
    pub min_intensity: f64,
    /// Most hits evaluated along one path, primary hit included (1..=64).
    pub max_depth: u32,
    pub background: DVec3,
    pub shadow_mode: ShadowMode,
    /// Samples per pixel: a perfect square k * k for the Whitted
    /// integrator (a k x k grid), any count >= 1 for the path tracer
    /// (uniformly random positions in the pixel).
    pub samples: u32,
    pub integrator: Integrator,
    /// The path tracer's random numbers: the same seed, the same image.
    pub seed: u32,
    /// How a path-traced PNG maps radiance to 8-bit sRGB, after scaling it
    /// by 2^`exposure`.
    pub tone_map: ToneMap,
    /// Stops, finite.
    pub exposure: f64,
}

impl RenderSettings {
    /// k for samples = k * k.
    pub fn samples_per_axis(&self) -> u32 {
        (self.samples as f64).sqrt().round() as u32
    }
}

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

/// A Phong material that may be glass. `T` is how it holds its texture:
/// a scene's material, an index into [`Scene::textures`] (the default); a
/// mesh file's ([`MeshMaterial`](mesh::MeshMaterial)), the decoded image.
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
/// triangles (the occlusion map by the Whitted integrator, the others by the
/// path tracer) (docs/scene-format.md, "glTF materials");
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
    /// The slots ([`crate::layout::UV_SLOT_BASE`] ...) that read a
    /// triangle's second channel of texture coordinates
    /// ([`Scene::triangle_second_uvs`]); 0: all read the first.
    pub second_uv: u32,
}

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
}

impl Physical {
    /// A Lambertian surface that emits nothing.
    pub const LAMBERTIAN: Physical = Physical {
        metal_rough: None,
        emission: DVec3::ZERO,
        two_sided: false,
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

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sphere {
    pub center: DVec3,
    pub radius: f64,
    pub material: u32,
}

/// A two-sided triangle, from `[[triangles]]` or a mesh (already
/// transformed). 88 bytes: its vertex normals and texture coordinates,
/// where it has them, lie in [`Scene::triangle_normals`] and
/// [`Scene::triangle_uvs`] (with the normals in it, a triangle took 160
/// bytes, and building the 1.1 M-triangle bunny's took 34 ms of its load,
/// 26 ms since; temporary timers, two threads).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Triangle {
    pub vertices: [DVec3; 3],
    pub material: u32,
    /// Index into [`Scene::triangle_normals`] of its unit shading normals at
    /// the three vertices, in world space, for smooth shading;
    /// [`Triangle::FLAT`]: the geometric normal everywhere.
    pub normals: u32,
    /// Index into [`Scene::triangle_uvs`] of its texture coordinates at the
    /// three vertices; [`Triangle::UNTEXTURED`]: none.
    pub uvs: u32,
}

impl Triangle {
    /// [`Triangle::normals`] of a flat-shaded triangle.
    pub const FLAT: u32 = u32::MAX;
    /// [`Triangle::uvs`] of a triangle without texture coordinates.
    pub const UNTEXTURED: u32 = u32::MAX;

    /// A flat-shaded triangle (no vertex normals).
    pub fn flat(vertices: [DVec3; 3], material: u32) -> Self {
        Triangle {
            vertices,
            material,
            normals: Triangle::FLAT,
            uvs: Triangle::UNTEXTURED,
        }
    }
}

impl Scene {
    /// Number of objects, spheres first then triangles: the object ids used by
    /// the k-d tree and the shader are `0..object_count()`.
    pub fn object_count(&self) -> usize {
        self.spheres.len() + self.triangles.len()
    }

    /// The shading normals of `t`, a triangle of this scene, or None for a
    /// flat one.
    pub fn normals_of(&self, t: &Triangle) -> Option<[DVec3; 3]> {
        self.triangle_normals.get(t.normals as usize).copied()
    }

    /// The texture coordinates of `t`, a triangle of this scene, or None for
    /// one without.
    pub fn uvs_of(&self, t: &Triangle) -> Option<[DVec2; 3]> {
        self.triangle_uvs.get(t.uvs as usize).copied()
    }

    /// The vertex colours of `t`, a triangle of this scene, if the scene
    /// has any and `t` has a record of texture coordinates.
    pub fn colours_of(&self, t: &Triangle) -> Option<[DVec4; 3]> {
        self.triangle_colours.get(t.uvs as usize).copied()
    }

    /// The texture coordinates of `t` that the slots `slot` (of
    /// [`crate::layout::UV_SLOT_BASE`] ...) of its material read, if it
    /// has a record.
    pub fn uvs_for(&self, t: &Triangle, slot: u32) -> Option<[DVec2; 3]> {
        let second = self
            .materials
            .get(t.material as usize)
            .is_some_and(|m| m.maps.second_uv & slot != 0);
        match second {
            true => self.triangle_second_uvs.get(t.uvs as usize).copied(),
            false => self.uvs_of(t),
        }
    }

    /// The tangents of `t`, a triangle of this scene, if it has them.
    pub fn tangents_of(&self, t: &Triangle) -> Option<[DVec4; 3]> {
        self.triangle_tangents
            .get(t.uvs as usize)
            .copied()
            .filter(|c| c[0].w != 0.0)
    }

    /// The texture of material `m`, if it has one.
    pub fn texture_of(&self, m: u32) -> Option<&Texture> {
        let t = self.materials.get(m as usize)?.texture?;
        self.textures.get(t as usize)
    }
}

/// What the scene keeps beside its triangles, as the meshes add them:
/// [`Scene::triangle_normals`](Scene::triangle_normals),
/// [`Scene::triangle_uvs`](Scene::triangle_uvs) and
/// [`Scene::textures`](Scene::textures).
#[derive(Default)]
struct TriangleParts {
    normals: Vec<[DVec3; 3]>,
    uvs: Vec<[DVec2; 3]>,
    second_uvs: Vec<[DVec2; 3]>,
    colours: Vec<[DVec4; 3]>,
    tangents: Vec<[DVec4; 3]>,
    textures: Vec<Texture>,
}

/// What one triangle keeps beside its corners in [`Scene::triangle_uvs`]
/// and its neighbours.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct SurfaceRecord {
    pub uvs: Option<[DVec2; 3]>,
    pub second_uvs: Option<[DVec2; 3]>,
    pub colours: Option<[DVec4; 3]>,
    pub tangents: Option<[DVec4; 3]>,
}

impl TriangleParts {
    /// White: the colour of a vertex without `COLOR_0`.
    const WHITE: [DVec4; 3] = [DVec4::ONE; 3];

    /// Gives `triangle` the record `r` (texture coordinates, colours,
    /// tangents) at the end of the tables, if it has texture coordinates or
    /// colours; the colour and tangent tables are filled in (white, none)
    /// for the entries before the first that has them.
    fn add_record(&mut self, triangle: &mut Triangle, r: SurfaceRecord) {
        if r.uvs.is_none() && r.colours.is_none() {
            return;
        }
        let Ok(index) = u32::try_from(self.uvs.len()) else {
            return;
        };
        triangle.uvs = index;
        self.uvs.push(r.uvs.unwrap_or([DVec2::ZERO; 3]));
        let n = self.uvs.len();
        if r.second_uvs.is_some() || !self.second_uvs.is_empty() {
            self.second_uvs.resize(n - 1, [DVec2::ZERO; 3]);
            self.second_uvs
                .push(r.second_uvs.unwrap_or([DVec2::ZERO; 3]));
        }
        if r.colours.is_some() || !self.colours.is_empty() {
            self.colours.resize(n - 1, Self::WHITE);
            self.colours.push(r.colours.unwrap_or(Self::WHITE));
        }
        if r.tangents.is_some() || !self.tangents.is_empty() {
            self.tangents.resize(n - 1, [DVec4::ZERO; 3]);
            self.tangents.push(r.tangents.unwrap_or([DVec4::ZERO; 3]));
        }
    }

    /// The tables filled to one entry per record (after the last triangle).
    fn finish(&mut self) {
        let n = self.uvs.len();
        if !self.second_uvs.is_empty() {
            self.second_uvs.resize(n, [DVec2::ZERO; 3]);
        }
        if !self.colours.is_empty() {
            self.colours.resize(n, Self::WHITE);
        }
        if !self.tangents.is_empty() {
            self.tangents.resize(n, [DVec4::ZERO; 3]);
        }
    }
}
