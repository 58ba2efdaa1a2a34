//! The rough dielectric (shaders/bsdf_rough_dielectric.wgsl): GGX
//! microfacets that reflect and refract (Walter et al. 2007, "Microfacet
//! models for refraction"), alpha = transmission_roughness^2, each
//! microfacet's exact Fresnel reflectance, height-correlated Smith masking;
//! thin-walled, the transmitted light is the reflected light mirrored
//! through the surface (glTF's thin-walled BTDF). Written in the path
//! tracer's importance form: a sample's weight is G2 / G1 on either side.

use glam::Vec3;

use super::microfacet::{ggx_d, ggx_g1, ggx_visibility, sample_ggx_vndf};
use super::{dielectric_etas, reflect, Lobe, LobeEval, LobeSample, Site, MIN_ALPHA};
use crate::layout::GpuMaterial;

pub struct RoughDielectric;

pub fn rough_dielectric_alpha(m: &GpuMaterial) -> f32 {
    (m.transmission_roughness * m.transmission_roughness).max(MIN_ALPHA)
}

/// The exact dielectric Fresnel reflectance for the cosine c to the
/// microfacet on the side of index eta_i.
pub fn fresnel_dielectric(c: f32, eta_i: f32, eta_t: f32) -> f32 {
    if eta_i == eta_t {
        return 0.0;
    }
    let cos_i = c.clamp(0.0, 1.0);
    let eta = eta_i / eta_t;
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let rs = (eta_i * cos_i - eta_t * cos_t) / (eta_i * cos_i + eta_t * cos_t);
    let rp = (eta_t * cos_i - eta_i * cos_t) / (eta_t * cos_i + eta_i * cos_t);
    0.5 * (rs * rs + rp * rp)
}

/// l mirrored through the plane of normal n.
pub fn mirror_through(n: Vec3, l: Vec3) -> Vec3 {
    l - 2.0 * n.dot(l) * n
}

const NONE: LobeEval = LobeEval::ZERO;

