//! Rays, boxes and the two primitives, in f32 exactly as the shader computes
//! them (shaders/intersect.wgsl mirrors every function here line by line), so
//! CPU tests exercise the same arithmetic the GPU runs.

use glam::Vec3;

/// Stand-in for infinity: WGSL implementations may assume no inf or NaN.
pub const T_INFINITY: f32 = 3.0e38;
/// Direction components smaller than this count as parallel to an axis
/// plane, so no division can overflow.
pub const PARALLEL_EPSILON: f32 = 1e-20;

/// A triangle's hit point may lie this share of the largest coordinate
/// its test works with outside the triangle's box, and no more
/// (`TriangleF32::holds_hit_at`).
pub const HIT_BOX_MARGIN: f32 = 1.0 / 1024.0;

/// A ray counts as lying in a triangle's plane when the normal's component
/// along it is at most this share of the normal's size (|n.x| + |n.y| +
/// |n.z|): about 1e-6 rad (`TriangleF32::runs_in_plane`).
pub const IN_PLANE_MARGIN: f32 = 1.0 / (1u32 << 20) as f32;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ray {
    pub origin: Vec3,
    /// Unit length.
    pub dir: Vec3,
}

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

/// The watertight triangle test's per-ray constants: `kz` is the axis the
/// ray runs most along, `kx`, `ky` the two others; the shear (sx, sy) and the
/// scale sz map the ray's direction onto (0, 0, 1). `|dir[kz]| >= 1/sqrt(3)` for
/// a unit direction, so the divisions are safe. Ties pick the lower axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RayShear {
    pub kx: usize,
    pub ky: usize,
    pub kz: usize,
    pub sx: f32,
    pub sy: f32,
    pub sz: f32,
}

