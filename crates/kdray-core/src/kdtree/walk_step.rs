//! The steps every k-d walk shares (`traverse`: kd-restart, plain or with a
//! short stack; `traverse_ropes`), mirroring shaders/walk_step.wgsl: what a
//! query returns ([`Hit`]) and what it cost ([`WalkCost`]), the clip of the
//! ray to the scene's box, one descent step through an inner node, the leaf
//! test, and the "every leaf left lies beyond t_max" exit.
//!
//! Every decision is a comparison of `t` values or of the origin with a
//! plane, computed the same way in every walk, so that all walks visit the
//! same leaves with the same intervals and return the same hit.

use crate::geometry::{Primitives, Ray, PARALLEL_EPSILON};

use super::build::KdTree;
use super::nodes::KdNode;
use super::ropes::Ropes;
use super::walk_observer::{WalkEvent, WalkObserver};

/// What every walk searches: the tree, its ropes (read by the rope walk
/// only) and the objects.
#[derive(Clone, Copy)]
pub struct WalkScene<'a> {
    pub tree: &'a KdTree,
    pub ropes: &'a Ropes,
    pub prims: &'a Primitives,
}

/// What a walk is asked: the ray, how far it reaches (0 < t <= t_limit for
/// the nearest hit, 0 < t < t_limit for any hit), and whether any hit will
/// do (shadow rays) or the nearest is wanted.
#[derive(Debug, Clone, Copy)]
pub struct WalkQuery<'a> {
    pub ray: &'a Ray,
    pub t_limit: f32,
    pub any: bool,
}

/// A hit: which object and where along the ray.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hit {
    pub object: u32,
    pub t: f32,
}

/// The work one query did, counted the same way by every walk, its shader
/// and the brute-force loops (`walk_cost` in shaders/walk_step.wgsl):
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

/// Safety net for a walk's loop: each leaf tested moves t_min past one
/// split plane's crossing, so a valid tree never needs more than its node
/// count + 1 steps; this bound only stops a corrupt tree from hanging a GPU.
pub fn max_restarts(node_count: usize) -> u32 {
    node_count.min(u32::MAX as usize) as u32 + 1
}

/// The part of the ray a walk searches, `(t_min, t_far)`: inside the
/// scene's box, after the origin and up to `t_limit`. `None` when there is
/// nothing to search (no objects, the box missed, or behind the origin).
pub(super) fn scene_segment<O: WalkObserver>(
    tree: &KdTree,
    prims: &Primitives,
    ray: &Ray,
    t_limit: f32,
    observer: &mut O,
) -> Option<(f32, f32)> {
    if prims.is_empty() {
        return None;
    }
    let (t_enter, t_exit) = tree.bounds.ray_interval(ray)?;
    let t_min = t_enter.max(0.0);
    let t_far = t_exit.min(t_limit);
    if t_min > t_far {
        return None;
    }
    observer.event(WalkEvent::Segment { t_min, t_far });
    Some((t_min, t_far))
}

/// One step down from an inner node with the segment [t_min, t_max] still
/// to search.
#[derive(Debug, Clone, Copy)]
pub(super) struct DescentStep {
    /// The child the segment is in first.
    pub near: usize,
    /// The other child.
    pub far: usize,
    /// Where the ray meets the plane (meaningful when `crosses`).
    pub t_split: f32,
    /// The segment is in `near` up to `t_split`, then in `far`.
    pub crosses: bool,
}

/// The descent step from inner node `n`, record `index` (its lower child is
/// the next record, its upper child `n.index`).
pub(super) fn descent_step(
    n: KdNode,
    index: usize,
    ray: &Ray,
    t_min: f32,
    t_max: f32,
) -> DescentStep {
    let a = n.kind as usize;
    let (o, d) = (ray.origin[a], ray.dir[a]);
    // Rays parallel to the plane stay on the origin's side; one lying in the
    // plane goes below, where objects touching it are.
    let mut go_below = o <= n.split;
    let mut t_split = crate::geometry::T_INFINITY;
    let mut crosses = false;
    if d.abs() >= PARALLEL_EPSILON {
        let below_first = o < n.split || (o == n.split && d < 0.0);
        t_split = (n.split - o) / d;
        if t_split > t_max || t_split <= 0.0 {
            go_below = below_first; // the segment stays on the first side
        } else if t_split <= t_min {
            go_below = !below_first; // the segment already crossed
        } else {
            go_below = below_first; // both: first side up to the plane
            crosses = true;
        }
    }
    let (below, above) = (index + 1, n.index as usize);
    let (near, far) = if go_below {
        (below, above)
    } else {
        (above, below)
    };
    DescentStep {
        near,
        far,
        t_split,
        crosses,
    }
}

/// [`descent_step`], reported to `observer`.
pub(super) fn observed_descent_step<O: WalkObserver>(
    n: KdNode,
    index: usize,
    ray: &Ray,
    (t_min, t_max): (f32, f32),
    observer: &mut O,
) -> DescentStep {
    let step = descent_step(n, index, ray, t_min, t_max);
    observer.event(WalkEvent::Node {
        node: index,
        t_min,
        t_max,
        near: step.near,
        far: step.far,
        t_split: step.t_split,
        crosses: step.crosses,
    });
    step
}

/// Tests the objects of leaf `node`, reporting each test to `observer`. Nearest hit (`any` false): `best`
/// improved by any hit with t <= t_limit, and at an equal t by the lower
/// id, which is the hit brute force's loop keeps (two objects met at one
/// point may lie in different leaves). Any hit: the first hit with
/// t < t_limit (the caller returns it at once), else `best` (None). Counts
/// each object it tests.
#[allow(clippy::too_many_arguments)] // the shader's parameters, plus the cost
pub(super) fn test_leaf<O: WalkObserver>(
    tree: &KdTree,
    prims: &Primitives,
    node: usize,
    ray: &Ray,
    t_limit: f32,
    any: bool,
    mut best: Option<Hit>,
    cost: &mut WalkCost,
    observer: &mut O,
) -> Option<Hit> {
    let leaf = tree.nodes[node];
    let ids = &tree.leaf_objects[leaf.index as usize..(leaf.index + leaf.count) as usize];
    for &id in ids {
        cost.objects_tested += 1;
        let t = prims.intersect(id, ray);
        observer.event(WalkEvent::Tested { object: id, t });
        if let Some(t) = t {
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

/// After a leaf whose segment ends at `t_max`: whether the walk has its
/// answer. An any-hit query has one once anything is hit; a nearest-hit
/// query once its nearest hit so far lies before `t_max` (one found beyond
/// its leaf's exit, an object reaching into later cells, may still lose to
/// one in a later leaf, and every leaf still to visit lies beyond
/// `t_max`), or once the segment reached `t_far`.
pub(super) fn walk_done(best: Option<Hit>, any: bool, t_max: f32, t_far: f32) -> bool {
    (any && best.is_some()) || best.is_some_and(|hit| hit.t <= t_max) || t_max >= t_far
}
