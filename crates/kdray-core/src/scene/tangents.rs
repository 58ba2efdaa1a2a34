//! The tangent frames of normal-mapped triangles whose file gives no
//! `TANGENT`: MikkTSpace's (Mikkelsen 2008), which glTF asks for and the
//! tools that bake normal maps use, so that a baked map bends the normals
//! it was baked for. Computed per mesh entry in world space, from each
//! triangle's corners, shading normals (the geometric normal where it is
//! flat) and the texture coordinates its normal map reads.
//!
//! glTF's texture coordinates have v pointing down the image and its normal
//! maps +Y up the image; MikkTSpace's bitangent follows increasing v. So
//! the sign MikkTSpace gives is negated: the bitangent `w * (n x t)` then
//! points up the image, as glTF's sample viewer and three.js have it.

use bevy_mikktspace::{Geometry, TangentSpace};
use glam::{DVec3, DVec4};

use super::material::Material;
use super::objects::Triangle;
use super::triangle_parts::TriangleParts;

/// Gives every triangle of `triangles` (the ones a mesh entry just
/// appended) whose material has a normal map and which has texture
/// coordinates but no tangents MikkTSpace's tangents, in `parts`.
pub(super) fn generate_missing(
    triangles: &[Triangle],
    materials: &[Material],
    parts: &mut TriangleParts,
) {
    let needs = |t: &&Triangle| {
        let mapped = materials
            .get(t.material as usize)
            .is_some_and(|m| m.maps.normal.is_some());
        let record = t.uvs as usize;
        let has = parts.tangents.get(record).is_some_and(|c| c[0].w != 0.0);
        mapped && record < parts.uvs.len() && !has
    };
    let faces: Vec<Triangle> = triangles.iter().filter(needs).copied().collect();
    if faces.is_empty() {
        return;
    }
    let second = |t: &Triangle| {
        materials
            .get(t.material as usize)
            .is_some_and(|m| m.maps.second_uv & super::material::UV_SLOT_NORMAL != 0)
    };
    let on_second: Vec<bool> = faces.iter().map(second).collect();
    let mut frames = Frames {
        faces: &faces,
        on_second: &on_second,
        parts,
        out: vec![[DVec4::ZERO; 3]; faces.len()],
    };
    // The crate's error type has no variants: it cannot fail.
    let _ = bevy_mikktspace::generate_tangents(&mut frames);
    let Frames { out, parts, .. } = frames;
    parts.tangents.resize(parts.uvs.len(), [DVec4::ZERO; 3]);
    for (t, frame) in faces.iter().zip(out) {
        parts.tangents[t.uvs as usize] = frame;
    }
}

/// The faces MikkTSpace reads, and the tangents it writes.
struct Frames<'a> {
    faces: &'a [Triangle],
    /// Whether face i's normal map reads the second channel.
    on_second: &'a [bool],
    parts: &'a mut TriangleParts,
    out: Vec<[DVec4; 3]>,
}

impl Frames<'_> {
    /// The shading normal at corner `vert` of `face`.
    fn shading_normal(&self, face: usize, vert: usize) -> DVec3 {
        let t = &self.faces[face];
        match self.parts.normals.get(t.normals as usize) {
            Some(n) => n[vert],
            None => {
                let [a, b, c] = t.vertices;
                (b - a).cross(c - a).normalize_or_zero()
            }
        }
    }
}

