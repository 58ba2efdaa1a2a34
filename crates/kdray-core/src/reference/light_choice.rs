//! Which light a shadow ray aims at ([`LightId`], in the scene's terms) and
//! the path tracer's chance of picking each from a shading point
//! ([`LightChoice`]): computed here from the scene itself, in f64, a scene
//! light's or the sky's as its share of the total power (the powers of
//! `layout::light_picks`), an emitter's as the emitters' share times the
//! probability of the light tree's walk from p ending at it
//! (`layout::light_tree`, the tree built from the scene's own emitters and
//! its importances computed in f64), without the blocks, f32 distributions
//! and binary searches the kernel picks through, so tests can hold the
//! probabilities the inspect kernel logs to it.

use std::f64::consts::PI;

use glam::{DVec3, Vec3};

use crate::geometry::Primitives;
use crate::layout::light_picks::{scene_radius, sky_power, tree_weights};
use crate::layout::light_tree::{LightBounds, LightTree};
use crate::scene::{LightKind, Scene};

/// A light as a user knows it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum LightId {
    /// The scene's `[[lights]]` entry of this index (point, spot or
    /// directional).
    Scene(u32),
    /// An object whose material emits, by its id (spheres first, then
    /// triangles, as hits name them).
    Emitter(u32),
    /// The sky image (`[environment] image`).
    Sky,
}

/// The light a shadow ray aims at and the probability it was picked with.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AimedLight {
    pub light: LightId,
    /// 1 in the Whitted integrator: every light gets its shadow ray.
    pub pick: f32,
}

/// The path tracer's lights (the scene's lights, the emitters, the sky
/// image) with the probability of picking each.
#[derive(Debug, Clone, PartialEq)]
pub struct LightChoice {
    /// Each light with its share of the power (an emitter's alone, not the
    /// probability of picking it: see [`LightChoice::probability`]).
    pub lights: Vec<(LightId, f64)>,
    /// The emitters' light tree, and its emitters' object ids.
    pub tree: LightTree,
    pub tree_emitters: Vec<u32>,
}

/// Rec. 709 luminance.
fn luminance(c: DVec3) -> f64 {
    0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z
}

impl LightChoice {
    /// Each light's power over the total (an entry of zero power is never
    /// picked; all zero: the same chance each), powers as
    /// `layout::light_picks` defines them, from the scene's f64 values;
    /// the scene's radius is that of the box around its objects.
    pub fn of(scene: &Scene) -> LightChoice {
        let prims = Primitives::from_scene(scene);
        let radius = scene_radius(&prims.scene_bounds());
        let mut lights: Vec<(LightId, f64)> = Vec::new();
        for (i, l) in scene.lights.iter().enumerate() {
            let intensity = luminance(l.diffuse) * l.path_intensity_scale();
            let power = match l.kind {
                LightKind::Point => 4.0 * PI * intensity,
                LightKind::Spot { outer_degrees, .. } => {
                    intensity * 2.0 * PI * (1.0 - outer_degrees.to_radians().cos())
                }
                LightKind::Directional { .. } => luminance(l.diffuse) * PI * radius * radius,
            };
            lights.push((LightId::Scene(i as u32), power));
        }
        let emission = |material: u32| {
            let m = &scene.materials[material as usize];
            (m.physical.emission, m.physical.two_sided)
        };
        // The tree's emitters: their bounds from the objects in f32, as the
        // kernel has them, keyed by object id.
        let mut tree_input = Vec::new();
        for (i, s) in scene.spheres.iter().enumerate() {
            let (e, _) = emission(s.material);
            if e.cmpgt(DVec3::ZERO).any() {
                let power = PI * 4.0 * PI * s.radius * s.radius * luminance(e);
                lights.push((LightId::Emitter(i as u32), power));
                let f = &prims.spheres[i];
                tree_input.push((i as u32, LightBounds::sphere(f.center, f.radius, power)));
            }
        }
        for (i, t) in scene.triangles.iter().enumerate() {
            let (e, two_sided) = emission(t.material);
            if e.cmpgt(DVec3::ZERO).any() {
                let [a, b, c] = t.vertices;
                let area = 0.5 * (b - a).cross(c - a).length();
                let sides = if two_sided { 2.0 } else { 1.0 };
                let id = (scene.spheres.len() + i) as u32;
                let power = sides * PI * area * luminance(e);
                lights.push((LightId::Emitter(id), power));
                let v = prims.triangles[i].v;
                tree_input.push((id, LightBounds::triangle(v, power, two_sided)));
            }
        }
        let tree_emitters = tree_input.iter().map(|&(id, _)| id).collect();
        let tree = LightTree::build(&tree_weights(tree_input));
        if let Some(env) = &scene.environment {
            lights.push((LightId::Sky, sky_power(env, radius)));
        }
        let power = |w: f64| if w > 0.0 && w.is_finite() { w } else { 0.0 };
        let total: f64 = lights.iter().map(|&(_, w)| power(w)).sum();
        let count = lights.len().max(1) as f64;
        for (_, w) in &mut lights {
            *w = match total > 0.0 && total.is_finite() {
                true => power(*w) / total,
                false => 1.0 / count,
            };
        }
        LightChoice {
            lights,
            tree,
            tree_emitters,
        }
    }

