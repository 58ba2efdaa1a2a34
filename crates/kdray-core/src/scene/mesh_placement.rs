//! A scene's `[[meshes]]` entries: each mesh file loaded, its vertices
//! placed in the world (scale, rotate, translate), its triangles built on
//! all threads straight into the scene's vectors, shaded flat or with the
//! file's or computed normals, and its materials (with their textures) added
//! to the scene's; a triangle of a textured material keeps the file's
//! texture coordinates where every corner has them.

use std::path::Path;

use glam::{DAffine3, DMat3, DVec3, DVec4};
use rayon::prelude::*;

use super::error::SceneError;
use super::material::Material;
use super::mesh::{has_area, Mesh, MeshTriangle};
use super::mesh_file;
use super::normals::{self, unit};
use super::objects::Triangle;
use super::schema::{RawMesh, RawScale};
use super::texture::Texture;
use super::triangle_parts::{SurfaceRecord, TriangleParts};
use super::validate::{Validator, MAX_COORDINATE};

/// What a mesh file places besides its triangles (glTF: a camera, lights).
#[derive(Debug, Default)]
pub(super) struct Placed {
    pub camera: Option<super::camera::Camera>,
    pub lights: Vec<super::light::Light>,
    /// glTF: the meshes it places several times, each once in its own
    /// space, and their copies (each instance's `shape` an index into
    /// these `shapes`), moved by the entry.
    pub shapes: Vec<super::instances::Shape>,
    pub instances: Vec<super::instances::Instance>,
}

