// Nearest-hit and any-hit queries: the stackless k-d walk (kd-restart with
// push-down) and the seed's brute-force loop. Mirrors src/kdtree/traverse.rs.

const NO_OBJECT: u32 = 0xffffffffu;

struct Hit {
    t: f32,
    object: u32,   // NO_OBJECT when nothing was hit
}

fn miss() -> Hit {
    return Hit(T_INFINITY, NO_OBJECT);
}

// Loop iterations this invocation has run, all loops together. llvmpipe
// (lavapipe, and GL on llvmpipe) silently ends every loop of an invocation
// once their iterations add up to 65535 (LP_MAX_TGSI_LOOP_ITERATIONS),
// counted per 8-wide SIMD group: a loop runs while any lane needs it. The
// host reports invocations whose own count reached half the limit.
var<private> loop_iterations: u32;
const LOOP_LIMIT_WARNING: u32 = 32768u;

fn inside_expanded(box_min: vec3<f32>, box_max: vec3<f32>, p: vec3<f32>, slack: f32) -> bool {
    return all(p >= box_min - vec3<f32>(slack)) && all(p <= box_max + vec3<f32>(slack));
}

// How far outside its leaf's box a hit point may lie and still be taken.
fn leaf_slack(p: vec3<f32>, magnitude: f32) -> f32 {
    return max(max_component(abs(p)), magnitude) * (1.0 / 65536.0);
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
    var restart_node = 0u;
    var restart_min = params.scene_min;
    var restart_max = params.scene_max;
    // Each restart moves t_min past one plane: node_count + 1 restarts suffice.
    for (var restarts = 0u; restarts <= params.node_count; restarts++) {
        loop_iterations += 1u;
        var node_index = restart_node;
        var cell_min = restart_min;
        var cell_max = restart_max;
        var t_max = t_far;
        var push_down = true;
        var node = kd_nodes[node_index];
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
            if (go_below) {
                cell_max[a] = node.split;
                node_index = node_index + 1u;
            } else {
                cell_min[a] = node.split;
                node_index = node.index;
            }
            if (push_down) {
                restart_node = node_index;
                restart_min = cell_min;
                restart_max = cell_max;
            }
            node = kd_nodes[node_index];
        }
        var best = miss();
        for (var i = node.index; i < node.index + node.count; i++) {
            loop_iterations += 1u;
            let id = leaf_objects[i];
            let t = intersect_object(id, ray);
            if (t > 0.0) {
                if (any_hit) {
                    if (t < t_limit) {
                        return Hit(t, id);
                    }
                } else if (t <= t_limit && t < best.t) {
                    best = Hit(t, id);
                }
            }
        }
        if (best.object != NO_OBJECT) {
            // Taken before the leaf's exit, or inside its box up to rounding.
            let p = ray.origin + best.t * ray.dir;
            if (best.t <= t_max || inside_expanded(cell_min, cell_max, p, leaf_slack(p, object_magnitude(best.object)))) {
                return best;
            }
        }
        if (t_max >= t_far) {
            return miss();
        }
        t_min = t_max;
    }
    return miss();
}

fn trace_brute(ray: Ray, t_limit: f32, any_hit: bool) -> Hit {
    var best = miss();
    for (var id = 0u; id < params.object_count; id++) {
        loop_iterations += 1u;
        let t = intersect_object(id, ray);
        if (t > 0.0) {
            if (any_hit) {
                if (t < t_limit) {
                    return Hit(t, id);
                }
            } else if (t <= t_limit && t < best.t) {
                best = Hit(t, id);
            }
        }
    }
    return best;
}

fn trace_ray(ray: Ray, t_limit: f32, any_hit: bool) -> Hit {
    if (params.accel == ACCEL_BRUTE) {
        return trace_brute(ray, t_limit, any_hit);
    }
    return trace_kdtree(ray, t_limit, any_hit);
}
