// The GGX microfacet terms the metal/rough and rough dielectric lobes share
// (crates/kdray-core/src/bsdf/microfacet.rs): the distribution D, Smith's
// masking G1 and height-correlated visibility, and the sampling of the
// normals visible from a direction.

fn ggx_d(n_dot_h: f32, a2: f32) -> f32 {
    let d = n_dot_h * n_dot_h * (a2 - 1.0) + 1.0;
    return a2 / (PI * d * d);
}

// Smith's G1 for GGX, in the direction with cosine c to the normal.
fn ggx_g1(c: f32, a2: f32) -> f32 {
    return 2.0 * c / (c + sqrt(a2 + (1.0 - a2) * c * c));
}

// Height-correlated Smith G2 divided by 4 n.l n.v (glTF's V), for the
// cosines n.l and n.v (both > 0).
fn ggx_visibility(n_dot_l: f32, n_dot_v: f32, a2: f32) -> f32 {
    return 0.5 / (n_dot_l * sqrt(n_dot_v * n_dot_v * (1.0 - a2) + a2)
        + n_dot_v * sqrt(n_dot_l * n_dot_l * (1.0 - a2) + a2));
}

// A GGX normal of width alpha about n from the distribution of normals
// visible from v (Heitz 2018, "Sampling the GGX Distribution of Visible
// Normals"): density G1(v) max(v.h, 0) D(h) / n.v.
fn sample_ggx_vndf(n: vec3<f32>, v: vec3<f32>, alpha: f32, u1: f32, u2: f32) -> vec3<f32> {
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
    return frame * ne;
}
