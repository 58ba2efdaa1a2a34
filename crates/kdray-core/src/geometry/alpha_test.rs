//! The walks' alpha test on the CPU, the mirror of shaders/alpha.wgsl: a
//! triangle whose material has an alpha mode ([`crate::scene::Alpha`]) is
//! not there where its alpha fails, so [`Primitives::intersect`]
//! (primitives.rs) finds no hit at such a point, for every walk and
//! brute force alike, nearest and any hit.
//!
//! The alpha at a hit is the material's factor times, on a textured
//! triangle, its base-colour texture's alpha at the hit's texture
//! coordinates (the barycentrics of the hit point, as the shading reads
//! them), on the base level by the magnification filter
//! ([`Texture::sample_alpha`]), times its vertex colours' alpha there. MASK, and BLEND in the Whitted integrator,
//! compare it with a fixed cutoff; BLEND in the path tracer with a number
//! in (0, 1] hashed from the ray and the object, so that a ray passes with
//! probability 1 - alpha and every walk of that ray decides alike.
//!
//! [`Primitives::intersect`]: super::Primitives::intersect

use glam::{Vec2, Vec3};

use super::ray::Ray;
use super::triangle::{barycentrics, TriangleF32};
use crate::scene::{AlphaMode, Integrator, Scene, Texture};

/// A tested material, in the f32 the kernel reads (GpuMaterial).
#[derive(Debug, Clone, PartialEq)]
struct TestedMaterial {
    /// The cutoff is the ray's coverage hash (BLEND, path tracer).
    stochastic: bool,
    cutoff: f32,
    factor: f32,
    /// Index into `AlphaTest::textures`.
    texture: Option<usize>,
}

/// What the alpha test reads of a scene with at least one tested material.
#[derive(Debug, Clone, PartialEq)]
pub struct AlphaTest {
    /// Per triangle (scene order): index into `materials`, or
    /// [`AlphaTest::UNTESTED`] where its material is opaque.
    of_triangle: Vec<u32>,
    materials: Vec<TestedMaterial>,
    /// Per triangle: its texture coordinates where its material's texture
    /// reads them.
    uvs: Vec<Option<[Vec2; 3]>>,
    /// Per triangle: its vertex colours' alphas (as the kernel reads them,
    /// 16-bit unorm) where its material is tested and the scene has them.
    colour_alphas: Vec<Option<[f32; 3]>>,
    /// The tested materials' base-colour textures.
    textures: Vec<Texture>,
}

impl AlphaTest {
    const UNTESTED: u32 = u32::MAX;

    /// The test for `scene`'s triangles; None where no material is tested
    /// (the walks then pay nothing for it).
    pub fn for_scene(scene: &Scene) -> Option<AlphaTest> {
        if !scene.materials.iter().any(|m| m.alpha.is_tested()) {
            return None;
        }
        let stochastic_blend = scene.render.integrator == Integrator::Path;
        let mut textures: Vec<Texture> = Vec::new();
        let mut texture_of: Vec<(u32, usize)> = Vec::new();
        let mut index = Vec::with_capacity(scene.materials.len());
        let mut materials = Vec::new();
        for m in &scene.materials {
            if !m.alpha.is_tested() {
                index.push(Self::UNTESTED);
                continue;
            }
            let texture = m.texture.and_then(|t| {
                if let Some(&(_, i)) = texture_of.iter().find(|(k, _)| *k == t) {
                    return Some(i);
                }
                textures.push(scene.textures.get(t as usize)?.clone());
                texture_of.push((t, textures.len() - 1));
                Some(textures.len() - 1)
            });
            index.push(materials.len() as u32);
            materials.push(TestedMaterial {
                stochastic: stochastic_blend && m.alpha.mode == AlphaMode::Blend,
                cutoff: m.alpha.fixed_cutoff() as f32,
                factor: m.alpha.factor as f32,
                texture,
            });
        }
        let of_triangle: Vec<u32> = scene
            .triangles
            .iter()
            .map(|t| index[t.material as usize])
            .collect();
        let uvs = scene
            .triangles
            .iter()
            .zip(&of_triangle)
            .map(|(t, &m)| match m {
                Self::UNTESTED => None,
                _ => scene.uvs_of(t).map(|uv| uv.map(|c| c.as_vec2())),
            })
            .collect();
        let unorm16 = |a: f64| ((a as f32).clamp(0.0, 1.0) * 65535.0).round() / 65535.0;
        let colour_alphas = scene
            .triangles
            .iter()
            .zip(&of_triangle)
            .map(|(t, &m)| match m {
                Self::UNTESTED => None,
                _ => scene.colours_of(t).map(|c| c.map(|c| unorm16(c.w))),
            })
            .collect();
        Some(AlphaTest {
            of_triangle,
            materials,
            uvs,
            colour_alphas,
            textures,
        })
    }

    /// Whether the hit at `t` along `ray` of triangle `index` (`tri`,
    /// object id `object`) lies in a hole: mirror of `alpha_hole`.
    pub fn is_hole(&self, index: usize, object: u32, tri: &TriangleF32, ray: &Ray, t: f32) -> bool {
        let Some(m) = self.materials.get(self.of_triangle[index] as usize) else {
            return false;
        };
        let mut alpha = m.factor;
        let b = || barycentrics(&tri.v, ray.origin + t * ray.dir);
        if let (Some(texture), Some(uvs)) = (m.texture, self.uvs[index]) {
            let b = b();
            let uv = b.x * uvs[0] + b.y * uvs[1] + b.z * uvs[2];
            alpha *= self.textures[texture].sample_alpha(uv);
        }
        if let Some(a) = self.colour_alphas[index] {
            let b = b();
            alpha *= b.x * a[0] + b.y * a[1] + b.z * a[2];
        }
        let cutoff = match m.stochastic {
            true => coverage_hash(ray, object),
            false => m.cutoff,
        };
        alpha < cutoff
    }
}

/// PCG's RXS-M-XS hash of one word: mirror of `pcg_hash` in
/// shaders/random.wgsl.
fn pcg_hash(v: u32) -> u32 {
    let state = v.wrapping_mul(747796405).wrapping_add(2891336453);
    let word = ((state >> ((state >> 28) + 4)) ^ state).wrapping_mul(277803737);
    (word >> 22) ^ word
}

/// A number in (0, 1], 24 bits, from the ray's origin and direction (their
/// f32 bits) and the object's id in the scene's order: mirror of
/// `coverage_hash` in shaders/alpha.wgsl.
pub fn coverage_hash(ray: &Ray, object: u32) -> f32 {
    let words = |v: Vec3| v.to_array().map(f32::to_bits);
    let mut h = pcg_hash(object);
    for w in words(ray.origin).into_iter().chain(words(ray.dir)) {
        h = pcg_hash(h ^ w);
    }
    ((h >> 8) + 1) as f32 * (1.0 / 16_777_216.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_coverage_hash_lies_in_the_open_closed_unit_interval_and_spreads_evenly() {
        let mut below_half = 0;
        for i in 0..4000u32 {
            let ray = Ray {
                origin: Vec3::new(i as f32 * 0.01, 1.0, -2.0),
                dir: Vec3::Z,
            };
            let u = coverage_hash(&ray, i % 7);
            assert!(u > 0.0 && u <= 1.0, "{u}");
            below_half += usize::from(u < 0.5);
        }
        assert!(
            (1800..2200).contains(&below_half),
            "{below_half} of 4000 below 0.5"
        );
    }
}
