//! A CPU reference of shaders/trace.wgsl + shade.wgsl: the same path loop,
//! shading and f32 arithmetic over the CPU mirror of the traversal, so GPU
//! images can be checked pixel by pixel and a single path can be inspected.
//! Slow (one thread); for tests and debugging only.

use glam::Vec3;

use crate::geometry::{spawn_offset, Primitives, Ray, T_INFINITY};
use crate::kdtree::traverse::{any_hit, any_hit_brute, closest_hit, closest_hit_brute, Hit};
use crate::kdtree::KdTree;
use crate::layout::GpuTriangleNormals;
use crate::scene::{Scene, ShadowMode};

/// Where a path meets a surface, seen from the incoming ray: mirror of
/// `Surface` in shaders/shade.wgsl.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Surface {
    /// Unit geometric normal facing the incoming ray.
    pub geometric: Vec3,
    /// Unit shading normal on the geometric normal's side.
    pub shading: Vec3,
    /// Where secondary rays start before the offset along `geometric`.
    pub spawn_point: Vec3,
}

/// Barycentric weights of `v[0]`, `v[1]`, `v[2]` at `p`, clamped into the
/// triangle: mirror of `barycentrics` in shaders/shade.wgsl.
pub fn barycentrics(v: &[Vec3; 3], p: Vec3) -> Vec3 {
    let e1 = v[1] - v[0];
    let e2 = v[2] - v[0];
    let w = p - v[0];
    let n = e1.cross(e2);
    let nn = n.dot(n);
    if nn < 1e-30 {
        return Vec3::splat(1.0 / 3.0);
    }
    let inv = 1.0 / nn;
    let b1 = (w.cross(e2).dot(n) * inv).clamp(0.0, 1.0);
    let b2 = (e1.cross(w).dot(n) * inv).clamp(0.0, 1.0 - b1);
    Vec3::new(1.0 - b1 - b2, b1, b2)
}

/// The surface of a smooth triangle (vertices `v`, unit vertex normals `n`)
/// at `p`, given its geometric normal `g` facing the ray: mirror of the
/// triangle branch of `surface_at` in shaders/shade.wgsl (interpolated
/// normal; the hit lifted onto the smooth surface, Hanika 2021).
pub fn smooth_surface(v: &[Vec3; 3], n: [Vec3; 3], p: Vec3, g: Vec3) -> Surface {
    let flat = Surface {
        geometric: g,
        shading: g,
        spawn_point: p,
    };
    let b = barycentrics(v, p);
    let [mut n0, mut n1, mut n2] = n;
    let mut n = b.x * n0 + b.y * n1 + b.z * n2;
    if n.dot(g) < 0.0 {
        n = -n;
        n0 = -n0;
        n1 = -n1;
        n2 = -n2;
    }
    if n.dot(n) < 1e-12 {
        return flat;
    }
    let d0 = (p - v[0]).dot(n0).min(0.0);
    let d1 = (p - v[1]).dot(n1).min(0.0);
    let d2 = (p - v[2]).dot(n2).min(0.0);
    let lifted = p - (b.x * d0 * n0 + b.y * d1 * n1 + b.z * d2 * n2);
    Surface {
        geometric: g,
        shading: n.normalize(),
        spawn_point: lifted,
    }
}

/// Mirror of `reflection_dir` in shaders/shade.wgsl.
pub fn reflection_dir(dir: Vec3, s: &Surface) -> Vec3 {
    let reflect = |n: Vec3| (dir - 2.0 * dir.dot(n) * n).normalize();
    let r = reflect(s.shading);
    if r.dot(s.geometric) > 0.0 {
        r
    } else {
        reflect(s.geometric)
    }
}

/// The scene prepared for CPU tracing.
pub struct ReferenceTracer<'a> {
    scene: &'a Scene,
    prims: Primitives,
    /// Per triangle, its vertex normals as the kernel decodes them (None: flat).
    normals: Vec<Option<[Vec3; 3]>>,
    tree: Option<KdTree>,
    forward: Vec3,
    right: Vec3,
    up: Vec3,
    tan_half_vfov: f32,
    aspect: f32,
}

impl<'a> ReferenceTracer<'a> {
    /// `use_tree`: walk the k-d tree (else the brute-force loop).
    pub fn new(scene: &'a Scene, use_tree: bool) -> Self {
        let prims = Primitives::from_scene(scene);
        let tree = use_tree.then(|| KdTree::for_primitives(&prims));
        let basis = scene.camera.basis();
        let normals = scene
            .triangles
            .iter()
            .map(|t| {
                scene
                    .normals_of(t)
                    .map(|n| GpuTriangleNormals::pack(n).unpack())
            })
            .collect();
        ReferenceTracer {
            scene,
            prims,
            normals,
            tree,
            forward: basis.forward.as_vec3(),
            right: basis.right.as_vec3(),
            up: basis.up.as_vec3(),
            tan_half_vfov: basis.tan_half_vfov as f32,
            aspect: (scene.render.width as f64 / scene.render.height as f64) as f32,
        }
    }

