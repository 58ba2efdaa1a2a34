//! The window camera's projection for drawing world-space lines over the
//! image (the inspected rays and cells): the inverse of the kernel's camera
//! ray generation (`camera_ray` in shaders/trace.wgsl), so that a point on
//! the primary ray through (u, v) lands at (u, v) of the window. Pure.

use glam::{DMat4, DVec2, DVec3, DVec4, Mat4};

use crate::scene::Camera;

/// The near plane's distance for `camera` (scene units): a thousandth of
/// its distance to its target, so that lines from points right in front of
/// it are still drawn whatever the scene's scale; a thousandth of a unit
/// for a camera on its target.
pub fn near_plane(camera: &Camera) -> f64 {
    let d = (camera.look_at - camera.position).length();
    if d.is_finite() && d > 0.0 {
        1e-3 * d
    } else {
        1e-3
    }
}

/// World to clip space for one camera: what the line shader multiplies
/// world positions by, and the same on the CPU (f64) for tests.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ViewProjection {
    /// World position (w = 1) to clip space. Clip x, y are the kernel's
    /// 2u - 1 and 1 - 2v times w; w is the depth along the view direction;
    /// z = w - near, so the GPU's z >= 0 clip drops what lies nearer than
    /// `near` (and z <= w always: no far plane).
    pub matrix: DMat4,
}

impl ViewProjection {
    /// The projection of `camera` in an image of `aspect` (width / height,
    /// as the kernel's `params.aspect`), clipping at `near` scene units in
    /// front of the camera.
    pub fn new(camera: &Camera, aspect: f64, near: f64) -> Self {
        let b = camera.basis();
        let h = if b.tan_half_vfov.is_finite() && b.tan_half_vfov > 0.0 {
            b.tan_half_vfov
        } else {
            1.0
        };
        let a = if aspect.is_finite() && aspect > 0.0 {
            aspect
        } else {
            1.0
        };
        let near = if near.is_finite() { near.max(0.0) } else { 0.0 };
        let row = |axis: DVec3, scale: f64, offset: f64| {
            let v = axis * scale;
            DVec4::new(v.x, v.y, v.z, -v.dot(b.position) + offset)
        };
        // Rows: right / (h a), up / h, forward (minus near), forward.
        let rows = [
            row(b.right, 1.0 / (h * a), 0.0),
            row(b.up, 1.0 / h, 0.0),
            row(b.forward, 1.0, -near),
            row(b.forward, 1.0, 0.0),
        ];
        ViewProjection {
            matrix: DMat4::from_cols_array_2d(&[
                rows[0].to_array(),
                rows[1].to_array(),
                rows[2].to_array(),
                rows[3].to_array(),
            ])
            .transpose(),
        }
    }

    /// The matrix the line shader reads (column-major, as WGSL's mat4x4).
    pub fn gpu_matrix(&self) -> Mat4 {
        self.matrix.as_mat4()
    }

    /// Clip-space position of world point `p`.
    pub fn clip(&self, p: DVec3) -> DVec4 {
        self.matrix * p.extend(1.0)
    }

    /// Where `p` lands in a `width` x `height` image, in pixels from the
    /// top-left corner (pixel (x, y) covers [x, x + 1) x [y, y + 1)); None
    /// when it lies nearer than the near plane (or behind the camera).
    pub fn to_image(&self, p: DVec3, (width, height): (u32, u32)) -> Option<DVec2> {
        self.clip_to_image(self.clip(p), (width, height))
    }

    fn clip_to_image(&self, c: DVec4, (width, height): (u32, u32)) -> Option<DVec2> {
        if !(c.z >= 0.0 && c.w > 0.0) {
            return None;
        }
        let ndc = DVec2::new(c.x / c.w, c.y / c.w);
        Some(DVec2::new(
            (ndc.x + 1.0) * 0.5 * width as f64,
            (1.0 - ndc.y) * 0.5 * height as f64,
        ))
    }

