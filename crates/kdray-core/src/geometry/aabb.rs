//! Axis-aligned boxes: unions, surface area, and a ray's interval inside
//! one (`box_interval` in shaders/intersect.wgsl).

use glam::Vec3;

use super::ray::{Ray, PARALLEL_EPSILON, T_INFINITY};

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aabb {
    pub min: Vec3,
    pub max: Vec3,
}

impl Aabb {
    pub const EMPTY: Aabb = Aabb {
        min: Vec3::splat(f32::MAX),
        max: Vec3::splat(-f32::MAX),
    };

    pub fn union(self, other: Aabb) -> Aabb {
        Aabb {
            min: self.min.min(other.min),
            max: self.max.max(other.max),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.min.cmpgt(self.max).any()
    }

    /// The largest coordinate magnitude in the box.
    pub fn magnitude(&self) -> f32 {
        self.min.abs().max(self.max.abs()).max_element()
    }

    pub fn surface_area(&self) -> f32 {
        let e = (self.max - self.min).max(Vec3::ZERO);
        2.0 * (e.x * e.y + e.y * e.z + e.z * e.x)
    }

    /// The ray's parameter interval inside the box, or None if it misses.
    /// Axes the ray is parallel to constrain only by the origin's position.
    pub fn ray_interval(&self, ray: &Ray) -> Option<(f32, f32)> {
        let mut t0 = -T_INFINITY;
        let mut t1 = T_INFINITY;
        for a in 0..3 {
            let (o, d) = (ray.origin[a], ray.dir[a]);
            if d.abs() < PARALLEL_EPSILON {
                if o < self.min[a] || o > self.max[a] {
                    return None;
                }
            } else {
                let inv = 1.0 / d;
                let ta = (self.min[a] - o) * inv;
                let tb = (self.max[a] - o) * inv;
                t0 = t0.max(ta.min(tb));
                t1 = t1.min(ta.max(tb));
            }
        }
        (t0 <= t1).then_some((t0, t1))
    }
}

/// Boxes per piece of [`union_in_pieces`].
const UNION_PIECE: usize = 1 << 15;

/// The union of boxes `0..n` (`bounds(id)`), joined from fixed pieces in
/// order, so that it does not depend on the threads (a min of 0.0 and -0.0
/// depends on the order): the pieces on all threads of the current rayon
/// pool with `parallel`, on this one without.
pub fn union_in_pieces(n: usize, bounds: impl Fn(u32) -> Aabb + Sync, parallel: bool) -> Aabb {
    let piece = |p: usize| {
        (p * UNION_PIECE..((p + 1) * UNION_PIECE).min(n))
            .map(|id| bounds(id as u32))
            .fold(Aabb::EMPTY, Aabb::union)
    };
    let pieces = 0..n.div_ceil(UNION_PIECE);
    let unions: Vec<Aabb> = if parallel {
        use rayon::prelude::*;
        pieces.into_par_iter().map(piece).collect()
    } else {
        pieces.map(piece).collect()
    };
    unions.into_iter().fold(Aabb::EMPTY, Aabb::union)
}
