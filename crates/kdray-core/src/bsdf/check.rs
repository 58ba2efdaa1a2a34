//! The checks every lobe's tests run (and tests/gpu/bsdf_lobes.rs on the
//! kernel's samples): its density integrated
//! over the sphere, a chi-square test of its samples against that density
//! (as Mitsuba 3 tests its BSDFs), reciprocity, and a white furnace.

use glam::Vec3;

use super::{from_local, tangent_frame, Lobe, LobeSample, Site, PI};
use crate::layout::{GpuMaterial, MODEL_LAMBERTIAN};

/// A material with every field the lobes read at a neutral value (glass
/// of index 1.5, roughness 0.5), changed by `f`.
pub fn material(f: impl FnOnce(&mut GpuMaterial)) -> GpuMaterial {
    let mut m = GpuMaterial {
        ambient: [0.0; 3],
        shininess: 0.0,
        diffuse: [0.8; 3],
        reflection: 0.0,
        specular: [0.0; 3],
        transmission: 0.0,
        ior: 1.5,
        texture: GpuMaterial::NO_TEXTURE,
        metallic: 0.0,
        roughness: 0.5,
        emission: [0.0; 3],
        model: MODEL_LAMBERTIAN,
        metal_rough_texture: GpuMaterial::NO_TEXTURE,
        emissive_texture: GpuMaterial::NO_TEXTURE,
        normal_texture: GpuMaterial::NO_TEXTURE,
        normal_scale: 1.0,
        alpha_mode: 0,
        alpha_cutoff: 0.5,
        alpha_factor: 1.0,
        occlusion_texture: GpuMaterial::NO_TEXTURE,
        occlusion_strength: 1.0,
        uv_channels: 0,
        two_sided: 0,
        transmission_roughness: 0.5,
        absorption: [0.0; 3],
        thin_walled: 0,
    };
    f(&mut m);
    m
}

/// Sites and incoming directions the checks run at: a normal along z and
/// a tilted one, directions from near the normal to grazing.
pub fn views() -> Vec<(Site, Vec3)> {
    let mut out = Vec::new();
    for n in [Vec3::Z, Vec3::new(0.3, -0.5, 0.8).normalize()] {
        let f = tangent_frame(n);
        for theta in [0.15f32, 0.9, 1.35] {
            let local = Vec3::new(theta.sin() * 0.6, theta.sin() * 0.8, theta.cos());
            out.push((Site::flat(n), from_local(&f, local).normalize()));
        }
    }
    out
}

/// A deterministic generator of uniform numbers in [0, 1) (PCG32).
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Rng {
        Rng(seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407))
    }

    pub fn uniform(&mut self) -> f32 {
        let old = self.0;
        self.0 = old
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let xorshifted = (((old >> 18) ^ old) >> 27) as u32;
        let rot = (old >> 59) as u32;
        let x = xorshifted.rotate_right(rot);
        (x >> 8) as f32 / (1u32 << 24) as f32
    }

    pub fn next3(&mut self) -> Vec3 {
        Vec3::new(self.uniform(), self.uniform(), self.uniform())
    }
}

/// The direction at polar angle theta and azimuth phi about the site's
/// shading normal.
fn direction(s: &Site, theta: f64, phi: f64) -> Vec3 {
    let local = Vec3::new(
        (theta.sin() * phi.cos()) as f32,
        (theta.sin() * phi.sin()) as f32,
        theta.cos() as f32,
    );
    from_local(&tangent_frame(s.shading), local).normalize()
}

/// Cells of the sphere: `THETA_CELLS` bands of equal polar angle about the
/// shading normal (fine at the poles, where a lobe seen head on peaks)
/// times `PHI_CELLS`.
const THETA_CELLS: usize = 30;
const PHI_CELLS: usize = 40;
/// Midpoint rule within each cell, per axis.
const SUB_THETA: usize = 16;
const SUB_PHI: usize = 8;

