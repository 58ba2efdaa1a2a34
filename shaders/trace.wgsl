// Entry points: camera rays, the bounded reflection loop, samples per pixel.
// render_tile traces all k x k samples of each pixel of a tile and writes
// 8-bit colour (or, path traced, radiance sums); accumulate_tile adds one
// sample per pass (the interactive window's and the page's progressive
// refinement). One invocation per pixel.

// Rays this invocation traced: primary, shadow, reflection.
var<private> ray_counts: vec3<u32>;
// Path samples this invocation dropped for non-finite radiance.
var<private> nonfinite_samples: u32;

fn camera_ray(u: f32, v: f32) -> Ray {
    let h = params.tan_half_vfov;
    let dir = params.camera_forward
        + (2.0 * u - 1.0) * h * params.aspect * params.camera_right
        + (1.0 - 2.0 * v) * h * params.camera_up;
    return Ray(params.camera_position, normalize(dir));
}

// The Whitted integrator, the seed's loop: colour += (1 - reflection) * weight * local;
// weight *= reflection.
// A scene with glass follows trace_whitted_glass (glass.wgsl) instead.
fn trace_whitted(primary: Ray) -> vec3<f32> {
    if (GLASS) {
        return trace_whitted_glass(primary);
    }
    var ray = primary;
    var color = vec3<f32>(0.0);
    var weight = 1.0;
    var hits = 0u;
    var path_length = 0.0; // from the eye to the hit, for the texture's ray cone
    ray_counts.x += 1u;
    mark_ray(RAY_PRIMARY);
    while (weight >= params.min_intensity && hits < params.max_depth) {
        loop_iterations += 1u;
        if (hits > 0u) {
            ray_counts.z += 1u;
        }
        let hit = trace_ray(ray, T_INFINITY, false);
        if (hit.object == NO_OBJECT) {
            color += weight * sky(ray.dir);
            break;
        }
        hits += 1u;
        let p = ray.origin + hit.t * ray.dir;
        let surface = mapped_surface_at(hit.object, p, ray.dir);
        let offset = spawn_offset(p, object_magnitude(hit.object));
        let origin = surface.spawn_point + offset * surface.geometric;
        path_length += hit.t;
        let m = material_at(hit.object, p, ray.dir, path_length);
        let s = shade(m, p, surface.shading, -ray.dir, origin);
        if (params.shadow_mode == SHADOW_SEED && !s.any_light_visible) {
            break;
        }
        color += (1.0 - m.reflection) * weight * s.color;
        weight *= m.reflection;
        if (weight == 0.0) {
            break; // nothing further can add to the colour
        }
        ray = Ray(origin, reflection_dir(ray.dir, surface));
        mark_ray(RAY_REFLECTED);
    }
    return color;
}

fn pack_rgb8(c: vec3<f32>) -> u32 {
    let q = vec3<u32>(floor(255.0 * clamp(c, vec3<f32>(0.0), vec3<f32>(1.0)) + 0.5));
    return q.x | (q.y << 8u) | (q.z << 16u) | (255u << 24u);
}

// The clamped colour of sample (sx, sy) of the k x k grid in `pixel`.
fn trace_sample(pixel: vec2<u32>, sx: u32, sy: u32, k: u32) -> vec3<f32> {
    let inv_k = 1.0 / f32(k);
    let u = (f32(pixel.x) + (f32(sx) + 0.5) * inv_k) / f32(params.width);
    let v = (f32(pixel.y) + (f32(sy) + 0.5) * inv_k) / f32(params.height);
    return clamp(trace_whitted(camera_ray(u, v)), vec3<f32>(0.0), vec3<f32>(1.0));
}

// Sample `s` of `pixel`, unclamped: path: a uniformly random position in
// the pixel and its path; Whitted: cell s of the k x k grid. A path sample
// whose radiance is not finite is dropped (0) and counted.
fn radiance_sample(pixel: vec2<u32>, s: u32) -> vec3<f32> {
    if (is_path()) {
        seed_random(pixel.y * params.width + pixel.x, s);
        let u = (f32(pixel.x) + random()) / f32(params.width);
        let v = (f32(pixel.y) + random()) / f32(params.height);
        let c = path_trace_sample(camera_ray(u, v));
        if (!is_finite3(c)) {
            nonfinite_samples += 1u;
            return vec3<f32>(0.0);
        }
        return c;
    }
    let k = params.samples_per_axis;
    let sx = s % k;
    let sy = (s / k) % k;
    let inv_k = 1.0 / f32(k);
    let u = (f32(pixel.x) + (f32(sx) + 0.5) * inv_k) / f32(params.width);
    let v = (f32(pixel.y) + (f32(sy) + 0.5) * inv_k) / f32(params.height);
    return trace_whitted(camera_ray(u, v));
}

