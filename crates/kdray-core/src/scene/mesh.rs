//! A mesh file in its own coordinates, whatever its format: its shared
//! vertices and normals, its triangles as index triples into them, and the
//! materials they use. The readers are `obj` and `gltf`; `mesh_file` picks
//! one by the file's extension.
//!
//! Indices rather than coordinates per triangle: a triangle is 28 bytes
//! instead of the 208 that three `DVec3` corners, three optional normals and
//! the corner ids took, and the scene's placement transforms each shared
//! vertex once instead of each corner (a closed mesh has about half as many
//! vertices as triangles, so six times fewer), for the 1.1M-triangle bunny.

use std::sync::Arc;

use glam::{DVec2, DVec3, DVec4};

use super::warning::Warning;

/// The index that stands for "none": in `MeshTriangle::normals`, a corner
/// without a file normal; in `MeshTriangle::material`, a triangle of a mesh
/// read without materials. No vertex, normal or material has this index
/// (the readers refuse a mesh that would need it).
pub const NO_INDEX: u32 = u32::MAX;

/// `i` as a mesh index, or None where it does not fit below [`NO_INDEX`].
pub fn mesh_index(i: usize) -> Option<u32> {
    u32::try_from(i).ok().filter(|&i| i != NO_INDEX)
}

/// A material of a mesh file, already in kdray's terms (for MTL: Ka, Kd, Ks,
/// Ns and no reflection; for glTF: the rule in docs/scene-format.md), with
/// its base-colour texture decoded (MTL `map_Kd`, glTF `baseColorTexture`)
/// and shared by the materials that name one image.
pub type MeshMaterial = super::material::Material<Arc<super::texture::Texture>>;

impl MeshMaterial {
    /// The material of an OBJ face that names none that kdray can find (no
    /// `usemtl`, an undefined name, an unreadable MTL file): a plain matte
    /// grey, diffuse 0.7 and ambient a tenth of that (the glTF rule's
    /// fraction), so the model reads as clay under any light.
    pub fn default_grey() -> Self {
        MeshMaterial {
            name: "(default grey)".to_string(),
            ambient: DVec3::splat(0.07),
            diffuse: DVec3::splat(0.7),
            specular: DVec3::ZERO,
            shininess: 0.0,
            reflection: 0.0,
            transmission: 0.0,
            ior: super::material::Material::DEFAULT_IOR,
            texture: None,
            physical: super::material::Physical::LAMBERTIAN,
            maps: super::material::MaterialMaps::NONE,
            alpha: super::alpha::Alpha::OPAQUE,
        }
    }
}

/// One triangle: indices into its mesh's arrays (40 bytes).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MeshTriangle {
    /// Each corner's vertex, an index into `Mesh::positions`. Corners with
    /// one index are one shared vertex, for computed smooth normals (OBJ:
    /// the `v` statement; glTF: a vertex of a primitive placed by one node).
    pub corners: [u32; 3],
    /// Each corner's normal from the file, an index into `Mesh::normals`;
    /// [`NO_INDEX`] where the file gives the corner none.
    pub normals: [u32; 3],
    /// Each corner's texture coordinates, an index into `Mesh::uvs`;
    /// [`NO_INDEX`] where the file gives the corner none.
    pub uvs: [u32; 3],
    /// Index into `Mesh::materials`; [`NO_INDEX`] when materials were not
    /// asked for.
    pub material: u32,
}

impl MeshTriangle {
    /// The index into `Mesh::normals` of corner `k`'s normal, if it has one.
    pub fn normal(&self, k: usize) -> Option<usize> {
        self.normals
            .get(k)
            .filter(|&&n| n != NO_INDEX)
            .map(|&n| n as usize)
    }

    /// Its texture coordinates among `uvs` (a mesh's), if every corner has
    /// them.
    pub fn uvs_in(&self, uvs: &[DVec2]) -> Option<[DVec2; 3]> {
        let [a, b, c] = self.uvs.map(|i| uvs.get(i as usize).copied());
        Some([a?, b?, c?])
    }

    /// Its three corners among `points` (a mesh's positions, or those
    /// positions placed in the scene); None where an index is out of range
    /// (the readers never write one).
    pub fn corners_in<T: Copy>(&self, points: &[T]) -> Option<[T; 3]> {
        let [a, b, c] = self.corners.map(|i| points.get(i as usize).copied());
        Some([a?, b?, c?])
    }

