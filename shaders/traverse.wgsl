// Nearest-hit and any-hit queries: the stackless k-d walk (kd-restart with
// push-down) and the seed's brute-force loop. Mirrors src/kdtree/traverse.rs.

struct Hit {
    t: f32,
    object: u32,     // NO_OBJECT when nothing was hit
    scene_id: u32,   // the object's id in the scene's order (NO_OBJECT: none)
}

fn miss() -> Hit {
    return Hit(T_INFINITY, NO_OBJECT, NO_OBJECT);
}

// Tests the objects of `leaf`, the step every walk shares. Nearest hit:
// `best_so_far` improved by any hit with t <= t_limit. Any hit: the first
// hit with t < t_limit (the caller returns it at once), else a miss. Takes
// and returns the hit by value: a ptr<function, Hit> parameter measured
// twice as slow on lavapipe (design.md).
fn test_leaf(leaf: KdNode, ray: Ray, t_limit: f32, any_hit: bool, best_so_far: Hit) -> Hit {
    var best = best_so_far;
    for (var i = leaf.index; i < leaf.index + leaf.count; i++) {
        loop_iterations += 1u;
        count_object();
        let id = leaf_object(i);
        let test = test_object(id, ray);
        let t = test.t;
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

// Loop iterations this invocation has run, all loops together. llvmpipe
// (lavapipe, and GL on llvmpipe) silently ends every loop of an invocation
// once their iterations add up to 65535 (LP_MAX_TGSI_LOOP_ITERATIONS),
// counted per 8-wide SIMD group: a loop runs while any lane needs it. The
// host reports invocations whose own count reached half the limit.
var<private> loop_iterations: u32;

// The work this invocation's walks did, over all its rays, counted as
// src/kdtree/traverse.rs WalkCost: x nodes visited (every k-d node record
// read: the inner nodes of each descent and its leaf), y leaves visited,
// z objects tested. Counted only where the pipeline is made to
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

// any_hit: return the first hit with t < t_limit; else the nearest hit with t <= t_limit.
fn trace_kdtree(ray: Ray, t_limit: f32, any_hit: bool) -> Hit {
    if (params.object_count == 0u) {
        return miss();
    }
    let span = box_interval(params.scene_min, params.scene_max, ray);
    if (span.x > span.y) {
        return miss();
    }
    var t_min = max(span.x, 0.0);
    let t_far = min(span.y, t_limit);
    if (t_min > t_far) {
        return miss();
    }
    // The nearest hit so far, over every leaf visited: one beyond its leaf's
    // exit may still lose to one in a later leaf (see traverse.rs).
    var best = miss();
    var restart_node = 0u;
    // Each restart moves t_min past one plane: node_count + 1 restarts suffice.
    for (var restarts = 0u; restarts <= params.node_count; restarts++) {
        loop_iterations += 1u;
        var node_index = restart_node;
        var t_max = t_far;
        var push_down = true;
        var node = kd_node(node_index);
        count_node();
        while (node.kind != KD_LEAF) {
            loop_iterations += 1u;
            let a = node.kind;
            let o = ray.origin[a];
            let d = ray.dir[a];
            // Parallel rays stay on the origin's side; in the plane, below.
            var go_below = o <= node.split;
            if (abs(d) >= PARALLEL_EPSILON) {
                let below_first = o < node.split || (o == node.split && d < 0.0);
                let t_split = (node.split - o) / d;
                if (t_split > t_max || t_split <= 0.0) {
                    go_below = below_first;
                } else if (t_split <= t_min) {
                    go_below = !below_first;
                } else {
                    go_below = below_first;
                    t_max = t_split;
                    push_down = false;
                }
            }
            node_index = select(node.index, node_index + 1u, go_below);
            if (push_down) {
                restart_node = node_index;
            }
            node = kd_node(node_index);
            count_node();
        }
        count_leaf();
        best = test_leaf(node, ray, t_limit, any_hit, best);
        if (any_hit && best.object != NO_OBJECT) {
            return best;
        }
        // Every leaf still to visit lies beyond t_max.
        if (best.t <= t_max || t_max >= t_far) {
            return best;
        }
        t_min = t_max;
    }
    return best;
}

fn trace_brute(ray: Ray, t_limit: f32, any_hit: bool) -> Hit {
    var best = miss();
    for (var id = 0u; id < params.object_count; id++) {
        loop_iterations += 1u;
        count_object();
        let t = test_object(id, ray).t;
        if (t > 0.0) {
            if (any_hit) {
                if (t < t_limit) {
                    return Hit(t, id, id);
                }
            } else if (t <= t_limit && t < best.t) {
                // Equal t: the first, which is the lower scene id where the
                // objects are in scene order, as `--accel brute` uploads them
                // (a tie check here cost this loop 6% on 10,000 spheres).
                // Its scene id is its GPU id there.
                best = Hit(t, id, id);
            }
        }
    }
    return best;
}

// The frame's walk; a specialised pipeline holds only that one (variant.wgsl).
fn trace_ray(ray: Ray, t_limit: f32, any_hit: bool) -> Hit {
    if (frame_accel() == ACCEL_BRUTE) {
        return trace_brute(ray, t_limit, any_hit);
    }
    let traversal = frame_traversal();
    if (traversal == TRAVERSAL_ROPES) {
        return trace_kdtree_ropes(ray, t_limit, any_hit);
    }
    if (traversal == TRAVERSAL_SHORT_STACK) {
        return trace_kdtree_short_stack(ray, t_limit, any_hit);
    }
    return trace_kdtree(ray, t_limit, any_hit);
}
