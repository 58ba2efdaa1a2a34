//! The Lambertian lobe (shaders/bsdf_diffuse.wgsl): f = diffuse / pi,
//! sampled by the cosine.

use glam::Vec3;

use super::{from_local, reflection_sample, tangent_frame, Lobe, LobeEval, LobeSample, Site, PI};
use crate::layout::GpuMaterial;

pub struct Diffuse;

/// A cosine-weighted direction about n.
pub fn sample_cosine(n: Vec3, u1: f32, u2: f32) -> Vec3 {
    let r = u1.sqrt();
    let phi = 2.0 * PI * u2;
    let local = Vec3::new(r * phi.cos(), r * phi.sin(), (1.0 - u1).max(0.0).sqrt());
    from_local(&tangent_frame(n), local)
}

impl Lobe for Diffuse {
    fn name(&self) -> &'static str {
        "diffuse"
    }

    fn eval(&self, m: &GpuMaterial, s: &Site, v: Vec3, l: Vec3) -> LobeEval {
        let n_dot_l = s.shading.dot(l);
        let n_dot_v = s.shading.dot(v);
        if n_dot_l <= 0.0 || n_dot_v <= 0.0 {
            return LobeEval::ZERO;
        }
        LobeEval {
            value: Vec3::from_array(m.diffuse) * (n_dot_l / PI),
            pdf: n_dot_l / PI,
        }
    }

    /// Reads u.y and u.z.
    fn sample(&self, m: &GpuMaterial, s: &Site, v: Vec3, u: Vec3) -> LobeSample {
        let l = sample_cosine(s.shading, u.y, u.z);
        reflection_sample(self.eval(m, s, v, l), s, l)
    }
}

#[cfg(test)]
mod tests {
    use super::super::check::*;
    use super::*;

    fn white() -> GpuMaterial {
        material(|m| m.diffuse = [1.0; 3])
    }

    #[test]
    fn the_diffuse_pdf_integrates_to_one() {
        for v in views() {
            assert_pdf_integrates_to_sampled_share(&Diffuse, &white(), v);
        }
    }

    #[test]
    fn diffuse_samples_have_the_density_of_its_pdf() {
        for v in views() {
            assert_samples_follow_pdf(&Diffuse, &white(), v);
        }
    }

    #[test]
    fn the_diffuse_lobe_is_reciprocal() {
        assert_reciprocal(&Diffuse, &material(|m| m.diffuse = [0.3, 0.6, 0.9]));
    }

    #[test]
    fn a_white_diffuse_lobe_reflects_all_it_receives() {
        for v in views() {
            let (by_eval, by_samples) = furnace(&Diffuse, &white(), v);
            assert!((by_eval - 1.0).abs() < 0.02, "{by_eval}");
            assert!((by_samples - 1.0).abs() < 1e-4, "{by_samples}");
        }
    }
}
