//! The surface at a hit, mirrors of shaders/surface.wgsl and texture.wgsl:
//! the shading frame (geometric and interpolated normals, the normal map
//! bending them), the mirror and refracted directions with Fresnel, and the
//! material with its textures read at the hit.

use glam::Vec3;

use crate::geometry::barycentrics;
use crate::scene::texture::texture_lod;

use super::tracer::ReferenceTracer;

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
/// mirror of `Refraction` in shaders/bsdf_dielectric.wgsl.
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
/// `eta_t`: mirror of `refract_fresnel` in shaders/bsdf_dielectric.wgsl. Equal indices
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

/// Mirror of `refraction_at` in shaders/bsdf_dielectric.wgsl.
pub fn refraction_at(d: Vec3, s: &Surface, eta_i: f32, eta_t: f32) -> Refraction {
    let r = refract_fresnel(d, s.shading, eta_i, eta_t);
    if r.fresnel == 1.0 || r.dir.dot(s.geometric) < 0.0 {
        return r;
    }
    refract_fresnel(d, s.geometric, eta_i, eta_t)
}

impl ReferenceTracer<'_> {
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

    /// Mirror of `mapped_surface_at` in shaders/surface.wgsl: the surface
    /// with its shading normal bent by the material's normal map, unless
    /// the bent normal would face away from the geometric side.
    pub fn mapped_surface(&self, id: u32, p: Vec3, ray_dir: Vec3) -> Surface {
        let mut s = self.surface(id, p, ray_dir);
        let bent = self.mapped_normal(id, p, s.shading);
        if bent.dot(s.geometric) > 0.0 {
            s.shading = bent;
        }
        s
    }

    /// Mirror of `mapped_normal` in shaders/surface.wgsl: the unit shading
    /// normal `n` bent by object `id`'s normal map at `p` (read on its base
    /// level), in the frame of the corners' tangents interpolated and made
    /// orthogonal to `n`; `n` itself without a map, coordinates or tangents.
    /// The kernel reads the tangents octahedral-encoded, this their exact
    /// values.
    fn mapped_normal(&self, id: u32, p: Vec3, n: Vec3) -> Vec3 {
        let Some(t) = (id as usize).checked_sub(self.scene.spheres.len()) else {
            return n;
        };
        let m = self.material(id);
        let triangle = &self.scene.triangles[t];
        let texture = m
            .maps
            .normal
            .and_then(|i| self.scene.textures.get(i as usize));
        let uvs = self.scene.uvs_for(triangle, crate::scene::UV_SLOT_NORMAL);
        let (Some(texture), Some(uvs), Some(tangents)) =
            (texture, uvs, self.scene.tangents_of(triangle))
        else {
            return n;
        };
        let b = barycentrics(&self.prims.triangles[t].v, p);
        let corner = |k: usize| tangents[k].truncate().as_vec3();
        let tangent = b.x * corner(0) + b.y * corner(1) + b.z * corner(2);
        let sign = |k: usize| if tangents[k].w < 0.0 { -1.0 } else { 1.0 };
        let w = b.x * sign(0) + b.y * sign(1) + b.z * sign(2);
        let ortho = tangent - n * n.dot(tangent);
        if ortho.length_squared() <= 0.0 || w == 0.0 {
            return n;
        }
        let tangent = ortho.normalize();
        let bitangent = if w < 0.0 { -1.0 } else { 1.0 } * n.cross(tangent);
        let uvs = uvs.map(|uv| uv.as_vec2());
        let uv = b.x * uvs[0] + b.y * uvs[1] + b.z * uvs[2];
        let c = texture.sample_lod(uv, 0.0) * 2.0 - Vec3::ONE;
        let scale = m.maps.normal_scale as f32;
        let bent = tangent * (c.x * scale) + bitangent * (c.y * scale) + n * c.z;
        if bent.length_squared() <= 0.0 {
            return n;
        }
        bent.normalize()
    }

    pub(super) fn material(&self, id: u32) -> &crate::scene::Material {
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
            let c = sample(texture, crate::scene::UV_SLOT_BASE);
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
            let ao = sample(texture, crate::scene::UV_SLOT_OCCLUSION).x;
            ambient *= 1.0 + m.maps.occlusion_strength as f32 * (ao - 1.0);
        }
        let mut read = m.clone();
        read.diffuse = diffuse.as_dvec3();
        read.ambient = ambient.as_dvec3();
        std::borrow::Cow::Owned(read)
    }
}
