//! The scene's objects: spheres and two-sided triangles, each naming its
//! material.

use glam::DVec3;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sphere {
    pub center: DVec3,
    pub radius: f64,
    pub material: u32,
}

/// A two-sided triangle, from `[[triangles]]` or a mesh (already
/// transformed). 88 bytes: its vertex normals and texture coordinates,
/// where it has them, lie in [`Scene::triangle_normals`](super::Scene::triangle_normals) and
/// [`Scene::triangle_uvs`](super::Scene::triangle_uvs) (with the normals in it, a triangle took 160
/// bytes, and building the 1.1 M-triangle bunny's took 34 ms of its load,
/// 26 ms since; temporary timers, two threads).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Triangle {
    pub vertices: [DVec3; 3],
    pub material: u32,
    /// Index into [`Scene::triangle_normals`](super::Scene::triangle_normals) of its unit shading normals at
    /// the three vertices, in world space, for smooth shading;
    /// [`Triangle::FLAT`]: the geometric normal everywhere.
    pub normals: u32,
    /// Index into [`Scene::triangle_uvs`](super::Scene::triangle_uvs) of its texture coordinates at the
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
