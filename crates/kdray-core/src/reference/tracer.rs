//! The tracer: the scene prepared for CPU tracing, its searches (brute
//! force or a k-d walk, each ray recorded while recording) and the camera's
//! rays, pixels and image.

use std::cell::{Cell, RefCell};

use glam::Vec3;

use crate::geometry::{Primitives, Ray, T_INFINITY};
use crate::kdtree::traverse::{brute_counted, Hit, WalkCost, SHORT_STACK_DEPTH};
use crate::kdtree::{traverse, KdTree, Ropes, Traversal, WalkObserver, WalkQuery, WalkScene};
use crate::layout::GpuTriangleNormals;
use crate::scene::texture::pixel_spread_angle;
use crate::scene::Scene;

use super::light_choice::AimedLight;
use super::rays::{RayKind, TracedRay};

/// How the tracer finds hits: brute force, or a k-d walk over a tree
/// built over the tracer's objects.
enum Search {
    Brute,
    Tree {
        tree: KdTree,
        /// Built for the rope walk only.
        ropes: Option<Ropes>,
        traversal: Traversal,
    },
}

/// The scene prepared for CPU tracing.
pub struct ReferenceTracer<'a> {
    pub(super) scene: &'a Scene,
    pub(super) prims: Primitives,
    /// Per triangle, its vertex normals as the kernel decodes them (None: flat).
    pub(super) normals: Vec<Option<[Vec3; 3]>>,
    search: Search,
    /// While recording: the rays traced so far.
    log: RefCell<Option<Vec<TracedRay>>>,
    /// The light the shadow rays traced now aim at.
    pub(super) aim: Cell<Option<AimedLight>>,
    /// Whether some material transmits: the kernel's GLASS variant.
    pub(super) glass: bool,
    forward: Vec3,
    right: Vec3,
    up: Vec3,
    tan_half_vfov: f32,
    aspect: f32,
    /// The spread angle of a pixel's ray cone.
    pub(super) pixel_spread: f32,
}

impl<'a> ReferenceTracer<'a> {
    /// `use_tree`: walk the k-d tree (built with the default parameters)
    /// with the plain restart walk (else the brute-force loop).
    pub fn new(scene: &'a Scene, use_tree: bool) -> Self {
        let prims = Primitives::from_scene(scene);
        let search = match use_tree {
            true => Search::Tree {
                tree: KdTree::for_primitives(&prims),
                ropes: None,
                traversal: Traversal::Restart,
            },
            false => Search::Brute,
        };
        Self::with_search(scene, prims, search)
    }

    /// Walks `tree` (built over `Primitives::from_scene(scene)`, objects
    /// numbered as there: spheres, then triangles) with `traversal`.
    pub fn with_tree(scene: &'a Scene, tree: KdTree, traversal: Traversal) -> Self {
        let prims = Primitives::from_scene(scene);
        let ropes = (traversal == Traversal::Ropes).then(|| Ropes::build(&tree));
        let search = Search::Tree {
            tree,
            ropes,
            traversal,
        };
        Self::with_search(scene, prims, search)
    }

    fn with_search(scene: &'a Scene, prims: Primitives, search: Search) -> Self {
        let basis = scene.camera.basis();
        let normals = scene
            .triangles
            .iter()
            .map(|t| {
                scene
                    .normals_of(t)
                    .map(|n| GpuTriangleNormals::pack(n).unpack())
            })
            .collect();
        ReferenceTracer {
            scene,
            prims,
            normals,
            search,
            log: RefCell::new(None),
            aim: Cell::new(None),
            glass: scene.materials.iter().any(|m| m.transmission as f32 > 0.0),
            forward: basis.forward.as_vec3(),
            right: basis.right.as_vec3(),
            up: basis.up.as_vec3(),
            tan_half_vfov: basis.tan_half_vfov as f32,
            aspect: (scene.render.width as f64 / scene.render.height as f64) as f32,
            pixel_spread: pixel_spread_angle(basis.tan_half_vfov as f32, scene.render.height),
        }
    }

    /// The objects, numbered as hits name them.
    pub fn primitives(&self) -> &Primitives {
        &self.prims
    }

