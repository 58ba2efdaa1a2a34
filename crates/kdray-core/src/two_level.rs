//! The two-level acceleration structure over instances ([`TwoLevel`]), on
//! the CPU: the SAH k-d tree built once per shape over its triangles in
//! its own space, and a top-level k-d tree over the instances' world
//! boxes. A walk ([`TwoLevel::closest_hit`], [`TwoLevel::any_hit`]) goes
//! front to back through the top tree and, at an instance, carries the ray
//! into the shape's space (by the inverse transform, its direction not
//! normalised, so that a distance t along it is the same t in the world)
//! and walks the shape's tree with any of the [`Traversal`]s. Memory grows
//! with the unique triangles plus the instances
//! ([`TwoLevel::bytes`] against [`flattened_bytes`]). The GPU kernels do not
//! walk it yet: they trace the flattened scene.

use glam::{DAffine3, DVec3, Vec3};

use crate::geometry::{Aabb, Primitives, Ray, TriangleF32, PARALLEL_EPSILON};
use crate::kdtree::{BuildParams, KdNode, KdTree, LeafRopes, Ropes, Traversal, WalkScene};
use crate::scene::{transformed_box, Scene};

/// A shape's triangles in its own space, in f32, with their tree.
#[derive(Debug, Clone)]
pub struct ShapeTree {
    pub prims: Primitives,
    pub tree: KdTree,
    pub ropes: Ropes,
}

impl ShapeTree {
    /// The tree built over `triangles` (in the shape's space) with the
    /// default SAH build.
    pub fn build(triangles: Vec<TriangleF32>) -> ShapeTree {
        let prims = Primitives {
            triangles,
            ..Primitives::default()
        };
        let tree = KdTree::build_for(&prims, BuildParams::for_primitives(&prims));
        let ropes = Ropes::build(&tree);
        ShapeTree { prims, tree, ropes }
    }

    /// The box of its triangles in its own space (min, max), in f64.
    fn bounds(&self) -> [DVec3; 2] {
        let mut b = Aabb::EMPTY;
        for t in &self.prims.triangles {
            b = b.union(t.bounds());
        }
        [b.min.as_dvec3(), b.max.as_dvec3()]
    }
}

/// An instance as the walk reads it: its shape, the transform from the
/// world into the shape's space, and its world box.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlacedInstance {
    pub shape: u32,
    pub to_shape: DAffine3,
    pub bounds: Aabb,
}

/// A hit: the instance, the triangle of its shape, and the distance along
/// the world ray.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InstanceHit {
    pub instance: u32,
    pub triangle: u32,
    pub t: f32,
}

/// Shapes, each with its tree, and the instances with the top-level tree
/// over their world boxes.
#[derive(Debug, Clone)]
pub struct TwoLevel {
    pub shapes: Vec<ShapeTree>,
    pub instances: Vec<PlacedInstance>,
    pub top: KdTree,
}

/// The relative widening of an instance's world box in f32: the shape's
/// triangles, carried into the world and rounded, stay inside it.
const BOX_SLACK: f32 = 1e-5;

impl TwoLevel {
    /// The structure over `shapes` (each tree already built) and
    /// `instances` (a shape's index and its transform from the shape's
    /// space to the world, invertible). An instance of a shape that is not
    /// there, or with a transform that cannot be inverted, is left out.
    pub fn build(shapes: Vec<ShapeTree>, instances: &[(u32, DAffine3)]) -> TwoLevel {
        let shape_bounds: Vec<[DVec3; 2]> = shapes.iter().map(ShapeTree::bounds).collect();
        let placed: Vec<PlacedInstance> = instances
            .iter()
            .filter_map(|&(shape, transform)| {
                let bounds = shape_bounds.get(shape as usize)?;
                let to_shape = transform.inverse();
                if !to_shape.is_finite() {
                    return None;
                }
                let [lo, hi] = transformed_box(&transform, bounds);
                let (lo, hi) = (lo.as_vec3(), hi.as_vec3());
                let slack = BOX_SLACK * lo.abs().max(hi.abs()).max_element().max(1e-30);
                Some(PlacedInstance {
                    shape,
                    to_shape,
                    bounds: Aabb {
                        min: lo - Vec3::splat(slack),
                        max: hi + Vec3::splat(slack),
                    },
                })
            })
            .collect();
        let boxes: Vec<Aabb> = placed.iter().map(|p| p.bounds).collect();
        let top = crate::kdtree::build(&boxes, BuildParams::for_object_count(boxes.len()));
        TwoLevel {
            shapes,
            instances: placed,
            top,
        }
    }

    /// The structure over `scene`'s shapes and instances (its other
    /// objects are not in it): each shape's triangles in its own space.
    pub fn from_scene(scene: &Scene) -> TwoLevel {
        let shapes = scene
            .shapes
            .iter()
            .map(|s| {
                let triangles = s
                    .mesh
                    .triangles
                    .iter()
                    .filter_map(|t| s.mesh.vertices(t))
                    .map(|v| TriangleF32 {
                        v: v.map(|p| p.as_vec3()),
                    })
                    .collect();
                ShapeTree::build(triangles)
            })
            .collect();
        let instances: Vec<(u32, DAffine3)> = scene
            .instances
            .iter()
            .map(|i| (i.shape, i.transform))
            .collect();
        TwoLevel::build(shapes, &instances)
    }

    /// The nearest hit with 0 < t <= `t_limit` along `ray` (in the
    /// world), each shape's tree walked by `walk`.
    pub fn closest_hit(&self, walk: Traversal, ray: &Ray, t_limit: f32) -> Option<InstanceHit> {
        self.walk(walk, ray, t_limit, false)
    }