impl Validator<'_> {
    /// Loads mesh `i`, transforms it to world space and appends its triangles
    /// (and, without an override, its MTL materials); returns what the file
    /// places besides (in the file's coordinates, not moved by the entry).
    pub(super) fn mesh(
        &self,
        i: usize,
        m: &RawMesh,
        override_material: Option<u32>,
        materials: &mut Vec<Material>,
        triangles: &mut Vec<Triangle>,
        parts: &mut TriangleParts,
    ) -> Result<Placed, SceneError> {
        let key = |k: &str| format!("meshes[{i}].{k}");
        let (transform, translate) = self.entry_transform(i, m)?;

        let mesh_path = self.file.parent().unwrap_or(Path::new("")).join(&m.path);
        let mut mesh =
            self.load_entry_mesh(&key("path"), &mesh_path, override_material.is_none(), true)?;
        let mut placed = Placed {
            camera: mesh.camera,
            lights: mesh.lights.clone(),
            ..Placed::default()
        };

        let first_material = materials.len() as u32;
        if override_material.is_none() {
            self.add_mesh_materials(
                &key("path"),
                &m.path,
                &mesh_path,
                &mesh,
                materials,
                &mut parts.textures,
            )?;
        }
        let world = self.place(&key("scale"), &mesh, transform, translate)?;
        let placement = Placement {
            mesh: &mesh,
            transform,
            smooth: m.smooth,
            override_material,
            first_material,
        };
        add_placed(&placement, world, materials, triangles, parts)
            .map_err(|message| self.error(&key("path"), message))?;
        let entry = DAffine3 {
            matrix3: transform,
            translation: translate,
        };
        for instanced in std::mem::take(&mut mesh.instanced) {
            let bounds = super::instances::mesh_bounds(&instanced.mesh);
            let shape = placed.shapes.len() as u32;
            for &copy in &instanced.transforms {
                let transform = entry * copy;
                let [lo, hi] = super::instances::transformed_box(&transform, &bounds);
                let in_range = |v: DVec3| v.is_finite() && v.abs().max_element() <= MAX_COORDINATE;
                if !(in_range(lo) && in_range(hi)) {
                    return Err(self.error(
                        &key("scale"),
                        format!(
                            "a copy of glTF mesh {} reaches beyond ±{MAX_COORDINATE:e} or out of the 64-bit floats (the GPU computes in f32)",
                            instanced.index
                        ),
                    ));
                }
                placed.instances.push(super::instances::Instance {
                    shape,
                    transform,
                    material: None,
                });
            }
            placed.shapes.push(super::instances::Shape {
                name: format!("{}#mesh{}", m.path, instanced.index),
                mesh: std::sync::Arc::new(instanced.mesh),
                smooth: m.smooth,
                material: override_material,
                first_material,
                bounds,
            });
        }
        crate::huge_pages::free_in_background(mesh);
        Ok(placed)
    }

    /// Mesh entry `i`'s `scale` (non-zero on every axis) and `rotate`, as
    /// one matrix, and its `translate`.
    fn entry_transform(&self, i: usize, m: &RawMesh) -> Result<(DMat3, DVec3), SceneError> {
        self.scale_rotate_translate(&format!("meshes[{i}]"), &m.scale, m.rotate, m.translate)
    }

    /// The `scale` (non-zero on every axis) and `rotate` of the table at
    /// `table` (a key path), as one matrix, and its `translate`.
    pub(super) fn scale_rotate_translate(
        &self,
        table: &str,
        scale: &RawScale,
        rotate: super::schema::Vec3,
        translate: super::schema::Vec3,
    ) -> Result<(DMat3, DVec3), SceneError> {
        let key = |k: &str| format!("{table}.{k}");
        let scale = match *scale {
            RawScale::Uniform(s) => DVec3::splat(self.number(&|| key("scale"), s)?),
            RawScale::PerAxis(v) => self.vector(&|| key("scale"), v)?,
        };
        if scale.abs().min_element() == 0.0 {
            return Err(self.error(&key("scale"), "must be non-zero on every axis"));
        }
        let rotate = self.vector(&|| key("rotate"), rotate)?;
        let translate = self.position(&|| key("translate"), translate)?;
        Ok((mesh_transform(scale, rotate), translate))
    }

    /// Mesh entry `i`'s file, loaded (with its materials when
    /// `with_materials`); its warnings handed to the scene's sink. A mesh
    /// file at fault as a whole is an error that also names the entry.
    pub(super) fn load_entry_mesh(
        &self,
        path_key: &str,
        mesh_path: &Path,
        with_materials: bool,
        instancing: bool,
    ) -> Result<Mesh, SceneError> {
        let mut mesh = {
            let mut on_read = self.on_read.borrow_mut();
            mesh_file::load_mesh_with(mesh_path, with_materials, instancing, &mut **on_read)
        }
        .map_err(|e| {
            // A model opened on its own has no scene file to point at.
            if e.line.is_some() || mesh_path == self.file {
                return e;
            }
            // A mesh file at fault as a whole: also say which entry asked for it.
            let at = match self.map.get().and_then(|m| m.line_of_path(path_key)) {
                Some(line) => format!("{}:{line}", self.file.display()),
                None => self.file.display().to_string(),
            };
            let message = format!("{} (from {path_key} in {at})", e.message);
            e.reworded(message)
        })?;
        for warning in std::mem::take(&mut mesh.warnings) {
            (self.warn.borrow_mut())(warning);
        }
        Ok(mesh)
    }

    /// The materials of mesh entry `i`'s file (`path` as the entry writes
    /// it), named `FILE:NAME`, appended to the scene's, and each image they
    /// use appended to `textures` once. A negative colour is an error.
    pub(super) fn add_mesh_materials(
        &self,
        path_key: &str,
        path: &str,
        mesh_path: &Path,
        mesh: &Mesh,
        materials: &mut Vec<Material>,
        textures: &mut Vec<Texture>,
    ) -> Result<(), SceneError> {
        let file_name = Path::new(path)
            .file_name()
            .map_or(path.to_string(), |f| f.to_string_lossy().into_owned());
        // The mesh readers check that colours are finite; the scene's
        // rule that colours are >= 0 holds for them too.
        for mm in &mesh.materials {
            let colours = [("Ka", mm.ambient), ("Kd", mm.diffuse), ("Ks", mm.specular)];
            if let Some((statement, c)) = colours.iter().find(|(_, c)| c.min_element() < 0.0) {
                let (kind, what) = match mesh_file::MeshFormat::of_path(mesh_path) {
                    Some(mesh_file::MeshFormat::Gltf) => ("glTF", "colour"),
                    _ => ("MTL", *statement),
                };
                return Err(self.error(
                    path_key,
                    format!(
                        "{kind} material \"{}\" has a negative {what} colour {:?}; colour components must be >= 0",
                        mm.name,
                        c.to_array()
                    ),
                ));
            }
        }
        // Each image once, however many materials use it.
        let mut added: Vec<(*const Texture, u32)> = Vec::new();
        for mm in &mesh.materials {
            let mut index_of = |t: &std::sync::Arc<Texture>| {
                let key = std::sync::Arc::as_ptr(t);
                match added.iter().find(|(k, _)| *k == key) {
                    Some(&(_, index)) => index,
                    None => {
                        let index = textures.len() as u32;
                        textures.push(Texture::clone(t));
                        added.push((key, index));
                        index
                    }
                }
            };
            let texture = mm.texture.as_ref().map(&mut index_of);
            let maps = mm.maps.map(&mut index_of);
            materials.push(Material {
                name: format!("{file_name}:{}", mm.name),
                ambient: mm.ambient,
                diffuse: mm.diffuse,
                specular: mm.specular,
                shininess: mm.shininess,
                reflection: mm.reflection,
                transmission: mm.transmission,
                ior: mm.ior,
                texture,
                physical: mm.physical,
                maps,
                alpha: mm.alpha,
            });
        }
        Ok(())
    }

    /// The mesh's shared vertices in world space, each transformed once.
    /// A vertex that lands beyond the GPU's range is an error only where a
    /// triangle uses it (an OBJ file may define vertices no face uses).
    fn place(
        &self,
        scale_key: &str,
        mesh: &Mesh,
        transform: DMat3,
        translate: DVec3,
    ) -> Result<Vec<DVec3>, SceneError> {
        let world: Vec<DVec3> = mesh
            .positions
            .par_iter()
            .map(|&v| transform * v + translate)
            .collect();
        let in_range = |v: &DVec3| v.is_finite() && v.abs().max_element() <= MAX_COORDINATE;
        // Usually every vertex is in range, and the triangles need no look.
        if !world.par_iter().all(in_range) {
            let uses_one_out_of_range = mesh.triangles.iter().any(|t| {
                t.corners
                    .iter()
                    .any(|&c| world.get(c as usize).is_some_and(|v| !in_range(v)))
            });
            if uses_one_out_of_range {
                return Err(self.error(
                    scale_key,
                    "the transformed mesh has a non-finite vertex, or one beyond ±1e15 (the GPU computes in f32)",
                ));
            }
        }
        Ok(world)
    }
}

