//! The CPU mirror of shaders/traverse.wgsl and traverse_short_stack.wgsl:
//! kd-restart with push-down (Foley & Sugerman 2005; Horn et al. 2007),
//! plain or with a short stack (Horn, Sugerman, Houston, Hanrahan 2007),
//! stackless walks over the flattened tree; plus the brute-force loops they
//! are tested against. The steps they share with the rope walk are in
//! [`super::walk_step`].
//!
//! The walk keeps the ray segment [t_min, t_max] still to search. From the
//! restart node it descends to the leaf the segment enters first, tests that
//! leaf's objects, keeps the nearest hit found so far, and returns it once it
//! lies before the leaf's exit (no later leaf can hold a nearer one);
//! otherwise it moves t_min to the leaf's exit and descends again. The
//! restart node is pushed down while the descent never had to choose between
//! two children, so restarts skip the part of the tree the rest of the ray
//! cannot leave. No stack, no per-ray arrays.
//!
//! The short stack: where the descent crosses both children of a node, it
//! also remembers the far child and the segment's end there, in a stack of
//! [`SHORT_STACK_DEPTH`] entries that drops its oldest entry when full.
//! After a leaf the walk resumes from the top entry; when the stack is empty
//! (never filled, or emptied after dropping entries) it restarts from the
//! restart node, with push-down, exactly as the plain walk does; the plain
//! walk is the short stack of depth 0. An entry needs no start: the far
//! child's segment starts where the near child's last leaf ends, the `t_min`
//! the walk has when it pops. A far child is remembered only when its
//! segment is not empty (`t_split < t_max`), the one the plain walk would
//! visit; so both see the same leaves with the same intervals and return
//! the same hit.
//!
//! The short-stack shader runs these steps in another loop shape: it leaves
//! a leaf without objects inside its descent loop, so that llvmpipe runs the
//! leaf loop only for leaves with objects (docs/design.md, "Short stack").
//! The leaves, intervals, hits and counted costs are these, which the
//! ray-query tests compare.

use crate::geometry::{Primitives, Ray};

use super::build::KdTree;
use super::walk_observer::{WalkEvent, WalkObserver};
use super::walk_step::{max_restarts, observed_descent_step, scene_segment, test_leaf, walk_done};
pub use super::walk_step::{Hit, WalkCost, WalkQuery};

/// Entries of the short stack. The shader keeps them in named variables
/// (lavapipe keeps private arrays in memory), and reads this value from the
/// host's contract (`gpu::bindings`). 3, the depth of the earlier
/// short-stack experiment (docs/design.md); the walk is correct for any
/// depth >= 1.
pub const SHORT_STACK_DEPTH: usize = 3;

/// Nearest hit with 0 < t <= t_limit over the tree, by the plain restart walk.
pub fn closest_hit(tree: &KdTree, prims: &Primitives, ray: &Ray, t_limit: f32) -> Option<Hit> {
    let query = WalkQuery {
        ray,
        t_limit,
        any: false,
    };
    walk_counted(tree, prims, query, 0).0
}

/// Whether anything is hit with 0 < t < t_limit (shadow rays), by the plain
/// restart walk.
pub fn any_hit(tree: &KdTree, prims: &Primitives, ray: &Ray, t_limit: f32) -> bool {
    let query = WalkQuery {
        ray,
        t_limit,
        any: true,
    };
    walk_counted(tree, prims, query, 0).0.is_some()
}

/// The nearest hit (`any` false) or any hit (`any` true), and the work the
/// walk did for it, with a short stack of `stack_depth` entries (0: the
/// plain restart walk; at most [`SHORT_STACK_DEPTH`]).
pub fn walk_counted(
    tree: &KdTree,
    prims: &Primitives,
    query: WalkQuery,
    stack_depth: usize,
) -> (Option<Hit>, WalkCost) {
    walk_observed(tree, prims, query, stack_depth, &mut ())
}

/// [`walk_counted`], reporting every step to `observer`.
pub fn walk_observed<O: WalkObserver>(
    tree: &KdTree,
    prims: &Primitives,
    query: WalkQuery,
    stack_depth: usize,
    observer: &mut O,
) -> (Option<Hit>, WalkCost) {
    assert!(
        stack_depth <= SHORT_STACK_DEPTH,
        "stack depth {stack_depth}"
    );
    let mut cost = WalkCost::default();
    let hit = walk(tree, prims, query, stack_depth, &mut cost, observer);
    (hit, cost)
}

