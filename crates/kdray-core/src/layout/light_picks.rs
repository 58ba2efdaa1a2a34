//! How the path tracer's next-event estimation picks a light
//! (shaders/emitters.wgsl, `sample_light`): the scene's lights, the
//! emitters together, and the sky image by power, through a cumulative
//! distribution built here and stored in the lights buffer's entries
//! (`GpuLight::pick`, `cdf` and `beyond`); one emitter among the emitters
//! through the light tree (`light_tree`), built here too, whose nodes
//! follow the emitters' entries in the lights buffer.
//!
//! The choice runs through three blocks, in the buffer's order: the scene's
//! lights, the emitters, the sky image. A scene light's entry holds its
//! probability (`pick`) and the sum of the picks before it (`cdf`); each
//! holds the probability of passing the scene lights (`beyond`): that the
//! choice falls on an emitter or the sky. Each emitter's entry holds the
//! probability of the emitters' block given that the choice passed the
//! scene lights (`pick`), that of the sky (`beyond`, 1 - `pick` in f32),
//! and its leaf in the tree (`leaf`). So the emitters' entries and the
//! tree depend on the emitters and the sky alone, which no frame changes,
//! and an animation's frame rewrites the scene lights' entries only, their
//! picks rebuilt with them ([`LightPicks::scene_lights`]).
//!
//! Power, in watts up to one constant factor, from the luminance of RGB
//! (Rec. 709 weights), I a radiant intensity and L a radiance:
//! - point light: 4 pi I, with I = `diffuse * path_scale` as the kernel has it;
//! - spot light: I 2 pi (1 - cos outer), its outer cone's solid angle: an
//!   upper bound (its falloff is at most 1);
//! - directional light: E pi R^2, E its irradiance (`diffuse`) and R the
//!   radius of the sphere around the scene's box: what falls on the scene;
//! - emissive triangle: pi A L, twice that two-sided, L the material's
//!   emission factor times, where the kernel reads an emissive texture on
//!   the triangle, that texture's mean linear colour (over the whole image,
//!   not the triangle's part of it: a weight, not the emission);
//! - emissive sphere: pi 4 pi r^2 L;
//! - the sky image: pi 4 pi R^2 times its mean radiance over the sphere of
//!   directions (with its intensity).
//!
//! An entry of zero power is never picked (an emitter of zero power is left
//! out of the tree); where every power is zero, the choice is uniform over
//! the entries (the emitters' block weighing as many entries as it holds,
//! and the tree weighing its emitters alike).

use std::f64::consts::PI;

use super::light::{GpuLight, LIGHT_DIRECTIONAL, LIGHT_EMITTER, LIGHT_SPOT};
use super::light_tree::{LightBounds, LightTree};
use super::material::GpuMaterial;
use super::objects::{GpuSphere, GpuTriangle};
use crate::geometry::Aabb;
use crate::scene::EnvironmentMap;

/// Rec. 709 luminance of linear RGB.
fn luminance(c: [f32; 3]) -> f64 {
    0.2126 * c[0] as f64 + 0.7152 * c[1] as f64 + 0.0722 * c[2] as f64
}

/// The radius of the sphere around `bounds` (0 for an empty box).
pub fn scene_radius(bounds: &Aabb) -> f64 {
    if bounds.is_empty() {
        return 0.0;
    }
    0.5 * (bounds.max - bounds.min).as_dvec3().length()
}

/// A scene light's power (point, spot or directional).
pub fn scene_light_power(light: &GpuLight, scene_radius: f64) -> f64 {
    let intensity = luminance(light.diffuse) * light.path_scale as f64;
    match light.kind {
        LIGHT_DIRECTIONAL => luminance(light.diffuse) * PI * scene_radius * scene_radius,
        LIGHT_SPOT => intensity * 2.0 * PI * (1.0 - light.cos_outer as f64),
        _ => 4.0 * PI * intensity,
    }
}

/// An emissive sphere's power, `emission` its radiance.
pub fn sphere_power(sphere: &GpuSphere, emission: [f32; 3]) -> f64 {
    let r = sphere.radius as f64;
    PI * 4.0 * PI * r * r * luminance(emission)
}

