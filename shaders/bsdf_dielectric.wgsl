// The smooth dielectric lobe (glass): refraction by Snell's law with the
// exact dielectric Fresnel reflectance and total internal reflection, a
// delta lobe (no density: next-event estimation cannot light it). The
// path tracer reflects with the Fresnel reflectance's probability, else
// refracts, untinted; a thin-walled material (`thin_walled`, glTF's
// transmission without a volume) lets the light through unbent, and the
// path stays on its side. The Whitted integrator (glass.wgsl) follows both
// rays with `refraction_at`. The interface is bsdf.wgsl's; the CPU
// counterpart is crates/kdray-core/src/bsdf/dielectric.rs.

// The refracted direction and the Fresnel reflectance at one interface.
struct Refraction {
    dir: vec3<f32>,   // unit; the incoming direction where fresnel == 1
    fresnel: f32,     // reflectance in [0, 1]; 1 at total internal reflection
}

// d: unit incoming direction; n: unit normal facing the incoming ray;
// eta_i: the index on the incoming side; eta_t: the index beyond.
// Equal indices bend nothing and reflect nothing, exactly.
fn refract_fresnel(d: vec3<f32>, n: vec3<f32>, eta_i: f32, eta_t: f32) -> Refraction {
    if (eta_i == eta_t) {
        return Refraction(d, 0.0);
    }
    let cos_i = clamp(-dot(d, n), 0.0, 1.0);
    let eta = eta_i / eta_t;
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i);
    if (sin2_t >= 1.0) {
        return Refraction(d, 1.0); // total internal reflection
    }
    let cos_t = sqrt(1.0 - sin2_t);
    let rs = (eta_i * cos_i - eta_t * cos_t) / (eta_i * cos_i + eta_t * cos_t);
    let rp = (eta_t * cos_i - eta_i * cos_t) / (eta_t * cos_i + eta_i * cos_t);
    let t = normalize(eta * d + (eta * cos_i - cos_t) * n);
    return Refraction(t, 0.5 * (rs * rs + rp * rp));
}

// Refraction about the shading normal, or about the geometric normal where
// that one would send the ray back out of the surface (as reflection_dir).
fn refraction_at(d: vec3<f32>, s: Surface, eta_i: f32, eta_t: f32) -> Refraction {
    let r = refract_fresnel(d, s.shading, eta_i, eta_t);
    if (r.fresnel == 1.0 || dot(r.dir, s.geometric) < 0.0) {
        return r;
    }
    return refract_fresnel(d, s.geometric, eta_i, eta_t);
}

// The indices on v's side and beyond: air outside, `ior` inside; a
// thin-walled surface has air on both sides, and its Fresnel that of
// entering `ior`.
fn dielectric_etas(m: Material, inside: bool) -> vec2<f32> {
    if (inside && m.thin_walled == 0u) {
        return vec2<f32>(m.ior, 1.0);
    }
    return vec2<f32>(1.0, m.ior);
}

fn dielectric_eval(m: Material, s: Surface, inside: bool, v: vec3<f32>, l: vec3<f32>) -> LobeEval {
    return LobeEval(vec3<f32>(0.0), 0.0);
}

fn dielectric_pdf(m: Material, s: Surface, inside: bool, v: vec3<f32>, l: vec3<f32>) -> f32 {
    return 0.0;
}

// Reads u.x only: reflect where it is below the Fresnel reflectance.
fn dielectric_sample(m: Material, s: Surface, inside: bool, v: vec3<f32>, u: vec3<f32>) -> LobeSample {
    let eta = dielectric_etas(m, inside);
    let d = -v;
    let r = refraction_at(d, s, eta.x, eta.y);
    if (u.x < r.fresnel) {
        return LobeSample(reflection_dir(d, s), vec3<f32>(1.0), 0.0, false);
    }
    if (m.thin_walled != 0u) {
        return LobeSample(d, vec3<f32>(1.0), 0.0, false);
    }
    return LobeSample(r.dir, vec3<f32>(1.0), 0.0, true);
}
