// The path tracer (`integrator = "path"`): one path per sample, up to
// `max_depth` scattering hits, next-event estimation at each hit combined
// with BSDF sampling by multiple importance sampling (emitters and a sky
// image; point lights are a delta, a uniform sky is found by BSDF sampling
// alone), Russian
// roulette from the fourth hit on. Light that reaches a path: the sky
// (`params.background`) where it escapes, emission where it hits an emitter.
// Reached where `is_path()` (variant.wgsl): a path-traced frame.

// A path's state after a hit: where the next ray starts and where it goes.
struct Bounce {
    dir: vec3<f32>,
    weight: vec3<f32>,   // the throughput's factor: f cos / pdf
    // The direction's solid-angle density as next-event estimation would
    // weigh it; 0 where it cannot find the direction (a delta lobe, a
    // transmitted direction).
    pdf: f32,
    refracted: bool,
    delta: bool,         // a perfect mirror's or smooth glass's bounce
}

// Three random numbers, drawn in the order x, y, z.
fn random3() -> vec3<f32> {
    let u0 = random();
    let u1 = random();
    let u2 = random();
    return vec3<f32>(u0, u1, u2);
}

// A direction sampled from one lobe of a material with a rough dielectric,
// weighed by the mixture of its lobes with a density (bsdf.wgsl,
// eval_mixture): the mixture's value over its density. Next-event
// estimation lights the side of the geometric normal only, so a
// transmitted direction's density is 0 to it.
fn mixture_bounce(m: Material, s: Surface, inside: bool, v: vec3<f32>, b: LobeSample) -> Bounce {
    if (all(b.weight == vec3<f32>(0.0))) {
        return Bounce(b.dir, vec3<f32>(0.0), 0.0, false, false);
    }
    if (b.pdf <= 0.0) {
        return Bounce(b.dir, b.weight, 0.0, b.refracted, true);
    }
    let e = eval_mixture(m, s, inside, v, b.dir);
    if (e.pdf <= 0.0) {
        return Bounce(b.dir, vec3<f32>(0.0), 0.0, false, false);
    }
    let lit = dot(b.dir, s.geometric) > 0.0;
    return Bounce(b.dir, e.value / e.pdf, select(0.0, e.pdf, lit), b.refracted, false);
}

// The next direction at a hit: the mirror with probability `reflection`,
// the dielectric (bsdf_dielectric.wgsl, bsdf_rough_dielectric.wgsl) with
// `(1 - reflection) transmission`, else the model's own sampling. Its
// weight is the lobe's value over its density (the lobe's choice cancels
// out), or with a rough dielectric the mixture's (mixture_bounce).
fn sample_bounce(m: Material, s: Surface, d: vec3<f32>, inside: bool) -> Bounce {
    let u = random();
    if (u < m.reflection) {
        return Bounce(reflection_dir(d, s), vec3<f32>(1.0), 0.0, false, true);
    }
    let v = -d;
    let rough = has_rough_dielectric(m);
    if (u < m.reflection + (1.0 - m.reflection) * m.transmission) {
        if (rough) {
            return mixture_bounce(m, s, inside, v, rough_dielectric_sample(m, s, inside, v, random3()));
        }
        let g = dielectric_sample(m, s, inside, v, vec3<f32>(random(), 0.0, 0.0));
        return Bounce(g.dir, g.weight, 0.0, g.refracted, true);
    }
    let b = sample_model(m, s, v, random3());
    if (rough) {
        return mixture_bounce(m, s, inside, v, b);
    }
    return Bounce(b.dir, b.weight, b.pdf * model_share(m), false, false);
}

// The share of light left after a length t in a medium of absorption
// `medium` (Beer-Lambert): 1 in a clear channel, whatever t (even infinite).
fn transmittance(medium: vec3<f32>, t: f32) -> vec3<f32> {
    return select(exp(-medium * t), vec3<f32>(1.0), medium == vec3<f32>(0.0));
}

// Light arriving at the hit p from one light chosen by sample_light, through
// the material's lobes with a density (the model's share; with a rough
// dielectric, bsdf.wgsl's eval_mixture), weighted against BSDF sampling;
// p lies in a medium of absorption `medium`, which the unblocked shadow
// ray never leaves.
fn next_event(m: Material, s: Surface, inside: bool, v: vec3<f32>, p: vec3<f32>, origin: vec3<f32>, medium: vec3<f32>) -> vec3<f32> {
    let rough = has_rough_dielectric(m);
    // The lobes' values are scaled by `share` (the model's alone), or
    // already weighted by their shares (the mixture).
    var share = model_share(m);
    if (share <= 0.0 && !rough) {
        return vec3<f32>(0.0);
    }
    let light = sample_light(p, s.geometric);
    if (light.pdf <= 0.0 || dot(light.dir, s.geometric) <= 0.0) {
        return vec3<f32>(0.0);
    }
    var e: LobeEval;
    if (rough) {
        e = eval_mixture(m, s, inside, v, light.dir);
        share = 1.0;
    } else {
        e = eval_model(m, s, v, light.dir);
    }
    if (all(e.value == vec3<f32>(0.0))) {
        return vec3<f32>(0.0);
    }
    let limit = shadow_limit(light, origin);
    if (limit <= 0.0) {
        return vec3<f32>(0.0);
    }
    ray_counts.y += 1u;
    mark_light_density(select(light.pdf, 0.0, light.delta));
    mark_ray(RAY_SHADOW);
    if (trace_ray(Ray(origin, light.dir), limit, true).object != NO_OBJECT) {
        return vec3<f32>(0.0);
    }
    var weight = 1.0;
    if (!light.delta) {
        weight = mis_weight(light.pdf, e.pdf * share);
    }
    var through = vec3<f32>(1.0);
    if (any(medium != vec3<f32>(0.0))) {
        through = transmittance(medium, light.distance);
    }
    return share * e.value * light.radiance * through * (weight / light.pdf);
}

