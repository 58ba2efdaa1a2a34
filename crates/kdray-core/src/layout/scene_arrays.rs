//! The scene flattened into the GPU's layout on the host ([`SceneArrays`]):
//! the objects in the order the tree's leaves name them, materials,
//! lights, the tree's nodes and ropes, vertex normals and textures, each
//! array as the kernel reads it. The `kdray` crate uploads them.

use super::light::{GpuLight, LIGHT_DIRECTIONAL, LIGHT_POINT, LIGHT_SPOT};
use super::light_picks::LightPicks;
use super::material::{
    GpuMaterial, ALPHA_BLEND, ALPHA_MASK, ALPHA_OPAQUE, MODEL_LAMBERTIAN, MODEL_METAL_ROUGH,
};
use super::objects::{GpuSphere, GpuTriangle, GpuTriangleNormals};
use super::texture_words::{Records, TextureWords};
use super::tree_nodes::GpuKdNode;
use crate::geometry::{Aabb, Primitives};
use crate::kdtree::LeafRopes;
use crate::kdtree::{KdTree, Ropes};
use crate::scene::{AlphaMode, Light, LightKind, Scene};

/// Host copies of every storage buffer, in the GPU layout.
pub struct SceneArrays {
    pub spheres: Vec<GpuSphere>,
    pub triangles: Vec<GpuTriangle>,
    /// Per GPU object: its material index and its scene id (the kernel's
    /// `objects` binding).
    pub objects: Vec<[u32; 2]>,
    pub materials: Vec<GpuMaterial>,
    /// The scene's point lights, then one entry per emissive object
    /// (`LIGHT_EMITTER`, in order of GPU id), `emitter_count` of them, each
    /// with its chance of being picked ([`LightPicks`]), then the
    /// `light_tree_nodes` nodes of the emitters' light tree
    /// (`light_tree::GpuLightNode::to_light`).
    pub lights: Vec<GpuLight>,
    pub emitter_count: u32,
    pub light_tree_nodes: u32,
    /// What a frame's scene lights need for their picks
    /// ([`LightPicks::scene_lights`]).
    pub light_picks: LightPicks,
    /// Where `[environment] image` lies in `textures`, if the scene has one.
    pub environment: EnvironmentWords,
    pub nodes: Vec<GpuKdNode>,
    pub leaf_objects: Vec<u32>,
    /// The rope walk's data: per leaf its box and ropes, per node its leaf
    /// record (`kdtree::Ropes`; node indices are the tree's).
    pub leaf_ropes: Vec<LeafRopes>,
    pub leaf_rope_index: Vec<u32>,
    /// Vertex normals of the smooth-shaded triangles only, in the order of
    /// `triangles` (`GpuTriangle::normals` indexes it): 12 bytes per smooth
    /// triangle, none per flat one.
    pub triangle_normals: Vec<GpuTriangleNormals>,
    /// The textures and the textured triangles' texture coordinates
    /// ([`TextureWords`]), in the order of `triangles`; empty without
    /// textures.
    pub textures: Vec<u32>,
    /// The box the walk clips rays to: the tree's root cell.
    pub bounds: Aabb,
    /// `scene_ids[gpu_id]` is the scene's object id (spheres first, then
    /// triangles) of the object the GPU stores at `gpu_id`.
    pub scene_ids: Vec<u32>,
}

fn f32x3(v: glam::DVec3) -> [f32; 3] {
    v.as_vec3().to_array()
}

impl SceneArrays {
    /// `lights` (a frame's, one per light of this scene) in the GPU layout
    /// with their picks: the head of the `lights` buffer, which an
    /// animation's frame rewrites.
    pub fn frame_lights(&self, lights: &[Light]) -> Vec<GpuLight> {
        self.light_picks.scene_lights(Self::lights_of(lights))
    }

    /// `lights` in the GPU layout, without their picks.
    fn lights_of(lights: &[Light]) -> Vec<GpuLight> {
        lights
            .iter()
            .map(|l| {
                let mut g = GpuLight {
                    position: f32x3(l.position),
                    ambient: f32x3(l.ambient),
                    diffuse: f32x3(l.diffuse),
                    specular: f32x3(l.specular),
                    path_scale: l.path_intensity_scale() as f32,
                    ..bytemuck::Zeroable::zeroed()
                };
                match l.kind {
                    LightKind::Point => g.kind = LIGHT_POINT,
                    LightKind::Spot {
                        direction,
                        inner_degrees,
                        outer_degrees,
                    } => {
                        let cos_inner = inner_degrees.to_radians().cos();
                        let cos_outer = outer_degrees.to_radians().cos();
                        g.kind = LIGHT_SPOT;
                        g.direction = f32x3(direction);
                        g.cos_outer = cos_outer as f32;
                        g.spot_scale = (1.0 / (cos_inner - cos_outer).max(0.001)) as f32;
                    }
                    LightKind::Directional { direction } => {
                        g.kind = LIGHT_DIRECTIONAL;
                        g.direction = f32x3(direction);
                    }
                }
                g
            })
            .collect()
    }