/// An emissive triangle's power, `emission` its radiance on each side that
/// emits.
pub fn triangle_power(triangle: &GpuTriangle, emission: [f32; 3], two_sided: bool) -> f64 {
    let v = [triangle.v0, triangle.v1, triangle.v2].map(|p| glam::Vec3::from(p).as_dvec3());
    let area = 0.5 * (v[1] - v[0]).cross(v[2] - v[0]).length();
    let sides = if two_sided { 2.0 } else { 1.0 };
    sides * PI * area * luminance(emission)
}

/// The sky image's power: pi 4 pi R^2 times its mean radiance, each row of
/// texels weighted by its exact solid angle.
pub fn sky_power(env: &EnvironmentMap, scene_radius: f64) -> f64 {
    let (w, h) = (env.width as usize, env.height as usize);
    let mut sum = 0.0; // luminance times solid angle
    for row in 0..h {
        let top = (row as f64 / h as f64 * PI).cos();
        let bottom = ((row + 1) as f64 / h as f64 * PI).cos();
        let solid_angle = 2.0 * PI / w as f64 * (top - bottom);
        let texels = &env.texels[row * w..(row + 1) * w];
        sum += texels.iter().map(|&t| luminance(t)).sum::<f64>() * solid_angle;
    }
    let mean = env.intensity * sum / (4.0 * PI);
    PI * 4.0 * PI * scene_radius * scene_radius * mean
}

/// One block's picks, as the kernel reads them ([`GpuLight::pick`], `cdf`,
/// `beyond`).
#[derive(Debug, Clone, PartialEq)]
pub struct Block {
    pub picks: Vec<f32>,
    pub cdfs: Vec<f32>,
    pub beyond: f32,
}

/// The picks of a block of entries of power `weights`, followed by
/// `beyond_count` entries of total power `beyond_power`. Each pick is the
/// width of its entry's interval in the f32 distribution the kernel
/// searches (the last `cdf` of the block with `cdf <= u`, for `u` below
/// `1 - beyond` computed in f32), so the probability the kernel uses is the
/// one it samples with, to f32 rounding. A weight that is not a positive
/// number counts as 0; if the block's and the rest's are all 0, every entry
/// has the same chance.
pub fn block(weights: &[f64], beyond_power: f64, beyond_count: usize) -> Block {
    let power = |w: f64| if w > 0.0 && w.is_finite() { w } else { 0.0 };
    let beyond_power = power(beyond_power);
    let total = weights.iter().map(|&w| power(w)).sum::<f64>() + beyond_power;
    let entries = weights.len() + beyond_count;
    let (shares, beyond): (Vec<f64>, f64) = if total > 0.0 && total.is_finite() {
        let shares = weights.iter().map(|&w| power(w) / total).collect();
        (shares, beyond_power / total)
    } else {
        let each = 1.0 / entries.max(1) as f64;
        (vec![each; weights.len()], beyond_count as f64 * each)
    };
    let beyond = beyond as f32;
    // Where the kernel's block ends: `1.0 - beyond` in f32.
    let end = 1.0 - beyond;
    let mut cdfs = Vec::with_capacity(weights.len());
    let mut running = 0.0f64;
    for share in shares {
        cdfs.push((running as f32).min(end));
        running += share;
    }
    let picks = (0..cdfs.len())
        .map(|i| {
            let next = cdfs.get(i + 1).copied().unwrap_or(end);
            (next as f64 - cdfs[i] as f64) as f32
        })
        .collect();
    Block {
        picks,
        cdfs,
        beyond,
    }
}

/// The tree's weights: the emitters' powers, where some is positive; else
/// the same for each (the uniform choice of the module header).
pub fn tree_weights(mut emitters: Vec<(u32, LightBounds)>) -> Vec<(u32, LightBounds)> {
    let positive = |w: f64| w > 0.0 && w.is_finite();
    if !emitters.iter().any(|(_, b)| positive(b.phi)) {
        for (_, b) in &mut emitters {
            b.phi = 1.0;
        }
    }
    emitters
}

