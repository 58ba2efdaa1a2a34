//! `kdray bench --wavefront-bound`: how much a wavefront path tracer (Laine,
//! Karras and Aila, "Megakernels considered harmful") could gain over
//! kdray's one loop per pixel on this adapter, bounded from above.
//!
//! A wavefront's frame is at least its extension and shadow stages: every
//! ray of the frame traced from a queue, with no camera, sampling or
//! shading. This measures that part alone, with the `trace_rays` kernel
//! specialised for the scene and walk (no cost counting), on a queue of
//! path rays made on the CPU (camera rays, then at each hit a cosine-
//! distributed bounce and a shadow ray toward a light, up to the scene's
//! `max_depth` hits), and sets it beside the megakernel's whole path-traced
//! frame of the same scene and walk. When the megakernel traces more rays
//! per second than the queue alone, no wavefront can be faster here: its
//! other stages and its queues only add to the queue's time.

use glam::Vec3;
use serde::Serialize;

use crate::error::Result;
use crate::geometry::{Primitives, Ray};
use crate::gpu::{GpuContext, GpuScene, PreparedScene, RayQueries, RayQuery};
use crate::kdtree::traverse::closest_hit;
use crate::kdtree::Traversal;
use crate::scene::{Integrator, Scene};
use kdray_core::random_scene::SplitMix64;

/// One walk's figures on one scene.
#[derive(Debug, Clone, Serialize)]
pub struct WavefrontBound {
    pub traversal: String,
    /// The path-traced frame: its rays (primary, shadow, bounces) and the
    /// median GPU time of its timed frames.
    pub megakernel_rays: u64,
    pub megakernel_ms: f64,
    /// The queue of path rays traced alone: its rays (nearest-hit bounces
    /// and camera rays, any-hit shadow rays) and the median time.
    pub queue_rays: u64,
    pub queue_shadow_rays: u64,
    pub queue_ms: f64,
    /// Millions of rays per second of each, and megakernel / queue.
    pub megakernel_mrays_per_s: f64,
    pub queue_mrays_per_s: f64,
    pub ratio: f64,
}

/// The figures of `scene` path traced (one sample per pixel) with every walk,
/// each time the median of `repeats` timed runs after a warm-up.
pub fn measure(ctx: &GpuContext, scene: &Scene, repeats: u32) -> Result<Vec<WavefrontBound>> {
    let mut scene = scene.clone();
    scene.render.integrator = Integrator::Path;
    scene.render.samples = 1;
    let uploaded = GpuScene::upload(
        ctx,
        PreparedScene::new(scene.clone(), crate::gpu::Accel::Kdtree),
    )?;
    let bounds = uploaded.prepared().arrays.bounds;
    let extent = (bounds.max - bounds.min).max_element();
    let queries = path_queue(&scene, &uploaded.prepared().tree, extent);
    let shadow = queries.iter().filter(|q| q.any_hit).count() as u64;
    let tracer = RayQueries::new(ctx)?;
    let mut out = Vec::new();
    for traversal in Traversal::ALL {
        let mut frames = Vec::new();
        let mut rays = 0;
        for _ in 0..=repeats {
            let (_, summary) = crate::render::render_streaming(
                ctx,
                &uploaded,
                None,
                crate::render::StreamOptions::new(traversal),
                &mut |_| Ok(()),
            )?;
            rays = summary.rays.total();
            frames.push(summary.gpu_ms);
        }
        let megakernel_ms = median(&frames[1..]);
        let times =
            tracer.time_queries(ctx, uploaded.buffers(), traversal, &queries, repeats + 1)?;
        let queue_ms = median(&times[1..]);
        let mk = rays as f64 / (megakernel_ms * 1e3);
        let q = queries.len() as f64 / (queue_ms * 1e3);
        out.push(WavefrontBound {
            traversal: crate::choice::Choice::name(traversal).to_string(),
            megakernel_rays: rays,
            megakernel_ms,
            queue_rays: queries.len() as u64,
            queue_shadow_rays: shadow,
            queue_ms,
            megakernel_mrays_per_s: mk,
            queue_mrays_per_s: q,
            ratio: mk / q,
        });
    }
    Ok(out)
}

