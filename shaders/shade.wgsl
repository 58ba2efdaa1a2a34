// Blinn-Phong shading at a hit, with shadow rays to every light (through
// glass: shadow_transmittance in glass.wgsl).

struct Shading {
    color: vec3<f32>,      // emission + ambient_term + direct_term
    // A light is visible from the hit, or the hit emits (it lights itself).
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

// KHR_lights_punctual's spot falloff (mirrors scene::spot_factor): the
// share of a spot light's intensity sent `cos_angle` (cosine off its axis)
// away; 1 inside the inner cone, 0 outside the outer one.
fn spot_factor(light: Light, cos_angle: f32) -> f32 {
    let t = clamp((cos_angle - light.cos_outer) * light.spot_scale, 0.0, 1.0);
    return t * t;
}

// p: hit point; n: unit normal facing the incoming ray; v = -ray direction;
// origin: p moved off the surface, where shadow rays start. A spot light is
// a point light times its falloff; a directional light's shadow ray is
// unbounded.
fn shade(m: Material, p: vec3<f32>, n: vec3<f32>, v: vec3<f32>, origin: vec3<f32>) -> Shading {
    var ambient = vec3<f32>(0.0);
    var direct = vec3<f32>(0.0);
    var visible_any = false;
    for (var i = 0u; i < params.light_count; i++) {
        loop_iterations += 1u;
        let light = lights[i];
        ambient += m.ambient * light.ambient;
        var l: vec3<f32>;
        var shadow_ray = Ray(origin, vec3<f32>(0.0, 0.0, 1.0));
        var shadow_length = T_INFINITY;
        var strength = 1.0; // the spot falloff
        let kind = scene_light_kind(light.kind);
        if (kind == LIGHT_DIRECTIONAL) {
            l = -light.direction;
            shadow_ray.dir = l;
        } else {
            let to_light = light.position - p;
            let distance = length(to_light);
            if (distance <= 0.0) {
                continue;
            }
            l = to_light / distance;
            if (kind == LIGHT_SPOT) {
                strength = spot_factor(light, dot(-l, light.direction));
                if (strength == 0.0) {
                    continue;
                }
            }
            let to_light_from_origin = light.position - origin;
            shadow_length = length(to_light_from_origin);
            if (shadow_length > 0.0) {
                shadow_ray.dir = to_light_from_origin / shadow_length;
            }
        }
        let l_dot_n = dot(l, n);
        if (l_dot_n <= 0.0) {
            continue;
        }
        var through = 1.0;
        if (shadow_length > 0.0) {
            ray_counts.y += 1u;
            mark_light(i, 1.0);
            mark_ray(RAY_SHADOW);
            through = shadow_transmittance(shadow_ray, shadow_length);
            if (through == 0.0) {
                continue;
            }
        }
        visible_any = true;
        let h = normalize(l + v);
        var light_term = m.diffuse * light.diffuse * l_dot_n
            + m.specular * light.specular * specular_power(dot(n, h), m.shininess * 0.25);
        if (GLASS) {
            light_term *= through; // 1 without glass on the way
        }
        direct += strength * light_term; // strength 1 but for a spot light
    }
    // Emission first: with none, emission + ambient is ambient bit for bit.
    let emits = any(m.emission > vec3<f32>(0.0));
    return Shading(m.emission + ambient + direct, visible_any || emits);
}

// A unit vector from its octahedral encoding (Cigolle et al. 2014): two
// 16-bit snorm coordinates, x in the low half. Mirrors decode_octahedral in
// crates/kdray-core/src/layout/.
fn decode_normal(w: u32) -> vec3<f32> {
    let x = max(f32(bitcast<i32>(w << 16u) >> 16u) * (1.0 / 32767.0), -1.0);
    let y = max(f32(bitcast<i32>(w) >> 16u) * (1.0 / 32767.0), -1.0);
    var n = vec3<f32>(x, y, 1.0 - abs(x) - abs(y));
    let fold = max(-n.z, 0.0);
    n.x += select(fold, -fold, n.x >= 0.0);
    n.y += select(fold, -fold, n.y >= 0.0);
    return normalize(n);
}

// Barycentric weights of v0, v1, v2 at p (a point on the triangle, up to
// rounding), clamped into the triangle. Computed here rather than taken from
// the intersection test, which returns t only.
fn barycentrics(tri: Triangle, p: vec3<f32>) -> vec3<f32> {
    let e1 = tri.v1 - tri.v0;
    let e2 = tri.v2 - tri.v0;
    let w = p - tri.v0;
    let n = cross(e1, e2);
    let nn = dot(n, n);
    if (nn < 1e-30) {
        return vec3<f32>(1.0 / 3.0); // too small to tell the corners apart
    }
    let inv = 1.0 / nn;
    let b1 = clamp(dot(cross(w, e2), n) * inv, 0.0, 1.0);
    let b2 = clamp(dot(cross(e1, w), n) * inv, 0.0, 1.0 - b1);
    return vec3<f32>(1.0 - b1 - b2, b1, b2);
}
