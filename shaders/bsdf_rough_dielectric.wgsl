// The rough dielectric lobe (frosted glass, `transmission_roughness` > 0):
// GGX microfacets that reflect and refract (Walter et al. 2007,
// "Microfacet models for refraction") with alpha = roughness^2, the exact
// dielectric Fresnel reflectance of each microfacet, height-correlated
// Smith masking. A thin-walled material (glTF's transmission without a
// volume) has air on both sides: its transmitted light leaves unbent, as
// the reflected light mirrored through the surface (glTF's thin-walled
// BTDF), and the path stays on its side. The transmission is written in
// the path tracer's (importance) form: a sampled direction's weight is
// G2 / G1 on either side, so the lobe tends to bsdf_dielectric.wgsl's as
// the roughness tends to 0. Sampled by the visible normals, then reflection
// with the Fresnel reflectance's probability. The interface is
// bsdf.wgsl's; the CPU counterpart is
// crates/kdray-core/src/bsdf/rough_dielectric.rs.

fn rough_dielectric_alpha(m: Material) -> f32 {
    return max(m.transmission_roughness * m.transmission_roughness, MIN_ALPHA);
}

// The exact dielectric Fresnel reflectance for the cosine c (> 0) to the
// microfacet on the side of index eta_i, eta_t beyond (refract_fresnel's).
fn fresnel_dielectric(c: f32, eta_i: f32, eta_t: f32) -> f32 {
    if (eta_i == eta_t) {
        return 0.0;
    }
    let cos_i = clamp(c, 0.0, 1.0);
    let eta = eta_i / eta_t;
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i);
    if (sin2_t >= 1.0) {
        return 1.0;
    }
    let cos_t = sqrt(1.0 - sin2_t);
    let rs = (eta_i * cos_i - eta_t * cos_t) / (eta_i * cos_i + eta_t * cos_t);
    let rp = (eta_t * cos_i - eta_i * cos_t) / (eta_t * cos_i + eta_i * cos_t);
    return 0.5 * (rs * rs + rp * rp);
}

// l mirrored through the surface's plane (a thin wall's transmission).
fn mirror_through(n: vec3<f32>, l: vec3<f32>) -> vec3<f32> {
    return l - 2.0 * dot(n, l) * n;
}

fn rough_dielectric_eval(m: Material, s: Surface, inside: bool, v: vec3<f32>, l: vec3<f32>) -> LobeEval {
    let n = s.shading;
    let n_dot_v = dot(n, v);
    let n_dot_l = dot(n, l);
    if (n_dot_v <= 0.0 || n_dot_l == 0.0) {
        return LobeEval(vec3<f32>(0.0), 0.0);
    }
    let eta = dielectric_etas(m, inside);
    let alpha = rough_dielectric_alpha(m);
    let a2 = alpha * alpha;
    let g1 = ggx_g1(n_dot_v, a2);
    let thin = m.thin_walled != 0u;
    if (n_dot_l > 0.0 || thin) {
        // Reflection, or a thin wall's transmission as the reflection
        // mirrored through the surface.
        let lr = select(l, mirror_through(n, l), n_dot_l < 0.0);
        let c_l = abs(n_dot_l);
        let h = normalize(v + lr);
        let v_dot_h = dot(v, h);
        if (v_dot_h <= 0.0) {
            return LobeEval(vec3<f32>(0.0), 0.0);
        }
        let d = ggx_d(max(dot(n, h), 0.0), a2);
        let f = fresnel_dielectric(v_dot_h, eta.x, eta.y);
        let share = select(f, 1.0 - f, n_dot_l < 0.0);
        let value = share * d * ggx_visibility(c_l, n_dot_v, a2) * c_l;
        return LobeEval(vec3<f32>(value), share * g1 * d / (4.0 * n_dot_v));
    }
    if (eta.x == eta.y) {
        return LobeEval(vec3<f32>(0.0), 0.0); // equal indices: a delta, straight through
    }
    // Refraction: the microfacet normal between v and l, on n's side.
    var h = normalize(-(eta.x * v + eta.y * l));
    if (dot(n, h) < 0.0) {
        h = -h;
    }
    let v_dot_h = dot(v, h);
    let l_dot_h = dot(l, h);
    if (v_dot_h <= 0.0 || l_dot_h >= 0.0) {
        return LobeEval(vec3<f32>(0.0), 0.0);
    }
    let d = ggx_d(dot(n, h), a2);
    let f = fresnel_dielectric(v_dot_h, eta.x, eta.y);
    let denom = eta.x * v_dot_h + eta.y * l_dot_h;
    // dh / dl: eta_t^2 |l.h| / (eta_i v.h + eta_t l.h)^2.
    let jacobian = eta.y * eta.y * abs(l_dot_h) / (denom * denom);
    let c_l = -n_dot_l;
    let value = (1.0 - f) * d * ggx_visibility(c_l, n_dot_v, a2) * 4.0 * c_l * v_dot_h * jacobian;
    let pdf = (1.0 - f) * g1 * v_dot_h * d / n_dot_v * jacobian;
    return LobeEval(vec3<f32>(value), pdf);
}

fn rough_dielectric_pdf(m: Material, s: Surface, inside: bool, v: vec3<f32>, l: vec3<f32>) -> f32 {
    return rough_dielectric_eval(m, s, inside, v, l).pdf;
}

// u.x chooses reflection (below the microfacet's Fresnel reflectance) or
// transmission; u.y and u.z pick the visible normal.
fn rough_dielectric_sample(m: Material, s: Surface, inside: bool, v: vec3<f32>, u: vec3<f32>) -> LobeSample {
    let n = s.shading;
    let none = LobeSample(v, vec3<f32>(0.0), 0.0, false);
    if (dot(n, v) <= 0.0) {
        return none;
    }
    let eta = dielectric_etas(m, inside);
    let thin = m.thin_walled != 0u;
    if (eta.x == eta.y && !thin) {
        return LobeSample(-v, vec3<f32>(1.0), 0.0, true); // nothing bends or reflects
    }
    let h = sample_ggx_vndf(n, v, rough_dielectric_alpha(m), u.y, u.z);
    let v_dot_h = dot(v, h);
    let f = fresnel_dielectric(v_dot_h, eta.x, eta.y);
    var l = normalize(reflect(-v, h));
    let reflected = u.x < f;
    if (thin) {
        if (dot(n, l) <= 0.0) {
            return none;
        }
        if (!reflected) {
            l = mirror_through(n, l);
        }
    } else if (!reflected) {
        // Refraction about h (no total internal reflection here: f < 1).
        let eta_ratio = eta.x / eta.y;
        let sin2_t = eta_ratio * eta_ratio * (1.0 - v_dot_h * v_dot_h);
        let cos_t = sqrt(max(1.0 - sin2_t, 0.0));
        l = normalize((eta_ratio * v_dot_h - cos_t) * h - eta_ratio * v);
    }
    let n_dot_l = dot(n, l);
    if ((n_dot_l > 0.0) != reflected) {
        return none; // a microfacet sent it to the other side
    }
    // The geometric surface must agree with the shading normal's side.
    if ((dot(l, s.geometric) > 0.0) != reflected) {
        return none;
    }
    let e = rough_dielectric_eval(m, s, inside, v, l);
    if (e.pdf <= 0.0) {
        return none;
    }
    return LobeSample(l, e.value / e.pdf, e.pdf, !reflected && !thin);
}
