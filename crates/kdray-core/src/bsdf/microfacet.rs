//! The GGX terms the metal/rough and rough dielectric lobes share
//! (shaders/bsdf_microfacet.wgsl).

use glam::Vec3;

use super::{from_local, tangent_frame, PI};

pub fn ggx_d(n_dot_h: f32, a2: f32) -> f32 {
    let d = n_dot_h * n_dot_h * (a2 - 1.0) + 1.0;
    a2 / (PI * d * d)
}

/// Smith's G1 for GGX, in the direction with cosine c to the normal.
pub fn ggx_g1(c: f32, a2: f32) -> f32 {
    2.0 * c / (c + (a2 + (1.0 - a2) * c * c).sqrt())
}

/// Height-correlated Smith G2 over 4 n.l n.v.
pub fn ggx_visibility(n_dot_l: f32, n_dot_v: f32, a2: f32) -> f32 {
    0.5 / (n_dot_l * (n_dot_v * n_dot_v * (1.0 - a2) + a2).sqrt()
        + n_dot_v * (n_dot_l * n_dot_l * (1.0 - a2) + a2).sqrt())
}

/// A GGX normal about n visible from v (Heitz 2018): density
/// G1(v) max(v.h, 0) D(h) / n.v.
pub fn sample_ggx_vndf(n: Vec3, v: Vec3, alpha: f32, u1: f32, u2: f32) -> Vec3 {
    let frame = tangent_frame(n);
    let lv = Vec3::new(v.dot(frame[0]), v.dot(frame[1]), v.dot(frame[2]));
    let vh = Vec3::new(alpha * lv.x, alpha * lv.y, lv.z).normalize();
    let len2 = vh.x * vh.x + vh.y * vh.y;
    let t1 = if len2 > 0.0 {
        Vec3::new(-vh.y, vh.x, 0.0) / len2.sqrt()
    } else {
        Vec3::X
    };
    let t2 = vh.cross(t1);
    let r = u1.sqrt();
    let phi = 2.0 * PI * u2;
    let p1 = r * phi.cos();
    let s = 0.5 * (1.0 + vh.z);
    let p2 = (1.0 - s) * (1.0 - p1 * p1).max(0.0).sqrt() + s * r * phi.sin();
    let nh = p1 * t1 + p2 * t2 + (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt() * vh;
    let ne = Vec3::new(alpha * nh.x, alpha * nh.y, nh.z.max(0.0)).normalize();
    from_local(&frame, ne)
}
