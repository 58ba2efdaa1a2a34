//! The validated scene ([`Scene`]): the camera, settings, lights and
//! materials with the objects and the tables beside the triangles.

use glam::{DVec2, DVec3, DVec4};

use super::animation::{Animation, CameraPath, Frame, FramePath};
use super::camera::Camera;
use super::environment::EnvironmentMap;
use super::instances::{Instance, Shape};
use super::light::Light;
use super::material::Material;
use super::objects::{Sphere, Triangle};
use super::render_settings::RenderSettings;
use super::texture::Texture;

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
    /// [`texture`](super::texture).
    pub triangle_uvs: Vec<[DVec2; 3]>,
    /// glTF's `COLOR_0` at the corners (linear RGBA), beside
    /// `triangle_uvs` and indexed alike ([`Scene::colours_of`]): empty when
    /// no triangle has vertex colours, else one per entry of `triangle_uvs`
    /// (white where a triangle has none). A triangle with colours and no
    /// texture coordinates has zero coordinates there.
    pub triangle_colours: Vec<[DVec4; 3]>,
    /// The second channel of texture coordinates, which the texture slots
    /// in a material's [`MaterialMaps::second_uv`](super::MaterialMaps::second_uv) read, beside
    /// `triangle_uvs` and indexed alike: empty when no material reads one,
    /// else one per entry (zero where a triangle has none).
    pub triangle_second_uvs: Vec<[DVec2; 3]>,
    /// The tangent frame of the normal-mapped triangles at the corners,
    /// beside `triangle_uvs` and indexed alike ([`Scene::tangents_of`]):
    /// xyz the tangent in world space, w = +-1 the sign of the bitangent
    /// `w * (n x t)`; glTF's `TANGENT` where the file gives it, else
    /// MikkTSpace's ([`tangents`](super::tangents)). Empty when no triangle has one; all
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
    /// `[shapes.NAME]`: the meshes that instances place, each once, in its
    /// own space (in name order).
    pub shapes: Vec<Shape>,
    /// `[[instances]]`: shapes placed by a transform. Their triangles are
    /// not in `triangles` (nor counted by [`Scene::object_count`]) until
    /// [`Scene::flatten_instances`] places them there, as every renderer's
    /// preparation does.
    pub instances: Vec<Instance>,
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
    /// [`crate::scene::UV_SLOT_BASE`] ...) of its material read, if it
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

/// The frames of an `[animation]` ([`Animation`]).
impl Scene {
    /// Number of frames: the animation's, or 1 for a still scene.
    pub fn frame_count(&self) -> u32 {
        self.animation.as_ref().map_or(1, |a| a.frames)
    }

    /// The camera and lights of every frame, for asking about many frames.
    pub fn frame_path(&self) -> FramePath {
        FramePath::new(&self.camera, &self.lights, self.animation.as_ref())
    }

    /// The camera and lights at `frame` (0-based): `self.camera` and
    /// `self.lights` for a still scene. Builds the path anew (O(keys)); use
    /// [`Scene::frame_path`] for many frames.
    pub fn frame(&self, frame: u32) -> Frame {
        self.frame_path().frame(frame)
    }

    /// The camera of every frame, for asking about many frames.
    pub fn camera_path(&self) -> CameraPath {
        CameraPath::new(&self.camera, self.animation.as_ref())
    }

    /// The camera at `frame` (0-based): `self.camera` for a still scene, and
    /// at frame 0 of an animation without a key at frame 0. Builds the path
    /// anew (O(keys)); use [`Scene::camera_path`] for many frames.
    pub fn camera_at(&self, frame: u32) -> Camera {
        self.camera_path().camera_at(frame)
    }
}