    /// Total bytes of the storage arrays: what the scene needs on the GPU.
    pub fn byte_size(&self) -> u64 {
        use std::mem::size_of_val;
        [
            size_of_val(self.spheres.as_slice()),
            size_of_val(self.triangles.as_slice()),
            size_of_val(self.objects.as_slice()),
            size_of_val(self.materials.as_slice()),
            size_of_val(self.lights.as_slice()),
            size_of_val(self.nodes.as_slice()),
            size_of_val(self.leaf_objects.as_slice()),
            size_of_val(self.leaf_ropes.as_slice()),
            size_of_val(self.leaf_rope_index.as_slice()),
            size_of_val(self.triangle_normals.as_slice()),
            size_of_val(self.textures.as_slice()),
        ]
        .iter()
        .map(|&b| b as u64)
        .sum()
    }

    /// The point lights at the head of `lights`.
    pub fn point_light_count(&self) -> u32 {
        self.lights.len() as u32 - self.emitter_count - self.light_tree_nodes
    }

    /// Whether some material transmits (the kernel's `GLASS`).
    pub fn glass(&self) -> bool {
        self.materials.iter().any(|m| m.transmission > 0.0)
    }

    /// Whether some material has an alpha mode (the kernel's `ALPHA_TEST`).
    pub fn alpha_test(&self) -> bool {
        self.materials.iter().any(|m| m.alpha_mode != ALPHA_OPAQUE)
    }

    /// Whether a scene light is a spot or directional light (the kernel's
    /// `SPOT_OR_DIRECTIONAL_LIGHTS`); an animation moves lights but keeps
    /// their kinds.
    pub fn spot_or_directional_lights(&self) -> bool {
        self.lights[..self.point_light_count() as usize]
            .iter()
            .any(|l| l.kind != LIGHT_POINT)
    }
}

/// The order of the objects on the GPU: `order[gpu_id]` is the scene's id.
/// Spheres come first, then triangles (the kernel tells them apart by
/// `id < sphere_count`), each in the order the tree's leaves first name
/// them, so that the objects of a leaf lie side by side in memory; objects
/// no leaf names (a brute-force render's tree names none) keep their order
/// after those.
fn leaf_order(tree: &KdTree, sphere_count: usize, object_count: usize) -> Vec<u32> {
    let mut placed = vec![false; object_count];
    let mut order = Vec::with_capacity(object_count);
    let candidates = tree
        .leaf_objects
        .iter()
        .copied()
        .chain(0..object_count as u32);
    for spheres in [true, false] {
        for id in candidates.clone() {
            let i = id as usize;
            if (i < sphere_count) == spheres && !std::mem::replace(&mut placed[i], true) {
                order.push(id);
            }
        }
    }
    order
}

impl SceneArrays {
    pub fn new(scene: &Scene, prims: &Primitives, tree: &KdTree) -> Self {
        // The ropes (a pass down the tree) beside the rest (passes over the
        // objects and leaves), each on a core of its own: for the
        // 1.1M-triangle bunny they take about 200 and 150 ms on one.
        let (ropes, arrays) = rayon::join(
            || Ropes::build(tree),
            || Self::all_but_ropes(scene, prims, tree),
        );
        SceneArrays {
            leaf_ropes: ropes.leaves,
            leaf_rope_index: ropes.leaf_of_node,
            ..arrays
        }
    }

