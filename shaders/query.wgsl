// trace_rays: the debug entry point. Traces the given rays with the frame's
// accel (no shading, no camera) and writes each one's hit, so tests can hold
// the kernel's walks against the CPU mirror and brute force ray by ray, hits
// and walk costs (query_costs: COST_WORDS per ray, as pixel_costs).
// One invocation per ray, QUERY_WORKGROUP rays per workgroup, rays in x then y.

@compute @workgroup_size(QUERY_WORKGROUP, 1, 1)
fn trace_rays(@builtin(global_invocation_id) gid: vec3<u32>,
              @builtin(num_workgroups) groups: vec3<u32>) {
    read_params();
    let i = gid.y * groups.x * QUERY_WORKGROUP + gid.x;
    if (i >= arrayLength(&query_rays)) {
        return;
    }
    let q = query_rays[i];
    let hit = trace_ray(Ray(q.origin, q.dir), q.t_limit, q.any_hit != 0u);
    query_hits[i] = QueryHit(hit.t, hit.object);
    let at = COST_WORDS * i;
    query_costs[at] = walk_cost.x;
    query_costs[at + 1u] = walk_cost.y;
    query_costs[at + 2u] = walk_cost.z;
}
