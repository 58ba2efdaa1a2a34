//! The triangle in f32 and its watertight ray test, line by line as
//! shaders/intersect.wgsl computes it, with the margins that turn away the
//! test's rounding, and the barycentric weights of a point on it.

use glam::Vec3;

use super::aabb::Aabb;
use super::ray::Ray;

/// A triangle's hit point may lie this share of the largest coordinate
/// its test works with outside the triangle's box, and no more
/// (`TriangleF32::holds_hit_at`).
pub const HIT_BOX_MARGIN: f32 = 1.0 / 1024.0;

/// A ray counts as lying in a triangle's plane when the normal's component
/// along it is at most this share of the normal's size (|n.x| + |n.y| +
/// |n.z|): about 1e-6 rad (`TriangleF32::runs_in_plane`).
pub const IN_PLANE_MARGIN: f32 = 1.0 / (1u32 << 20) as f32;

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

/// Barycentric weights of `v[0]`, `v[1]`, `v[2]` at `p`, clamped into the
/// triangle: mirror of `barycentrics` in shaders/shade.wgsl.
pub fn barycentrics(v: &[Vec3; 3], p: Vec3) -> Vec3 {
    let e1 = v[1] - v[0];
    let e2 = v[2] - v[0];
    let w = p - v[0];
    let n = e1.cross(e2);
    let nn = n.dot(n);
    if nn < 1e-30 {
        return Vec3::splat(1.0 / 3.0);
    }
    let inv = 1.0 / nn;
    let b1 = (w.cross(e2).dot(n) * inv).clamp(0.0, 1.0);
    let b2 = (e1.cross(w).dot(n) * inv).clamp(0.0, 1.0 - b1);
    Vec3::new(1.0 - b1 - b2, b1, b2)
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