    /// The probability of picking `light` from the shading point p, whose
    /// surface's geometric normal (facing the ray) is n (0 for one the
    /// scene lacks): a scene light's or the sky's share of the power; an
    /// emitter's, the emitters' share times the tree's.
    pub fn probability(&self, light: LightId, p: Vec3, n: Vec3) -> f64 {
        let share = |light: LightId| {
            self.lights
                .iter()
                .find(|(id, _)| *id == light)
                .map_or(0.0, |&(_, p)| p)
        };
        let LightId::Emitter(object) = light else {
            return share(light);
        };
        let Some(k) = self.tree_emitters.iter().position(|&id| id == object) else {
            return 0.0;
        };
        let emitters: f64 = self
            .lights
            .iter()
            .filter(|(id, _)| matches!(id, LightId::Emitter(_)))
            .map(|&(_, p)| p)
            .sum();
        emitters * self.tree.pmf(p.as_dvec3(), n.as_dvec3(), k)
    }

    /// The solid-angle density with which next-event estimation at `p`
    /// (normal `n`, as for [`LightChoice::probability`]) picks the
    /// direction toward `q`, a point on emitter `object` (the pick
    /// included): uniform over the cone a sphere subtends, uniform by
    /// area over a triangle. None for an object that does not emit, a point
    /// inside its sphere or behind its triangle's emitting side.
    pub fn emitter_density(
        &self,
        scene: &Scene,
        object: u32,
        p: Vec3,
        n: Vec3,
        q: Vec3,
    ) -> Option<f64> {
        let pick = self.probability(LightId::Emitter(object), p, n);
        if pick <= 0.0 {
            return None;
        }
        let (p, q) = (p.as_dvec3(), q.as_dvec3());
        let spheres = scene.spheres.len();
        if let Some(s) = scene.spheres.get(object as usize) {
            let d2 = (s.center - p).length_squared();
            let sin2 = s.radius * s.radius / d2;
            if sin2 >= 1.0 {
                return None;
            }
            let width = 1.0 - (1.0 - sin2).sqrt();
            return Some(pick / (2.0 * PI * width));
        }
        let t = scene.triangles.get(object as usize - spheres)?;
        let [a, b, c] = t.vertices;
        let front = (b - a).cross(c - a);
        let twice_area = front.length();
        let to = q - p;
        let d2 = to.length_squared();
        let mut cos_l = -front.dot(to) / (twice_area * d2.sqrt());
        if scene.materials[t.material as usize].physical.two_sided {
            cos_l = cos_l.abs();
        }
        (cos_l > 0.0).then(|| pick * d2 / (0.5 * twice_area * cos_l))
    }
}