    /// Every array but the ropes' two, which are left empty.
    fn all_but_ropes(scene: &Scene, prims: &Primitives, tree: &KdTree) -> Self {
        let sphere_count = prims.spheres.len();
        let order = leaf_order(tree, sphere_count, prims.len());
        let mut gpu_id = vec![0u32; order.len()];
        for (new, &old) in order.iter().enumerate() {
            gpu_id[old as usize] = new as u32;
        }
        let material = |id: u32| match scene.spheres.get(id as usize) {
            Some(s) => s.material,
            None => scene.triangles[id as usize - sphere_count].material,
        };
        let mut triangle_normals = Vec::new();
        let mut normals_of =
            |id: u32| match scene.normals_of(&scene.triangles[id as usize - sphere_count]) {
                Some(n) => {
                    triangle_normals.push(GpuTriangleNormals::pack(n));
                    triangle_normals.len() as u32 - 1
                }
                None => GpuTriangle::FLAT,
            };
        let (record_index, records) = surface_records(scene, &order[sphere_count..], sphere_count);
        let triangles = order[sphere_count..]
            .iter()
            .zip(record_index)
            .map(|(&id, uvs)| {
                let t = &prims.triangles[id as usize - sphere_count];
                GpuTriangle {
                    v0: t.v[0].to_array(),
                    normals: normals_of(id),
                    v1: t.v[1].to_array(),
                    scene_id: id,
                    v2: t.v[2].to_array(),
                    uvs,
                }
            })
            .collect();
        let textures = match records.uvs.is_empty() {
            true => Vec::new(),
            false => TextureWords::pack(&scene.textures, &records),
        };
        // A material's texture in the buffer, or none where no triangle is
        // textured (the buffer is then empty).
        let texture_index = |t: Option<u32>| match (t, textures.is_empty()) {
            (Some(t), false) => t,
            _ => GpuMaterial::NO_TEXTURE,
        };
        let mut arrays = SceneArrays {
            spheres: order[..sphere_count]
                .iter()
                .map(|&id| {
                    let s = &prims.spheres[id as usize];
                    GpuSphere {
                        center: s.center.to_array(),
                        radius: s.radius,
                    }
                })
                .collect(),
            triangles,
            objects: order.iter().map(|&id| [material(id), id]).collect(),
            materials: scene
                .materials
                .iter()
                .map(|m| gpu_material(m, &texture_index))
                .collect(),
            lights: Vec::new(),
            emitter_count: 0,
            light_tree_nodes: 0,
            light_picks: LightPicks::default(),
            environment: EnvironmentWords::default(),
            nodes: tree.nodes.iter().map(GpuKdNode::pack).collect(),
            leaf_objects: tree
                .leaf_objects
                .iter()
                .map(|&id| gpu_id[id as usize])
                .collect(),
            leaf_ropes: Vec::new(),
            leaf_rope_index: Vec::new(),
            triangle_normals,
            textures,
            bounds: tree.bounds,
            scene_ids: order,
        };
        if let Some(env) = &scene.environment {
            arrays.environment = EnvironmentWords::append(env, &mut arrays.textures);
        }
        let emissive_means: Vec<Option<[f64; 3]>> = arrays
            .materials
            .iter()
            .map(|m| {
                (m.emissive_texture != GpuMaterial::NO_TEXTURE)
                    .then(|| scene.textures[m.emissive_texture as usize].mean_linear_colour())
            })
            .collect();
        let (emitters, tree, picks) = LightPicks::with_emitters(
            &arrays.objects,
            &arrays.materials,
            &emissive_means,
            &arrays.spheres,
            &arrays.triangles,
            scene.environment.as_ref(),
            &arrays.bounds,
        );
        arrays.light_picks = picks;
        arrays.lights = arrays.frame_lights(&scene.lights);
        arrays.emitter_count = emitters.len() as u32;
        arrays.light_tree_nodes = tree.nodes.len() as u32;
        arrays.lights.extend(emitters);
        arrays
            .lights
            .extend(tree.nodes.iter().map(|n| n.to_light()));
        arrays
    }
}

/// The records (texture coordinates, vertex colours, tangents, second
/// channel) of the triangles `ids` (scene ids, in GPU order), and each
/// one's record index or [`GpuTriangle::UNTEXTURED`]: a record only where
/// the triangle's material has a texture or a map, or the scene has vertex
/// colours (the kernel reads them only there).
fn surface_records(scene: &Scene, ids: &[u32], sphere_count: usize) -> (Vec<u32>, Records) {
    let has_colours = !scene.triangle_colours.is_empty();
    let mut records = Records::default();
    let mut record_of = |id: u32| {
        let t = &scene.triangles[id as usize - sphere_count];
        let textured = scene
            .materials
            .get(t.material as usize)
            .is_some_and(|m| m.texture.is_some() || m.maps.any());
        let Some(uvs) = scene.uvs_of(t).filter(|_| textured || has_colours) else {
            return GpuTriangle::UNTEXTURED;
        };
        records.uvs.push(uvs.map(|uv| uv.as_vec2()));
        if has_colours {
            let c = scene.colours_of(t).unwrap_or([glam::DVec4::ONE; 3]);
            records.colours.push(c.map(|c| c.as_vec4()));
        }
        if !scene.triangle_tangents.is_empty() {
            let c = scene.tangents_of(t).unwrap_or([glam::DVec4::ZERO; 3]);
            records.tangents.push(c.map(|c| c.as_vec4()));
        }
        if !scene.triangle_second_uvs.is_empty() {
            let c = scene.triangle_second_uvs.get(t.uvs as usize);
            let c = c.copied().unwrap_or_default();
            records.second_uvs.push(c.map(|uv| uv.as_vec2()));
        }
        records.uvs.len() as u32 - 1
    };
    let index = ids.iter().map(|&id| record_of(id)).collect();
    (index, records)
}

