//! Instancing in the validated scene: [`Shape`]s, meshes declared once and
//! kept in their own space, and [`Instance`]s, each a shape's placement
//! (an affine transform and an optional material override). Flattening
//! ([`Scene::flatten_instances`]) turns every instance into world-space
//! triangles exactly as a `[[meshes]]` entry with the same transform is
//! placed (the same code, `mesh_placement::add_placed`): what the renderers
//! consume today.

use std::sync::Arc;

use glam::{DAffine3, DVec3};
use rayon::prelude::*;

use super::mesh::Mesh;
use super::mesh_placement::{add_placed, Placement};
use super::triangle_parts::TriangleParts;
use super::validated_scene::Scene;

/// The most objects a scene may hold once its instances are flattened:
/// the k-d tree's build takes at most 2^30.
pub const MAX_FLATTENED_OBJECTS: usize = 1 << 30;

/// A mesh declared once (`[shapes.NAME]`), in its own space.
#[derive(Debug, Clone, PartialEq)]
pub struct Shape {
    pub name: String,
    /// Its vertices, normals and triangles in its own space; a triangle's
    /// material indexes the file's materials, which lie in
    /// [`Scene::materials`] from `first_material` on.
    pub mesh: Arc<Mesh>,
    /// As `[[meshes]]`' `smooth`.
    pub smooth: Option<bool>,
    /// The material of all its triangles (the shape's `material`), unless
    /// an instance overrides it; None: the file's own.
    pub material: Option<u32>,
    pub first_material: u32,
    /// The box of its triangles' corners, in its own space (min, max).
    pub bounds: [DVec3; 2],
}

/// A shape placed in the world (`[[instances]]`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Instance {
    /// Index into [`Scene::shapes`].
    pub shape: u32,
    /// From the shape's space to the world's; invertible.
    pub transform: DAffine3,
    /// Every triangle's material, over the shape's.
    pub material: Option<u32>,
}

/// The box of `bounds` (min, max) carried by `transform`: the box of its
/// eight transformed corners, which holds everything inside it.
pub fn transformed_box(transform: &DAffine3, bounds: &[DVec3; 2]) -> [DVec3; 2] {
    let [lo, hi] = *bounds;
    let mut out = [DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)];
    for k in 0..8 {
        let corner = DVec3::new(
            if k & 1 == 0 { lo.x } else { hi.x },
            if k & 2 == 0 { lo.y } else { hi.y },
            if k & 4 == 0 { lo.z } else { hi.z },
        );
        let p = transform.transform_point3(corner);
        out = [out[0].min(p), out[1].max(p)];
    }
    out
}

/// The box (min, max) of the corners of `mesh`'s triangles; the empty box
/// (min above max) where it has none.
pub(super) fn mesh_bounds(mesh: &Mesh) -> [DVec3; 2] {
    let mut out = [DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)];
    for t in &mesh.triangles {
        for v in mesh.vertices(t).into_iter().flatten() {
            out = [out[0].min(v), out[1].max(v)];
        }
    }
    out
}

impl Scene {
    /// The number of triangles the instances place (each instance counts
    /// its shape's triangles): what flattening adds, at most.
    pub fn instanced_triangle_count(&self) -> usize {
        self.instances
            .iter()
            .map(|i| {
                self.shapes
                    .get(i.shape as usize)
                    .map_or(0, |s| s.mesh.triangles.len())
            })
            .sum()
    }

    /// The world box of instance `i`'s shape (min, max), if `i` and its
    /// shape exist.
    pub fn instance_bounds(&self, i: usize) -> Option<[DVec3; 2]> {
        let instance = self.instances.get(i)?;
        let shape = self.shapes.get(instance.shape as usize)?;
        Some(transformed_box(&instance.transform, &shape.bounds))
    }

    /// Every instance's triangles appended to [`Scene::triangles`] in world
    /// space, in instance order, with their normals (carried by the
    /// inverse transpose), texture coordinates, colours and tangents in
    /// the tables beside, exactly as a `[[meshes]]` entry with the same
    /// transform and material would place them; then no instances and no
    /// shapes are left. A scene without instances is unchanged.
    pub fn flatten_instances(&mut self) {
        if self.instances.is_empty() && self.shapes.is_empty() {
            return;
        }
        let mut parts = TriangleParts {
            normals: std::mem::take(&mut self.triangle_normals),
            uvs: std::mem::take(&mut self.triangle_uvs),
            second_uvs: std::mem::take(&mut self.triangle_second_uvs),
            colours: std::mem::take(&mut self.triangle_colours),
            tangents: std::mem::take(&mut self.triangle_tangents),
            textures: std::mem::take(&mut self.textures),
        };
        let shapes = std::mem::take(&mut self.shapes);
        for instance in std::mem::take(&mut self.instances) {
            let Some(shape) = shapes.get(instance.shape as usize) else {
                continue;
            };
            let DAffine3 {
                matrix3,
                translation,
            } = instance.transform;
            let world: Vec<DVec3> = shape
                .mesh
                .positions
                .par_iter()
                .map(|&v| matrix3 * v + translation)
                .collect();
            let placement = Placement {
                mesh: &shape.mesh,
                transform: matrix3,
                smooth: shape.smooth,
                override_material: instance.material.or(shape.material),
                first_material: shape.first_material,
            };
            // A validated shape cannot fail: the readers write indices in
            // range, and each face has a material (its file's, when loaded
            // with them, or the shape's).
            let _ = add_placed(
                &placement,
                world,
                &self.materials,
                &mut self.triangles,
                &mut parts,
            );
        }
        parts.finish();
        self.triangle_normals = parts.normals;
        self.triangle_uvs = parts.uvs;
        self.triangle_second_uvs = parts.second_uvs;
        self.triangle_colours = parts.colours;
        self.triangle_tangents = parts.tangents;
        self.textures = parts.textures;
    }

    /// The scene with its instances flattened ([`Scene::flatten_instances`]).
    pub fn flattened(mut self) -> Scene {
        self.flatten_instances();
        self
    }
}