/// A mesh in its own space and how it is placed: by `transform` (its
/// vertices already carried by it and a translation, in `add_placed`'s
/// `world`), shaded as `smooth` says (`[[meshes]]`' key), every triangle
/// of material `override_material` or else of its file's material, which
/// lie in the scene's materials from `first_material` on.
pub(super) struct Placement<'a> {
    pub(super) mesh: &'a Mesh,
    pub(super) transform: DMat3,
    pub(super) smooth: Option<bool>,
    pub(super) override_material: Option<u32>,
    pub(super) first_material: u32,
}

/// Appends the triangles of `p` placed at `world` (its vertices in world
/// space) to `triangles`, with their normals, texture coordinates, colours
/// and tangents in `parts`: what a `[[meshes]]` entry and a flattened
/// instance both do. The fault of a mesh no reader writes (an index out of
/// range, a face without a material) is the error.
pub(super) fn add_placed(
    p: &Placement,
    world: Vec<DVec3>,
    materials: &[Material],
    triangles: &mut Vec<Triangle>,
    parts: &mut TriangleParts,
) -> Result<(), &'static str> {
    let mesh = p.mesh;
    let records = SurfaceRecords {
        mesh,
        transform: p.transform,
        mirror: p.transform.determinant().signum(),
        with_materials: p.override_material.is_none(),
    };
    let shading = MeshNormals::new(p.smooth, mesh, &world, p.transform);
    let material_of = |t: &MeshTriangle| match (p.override_material, t.material()) {
        (Some(m), _) => Some(m),
        (None, Some(local)) => Some(p.first_material + local as u32),
        (None, None) => None,
    };
    let first = triangles.len();
    let world_mesh = WorldMesh {
        mesh,
        world: &world,
        shading: &shading,
    };
    if build_in_parallel(&world_mesh, material_of, triangles, &mut parts.normals) {
        if records.any() {
            for (triangle, t) in triangles[first..].iter_mut().zip(&mesh.triangles) {
                parts.add_record(triangle, records.of(t));
            }
        }
    } else {
        build_one_by_one(&world_mesh, material_of, &records, triangles, parts)?;
    }
    super::tangents::generate_missing(&triangles[first..], materials, parts);
    crate::huge_pages::free_in_background((world, shading));
    Ok(())
}

/// A mesh file's triangles ready to be built: the file, its vertices in
/// world space, and how its triangles are shaded.
struct WorldMesh<'a> {
    mesh: &'a Mesh,
    world: &'a [DVec3],
    shading: &'a MeshNormals,
}

