//! The scene's objects in f32 with their ids, the one object test every
//! walk runs (with the alpha test's holes), and their bounds.

use std::sync::Arc;

use super::aabb::{union_in_pieces, Aabb};
use super::alpha_test::AlphaTest;
use super::ray::Ray;
use super::sphere::SphereF32;
use super::triangle::TriangleF32;

/// The scene's objects in f32, exactly as uploaded to the GPU. Object ids:
/// spheres are `0..spheres.len()`, triangles follow.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Primitives {
    pub spheres: Vec<SphereF32>,
    pub triangles: Vec<TriangleF32>,
    /// The alpha test of triangles whose material has an alpha mode
    /// ([`AlphaTest`]); None where none has, as in most scenes.
    pub alpha: Option<Arc<AlphaTest>>,
}

impl Primitives {
    /// The scene's objects rounded to f32, on all threads, into vectors on
    /// huge pages (the 1.1 M-triangle bunny: 36 ms on one thread).
    pub fn from_scene(scene: &crate::scene::Scene) -> Self {
        use rayon::prelude::*;
        let mut spheres = crate::huge_pages::with_capacity(scene.spheres.len());
        spheres.par_extend(scene.spheres.par_iter().map(|s| SphereF32 {
            center: s.center.as_vec3(),
            radius: s.radius as f32,
        }));
        let mut triangles = crate::huge_pages::with_capacity(scene.triangles.len());
        triangles.par_extend(scene.triangles.par_iter().map(|t| TriangleF32 {
            v: t.vertices.map(|v| v.as_vec3()),
        }));
        let alpha = AlphaTest::for_scene(scene).map(Arc::new);
        Primitives {
            spheres,
            triangles,
            alpha,
        }
    }

    pub fn len(&self) -> usize {
        self.spheres.len() + self.triangles.len()
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    pub fn bounds(&self, id: u32) -> Aabb {
        let id = id as usize;
        match self.spheres.get(id) {
            Some(s) => s.bounds(),
            None => self.triangles[id - self.spheres.len()].bounds(),
        }
    }

    /// The object test every walk runs: the hit's t, or None; a hit in a
    /// hole of an alpha-tested triangle is none (mirror of `test_object`
    /// in shaders/intersect.wgsl).
    pub fn intersect(&self, id: u32, ray: &Ray) -> Option<f32> {
        let object = id;
        let id = id as usize;
        match self.spheres.get(id) {
            Some(s) => s.intersect(ray),
            None => {
                let index = id - self.spheres.len();
                let tri = &self.triangles[index];
                let t = tri.intersect(ray)?;
                match &self.alpha {
                    Some(a) if a.is_hole(index, object, tri, ray, t) => None,
                    _ => Some(t),
                }
            }
        }
    }

    pub fn magnitude(&self, id: u32) -> f32 {
        let id = id as usize;
        match self.spheres.get(id) {
            Some(s) => s.magnitude(),
            None => self.triangles[id - self.spheres.len()].magnitude(),
        }
    }

    /// Union of all objects' bounds (EMPTY for an empty scene), on all
    /// threads ([`union_in_pieces`]; for the 1.1 M-triangle bunny 6 ms on
    /// one thread).
    pub fn scene_bounds(&self) -> Aabb {
        union_in_pieces(self.len(), |id| self.bounds(id), true)
    }
}
