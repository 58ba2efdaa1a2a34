//! Flattening a scene's instances ([`Scene::flatten_instances`]): every
//! instance turned into world-space triangles exactly as a `[[meshes]]`
//! entry with the same transform is placed (the same code,
//! `mesh_placement::add_placed`): what the renderers consume today.

use glam::{DAffine3, DVec3};
use rayon::prelude::*;

use super::instances::transformed_box;
use super::mesh_placement::{add_placed, Placement};
use super::triangle_parts::TriangleParts;
use super::validated_scene::Scene;

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
