//! The Whitted path loop, mirror of shaders/trace.wgsl, shade.wgsl and
//! glass.wgsl: the path from a camera ray, the stack of pending glass rays,
//! shadow rays through glass, and the shading at each hit.

use glam::Vec3;

use crate::geometry::{spawn_offset, Ray};
use crate::kdtree::traverse::Hit;
use crate::layout::{GLASS_STACK_DEPTH, SHADOW_CROSSINGS};
use crate::scene::{LightKind, ShadowMode};

use super::light_choice::{AimedLight, LightId};
use super::rays::{RayKind, WhittedRay, WhittedStep};
use super::surface::{reflection_dir, refraction_at};
use super::tracer::ReferenceTracer;

impl ReferenceTracer<'_> {
    /// Mirror of `shadow_transmittance` in shaders/glass.wgsl: an any-hit
    /// query first; only a ray whose first blocker found is glass is walked
    /// again, surface by surface.
    fn shadow_transmittance(&self, ray: &Ray, length: f32) -> f32 {
        let Some(first) = self.query(RayKind::Shadow, ray, length, true) else {
            return 1.0;
        };
        if !self.glass || self.material(first.object).transmission == 0.0 {
            return 0.0;
        }
        let mut through = 1.0f32;
        let mut origin = ray.origin;
        let mut remaining = length;
        for crossing in 0..=SHADOW_CROSSINGS {
            let part = Ray {
                origin,
                dir: ray.dir,
            };
            let hit = self.query(RayKind::Shadow, &part, remaining, false);
            let Some(hit) = hit.filter(|h| h.t < remaining) else {
                return through;
            };
            through *= self.material(hit.object).transmission as f32;
            if through == 0.0 || crossing == SHADOW_CROSSINGS {
                return 0.0;
            }
            let p = origin + hit.t * ray.dir;
            let step = spawn_offset(p, self.prims.magnitude(hit.object));
            origin = p + step * ray.dir;
            remaining -= hit.t + step;
            if remaining <= 0.0 {
                return through;
            }
        }
        0.0
    }

    /// Mirror of `trace_whitted` in shaders/trace.wgsl: the colour of one
    /// path (unclamped), and the hits along it (with glass: of every ray the
    /// sample traced, in order).
    pub fn trace_whitted(&self, primary: Ray) -> (Vec3, Vec<Hit>) {
        if self.glass {
            let mut steps = Vec::new();
            let color = self.trace_whitted_glass(primary, &mut steps);
            return (color, steps.iter().filter_map(|s| s.hit).collect());
        }
        let r = &self.scene.render;
        let mut ray = primary;
        let mut color = Vec3::ZERO;
        let mut weight = 1.0f32;
        let mut path_length = 0.0f32;
        let mut hits = Vec::new();
        while weight >= r.min_intensity as f32 && (hits.len() as u32) < r.max_depth {
            let kind = match hits.is_empty() {
                true => RayKind::Primary,
                false => RayKind::Reflected,
            };
            let Some(hit) = self.closest(&ray, kind) else {
                color += weight * r.background.as_vec3();
                break;
            };
            hits.push(hit);
            let p = ray.origin + hit.t * ray.dir;
            let surface = self.mapped_surface(hit.object, p, ray.dir);
            let offset = spawn_offset(p, self.prims.magnitude(hit.object));
            let origin = surface.spawn_point + offset * surface.geometric;
            path_length += hit.t;
            let material = self.material_at(hit.object, p, ray.dir, path_length);
            let m = &*material;
            let (local, any_visible) = self.shade(m, p, surface.shading, -ray.dir, origin);
            if self.scene.render.shadow_mode == ShadowMode::Seed && !any_visible {
                break;
            }
            let reflection = m.reflection as f32;
            color += (1.0 - reflection) * weight * local;
            weight *= reflection;
            if weight == 0.0 {
                break;
            }
            ray = Ray {
                origin,
                dir: reflection_dir(ray.dir, &surface),
            };
        }
        (color, hits)
    }

    /// The rays one sample traces on the glass path, in order (for a scene
    /// with glass; see `trace_whitted_glass`).
    pub fn whitted_steps(&self, primary: Ray) -> (Vec3, Vec<WhittedStep>) {
        let mut steps = Vec::new();
        let color = self.trace_whitted_glass(primary, &mut steps);
        (color, steps)
    }

    /// Mirror of `trace_whitted_glass` in shaders/glass.wgsl: each hit adds
    /// `local_share * weight * local` and splits the rest of the weight into
    /// the mirror ray and the refracted ray; the sample follows the
    /// refracted ray and pushes the mirror ray on a stack of at most
    /// [`GLASS_STACK_DEPTH`] (if it would be traced and there is room), and
    /// resumes from the stack's top when a path ends.
    fn trace_whitted_glass(&self, primary: Ray, steps: &mut Vec<WhittedStep>) -> Vec3 {
        let r = &self.scene.render;
        let min_intensity = r.min_intensity as f32;
        let traced = |p: &WhittedRay| p.weight >= min_intensity && p.hits < r.max_depth;
        let mut pending: Vec<WhittedRay> = Vec::new();
        let mut path = WhittedRay {
            ray: primary,
            kind: RayKind::Primary,
            weight: 1.0,
            hits: 0,
            path_length: 0.0,
            inside: false,
        };
        let mut color = Vec3::ZERO;
        loop {
            let next = if traced(&path) {
                self.glass_step(&mut path, &mut pending, &mut color, steps)
            } else {
                false
            };
            if !next {
                match pending.pop() {
                    Some(p) => path = p,
                    None => return color,
                }
            }
        }
    }

    /// One traced ray of [`Self::trace_whitted_glass`]: false when its path ends.
    fn glass_step(
        &self,
        path: &mut WhittedRay,
        pending: &mut Vec<WhittedRay>,
        color: &mut Vec3,
        steps: &mut Vec<WhittedStep>,
    ) -> bool {
        let r = &self.scene.render;
        let ray = path.ray;
        let hit = self.closest(&ray, path.kind);
        steps.push(WhittedStep { ray: *path, hit });
        let Some(hit) = hit else {
            *color += path.weight * r.background.as_vec3();
            return false;
        };
        path.hits += 1;
        let p = ray.origin + hit.t * ray.dir;
        let surface = self.mapped_surface(hit.object, p, ray.dir);
        let offset = spawn_offset(p, self.prims.magnitude(hit.object));
        let origin = surface.spawn_point + offset * surface.geometric;
        let path_length = path.path_length + hit.t;
        let material = self.material_at(hit.object, p, ray.dir, path_length);
        let m = &*material;
        let (reflection, transmission) = (m.reflection as f32, m.transmission as f32);
        let local_share = (1.0 - reflection) * (1.0 - transmission);
        let opaque = transmission == 0.0;
        if local_share > 0.0 || opaque {
            let (local, any_visible) = self.shade(m, p, surface.shading, -ray.dir, origin);
            if opaque && r.shadow_mode == ShadowMode::Seed && !any_visible {
                return false;
            }
            *color += local_share * path.weight * local;
        }
        let mut reflect_share = reflection;
        let mut transmit_share = 0.0f32;
        let mut refracted = ray.dir;
        if transmission > 0.0 {
            let dielectric = (1.0 - reflection) * transmission;
            let ior = m.ior as f32;
            let (eta_i, eta_t) = if path.inside { (ior, 1.0) } else { (1.0, ior) };
            let refraction = refraction_at(ray.dir, &surface, eta_i, eta_t);
            reflect_share = reflection + dielectric * refraction.fresnel;
            transmit_share = dielectric * (1.0 - refraction.fresnel);
            refracted = refraction.dir;
        }
        let reflected = WhittedRay {
            ray: Ray {
                origin,
                dir: reflection_dir(ray.dir, &surface),
            },
            kind: RayKind::Reflected,
            weight: path.weight * reflect_share,
            hits: path.hits,
            path_length,
            inside: path.inside,
        };
        if transmit_share > 0.0 {
            let traced = reflect_share > 0.0
                && reflected.weight >= r.min_intensity as f32
                && reflected.hits < r.max_depth;
            if traced && pending.len() < GLASS_STACK_DEPTH as usize {
                pending.push(reflected);
            }
            *path = WhittedRay {
                ray: Ray {
                    origin: p - offset * surface.geometric,
                    dir: refracted,
                },
                kind: RayKind::Refracted,
                weight: path.weight * transmit_share,
                hits: path.hits,
                path_length,
                inside: !path.inside,
            };
        } else {
            *path = reflected;
        }
        path.weight != 0.0
    }

    fn shade(
        &self,
        m: &crate::scene::Material,
        p: Vec3,
        n: Vec3,
        v: Vec3,
        origin: Vec3,
    ) -> (Vec3, bool) {
        let mut ambient = Vec3::ZERO;
        let mut direct = Vec3::ZERO;
        let mut any_visible = false;
        for (i, light) in self.scene.lights.iter().enumerate() {
            let lp = light.position.as_vec3();
            ambient += m.ambient.as_vec3() * light.ambient.as_vec3();
            // As shade.wgsl: a spot light is a point light times its
            // falloff; a directional light's shadow ray is unbounded.
            let mut strength = 1.0f32;
            let (l, shadow_ray, shadow_length) = match light.kind {
                LightKind::Directional { direction } => {
                    let l = -direction.as_vec3();
                    (l, Ray { origin, dir: l }, f32::INFINITY)
                }
                _ => {
                    let to_light = lp - p;
                    let distance = to_light.length();
                    if distance <= 0.0 {
                        continue;
                    }
                    let l = to_light / distance;
                    if let LightKind::Spot {
                        direction,
                        inner_degrees,
                        outer_degrees,
                    } = light.kind
                    {
                        // In f32 from the values the lights buffer holds
                        // (crates/kdray-core/src/layout/scene_arrays.rs).
                        let cos_inner = inner_degrees.to_radians().cos();
                        let cos_outer = outer_degrees.to_radians().cos();
                        let scale = (1.0 / (cos_inner - cos_outer).max(0.001)) as f32;
                        let cos_angle = (-l).dot(direction.as_vec3());
                        let t = ((cos_angle - cos_outer as f32) * scale).clamp(0.0, 1.0);
                        strength = t * t;
                        if strength == 0.0 {
                            continue;
                        }
                    }
                    let from_origin = lp - origin;
                    let shadow_length = from_origin.length();
                    let dir = if shadow_length > 0.0 {
                        from_origin / shadow_length
                    } else {
                        Vec3::Z
                    };
                    (l, Ray { origin, dir }, shadow_length)
                }
            };
            let l_dot_n = l.dot(n);
            if l_dot_n <= 0.0 {
                continue;
            }
            let mut through = 1.0f32;
            if shadow_length > 0.0 {
                self.aim.set(Some(AimedLight {
                    light: LightId::Scene(i as u32),
                    pick: 1.0,
                }));
                through = self.shadow_transmittance(&shadow_ray, shadow_length);
                if through == 0.0 {
                    continue;
                }
            }
            any_visible = true;
            let h = (l + v).normalize();
            let e = (m.shininess * 0.25) as f32;
            let spec = if e == 0.0 {
                1.0
            } else if n.dot(h) <= 0.0 {
                0.0
            } else {
                n.dot(h).powf(e)
            };
            let mut light_term = m.diffuse.as_vec3() * light.diffuse.as_vec3() * l_dot_n
                + m.specular.as_vec3() * light.specular.as_vec3() * spec;
            if self.glass {
                light_term *= through;
            }
            direct += strength * light_term;
        }
        // Emission first, as in the shader: with none the sum is unchanged.
        let emission = m.physical.emission.as_vec3();
        let emits = emission.cmpgt(Vec3::ZERO).any();
        (emission + ambient + direct, any_visible || emits)
    }
}
