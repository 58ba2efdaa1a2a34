// The rope walk (Popov, Günther, Seidel, Slusallek 2007). Mirrors
// crates/kdray-core/src/kdtree/traverse_ropes.rs, which explains the cases: the
// descent classifies planes by t (crossed at or before t_min: past it), a
// leaf's exit is its first face ahead (faces on the scene's boundary lie at
// infinity, so the ray leaves through them at t_far), and a leaf reached
// through a rope that the ray spends no time in (an edge or a corner) is
// skipped for a descent from the root.

// The first face ahead so far: where the ray meets it, and which face.
struct RopeExit {
    t: f32,
    face: u32,   // NO_FACE: none met before t_far
}

const NO_FACE: u32 = 6u;

// `exit`, or the face of leaf record `r` ahead on axis `a` if the ray meets
// it sooner. Only the plane is loaded: a face on the scene's boundary lies
// at infinity (t_face = +inf), so it is never sooner.
fn rope_exit_on_axis(r: u32, a: u32, ray: Ray, exit: RopeExit) -> RopeExit {
    let d = ray.dir[a];
    if (abs(d) >= PARALLEL_EPSILON) {
        let face = 2u * a + select(0u, 1u, d > 0.0);
        let t_face = (rope_plane(r, face) - ray.origin[a]) / d;
        if (t_face < exit.t) {
            return RopeExit(t_face, face);
        }
    }
    return exit;
}

// any_hit: return the first hit with t < t_limit; else the nearest hit with
// t <= t_limit. `segment`: the non-empty part of the ray to search (scene_segment).
fn trace_kdtree_ropes(ray: Ray, t_limit: f32, any_hit: bool, segment: vec2<f32>) -> Hit {
    var t_min = segment.x;
    let t_far = segment.y;
    var best = miss();
    // Where the next descent starts: the root, or the rope of the face the
    // ray left the last leaf through.
    var start = 0u;
    var from_root = true;
    // Each leaf tested moves t_min past one more plane, and each skipped
    // leaf is followed by a tested one: node_count + 1 steps suffice.
    for (var steps = 0u; steps <= params.node_count; steps++) {
        loop_iterations += 1u;
        var node_index = start;
        var node = kd_node(node_index);
        count_node();
        while (node.kind != KD_LEAF) {
            loop_iterations += 1u;
            // Only the side matters: planes crossed at or before t_min are
            // behind the ray, every other one ahead (t_far bounds nothing).
            let step = descent_step(node, node_index, ray, t_min, t_far);
            record_node(node_index, t_min, t_far, step);
            node_index = step.near;
            node = kd_node(node_index);
            count_node();
        }
        count_leaf();
        // The exit: the first face ahead, else t_far.
        let r = leaf_rope_record(node_index);
        var exit = RopeExit(t_far, NO_FACE);
        exit = rope_exit_on_axis(r, 0u, ray, exit);
        exit = rope_exit_on_axis(r, 1u, ray, exit);
        exit = rope_exit_on_axis(r, 2u, ray, exit);
        let t_max = exit.t;
        record_leaf(node_index, t_min, t_max);
        // A leaf the ray spends no time in: start over from the root.
        if (t_max <= t_min && !from_root) {
            start = 0u;
            from_root = true;
            record_skipped_leaf(node_index);
            record_restart(0u, t_min);
            continue;
        }
        best = test_leaf(node, ray, t_limit, any_hit, best);
        if (walk_done(best, any_hit, t_max, t_far)) {
            return best;
        }
        // t_max < t_far, so a face was met: load its rope, the one rope
        // this leaf needs.
        t_min = t_max;
        start = rope_target(r, exit.face);
        from_root = false;
        record_rope(exit.face, start, t_min);
    }
    return best;
}