// render_tile with RADIANCE_OUTPUT: adds samples sample_index ..
// sample_index + sample_count to the pixel's sums, one at a time (the same
// additions in the same order however the host splits the samples into
// dispatches). With FEATURE_OUTPUT a pixel's output is 12 words, not 4:
// its radiance sums, then its samples' albedo sums and normal sums (each
// three f32 and one unused word); every sample adds its features, a
// dropped one too.
fn add_radiance(pixel: vec2<u32>, i: u32) {
    var at = 4u * i;
    if (FEATURE_OUTPUT) {
        at = 12u * i;
    }
    var sum = read_sum(at);
    var albedo = vec3<f32>(0.0);
    var normal = vec3<f32>(0.0);
    if (FEATURE_OUTPUT) {
        albedo = read_sum(at + 4u);
        normal = read_sum(at + 8u);
    }
    let end = params.sample_index + params.sample_count;
    for (var s = params.sample_index; s < end; s++) {
        loop_iterations += 1u;
        // A sum that would overflow drops the sample too: no infinity
        // reaches a pixel.
        let next = sum + radiance_sample(pixel, s);
        if (is_finite3(next)) {
            sum = next;
        } else {
            nonfinite_samples += 1u;
        }
        if (FEATURE_OUTPUT) {
            albedo += feature_albedo;
            normal += feature_normal;
        }
    }
    write_sum(at, sum);
    if (FEATURE_OUTPUT) {
        write_sum(at + 4u, albedo);
        write_sum(at + 8u, normal);
    }
}

fn read_sum(at: u32) -> vec3<f32> {
    return vec3<f32>(
        bitcast<f32>(tile_output.pixels[at]),
        bitcast<f32>(tile_output.pixels[at + 1u]),
        bitcast<f32>(tile_output.pixels[at + 2u])
    );
}

fn write_sum(at: u32, sum: vec3<f32>) {
    tile_output.pixels[at] = bitcast<u32>(sum.x);
    tile_output.pixels[at + 1u] = bitcast<u32>(sum.y);
    tile_output.pixels[at + 2u] = bitcast<u32>(sum.z);
}

// Adds this invocation's walk cost to pixel `i` of `pixel_costs`
// (COST_WORDS = 3 words each), if the pipeline counts and the buffer has room: a one-word
// buffer means "not asked for".
fn add_pixel_cost(i: u32) {
    let at = COST_WORDS * i;
    if (COUNT_COSTS && at + 2u < pixel_costs_length()) {
        pixel_costs[at] += walk_cost.x;
        pixel_costs[at + 1u] += walk_cost.y;
        pixel_costs[at + 2u] += walk_cost.z;
    }
}

fn add_ray_counts() {
    atomicAdd(&tile_output.rays.primary, ray_counts.x);
    atomicAdd(&tile_output.rays.shadow, ray_counts.y);
    atomicAdd(&tile_output.rays.reflection, ray_counts.z);
    if (nonfinite_samples > 0u) {
        atomicAdd(&tile_output.rays.nonfinite, nonfinite_samples);
    }
    if (loop_iterations >= LOOP_LIMIT_WARNING) {
        atomicAdd(&tile_output.rays.loop_limited, 1u);
    }
}

@compute @workgroup_size(TRACE_WORKGROUP_X, TRACE_WORKGROUP_Y, 1)
fn render_tile(@builtin(global_invocation_id) gid: vec3<u32>) {
    read_params();
    if (gid.x >= params.tile_size.x || gid.y >= params.tile_size.y) {
        return;
    }
    let pixel = params.tile_origin + gid.xy;
    let i = gid.y * params.tile_size.x + gid.x;
    if (RADIANCE_OUTPUT) {
        add_radiance(pixel, i);
        add_ray_counts();
        add_pixel_cost(i); // the host clears the buffers per tile
        return;
    }
    let k = params.samples_per_axis;
    var sum = vec3<f32>(0.0);
    for (var sy = 0u; sy < k; sy++) {
        for (var sx = 0u; sx < k; sx++) {
            loop_iterations += 1u;
            sum += trace_sample(pixel, sx, sy, k);
        }
    }
    // Divide like the window's present pass does, so both round alike.
    tile_output.pixels[i] = pack_rgb8(sum / f32(k * k));
    add_ray_counts();
    add_pixel_cost(i); // the host clears the buffer per tile
}

@compute @workgroup_size(TRACE_WORKGROUP_X, TRACE_WORKGROUP_Y, 1)
fn accumulate_tile(@builtin(global_invocation_id) gid: vec3<u32>) {
    read_params();
    if (gid.x >= params.tile_size.x || gid.y >= params.tile_size.y) {
        return;
    }
    let pixel = params.tile_origin + gid.xy;
    let i = pixel.y * params.width + pixel.x;
    if (is_path()) {
        // Radiance, summed as add_radiance sums it (a sample that would
        // make the sum non-finite adds nothing but still counts), so that
        // pass n shows the headless render of n samples.
        let old = accumulation[i];
        let next = old.xyz + radiance_sample(pixel, params.sample_index);
        accumulation[i] = vec4<f32>(select(old.xyz, next, is_finite3(next)), old.w + 1.0);
    } else {
        let k = params.samples_per_axis;
        let s = params.sample_index % (k * k);
        accumulation[i] += vec4<f32>(trace_sample(pixel, s % k, s / k, k), 1.0);
    }
    add_pixel_cost(i); // summed over passes, like the colour
}
