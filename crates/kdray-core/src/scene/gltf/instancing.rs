//! glTF instancing: a mesh that several nodes place, and a node's
//! `EXT_mesh_gpu_instancing` (its TRANSLATION, ROTATION and SCALE
//! accessors, one element per copy, each copy placed by the node's
//! transform times its own T * R * S). Read with instancing, such a mesh is
//! read once in its own space into [`Mesh::instanced`] with each copy's
//! transform; without, each copy is placed into the mesh's triangles, as
//! any node's mesh is.

use std::collections::HashMap;

use glam::{DAffine3, DMat4, DQuat, DVec3};

use super::accessors::Attribute;
use crate::scene::mesh::{InstancedMesh, Mesh};

/// The extension's name.
const EXT: &str = "EXT_mesh_gpu_instancing";

/// How many copies of each mesh (by index) the nodes of `scene` place: one
/// per node, two for a node with `EXT_mesh_gpu_instancing` (however many
/// copies it lists: it is instanced either way). A node reached twice is
/// counted once (the walk refuses such a file).
pub(super) fn mesh_uses(document: &gltf::Document, scene: &gltf::Scene) -> Vec<usize> {
    let mut uses = vec![0usize; document.meshes().count()];
    let mut visited = vec![false; document.nodes().count()];
    let mut stack: Vec<gltf::Node> = scene.nodes().collect();
    while let Some(node) = stack.pop() {
        if std::mem::replace(&mut visited[node.index()], true) {
            continue;
        }
        if let Some(mesh) = node.mesh() {
            let copies = if node.extension_value(EXT).is_some() {
                2
            } else {
                1
            };
            uses[mesh.index()] += copies;
        }
        stack.extend(node.children());
    }
    uses
}

impl super::Reader<'_, '_> {
    /// The copies `node`'s `EXT_mesh_gpu_instancing` lists, as transforms
    /// in the node's space (T * R * S), or None where it has none. An
    /// accessor that is missing, of the wrong type or of another count than
    /// the others is an error.
    pub(super) fn gpu_instances(&self, node: &gltf::Node) -> Result<Option<Vec<DMat4>>, String> {
        let Some(ext) = node.extension_value(EXT) else {
            return Ok(None);
        };
        let at = format!("node {} {EXT}", node.index());
        let attributes = ext
            .get("attributes")
            .and_then(|a| a.as_object())
            .ok_or_else(|| format!("{at}: no attributes object"))?;
        let accessor = |name: &str| -> Result<Option<gltf::Accessor>, String> {
            let Some(value) = attributes.get(name) else {
                return Ok(None);
            };
            let index = value
                .as_u64()
                .ok_or_else(|| format!("{at}: {name} is not an accessor index: {value}"))?;
            let accessor = usize::try_from(index)
                .ok()
                .and_then(|i| self.document.accessors().nth(i))
                .ok_or_else(|| format!("{at}: {name}: there is no accessor {index}"))?;
            Ok(Some(accessor))
        };
        let read3 = |name: &str| -> Result<Option<Vec<DVec3>>, String> {
            accessor(name)?
                .map(|a| self.read_vec3(&a, Attribute::Position))
                .transpose()
                .map_err(|m| format!("{at}: {name} {m}"))
        };
        let translation = read3("TRANSLATION")?;
        let scale = read3("SCALE")?;
        let rotation = accessor("ROTATION")?
            .map(|a| self.read_tangents(&a))
            .transpose()
            .map_err(|m| format!("{at}: ROTATION {m}"))?;
        let counts = [
            ("TRANSLATION", translation.as_ref().map(Vec::len)),
            ("ROTATION", rotation.as_ref().map(Vec::len)),
            ("SCALE", scale.as_ref().map(Vec::len)),
        ];
        let given: Vec<(&str, usize)> = counts
            .iter()
            .filter_map(|&(name, n)| Some((name, n?)))
            .collect();
        let Some(&(_, count)) = given.first() else {
            return Err(format!(
                "{at}: names none of TRANSLATION, ROTATION and SCALE"
            ));
        };
        if let Some(&(name, n)) = given.iter().find(|&&(_, n)| n != count) {
            return Err(format!(
                "{at}: {name} has {n} elements, {} has {count}: each attribute must give every copy one",
                given[0].0
            ));
        }
        (0..count)
            .map(|i| {
                let t = translation.as_ref().map_or(DVec3::ZERO, |v| v[i]);
                let s = scale.as_ref().map_or(DVec3::ONE, |v| v[i]);
                let q = rotation.as_ref().map_or(DQuat::IDENTITY, |v| {
                    DQuat::from_xyzw(v[i].x, v[i].y, v[i].z, v[i].w)
                });
                let length = q.length();
                if !(length > 0.0 && length.is_finite()) {
                    return Err(format!(
                        "{at}: ROTATION element {i} is zero, not a rotation"
                    ));
                }
                let q = q / length;
                Ok(DMat4::from_scale_rotation_translation(s, q, t))
            })
            .collect::<Result<Vec<_>, String>>()
            .map(Some)
    }

    /// Places `mesh` at `worlds`: with instancing, read once in its own
    /// space (at its first placement) and each copy's transform kept
    /// beside; without, each copy placed into the mesh's triangles. A copy
    /// that cannot be inverted (a scale of 0) draws nothing and is left out.
    pub(super) fn place_copies(
        &mut self,
        mesh: &gltf::Mesh,
        worlds: Vec<DMat4>,
        instanced_of: &mut HashMap<usize, usize>,
    ) -> Result<(), String> {
        if !self.instancing {
            for world in worlds {
                self.mesh(mesh, world)?;
            }
            return Ok(());
        }
        let k = match instanced_of.get(&mesh.index()) {
            Some(&k) => k,
            None => {
                // Read into a mesh of its own that borrows the file's
                // materials and warnings, so that its triangles index the
                // file's materials.
                let mut own = Mesh {
                    materials: std::mem::take(&mut self.mesh.materials),
                    warnings: std::mem::take(&mut self.mesh.warnings),
                    ..Mesh::default()
                };
                std::mem::swap(&mut self.mesh, &mut own);
                let read = self.mesh(mesh, DMat4::IDENTITY);
                std::mem::swap(&mut self.mesh, &mut own);
                self.mesh.materials = std::mem::take(&mut own.materials);
                self.mesh.warnings = std::mem::take(&mut own.warnings);
                read?;
                let k = self.mesh.instanced.len();
                self.mesh.instanced.push(InstancedMesh {
                    index: mesh.index(),
                    mesh: own,
                    transforms: Vec::new(),
                });
                instanced_of.insert(mesh.index(), k);
                k
            }
        };
        let copies = worlds
            .into_iter()
            .map(DAffine3::from_mat4)
            .filter(|a| a.matrix3.determinant() != 0.0 && a.inverse().is_finite());
        if let Some(instanced) = self.mesh.instanced.get_mut(k) {
            instanced.transforms.extend(copies);
        }
        Ok(())
    }
}
