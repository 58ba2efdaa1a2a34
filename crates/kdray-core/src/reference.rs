//! A CPU reference of shaders/trace.wgsl + shade.wgsl + glass.wgsl +
//! texture.wgsl: the same path loop (with glass: refraction, Fresnel, the
//! stack of pending rays, shadow rays through glass; with textures: the
//! texture at the hit, its mip level chosen by the ray cone of the path's
//! length from the eye, multiplying diffuse and ambient), shading and f32 arithmetic over the CPU
//! mirror of the traversal, so GPU images can be checked pixel by pixel and
//! a single path can be inspected: [`ReferenceTracer::trace_recorded`](crate::reference::ReferenceTracer::trace_recorded)
//! returns every ray a sample traces with its walk, step by step (what
//! `kdray inspect` prints). Slow (one thread); for tests, debugging and
//! inspection only.

use std::cell::RefCell;

use glam::Vec3;

use crate::geometry::{spawn_offset, Primitives, Ray, T_INFINITY};
use crate::kdtree::traverse::{brute_counted, Hit, WalkCost, SHORT_STACK_DEPTH};
use crate::kdtree::{
    traverse, KdTree, Ropes, Traversal, WalkEvent, WalkObserver, WalkQuery, WalkScene,
};
use crate::layout::{GpuTriangleNormals, GLASS_STACK_DEPTH, SHADOW_CROSSINGS};
use crate::scene::texture::{pixel_spread_angle, texture_lod};
use crate::scene::{LightKind, Scene, ShadowMode};

/// Where a path meets a surface, seen from the incoming ray: mirror of
/// `Surface` in shaders/surface.wgsl.
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
/// triangle branch of `surface_at` in shaders/surface.wgsl (interpolated
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

/// Mirror of `reflection_dir` in shaders/surface.wgsl.
pub fn reflection_dir(dir: Vec3, s: &Surface) -> Vec3 {
    let reflect = |n: Vec3| (dir - 2.0 * dir.dot(n) * n).normalize();
    let r = reflect(s.shading);
    if r.dot(s.geometric) > 0.0 {
        r
    } else {
        reflect(s.geometric)
    }
}

/// The refracted direction and the Fresnel reflectance at one interface:
/// mirror of `Refraction` in shaders/glass.wgsl.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Refraction {
    /// Unit; the incoming direction where `fresnel == 1`.
    pub dir: Vec3,
    /// Exact dielectric reflectance (unpolarised: the mean of the s and p
    /// reflectances); 1 at total internal reflection.
    pub fresnel: f32,
}

/// Snell's law and the exact dielectric Fresnel reflectance for unit `d`
/// arriving at unit `n` (facing the incoming ray) from index `eta_i` into
/// `eta_t`: mirror of `refract_fresnel` in shaders/glass.wgsl. Equal indices
/// bend nothing and reflect nothing, exactly.
pub fn refract_fresnel(d: Vec3, n: Vec3, eta_i: f32, eta_t: f32) -> Refraction {
    if eta_i == eta_t {
        return Refraction {
            dir: d,
            fresnel: 0.0,
        };
    }
    let cos_i = (-d.dot(n)).clamp(0.0, 1.0);
    let eta = eta_i / eta_t;
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i);
    if sin2_t >= 1.0 {
        return Refraction {
            dir: d,
            fresnel: 1.0,
        };
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let rs = (eta_i * cos_i - eta_t * cos_t) / (eta_i * cos_i + eta_t * cos_t);
    let rp = (eta_t * cos_i - eta_i * cos_t) / (eta_t * cos_i + eta_i * cos_t);
    Refraction {
        dir: (eta * d + (eta * cos_i - cos_t) * n).normalize(),
        fresnel: 0.5 * (rs * rs + rp * rp),
    }
}

/// Mirror of `refraction_at` in shaders/glass.wgsl.
pub fn refraction_at(d: Vec3, s: &Surface, eta_i: f32, eta_t: f32) -> Refraction {
    let r = refract_fresnel(d, s.shading, eta_i, eta_t);
    if r.fresnel == 1.0 || r.dir.dot(s.geometric) < 0.0 {
        return r;
    }
    refract_fresnel(d, s.geometric, eta_i, eta_t)
}

