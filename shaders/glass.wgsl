// Glass: refraction by Snell's law with the exact dielectric Fresnel
// reflectance, total internal reflection, shadow rays through transmissive
// surfaces, and the path that follows both the reflected and the refracted ray
// with a small stack (the refraction itself is bsdf_dielectric.wgsl's
// refraction_at). Mirrored by crates/kdray-core/src/reference/whitted.rs; the
// rules, exactly, are in docs/scene-format.md (Semantics, "Glass"). Reached
// only in pipelines with the GLASS override (variant.wgsl): a scene without
// glass runs the opaque path of trace.wgsl.

// How much of a light a shadow ray from `ray.origin`, `length` long, lets
// through: 1 unblocked, 0 blocked by an opaque object; each transmissive
// surface on the way multiplies it by its transmission (no caustics).
// The any-hit walk first: it settles every ray that meets nothing or an
// opaque object at the cost it has without glass (the general kernel's walk
// costs equal the specialised ones'); only one that meets glass is walked
// again, surface by surface (the result is the same either way).
fn shadow_transmittance(ray: Ray, length: f32) -> f32 {
    let first = trace_ray(ray, length, true).object;
    if (first == NO_OBJECT) {
        return 1.0;
    }
    if (!GLASS || materials[objects[first].x].transmission == 0.0) {
        return 0.0;
    }
    var through = 1.0;
    var origin = ray.origin;
    var remaining = length;
    for (var crossing = 0u; crossing <= SHADOW_CROSSINGS; crossing++) {
        loop_iterations += 1u;
        ray_counts.y += 1u; // the caller counted the any-hit ray
        let hit = trace_ray(Ray(origin, ray.dir), remaining, false);
        if (hit.object == NO_OBJECT || hit.t >= remaining) {
            return through;
        }
        through *= materials[objects[hit.object].x].transmission;
        if (through == 0.0 || crossing == SHADOW_CROSSINGS) {
            return 0.0;
        }
        let p = origin + hit.t * ray.dir;
        let step = spawn_offset(p, object_magnitude(hit.object));
        origin = p + step * ray.dir;
        remaining -= hit.t + step;
        if (remaining <= 0.0) {
            return through;
        }
    }
    return 0.0;
}

// A ray a sample still has to follow: where it starts, its share of the
// sample, the hits its path has had, the path's length from the eye to its
// origin (the texture's ray cone), and whether it is inside glass.
struct WhittedRay {
    origin: vec3<f32>,
    weight: f32,
    dir: vec3<f32>,
    hits: u32,
    path_length: f32,
    inside: bool,
}

// The path of one sample through mirrors and glass. Each hit adds
// local_share x weight x local, and splits the rest of the weight between
// the mirror direction (reflect_share) and the refracted one
// (transmit_share). The sample follows the refracted ray and pushes the
// reflected one, if it would be traced and the stack has room; a path that
// ends resumes from the last ray pushed.
fn trace_whitted_glass(primary: Ray) -> vec3<f32> {
    var pending: array<WhittedRay, GLASS_STACK_DEPTH>;
    var pending_count = 0u;
    var path = WhittedRay(primary.origin, 1.0, primary.dir, 0u, 0.0, false);
    var color = vec3<f32>(0.0);
    ray_counts.x += 1u;
    mark_ray(RAY_PRIMARY);
    loop {
        loop_iterations += 1u;
        var alive = path.weight >= params.min_intensity && path.hits < params.max_depth;
        if (alive) {
            if (path.hits > 0u) {
                ray_counts.z += 1u;
            }
            let ray = Ray(path.origin, path.dir);
            let hit = trace_ray(ray, T_INFINITY, false);
            if (hit.object == NO_OBJECT) {
                color += path.weight * sky(ray.dir);
                alive = false;
            } else {
                path.hits += 1u;
                let p = ray.origin + hit.t * ray.dir;
                let surface = mapped_surface_at(hit.object, p, ray.dir);
                let offset = spawn_offset(p, object_magnitude(hit.object));
                let origin = surface.spawn_point + offset * surface.geometric;
                let path_length = path.path_length + hit.t;
                let m = material_at(hit.object, p, ray.dir, path_length);
                let local_share = (1.0 - m.reflection) * (1.0 - m.transmission);
                // A surface with no local share and some transmission is
                // not shaded (no shadow rays); the seed mode's rule ends a
                // path at opaque surfaces only.
                let opaque = m.transmission == 0.0;
                if (local_share > 0.0 || opaque) {
                    let s = shade(m, p, surface.shading, -ray.dir, origin);
                    if (opaque && params.shadow_mode == SHADOW_SEED && !s.any_light_visible) {
                        alive = false;
                    } else {
                        color += local_share * path.weight * s.color;
                    }
                }
                if (alive) {
                    var reflect_share = m.reflection;
                    var transmit_share = 0.0;
                    var refracted = ray.dir;
                    if (m.transmission > 0.0) {
                        let dielectric = (1.0 - m.reflection) * m.transmission;
                        var eta_i = 1.0;
                        var eta_t = m.ior;
                        if (path.inside) {
                            eta_i = m.ior;
                            eta_t = 1.0;
                        }
                        let r = refraction_at(ray.dir, surface, eta_i, eta_t);
                        reflect_share = m.reflection + dielectric * r.fresnel;
                        transmit_share = dielectric * (1.0 - r.fresnel);
                        refracted = r.dir;
                    }
                    let reflected = WhittedRay(
                        origin,
                        path.weight * reflect_share,
                        reflection_dir(ray.dir, surface),
                        path.hits,
                        path_length,
                        path.inside
                    );
                    if (transmit_share > 0.0) {
                        let traced = reflect_share > 0.0
                            && reflected.weight >= params.min_intensity
                            && reflected.hits < params.max_depth;
                        if (traced && pending_count < GLASS_STACK_DEPTH) {
                            pending[pending_count] = reflected;
                            pending_count += 1u;
                        }
                        mark_ray(RAY_REFRACTED);
                        path = WhittedRay(
                            p - offset * surface.geometric,
                            path.weight * transmit_share,
                            refracted,
                            path.hits,
                            path_length,
                            !path.inside
                        );
                    } else {
                        mark_ray(RAY_REFLECTED);
                        path = reflected;
                    }
                    if (path.weight == 0.0) {
                        alive = false; // nothing further can add to the colour
                    }
                }
            }
        }
        if (!alive) {
            if (pending_count == 0u) {
                break;
            }
            pending_count -= 1u;
            path = pending[pending_count];
            mark_ray(RAY_REFLECTED);
        }
    }
    return color;
}