    fn closest(&self, ray: &Ray) -> Option<Hit> {
        match &self.tree {
            Some(tree) => closest_hit(tree, &self.prims, ray, T_INFINITY),
            None => closest_hit_brute(&self.prims, ray, T_INFINITY),
        }
    }

    fn blocked(&self, ray: &Ray, t_limit: f32) -> bool {
        match &self.tree {
            Some(tree) => any_hit(tree, &self.prims, ray, t_limit),
            None => any_hit_brute(&self.prims, ray, t_limit),
        }
    }

    pub fn camera_ray(&self, u: f32, v: f32) -> Ray {
        let h = self.tan_half_vfov;
        let dir = self.forward
            + (2.0 * u - 1.0) * h * self.aspect * self.right
            + (1.0 - 2.0 * v) * h * self.up;
        Ray {
            origin: self.scene.camera.position.as_vec3(),
            dir: dir.normalize(),
        }
    }

    /// Mirror of `surface_at` in shaders/shade.wgsl.
    pub fn surface(&self, id: u32, p: Vec3, ray_dir: Vec3) -> Surface {
        let id = id as usize;
        let triangle = id.checked_sub(self.prims.spheres.len());
        let mut g = match triangle {
            None => (p - self.prims.spheres[id].center).normalize(),
            Some(t) => self.prims.triangles[t].normal(),
        };
        if g.dot(ray_dir) > 0.0 {
            g = -g;
        }
        match triangle.and_then(|t| Some((t, self.normals[t]?))) {
            Some((t, n)) => smooth_surface(&self.prims.triangles[t].v, n, p, g),
            None => Surface {
                geometric: g,
                shading: g,
                spawn_point: p,
            },
        }
    }

    fn material(&self, id: u32) -> &crate::scene::Material {
        let id = id as usize;
        let index = match self.scene.spheres.get(id) {
            Some(s) => s.material,
            None => self.scene.triangles[id - self.scene.spheres.len()].material,
        };
        &self.scene.materials[index as usize]
    }

    /// The colour of one path (unclamped), and the hits along it.
    pub fn trace_path(&self, primary: Ray) -> (Vec3, Vec<Hit>) {
        let r = &self.scene.render;
        let mut ray = primary;
        let mut color = Vec3::ZERO;
        let mut weight = 1.0f32;
        let mut hits = Vec::new();
        while weight >= r.min_intensity as f32 && (hits.len() as u32) < r.max_depth {
            let Some(hit) = self.closest(&ray) else {
                color += weight * r.background.as_vec3();
                break;
            };
            hits.push(hit);
            let p = ray.origin + hit.t * ray.dir;
            let surface = self.surface(hit.object, p, ray.dir);
            let offset = spawn_offset(p, self.prims.magnitude(hit.object));
            let origin = surface.spawn_point + offset * surface.geometric;
            let m = self.material(hit.object);
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
        for light in &self.scene.lights {
            let lp = light.position.as_vec3();
            ambient += m.ambient.as_vec3() * light.ambient.as_vec3();
            let to_light = lp - p;
            let distance = to_light.length();
            if distance <= 0.0 {
                continue;
            }
            let l = to_light / distance;
            let l_dot_n = l.dot(n);
            if l_dot_n <= 0.0 {
                continue;
            }
            let from_origin = lp - origin;
            let shadow_length = from_origin.length();
            if shadow_length > 0.0
                && self.blocked(
                    &Ray {
                        origin,
                        dir: from_origin / shadow_length,
                    },
                    shadow_length,
                )
            {
                continue;
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
            direct += m.diffuse.as_vec3() * light.diffuse.as_vec3() * l_dot_n
                + m.specular.as_vec3() * light.specular.as_vec3() * spec;
        }
        (ambient + direct, any_visible)
    }

    /// The 8-bit colour of pixel (row, column), as render_tile computes it.
    pub fn pixel(&self, row: u32, column: u32) -> [u8; 3] {
        let r = &self.scene.render;
        let k = r.samples_per_axis();
        let inv_k = 1.0 / k as f32;
        let mut sum = Vec3::ZERO;
        for sy in 0..k {
            for sx in 0..k {
                let u = (column as f32 + (sx as f32 + 0.5) * inv_k) / r.width as f32;
                let v = (row as f32 + (sy as f32 + 0.5) * inv_k) / r.height as f32;
                sum += self
                    .trace_path(self.camera_ray(u, v))
                    .0
                    .clamp(Vec3::ZERO, Vec3::ONE);
            }
        }
        let c = sum / (k * k) as f32;
        let q = (255.0 * c.clamp(Vec3::ZERO, Vec3::ONE) + 0.5).floor();
        [q.x as u8, q.y as u8, q.z as u8]
    }

    /// The whole image, 8-bit RGB, top row first.
    pub fn image(&self) -> Vec<u8> {
        let r = &self.scene.render;
        (0..r.height)
            .flat_map(|row| (0..r.width).flat_map(move |column| self.pixel(row, column)))
            .collect()
    }
}