/// A remembered far child and the end of the segment in it.
#[derive(Clone, Copy)]
struct Entry {
    node: usize,
    t_max: f32,
}

fn walk<O: WalkObserver>(
    tree: &KdTree,
    prims: &Primitives,
    query: WalkQuery,
    stack_depth: usize,
    cost: &mut WalkCost,
    observer: &mut O,
) -> Option<Hit> {
    let WalkQuery { ray, t_limit, any } = query;
    let (mut t_min, t_far) = scene_segment(tree, prims, ray, t_limit, observer)?;
    let nodes = &tree.nodes;
    let mut best: Option<Hit> = None;
    let mut restart_node = 0usize;
    // stack[0] is the top; `depth` entries are live.
    let mut stack = [Entry {
        node: 0,
        t_max: 0.0,
    }; SHORT_STACK_DEPTH];
    let mut depth = 0usize;
    for step in 0..max_restarts(nodes.len()) {
        let mut node;
        let mut t_max;
        let mut push_down;
        if depth > 0 {
            node = stack[0].node;
            t_max = stack[0].t_max;
            stack.copy_within(1.., 0);
            depth -= 1;
            push_down = false; // the rest of the ray may leave this node
            observer.event(WalkEvent::Pop { node, t_max });
        } else {
            node = restart_node;
            t_max = t_far;
            push_down = true;
            if step > 0 {
                observer.event(WalkEvent::Restart { node, t_min });
            }
        }
        cost.nodes_visited += 1;
        while !nodes[node].is_leaf() {
            let step = observed_descent_step(nodes[node], node, ray, (t_min, t_max), observer);
            if step.crosses {
                if stack_depth > 0 && step.t_split < t_max {
                    // Remember the far side; a full stack forgets its oldest.
                    stack.copy_within(..stack_depth - 1, 1);
                    stack[0] = Entry {
                        node: step.far,
                        t_max,
                    };
                    depth = (depth + 1).min(stack_depth);
                    observer.event(WalkEvent::Push {
                        node: step.far,
                        t_max,
                    });
                }
                t_max = step.t_split;
                push_down = false;
            }
            node = step.near;
            if push_down {
                restart_node = node;
            }
            cost.nodes_visited += 1;
        }
        cost.leaves_visited += 1;
        observer.event(WalkEvent::Leaf { node, t_min, t_max });
        best = test_leaf(tree, prims, node, ray, t_limit, any, best, cost, observer);
        if walk_done(best, any, t_max, t_far) {
            return best;
        }
        t_min = t_max;
    }
    debug_assert!(false, "the restart walk ran out of steps: {ray:?}");
    best
}

/// Nearest hit with 0 < t <= t_limit by testing every object (the seed's loop).
pub fn closest_hit_brute(prims: &Primitives, ray: &Ray, t_limit: f32) -> Option<Hit> {
    brute_counted(prims, ray, t_limit, false).0
}

/// Whether any object is hit with 0 < t < t_limit, by testing every object.
pub fn any_hit_brute(prims: &Primitives, ray: &Ray, t_limit: f32) -> bool {
    brute_counted(prims, ray, t_limit, true).0.is_some()
}

/// The brute-force loop (`trace_brute` in shaders/traverse.wgsl): nearest
/// hit with 0 < t <= t_limit, or (`any`) the first hit with t < t_limit;
/// and its cost, objects tested only (no node is read).
pub fn brute_counted(
    prims: &Primitives,
    ray: &Ray,
    t_limit: f32,
    any: bool,
) -> (Option<Hit>, WalkCost) {
    let mut cost = WalkCost::default();
    let mut best: Option<Hit> = None;
    for id in 0..prims.len() as u32 {
        cost.objects_tested += 1;
        if let Some(t) = prims.intersect(id, ray) {
            if any {
                if t < t_limit {
                    return (Some(Hit { object: id, t }), cost);
                }
            } else if t <= t_limit && best.is_none_or(|b| t < b.t) {
                best = Some(Hit { object: id, t });
            }
        }
    }
    (best, cost)
}
