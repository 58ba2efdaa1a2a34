//! Property tests of the k-d tree: the CPU mirrors of the shader's
//! stackless walks (every `Traversal`: restart, ropes, short stack) agree
//! with brute force, the flat layout is what the kernel assumes, and the
//! thread count does not change the tree. The properties are written once,
//! here (`check_closest`, `check_any`, `check_flat_layout`,
//! `threads_do_not_change_the_tree`), and run over two families of cases:
//! [`walks`] (random scenes and rays shared with the GPU query tests, and
//! the numerically awkward rays) and [`build`] (scenes that stress the
//! build's clipping, with every build strategy). Each family's proptest
//! seeds are replayed from the .proptest-regressions file beside it.

#[path = "../common/mod.rs"]
mod common;

mod alpha;
mod build;
mod instances;
mod walks;

use kdray_core::geometry::{Primitives, Ray, T_INFINITY};
use kdray_core::kdtree::traverse::WalkCost;
use kdray_core::kdtree::traverse::{any_hit_brute, closest_hit_brute, Hit};
use kdray_core::kdtree::{
    build_primitives, BuildStrategy, KdTree, Ropes, Traversal, WalkEvent, WalkQuery, WalkScene,
};
use proptest::prelude::*;

/// A tree and its ropes: what every walk needs.
struct Walks {
    tree: KdTree,
    ropes: Ropes,
}

impl Walks {
    fn new(tree: KdTree) -> Self {
        let ropes = Ropes::build(&tree);
        Walks { tree, ropes }
    }

    fn closest_hit(
        &self,
        walk: Traversal,
        prims: &Primitives,
        ray: &Ray,
        t_limit: f32,
    ) -> Option<Hit> {
        walk.closest_hit(self.scene(prims), ray, t_limit)
    }

    fn any_hit(&self, walk: Traversal, prims: &Primitives, ray: &Ray, t_limit: f32) -> bool {
        walk.any_hit(self.scene(prims), ray, t_limit)
    }

    fn scene<'a>(&'a self, prims: &'a Primitives) -> WalkScene<'a> {
        WalkScene {
            tree: &self.tree,
            ropes: &self.ropes,
            prims,
        }
    }
}

/// Every walk's nearest hit against brute force. The walks also agree with
/// each other exactly (same object, same t): they visit the same leaves with
/// the same intervals (see `kdray_core::kdtree::traversal`).
fn check_closest(walks: &Walks, prims: &Primitives, ray: &Ray) -> Result<(), TestCaseError> {
    let brute = closest_hit_brute(prims, ray, T_INFINITY);
    let restart = walks.closest_hit(Traversal::Restart, prims, ray, T_INFINITY);
    for walk in Traversal::ALL {
        let kd = walks.closest_hit(walk, prims, ray, T_INFINITY);
        match (kd, brute) {
            (None, None) => {}
            (Some(k), Some(b)) => {
                let tol = 1e-4 * b.t.max(1.0);
                prop_assert!(
                    (k.t - b.t).abs() <= tol,
                    "{}: t differs: kd {:?} brute {:?} ray {:?}",
                    walk,
                    k,
                    b,
                    ray
                );
                // A different object is fine only for a tie (coincident objects).
            }
            (k, b) => prop_assert!(false, "{}: kd {:?} brute {:?} ray {:?}", walk, k, b, ray),
        }
        check_observed(walks, walk, prims, ray)?;
        prop_assert_eq!(
            kd,
            restart,
            "{} differs from the restart walk, ray {:?}",
            walk,
            ray
        );
    }
    Ok(())
}

/// A walk that reports its steps returns the hit and cost it returns
/// unobserved, and its events account for that cost: a `Node` or `Leaf`
/// per node read, a `Leaf` per leaf, a `Tested` per object test. The leaves
/// it tests (all but the rope walk's skipped ones) follow each other front
/// to back without a gap: each starts where the one before ends, the first
/// where the segment starts.
fn check_observed(
    walks: &Walks,
    walk: Traversal,
    prims: &Primitives,
    ray: &Ray,
) -> Result<(), TestCaseError> {
    let query = WalkQuery {
        ray,
        t_limit: T_INFINITY,
        any: false,
    };
    let plain = walk.walk_counted(walks.scene(prims), query);
    let mut events = Vec::new();
    let observed = walk.walk_observed(walks.scene(prims), query, &mut events);
    prop_assert_eq!(observed, plain, "{}: observing changed the walk", walk);
    let mut counted = WalkCost::default();
    let mut tested: Vec<(f32, f32)> = Vec::new();
    let mut segment_start = None;
    for e in &events {
        match *e {
            WalkEvent::Segment { t_min, .. } => segment_start = Some(t_min),
            WalkEvent::Node { .. } => counted.nodes_visited += 1,
            WalkEvent::Leaf { t_min, t_max, .. } => {
                counted.nodes_visited += 1;
                counted.leaves_visited += 1;
                tested.push((t_min, t_max));
            }
            WalkEvent::SkippedLeaf { .. } => {
                tested.pop();
            }
            WalkEvent::Tested { .. } => counted.objects_tested += 1,
            _ => {}
        }
    }
    prop_assert_eq!(counted, plain.1, "{}: events {:?}", walk, events);
    let mut expected_start = segment_start;
    for &(t_min, t_max) in &tested {
        prop_assert_eq!(Some(t_min), expected_start, "{}: events {:?}", walk, events);
        expected_start = Some(t_max);
    }
    Ok(())
}