/// Material `m` as the kernel reads it; `texture_index` gives a texture's
/// place in the `textures` buffer (or none).
fn gpu_material(
    m: &crate::scene::Material,
    texture_index: &dyn Fn(Option<u32>) -> u32,
) -> GpuMaterial {
    GpuMaterial {
        ambient: f32x3(m.ambient),
        shininess: m.shininess as f32,
        diffuse: f32x3(m.diffuse),
        reflection: m.reflection as f32,
        specular: f32x3(m.specular),
        transmission: m.transmission as f32,
        ior: m.ior as f32,
        texture: texture_index(m.texture),
        metallic: m.physical.metal_rough.map_or(0.0, |p| p.metallic as f32),
        roughness: m.physical.metal_rough.map_or(1.0, |p| p.roughness as f32),
        emission: f32x3(m.physical.emission),
        model: match m.physical.metal_rough {
            Some(_) => MODEL_METAL_ROUGH,
            None => MODEL_LAMBERTIAN,
        },
        metal_rough_texture: texture_index(m.maps.metal_rough),
        emissive_texture: texture_index(m.maps.emissive),
        normal_texture: texture_index(m.maps.normal),
        normal_scale: m.maps.normal_scale as f32,
        alpha_mode: match m.alpha.mode {
            AlphaMode::Opaque => ALPHA_OPAQUE,
            AlphaMode::Mask => ALPHA_MASK,
            AlphaMode::Blend => ALPHA_BLEND,
        },
        alpha_cutoff: m.alpha.fixed_cutoff() as f32,
        alpha_factor: m.alpha.factor as f32,
        occlusion_texture: texture_index(m.maps.occlusion),
        occlusion_strength: m.maps.occlusion_strength as f32,
        uv_channels: m.maps.second_uv,
        two_sided: u32::from(m.physical.two_sided),
        transmission_roughness: m.physical.transmission_roughness as f32,
        absorption: f32x3(
            m.physical
                .volume
                .map_or(glam::DVec3::ZERO, |v| v.absorption()),
        ),
        thin_walled: u32::from(m.physical.thin_walled),
    }
}

/// Where the sky image lies in the `textures` buffer (all zero: no image):
/// the words from `offset` hold its texels (three f32 a texel, row-major,
/// top row first), the rows' cumulative distribution (`height + 1` f32),
/// then each row's (`width + 1` f32 a row), as
/// [`EnvironmentMap::sampling_tables`](crate::scene::EnvironmentMap::sampling_tables)
/// makes them; shaders/environment.wgsl reads them.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct EnvironmentWords {
    pub offset: u32,
    pub width: u32,
    pub height: u32,
    pub intensity: f32,
    pub rotation_cos: f32,
    pub rotation_sin: f32,
}