    /// The part of segment `a`-`b` beyond the near plane, in image pixels,
    /// as the GPU clips and draws it; None if none of it is.
    pub fn segment_to_image(&self, a: DVec3, b: DVec3, size: (u32, u32)) -> Option<(DVec2, DVec2)> {
        let (mut ca, mut cb) = (self.clip(a), self.clip(b));
        if ca.z < 0.0 && cb.z < 0.0 {
            return None;
        }
        // Clip at z = 0 (the near plane), as the rasteriser does.
        if ca.z < 0.0 {
            ca = ca + (cb - ca) * (ca.z / (ca.z - cb.z));
            ca.z = 0.0;
        } else if cb.z < 0.0 {
            cb = cb + (ca - cb) * (cb.z / (cb.z - ca.z));
            cb.z = 0.0;
        }
        Some((self.clip_to_image(ca, size)?, self.clip_to_image(cb, size)?))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::inspect::{build_tree, inspect_scene};
    use crate::kdtree::{BuildStrategy, Traversal};
    use crate::window::test_scenes::scene;
    use kdray_core::reference::ReferenceTracer;

    /// A point on the kernel's camera ray through (u, v) projects to
    /// (u * width, v * height), at any distance along the ray.
    #[test]
    fn points_on_a_camera_ray_project_where_the_ray_was_generated() {
        for (name, (w, h)) in [
            ("scenes/seed.toml", (96, 64)),
            ("scenes/torus.toml", (40, 90)),
            ("scenes/cornell_box.toml", (64, 64)),
        ] {
            let scene = scene(name, w, h);
            let tracer = ReferenceTracer::new(&scene, false);
            let projection = ViewProjection::new(&scene.camera, w as f64 / h as f64, 1e-3);
            for (u, v) in [(0.5, 0.5), (0.1, 0.9), (0.83, 0.27), (0.0, 0.0)] {
                let ray = tracer.camera_ray(u as f32, v as f32);
                for t in [0.5, 3.0, 40.0] {
                    let p = (ray.origin + ray.dir * t).as_dvec3();
                    let q = projection.to_image(p, (w, h)).unwrap();
                    let expected = DVec2::new(u * w as f64, v * h as f64);
                    assert!(
                        (q - expected).length() < 1e-3,
                        "{name}: ({u}, {v}) at t {t}: projected to {q}, expected {expected}"
                    );
                }
            }
        }
    }

    /// The primary ray's hit point of an inspected pixel lands inside that
    /// pixel (sample 0 of one sample a pixel: its centre).
    #[test]
    fn the_primary_hit_of_an_inspected_pixel_projects_into_that_pixel() {
        let mut hits = 0;
        for (name, (w, h), pixels) in [
            ("scenes/seed.toml", (96, 64), [(48, 32), (20, 40), (70, 10)]),
            (
                "scenes/torus.toml",
                (80, 60),
                [(40, 30), (30, 25), (55, 33)],
            ),
            (
                "scenes/cornell_box.toml",
                (64, 64),
                [(32, 32), (5, 60), (60, 3)],
            ),
        ] {
            let scene = scene(name, w, h);
            let projection = ViewProjection::new(&scene.camera, w as f64 / h as f64, 1e-3);
            for (x, y) in pixels {
                let tree = build_tree(&scene, BuildStrategy::default());
                let inspection =
                    inspect_scene(&scene, Some(tree), Traversal::Ropes, (x, y)).unwrap();
                let primary = &inspection.rays[0];
                assert_eq!(primary.kind, "primary");
                let Some(hit) = &primary.hit else { continue };
                hits += 1;
                let q = projection
                    .to_image(glam::Vec3::from(hit.point).as_dvec3(), (w, h))
                    .unwrap();
                assert!(
                    q.x >= x as f64
                        && q.x < x as f64 + 1.0
                        && q.y >= y as f64
                        && q.y < y as f64 + 1.0,
                    "{name}: the hit of pixel ({x}, {y}) projects to {q}"
                );
            }
        }
        assert!(hits >= 6, "too few of the pixels hit something: {hits}");
    }

    /// Points behind the camera or nearer than the near plane do not
    /// project; a segment crossing the plane is cut where it crosses it.
    #[test]
    fn the_near_plane_cuts_what_lies_in_front_of_the_camera() {
        let camera = Camera {
            position: DVec3::new(0.0, 0.0, 5.0),
            look_at: DVec3::ZERO,
            up: DVec3::Y,
            vfov_degrees: 90.0,
        };
        let projection = ViewProjection::new(&camera, 2.0, 0.5);
        let size = (200, 100);
        assert_eq!(projection.to_image(DVec3::new(0.0, 0.0, 6.0), size), None);
        assert_eq!(projection.to_image(DVec3::new(0.0, 0.0, 4.8), size), None);
        let centre = projection.to_image(DVec3::ZERO, size).unwrap();
        assert!((centre - DVec2::new(100.0, 50.0)).length() < 1e-9);
        // One unit right at distance 1 is the right edge (tan 45 = 1,
        // aspect 2: half width 2 units there).
        let right = projection
            .to_image(DVec3::new(2.0, 1.0, 4.0), size)
            .unwrap();
        assert!((right - DVec2::new(200.0, 0.0)).length() < 1e-9, "{right}");
        // From behind the camera to the origin: cut at distance 0.5, whose
        // point x = 1 lies at 1 / (2 * 0.5) of the half width.
        let (a, b) = projection
            .segment_to_image(DVec3::new(1.0, 0.0, 5.0), DVec3::new(1.0, 0.0, 3.0), size)
            .unwrap();
        assert!((a - DVec2::new(200.0, 50.0)).length() < 1e-9, "{a}");
        assert!((b - DVec2::new(125.0, 50.0)).length() < 1e-9, "{b}");
        assert_eq!(
            projection.segment_to_image(DVec3::new(0.0, 0.0, 6.0), DVec3::new(1.0, 0.0, 5.0), size),
            None
        );
    }
}
