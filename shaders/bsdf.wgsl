// The path tracer's materials (docs/scene-format.md, "The path tracer"):
// with probability `reflection` a perfect mirror, else with probability
// `transmission` a dielectric (smooth, bsdf_dielectric.wgsl, or rough,
// bsdf_rough_dielectric.wgsl, by `transmission_roughness`), else the
// material's model: a Lambertian albedo (MODEL_LAMBERTIAN,
// bsdf_diffuse.wgsl) or glTF 2.0's metal/rough BRDF (MODEL_METAL_ROUGH,
// bsdf_metal_rough.wgsl). `specular`, `shininess` and `ambient` are the
// Whitted integrator's only.
//
// Every lobe has the same interface, mirrored one file a lobe by
// crates/kdray-core/src/bsdf/ (and checked against it on the GPU):
//   fn LOBE_eval(m: Material, s: Surface, inside: bool, v, l) -> LobeEval
//   fn LOBE_pdf(m: Material, s: Surface, inside: bool, v, l) -> f32
//   fn LOBE_sample(m: Material, s: Surface, inside: bool, v, u: vec3<f32>) -> LobeSample
// Directions are unit vectors pointing away from the surface: v towards
// where the path came from, l where it goes; s.shading is the shading
// normal on the side of v; `inside`: the path is inside the object (a
// dielectric's indices swap); u: uniform random numbers in [0, 1), which
// a lobe reads in the order x, y, z (the smooth dielectric reads x only).
// A lobe draws no random numbers of its own.

const PI: f32 = 3.14159265358979;

// Smallest GGX alpha: roughness 0 is a mirror the microfacet terms cannot
// represent in f32 (D grows without bound).
const MIN_ALPHA: f32 = 1e-3;

// A lobe's value f x |cos(n, l)| for a pair of directions, and the
// solid-angle density with which its sample picks l (0 for a delta lobe).
struct LobeEval {
    value: vec3<f32>,
    pdf: f32,
}

// A direction a lobe picked: its weight f |cos| / pdf (a delta lobe's:
// what it lets through), its density (0: a delta lobe, which next-event
// estimation cannot find), and whether it crossed into the object (a
// refraction, which swaps the side the path is on).
struct LobeSample {
    dir: vec3<f32>,
    weight: vec3<f32>,
    pdf: f32,
    refracted: bool,
}

// The share of a hit's light handled by the material's model (the rest is
// the mirror's and the dielectric's).
fn model_share(m: Material) -> f32 {
    return (1.0 - m.reflection) * (1.0 - m.transmission);
}

// The share of a hit's light handled by the dielectric.
fn dielectric_share(m: Material) -> f32 {
    return (1.0 - m.reflection) * m.transmission;
}

// Whether the material's dielectric is the rough one (a lobe with a
// density, lit by next-event estimation) rather than smooth glass.
fn has_rough_dielectric(m: Material) -> bool {
    return m.transmission > 0.0 && m.transmission_roughness > 0.0;
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

// The model's value and density (the model is the Lambertian lobe or the
// metal/rough one).
fn eval_model(m: Material, s: Surface, v: vec3<f32>, l: vec3<f32>) -> LobeEval {
    if (m.model != MODEL_METAL_ROUGH) {
        return diffuse_eval(m, s, false, v, l);
    }
    return metal_rough_eval(m, s, false, v, l);
}

// A direction from the model's density (`eval_model`'s pdf), from three
// random numbers.
fn sample_model(m: Material, s: Surface, v: vec3<f32>, u: vec3<f32>) -> LobeSample {
    if (m.model == MODEL_METAL_ROUGH) {
        return metal_rough_sample(m, s, false, v, u);
    }
    return diffuse_sample(m, s, false, v, u);
}

// The material's lobes with a density (the model's share and, where it is
// rough, the dielectric's) for a pair of directions, each weighted by its
// share: what next-event estimation and a sampled direction's weight
// read where the material has a rough dielectric.
fn eval_mixture(m: Material, s: Surface, inside: bool, v: vec3<f32>, l: vec3<f32>) -> LobeEval {
    let ms = model_share(m);
    let ds = dielectric_share(m);
    var value = vec3<f32>(0.0);
    var pdf = 0.0;
    if (ms > 0.0) {
        let e = eval_model(m, s, v, l);
        value += ms * e.value;
        pdf += ms * e.pdf;
    }
    if (ds > 0.0) {
        let e = rough_dielectric_eval(m, s, inside, v, l);
        value += ds * e.value;
        pdf += ds * e.pdf;
    }
    return LobeEval(value, pdf);
}
