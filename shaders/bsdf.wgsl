// The path tracer's materials (docs/scene-format.md, "The path tracer"):
// with probability `reflection` a perfect mirror, else with probability
// `transmission` smooth glass (exact Fresnel, glass.wgsl's refract_fresnel),
// else the material's model: a Lambertian albedo (MODEL_LAMBERTIAN) or glTF
// 2.0's metal/rough BRDF (MODEL_METAL_ROUGH: GGX with alpha = roughness^2,
// height-correlated Smith visibility, Schlick's Fresnel with F0 from the base
// colour and metallic, Lambertian diffuse for the dielectric part; the glTF
// specification's Appendix B). `specular`, `shininess` and `ambient` are the
// Whitted integrator's only. Directions are unit vectors pointing away from
// the surface; n is the shading normal on the side of the incoming ray.

const PI: f32 = 3.14159265358979;

// Smallest GGX alpha: roughness 0 is a mirror the microfacet terms cannot
// represent in f32 (D grows without bound).
const MIN_ALPHA: f32 = 1e-3;

// The share of a hit's light handled by the material's model (the rest is
// the mirror's and the glass's, both delta lobes).
fn model_share(m: Material) -> f32 {
    return (1.0 - m.reflection) * (1.0 - m.transmission);
}

// An orthonormal basis with n as its third axis (Duff et al. 2017).
fn tangent_frame(n: vec3<f32>) -> mat3x3<f32> {
    let s = select(-1.0, 1.0, n.z >= 0.0);
    let a = -1.0 / (s + n.z);
    let b = n.x * n.y * a;
    return mat3x3<f32>(
        vec3<f32>(1.0 + s * n.x * n.x * a, s * b, -s * n.x),
        vec3<f32>(b, s + n.y * n.y * a, -n.y),
        n
    );
}

fn to_local(f: mat3x3<f32>, v: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(dot(v, f[0]), dot(v, f[1]), dot(v, f[2]));
}

fn ggx_alpha(m: Material) -> f32 {
    return max(m.roughness * m.roughness, MIN_ALPHA);
}

fn ggx_d(n_dot_h: f32, a2: f32) -> f32 {
    let d = n_dot_h * n_dot_h * (a2 - 1.0) + 1.0;
    return a2 / (PI * d * d);
}

// Smith's G1 for GGX, in the direction with cosine c to the normal.
fn ggx_g1(c: f32, a2: f32) -> f32 {
    return 2.0 * c / (c + sqrt(a2 + (1.0 - a2) * c * c));
}

// The base colour's reflectance at normal incidence: 0.04 for the
// dielectric part (ior 1.5), the base colour for the metal.
fn metal_rough_f0(m: Material) -> vec3<f32> {
    return mix(vec3<f32>(0.04), m.diffuse, m.metallic);
}

// Probability of sampling the metal/rough model's specular lobe rather than
// its diffuse one: by their reflectances at normal incidence, kept in
// [0.25, 0.9] while the diffuse lobe has any colour (so both are sampled
// wherever they are non-zero).
fn specular_probability(m: Material) -> f32 {
    let diffuse = dot(m.diffuse, vec3<f32>(0.2126, 0.7152, 0.0722)) * (1.0 - m.metallic);
    if (diffuse <= 0.0) {
        return 1.0;
    }
    let specular = dot(metal_rough_f0(m), vec3<f32>(0.2126, 0.7152, 0.0722));
    return clamp(specular / (specular + diffuse), 0.25, 0.9);
}

// The model's value f x cos(n, l) and the solid-angle density with which
// `sample_model` picks l, for v and l on the outer side.
struct ModelEval {
    value: vec3<f32>,
    pdf: f32,
}