/// Why a ray is traced.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RayKind {
    /// From the camera.
    Primary,
    /// Towards a light (with glass: each part between two glass surfaces).
    Shadow,
    /// The mirror ray of a hit.
    Reflected,
    /// Through a glass surface.
    Refracted,
    /// A path tracer's next ray, sampled from the surface's scattering
    /// (the GPU's inspect kernel records these; this tracer follows the
    /// Whitted integrator only).
    Bounce,
}

/// One ray a sample traced, in order, recorded by
/// [`ReferenceTracer::trace_recorded`].
#[derive(Debug, Clone, PartialEq)]
pub struct TracedRay {
    pub kind: RayKind,
    pub ray: Ray,
    /// How far the query looked (`T_INFINITY`: no limit).
    pub t_limit: f32,
    /// An any-hit query (a shadow ray without glass) rather than nearest hit.
    pub any: bool,
    pub hit: Option<Hit>,
    /// The walk's counted work, as the kernel counts it.
    pub cost: WalkCost,
    /// The walk's steps (none for brute force).
    pub walk: Vec<WalkEvent>,
}

/// How the tracer finds hits: brute force, or a k-d walk over a tree
/// built over the tracer's objects.
enum Search {
    Brute,
    Tree {
        tree: KdTree,
        /// Built for the rope walk only.
        ropes: Option<Ropes>,
        traversal: Traversal,
    },
}

/// A ray a sample follows on the glass path: mirror of `PathRay` in
/// shaders/glass.wgsl.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathRay {
    pub ray: Ray,
    pub kind: RayKind,
    /// Its share of the sample's colour.
    pub weight: f32,
    /// Hits on its path before this ray.
    pub hits: u32,
    /// The path's length from the eye to its origin (the texture's ray cone).
    pub path_length: f32,
    /// Whether it runs inside glass.
    pub inside: bool,
}

/// One ray the glass path traced, in order, and what it hit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathStep {
    pub ray: PathRay,
    pub hit: Option<Hit>,
}

/// The scene prepared for CPU tracing.
pub struct ReferenceTracer<'a> {
    scene: &'a Scene,
    prims: Primitives,
    /// Per triangle, its vertex normals as the kernel decodes them (None: flat).
    normals: Vec<Option<[Vec3; 3]>>,
    search: Search,
    /// While recording: the rays traced so far.
    log: RefCell<Option<Vec<TracedRay>>>,
    /// Whether some material transmits: the kernel's GLASS variant.
    glass: bool,
    forward: Vec3,
    right: Vec3,
    up: Vec3,
    tan_half_vfov: f32,
    aspect: f32,
    /// The spread angle of a pixel's ray cone.
    pixel_spread: f32,
}

impl<'a> ReferenceTracer<'a> {
    /// `use_tree`: walk the k-d tree (built with the default parameters)
    /// with the plain restart walk (else the brute-force loop).
    pub fn new(scene: &'a Scene, use_tree: bool) -> Self {
        let prims = Primitives::from_scene(scene);
        let search = match use_tree {
            true => Search::Tree {
                tree: KdTree::for_primitives(&prims),
                ropes: None,
                traversal: Traversal::Restart,
            },
            false => Search::Brute,
        };
        Self::with_search(scene, prims, search)
    }

    /// Walks `tree` (built over `Primitives::from_scene(scene)`, objects
    /// numbered as there: spheres, then triangles) with `traversal`.
    pub fn with_tree(scene: &'a Scene, tree: KdTree, traversal: Traversal) -> Self {
        let prims = Primitives::from_scene(scene);
        let ropes = (traversal == Traversal::Ropes).then(|| Ropes::build(&tree));
        let search = Search::Tree {
            tree,
            ropes,
            traversal,
        };
        Self::with_search(scene, prims, search)
    }