    /// Whether anything is hit with 0 < t < `t_limit`.
    pub fn any_hit(&self, walk: Traversal, ray: &Ray, t_limit: f32) -> bool {
        self.walk(walk, ray, t_limit, true).is_some()
    }

    /// Instance `i` tested: the ray carried into its shape's space and
    /// walked through the shape's tree, up to `t_limit`.
    pub fn instance_hit(
        &self,
        walk: Traversal,
        i: u32,
        ray: &Ray,
        t_limit: f32,
        any: bool,
    ) -> Option<InstanceHit> {
        let instance = self.instances.get(i as usize)?;
        let shape = self.shapes.get(instance.shape as usize)?;
        let local = shape_ray(&instance.to_shape, ray);
        let scene = WalkScene {
            tree: &shape.tree,
            ropes: &shape.ropes,
            prims: &shape.prims,
        };
        let hit = if any {
            // The any-hit walk counts hits with t < t_limit.
            let query = crate::kdtree::WalkQuery {
                ray: &local,
                t_limit,
                any: true,
            };
            walk.walk_counted(scene, query).0
        } else {
            walk.closest_hit(scene, &local, t_limit)
        }?;
        Some(InstanceHit {
            instance: i,
            triangle: hit.object,
            t: hit.t,
        })
    }

    /// The top level's front-to-back walk with a stack: at each leaf its
    /// instances are tested up to the nearest hit so far; the walk ends at
    /// a leaf whose far end lies beyond that hit.
    fn walk(&self, walk: Traversal, ray: &Ray, t_limit: f32, any: bool) -> Option<InstanceHit> {
        if self.instances.is_empty() {
            return None;
        }
        let (t0, t1) = self.top.bounds.ray_interval(ray)?;
        let (t0, t1) = (t0.max(0.0), t1.min(t_limit));
        if t0 > t1 {
            return None;
        }
        let mut best: Option<InstanceHit> = None;
        let mut limit = t_limit;
        let mut stack: Vec<(usize, f32, f32)> = vec![(0, t0, t1)];
        while let Some((mut node, t0, t1)) = stack.pop() {
            if t0 > limit {
                continue;
            }
            let mut t1 = t1;
            loop {
                let n: &KdNode = self.top.nodes.get(node)?;
                if n.is_leaf() {
                    let first = n.index as usize;
                    let ids = self.top.leaf_objects.get(first..first + n.count as usize)?;
                    for &id in ids {
                        if let Some(hit) = self.instance_hit(walk, id, ray, limit, any) {
                            if any {
                                return Some(hit);
                            }
                            if best.is_none_or(|b| hit.t < b.t) {
                                limit = hit.t;
                                best = Some(hit);
                            }
                        }
                    }
                    break;
                }
                let axis = n.kind as usize;
                let (o, d) = (ray.origin[axis], ray.dir[axis]);
                let below = node + 1;
                let above = n.index as usize;
                if d.abs() < PARALLEL_EPSILON {
                    // Parallel to the plane: the side the origin is on (both
                    // when it lies on the plane).
                    node = if o < n.split {
                        below
                    } else if o > n.split {
                        above
                    } else {
                        stack.push((above, t0, t1));
                        below
                    };
                    continue;
                }
                let t_split = (n.split - o) / d;
                let (near, far) = if o < n.split || (o == n.split && d < 0.0) {
                    (below, above)
                } else {
                    (above, below)
                };
                // Widened by a hair, so rounding never skips a child the
                // ray reaches.
                let slack = 1e-6 * t_split.abs().max(t1.abs()).max(1.0);
                if t_split > t1 + slack || t_split < -slack {
                    node = near;
                } else if t_split < t0 - slack {
                    node = far;
                } else {
                    stack.push((far, (t_split - slack).max(t0), t1));
                    node = near;
                    t1 = (t_split + slack).min(t1);
                }
            }
            if best.is_some_and(|b| b.t <= t1) {
                break;
            }
        }
        best
    }

    /// The bytes the structure holds: each shape's f32 triangles, nodes,
    /// leaf lists and ropes, each instance's record, and the top tree.
    pub fn bytes(&self) -> usize {
        let shapes: usize = self
            .shapes
            .iter()
            .map(|s| {
                s.prims.triangles.len() * size_of::<TriangleF32>()
                    + tree_bytes(&s.tree)
                    + s.ropes.leaves.len() * size_of::<LeafRopes>()
                    + s.ropes.leaf_of_node.len() * size_of::<u32>()
            })
            .sum();
        shapes + self.instances.len() * size_of::<PlacedInstance>() + tree_bytes(&self.top)
    }
}

/// The bytes of the flattened structure: `prims` (every instance's
/// triangles in the world, in f32) and one tree over them, with its ropes.
pub fn flattened_bytes(prims: &Primitives, tree: &KdTree, ropes: &Ropes) -> usize {
    prims.triangles.len() * size_of::<TriangleF32>()
        + prims.spheres.len() * size_of::<crate::geometry::SphereF32>()
        + tree_bytes(tree)
        + ropes.leaves.len() * size_of::<LeafRopes>()
        + ropes.leaf_of_node.len() * size_of::<u32>()
}

fn tree_bytes(tree: &KdTree) -> usize {
    tree.nodes.len() * size_of::<KdNode>() + tree.leaf_objects.len() * size_of::<u32>()
}

/// `ray` carried into a shape's space by `to_shape`: its origin as a
/// point, its direction as a vector, not normalised (t is unchanged).
pub fn shape_ray(to_shape: &DAffine3, ray: &Ray) -> Ray {
    Ray {
        origin: to_shape.transform_point3(ray.origin.as_dvec3()).as_vec3(),
        dir: to_shape.transform_vector3(ray.dir.as_dvec3()).as_vec3(),
    }
}
