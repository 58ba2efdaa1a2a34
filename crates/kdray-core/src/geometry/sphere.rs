//! The sphere in f32 and its ray test, as shaders/intersect.wgsl computes it.

use glam::Vec3;

use super::aabb::Aabb;
use super::ray::Ray;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SphereF32 {
    pub center: Vec3,
    pub radius: f32,
}

impl SphereF32 {
    pub fn bounds(&self) -> Aabb {
        Aabb {
            min: self.center - Vec3::splat(self.radius),
            max: self.center + Vec3::splat(self.radius),
        }
    }

    /// Smallest root t > 0, by the formulation of Haines et al. (Ray Tracing
    /// Gems, ch. 7): the discriminant from the ray's closest approach, and the
    /// near root from c / q, which avoid the cancellations of the textbook form.
    pub fn intersect(&self, ray: &Ray) -> Option<f32> {
        let f = ray.origin - self.center;
        let b = f.dot(ray.dir);
        let l = f - b * ray.dir;
        let r2 = self.radius * self.radius;
        let disc = r2 - l.dot(l);
        if disc < 0.0 {
            return None;
        }
        let sign_b = if b >= 0.0 { 1.0 } else { -1.0 };
        let q = -b - sign_b * disc.sqrt();
        if q == 0.0 {
            return None; // tangent at the origin
        }
        let c = f.dot(f) - r2;
        let (ta, tb) = (c / q, q);
        let (near, far) = (ta.min(tb), ta.max(tb));
        if near > 0.0 {
            Some(near)
        } else if far > 0.0 {
            Some(far)
        } else {
            None
        }
    }

    /// Largest coordinate magnitude the intersection works with (see `spawn_offset`).
    pub fn magnitude(&self) -> f32 {
        self.center.abs().max_element() + self.radius
    }
}