/// Appends every triangle of `w` (material by `material_of`) to
/// `triangles`, with its normals to `normals` unless flat, on all threads;
/// whether every triangle was kept. Where one was not (collapsed, an index
/// out of range, no material), nothing is appended.
fn build_in_parallel(
    w: &WorldMesh,
    material_of: impl Fn(&MeshTriangle) -> Option<u32> + Sync,
    triangles: &mut Vec<Triangle>,
    normals: &mut Vec<[DVec3; 3]>,
) -> bool {
    let WorldMesh {
        mesh,
        world,
        shading,
    } = *w;
    // Usually every triangle is kept (none collapsed, every index in
    // range): then they are built on all threads, straight into the
    // scene's vector (rayon writes an indexed iterator in place), which
    // on two cores also halves the wait for its fresh pages. Built first
    // and checked on the way (a separate pass of checks took 15 ms of
    // the 1.1 M-triangle bunny's 0.22 s load); where one is not kept,
    // they are dropped, and `build_one_by_one` builds them again.
    let (first, first_normals) = (triangles.len(), normals.len());
    let all_kept = std::sync::atomic::AtomicBool::new(true);
    let kept = |t: &MeshTriangle| {
        let vertices = t.corners_in(world).filter(has_area);
        let kept = vertices.zip(material_of(t));
        if kept.is_none() {
            all_kept.store(false, std::sync::atomic::Ordering::Relaxed);
        }
        kept.unwrap_or_default()
    };
    triangles.reserve(mesh.triangles.len());
    crate::huge_pages::advise(triangles);
    if let MeshNormals::Flat = shading {
        triangles.par_extend(mesh.triangles.par_iter().map(|t| {
            let (vertices, material) = kept(t);
            Triangle::flat(vertices, material)
        }));
    } else {
        // Triangle i's normals at `first_normals + i` (left unused,
        // zero, for the rare triangle shaded flat): so each triangle
        // knows its index, and both vectors are written in place. (An
        // index past u32 cannot arise: the tree holds at most 2^30
        // objects.)
        normals.reserve(mesh.triangles.len());
        crate::huge_pages::advise(normals);
        let pairs = mesh.triangles.par_iter().enumerate().map(|(i, t)| {
            let (vertices, material) = kept(t);
            let n = shading.of(t, &vertices);
            let index = u32::try_from(first_normals + i)
                .ok()
                .filter(|_| n.is_some());
            let triangle = Triangle {
                vertices,
                material,
                normals: index.unwrap_or(Triangle::FLAT),
                uvs: Triangle::UNTEXTURED,
            };
            (triangle, n.unwrap_or_default())
        });
        let mut both = (std::mem::take(triangles), std::mem::take(normals));
        both.par_extend(pairs);
        (*triangles, *normals) = both;
    }
    if all_kept.into_inner() {
        return true;
    }
    triangles.truncate(first);
    normals.truncate(first_normals);
    false
}

/// Appends the triangles of `w` one by one, collapsed ones skipped, with
/// their normals and records (`records`); the first fault is the error: a
/// vertex index out of range or a face without a material.
fn build_one_by_one(
    w: &WorldMesh,
    material_of: impl Fn(&MeshTriangle) -> Option<u32>,
    records: &SurfaceRecords,
    triangles: &mut Vec<Triangle>,
    parts: &mut TriangleParts,
) -> Result<(), &'static str> {
    let WorldMesh {
        mesh,
        world,
        shading,
    } = *w;
    for t in &mesh.triangles {
        let Some(vertices) = t.corners_in(world) else {
            // The readers write only indices in range.
            return Err("a face has a vertex index out of range");
        };
        if !has_area(&vertices) {
            continue; // collapsed by an extreme scale: it can never be hit
        }
        let Some(material) = material_of(t) else {
            // The readers guarantee a material when asked for them.
            return Err("a face has no material");
        };
        let mut triangle = Triangle::flat(vertices, material);
        if let Some(n) = shading.of(t, &vertices) {
            triangle.normals = u32::try_from(parts.normals.len()).unwrap_or(Triangle::FLAT);
            parts.normals.push(n);
        }
        if records.any() {
            parts.add_record(&mut triangle, records.of(t));
        }
        triangles.push(triangle);
    }
    Ok(())
}

/// What a mesh entry's triangles keep beside their corners: the file's
/// texture coordinates where the triangle's material has a texture or a
/// map and every corner has them, its vertex colours, and its tangents
/// (carried by the entry's transform) where its material has a normal map.
/// None of them under an override material.
struct SurfaceRecords<'a> {
    mesh: &'a Mesh,
    transform: DMat3,
    /// -1 where `transform` mirrors (a tangent's bitangent sign flips), 1
    /// elsewhere.
    mirror: f64,
    with_materials: bool,
}