/// Writes `block`'s values into `entries`, one each.
fn store(entries: &mut [GpuLight], block: &Block) {
    for (i, e) in entries.iter_mut().enumerate() {
        e.pick = block.picks[i];
        e.cdf = block.cdfs[i];
        e.beyond = block.beyond;
    }
}

/// What the scene lights' picks depend on besides the scene lights: kept
/// with the scene's arrays, so that a frame's lights get theirs
/// ([`LightPicks::scene_lights`]).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct LightPicks {
    /// The radius of the sphere around the scene's box.
    pub scene_radius: f64,
    /// The emitters' and the sky's power, together.
    pub emitters_and_sky_power: f64,
    /// The emitters and the sky image (0 or 1): the entries after the scene
    /// lights.
    pub emitters_and_sky: u32,
}

impl LightPicks {
    /// The emitters' entries (one per emissive object, in order of GPU id,
    /// as [`GpuLight`]s of kind `LIGHT_EMITTER` with their block's pick and
    /// their leaf), the light tree over them, and what the scene lights'
    /// picks need. `objects` are the kernel's (material, scene id) by GPU
    /// id, spheres first; `emissive_means` by material, the mean linear
    /// colour of the emissive texture the kernel reads for it, if any.
    pub fn with_emitters(
        objects: &[[u32; 2]],
        materials: &[GpuMaterial],
        emissive_means: &[Option<[f64; 3]>],
        spheres: &[GpuSphere],
        triangles: &[GpuTriangle],
        sky: Option<&EnvironmentMap>,
        bounds: &Aabb,
    ) -> (Vec<GpuLight>, LightTree, LightPicks) {
        let scene_radius = scene_radius(bounds);
        let mut emitters = Vec::new();
        let mut tree_input = Vec::new();
        for (gpu_id, &[material, scene_id]) in objects.iter().enumerate() {
            let m = &materials[material as usize];
            if !m.emission.iter().any(|&e| e > 0.0) {
                continue;
            }
            tree_input.push(match spheres.get(gpu_id) {
                Some(s) => {
                    let power = sphere_power(s, m.emission);
                    let b = LightBounds::sphere(s.center.into(), s.radius, power);
                    (scene_id, b)
                }
                None => {
                    let triangle = &triangles[gpu_id - spheres.len()];
                    let emission = match emissive_means.get(material as usize) {
                        Some(Some(mean)) if triangle.uvs != GpuTriangle::UNTEXTURED => {
                            std::array::from_fn(|c| (m.emission[c] as f64 * mean[c]) as f32)
                        }
                        _ => m.emission,
                    };
                    let two_sided = m.two_sided != 0;
                    let power = triangle_power(triangle, emission, two_sided);
                    let v = [triangle.v0, triangle.v1, triangle.v2].map(glam::Vec3::from);
                    (scene_id, LightBounds::triangle(v, power, two_sided))
                }
            });
            emitters.push(GpuLight {
                kind: LIGHT_EMITTER,
                object: gpu_id as u32,
                diffuse: m.emission,
                ..bytemuck::Zeroable::zeroed()
            });
        }
        let powers: Vec<f64> = tree_input.iter().map(|(_, b)| b.phi).collect();
        let sky_power = sky.map_or(0.0, |env| sky_power(env, scene_radius));
        let skies = usize::from(sky.is_some());
        let emitters_block = block(&powers, sky_power, skies);
        tree_input = tree_weights(tree_input);
        let tree = LightTree::build(&tree_input);
        for (i, e) in emitters.iter_mut().enumerate() {
            e.pick = 1.0 - emitters_block.beyond;
            e.beyond = emitters_block.beyond;
            e.leaf = tree.leaf_of[i];
        }
        let picks = LightPicks {
            scene_radius,
            emitters_and_sky_power: powers.iter().sum::<f64>() + sky_power,
            emitters_and_sky: (emitters.len() + skies) as u32,
        };
        (emitters, tree, picks)
    }

