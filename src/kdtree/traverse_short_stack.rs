//! The CPU mirror of shaders/traverse_short_stack.wgsl: kd-restart with a
//! short stack (Horn, Sugerman, Houston, Hanrahan 2007). The descent is the
//! restart walk's (`traverse`); where it crosses both children of a node it
//! also remembers the far child and the segment's end there, in a stack of
//! `SHORT_STACK_DEPTH` entries that drops its oldest entry when full. After
//! a leaf the walk resumes from the top entry; when the stack is empty
//! (never filled, or emptied after dropping entries) it restarts from the
//! restart node, with push-down, exactly as the restart walk does.
//!
//! The shader runs these steps in another loop shape: it leaves a leaf
//! without objects inside its descent loop, so that llvmpipe runs the leaf
//! loop only for leaves with objects (docs/design.md, "Short stack"). The
//! leaves, intervals, hits and counted costs are these, which the ray-query
//! tests compare.
//!
//! An entry needs no start: the far child's segment starts where the near
//! child's last leaf ends, which is the `t_min` the walk has when it pops.
//! A far child is remembered only when its segment is not empty
//! (`t_split < t_max`), the one the restart walk would visit; so both walks
//! see the same leaves with the same intervals and return the same hit.

use crate::geometry::{Primitives, Ray, PARALLEL_EPSILON};

use super::traverse::{max_restarts, test_leaf, Hit, WalkCost};
use super::KdTree;

/// Entries of the short stack. The shader keeps them in named variables
/// (lavapipe keeps private arrays in memory). 3, the depth of the earlier
/// short-stack experiment (docs/design.md); the walk is correct for any
/// depth >= 1.
pub const SHORT_STACK_DEPTH: usize = 3;

/// Nearest hit with 0 < t <= t_limit, by the short-stack walk.
pub fn closest_hit(tree: &KdTree, prims: &Primitives, ray: &Ray, t_limit: f32) -> Option<Hit> {
    walk(tree, prims, ray, t_limit, false, &mut WalkCost::default())
}

/// Whether anything is hit with 0 < t < t_limit, by the short-stack walk.
pub fn any_hit(tree: &KdTree, prims: &Primitives, ray: &Ray, t_limit: f32) -> bool {
    walk(tree, prims, ray, t_limit, true, &mut WalkCost::default()).is_some()
}

/// The nearest hit (`any` false) or any hit (`any` true) by the short-stack
/// walk, and the work it did.
pub fn walk_counted(
    tree: &KdTree,
    prims: &Primitives,
    ray: &Ray,
    t_limit: f32,
    any: bool,
) -> (Option<Hit>, WalkCost) {
    let mut cost = WalkCost::default();
    let hit = walk(tree, prims, ray, t_limit, any, &mut cost);
    (hit, cost)
}

/// A remembered far child and the end of the segment in it.
#[derive(Clone, Copy)]
struct Entry {
    node: usize,
    t_max: f32,
}

fn walk(
    tree: &KdTree,
    prims: &Primitives,
    ray: &Ray,
    t_limit: f32,
    any: bool,
    cost: &mut WalkCost,
) -> Option<Hit> {
    if prims.is_empty() {
        return None;
    }
    let (t_enter, t_exit) = tree.bounds.ray_interval(ray)?;
    let mut t_min = t_enter.max(0.0);
    let t_far = t_exit.min(t_limit);
    if t_min > t_far {
        return None;
    }
    let nodes = &tree.nodes;
    let mut best: Option<Hit> = None;
    let mut restart_node = 0usize;
    // stack[0] is the top; `depth` entries are live.
    let mut stack = [Entry {
        node: 0,
        t_max: 0.0,
    }; SHORT_STACK_DEPTH];
    let mut depth = 0usize;
    // Every leaf's interval is non-empty, as in the restart walk, so each
    // step moves t_min past one more plane: node_count + 1 steps suffice.
    for _ in 0..max_restarts(nodes.len()) {
        let mut node;
        let mut t_max;
        let mut push_down;
        if depth > 0 {
            node = stack[0].node;
            t_max = stack[0].t_max;
            stack.copy_within(1.., 0);
            depth -= 1;
            push_down = false; // the rest of the ray may leave this node
        } else {
            node = restart_node;
            t_max = t_far;
            push_down = true;
        }
        cost.nodes_visited += 1;
        while !nodes[node].is_leaf() {
            let n = nodes[node];
            let a = n.kind as usize;
            let (o, d) = (ray.origin[a], ray.dir[a]);
            let left = node + 1;
            let right = n.index as usize;
            // Parallel rays stay on the origin's side; in the plane, below.
            let mut go_below = o <= n.split;
            if d.abs() >= PARALLEL_EPSILON {
                let below_first = o < n.split || (o == n.split && d < 0.0);
                let t_split = (n.split - o) / d;
                if t_split > t_max || t_split <= 0.0 {
                    go_below = below_first;
                } else if t_split <= t_min {
                    go_below = !below_first;
                } else {
                    go_below = below_first;
                    if t_split < t_max {
                        // Remember the far side; a full stack forgets its oldest.
                        stack.copy_within(..SHORT_STACK_DEPTH - 1, 1);
                        stack[0] = Entry {
                            node: if below_first { right } else { left },
                            t_max,
                        };
                        depth = (depth + 1).min(SHORT_STACK_DEPTH);
                    }
                    t_max = t_split;
                    push_down = false;
                }
            }
            node = if go_below { left } else { right };
            if push_down {
                restart_node = node;
            }
            cost.nodes_visited += 1;
        }
        cost.leaves_visited += 1;
        best = test_leaf(tree, prims, node, ray, t_limit, any, best, cost);
        if any && best.is_some() {
            return best;
        }
        // Every leaf still to visit lies beyond t_max.
        if best.is_some_and(|hit| hit.t <= t_max) || t_max >= t_far {
            return best;
        }
        t_min = t_max;
    }
    debug_assert!(false, "the short-stack walk ran out of steps: {ray:?}");
    best
}
