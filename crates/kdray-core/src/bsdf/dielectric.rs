//! The smooth dielectric (shaders/bsdf_dielectric.wgsl): reflection with
//! the exact Fresnel reflectance's probability, else refraction by Snell's
//! law (or, thin-walled, straight through), a delta lobe whose every
//! sample lets all its light through.

use glam::Vec3;

use super::{dielectric_etas, Lobe, LobeEval, LobeSample, Site};
use crate::layout::GpuMaterial;
use crate::reference::{reflection_dir, refraction_at, Surface};

pub struct Dielectric;

/// The reference's surface of a site (its refraction and mirror
/// direction are the kernel's, shared with the Whitted loop).
fn surface(s: &Site) -> Surface {
    Surface {
        geometric: s.geometric,
        shading: s.shading,
        spawn_point: Vec3::ZERO,
    }
}

impl Lobe for Dielectric {
    fn name(&self) -> &'static str {
        "dielectric"
    }

    fn is_delta(&self) -> bool {
        true
    }

    fn eval(&self, _: &GpuMaterial, _: &Site, _: Vec3, _: Vec3) -> LobeEval {
        LobeEval::ZERO
    }

    /// Reads u.x only.
    fn sample(&self, m: &GpuMaterial, s: &Site, v: Vec3, u: Vec3) -> LobeSample {
        let (eta_i, eta_t) = dielectric_etas(m, s.inside);
        let d = -v;
        let surface = surface(s);
        let r = refraction_at(d, &surface, eta_i, eta_t);
        let (dir, refracted) = if u.x < r.fresnel {
            (reflection_dir(d, &surface), false)
        } else if m.thin_walled != 0 {
            (d, false)
        } else {
            (r.dir, true)
        };
        LobeSample {
            dir,
            weight: Vec3::ONE,
            pdf: 0.0,
            refracted,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::check::*;
    use super::*;

    /// Glass reflects with the Fresnel reflectance's frequency (4% head on
    /// for index 1.5, all past the critical angle from inside), refracts
    /// by Snell's law, and every sample carries all its light: a white
    /// furnace gives exactly 1.
    #[test]
    fn smooth_glass_reflects_by_fresnel_refracts_by_snell_and_loses_nothing() {
        let m = material(|m| m.transmission = 1.0);
        // The textbook reflectance, in f64: the mean of the s and p
        // polarisations, 1 past the critical angle.
        let fresnel = |theta: f64, eta_i: f64, eta_t: f64| {
            let sin_t = eta_i / eta_t * theta.sin();
            if sin_t >= 1.0 {
                return 1.0;
            }
            let (ci, ct) = (theta.cos(), (1.0 - sin_t * sin_t).sqrt());
            let rs = (eta_i * ci - eta_t * ct) / (eta_i * ci + eta_t * ct);
            let rp = (eta_t * ci - eta_i * ct) / (eta_t * ci + eta_i * ct);
            0.5 * (rs * rs + rp * rp)
        };
        for (inside, theta) in [(false, 0.0f32), (true, 0.8), (false, 1.2), (true, 0.3)] {
            let expected = match inside {
                true => fresnel(theta as f64, 1.5, 1.0),
                false => fresnel(theta as f64, 1.0, 1.5),
            } as f32;
            let s = Site {
                inside,
                ..Site::flat(Vec3::Z)
            };
            let v = Vec3::new(theta.sin(), 0.0, theta.cos());
            let mut rng = Rng::new(9);
            let (mut reflected, n) = (0usize, 100_000);
            for _ in 0..n {
                let smp = Dielectric.sample(&m, &s, v, rng.next3());
                assert_eq!(smp.weight, Vec3::ONE);
                if smp.dir.z > 0.0 {
                    reflected += 1;
                    assert!((smp.dir - Vec3::new(-v.x, 0.0, v.z)).length() < 1e-5);
                } else {
                    let (ei, et) = if inside { (1.5, 1.0) } else { (1.0, 1.5) };
                    let sin_t = (smp.dir.x * smp.dir.x + smp.dir.y * smp.dir.y).sqrt();
                    assert!((ei * theta.sin() - et * sin_t).abs() < 1e-5);
                    assert!(smp.refracted);
                }
            }
            let share = reflected as f32 / n as f32;
            assert!((share - expected).abs() < 0.005, "{share} vs {expected}");
        }
    }

    #[test]
    fn thin_walled_smooth_glass_passes_light_unbent() {
        let m = material(|m| {
            m.transmission = 1.0;
            m.thin_walled = 1;
        });
        let v = Vec3::new(0.6, 0.0, 0.8);
        let mut rng = Rng::new(1);
        for _ in 0..1000 {
            let smp = Dielectric.sample(&m, &Site::flat(Vec3::Z), v, rng.next3());
            if smp.dir.z < 0.0 {
                assert_eq!(smp.dir, -v);
                assert!(!smp.refracted);
            }
        }
    }
}
