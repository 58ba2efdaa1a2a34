// The steps every k-d walk shares (traverse.wgsl, traverse_ropes.wgsl,
// traverse_short_stack.wgsl): the hit record, the work counters, the clip of
// the ray to the scene's box, one descent step through an inner node, the leaf
// test, and the "every leaf left lies beyond t_max" exit. Mirrors
// crates/kdray-core/src/kdtree/walk_step.rs. The compilers inline these
// functions; the walks measured as fast as with the steps written out
// (design.md).

struct Hit {
    t: f32,
    object: u32,     // NO_OBJECT when nothing was hit
    scene_id: u32,   // the object's id in the scene's order (NO_OBJECT: none)
}

fn miss() -> Hit {
    return Hit(T_INFINITY, NO_OBJECT, NO_OBJECT);
}

// Loop iterations this invocation has run, all loops together. llvmpipe
// (lavapipe, and GL on llvmpipe) silently ends every loop of an invocation
// once their iterations add up to 65535 (LP_MAX_TGSI_LOOP_ITERATIONS),
// counted per 8-wide SIMD group: a loop runs while any lane needs it. The
// host reports invocations whose own count reached half the limit.
var<private> loop_iterations: u32;

// The work this invocation's walks did, over all its rays, counted as
// crates/kdray-core/src/kdtree/walk_step.rs WalkCost: x nodes visited (every
// k-d node record read: the inner nodes of each descent and its leaf), y leaves
// visited, z objects tested. Counted only where the pipeline is made to
// (COUNT_COSTS, variant.wgsl); elsewhere it stays zero.
var<private> walk_cost: vec3<u32>;

fn count_node() {
    if (COUNT_COSTS) {
        walk_cost.x += 1u;
    }
}

fn count_leaf() {
    if (COUNT_COSTS) {
        walk_cost.y += 1u;
    }
}

fn count_object() {
    if (COUNT_COSTS) {
        walk_cost.z += 1u;
    }
}

// The part of the ray a walk searches: inside the scene's box, after the
// origin and up to t_limit. x = t_min, y = t_far; empty (x > y) when there
// is nothing to search. trace_ray clips once, for whichever walk it runs.
fn scene_segment(ray: Ray, t_limit: f32) -> vec2<f32> {
    let empty = vec2<f32>(1.0, 0.0);
    if (params.object_count == 0u) {
        return empty;
    }
    let span = box_interval(params.scene_min, params.scene_max, ray);
    if (span.x > span.y) {
        return empty;
    }
    return vec2<f32>(max(span.x, 0.0), min(span.y, t_limit));
}

// One step down from inner node `node` (record `node_index`) with the
// segment [t_min, t_max] still to search.
struct DescentStep {
    near: u32,      // the child the segment is in first
    far: u32,       // the other child
    t_split: f32,   // where the ray meets the plane (when `crosses`)
    crosses: bool,  // the segment is in `near` up to t_split, then in `far`
}

fn descent_step(node: KdNode, node_index: u32, ray: Ray, t_min: f32, t_max: f32) -> DescentStep {
    let a = node.kind;
    let o = ray.origin[a];
    let d = ray.dir[a];
    // Parallel rays stay on the origin's side; in the plane, below.
    var go_below = o <= node.split;
    var t_split = T_INFINITY;
    var crosses = false;
    if (abs(d) >= PARALLEL_EPSILON) {
        let below_first = o < node.split || (o == node.split && d < 0.0);
        t_split = (node.split - o) / d;
        if (t_split > t_max || t_split <= 0.0) {
            go_below = below_first;      // the segment stays on the first side
        } else if (t_split <= t_min) {
            go_below = !below_first;     // the segment already crossed
        } else {
            go_below = below_first;      // both: first side up to the plane
            crosses = true;
        }
    }
    let below = node_index + 1u;
    return DescentStep(select(node.index, below, go_below), select(below, node.index, go_below), t_split, crosses);
}

// Tests the objects of `leaf`. Nearest hit: `best_so_far` improved by any
// hit with t <= t_limit. Any hit: the first hit with t < t_limit (the
// caller returns it at once), else a miss. Takes and returns the hit by
// value: a ptr<function, Hit> parameter measured twice as slow on lavapipe
// (design.md).
fn test_leaf(leaf: KdNode, ray: Ray, t_limit: f32, any_hit: bool, best_so_far: Hit) -> Hit {
    var best = best_so_far;
    for (var i = leaf.index; i < leaf.index + leaf.count; i++) {
        loop_iterations += 1u;
        count_object();
        let id = leaf_object(i);
        let test = test_object(id, ray);
        let t = test.t;
        record_test(test.scene_id, t);
        if (t > 0.0) {
            if (any_hit) {
                if (t < t_limit) {
                    return Hit(t, id, test.scene_id);
                }
            } else if (t <= t_limit && (t < best.t || (t == best.t && test.scene_id < best.scene_id))) {
                // Equal t: the lower scene id, as brute force's loop keeps it.
                // The GPU stores objects in the tree's leaf order, so its ids
                // do not order ties as the scene's do (two faces met at one
                // edge rendered differently with another tree).
                best = Hit(t, id, test.scene_id);
            }
        }
    }
    return best;
}

// After a leaf whose segment ends at t_max: whether the walk has its
// answer. An any-hit query has one once anything is hit; a nearest-hit
// query once its nearest hit lies before t_max, since every leaf still to
// visit lies beyond t_max, or once the segment reached t_far.
fn walk_done(best: Hit, any_hit: bool, t_max: f32, t_far: f32) -> bool {
    return (any_hit && best.object != NO_OBJECT) || best.t <= t_max || t_max >= t_far;
}