    /// `lights` (the scene's lights in the GPU layout, in order) with their
    /// picks: the head of the lights buffer, which a frame rewrites.
    pub fn scene_lights(&self, mut lights: Vec<GpuLight>) -> Vec<GpuLight> {
        let powers: Vec<f64> = lights
            .iter()
            .map(|l| scene_light_power(l, self.scene_radius))
            .collect();
        let b = block(
            &powers,
            self.emitters_and_sky_power,
            self.emitters_and_sky as usize,
        );
        store(&mut lights, &b);
        lights
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::layout::LIGHT_POINT;

    fn light(kind: u32, diffuse: [f32; 3]) -> GpuLight {
        GpuLight {
            kind,
            diffuse,
            path_scale: 1.0,
            ..bytemuck::Zeroable::zeroed()
        }
    }

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-6 * b.abs().max(1e-12)
    }

    /// The kernel's choice within a block: the last entry whose cdf is at
    /// most u, below the block's end.
    fn kernel_choice(b: &Block, u: f32) -> Option<usize> {
        if u >= 1.0 - b.beyond {
            return None;
        }
        b.cdfs.iter().rposition(|&c| c <= u)
    }

    #[test]
    fn a_blocks_picks_and_the_rest_sum_to_one() {
        let weights = [3.0, 0.25, 7.5, 1e-3, 40.0, 0.0, 2.0];
        for (beyond_power, count) in [(0.0, 0), (5.0, 3), (0.0, 2), (1e6, 1)] {
            let b = block(&weights, beyond_power, count);
            let sum: f64 = b.picks.iter().map(|&p| p as f64).sum::<f64>() + b.beyond as f64;
            assert!((sum - 1.0).abs() < 1e-6, "{sum}");
            let total = weights.iter().sum::<f64>() + beyond_power;
            for (p, w) in b.picks.iter().zip(weights) {
                assert!((*p as f64 - w / total).abs() < 1e-6, "{p} vs {}", w / total);
            }
            assert_eq!(b.cdfs[0], 0.0);
            assert!(b.cdfs.windows(2).all(|c| c[0] <= c[1]));
        }
    }

    /// Each pick is the share of u in [0, 1) the kernel's search gives its
    /// entry, counted over a fine grid of u.
    #[test]
    fn picks_are_the_shares_the_kernels_search_gives() {
        let weights = [1.0, 0.0, 5.0, 2.5, 0.5];
        let b = block(&weights, 1.0, 1);
        let n = 1 << 20;
        let mut counts = vec![0u32; weights.len() + 1];
        for i in 0..n {
            let u = (i as f64 + 0.5) as f32 / n as f32;
            counts[kernel_choice(&b, u).unwrap_or(weights.len())] += 1;
        }
        for (k, &c) in counts.iter().enumerate() {
            let want = b.picks.get(k).copied().unwrap_or(b.beyond);
            assert!((c as f64 / n as f64 - want as f64).abs() < 1e-5, "{k}");
        }
    }

    #[test]
    fn zero_power_entries_are_never_picked() {
        let weights = [0.0, 2.0, 0.0, 0.0, 3.0, 0.0];
        let b = block(&weights, 0.0, 2);
        assert_eq!(b.beyond, 0.0, "the rest has no power");
        for (k, &w) in weights.iter().enumerate() {
            assert_eq!(b.picks[k] == 0.0, w == 0.0, "{k}");
        }
        for i in 0..4096 {
            let u = i as f32 / 4096.0;
            let k = kernel_choice(&b, u).expect("the block holds all");
            assert!(weights[k] > 0.0, "u {u} picked entry {k}");
        }
        // A zero-power block before a powered rest: the rest takes all.
        let b = block(&[0.0, 0.0], 4.0, 1);
        assert_eq!((b.picks.as_slice(), b.beyond), (&[0.0f32, 0.0][..], 1.0));
    }

    #[test]
    fn all_zero_power_falls_back_to_uniform() {
        let b = block(&[0.0, 0.0, 0.0], 0.0, 1);
        assert_eq!(b.picks, vec![0.25f32; 3]);
        assert_eq!(b.cdfs, vec![0.0, 0.25, 0.5]);
        assert_eq!(b.beyond, 0.25);
        // Chained: a uniform rest under a uniform head is uniform overall.
        let (rest, tree, _) =
            LightPicks::with_emitters(&[], &[], &[], &[], &[], None, &Aabb::EMPTY);
        assert!(rest.is_empty() && tree.nodes.is_empty());
        let picks = LightPicks {
            scene_radius: 1.0,
            emitters_and_sky_power: 0.0,
            emitters_and_sky: 3,
        };
        let lights = picks.scene_lights(vec![light(LIGHT_POINT, [0.0; 3]); 2]);
        for l in lights {
            assert!((l.pick - 0.2).abs() < 1e-7 && (l.beyond - 0.6).abs() < 1e-7);
        }
    }