impl SurfaceRecords<'_> {
    /// Whether some triangle may have a record.
    fn any(&self) -> bool {
        let textured = |m: &super::mesh::MeshMaterial| m.texture.is_some() || m.maps.any();
        self.with_materials
            && (!self.mesh.colours.is_empty()
                || (!self.mesh.uvs.is_empty() && self.mesh.materials.iter().any(textured)))
    }

    /// Triangle `t`'s record.
    fn of(&self, t: &MeshTriangle) -> SurfaceRecord {
        let Some(m) = t
            .material()
            .and_then(|m| self.mesh.materials.get(m))
            .filter(|_| self.with_materials)
        else {
            return SurfaceRecord::default();
        };
        let textured = m.texture.is_some() || m.maps.any();
        let carry = |c: DVec4| (self.transform * c.truncate()).extend(c.w * self.mirror);
        SurfaceRecord {
            uvs: t.uvs_in(&self.mesh.uvs).filter(|_| textured),
            second_uvs: t
                .corners_in(&self.mesh.second_uvs)
                .filter(|_| textured && m.maps.second_uv != 0),
            colours: self.mesh.colours_of(t),
            tangents: self
                .mesh
                .tangents_of(t)
                .filter(|_| m.maps.normal.is_some())
                .map(|c| c.map(carry)),
        }
    }
}

/// How a mesh entry's triangles are shaded: flat, or with normals from the
/// file (carried to world space) and/or computed from the faces.
enum MeshNormals {
    Flat,
    /// The file's normals where all three corners of a triangle have one.
    FromFile {
        /// Each of the file's normals in world space, of unit length; None
        /// where it cannot be normalised.
        file: Vec<Option<DVec3>>,
    },
    /// The file's normals where a corner has one, else the angle-weighted
    /// normal of its shared vertex (computed in world space).
    Smooth {
        file: Vec<Option<DVec3>>,
        computed: Vec<DVec3>,
    },
}

impl MeshNormals {
    /// `world`: the mesh's vertices in world space.
    fn new(smooth: Option<bool>, mesh: &Mesh, world: &[DVec3], transform: DMat3) -> Self {
        // Each file normal carried once (not once per corner that names it).
        let file_normals = || {
            let normal_matrix = normals::normal_matrix(transform);
            mesh.normals
                .iter()
                .map(|&n| unit(normal_matrix * n))
                .collect()
        };
        match smooth {
            Some(false) => MeshNormals::Flat,
            // A file without normals is flat unless asked otherwise.
            None if mesh.normals.is_empty() => MeshNormals::Flat,
            None => MeshNormals::FromFile {
                file: file_normals(),
            },
            Some(true) => MeshNormals::Smooth {
                file: file_normals(),
                computed: normals::angle_weighted(world, &mesh.triangles, |t| {
                    t.corners.map(|c| c as usize)
                }),
            },
        }
    }

    /// The world-space unit normals of `t` (placed at `vertices`), or None
    /// for flat shading. A normal that cannot be normalised (zero in the
    /// file, or a vertex whose faces cancel) is the face's own normal.
    fn of(&self, t: &MeshTriangle, vertices: &[DVec3; 3]) -> Option<[DVec3; 3]> {
        let face = || unit((vertices[1] - vertices[0]).cross(vertices[2] - vertices[0]));
        let from_file = |file: &[Option<DVec3>], k: usize| {
            t.normal(k).and_then(|n| file.get(n).copied().flatten())
        };
        match self {
            MeshNormals::Flat => None,
            MeshNormals::FromFile { file } => {
                if (0..3).any(|k| t.normal(k).is_none()) {
                    return None;
                }
                let face = face()?;
                Some([0, 1, 2].map(|k| from_file(file, k).unwrap_or(face)))
            }
            MeshNormals::Smooth { file, computed } => {
                let face = face()?;
                Some([0, 1, 2].map(|k| {
                    from_file(file, k)
                        .or_else(|| computed.get(t.corners[k] as usize).copied().and_then(unit))
                        .unwrap_or(face)
                }))
            }
        }
    }
}
/// Rz * Ry * Rx * diag(scale), angles in degrees about the world axes.
pub(super) fn mesh_transform(scale: DVec3, rotate_degrees: DVec3) -> DMat3 {
    let r = rotate_degrees * (std::f64::consts::PI / 180.0);
    DMat3::from_rotation_z(r.z)
        * DMat3::from_rotation_y(r.y)
        * DMat3::from_rotation_x(r.x)
        * DMat3::from_diagonal(scale)
}