    fn with_search(scene: &'a Scene, prims: Primitives, search: Search) -> Self {
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
            search,
            log: RefCell::new(None),
            glass: scene.materials.iter().any(|m| m.transmission as f32 > 0.0),
            forward: basis.forward.as_vec3(),
            right: basis.right.as_vec3(),
            up: basis.up.as_vec3(),
            tan_half_vfov: basis.tan_half_vfov as f32,
            aspect: (scene.render.width as f64 / scene.render.height as f64) as f32,
            pixel_spread: pixel_spread_angle(basis.tan_half_vfov as f32, scene.render.height),
        }
    }

    /// The objects, numbered as hits name them.
    pub fn primitives(&self) -> &Primitives {
        &self.prims
    }

    /// The hit `query` asks for and the work the search did, each step
    /// reported to `observer`.
    fn search<O: WalkObserver>(
        &self,
        query: WalkQuery,
        observer: &mut O,
    ) -> (Option<Hit>, WalkCost) {
        let prims = &self.prims;
        match &self.search {
            Search::Brute => brute_counted(prims, query.ray, query.t_limit, query.any),
            Search::Tree {
                tree,
                ropes: Some(ropes),
                traversal,
            } => traversal.walk_observed(WalkScene { tree, ropes, prims }, query, observer),
            Search::Tree {
                tree, traversal, ..
            } => {
                let depth = match traversal {
                    Traversal::ShortStack => SHORT_STACK_DEPTH,
                    _ => 0,
                };
                traverse::walk_observed(tree, prims, query, depth, observer)
            }
        }
    }

    /// One query of the path, recorded while recording.
    fn query(&self, kind: RayKind, ray: &Ray, t_limit: f32, any: bool) -> Option<Hit> {
        let query = WalkQuery { ray, t_limit, any };
        let mut log = self.log.borrow_mut();
        let Some(log) = log.as_mut() else {
            return self.search(query, &mut ()).0;
        };
        let mut walk = Vec::new();
        let (hit, cost) = self.search(query, &mut walk);
        log.push(TracedRay {
            kind,
            ray: *ray,
            t_limit,
            any,
            hit,
            cost,
            walk,
        });
        hit
    }

    fn closest(&self, ray: &Ray, kind: RayKind) -> Option<Hit> {
        self.query(kind, ray, T_INFINITY, false)
    }

    /// Every ray the path from `primary` traces, in order, with its walk.
    pub fn trace_recorded(&self, primary: Ray) -> Vec<TracedRay> {
        *self.log.borrow_mut() = Some(Vec::new());
        self.trace_whitted(primary);
        self.log.borrow_mut().take().unwrap_or_default()
    }

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

    /// Mirror of `surface_at` in shaders/surface.wgsl.
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

    /// Mirror of `material_at` in shaders/surface.wgsl (the Whitted
    /// integrator's reading): the material of object `id` at hit point `p`,
    /// reached along unit `dir` by a path `path_length` long from the eye;
    /// on a triangle with a record, its diffuse and ambient colours
    /// multiplied (in f32) by its texture and its vertex colours, its
    /// ambient colour darkened by its occlusion map.
    pub fn material_at(
        &self,
        id: u32,
        p: Vec3,
        dir: Vec3,
        path_length: f32,
    ) -> std::borrow::Cow<'_, crate::scene::Material> {
        let m = self.material(id);
        let Some(t) = (id as usize).checked_sub(self.scene.spheres.len()) else {
            return std::borrow::Cow::Borrowed(m);
        };
        let triangle = &self.scene.triangles[t];
        if self.scene.uvs_of(triangle).is_none() {
            return std::borrow::Cow::Borrowed(m);
        }
        let textured = m.texture.is_some() || m.maps.any();
        let colours = self.scene.colours_of(triangle);
        if !textured && colours.is_none() {
            return std::borrow::Cow::Borrowed(m);
        }
        let v = &self.prims.triangles[t].v;
        let b = barycentrics(v, p);
        let cone_width = self.pixel_spread * path_length;
        // Texture `texture` of the slot `slot`, on that slot's coordinates.
        let sample = |texture: &crate::scene::Texture, slot: u32| {
            let uvs = self.scene.uvs_for(triangle, slot).unwrap_or_default();
            let uvs = uvs.map(|uv| uv.as_vec2());
            let uv = b.x * uvs[0] + b.y * uvs[1] + b.z * uvs[2];
            let size = glam::Vec2::new(texture.width as f32, texture.height as f32);
            let lambda = texture_lod(v, uvs, size, dir, cone_width);
            texture.sample_lod(uv, lambda)
        };
        let texture = |i: Option<u32>| i.and_then(|i| self.scene.textures.get(i as usize));
        let mut diffuse = m.diffuse.as_vec3();
        let mut ambient = m.ambient.as_vec3();
        if let Some(texture) = texture(m.texture) {
            let c = sample(texture, crate::layout::UV_SLOT_BASE);
            diffuse *= c;
            ambient *= c;
        }
        if let Some(corners) = colours {
            // As the kernel reads them: 16-bit unorm.
            let q = |c: glam::DVec4| {
                let c = (c.as_vec4().clamp(glam::Vec4::ZERO, glam::Vec4::ONE) * 65535.0).round();
                c / 65535.0
            };
            let c = (b.x * q(corners[0]) + b.y * q(corners[1]) + b.z * q(corners[2])).truncate();
            diffuse *= c;
            ambient *= c;
        }
        if let Some(texture) = texture(m.maps.occlusion) {
            let ao = sample(texture, crate::layout::UV_SLOT_OCCLUSION).x;
            ambient *= 1.0 + m.maps.occlusion_strength as f32 * (ao - 1.0);
        }
        let mut read = m.clone();
        read.diffuse = diffuse.as_dvec3();
        read.ambient = ambient.as_dvec3();
        std::borrow::Cow::Owned(read)
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
            let surface = self.surface(hit.object, p, ray.dir);
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
    pub fn path_steps(&self, primary: Ray) -> (Vec3, Vec<PathStep>) {
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
    fn trace_whitted_glass(&self, primary: Ray, steps: &mut Vec<PathStep>) -> Vec3 {
        let r = &self.scene.render;
        let min_intensity = r.min_intensity as f32;
        let traced = |p: &PathRay| p.weight >= min_intensity && p.hits < r.max_depth;
        let mut pending: Vec<PathRay> = Vec::new();
        let mut path = PathRay {
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
        path: &mut PathRay,
        pending: &mut Vec<PathRay>,
        color: &mut Vec3,
        steps: &mut Vec<PathStep>,
    ) -> bool {
        let r = &self.scene.render;
        let ray = path.ray;
        let hit = self.closest(&ray, path.kind);
        steps.push(PathStep { ray: *path, hit });
        let Some(hit) = hit else {
            *color += path.weight * r.background.as_vec3();
            return false;
        };
        path.hits += 1;
        let p = ray.origin + hit.t * ray.dir;
        let surface = self.surface(hit.object, p, ray.dir);
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
        let reflected = PathRay {
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
            *path = PathRay {
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
        for light in &self.scene.lights {
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

    /// The camera ray of Whitted sample (`sx`, `sy`) of the k x k grid in
    /// pixel (row, column): mirror of `trace_sample` in shaders/trace.wgsl.
    pub fn sample_ray(&self, row: u32, column: u32, sx: u32, sy: u32) -> Ray {
        let r = &self.scene.render;
        let inv_k = 1.0 / r.samples_per_axis() as f32;
        let u = (column as f32 + (sx as f32 + 0.5) * inv_k) / r.width as f32;
        let v = (row as f32 + (sy as f32 + 0.5) * inv_k) / r.height as f32;
        self.camera_ray(u, v)
    }

    /// The 8-bit colour of pixel (row, column), as render_tile computes it.
    pub fn pixel(&self, row: u32, column: u32) -> [u8; 3] {
        let r = &self.scene.render;
        let k = r.samples_per_axis();
        let mut sum = Vec3::ZERO;
        for sy in 0..k {
            for sx in 0..k {
                sum += self
                    .trace_whitted(self.sample_ray(row, column, sx, sy))
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
