//! The CPU mirror of shaders/traverse.wgsl: kd-restart with push-down
//! (Foley & Sugerman 2005; Horn et al. 2007), a stackless walk over the
//! flattened tree, plus the brute-force loops it is tested against.
//!
//! The walk keeps the ray segment [t_min, t_max] still to search. From the
//! restart node it descends to the leaf the segment enters first, tests that
//! leaf's objects, keeps the nearest hit found so far, and returns it once it
//! lies before the leaf's exit (no later leaf can hold a nearer one);
//! otherwise it moves t_min to the leaf's exit and descends again. The
//! restart node is pushed down while the descent never had to choose between
//! two children, so restarts skip the part of the tree the rest of the ray
//! cannot leave. No stack, no per-ray arrays.

use crate::geometry::{Primitives, Ray, PARALLEL_EPSILON, T_INFINITY};

use super::KdTree;

/// A hit: which object and where along the ray.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hit {
    pub object: u32,
    pub t: f32,
}

/// The work one query did, counted the same way by every walk, its shader
/// and the brute-force loops (`walk_cost` in shaders/traverse.wgsl):
/// - `nodes_visited`: every k-d node whose record the walk read: the inner
///   nodes of each descent (from the root, a restart node, a popped stack
///   entry or a rope) and the leaf it ends in;
/// - `leaves_visited`: the leaves reached (a rope walk's skipped leaf
///   included), so never more than `nodes_visited`;
/// - `objects_tested`: object intersection tests (brute force: all of them,
///   or up to the first hit of an any-hit query).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize)]
pub struct WalkCost {
    pub nodes_visited: u32,
    pub leaves_visited: u32,
    pub objects_tested: u32,
}

impl WalkCost {
    /// From the kernel's three words (nodes, leaves, objects).
    pub fn from_words(words: &[u32]) -> WalkCost {
        WalkCost {
            nodes_visited: words[0],
            leaves_visited: words[1],
            objects_tested: words[2],
        }
    }

    /// What the heatmap shows: nodes visited plus objects tested.
    pub fn work(&self) -> u32 {
        self.nodes_visited.saturating_add(self.objects_tested)
    }
}

impl std::ops::AddAssign for WalkCost {
    fn add_assign(&mut self, other: WalkCost) {
        self.nodes_visited += other.nodes_visited;
        self.leaves_visited += other.leaves_visited;
        self.objects_tested += other.objects_tested;
    }
}

/// Safety net for the restart loop: each iteration moves t_min past one
/// split plane's crossing, so a valid tree never needs more than its node
/// count; this bound only stops a corrupt tree from hanging a GPU.
pub fn max_restarts(node_count: usize) -> u32 {
    node_count.min(u32::MAX as usize) as u32 + 1
}

/// Nearest hit with 0 < t <= t_limit over the tree.
pub fn closest_hit(tree: &KdTree, prims: &Primitives, ray: &Ray, t_limit: f32) -> Option<Hit> {
    walk(tree, prims, ray, t_limit, false, &mut WalkCost::default())
}

/// Whether anything is hit with 0 < t < t_limit (shadow rays).
pub fn any_hit(tree: &KdTree, prims: &Primitives, ray: &Ray, t_limit: f32) -> bool {
    walk(tree, prims, ray, t_limit, true, &mut WalkCost::default()).is_some()
}

/// The nearest hit (`any` false) or any hit (`any` true), and the work the
/// walk did for it.
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
    // The nearest hit so far, over every leaf visited: one found beyond its
    // leaf's exit (an object reaching into the next cells) may still lose to
    // one in a later leaf, so it waits until the walk has passed its t.
    let mut best: Option<Hit> = None;
    let mut restart_node = 0usize;
    for _ in 0..max_restarts(nodes.len()) {
        let mut node = restart_node;
        let mut t_max = t_far;
        let mut push_down = true;
        cost.nodes_visited += 1;
        while !nodes[node].is_leaf() {
            let n = nodes[node];
            let a = n.kind as usize;
            let (o, d) = (ray.origin[a], ray.dir[a]);
            let left = node + 1;
            let right = n.index as usize;
            // Rays parallel to the plane stay on the origin's side; one lying
            // in the plane goes below, where objects touching it are.
            let mut go_below = o <= n.split;
            if d.abs() >= PARALLEL_EPSILON {
                let below_first = o < n.split || (o == n.split && d < 0.0);
                let t_split = (n.split - o) / d;
                if t_split > t_max || t_split <= 0.0 {
                    go_below = below_first; // the segment stays on the first side
                } else if t_split <= t_min {
                    go_below = !below_first; // the segment already crossed
                } else {
                    go_below = below_first; // both: first side up to the plane
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
    best
}

/// Tests the objects of leaf `node`, the step every walk shares. Nearest
/// hit (`any` false): `best` improved by any hit with t <= t_limit, and at
/// an equal t by the lower id, which is the hit brute force's loop keeps
/// (two objects met at one point may lie in different leaves). Any hit:
/// the first hit with t < t_limit (the caller returns it at once), else
/// `best` (None). Counts each object it tests. Mirrors `test_leaf` in
/// shaders/traverse.wgsl.
#[allow(clippy::too_many_arguments)] // the shader's parameters, plus the cost
pub(super) fn test_leaf(
    tree: &KdTree,
    prims: &Primitives,
    node: usize,
    ray: &Ray,
    t_limit: f32,
    any: bool,
    mut best: Option<Hit>,
    cost: &mut WalkCost,
) -> Option<Hit> {
    let leaf = tree.nodes[node];
    let ids = &tree.leaf_objects[leaf.index as usize..(leaf.index + leaf.count) as usize];
    for &id in ids {
        cost.objects_tested += 1;
        if let Some(t) = prims.intersect(id, ray) {
            if any {
                if t < t_limit {
                    return Some(Hit { object: id, t });
                }
            } else if t <= t_limit && best.is_none_or(|b| t < b.t || (t == b.t && id < b.object)) {
                best = Some(Hit { object: id, t });
            }
        }
    }
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

/// `T_INFINITY`, re-exported for callers that want an unbounded ray.
pub const UNBOUNDED: f32 = T_INFINITY;