/// The integral of `g` over each cell of the sphere (midpoint rule in
/// theta and phi, weighed by sin theta).
fn cell_integrals(s: &Site, g: impl Fn(Vec3) -> f64) -> Vec<f64> {
    use std::f64::consts::PI as PI64;
    let dt = PI64 / (THETA_CELLS * SUB_THETA) as f64;
    let dp = 2.0 * PI64 / (PHI_CELLS * SUB_PHI) as f64;
    let mut cells = vec![0.0; THETA_CELLS * PHI_CELLS];
    for i in 0..THETA_CELLS * SUB_THETA {
        let t = (i as f64 + 0.5) * dt;
        let area = t.sin() * dt * dp;
        for j in 0..PHI_CELLS * SUB_PHI {
            let p = (j as f64 + 0.5) * dp;
            cells[(i / SUB_THETA) * PHI_CELLS + j / SUB_PHI] += g(direction(s, t, p)) * area;
        }
    }
    cells
}

/// The cell a direction falls in.
fn cell_of(s: &Site, d: Vec3) -> usize {
    use std::f64::consts::PI as PI64;
    let f = tangent_frame(s.shading);
    let (x, y, z) = (d.dot(f[0]) as f64, d.dot(f[1]) as f64, d.dot(f[2]) as f64);
    let theta = z.clamp(-1.0, 1.0).acos();
    let i = ((theta / PI64 * THETA_CELLS as f64) as usize).min(THETA_CELLS - 1);
    let mut phi = y.atan2(x);
    if phi < 0.0 {
        phi += 2.0 * PI64;
    }
    let j = ((phi / (2.0 * PI64) * PHI_CELLS as f64) as usize).min(PHI_CELLS - 1);
    i * PHI_CELLS + j
}

const SAMPLES: usize = 200_000;

/// The integral of the lobe's pdf over the sphere equals the share of its
/// samples that are directions (the rest, a microfacet's reflection below
/// the surface, are none), within the quadrature's and the count's error.
pub fn assert_pdf_integrates_to_sampled_share(
    lobe: &dyn Lobe,
    m: &GpuMaterial,
    (s, v): (Site, Vec3),
) {
    let integral: f64 = cell_integrals(&s, |l| lobe.pdf(m, &s, v, l) as f64)
        .iter()
        .sum();
    let mut rng = Rng::new(7);
    let valid = (0..SAMPLES)
        .filter(|_| lobe.sample(m, &s, v, rng.next3()).pdf > 0.0)
        .count() as f64
        / SAMPLES as f64;
    assert!(
        (integral - valid).abs() < 0.01 && integral <= 1.005,
        "{}: the pdf integrates to {integral}, {valid} of the samples are directions (v {v})",
        lobe.name()
    );
}

/// Pearson's statistic of the lobe's samples against its pdf, and its
/// degrees of freedom: cells whose expected count is below 5 pooled, the
/// samples that are no direction a cell of their own.
pub fn chi_square(
    lobe: &dyn Lobe,
    m: &GpuMaterial,
    (s, v): (Site, Vec3),
    seed: u64,
) -> (f64, usize) {
    let mut rng = Rng::new(seed);
    let samples: Vec<LobeSample> = (0..SAMPLES)
        .map(|_| lobe.sample(m, &s, v, rng.next3()))
        .collect();
    chi_square_of(lobe, m, (s, v), &samples)
}

/// [`chi_square`] of given samples (the kernel's, say) against the lobe's
/// pdf.
pub fn chi_square_of(
    lobe: &dyn Lobe,
    m: &GpuMaterial,
    (s, v): (Site, Vec3),
    samples: &[LobeSample],
) -> (f64, usize) {
    let count = samples.len() as f64;
    let expected: Vec<f64> = cell_integrals(&s, |l| lobe.pdf(m, &s, v, l) as f64)
        .into_iter()
        .map(|p| p * count)
        .collect();
    let mut observed = vec![0.0f64; expected.len()];
    let mut none = 0.0;
    for smp in samples {
        if smp.pdf > 0.0 {
            observed[cell_of(&s, smp.dir)] += 1.0;
        } else {
            none += 1.0;
        }
    }
    let none_expected = (count - expected.iter().sum::<f64>()).max(0.0);
    let mut cells: Vec<(f64, f64)> = observed.into_iter().zip(expected).collect();
    cells.push((none, none_expected));
    let (mut statistic, mut dof) = (0.0, 0usize);
    let (mut pooled_o, mut pooled_e) = (0.0, 0.0);
    for (o, e) in cells {
        if e < 5.0 {
            pooled_o += o;
            pooled_e += e;
        } else {
            statistic += (o - e) * (o - e) / e;
            dof += 1;
        }
    }
    if pooled_e >= 5.0 {
        statistic += (pooled_o - pooled_e) * (pooled_o - pooled_e) / pooled_e;
        dof += 1;
    } else if pooled_o > 10.0 {
        statistic += f64::INFINITY; // samples where the pdf says there are none
    }
    (statistic, dof.saturating_sub(1))
}

