//! Random scenes, rays and trees for the property tests of the k-d walks:
//! shared by the CPU mirror's tests (crates/kdray-core/tests/kdtree_props/) and the GPU
//! kernel's (tests/gpu/gpu_ray_queries.rs), so both meet the same cases: tiny,
//! huge, coincident and axis-aligned objects; random, axis-parallel and
//! plane-parallel rays; origins on split planes.
#![allow(dead_code)]

use glam::Vec3;
use kdray_core::geometry::{Primitives, Ray, SphereF32, TriangleF32};
use kdray_core::kdtree::KdTree;
use proptest::prelude::*;

pub fn vec3(range: f32) -> impl Strategy<Value = Vec3> {
    (-range..range, -range..range, -range..range).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

/// Object sizes spanning tiny to huge relative to the 10-unit scene.
pub fn size() -> impl Strategy<Value = f32> {
    prop_oneof![4 => 0.05f32..1.0, 1 => 1e-4f32..1e-2, 1 => 3.0f32..30.0]
}

#[derive(Debug, Clone)]
pub enum Object {
    Sphere(SphereF32),
    Triangle(TriangleF32),
}

pub fn object() -> impl Strategy<Value = Object> {
    prop_oneof![
        (vec3(10.0), size()).prop_map(|(c, r)| Object::Sphere(SphereF32 {
            center: c,
            radius: r
        })),
        (vec3(10.0), size(), vec3(1.0), vec3(1.0)).prop_map(|(c, s, a, b)| Object::Triangle(
            TriangleF32 {
                v: [c, c + a * s, c + b * s],
            }
        )),
        // Axis-aligned triangles: they lie in, and bound, candidate split planes.
        (vec3(10.0), size(), 0usize..3).prop_map(|(c, s, axis)| {
            let (u, v) = (Vec3::AXES[(axis + 1) % 3], Vec3::AXES[(axis + 2) % 3]);
            Object::Triangle(TriangleF32 {
                v: [c, c + u * s, c + v * s],
            })
        }),
    ]
}

pub fn scene() -> impl Strategy<Value = Primitives> {
    scene_of(object(), 1..120, 4)
}

/// Scenes of `objects` (a count in `count`), the first few (fewer than
/// `max_copies`) repeated exactly: coincident objects.
pub fn scene_of(
    object: impl Strategy<Value = Object>,
    count: std::ops::Range<usize>,
    max_copies: usize,
) -> impl Strategy<Value = Primitives> {
    (prop::collection::vec(object, count), 0..max_copies).prop_map(|(objects, copies)| {
        let mut prims = Primitives::default();
        let repeated = objects.iter().take(copies).cloned().collect::<Vec<_>>();
        for o in objects.into_iter().chain(repeated) {
            match o {
                Object::Sphere(s) => prims.spheres.push(s),
                Object::Triangle(t) => prims.triangles.push(t),
            }
        }
        prims
    })
}

/// A random unit vector.
pub fn unit() -> impl Strategy<Value = Vec3> {
    vec3(1.0)
        .prop_filter("non-zero", |v| v.length() > 1e-3)
        .prop_map(|v| v.normalize())
}

/// Directions: random, along an axis, parallel to an axis plane.
pub fn direction() -> impl Strategy<Value = Vec3> {
    prop_oneof![
        3 => unit(),
        1 => (0usize..3, any::<bool>()).prop_map(|(a, neg)| if neg { -Vec3::AXES[a] } else { Vec3::AXES[a] }),
        // Parallel to one axis plane but not to an axis.
        1 => (0usize..3, -1.0f32..1.0, -1.0f32..1.0).prop_filter("non-zero", |(_, x, y)| x.abs() + y.abs() > 1e-3).prop_map(|(a, x, y)| {
            let mut v = Vec3::ZERO;
            v[(a + 1) % 3] = x;
            v[(a + 2) % 3] = y;
            v.normalize()
        }),
    ]
}

/// Origins anywhere, or exactly on one of the tree's split planes.
pub fn ray_for(tree: &KdTree, origin: Vec3, dir: Vec3, on_plane: Option<usize>) -> Ray {
    let mut origin = origin;
    if let Some(pick) = on_plane {
        let inner: Vec<_> = tree.nodes.iter().filter(|n| !n.is_leaf()).collect();
        if !inner.is_empty() {
            let n = inner[pick % inner.len()];
            origin[n.kind as usize] = n.split;
        }
    }
    Ray { origin, dir }
}

/// Traversal costs for the build: 1 splits small scenes deeply (many planes
/// for rays to start on and run along), 40 is the default.
pub fn traversal_cost() -> impl Strategy<Value = f32> {
    prop_oneof![Just(1.0f32), Just(15.0), Just(40.0)]
}

pub fn tree_for(prims: &Primitives, traversal_cost: f32) -> KdTree {
    let bounds: Vec<_> = (0..prims.len() as u32).map(|id| prims.bounds(id)).collect();
    let params = kdray_core::kdtree::BuildParams {
        traversal_cost,
        ..kdray_core::kdtree::BuildParams::for_object_count(bounds.len())
    };
    kdray_core::kdtree::build(&bounds, params)
}

/// What is wrong with the tree's flat layout, as the kernel reads it, or
/// `None`: every inner node's below child right after it and its above
/// child later, every node reached exactly once, leaf ranges in bounds,
/// each leaf's ids ascending, distinct and below `object_count`.
pub fn flat_layout_error(tree: &KdTree, object_count: usize) -> Option<String> {
    let n = tree.nodes.len();
    if n == 0 {
        return Some("no nodes".into());
    }
    let mut reached = vec![0u32; n];
    let mut pending = vec![0usize];
    while let Some(i) = pending.pop() {
        reached[i] += 1;
        let node = tree.nodes[i];
        if node.is_leaf() {
            let end = node.index as usize + node.count as usize;
            if end > tree.leaf_objects.len() {
                return Some(format!("leaf {i} ends at {end}"));
            }
            let ids = &tree.leaf_objects[node.index as usize..end];
            if !ids.windows(2).all(|w| w[0] < w[1]) {
                return Some(format!("leaf {i} ids {ids:?}"));
            }
            if let Some(id) = ids.iter().find(|&&id| id as usize >= object_count) {
                return Some(format!("leaf {i} names object {id}"));
            }
        } else {
            if node.kind >= 3 || !node.split.is_finite() {
                return Some(format!(
                    "node {i}: kind {}, split {}",
                    node.kind, node.split
                ));
            }
            let above = node.index as usize;
            if !(i + 1 < above && above < n) {
                return Some(format!("node {i}: children {} and {above} of {n}", i + 1));
            }
            pending.push(i + 1);
            pending.push(above);
        }
    }
    reached
        .iter()
        .position(|&r| r != 1)
        .map(|i| format!("node {i} reached {} times", reached[i]))
}