impl Geometry for Frames<'_> {
    fn num_faces(&self) -> usize {
        self.faces.len()
    }

    fn num_vertices_of_face(&self, _face: usize) -> usize {
        3
    }

    fn position(&self, face: usize, vert: usize) -> [f32; 3] {
        self.faces[face].vertices[vert].as_vec3().to_array()
    }

    fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
        self.shading_normal(face, vert).as_vec3().to_array()
    }

    fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
        let record = self.faces[face].uvs as usize;
        let uvs = match self.on_second[face] {
            true => self.parts.second_uvs.get(record),
            false => self.parts.uvs.get(record),
        };
        uvs.map_or([0.0; 2], |c| c[vert].as_vec2().to_array())
    }

    fn set_tangent(&mut self, space: Option<TangentSpace>, face: usize, vert: usize) {
        // None: a degenerate face with no neighbour to borrow from; it keeps
        // no tangent (the kernel then bends nothing there).
        if let Some(space) = space {
            let [x, y, z, w] = space.tangent_encoded().map(f64::from);
            let t = DVec3::new(x, y, z);
            if t.length_squared() > 0.0 {
                self.out[face][vert] = t.extend(-w);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec2;

    /// A square in the xy plane facing +z, u along +x and v down the image
    /// (along -y), as glTF maps a picture onto it.
    fn square(flip_u: bool) -> (Vec<Triangle>, TriangleParts) {
        let p = [
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
        ];
        let uv = |v: DVec3| {
            let u = if flip_u { 1.0 - v.x } else { v.x };
            DVec2::new(u, 1.0 - v.y)
        };
        let mut parts = TriangleParts::default();
        let mut triangles = Vec::new();
        for corners in [[0, 1, 2], [0, 2, 3]] {
            let vertices = corners.map(|i| p[i]);
            let mut t = Triangle::flat(vertices, 0);
            parts.add_record(
                &mut t,
                super::super::triangle_parts::SurfaceRecord {
                    uvs: Some(vertices.map(uv)),
                    ..Default::default()
                },
            );
            triangles.push(t);
        }
        (triangles, parts)
    }

    fn normal_mapped() -> Vec<Material> {
        vec![Material {
            name: "mapped".to_string(),
            ambient: DVec3::ZERO,
            diffuse: DVec3::ONE,
            specular: DVec3::ZERO,
            shininess: 0.0,
            reflection: 0.0,
            transmission: 0.0,
            ior: 1.0,
            texture: None,
            physical: crate::scene::material::Physical::LAMBERTIAN,
            maps: crate::scene::material::MaterialMaps {
                normal: Some(0),
                ..crate::scene::material::MaterialMaps::NONE
            },
            alpha: crate::scene::alpha::Alpha::OPAQUE,
        }]
    }

    #[test]
    fn a_square_mapped_as_gltf_maps_a_picture_gets_u_as_tangent_and_up_the_image_as_bitangent() {
        let (triangles, mut parts) = square(false);
        generate_missing(&triangles, &normal_mapped(), &mut parts);
        for corners in &parts.tangents {
            for t in corners {
                assert!((t.truncate() - DVec3::X).length() < 1e-6, "{t}");
                // w (n x t) = +y: up the image.
                assert_eq!(t.w, 1.0, "{t}");
            }
        }
    }

    #[test]
    fn a_mirrored_mapping_turns_the_tangent_and_keeps_the_bitangent_up_the_image() {
        let (triangles, mut parts) = square(true);
        generate_missing(&triangles, &normal_mapped(), &mut parts);
        for corners in &parts.tangents {
            for t in corners {
                assert!((t.truncate() + DVec3::X).length() < 1e-6, "{t}");
                // w (z x -x) = -w y must be +y: w = -1.
                assert_eq!(t.w, -1.0, "{t}");
            }
        }
    }

    #[test]
    fn triangles_without_a_normal_map_or_with_tangents_are_left_alone() {
        let (triangles, mut parts) = square(false);
        let mut plain = normal_mapped();
        plain[0].maps.normal = None;
        generate_missing(&triangles, &plain, &mut parts);
        assert!(parts.tangents.is_empty());
        let given = [DVec4::new(0.0, 1.0, 0.0, 1.0); 3];
        parts.tangents = vec![given; 2];
        generate_missing(&triangles, &normal_mapped(), &mut parts);
        assert_eq!(parts.tangents, vec![given; 2]);
    }
}
