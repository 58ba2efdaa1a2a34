// Blinn-Phong shading at a hit, with shadow rays to every light.

struct Shading {
    color: vec3<f32>,      // ambient_term + direct_term
    any_light_visible: bool,
}

// max(x, 0)^e with 0^0 = 1, without pow's undefined cases (log of 0).
fn specular_power(x: f32, e: f32) -> f32 {
    if (e == 0.0) {
        return 1.0;
    }
    if (x <= 0.0) {
        return 0.0;
    }
    return pow(x, e);
}

// p: hit point; n: unit normal facing the incoming ray; v = -ray direction;
// origin: p moved off the surface, where shadow rays start.
fn shade(m: Material, p: vec3<f32>, n: vec3<f32>, v: vec3<f32>, origin: vec3<f32>) -> Shading {
    var ambient = vec3<f32>(0.0);
    var direct = vec3<f32>(0.0);
    var visible_any = false;
    for (var i = 0u; i < params.light_count; i++) {
        loop_iterations += 1u;
        let light = lights[i];
        ambient += m.ambient * light.ambient;
        let to_light = light.position - p;
        let distance = length(to_light);
        if (distance <= 0.0) {
            continue;
        }
        let l = to_light / distance;
        let l_dot_n = dot(l, n);
        if (l_dot_n <= 0.0) {
            continue;
        }
        let to_light_from_origin = light.position - origin;
        let shadow_length = length(to_light_from_origin);
        if (shadow_length > 0.0) {
            let shadow_ray = Ray(origin, to_light_from_origin / shadow_length);
            ray_counts.y += 1u;
            if (trace_ray(shadow_ray, shadow_length, true).object != NO_OBJECT) {
                continue;
            }
        }
        visible_any = true;
        let h = normalize(l + v);
        direct += m.diffuse * light.diffuse * l_dot_n
            + m.specular * light.specular * specular_power(dot(n, h), m.shininess * 0.25);
    }
    return Shading(ambient + direct, visible_any);
}