fn eval_model(m: Material, n: vec3<f32>, v: vec3<f32>, l: vec3<f32>) -> ModelEval {
    let n_dot_l = dot(n, l);
    let n_dot_v = dot(n, v);
    if (n_dot_l <= 0.0 || n_dot_v <= 0.0) {
        return ModelEval(vec3<f32>(0.0), 0.0);
    }
    if (m.model != MODEL_METAL_ROUGH) {
        return ModelEval(m.diffuse * (n_dot_l / PI), n_dot_l / PI);
    }
    let h = normalize(v + l);
    let n_dot_h = max(dot(n, h), 0.0);
    let v_dot_h = max(dot(v, h), 0.0);
    let alpha = ggx_alpha(m);
    let a2 = alpha * alpha;
    let d = ggx_d(n_dot_h, a2);
    // Height-correlated Smith, divided by 4 n.l n.v (glTF's V).
    let vis = 0.5 / (n_dot_l * sqrt(n_dot_v * n_dot_v * (1.0 - a2) + a2)
        + n_dot_v * sqrt(n_dot_l * n_dot_l * (1.0 - a2) + a2));
    let f0 = metal_rough_f0(m);
    let fresnel = f0 + (vec3<f32>(1.0) - f0) * pow(1.0 - v_dot_h, 5.0);
    let diffuse = (vec3<f32>(1.0) - fresnel) * m.diffuse * ((1.0 - m.metallic) / PI);
    let value = (diffuse + fresnel * (d * vis)) * n_dot_l;
    let q = specular_probability(m);
    // VNDF sampling's density (Heitz 2018): G1(v) D / (4 n.v).
    let pdf_specular = ggx_g1(n_dot_v, a2) * d / (4.0 * n_dot_v);
    return ModelEval(value, q * pdf_specular + (1.0 - q) * n_dot_l / PI);
}

// A cosine-weighted direction about n.
fn sample_cosine(n: vec3<f32>, u1: f32, u2: f32) -> vec3<f32> {
    let r = sqrt(u1);
    let phi = 2.0 * PI * u2;
    let local = vec3<f32>(r * cos(phi), r * sin(phi), sqrt(max(1.0 - u1, 0.0)));
    return tangent_frame(n) * local;
}

// A GGX normal from the distribution of normals visible from v (Heitz 2018,
// "Sampling the GGX Distribution of Visible Normals"), reflected about.
fn sample_ggx_reflection(n: vec3<f32>, v: vec3<f32>, alpha: f32, u1: f32, u2: f32) -> vec3<f32> {
    let frame = tangent_frame(n);
    let lv = to_local(frame, v);
    let vh = normalize(vec3<f32>(alpha * lv.x, alpha * lv.y, lv.z));
    let len2 = vh.x * vh.x + vh.y * vh.y;
    var t1 = vec3<f32>(1.0, 0.0, 0.0);
    if (len2 > 0.0) {
        t1 = vec3<f32>(-vh.y, vh.x, 0.0) / sqrt(len2);
    }
    let t2 = cross(vh, t1);
    let r = sqrt(u1);
    let phi = 2.0 * PI * u2;
    let p1 = r * cos(phi);
    let s = 0.5 * (1.0 + vh.z);
    let p2 = (1.0 - s) * sqrt(max(1.0 - p1 * p1, 0.0)) + s * r * sin(phi);
    let nh = p1 * t1 + p2 * t2 + sqrt(max(1.0 - p1 * p1 - p2 * p2, 0.0)) * vh;
    let ne = normalize(vec3<f32>(alpha * nh.x, alpha * nh.y, max(nh.z, 0.0)));
    let m_world = frame * ne;
    return normalize(reflect(-v, m_world));
}

// A direction from the model's density (`eval_model`'s pdf).
fn sample_model(m: Material, n: vec3<f32>, v: vec3<f32>) -> vec3<f32> {
    let u0 = random();
    let u1 = random();
    let u2 = random();
    if (m.model == MODEL_METAL_ROUGH && u0 < specular_probability(m)) {
        return sample_ggx_reflection(n, v, ggx_alpha(m), u1, u2);
    }
    return sample_cosine(n, u1, u2);
}
