// Nearest-hit and any-hit queries: the stackless k-d walk (kd-restart with
// push-down), the seed's brute-force loop, and the frame's choice between the
// walks. Mirrors crates/kdray-core/src/kdtree/traverse.rs; the steps the walks
// share are in walk_step.wgsl.

// any_hit: return the first hit with t < t_limit; else the nearest hit with
// t <= t_limit. `segment`: the non-empty part of the ray to search (scene_segment).
fn trace_kdtree(ray: Ray, t_limit: f32, any_hit: bool, segment: vec2<f32>) -> Hit {
    var t_min = segment.x;
    let t_far = segment.y;
    // The nearest hit so far, over every leaf visited: one beyond its leaf's
    // exit may still lose to one in a later leaf (see traverse.rs).
    var best = miss();
    var restart_node = 0u;
    // Each restart moves t_min past one plane: node_count + 1 restarts suffice.
    for (var restarts = 0u; restarts <= params.node_count; restarts++) {
        loop_iterations += 1u;
        if (restarts > 0u) {
            record_restart(restart_node, t_min);
        }
        var node_index = restart_node;
        var t_max = t_far;
        var push_down = true;
        var node = kd_node(node_index);
        count_node();
        while (node.kind != KD_LEAF) {
            loop_iterations += 1u;
            let step = descent_step(node, node_index, ray, t_min, t_max);
            record_node(node_index, t_min, t_max, step);
            if (step.crosses) {
                t_max = step.t_split;
                push_down = false;
            }
            node_index = step.near;
            if (push_down) {
                restart_node = node_index;
            }
            node = kd_node(node_index);
            count_node();
        }
        count_leaf();
        record_leaf(node_index, t_min, t_max);
        best = test_leaf(node, ray, t_limit, any_hit, best);
        if (walk_done(best, any_hit, t_max, t_far)) {
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
// The inspect kernel records the ray and what it hit (walk_record.wgsl).
fn trace_ray(ray: Ray, t_limit: f32, any_hit: bool) -> Hit {
    record_ray(ray, t_limit, any_hit);
    let hit = walk_ray(ray, t_limit, any_hit);
    record_hit(ray, hit);
    return hit;
}

fn walk_ray(ray: Ray, t_limit: f32, any_hit: bool) -> Hit {
    if (frame_accel() == ACCEL_BRUTE) {
        return trace_brute(ray, t_limit, any_hit);
    }
    let segment = scene_segment(ray, t_limit);
    if (segment.x > segment.y) {
        return miss();
    }
    record_segment(segment);
    let traversal = frame_traversal();
    if (traversal == TRAVERSAL_ROPES) {
        return trace_kdtree_ropes(ray, t_limit, any_hit, segment);
    }
    if (traversal == TRAVERSAL_SHORT_STACK) {
        return trace_kdtree_short_stack(ray, t_limit, any_hit, segment);
    }
    return trace_kdtree(ray, t_limit, any_hit, segment);
}