    /// The hit `query` asks for and the work the search did, each step
    /// reported to `observer`.
    fn search<O: WalkObserver>(
        &self,
        query: WalkQuery,
        observer: &mut O,
    ) -> (Option<Hit>, WalkCost) {
        let prims = &self.prims;
        match &self.search {
            Search::Brute => brute_counted(prims, query.ray, query.t_limit, query.any),
            Search::Tree {
                tree,
                ropes: Some(ropes),
                traversal,
            } => traversal.walk_observed(WalkScene { tree, ropes, prims }, query, observer),
            Search::Tree {
                tree, traversal, ..
            } => {
                let depth = match traversal {
                    Traversal::ShortStack => SHORT_STACK_DEPTH,
                    _ => 0,
                };
                traverse::walk_observed(tree, prims, query, depth, observer)
            }
        }
    }

    /// One query of the path, recorded while recording.
    pub(super) fn query(&self, kind: RayKind, ray: &Ray, t_limit: f32, any: bool) -> Option<Hit> {
        let query = WalkQuery { ray, t_limit, any };
        let mut log = self.log.borrow_mut();
        let Some(log) = log.as_mut() else {
            return self.search(query, &mut ()).0;
        };
        let mut walk = Vec::new();
        let (hit, cost) = self.search(query, &mut walk);
        log.push(TracedRay {
            kind,
            ray: *ray,
            t_limit,
            any,
            hit,
            cost,
            walk,
            light: self.aim.get().filter(|_| kind == RayKind::Shadow),
        });
        hit
    }

    pub(super) fn closest(&self, ray: &Ray, kind: RayKind) -> Option<Hit> {
        self.query(kind, ray, T_INFINITY, false)
    }

    /// Every ray the path from `primary` traces, in order, with its walk.
    pub fn trace_recorded(&self, primary: Ray) -> Vec<TracedRay> {
        *self.log.borrow_mut() = Some(Vec::new());
        self.trace_whitted(primary);
        self.log.borrow_mut().take().unwrap_or_default()
    }

    pub fn camera_ray(&self, u: f32, v: f32) -> Ray {
        let h = self.tan_half_vfov;
        let dir = self.forward
            + (2.0 * u - 1.0) * h * self.aspect * self.right
            + (1.0 - 2.0 * v) * h * self.up;
        Ray {
            origin: self.scene.camera.position.as_vec3(),
            dir: dir.normalize(),
        }
    }

    /// The camera ray of Whitted sample (`sx`, `sy`) of the k x k grid in
    /// pixel (row, column): mirror of `trace_sample` in shaders/trace.wgsl.
    pub fn sample_ray(&self, row: u32, column: u32, sx: u32, sy: u32) -> Ray {
        let r = &self.scene.render;
        let inv_k = 1.0 / r.samples_per_axis() as f32;
        let u = (column as f32 + (sx as f32 + 0.5) * inv_k) / r.width as f32;
        let v = (row as f32 + (sy as f32 + 0.5) * inv_k) / r.height as f32;
        self.camera_ray(u, v)
    }

    /// The 8-bit colour of pixel (row, column), as render_tile computes it.
    pub fn pixel(&self, row: u32, column: u32) -> [u8; 3] {
        let r = &self.scene.render;
        let k = r.samples_per_axis();
        let mut sum = Vec3::ZERO;
        for sy in 0..k {
            for sx in 0..k {
                sum += self
                    .trace_whitted(self.sample_ray(row, column, sx, sy))
                    .0
                    .clamp(Vec3::ZERO, Vec3::ONE);
            }
        }
        let c = sum / (k * k) as f32;
        let q = (255.0 * c.clamp(Vec3::ZERO, Vec3::ONE) + 0.5).floor();
        [q.x as u8, q.y as u8, q.z as u8]
    }

    /// The whole image, 8-bit RGB, top row first.
    pub fn image(&self) -> Vec<u8> {
        let r = &self.scene.render;
        (0..r.height)
            .flat_map(|row| (0..r.width).flat_map(move |column| self.pixel(row, column)))
            .collect()
    }
}
