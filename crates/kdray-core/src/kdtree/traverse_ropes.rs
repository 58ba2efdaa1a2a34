//! The CPU mirror of shaders/traverse_ropes.wgsl: the rope walk (Popov,
//! Günther, Seidel, Slusallek 2007). It descends from the root to the leaf
//! the segment enters first; after each leaf it leaves through the face the
//! ray reaches first and descends from that face's rope to the next leaf.
//!
//! Everything is a comparison of `t` values or of the origin with a plane,
//! made by the steps every walk shares (`walk_step`), so that the rope and
//! restart walks see the same leaves with the same intervals and return the
//! same hit:
//! - the descent classifies planes by the ray's `t`: one crossed at or
//!   before `t_min` (`0 < t_split <= t_min`) is behind, the ray is on its
//!   far side; any other plane is ahead or never crossed, the ray is on its
//!   first side. No entry point is computed.
//! - a leaf's exit is the smallest `t` at which the ray meets one of its
//!   faces ahead, computed as the restart walk computes `t_split`
//!   (`(plane - o) / d`); faces on the scene's boundary lie at infinity
//!   (`LeafRopes::faces`), so the ray leaves through them at `t_far`, as in
//!   the restart walk. Only the face it leaves through needs its rope.
//! - at an edge or a corner, two or three faces are met at the same `t`.
//!   The walk takes the first, and the rope's node may then lie on the near
//!   side of a plane the ray crossed at that same `t` (the face's other
//!   edge). The descent cannot see that plane (it is above the rope's node),
//!   so it reaches a leaf the ray never spends time in: one of its faces
//!   ahead is met at or before `t_min`. Such a leaf is skipped, and the walk
//!   descends again from the root, which finds the right one. Rounding can
//!   make faces meet at the same `t` too, and is caught the same way.
//!
//! Hits count as in the restart walk: the nearest over all visited leaves,
//! returned once it lies before the current leaf's exit.

use crate::geometry::{Ray, PARALLEL_EPSILON};

use super::nodes::{KdNode, LeafRopes};
use super::walk_observer::{WalkEvent, WalkObserver};
use super::walk_step::{
    max_restarts, observed_descent_step, scene_segment, test_leaf, walk_done, Hit, WalkCost,
    WalkQuery, WalkScene,
};

/// The nearest hit (`any` false) or any hit (`any` true) by the rope walk,
/// and the work it did (`Traversal::closest_hit` and `any_hit` call it).
pub fn walk_counted(scene: WalkScene, query: WalkQuery) -> (Option<Hit>, WalkCost) {
    walk_observed(scene, query, &mut ())
}

/// [`walk_counted`], reporting every step to `observer`.
pub fn walk_observed<O: WalkObserver>(
    scene: WalkScene,
    query: WalkQuery,
    observer: &mut O,
) -> (Option<Hit>, WalkCost) {
    let mut cost = WalkCost::default();
    let hit = walk(scene, query, &mut cost, observer);
    (hit, cost)
}

/// From `node` down to the leaf the ray is in just after `t_min`, counting
/// the nodes read (`node` and the leaf included) and the leaf. Only the side
/// of each plane matters: one crossed at or before `t_min` is behind the
/// ray, any other ahead (`t_far` bounds nothing, the segment ends there).
fn descend<O: WalkObserver>(
    nodes: &[KdNode],
    mut node: usize,
    ray: &Ray,
    (t_min, t_far): (f32, f32),
    cost: &mut WalkCost,
    observer: &mut O,
) -> usize {
    cost.nodes_visited += 1;
    while !nodes[node].is_leaf() {
        node = observed_descent_step(nodes[node], node, ray, (t_min, t_far), observer).near;
        cost.nodes_visited += 1;
    }
    cost.leaves_visited += 1;
    node
}

/// The first face ahead so far: where the ray meets it, and which face
/// (`None`: none before `t_far`).
#[derive(Clone, Copy)]
struct RopeExit {
    t: f32,
    face: Option<usize>,
}

/// `exit`, or `leaf`'s face ahead on axis `a` if the ray meets it sooner.
/// A face on the scene's boundary lies at infinity, so it never is.
fn rope_exit_on_axis(leaf: &LeafRopes, a: usize, ray: &Ray, exit: RopeExit) -> RopeExit {
    let d = ray.dir[a];
    if d.abs() >= PARALLEL_EPSILON {
        let face = 2 * a + usize::from(d > 0.0);
        let t_face = (leaf.faces[face] - ray.origin[a]) / d;
        if t_face < exit.t {
            return RopeExit {
                t: t_face,
                face: Some(face),
            };
        }
    }
    exit
}

fn walk<O: WalkObserver>(
    scene: WalkScene,
    query: WalkQuery,
    cost: &mut WalkCost,
    observer: &mut O,
) -> Option<Hit> {
    let WalkScene { tree, ropes, prims } = scene;
    let WalkQuery { ray, t_limit, any } = query;
    let (mut t_min, t_far) = scene_segment(tree, prims, ray, t_limit, observer)?;
    let nodes = &tree.nodes;
    let mut best: Option<Hit> = None;
    // Where the next descent starts: the root, or the rope of the face the
    // ray left the last leaf through.
    let mut start = 0usize;
    let mut from_root = true;
    // Each leaf tested moves t_min past one more plane and each rope leaf
    // skipped is followed by a tested one, so node_count + 1 steps suffice
    // (see docs/design.md).
    for _ in 0..max_restarts(nodes.len()) {
        let node = descend(nodes, start, ray, (t_min, t_far), cost, observer);
        let leaf = ropes.leaf(node);
        // The exit: the first face ahead, else t_far.
        let mut exit = RopeExit {
            t: t_far,
            face: None,
        };
        for a in 0..3 {
            exit = rope_exit_on_axis(leaf, a, ray, exit);
        }
        let t_max = exit.t;
        observer.event(WalkEvent::Leaf { node, t_min, t_max });
        // A leaf the ray spends no time in: the rope led to the near side of
        // a plane crossed at t_min (an edge or a corner). Start over from the root.
        if t_max <= t_min && !from_root {
            start = 0;
            from_root = true;
            observer.event(WalkEvent::SkippedLeaf { node });
            observer.event(WalkEvent::Restart { node: 0, t_min });
            continue;
        }
        best = test_leaf(tree, prims, node, ray, t_limit, any, best, cost, observer);
        if walk_done(best, any, t_max, t_far) {
            return best;
        }
        // t_max < t_far, so a face was met: its rope is the one the walk needs.
        let Some(face) = exit.face else {
            debug_assert!(false, "no exit face before t_far: {ray:?}");
            return best;
        };
        t_min = t_max;
        start = leaf.ropes[face] as usize;
        from_root = false;
        observer.event(WalkEvent::Rope {
            face,
            node: start,
            t_min,
        });
    }
    debug_assert!(false, "the rope walk ran out of steps: {ray:?}");
    best
}