/// Every walk's any-hit answer on the segment [0, length] against brute force.
fn check_any(
    walks: &Walks,
    prims: &Primitives,
    ray: &Ray,
    length: f32,
) -> Result<(), TestCaseError> {
    let brute = any_hit_brute(prims, ray, length);
    for walk in Traversal::ALL {
        prop_assert_eq!(
            walks.any_hit(walk, prims, ray, length),
            brute,
            "{}: ray {:?} length {}",
            walk,
            ray,
            length
        );
    }
    Ok(())
}

/// The flat layout the kernel relies on for bounds and termination
/// (shaders/traverse.wgsl; naga's forced loop bounds are off, see
/// `gpu::shaders::trace_module`): the root at 0; an interior node's
/// children after it (below at i + 1, above past the whole below subtree),
/// so a descent only moves forward; every node reached once; leaf ranges
/// inside `leaf_objects`, each leaf's ids ascending, distinct and naming
/// real objects.
fn check_flat_layout(tree: &KdTree, object_count: usize) -> Result<(), TestCaseError> {
    let error = common::strategies::flat_layout_error(tree, object_count);
    prop_assert!(error.is_none(), "{}", error.unwrap_or_default());
    Ok(())
}

/// The tree does not depend on how many threads build it (subtrees built
/// apart are appended in single-thread order), on scenes big enough for the
/// parallel path: over boxes, and over primitives with clipping.
#[test]
fn threads_do_not_change_the_tree() {
    threads_do_not_change_the_tree_over_boxes();
    threads_do_not_change_the_tree_with_clipping();
}

/// Over the boxes of random spheres and of a mixed scene.
fn threads_do_not_change_the_tree_over_boxes() {
    use kdray_core::random_scene::{random_scene, RandomSceneSpec, SceneKind};
    for (kind, count) in [(SceneKind::Spheres, 20_000), (SceneKind::Mixed, 9_000)] {
        let scene = random_scene(&RandomSceneSpec {
            kind,
            count,
            seed: 7,
            width: 8,
            height: 8,
        });
        let prims = Primitives::from_scene(&scene);
        let bounds: Vec<_> = (0..prims.len() as u32).map(|id| prims.bounds(id)).collect();
        let params = kdray_core::kdtree::BuildParams::for_object_count(bounds.len());
        let serial = kdray_core::kdtree::build_with_threads(&bounds, params, 1);
        assert!(serial.nodes.len() > 1000, "{kind:?}: a deep tree");
        for threads in [2, 3, 8] {
            let parallel = kdray_core::kdtree::build_with_threads(&bounds, params, threads);
            assert!(
                parallel == serial,
                "{kind:?}: {threads} threads built another tree"
            );
        }
    }
}

/// With clipping: the gear scene and a larger one (subtrees of 4,096
/// objects or more go to threads), mixed spheres and triangles, every
/// strategy.
fn threads_do_not_change_the_tree_with_clipping() {
    use kdray_core::random_scene::{random_scene, RandomSceneSpec, SceneKind};
    for (kind, count) in [
        (SceneKind::Gears, 4_578),
        (SceneKind::Gears, 8_000),
        (SceneKind::Mixed, 9_000),
    ] {
        let scene = random_scene(&RandomSceneSpec::new(kind, count));
        let prims = Primitives::from_scene(&scene);
        for strategy in BuildStrategy::ALL {
            let params = build::params(&prims, strategy, 40.0);
            let serial = build_primitives(&prims, params, 1);
            assert!(serial.nodes.len() > 1000, "{kind:?} {count}: a deep tree");
            for threads in [2, 3, 8] {
                let parallel = build_primitives(&prims, params, threads);
                assert!(
                    parallel == serial,
                    "{kind:?} {count} {strategy}: {threads} threads built another tree"
                );
            }
        }
    }
}
