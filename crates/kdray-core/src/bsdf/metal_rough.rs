//! glTF 2.0's metal/rough BRDF (shaders/bsdf_metal_rough.wgsl): GGX with
//! alpha = roughness^2, height-correlated Smith visibility, Schlick's
//! Fresnel with F0 from the base colour and metallic, Lambertian diffuse
//! for the dielectric part; the specular lobe sampled by its visible
//! normals, the diffuse one by the cosine.

use glam::Vec3;

use super::diffuse::sample_cosine;
use super::microfacet::{ggx_d, ggx_g1, ggx_visibility, sample_ggx_vndf};
use super::{reflect, reflection_sample, Lobe, LobeEval, LobeSample, Site, MIN_ALPHA, PI};
use crate::layout::GpuMaterial;

pub struct MetalRough;

const LUMINANCE: Vec3 = Vec3::new(0.2126, 0.7152, 0.0722);

pub fn ggx_alpha(m: &GpuMaterial) -> f32 {
    (m.roughness * m.roughness).max(MIN_ALPHA)
}

/// The reflectance at normal incidence: 0.04 mixed to the base colour by
/// metallic.
pub fn metal_rough_f0(m: &GpuMaterial) -> Vec3 {
    Vec3::splat(0.04).lerp(Vec3::from_array(m.diffuse), m.metallic)
}

/// The probability of sampling the specular lobe.
pub fn specular_probability(m: &GpuMaterial) -> f32 {
    let diffuse = Vec3::from_array(m.diffuse).dot(LUMINANCE) * (1.0 - m.metallic);
    if diffuse <= 0.0 {
        return 1.0;
    }
    let specular = metal_rough_f0(m).dot(LUMINANCE);
    (specular / (specular + diffuse)).clamp(0.25, 0.9)
}

impl Lobe for MetalRough {
    fn name(&self) -> &'static str {
        "metal_rough"
    }

    fn eval(&self, m: &GpuMaterial, s: &Site, v: Vec3, l: Vec3) -> LobeEval {
        let n = s.shading;
        let n_dot_l = n.dot(l);
        let n_dot_v = n.dot(v);
        if n_dot_l <= 0.0 || n_dot_v <= 0.0 {
            return LobeEval::ZERO;
        }
        let h = (v + l).normalize();
        let n_dot_h = n.dot(h).max(0.0);
        let v_dot_h = v.dot(h).max(0.0);
        let alpha = ggx_alpha(m);
        let a2 = alpha * alpha;
        let d = ggx_d(n_dot_h, a2);
        let vis = ggx_visibility(n_dot_l, n_dot_v, a2);
        let f0 = metal_rough_f0(m);
        let fresnel = f0 + (Vec3::ONE - f0) * (1.0 - v_dot_h).powf(5.0);
        let diffuse =
            (Vec3::ONE - fresnel) * Vec3::from_array(m.diffuse) * ((1.0 - m.metallic) / PI);
        let value = (diffuse + fresnel * (d * vis)) * n_dot_l;
        let q = specular_probability(m);
        let pdf_specular = ggx_g1(n_dot_v, a2) * d / (4.0 * n_dot_v);
        LobeEval {
            value,
            pdf: q * pdf_specular + (1.0 - q) * n_dot_l / PI,
        }
    }

    /// u.x picks the lobe; u.y and u.z sample it.
    fn sample(&self, m: &GpuMaterial, s: &Site, v: Vec3, u: Vec3) -> LobeSample {
        let l = if u.x < specular_probability(m) {
            let h = sample_ggx_vndf(s.shading, v, ggx_alpha(m), u.y, u.z);
            reflect(-v, h).normalize()
        } else {
            sample_cosine(s.shading, u.y, u.z)
        };
        reflection_sample(self.eval(m, s, v, l), s, l)
    }
}

#[cfg(test)]
mod tests {
    use super::super::check::*;
    use super::*;
    use crate::layout::MODEL_METAL_ROUGH;

    fn metal(roughness: f32, metallic: f32, base: [f32; 3]) -> GpuMaterial {
        material(|m| {
            m.model = MODEL_METAL_ROUGH;
            m.roughness = roughness;
            m.metallic = metallic;
            m.diffuse = base;
        })
    }

    fn materials() -> [GpuMaterial; 3] {
        [
            metal(0.5, 1.0, [1.0; 3]),
            metal(0.7, 0.0, [0.8, 0.3, 0.2]),
            metal(0.35, 0.5, [0.9, 0.7, 0.3]),
        ]
    }

    #[test]
    fn the_metal_rough_pdf_integrates_to_its_sampled_share() {
        for m in materials() {
            for view in views() {
                assert_pdf_integrates_to_sampled_share(&MetalRough, &m, view);
            }
        }
    }

    #[test]
    fn metal_rough_samples_have_the_density_of_its_pdf() {
        for m in materials() {
            for view in views() {
                assert_samples_follow_pdf(&MetalRough, &m, view);
            }
        }
    }

    /// The chi-square test is not blind: a pdf whose roughness is off by
    /// a tenth, or samples drawn with another lobe choice, fail it.
    #[test]
    fn the_chi_square_test_rejects_a_perturbed_metal_rough_pdf() {
        struct Perturbed(f32, f32);
        impl Lobe for Perturbed {
            fn name(&self) -> &'static str {
                "perturbed"
            }
            fn eval(&self, m: &GpuMaterial, s: &Site, v: Vec3, l: Vec3) -> LobeEval {
                let mut p = *m;
                p.roughness *= self.0;
                MetalRough.eval(&p, s, v, l)
            }
            fn sample(&self, m: &GpuMaterial, s: &Site, v: Vec3, u: Vec3) -> LobeSample {
                MetalRough.sample(m, s, v, Vec3::new(u.x * self.1, u.y, u.z))
            }
        }
        let m = metal(0.5, 0.5, [0.9, 0.7, 0.3]);
        let view = views()[1];
        for lobe in [Perturbed(1.1, 1.0), Perturbed(1.0, 1.1)] {
            let (statistic, dof) = chi_square(&lobe, &m, view, 11);
            assert!(chi_square_z(statistic, dof) > 4.0, "{statistic} / {dof}");
        }
    }

    #[test]
    fn the_metal_rough_lobe_is_reciprocal() {
        for m in materials() {
            assert_reciprocal(&MetalRough, &m);
        }
    }

    /// A white metal reflects no more than it receives. A white dielectric
    /// base does too seen from near its normal; seen at grazing angles
    /// glTF's mix (the specification's Appendix B: the Lambertian part
    /// weighed by 1 - F(v.h) of the specular half vector) reflects up to a
    /// fifth more, which the kernel keeps, as the specification does.
    #[test]
    fn a_white_metal_reflects_no_more_than_it_receives() {
        for view in views() {
            let (by_eval, by_samples) = furnace(&MetalRough, &metal(0.5, 1.0, [1.0; 3]), view);
            assert!(by_eval <= 1.01 && by_eval > 0.7, "{by_eval}");
            assert!(
                (by_samples - by_eval).abs() < 0.02,
                "{by_samples} {by_eval}"
            );
        }
        for view in views() {
            let (by_eval, _) = furnace(&MetalRough, &metal(0.3, 0.0, [1.0; 3]), view);
            let bound = if view.1.dot(view.0.shading) > 0.5 {
                1.01
            } else {
                1.2
            };
            assert!(by_eval <= bound, "{by_eval}");
        }
    }
}
