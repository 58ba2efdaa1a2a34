// kd-restart with a short stack (Horn, Sugerman, Houston, Hanrahan 2007).
// Mirrors the short stack of crates/kdray-core/src/kdtree/traverse.rs: the
// restart walk's descent, which also remembers the far child (and the segment's
// end there) where it crosses both; after a leaf it resumes from the last one
// remembered, and restarts (with push-down) when none is left. The entries are
// named variables, not an array: lavapipe keeps private arrays in memory; there
// are SHORT_STACK_DEPTH (3, from the host's contract) of them.
//
// The loops are shaped for llvmpipe, which runs a loop body at least once
// for a whole SIMD group even when no lane needs it: a leaf without objects
// is left inside the descent loop, so the leaf loop (test_leaf) runs only
// for leaves with objects (8 - 10% off the meshes' frames, design.md). The
// leaves, intervals and hits are the mirror's, step for step. The leaf
// found is kept in two scalars set just before the break: with a KdNode
// variable assigned in the loop and read after it, Mesa 22.3 tested the
// wrong node for lanes that had left the loop early.

// any_hit: return the first hit with t < t_limit; else the nearest hit with
// t <= t_limit. `segment`: the non-empty part of the ray to search (scene_segment).
fn trace_kdtree_short_stack(ray: Ray, t_limit: f32, any_hit: bool, segment: vec2<f32>) -> Hit {
    var t_min = segment.x;
    let t_far = segment.y;
    var best = miss();
    var restart_node = 0u;
    // The stack, top first; `depth` entries are live. An entry is a far
    // child and the segment's end in it (its start is where the last leaf ends).
    var stack0_node = 0u;
    var stack0_t_max = 0.0;
    var stack1_node = 0u;
    var stack1_t_max = 0.0;
    var stack2_node = 0u;
    var stack2_t_max = 0.0;
    var depth = 0u;
    var node_index = 0u;
    var t_max = t_far;
    var push_down = true;
    // Where the next descent starts: popped from the stack, or the restart node.
    var resume = true;
    // Leaves left behind; every leaf's interval is non-empty, so node_count
    // + 1 of them suffice.
    var leaves = 0u;
    loop {
        // Descend, leaving leaves without objects behind, to a leaf with objects.
        var leaf_first = 0u;
        var leaf_count = 0u;
        loop {
            loop_iterations += 1u;
            if (resume) {
                resume = false;
                if (depth > 0u) {
                    node_index = stack0_node;
                    t_max = stack0_t_max;
                    stack0_node = stack1_node;
                    stack0_t_max = stack1_t_max;
                    stack1_node = stack2_node;
                    stack1_t_max = stack2_t_max;
                    depth -= 1u;
                    push_down = false; // the rest of the ray may leave this node
                    record_pop(node_index, t_max);
                } else {
                    node_index = restart_node;
                    t_max = t_far;
                    push_down = true;
                    if (leaves > 0u) {
                        record_restart(node_index, t_min);
                    }
                }
            }
            let node = kd_node(node_index);
            count_node();
            if (node.kind == KD_LEAF) {
                count_leaf();
                record_leaf(node_index, t_min, t_max);
                if (node.count != 0u) {
                    leaf_first = node.index;
                    leaf_count = node.count;
                    break;
                }
                // Nothing to test: leave it as a tested leaf is left (below).
                if (walk_done(best, any_hit, t_max, t_far) || leaves >= params.node_count) {
                    return best;
                }
                t_min = t_max;
                leaves += 1u;
                resume = true;
            } else {
                let step = descent_step(node, node_index, ray, t_min, t_max);
                record_node(node_index, t_min, t_max, step);
                if (step.crosses) {
                    if (step.t_split < t_max) {
                        record_push(step.far, t_max);
                        // Remember the far side; a full stack forgets its oldest.
                        stack2_node = stack1_node;
                        stack2_t_max = stack1_t_max;
                        stack1_node = stack0_node;
                        stack1_t_max = stack0_t_max;
                        stack0_node = step.far;
                        stack0_t_max = t_max;
                        depth = min(depth + 1u, SHORT_STACK_DEPTH);
                    }
                    t_max = step.t_split;
                    push_down = false;
                }
                node_index = step.near;
                if (push_down) {
                    restart_node = node_index;
                }
            }
        }
        // Leaving a tested leaf repeats the empty leaf's steps above: one
        // copy, run from the descent loop after the test, measured 4 - 7%
        // slower on the meshes (an extra masked pass through that loop).
        best = test_leaf(KdNode(KD_LEAF, 0.0, leaf_first, leaf_count), ray, t_limit, any_hit, best);
        if (walk_done(best, any_hit, t_max, t_far) || leaves >= params.node_count) {
            return best;
        }
        t_min = t_max;
        leaves += 1u;
        resume = true;
    }
    return best;
}