/// The standard normal deviate of a chi-square statistic with `dof`
/// degrees of freedom (Wilson and Hilferty 1931).
pub fn chi_square_z(statistic: f64, dof: usize) -> f64 {
    let k = dof.max(1) as f64;
    ((statistic / k).powf(1.0 / 3.0) - (1.0 - 2.0 / (9.0 * k))) / (2.0 / (9.0 * k)).sqrt()
}

/// The samples' histogram fits the pdf: the statistic's deviate below 4
/// (a chance of about 3e-5 of failing a correct lobe).
pub fn assert_samples_follow_pdf(lobe: &dyn Lobe, m: &GpuMaterial, view: (Site, Vec3)) {
    let (statistic, dof) = chi_square(lobe, m, view, 11);
    let z = chi_square_z(statistic, dof);
    assert!(
        z < 4.0,
        "{}: chi-square {statistic} with {dof} degrees of freedom (z = {z}) at v {}",
        lobe.name(),
        view.1
    );
}

/// f(v, l) / eta_l^2 = f(l, v) / eta_v^2 for directions on both sides
/// (eta the index on each direction's side: f is written with the
/// importance of the path tracer, so a transmission differs by the indices'
/// squares; reflection and equal indices are reciprocal as they are).
pub fn assert_reciprocal(lobe: &dyn Lobe, m: &GpuMaterial) {
    let mut rng = Rng::new(3);
    let mut compared = 0;
    for _ in 0..2000 {
        let v = uniform_sphere(rng.uniform(), rng.uniform());
        let l = uniform_sphere(rng.uniform(), rng.uniform());
        let n = Vec3::Z;
        if v.z.abs() < 0.05 || l.z.abs() < 0.05 {
            continue;
        }
        // Each side's own site: its normal faces its direction.
        let site = |d: Vec3| Site {
            shading: n * d.z.signum(),
            geometric: n * d.z.signum(),
            inside: d.z < 0.0,
        };
        let eta = |d: Vec3| {
            if d.z < 0.0 && m.thin_walled == 0 {
                m.ior
            } else {
                1.0
            }
        };
        let forward = lobe.eval(m, &site(v), v, l).value / (l.z.abs() * eta(l) * eta(l));
        let backward = lobe.eval(m, &site(l), l, v).value / (v.z.abs() * eta(v) * eta(v));
        let scale = forward.max_element().max(backward.max_element());
        if scale > 0.0 {
            compared += 1;
        }
        assert!(
            (forward - backward).abs().max_element() <= 2e-3 * scale + 1e-6,
            "{}: f(v, l) {forward} but f(l, v) {backward} (v {v}, l {l})",
            lobe.name()
        );
    }
    assert!(
        compared > 100,
        "{}: only {compared} non-zero pairs",
        lobe.name()
    );
}

pub fn uniform_sphere(u1: f32, u2: f32) -> Vec3 {
    let z = 1.0 - 2.0 * u1;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * u2;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// The lobe's albedo from v for a white furnace, two ways: the integral
/// of its value over the sphere (quadrature; the largest channel), and the
/// mean weight of its samples (a sample that is no direction weighs 0;
/// exact for a delta lobe).
pub fn furnace(lobe: &dyn Lobe, m: &GpuMaterial, (s, v): (Site, Vec3)) -> (f64, f64) {
    let by_eval: f64 = cell_integrals(&s, |l| lobe.eval(m, &s, v, l).value.max_element() as f64)
        .iter()
        .sum();
    let mut rng = Rng::new(5);
    let by_samples = (0..SAMPLES)
        .map(|_| lobe.sample(m, &s, v, rng.next3()).weight.max_element() as f64)
        .sum::<f64>()
        / SAMPLES as f64;
    (by_eval, by_samples)
}