fn median(values: &[f64]) -> f64 {
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Where shadow rays aim: the point lights and the emitting spheres'
/// centres and triangles' centroids.
fn light_points(scene: &Scene) -> Vec<Vec3> {
    let emits = |m: u32| scene.materials[m as usize].physical.emission != glam::DVec3::ZERO;
    let mut points: Vec<Vec3> = scene.lights.iter().map(|l| l.position.as_vec3()).collect();
    points.extend(
        scene
            .spheres
            .iter()
            .filter(|s| emits(s.material))
            .map(|s| s.center.as_vec3()),
    );
    points.extend(
        scene
            .triangles
            .iter()
            .filter(|t| emits(t.material))
            .map(|t| ((t.vertices[0] + t.vertices[1] + t.vertices[2]) / 3.0).as_vec3()),
    );
    points
}

/// The queue: for each pixel a camera ray through a random point of it,
/// then at each hit, up to `max_depth` hits, a shadow ray toward a random
/// light point and a bounce in a cosine-distributed direction about the
/// geometric normal (facing the ray), as the path tracer's diffuse lobe.
fn path_queue(scene: &Scene, tree: &crate::kdtree::KdTree, extent: f32) -> Vec<RayQuery> {
    let prims = Primitives::from_scene(scene);
    let lights = light_points(scene);
    let basis = scene.camera.basis();
    let (w, h) = (scene.render.width, scene.render.height);
    let aspect = w as f64 / h as f64;
    // Off the surface by a share of the scene's size, as the kernel's spawn offset.
    let offset = (extent * 1e-4).max(1e-6);
    let mut rng = SplitMix64::new(7);
    let mut queue = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let u = (x as f64 + rng.next_f64()) / w as f64;
            let v = (y as f64 + rng.next_f64()) / h as f64;
            let dir = basis.forward
                + (2.0 * u - 1.0) * basis.tan_half_vfov * aspect * basis.right
                + (1.0 - 2.0 * v) * basis.tan_half_vfov * basis.up;
            let mut ray = Ray {
                origin: basis.position.as_vec3(),
                dir: dir.as_vec3().normalize(),
            };
            for _ in 0..scene.render.max_depth {
                queue.push(RayQuery {
                    ray,
                    t_limit: f32::MAX,
                    any_hit: false,
                });
                let Some(hit) = closest_hit(tree, &prims, &ray, f32::MAX) else {
                    break;
                };
                let p = ray.origin + hit.t * ray.dir;
                let mut n = normal_at(&prims, hit.object, p);
                if n.dot(ray.dir) > 0.0 {
                    n = -n;
                }
                let origin = p + offset * n;
                if !lights.is_empty() {
                    let target =
                        lights[(rng.next_f64() * lights.len() as f64) as usize % lights.len()];
                    let to = target - origin;
                    let d = to.length();
                    if d > 0.0 {
                        let shadow = Ray {
                            origin,
                            dir: to / d,
                        };
                        queue.push(RayQuery {
                            ray: shadow,
                            t_limit: d * 0.999,
                            any_hit: true,
                        });
                    }
                }
                ray = Ray {
                    origin,
                    dir: cosine_about(n, &mut rng),
                };
            }
        }
    }
    queue
}

/// The geometric normal of object `id` at `p` (not normalised for facing).
fn normal_at(prims: &Primitives, id: u32, p: Vec3) -> Vec3 {
    match prims.spheres.get(id as usize) {
        Some(s) => (p - s.center).normalize_or_zero(),
        None => prims.triangles[id as usize - prims.spheres.len()].normal(),
    }
}

/// A direction about unit `n` with density cos(theta) / pi.
fn cosine_about(n: Vec3, rng: &mut SplitMix64) -> Vec3 {
    let (r1, r2) = (rng.next_f64() as f32, rng.next_f64() as f32);
    let (r, phi) = (r1.sqrt(), std::f32::consts::TAU * r2);
    let (t, b) = n.any_orthonormal_pair();
    (r * phi.cos() * t + r * phi.sin() * b + (1.0_f32 - r1).max(0.0).sqrt() * n).normalize()
}
