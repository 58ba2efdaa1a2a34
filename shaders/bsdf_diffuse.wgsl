// The Lambertian lobe (MODEL_LAMBERTIAN): f = diffuse / pi, sampled by the
// cosine. The interface is bsdf.wgsl's; the CPU counterpart is
// crates/kdray-core/src/bsdf/diffuse.rs.

fn diffuse_eval(m: Material, s: Surface, inside: bool, v: vec3<f32>, l: vec3<f32>) -> LobeEval {
    let n_dot_l = dot(s.shading, l);
    let n_dot_v = dot(s.shading, v);
    if (n_dot_l <= 0.0 || n_dot_v <= 0.0) {
        return LobeEval(vec3<f32>(0.0), 0.0);
    }
    return LobeEval(m.diffuse * (n_dot_l / PI), n_dot_l / PI);
}

fn diffuse_pdf(m: Material, s: Surface, inside: bool, v: vec3<f32>, l: vec3<f32>) -> f32 {
    return diffuse_eval(m, s, inside, v, l).pdf;
}

// A cosine-weighted direction about n.
fn sample_cosine(n: vec3<f32>, u1: f32, u2: f32) -> vec3<f32> {
    let r = sqrt(u1);
    let phi = 2.0 * PI * u2;
    let local = vec3<f32>(r * cos(phi), r * sin(phi), sqrt(max(1.0 - u1, 0.0)));
    return tangent_frame(n) * local;
}

// Reads u.y and u.z (u.x is the metal/rough lobe's choice, which this
// lobe's sampling shares).
fn diffuse_sample(m: Material, s: Surface, inside: bool, v: vec3<f32>, u: vec3<f32>) -> LobeSample {
    let l = sample_cosine(s.shading, u.y, u.z);
    return reflection_sample(diffuse_eval(m, s, inside, v, l), s, l);
}

// A sampled reflected direction's weight from the lobe's value `e` there:
// none below the geometric surface or where the density is 0.
fn reflection_sample(e: LobeEval, s: Surface, l: vec3<f32>) -> LobeSample {
    if (dot(l, s.geometric) <= 0.0 || e.pdf <= 0.0) {
        return LobeSample(l, vec3<f32>(0.0), 0.0, false);
    }
    return LobeSample(l, e.value / e.pdf, e.pdf, false);
}