impl Lobe for RoughDielectric {
    fn name(&self) -> &'static str {
        "rough_dielectric"
    }

    fn eval(&self, m: &GpuMaterial, s: &Site, v: Vec3, l: Vec3) -> LobeEval {
        let n = s.shading;
        let n_dot_v = n.dot(v);
        let n_dot_l = n.dot(l);
        if n_dot_v <= 0.0 || n_dot_l == 0.0 {
            return NONE;
        }
        let (eta_i, eta_t) = dielectric_etas(m, s.inside);
        let alpha = rough_dielectric_alpha(m);
        let a2 = alpha * alpha;
        let g1 = ggx_g1(n_dot_v, a2);
        let thin = m.thin_walled != 0;
        if n_dot_l > 0.0 || thin {
            let lr = if n_dot_l < 0.0 {
                mirror_through(n, l)
            } else {
                l
            };
            let c_l = n_dot_l.abs();
            let h = (v + lr).normalize();
            let v_dot_h = v.dot(h);
            if v_dot_h <= 0.0 {
                return NONE;
            }
            let d = ggx_d(n.dot(h).max(0.0), a2);
            let f = fresnel_dielectric(v_dot_h, eta_i, eta_t);
            let share = if n_dot_l < 0.0 { 1.0 - f } else { f };
            let value = share * d * ggx_visibility(c_l, n_dot_v, a2) * c_l;
            return LobeEval {
                value: Vec3::splat(value),
                pdf: share * g1 * d / (4.0 * n_dot_v),
            };
        }
        if eta_i == eta_t {
            return NONE;
        }
        let mut h = (-(eta_i * v + eta_t * l)).normalize();
        if n.dot(h) < 0.0 {
            h = -h;
        }
        let v_dot_h = v.dot(h);
        let l_dot_h = l.dot(h);
        if v_dot_h <= 0.0 || l_dot_h >= 0.0 {
            return NONE;
        }
        let d = ggx_d(n.dot(h), a2);
        let f = fresnel_dielectric(v_dot_h, eta_i, eta_t);
        let denom = eta_i * v_dot_h + eta_t * l_dot_h;
        let jacobian = eta_t * eta_t * l_dot_h.abs() / (denom * denom);
        let c_l = -n_dot_l;
        let value =
            (1.0 - f) * d * ggx_visibility(c_l, n_dot_v, a2) * 4.0 * c_l * v_dot_h * jacobian;
        let pdf = (1.0 - f) * g1 * v_dot_h * d / n_dot_v * jacobian;
        LobeEval {
            value: Vec3::splat(value),
            pdf,
        }
    }

    /// u.x chooses reflection or transmission; u.y and u.z the normal.
    fn sample(&self, m: &GpuMaterial, s: &Site, v: Vec3, u: Vec3) -> LobeSample {
        let n = s.shading;
        let none = LobeSample {
            dir: v,
            weight: Vec3::ZERO,
            pdf: 0.0,
            refracted: false,
        };
        if n.dot(v) <= 0.0 {
            return none;
        }
        let (eta_i, eta_t) = dielectric_etas(m, s.inside);
        let thin = m.thin_walled != 0;
        if eta_i == eta_t && !thin {
            return LobeSample {
                dir: -v,
                weight: Vec3::ONE,
                pdf: 0.0,
                refracted: true,
            };
        }
        let h = sample_ggx_vndf(n, v, rough_dielectric_alpha(m), u.y, u.z);
        let v_dot_h = v.dot(h);
        let f = fresnel_dielectric(v_dot_h, eta_i, eta_t);
        let mut l = reflect(-v, h).normalize();
        let reflected = u.x < f;
        if thin {
            if n.dot(l) <= 0.0 {
                return none;
            }
            if !reflected {
                l = mirror_through(n, l);
            }
        } else if !reflected {
            let eta = eta_i / eta_t;
            let sin2_t = eta * eta * (1.0 - v_dot_h * v_dot_h);
            let cos_t = (1.0 - sin2_t).max(0.0).sqrt();
            l = ((eta * v_dot_h - cos_t) * h - eta * v).normalize();
        }
        if (n.dot(l) > 0.0) != reflected || (l.dot(s.geometric) > 0.0) != reflected {
            return none;
        }
        let e = self.eval(m, s, v, l);
        if e.pdf <= 0.0 {
            return none;
        }
        LobeSample {
            dir: l,
            weight: e.value / e.pdf,
            pdf: e.pdf,
            refracted: !reflected && !thin,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::check::*;
    use super::*;

    fn frosted(roughness: f32, ior: f32, thin: bool) -> GpuMaterial {
        material(|m| {
            m.transmission = 1.0;
            m.transmission_roughness = roughness;
            m.ior = ior;
            m.thin_walled = u32::from(thin);
        })
    }

    /// Outside and inside a volume of glass, and thin-walled.
    fn cases() -> Vec<(GpuMaterial, bool)> {
        vec![
            (frosted(0.5, 1.5, false), false),
            (frosted(0.5, 1.5, false), true),
            (frosted(0.7, 1.33, false), false),
            (frosted(0.5, 1.5, true), false),
        ]
    }

    fn inside((s, v): (Site, Vec3), inside: bool) -> (Site, Vec3) {
        (Site { inside, ..s }, v)
    }

    #[test]
    fn the_rough_dielectric_pdf_integrates_to_its_sampled_share() {
        for (m, side) in cases() {
            for view in views() {
                assert_pdf_integrates_to_sampled_share(&RoughDielectric, &m, inside(view, side));
            }
        }
    }

    #[test]
    fn rough_dielectric_samples_have_the_density_of_its_pdf() {
        for (m, side) in cases() {
            for view in views() {
                assert_samples_follow_pdf(&RoughDielectric, &m, inside(view, side));
            }
        }
    }

    /// The chi-square test is not blind: a transmission density off by
    /// a tenth of the index, or a roughness off by a tenth, fails it.
    #[test]
    fn the_chi_square_test_rejects_a_perturbed_rough_dielectric_pdf() {
        struct Perturbed(f32, f32);
        impl Lobe for Perturbed {
            fn name(&self) -> &'static str {
                "perturbed"
            }
            fn eval(&self, m: &GpuMaterial, s: &Site, v: Vec3, l: Vec3) -> LobeEval {
                let mut p = *m;
                p.ior *= self.0;
                p.transmission_roughness *= self.1;
                RoughDielectric.eval(&p, s, v, l)
            }
            fn sample(&self, m: &GpuMaterial, s: &Site, v: Vec3, u: Vec3) -> LobeSample {
                RoughDielectric.sample(m, s, v, u)
            }
        }
        let m = frosted(0.5, 1.5, false);
        let view = views()[1];
        for lobe in [Perturbed(1.1, 1.0), Perturbed(1.0, 1.1)] {
            let (statistic, dof) = chi_square(&lobe, &m, view, 11);
            assert!(chi_square_z(statistic, dof) > 4.0, "{statistic} / {dof}");
        }
    }

    /// Reflection is reciprocal; transmission as the importance form says
    /// (f(v, l) / eta_l^2 = f(l, v) / eta_v^2); a thin wall both ways.
    #[test]
    fn the_rough_dielectric_is_reciprocal_up_to_the_indices() {
        for (m, _) in cases() {
            assert_reciprocal(&RoughDielectric, &m);
        }
    }

    /// No sample carries more light than it receives (weight G2 / G1), and
    /// the lobe loses little at low roughness (what single scattering
    /// misses) from outside, where no light is trapped by total internal
    /// reflection.
    #[test]
    fn a_rough_dielectric_passes_or_reflects_no_more_than_it_receives() {
        for (m, side) in cases() {
            for view in views() {
                let view = inside(view, side);
                let mut rng = Rng::new(2);
                for _ in 0..20_000 {
                    let smp = RoughDielectric.sample(&m, &view.0, view.1, rng.next3());
                    assert!(smp.weight.max_element() <= 1.0 + 1e-5, "{}", smp.weight);
                }
                let (by_eval, by_samples) = furnace(&RoughDielectric, &m, view);
                assert!(by_eval <= 1.01, "{by_eval}");
                assert!(
                    (by_eval - by_samples).abs() < 0.02,
                    "{by_eval} {by_samples}"
                );
            }
        }
        for view in views() {
            let (_, by_samples) = furnace(&RoughDielectric, &frosted(0.2, 1.5, false), view);
            assert!(by_samples > 0.9, "{by_samples}");
        }
    }

    /// As the roughness tends to 0 the lobe tends to smooth glass: samples
    /// reflect with the Fresnel reflectance's frequency and refract close
    /// to Snell's direction.
    #[test]
    fn a_nearly_smooth_rough_dielectric_is_smooth_glass() {
        let m = frosted(0.02, 1.5, false);
        let s = Site::flat(Vec3::Z);
        let v = Vec3::new(0.6, 0.0, 0.8);
        let fresnel = crate::reference::refract_fresnel(-v, Vec3::Z, 1.0, 1.5).fresnel;
        let mut rng = Rng::new(4);
        let (mut reflected, mut off, mut weight) = (0, 0, 0.0);
        let n = 50_000;
        for _ in 0..n {
            let smp = RoughDielectric.sample(&m, &s, v, rng.next3());
            let side = if smp.dir.z > 0.0 { 0.0 } else { 1.0 };
            let smooth = super::super::Dielectric.sample(&m, &s, v, Vec3::new(side, 0.0, 0.0));
            // GGX's tails: a share of about (alpha / 0.025)^2 of the
            // normals lean further than 0.025 rad.
            off += usize::from((smp.dir - smooth.dir).length() > 0.05);
            weight += smp.weight.x / n as f32;
            reflected += usize::from(smp.dir.z > 0.0);
        }
        assert!(
            off < n / 100,
            "{off} of {n} samples far from smooth glass's"
        );
        assert!(weight > 0.99, "{weight}");
        let share = reflected as f32 / n as f32;
        assert!((share - fresnel).abs() < 0.005, "{share} vs {fresnel}");
    }
}