impl EnvironmentWords {
    /// Appends `env`'s words to `words` and says where they lie.
    fn append(env: &crate::scene::EnvironmentMap, words: &mut Vec<u32>) -> Self {
        let offset = words.len() as u32;
        let (rows, columns) = env.sampling_tables();
        words.reserve(env.texels.len() * 3 + rows.len() + columns.len());
        words.extend(env.texels.iter().flatten().map(|c| c.to_bits()));
        words.extend(rows.iter().chain(&columns).map(|c| c.to_bits()));
        let (sin, cos) = env.rotation_degrees.to_radians().sin_cos();
        EnvironmentWords {
            offset,
            width: env.width,
            height: env.height,
            intensity: env.intensity as f32,
            rotation_cos: cos as f32,
            rotation_sin: sin as f32,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random_scene::{random_scene, RandomSceneSpec, SceneKind};

    /// Smooth triangles carry their own vertex normals to the GPU, whatever
    /// order the leaves put them in, and flat ones none: the normals array
    /// holds one record per smooth triangle.
    #[test]
    fn vertex_normals_follow_their_triangle_into_leaf_order() {
        let mut scene = random_scene(&RandomSceneSpec {
            kind: SceneKind::Triangles,
            count: 300,
            seed: 5,
            width: 8,
            height: 8,
        });
        // Every third triangle smooth, with normals that name it: distinct
        // unit vectors derived from its first vertex.
        for (i, t) in scene.triangles.iter_mut().enumerate() {
            if i % 3 == 0 {
                let v = t.vertices[0];
                t.normals = scene.triangle_normals.len() as u32;
                scene.triangle_normals.push([
                    glam::DVec3::new(v.x, 1.0, 0.5).normalize(),
                    glam::DVec3::new(-1.0, v.y, 0.25).normalize(),
                    glam::DVec3::new(0.5, -0.5, v.z).normalize(),
                ]);
            }
        }
        let prims = Primitives::from_scene(&scene);
        let tree = KdTree::for_primitives(&prims);
        let a = SceneArrays::new(&scene, &prims, &tree);
        assert_eq!(a.triangle_normals.len(), 100);
        let spheres = prims.spheres.len();
        let mut records = Vec::new();
        for (gpu, t) in a.triangles.iter().enumerate() {
            let original = &scene.triangles[a.scene_ids[spheres + gpu] as usize - spheres];
            assert_eq!(original.vertices[0].as_vec3().to_array(), t.v0);
            match scene.normals_of(original) {
                None => assert_eq!(t.normals, GpuTriangle::FLAT),
                Some(expected) => {
                    records.push(t.normals);
                    let got = a.triangle_normals[t.normals as usize].unpack();
                    for (e, g) in expected.iter().zip(got) {
                        assert!(e.angle_between(g.as_dvec3()) < 1e-4, "{e} vs {g}");
                    }
                }
            }
        }
        records.sort_unstable();
        assert_eq!(records, (0..100).collect::<Vec<u32>>(), "one record each");
    }

    /// The GPU arrays hold the scene's objects in leaf order: every object
    /// once, spheres before triangles, each with its own geometry and
    /// material, and the leaves name the same objects as the tree's.
    #[test]
    fn objects_are_stored_in_leaf_order_and_stay_themselves() {
        let scene = random_scene(&RandomSceneSpec {
            kind: SceneKind::Mixed,
            count: 500,
            seed: 3,
            width: 8,
            height: 8,
        });
        let prims = Primitives::from_scene(&scene);
        let tree = KdTree::for_primitives(&prims);
        let a = SceneArrays::new(&scene, &prims, &tree);
        let spheres = prims.spheres.len();
        assert!(spheres > 0 && !prims.triangles.is_empty());
        assert_eq!(a.spheres.len(), spheres);
        assert_eq!(a.triangles.len(), prims.triangles.len());
        // Which scene object each GPU id holds, found by its geometry
        // (random objects are all different).
        let original = |gpu: u32| -> usize {
            let g = gpu as usize;
            if g < spheres {
                let s = a.spheres[g];
                prims
                    .spheres
                    .iter()
                    .position(|p| p.center.to_array() == s.center && p.radius == s.radius)
                    .unwrap()
            } else {
                let t = a.triangles[g - spheres];
                spheres
                    + prims
                        .triangles
                        .iter()
                        .position(|p| p.v[0].to_array() == t.v0 && p.v[2].to_array() == t.v2)
                        .unwrap()
            }
        };
        let material = |id: usize| match scene.spheres.get(id) {
            Some(s) => s.material,
            None => scene.triangles[id - spheres].material,
        };
        let mut seen = vec![false; prims.len()];
        for gpu in 0..prims.len() as u32 {
            let id = original(gpu);
            assert!(!std::mem::replace(&mut seen[id], true), "object {id} twice");
            assert_eq!(a.objects[gpu as usize], [material(id), id as u32]);
        }
        for (&gpu, &id) in a.leaf_objects.iter().zip(&tree.leaf_objects) {
            assert_eq!(original(gpu), id as usize);
        }
        // Leaf order: the first leaf's objects get the first ids of their kind.
        let first_leaf = tree
            .nodes
            .iter()
            .find(|n| n.is_leaf() && n.count > 0)
            .unwrap();
        let first = a.leaf_objects[first_leaf.index as usize];
        assert!(
            first == 0 || first as usize == spheres,
            "first leaf object has GPU id {first}"
        );
    }
}