    #[test]
    fn each_kind_of_light_has_the_power_of_its_formula() {
        let (r, i) = (3.0f64, [2.0f32, 1.0, 0.5]);
        let lum = 0.2126 * 2.0 + 0.7152 + 0.0722 * 0.5;
        let mut point = light(LIGHT_POINT, i);
        point.path_scale = 1.5;
        assert!(close(scene_light_power(&point, r), 4.0 * PI * 1.5 * lum));
        let mut spot = light(LIGHT_SPOT, i);
        spot.cos_outer = 0.8;
        assert!(close(
            scene_light_power(&spot, r),
            lum * 2.0 * PI * (1.0 - 0.8f32 as f64)
        ));
        let sun = light(LIGHT_DIRECTIONAL, i);
        assert!(close(scene_light_power(&sun, r), lum * PI * r * r));
        let sphere = GpuSphere {
            center: [1.0, 2.0, 3.0],
            radius: 0.5,
        };
        assert!(close(sphere_power(&sphere, i), PI * 4.0 * PI * 0.25 * lum));
        let triangle = GpuTriangle {
            v0: [0.0, 0.0, 0.0],
            v1: [2.0, 0.0, 0.0],
            v2: [0.0, 3.0, 0.0],
            ..bytemuck::Zeroable::zeroed()
        };
        assert!(close(triangle_power(&triangle, i, false), PI * 3.0 * lum));
        assert!(close(
            triangle_power(&triangle, i, true),
            2.0 * PI * 3.0 * lum
        ));
        // A uniform sky of radiance L: its mean is L.
        let sky = EnvironmentMap {
            path: "sky.hdr".into(),
            width: 8,
            height: 5,
            texels: vec![i; 40],
            intensity: 2.0,
            rotation_degrees: 30.0,
        };
        assert!(close(sky_power(&sky, r), PI * 4.0 * PI * r * r * 2.0 * lum));
        // The radius of the sphere around a box.
        let bounds = Aabb {
            min: glam::Vec3::new(-1.0, 0.0, 2.0),
            max: glam::Vec3::new(1.0, 2.0, 3.0),
        };
        assert!(close(scene_radius(&bounds), 1.5));
    }