// Features (FEATURE_OUTPUT): what the denoiser reads beside the radiance,
// for one sample: the albedo and the shading normal (world space, facing
// the ray) of the path's first hit whose sampled bounce is not a delta one
// (a perfect mirror, smooth glass), followed through those as Open Image
// Denoise asks. The albedo is the material's base colour (`diffuse`, with
// its texture and vertex colour). A path that escapes before such a hit
// takes the sky's radiance there, clamped to [0, 1], as its albedo and 0 as
// its normal; one that ends on a delta surface (max_depth, Russian
// roulette) keeps that surface's. No random number is drawn for them, so
// the path and its radiance are the plain variant's.
var<private> feature_albedo: vec3<f32>;
var<private> feature_normal: vec3<f32>;

// The path tracer: the radiance one path from `primary` brings back (and,
// with FEATURE_OUTPUT, its features in feature_albedo and feature_normal).
fn path_trace_sample(primary: Ray) -> vec3<f32> {
    var ray = primary;
    var throughput = vec3<f32>(1.0);
    var radiance = vec3<f32>(0.0);
    var last_pdf = 0.0; // the BSDF density of the ray's direction; 0: camera or delta
    // The hit the ray left and its geometric normal, where next_event chose its light.
    var last_point = vec3<f32>(0.0);
    var last_normal = vec3<f32>(0.0);
    var inside = false;
    // The absorption of the medium the ray travels in: the inside of the
    // last transmissive object it entered (media do not nest), 0 in air.
    var medium = vec3<f32>(0.0);
    var path_length = 0.0;
    // Whether the features are still to be taken at the next hit.
    var features_open = FEATURE_OUTPUT;
    if (FEATURE_OUTPUT) {
        feature_albedo = vec3<f32>(0.0);
        feature_normal = vec3<f32>(0.0);
    }
    ray_counts.x += 1u;
    mark_ray(RAY_PRIMARY);
    for (var hits = 0u; ; hits++) {
        loop_iterations += 1u;
        if (hits > 0u) {
            ray_counts.z += 1u;
        }
        let hit = trace_ray(ray, T_INFINITY, false);
        if (inside) {
            throughput *= transmittance(medium, select(hit.t, T_INFINITY, hit.object == NO_OBJECT));
        }
        if (hit.object == NO_OBJECT) {
            var weight = 1.0;
            if (last_pdf > 0.0 && has_environment_image()) {
                weight = mis_weight(last_pdf, sky_pick() * environment_pdf(ray.dir));
            }
            let seen = sky(ray.dir);
            radiance += throughput * seen * weight;
            if (features_open) {
                feature_albedo = clamp(seen, vec3<f32>(0.0), vec3<f32>(1.0));
                feature_normal = vec3<f32>(0.0);
            }
            break;
        }
        let p = ray.origin + hit.t * ray.dir;
        path_length += hit.t;
        let m = material_at(hit.object, p, ray.dir, path_length);
        if (any(m.emission > vec3<f32>(0.0))) {
            let e = emitted(hit.object, p, ray.dir);
            var weight = 1.0;
            if (last_pdf > 0.0) {
                weight = mis_weight(last_pdf, light_pdf(hit.object, last_point, last_normal, ray.origin, ray.dir, hit.t));
            }
            radiance += throughput * e * weight;
        }
        if (hits >= params.max_depth) {
            if (features_open) {
                feature_albedo = m.diffuse;
                feature_normal = mapped_surface_at(hit.object, p, ray.dir).shading;
            }
            break;
        }
        let surface = mapped_surface_at(hit.object, p, ray.dir);
        if (features_open) {
            feature_albedo = m.diffuse;
            feature_normal = surface.shading;
        }
        let offset = spawn_offset(p, object_magnitude(hit.object));
        let outside = surface.spawn_point + offset * surface.geometric;
        radiance += throughput * next_event(m, surface, inside, -ray.dir, p, outside, medium);
        let b = sample_bounce(m, surface, ray.dir, inside);
        // A mirror's or smooth glass's bounce (a delta lobe: no density, a
        // weight) passes the features on to the next hit.
        features_open = features_open && b.delta && any(b.weight != vec3<f32>(0.0));
        throughput *= b.weight;
        if (all(throughput == vec3<f32>(0.0))) {
            break;
        }
        if (hits >= 3u) {
            let keep = min(max_component(throughput), 0.95);
            if (random() >= keep) {
                break;
            }
            throughput /= keep;
        }
        var origin = outside;
        if (dot(b.dir, surface.geometric) < 0.0) {
            origin = p - offset * surface.geometric;
        }
        if (b.refracted) {
            inside = !inside;
            medium = select(vec3<f32>(0.0), m.absorption, inside);
        }
        last_pdf = b.pdf;
        last_point = p;
        last_normal = surface.geometric;
        ray = Ray(origin, b.dir);
        mark_ray(RAY_BOUNCE);
    }
    return radiance;
}

// Whether every component of c is a finite number, read from the bits: WGSL
// lets compilers assume floats are never NaN or infinite, so x == x and
// comparisons may be folded away.
fn is_finite3(c: vec3<f32>) -> bool {
    let exponent = bitcast<vec3<u32>>(c) & vec3<u32>(0x7f800000u);
    return all(exponent != vec3<u32>(0x7f800000u));
}
