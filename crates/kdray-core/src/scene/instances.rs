//! Instancing in the validated scene: [`Shape`]s, meshes declared once and
//! kept in their own space, and [`Instance`]s, each a shape's placement
//! (an affine transform and an optional material override), with their
//! boxes. Flattening them into world-space triangles is
//! scene/flatten_instances.rs.

use std::sync::Arc;

use glam::{DAffine3, DVec3};

use super::mesh::Mesh;

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
