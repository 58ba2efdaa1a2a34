//! The path tracer's BSDF lobes on the CPU, one file a lobe, each the
//! counterpart of one shaders/bsdf_*.wgsl file with the same arithmetic in
//! f32 (the GPU test `bsdf_lobes` runs both on the same inputs). Each lobe
//! has the interface of shaders/bsdf.wgsl, [`Lobe`]: its value f x |cos|
//! and density for a pair of directions, and a direction sampled from three
//! uniform numbers. The lobes read the material as the kernel does, a
//! [`GpuMaterial`]; their tests (beside each lobe, with the checks of
//! `check.rs`) hold them to their densities and to energy conservation.
//!
//! Directions are unit vectors pointing away from the surface: `v` towards
//! where the path came from, `l` where it goes; the site's shading normal is
//! on `v`'s side.

pub mod dielectric;
pub mod diffuse;
pub mod metal_rough;
pub mod microfacet;
pub mod rough_dielectric;

/// The checks the lobes' tests run, shared with the GPU tests (which run
/// them on the kernel's own samples).
#[cfg(any(test, feature = "test-support"))]
#[doc(hidden)]
pub mod check;

use glam::Vec3;

use crate::layout::GpuMaterial;

pub use dielectric::Dielectric;
pub use diffuse::Diffuse;
pub use metal_rough::MetalRough;
pub use rough_dielectric::RoughDielectric;

/// The kernel's `PI` (shaders/bsdf.wgsl), the same f32.
pub const PI: f32 = std::f32::consts::PI;

/// Smallest GGX alpha (shaders/bsdf.wgsl's `MIN_ALPHA`).
pub const MIN_ALPHA: f32 = 1e-3;

/// Where a lobe is evaluated: the kernel's `Surface` normals and whether
/// the path is inside the object.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Site {
    /// Unit shading normal, on the side of `v`.
    pub shading: Vec3,
    /// Unit geometric normal, on the same side.
    pub geometric: Vec3,
    /// The path is inside the object (a dielectric's indices swap).
    pub inside: bool,
}

impl Site {
    /// A site whose shading normal is its geometric one, outside.
    pub fn flat(n: Vec3) -> Site {
        Site {
            shading: n,
            geometric: n,
            inside: false,
        }
    }
}

/// A lobe's value f x |cos(n, l)| and the density with which its sample
/// picks l (0 for a delta lobe).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LobeEval {
    pub value: Vec3,
    pub pdf: f32,
}

impl LobeEval {
    pub const ZERO: LobeEval = LobeEval {
        value: Vec3::ZERO,
        pdf: 0.0,
    };
}

/// A sampled direction, its weight f |cos| / pdf (a delta lobe's: what it
/// lets through), its density (0: a delta lobe) and whether it crossed into
/// the object.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LobeSample {
    pub dir: Vec3,
    pub weight: Vec3,
    pub pdf: f32,
    pub refracted: bool,
}

/// One BSDF lobe: shaders/bsdf.wgsl's interface.
pub trait Lobe {
    /// Its name in the kernel: the WGSL functions are `NAME_eval`,
    /// `NAME_pdf` and `NAME_sample`.
    fn name(&self) -> &'static str;
    /// Whether it is a delta lobe (no density; `eval` is zero).
    fn is_delta(&self) -> bool {
        false
    }
    fn eval(&self, m: &GpuMaterial, s: &Site, v: Vec3, l: Vec3) -> LobeEval;
    fn pdf(&self, m: &GpuMaterial, s: &Site, v: Vec3, l: Vec3) -> f32 {
        self.eval(m, s, v, l).pdf
    }
    /// A direction from `u`, three numbers in [0, 1).
    fn sample(&self, m: &GpuMaterial, s: &Site, v: Vec3, u: Vec3) -> LobeSample;
}

/// Every lobe, in the order of the kernel's files.
pub const LOBES: [&(dyn Lobe + Sync); 4] = [&Diffuse, &MetalRough, &Dielectric, &RoughDielectric];

/// An orthonormal basis with n as its third axis (Duff et al. 2017), as
/// the kernel's `tangent_frame`: the columns.
pub fn tangent_frame(n: Vec3) -> [Vec3; 3] {
    let s = if n.z >= 0.0 { 1.0 } else { -1.0 };
    let a = -1.0 / (s + n.z);
    let b = n.x * n.y * a;
    [
        Vec3::new(1.0 + s * n.x * n.x * a, s * b, -s * n.x),
        Vec3::new(b, s + n.y * n.y * a, -n.y),
        n,
    ]
}

/// `f * local`: a local vector in world space.
pub fn from_local(f: &[Vec3; 3], local: Vec3) -> Vec3 {
    f[0] * local.x + f[1] * local.y + f[2] * local.z
}

/// WGSL's `reflect(e, n)`: `e - 2 dot(n, e) n`.
pub fn reflect(e: Vec3, n: Vec3) -> Vec3 {
    e - 2.0 * n.dot(e) * n
}

/// A reflected direction's sample from the lobe's value there: none below
/// the geometric surface or where the density is 0 (the kernel's
/// `reflection_sample`).
pub fn reflection_sample(e: LobeEval, s: &Site, l: Vec3) -> LobeSample {
    if l.dot(s.geometric) <= 0.0 || e.pdf <= 0.0 {
        return LobeSample {
            dir: l,
            weight: Vec3::ZERO,
            pdf: 0.0,
            refracted: false,
        };
    }
    LobeSample {
        dir: l,
        weight: e.value / e.pdf,
        pdf: e.pdf,
        refracted: false,
    }
}

/// The indices on v's side and beyond (the kernel's `dielectric_etas`).
pub fn dielectric_etas(m: &GpuMaterial, inside: bool) -> (f32, f32) {
    if inside && m.thin_walled == 0 {
        (m.ior, 1.0)
    } else {
        (1.0, m.ior)
    }
}
