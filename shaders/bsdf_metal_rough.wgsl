// glTF 2.0's metal/rough BRDF (MODEL_METAL_ROUGH; the specification's
// Appendix B): GGX with alpha = roughness^2 (bsdf_microfacet.wgsl),
// height-correlated Smith visibility, Schlick's Fresnel with F0 from the
// base colour and metallic, Lambertian diffuse for the dielectric part.
// Sampled by picking the specular lobe (visible normals) or the diffuse
// one (the cosine). The interface is bsdf.wgsl's; the CPU counterpart is
// crates/kdray-core/src/bsdf/metal_rough.rs.

fn ggx_alpha(m: Material) -> f32 {
    return max(m.roughness * m.roughness, MIN_ALPHA);
}

// The base colour's reflectance at normal incidence: 0.04 for the
// dielectric part (ior 1.5), the base colour for the metal.
fn metal_rough_f0(m: Material) -> vec3<f32> {
    return mix(vec3<f32>(0.04), m.diffuse, m.metallic);
}

// Probability of sampling the specular lobe rather than the diffuse one:
// by their reflectances at normal incidence, kept in [0.25, 0.9] while the
// diffuse lobe has any colour (so both are sampled wherever they are
// non-zero).
fn specular_probability(m: Material) -> f32 {
    let diffuse = dot(m.diffuse, vec3<f32>(0.2126, 0.7152, 0.0722)) * (1.0 - m.metallic);
    if (diffuse <= 0.0) {
        return 1.0;
    }
    let specular = dot(metal_rough_f0(m), vec3<f32>(0.2126, 0.7152, 0.0722));
    return clamp(specular / (specular + diffuse), 0.25, 0.9);
}

fn metal_rough_eval(m: Material, s: Surface, inside: bool, v: vec3<f32>, l: vec3<f32>) -> LobeEval {
    let n = s.shading;
    let n_dot_l = dot(n, l);
    let n_dot_v = dot(n, v);
    if (n_dot_l <= 0.0 || n_dot_v <= 0.0) {
        return LobeEval(vec3<f32>(0.0), 0.0);
    }
    let h = normalize(v + l);
    let n_dot_h = max(dot(n, h), 0.0);
    let v_dot_h = max(dot(v, h), 0.0);
    let alpha = ggx_alpha(m);
    let a2 = alpha * alpha;
    let d = ggx_d(n_dot_h, a2);
    let vis = ggx_visibility(n_dot_l, n_dot_v, a2);
    let f0 = metal_rough_f0(m);
    let fresnel = f0 + (vec3<f32>(1.0) - f0) * pow(1.0 - v_dot_h, 5.0);
    let diffuse = (vec3<f32>(1.0) - fresnel) * m.diffuse * ((1.0 - m.metallic) / PI);
    let value = (diffuse + fresnel * (d * vis)) * n_dot_l;
    let q = specular_probability(m);
    // VNDF sampling's density (Heitz 2018): G1(v) D / (4 n.v).
    let pdf_specular = ggx_g1(n_dot_v, a2) * d / (4.0 * n_dot_v);
    return LobeEval(value, q * pdf_specular + (1.0 - q) * n_dot_l / PI);
}

fn metal_rough_pdf(m: Material, s: Surface, inside: bool, v: vec3<f32>, l: vec3<f32>) -> f32 {
    return metal_rough_eval(m, s, inside, v, l).pdf;
}

// u.x picks the lobe; u.y and u.z sample it.
fn metal_rough_sample(m: Material, s: Surface, inside: bool, v: vec3<f32>, u: vec3<f32>) -> LobeSample {
    var l: vec3<f32>;
    if (u.x < specular_probability(m)) {
        let h = sample_ggx_vndf(s.shading, v, ggx_alpha(m), u.y, u.z);
        l = normalize(reflect(-v, h));
    } else {
        l = sample_cosine(s.shading, u.y, u.z);
    }
    return reflection_sample(metal_rough_eval(m, s, inside, v, l), s, l);
}
