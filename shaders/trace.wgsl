// Entry point: camera rays, the bounded reflection loop, samples per pixel
// and the 8-bit output. One invocation per pixel of the current tile.

fn camera_ray(u: f32, v: f32) -> Ray {
    let h = params.tan_half_vfov;
    let dir = params.camera_forward
        + (2.0 * u - 1.0) * h * params.aspect * params.camera_right
        + (1.0 - 2.0 * v) * h * params.camera_up;
    return Ray(params.camera_position, normalize(dir));
}

// The seed's loop: colour += (1 - reflection) * weight * local; weight *= reflection.
fn trace_path(primary: Ray) -> vec3<f32> {
    var ray = primary;
    var color = vec3<f32>(0.0);
    var weight = 1.0;
    var hits = 0u;
    while (weight >= params.min_intensity && hits < params.max_depth) {
        let hit = trace_ray(ray, T_INFINITY, false);
        if (hit.object == NO_OBJECT) {
            color += weight * params.background;
            break;
        }
        hits += 1u;
        let p = ray.origin + hit.t * ray.dir;
        var n = object_normal(hit.object, p);
        if (dot(n, ray.dir) > 0.0) {
            n = -n;
        }
        let origin = p + spawn_offset(p, object_magnitude(hit.object)) * n;
        let m = materials[object_materials[hit.object]];
        let s = shade(m, p, n, -ray.dir, origin);
        if (params.shadow_mode == SHADOW_SEED && !s.any_light_visible) {
            break;
        }
        color += (1.0 - m.reflection) * weight * s.color;
        weight *= m.reflection;
        if (weight == 0.0) {
            break; // nothing further can add to the colour
        }
        ray = Ray(origin, normalize(reflect(ray.dir, n)));
    }
    return color;
}

fn pack_rgb8(c: vec3<f32>) -> u32 {
    let q = vec3<u32>(floor(255.0 * clamp(c, vec3<f32>(0.0), vec3<f32>(1.0)) + 0.5));
    return q.x | (q.y << 8u) | (q.z << 16u) | (255u << 24u);
}

@compute @workgroup_size(8, 8, 1)
fn render_tile(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= params.tile_size.x || gid.y >= params.tile_size.y) {
        return;
    }
    let pixel = params.tile_origin + gid.xy;
    let k = params.samples_per_axis;
    let inv_k = 1.0 / f32(k);
    var sum = vec3<f32>(0.0);
    for (var sy = 0u; sy < k; sy++) {
        for (var sx = 0u; sx < k; sx++) {
            let u = (f32(pixel.x) + (f32(sx) + 0.5) * inv_k) / f32(params.width);
            let v = (f32(pixel.y) + (f32(sy) + 0.5) * inv_k) / f32(params.height);
            sum += clamp(trace_path(camera_ray(u, v)), vec3<f32>(0.0), vec3<f32>(1.0));
        }
    }
    output_pixels[gid.y * params.tile_size.x + gid.x] = pack_rgb8(sum * (inv_k * inv_k));
}