    /// The index into `Mesh::materials`, if materials were asked for.
    pub fn material(&self) -> Option<usize> {
        (self.material != NO_INDEX).then_some(self.material as usize)
    }
}

/// Whether three corners span a triangle of nonzero area.
pub(super) fn has_area(v: &[DVec3; 3]) -> bool {
    (v[1] - v[0]).cross(v[2] - v[0]).length_squared() > 0.0
}

/// The vertices, normals and triangles of a mesh file and the materials
/// they use.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Mesh {
    /// The shared vertices, in the file's coordinates (glTF: its scene's,
    /// the node transforms applied; a mesh placed by two nodes has its
    /// vertices twice). All of the file's, also those no triangle uses (OBJ:
    /// every `v` statement, in order).
    pub positions: Vec<DVec3>,
    /// The file's vertex normals, carried like the positions (glTF: by the
    /// inverse transpose of the node transform); not necessarily of unit
    /// length. OBJ: every `vn` statement, in order.
    pub normals: Vec<DVec3>,
    /// The file's texture coordinates, in the convention of
    /// [`texture`](super::texture) (OBJ: every `vt` statement, in order,
    /// v turned to 1 - v; kept only where a material has a texture).
    pub uvs: Vec<DVec2>,
    /// glTF: the second channel of texture coordinates (a set with a
    /// transform, which the slots in a material's `maps.second_uv` read),
    /// one per position; empty: no material reads one.
    pub second_uvs: Vec<DVec2>,
    /// glTF's `COLOR_0`, linear RGBA, one per position (empty: no primitive
    /// has it; white for the vertices of primitives without it).
    pub colours: Vec<DVec4>,
    /// glTF's `TANGENT`, one per position, carried like the positions (xyz
    /// by the node transforms, w the bitangent's sign, flipped by a
    /// mirroring transform); empty: no primitive has it; all zero for the
    /// vertices of primitives without it.
    pub tangents: Vec<DVec4>,
    /// Only triangles with an area in the file's coordinates.
    pub triangles: Vec<MeshTriangle>,
    /// Deduplicated, in order of first use by a triangle; only materials some
    /// triangle uses are here.
    pub materials: Vec<MeshMaterial>,
    /// What the file asked for that the reader ignored or filled in, in
    /// file order; the caller decides where they go.
    pub warnings: Vec<Warning>,
    /// glTF: the first perspective camera the scene's node walk meets
    /// (depth first, children in order), in the file's coordinates.
    pub camera: Option<super::camera::Camera>,
    /// glTF: the `KHR_lights_punctual` lights the node walk meets, in the
    /// file's coordinates.
    pub lights: Vec<super::light::Light>,
    /// glTF read with instancing: each mesh that several nodes place, or
    /// that a node places by `EXT_mesh_gpu_instancing`, once in its own
    /// space, with the transform of each copy; their triangles are not in
    /// `triangles`. Empty when read without instancing (the copies are
    /// then in `triangles`, each placed).
    pub instanced: Vec<InstancedMesh>,
}

/// A mesh of a glTF file placed several times: its vertices, normals and
/// triangles in its own space (its triangles' materials index the
/// materials of the [`Mesh`] that holds it; its own are empty), and the
/// transform from its space to the file's of each copy.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct InstancedMesh {
    /// The glTF mesh's index.
    pub index: usize,
    pub mesh: Mesh,
    pub transforms: Vec<glam::DAffine3>,
}

impl Mesh {
    /// The three vertices of `t`, in the file's coordinates; None where a
    /// corner's index is out of range (the readers never write one).
    pub fn vertices(&self, t: &MeshTriangle) -> Option<[DVec3; 3]> {
        t.corners_in(&self.positions)
    }

    /// The file's normal at corner `k` of `t`, if it gives one.
    pub fn normal(&self, t: &MeshTriangle, k: usize) -> Option<DVec3> {
        self.normals.get(t.normal(k)?).copied()
    }

    /// The file's vertex colours at the corners of `t`, if it gives them.
    pub fn colours_of(&self, t: &MeshTriangle) -> Option<[DVec4; 3]> {
        t.corners_in(&self.colours)
    }

    /// The file's tangents at the corners of `t`, where all three have one.
    pub fn tangents_of(&self, t: &MeshTriangle) -> Option<[DVec4; 3]> {
        t.corners_in(&self.tangents)
            .filter(|c| c.iter().all(|t| t.w != 0.0))
    }
}