impl RayShear {
    pub fn of(dir: Vec3) -> RayShear {
        let m = dir.abs();
        let kz = if m.x >= m.y && m.x >= m.z {
            0
        } else if m.y >= m.z {
            1
        } else {
            2
        };
        // The winding-preserving swap of the paper is left out: the test is
        // two-sided, so the orientation of the projected triangle does not matter.
        let kx = (kz + 1) % 3;
        let ky = (kz + 2) % 3;
        let sz = 1.0 / dir[kz];
        RayShear {
            kx,
            ky,
            kz,
            sx: dir[kx] * sz,
            sy: dir[ky] * sz,
            sz,
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TriangleF32 {
    pub v: [Vec3; 3],
}

impl TriangleF32 {
    pub fn bounds(&self) -> Aabb {
        Aabb {
            min: self.v[0].min(self.v[1]).min(self.v[2]),
            max: self.v[0].max(self.v[1]).max(self.v[2]),
        }
    }

    /// Watertight, two-sided; t > 0. Woop, Benthin and Wald, "Watertight
    /// Ray/Triangle Intersection" (JCGT 2013): the vertices are moved into a
    /// frame where the ray is the +z axis through (0, 0), and the ray hits if
    /// (0, 0) is inside or on the projected triangle, by the signs of its three
    /// edge functions. A shared edge's function is, in both triangles, the
    /// difference of the same two rounded products, so each sign decision is a
    /// comparison of those products: a ray through a shared edge or vertex hits
    /// at least one of the triangles there, never neither. A product equal to
    /// the other (an edge function of exactly 0) counts as inside, where the
    /// paper recomputes in f64 (WGSL has none): a ray exactly on an edge hits
    /// both triangles. Degenerate triangles and rays in the triangle's plane
    /// (|det| < 1e-30) never hit.
    pub fn intersect(&self, ray: &Ray) -> Option<f32> {
        let sh = RayShear::of(ray.dir);
        let a = self.v[0] - ray.origin;
        let b = self.v[1] - ray.origin;
        let c = self.v[2] - ray.origin;
        let (ax, ay) = (a[sh.kx] - sh.sx * a[sh.kz], a[sh.ky] - sh.sy * a[sh.kz]);
        let (bx, by) = (b[sh.kx] - sh.sx * b[sh.kz], b[sh.ky] - sh.sy * b[sh.kz]);
        let (cx, cy) = (c[sh.kx] - sh.sx * c[sh.kz], c[sh.ky] - sh.sy * c[sh.kz]);
        // Edge functions u = cx by - cy bx (edge b-c), v (c-a), w (a-b): their
        // signs come from comparing the products, which no fused multiply-add
        // can round differently in two triangles.
        let (u0, u1) = (cx * by, cy * bx);
        let (v0, v1) = (ax * cy, ay * cx);
        let (w0, w1) = (bx * ay, by * ax);
        let any_negative = u0 < u1 || v0 < v1 || w0 < w1;
        let any_positive = u0 > u1 || v0 > v1 || w0 > w1;
        if any_negative && any_positive {
            return None;
        }
        let det = (u0 - u1) + (v0 - v1) + (w0 - w1);
        if det.abs() < 1e-30 || self.runs_in_plane(ray.dir) {
            return None; // degenerate, or the ray lies in the triangle's plane
        }
        let (az, bz, cz) = (sh.sz * a[sh.kz], sh.sz * b[sh.kz], sh.sz * c[sh.kz]);
        let t_scaled = (u0 - u1) * az + (v0 - v1) * bz + (w0 - w1) * cz;
        let t = t_scaled * (1.0 / det);
        (t > 0.0 && self.holds_hit_at(ray, t)).then_some(t)
    }

    /// Whether the point at `t` lies within the test's rounding of the
    /// triangle's box. Far from it, the hit is the rounding's: a small
    /// triangle seen nearly edge-on from afar (a CI run's: 1.5e-4 across,
    /// 18 units out, 5e-4 rad off its plane) has sheared coordinates whose
    /// rounding (2^-24 of the distances, ~1e-6) dwarfs its projected width
    /// (~1e-8), so its edge functions are noise that may share a sign, and
    /// `t`, a weighted mean of the vertices' depths, puts the point on the
    /// ray beside the triangle, 19 units from it there. The margin, 2^-10 of
    /// the largest coordinate the test works with, is far above the
    /// rounding of a true hit's point and far below such misses. Mirrors
    /// `holds_hit_at` in shaders/intersect.wgsl.
    pub fn holds_hit_at(&self, ray: &Ray, t: f32) -> bool {
        let b = self.bounds();
        let p = ray.origin + ray.dir * t;
        let scale = b
            .min
            .abs()
            .max(b.max.abs())
            .max(ray.origin.abs())
            .max_element();
        let margin = Vec3::splat(scale * HIT_BOX_MARGIN);
        (b.min - margin).cmple(p).all() && p.cmple(b.max + margin).all()
    }

    /// Whether `dir` lies in the triangle's plane as far as the triangle's
    /// own arithmetic can tell: the normal's component along it, made from
    /// the edges alone (so it does not grow with the ray's length, as the
    /// sheared coordinates' rounding does), is within 2^-20 of the normal's
    /// size, about 1e-6 rad. The edge functions are then rounding noise that
    /// may share a sign (a CI run's ray in the plane of a grid triangle was
    /// hit 6 units beyond its box). A margin of 2^-18 of |e1|max |e2|max,
    /// the bound on this dot product's rounding, was tried first: it turned
    /// slivers (edges 2.6e-4 rad apart) away from rays 0.4 degrees off their
    /// plane, and a fan of them cracked (`tests/gpu/triangle_edges.rs`). For a
    /// sliver whose normal is itself uncertain the edge functions decide,
    /// and `holds_hit_at` catches what they get wrong far from the
    /// triangle. Asked only of candidate hits. Mirrors `runs_in_plane` in
    /// shaders/intersect.wgsl.
    pub fn runs_in_plane(&self, dir: Vec3) -> bool {
        let e1 = self.v[1] - self.v[0];
        let e2 = self.v[2] - self.v[0];
        let n = e1.cross(e2);
        n.dot(dir).abs() <= (n.x.abs() + n.y.abs() + n.z.abs()) * IN_PLANE_MARGIN
    }

    /// Unit geometric normal (not yet turned to face a ray).
    pub fn normal(&self) -> Vec3 {
        (self.v[1] - self.v[0])
            .cross(self.v[2] - self.v[0])
            .normalize_or_zero()
    }

    pub fn magnitude(&self) -> f32 {
        self.v[0]
            .abs()
            .max(self.v[1].abs())
            .max(self.v[2].abs())
            .max_element()
    }
}

/// Distance to move a secondary ray's origin off the surface along N.
///
/// 1e-4 of the hit point's magnitude (at least 1e-4 scene units), and never
/// less than 2^-22 of the largest coordinate the intersection test worked
/// with: a sphere of radius 9000 centred 9000 away computes |o - c|^2 - r^2
/// with an absolute error of ~16 units^2, i.e. ~1e-3 units of distance, far
/// more than 1e-4. Scaling with the object (not the scene's extent) keeps
/// small objects' contact shadows tight while big ones show no acne.
pub fn spawn_offset(hit_point: Vec3, object_magnitude: f32) -> f32 {
    (1e-4 * hit_point.abs().max_element().max(1.0)).max(object_magnitude * (1.0 / 4_194_304.0))
}

/// The scene's objects in f32, exactly as uploaded to the GPU. Object ids:
/// spheres are `0..spheres.len()`, triangles follow.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Primitives {
    pub spheres: Vec<SphereF32>,
    pub triangles: Vec<TriangleF32>,
    /// The alpha test of triangles whose material has an alpha mode
    /// (crate::alpha_test); None where none has, as in most scenes.
    pub alpha: Option<std::sync::Arc<crate::alpha_test::AlphaTest>>,
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
        let alpha = crate::alpha_test::AlphaTest::for_scene(scene).map(std::sync::Arc::new);
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

#[cfg(test)]
mod tests {
    use super::*;

    fn ray(origin: Vec3, dir: Vec3) -> Ray {
        Ray {
            origin,
            dir: dir.normalize(),
        }
    }

    /// A CI run's case: a ray lying in the triangle's plane (normal
    /// (-1, 1, -1), direction (0, -1, -1)), 6 units past its box. The shear's
    /// rounding left the three edge functions at noise of one sign, and the
    /// test reported a hit at t = 11.67, at x = 7.5 on a triangle whose x
    /// ends at 1.25.
    #[test]
    fn a_ray_in_the_plane_beyond_the_triangle_misses_it() {
        let tri = TriangleF32 {
            v: [
                Vec3::new(-7.75, 4.25, 7.5),
                Vec3::new(-2.25, 7.75, 5.5),
                Vec3::new(1.25, 5.5, -0.25),
            ],
        };
        let r = ray(
            Vec3::new(7.5000725, 16.0, 3.9999275),
            Vec3::new(0.0, -1.0, -1.0),
        );
        assert!(tri.runs_in_plane(r.dir));
        assert_eq!(tri.intersect(&r), None);
    }

    /// A CI run's case: a triangle 1.5e-4 across, 18 units from the ray's
    /// origin and 5e-4 rad off its plane. The shear's rounding swamped the
    /// projected triangle, the edge functions shared a sign, and the test
    /// reported a hit at a point 19 units beside the triangle.
    #[test]
    fn a_far_small_triangle_nearly_edge_on_is_not_hit_beside_itself() {
        let tri = TriangleF32 {
            v: [
                Vec3::new(0.09544055, 6.176846, 3.757659),
                Vec3::new(0.09544055, 6.176853, 3.7576532),
                Vec3::new(0.09558137, 6.176692, 3.7577822),
            ],
        };
        let r = Ray {
            origin: Vec3::new(-8.836889, -6.568033, 13.11186),
            dir: Vec3::new(0.7282444, -0.5278434, 0.4370827),
        };
        assert!(!tri.runs_in_plane(r.dir), "not parallel to rounding");
        assert_eq!(tri.intersect(&r), None);
    }

    /// Small triangles far away, hit head-on and at 1e-2 rad from edge-on
    /// through their centroid, are hit there: the box check keeps true hits.
    #[test]
    fn far_small_triangles_are_hit_where_rays_cross_them() {
        for (size, distance) in [(1e-3f32, 100.0f32), (1e-4, 10.0), (1e-2, 1000.0)] {
            let centre = Vec3::new(3.0, -2.0, 5.0);
            let tri = TriangleF32 {
                v: [
                    centre,
                    centre + Vec3::new(size, 0.0, 0.0),
                    centre + Vec3::new(0.0, size, 0.0),
                ],
            };
            let centroid = (tri.v[0] + tri.v[1] + tri.v[2]) / 3.0;
            for dir in [Vec3::Z, Vec3::new(1.0, 0.3, 1e-2)] {
                let dir = dir.normalize();
                let r = ray(centroid - dir * distance, dir);
                let t = tri.intersect(&r);
                assert!(
                    t.is_some_and(|t| (t - distance).abs() <= 1e-3 * distance),
                    "{tri:?} by {r:?}: {t:?}"
                );
            }
        }
    }

    /// Rays in the plane of a triangle, through its inside, from afar and
    /// near, in many directions, miss it (it is seen edge-on); the same
    /// rays tilted out of the plane by 1e-3 rad hit it where they cross the
    /// plane, near the centroid.
    #[test]
    fn rays_in_a_triangles_plane_miss_it_and_tilted_ones_hit() {
        let triangles = [
            [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            [[-7.75, 4.25, 7.5], [-2.25, 7.75, 5.5], [1.25, 5.5, -0.25]],
            [[3.1, -2.7, 9.4], [5.3, 1.9, -4.2], [-6.6, 0.35, 2.05]],
            [
                [1000.0, 1000.5, 999.0],
                [1000.2, 1000.1, 1000.3],
                [999.7, 999.9, 1000.6],
            ],
        ];
        let mut tilted_hits = 0;
        for v in triangles {
            let tri = TriangleF32 {
                v: v.map(Vec3::from_array),
            };
            let n = tri.normal();
            let (u, w) = n.any_orthonormal_pair();
            let centroid = (tri.v[0] + tri.v[1] + tri.v[2]) / 3.0;
            for k in 0..16 {
                let angle = k as f32 * std::f32::consts::TAU / 16.0;
                let along = u * angle.cos() + w * angle.sin();
                for distance in [0.5f32, 5.0, 50.0] {
                    let in_plane = ray(centroid - along * distance, along);
                    assert_eq!(
                        tri.intersect(&in_plane),
                        None,
                        "{tri:?} hit by {in_plane:?}, which lies in its plane"
                    );
                    let dir = (along + n * 1e-3).normalize();
                    let tilted = ray(centroid - dir * distance, dir);
                    // Where the f32 ray meets the f32 triangle's plane, in f64.
                    let (o, d) = (tilted.origin.as_dvec3(), tilted.dir.as_dvec3());
                    let [a, b, c] = tri.v.map(|p| p.as_dvec3());
                    let normal = (b - a).cross(c - a);
                    let expected = normal.dot(a - o) / normal.dot(d);
                    let t = tri.intersect(&tilted);
                    assert!(
                        t.is_some_and(|t| (t as f64 - expected).abs() <= 1e-3 * expected),
                        "{tri:?} missed by {tilted:?} (t {t:?}, expected {expected})"
                    );
                    tilted_hits += 1;
                }
            }
        }
        assert_eq!(tilted_hits, 4 * 16 * 3);
    }
}