    /// The emitters' entries come in order of object id (the kernel finds
    /// an emitter's entry by a binary search on it), each with the
    /// emitters' share of the power and its leaf in the light tree, which
    /// holds its power; the sky takes the rest.
    #[test]
    fn emitter_entries_are_sorted_by_object_id_with_their_powers() {
        let lit = GpuMaterial {
            emission: [1.0, 1.0, 1.0],
            ..bytemuck::Zeroable::zeroed()
        };
        let dark: GpuMaterial = bytemuck::Zeroable::zeroed();
        let two_sided = GpuMaterial {
            two_sided: 1,
            ..lit
        };
        let spheres = [
            GpuSphere {
                center: [0.0; 3],
                radius: 1.0,
            },
            GpuSphere {
                center: [0.0; 3],
                radius: 2.0,
            },
        ];
        let tri = |s: f32| GpuTriangle {
            v0: [0.0; 3],
            v1: [s, 0.0, 0.0],
            v2: [0.0, s, 0.0],
            ..bytemuck::Zeroable::zeroed()
        };
        let triangles = [tri(1.0), tri(2.0), tri(3.0), tri(4.0)];
        // GPU ids 0, 1 spheres, 2 - 5 triangles; materials 0 lit, 1 dark, 2 two-sided.
        let objects = [[1, 0], [0, 1], [0, 2], [1, 3], [2, 4], [0, 5]];
        let materials = [lit, dark, two_sided];
        let sky = EnvironmentMap {
            path: "sky.hdr".into(),
            width: 2,
            height: 2,
            texels: vec![[0.5; 3]; 4],
            intensity: 1.0,
            rotation_degrees: 0.0,
        };
        let bounds = Aabb {
            min: glam::Vec3::splat(-1.0),
            max: glam::Vec3::splat(1.0),
        };
        let (emitters, tree, picks) = LightPicks::with_emitters(
            &objects,
            &materials,
            &[],
            &spheres,
            &triangles,
            Some(&sky),
            &bounds,
        );
        let ids: Vec<u32> = emitters.iter().map(|e| e.object).collect();
        assert_eq!(ids, [1, 2, 4, 5]);
        assert!(ids.windows(2).all(|w| w[0] < w[1]));
        let powers = [PI * 4.0 * PI * 4.0, PI * 0.5, 2.0 * PI * 4.5, PI * 8.0];
        let sky_power = PI * 4.0 * PI * 3.0 * 0.5;
        let total = powers.iter().sum::<f64>() + sky_power;
        // Each entry holds the emitters' share, its leaf its own power.
        let emitters_share = powers.iter().sum::<f64>() / total;
        for (e, p) in emitters.iter().zip(powers) {
            assert!((e.pick as f64 - emitters_share).abs() < 1e-6);
            assert_eq!(e.pick, 1.0 - e.beyond);
            assert_eq!(e.kind, LIGHT_EMITTER);
            let leaf = tree.nodes[e.leaf as usize];
            assert!(leaf.is_leaf() && close(leaf.phi as f64, p), "{leaf:?}");
        }
        assert_eq!(tree.nodes.len(), 2 * emitters.len() - 1);
        assert!((emitters[0].beyond as f64 - sky_power / total).abs() < 1e-6);
        assert_eq!(picks.emitters_and_sky, 5);
        assert!(close(picks.emitters_and_sky_power, total));
    }

    /// An emissive texture scales a textured triangle's power by its mean
    /// colour's luminance, and leaves an untextured one (which the kernel
    /// lights by the factor alone) as it is.
    #[test]
    fn an_emissive_textures_mean_scales_its_textured_triangles_power() {
        let lit = GpuMaterial {
            emission: [2.0, 2.0, 2.0],
            ..bytemuck::Zeroable::zeroed()
        };
        let tri = |uvs: u32| GpuTriangle {
            v0: [0.0; 3],
            v1: [1.0, 0.0, 0.0],
            v2: [0.0, 1.0, 0.0],
            uvs,
            ..bytemuck::Zeroable::zeroed()
        };
        let triangles = [tri(0), tri(GpuTriangle::UNTEXTURED)];
        let objects = [[0, 0], [0, 1]];
        let powers = |means: &[Option<[f64; 3]>]| {
            let (emitters, tree, _) = LightPicks::with_emitters(
                &objects,
                &[lit],
                means,
                &[],
                &triangles,
                None,
                &Aabb::EMPTY,
            );
            emitters
                .iter()
                .map(|e| tree.nodes[e.leaf as usize].phi as f64)
                .collect::<Vec<_>>()
        };
        let plain = powers(&[None]);
        assert!(close(plain[0], PI * 0.5 * 2.0) && close(plain[1], plain[0]));
        let textured = powers(&[Some([0.25, 0.25, 0.25])]);
        assert!(close(textured[0], plain[0] * 0.25), "{textured:?}");
        assert!(close(textured[1], plain[1]), "{textured:?}");
    }

    /// A frame's scene lights share with the emitters and the sky by power:
    /// brighter lights leave them less.
    #[test]
    fn scene_lights_share_with_the_rest_by_power() {
        let picks = LightPicks {
            scene_radius: 2.0,
            emitters_and_sky_power: 4.0 * PI,
            emitters_and_sky: 10,
        };
        let dim = picks.scene_lights(vec![light(LIGHT_POINT, [1.0; 3])]);
        assert!((dim[0].pick - 0.5).abs() < 1e-6 && (dim[0].beyond - 0.5).abs() < 1e-6);
        let bright = picks.scene_lights(vec![light(LIGHT_POINT, [3.0; 3])]);
        assert!((bright[0].pick - 0.75).abs() < 1e-6 && (bright[0].beyond - 0.25).abs() < 1e-6);
    }
}
