//! A scene's `[[meshes]]` entries: each mesh file loaded, its vertices
//! placed in the world (scale, rotate, translate), its triangles built on
//! all threads straight into the scene's vectors, shaded flat or with the
//! file's or computed normals, and its materials added to the scene's.

use std::path::Path;

use glam::{DMat3, DVec3};
use rayon::prelude::*;

use super::mesh::{Mesh, MeshTriangle};
use super::mesh_file;
use super::normals::{self, unit};
use super::schema::{RawMesh, RawScale};
use super::validate::{Validator, MAX_COORDINATE};
use super::{Material, SceneError, Triangle};

impl Validator<'_> {
    /// Loads mesh `i`, transforms it to world space and appends its triangles
    /// (and, without an override, its MTL materials).
    pub(super) fn mesh(
        &self,
        i: usize,
        m: &RawMesh,
        override_material: Option<u32>,
        materials: &mut Vec<Material>,
        triangles: &mut Vec<Triangle>,
        normals: &mut Vec<[DVec3; 3]>,
    ) -> Result<(), SceneError> {
        let key = |k: &str| format!("meshes[{i}].{k}");
        let scale = match m.scale {
            RawScale::Uniform(s) => DVec3::splat(self.number(&|| key("scale"), s)?),
            RawScale::PerAxis(v) => self.vector(&|| key("scale"), v)?,
        };
        if scale.abs().min_element() == 0.0 {
            return Err(self.error(&key("scale"), "must be non-zero on every axis"));
        }
        let rotate = self.vector(&|| key("rotate"), m.rotate)?;
        let translate = self.position(&|| key("translate"), m.translate)?;
        let transform = mesh_transform(scale, rotate);

        let base = self.file.parent().unwrap_or(Path::new(""));
        let mesh_path = base.join(&m.path);
        let mesh = {
            let mut on_read = self.on_read.borrow_mut();
            mesh_file::load_mesh(&mesh_path, override_material.is_none(), &mut **on_read)
        }
        .map_err(|e| {
            if e.line.is_some() {
                return e;
            }
            // A mesh file at fault as a whole: also say which entry asked for it.
            let at = match self.map.get().and_then(|m| m.line_of_path(&key("path"))) {
                Some(line) => format!("{}:{line}", self.file.display()),
                None => self.file.display().to_string(),
            };
            let message = format!("{} (from {} in {at})", e.message, key("path"));
            e.reworded(message)
        })?;

        let first_material = materials.len() as u32;
        if override_material.is_none() {
            let file_name = Path::new(&m.path)
                .file_name()
                .map_or(m.path.clone(), |f| f.to_string_lossy().into_owned());
            // The mesh readers check that colours are finite; the scene's
            // rule that colours are >= 0 holds for them too.
            for mm in &mesh.materials {
                let colours = [("Ka", mm.ambient), ("Kd", mm.diffuse), ("Ks", mm.specular)];
                if let Some((statement, c)) = colours.iter().find(|(_, c)| c.min_element() < 0.0) {
                    let (kind, what) = match mesh_file::MeshFormat::of_path(&mesh_path) {
                        Some(mesh_file::MeshFormat::Gltf) => ("glTF", "colour"),
                        _ => ("MTL", *statement),
                    };
                    return Err(self.error(
                        &key("path"),
                        format!(
                            "{kind} material \"{}\" has a negative {what} colour {:?}; colour components must be >= 0",
                            mm.name,
                            c.to_array()
                        ),
                    ));
                }
            }
            materials.extend(mesh.materials.iter().map(|mm| Material {
                name: format!("{file_name}:{}", mm.name),
                ambient: mm.ambient,
                diffuse: mm.diffuse,
                specular: mm.specular,
                shininess: mm.shininess,
                reflection: mm.reflection,
            }));
        }
        let world = self.place(i, &mesh, transform, translate)?;
        let shading = MeshNormals::new(m.smooth, &mesh, &world, transform);
        let material_of = |t: &MeshTriangle| match (override_material, t.material()) {
            (Some(m), _) => Some(m),
            (None, Some(local)) => Some(first_material + local as u32),
            (None, None) => None,
        };
        // Usually every triangle is kept (none collapsed, every index in
        // range): then they are built on all threads, straight into the
        // scene's vector (rayon writes an indexed iterator in place), which
        // on two cores also halves the wait for its fresh pages. Built first
        // and checked on the way (a separate pass of checks took 15 ms of
        // the 1.1 M-triangle bunny's 0.22 s load); where one is not kept,
        // they are dropped and built again below.
        let (first, first_normals) = (triangles.len(), normals.len());
        let all_kept = std::sync::atomic::AtomicBool::new(true);
        let kept = |t: &MeshTriangle| {
            let vertices = t.corners_in(&world).filter(has_area);
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
                };
                (triangle, n.unwrap_or_default())
            });
            let mut both = (std::mem::take(triangles), std::mem::take(normals));
            both.par_extend(pairs);
            (*triangles, *normals) = both;
        }
        if all_kept.into_inner() {
            crate::huge_pages::free_in_background((mesh, world, shading));
            return Ok(());
        }
        triangles.truncate(first);
        normals.truncate(first_normals);
        // Otherwise one by one: collapsed triangles skipped, the first fault
        // reported.
        for t in &mesh.triangles {
            let Some(vertices) = t.corners_in(&world) else {
                // The readers write only indices in range.
                return Err(self.error(&key("path"), "a face has a vertex index out of range"));
            };
            if !has_area(&vertices) {
                continue; // collapsed by an extreme scale: it can never be hit
            }
            let Some(material) = material_of(t) else {
                // The readers guarantee a material when asked for them.
                return Err(self.error(&key("path"), "a face has no material"));
            };
            let mut triangle = Triangle::flat(vertices, material);
            if let Some(n) = shading.of(t, &vertices) {
                triangle.normals = u32::try_from(normals.len()).unwrap_or(Triangle::FLAT);
                normals.push(n);
            }
            triangles.push(triangle);
        }
        Ok(())
    }

    /// The mesh's shared vertices in world space, each transformed once.
    /// A vertex that lands beyond the GPU's range is an error only where a
    /// triangle uses it (an OBJ file may define vertices no face uses).
    fn place(
        &self,
        i: usize,
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
                    &format!("meshes[{i}].scale"),
                    "the transformed mesh has a non-finite vertex, or one beyond ±1e15 (the GPU computes in f32)",
                ));
            }
        }
        Ok(world)
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

pub(super) fn has_area(v: &[DVec3; 3]) -> bool {
    (v[1] - v[0]).cross(v[2] - v[0]).length_squared() > 0.0
}

#[cfg(test)]
mod tests {
    //! Meshes through the whole load: the scene's triangles and normals
    //! against coordinates worked out here from the files' numbers, so that
    //! a wrong vertex, normal or offset index shows.
    use super::*;
    use crate::scene::{load_scene, Scene};
    use std::path::PathBuf;

    /// A fresh folder under the temp dir, unique per process and test.
    fn temp_dir(tag: &str) -> PathBuf {
        let dir =
            std::env::temp_dir().join(format!("kdray-parse-test-{}-{tag}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    /// A scene of one mesh entry (`mesh` is the rest of its table), material `m`.
    fn mesh_scene(dir: &Path, mesh: &str) -> Scene {
        let path = dir.join("scene.toml");
        let text = format!(
            "[camera]\nposition = [0, 0, 10]\nlook_at = [0, 0, 0]\n\
             [[lights]]\nposition = [0, 10, 0]\n[materials.m]\ndiffuse = [1, 1, 1]\n\
             [[meshes]]\nmaterial = \"m\"\n{mesh}\n"
        );
        std::fs::write(&path, text).unwrap();
        load_scene(&path).unwrap_or_else(|e| panic!("{e}"))
    }

    fn assert_near(got: DVec3, want: DVec3) {
        assert!(
            (got - want).abs().max_element() < 1e-9,
            "got {got}, want {want}"
        );
    }

    fn assert_triangle(scene: &Scene, i: usize, vertices: [DVec3; 3], normals: Option<[DVec3; 3]>) {
        let t = &scene.triangles[i];
        for (got, want) in t.vertices.iter().zip(vertices) {
            assert_near(*got, want);
        }
        match (scene.normals_of(t), normals) {
            (Some(got), Some(want)) => {
                for (g, w) in got.iter().zip(want) {
                    assert_near(*g, w);
                }
            }
            (got, want) => assert_eq!(got, want),
        }
        assert_eq!(t.material, 0);
    }

    #[test]
    fn obj_indices_in_every_form_reach_the_right_vertices_and_normals() {
        let dir = temp_dir("obj-indices");
        // Vertex 3 is used by no face; placed, it lies at 1.8e15, beyond
        // the GPU's range, which only matters for vertices faces use.
        std::fs::write(
            dir.join("m.obj"),
            "v 0 0 0\nv 2 0 0\nv 9e14 9 9\nv 0 3 0\nvt 0 0\n\
             vn 0 0 1\nvn 1 0 0\nv 1 1 2\nvn 0 1 0\n\
             f 1//1 2//2 4//3\n\
             f -1/1/-1 -4/1/-3 -2/1/-2\n\
             f 5 1/1 -4\n",
        )
        .unwrap();
        let scene = mesh_scene(
            &dir,
            "path = \"m.obj\"\nscale = [2, 1, 0.5]\nrotate = [0, 0, 90]\ntranslate = [1, 2, 3]",
        );
        // Scaled by (2, 1, 0.5), turned 90 degrees about z, then moved.
        let place = |x: f64, y: f64, z: f64| DVec3::new(1.0 - y, 2.0 + 2.0 * x, 3.0 + 0.5 * z);
        let v = [
            place(0.0, 0.0, 0.0),
            place(2.0, 0.0, 0.0),
            place(9e14, 9.0, 9.0),
            place(0.0, 3.0, 0.0),
            place(1.0, 1.0, 2.0),
        ];
        // Normals go through the inverse scale, then the same turn.
        let turn = |x: f64, y: f64, z: f64| {
            let n = DVec3::new(x / 2.0, y, z * 2.0);
            DVec3::new(-n.y, n.x, n.z).normalize()
        };
        let n = [
            turn(0.0, 0.0, 1.0),
            turn(1.0, 0.0, 0.0),
            turn(0.0, 1.0, 0.0),
        ];
        assert_eq!(scene.triangles.len(), 3);
        assert_triangle(&scene, 0, [v[0], v[1], v[3]], Some([n[0], n[1], n[2]]));
        // -1 is the fifth vertex and the third normal, as defined so far.
        assert_triangle(&scene, 1, [v[4], v[1], v[3]], Some([n[2], n[0], n[1]]));
        // Corners without normals: flat shading from the file.
        assert_triangle(&scene, 2, [v[4], v[0], v[1]], None);
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn triangles_a_scale_collapses_are_skipped_and_the_others_kept_in_order() {
        let dir = temp_dir("collapse");
        std::fs::write(
            dir.join("m.obj"),
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 4\nf 1 2 3\nf 1 3 4\n",
        )
        .unwrap();
        // The face in z = 0 keeps an area of 1e-320, whose square is 0 in
        // f64; the two upright ones keep 1e-160.
        let scene = mesh_scene(&dir, "path = \"m.obj\"\nscale = [1e-160, 1e-160, 1]");
        let (o, x, y, z) = (
            DVec3::ZERO,
            DVec3::new(1e-160, 0.0, 0.0),
            DVec3::new(0.0, 1e-160, 0.0),
            DVec3::Z,
        );
        let got: Vec<_> = scene.triangles.iter().map(|t| t.vertices).collect();
        assert_eq!(got, [[o, x, z], [o, y, z]]);
        // With a normal per face (its own face's, on the axes, which the
        // normal matrix keeps), each kept triangle keeps its own.
        std::fs::write(
            dir.join("n.obj"),
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvn 0 -1 0\nvn 0 0 1\nvn 2 0 0\n\
             f 1//1 2//1 4//1\nf 1//2 2//2 3//2\nf 1//3 3//3 4//3\n",
        )
        .unwrap();
        let scene = mesh_scene(&dir, "path = \"n.obj\"\nscale = [1e-160, 1e-160, 1]");
        let got: Vec<_> = scene
            .triangles
            .iter()
            .map(|t| (t.vertices, scene.normals_of(t)))
            .collect();
        let want = [
            ([o, x, z], Some([DVec3::NEG_Y; 3])),
            ([o, y, z], Some([DVec3::X; 3])),
        ];
        assert_eq!(got, want);
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// `floats` as little-endian f32 bytes.
    fn f32_bytes(floats: &[f32]) -> Vec<u8> {
        floats.iter().flat_map(|f| f.to_le_bytes()).collect()
    }

    #[test]
    fn gltf_primitives_are_offset_into_one_mesh_under_a_node_transform() {
        let dir = temp_dir("gltf-offsets");
        // Primitive 0: five vertices (the fifth unused), no normals, two
        // indexed triangles. Primitive 1: three vertices with normals, not
        // indexed. So primitive 1's vertices start at 5 and its normals at 0.
        let first: [[f32; 3]; 5] = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
            [7.0, 7.0, 7.0],
        ];
        let indices: [u16; 6] = [0, 1, 2, 0, 2, 3];
        let second: [[f32; 3]; 3] = [[0.0, 0.0, 1.0], [0.0, 2.0, 1.0], [0.0, 0.0, 3.0]];
        let normals: [[f32; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        let mut bin = f32_bytes(first.as_flattened());
        bin.extend(indices.iter().flat_map(|i| i.to_le_bytes()));
        bin.extend(f32_bytes(second.as_flattened()));
        bin.extend(f32_bytes(normals.as_flattened()));
        assert_eq!(bin.len(), 144);
        std::fs::write(dir.join("m.bin"), &bin).unwrap();
        // The parent turns 90 degrees about z (quaternion) and moves; the
        // child scales x by 2.
        let h = std::f32::consts::FRAC_1_SQRT_2;
        let gltf = format!(
            r#"{{"asset": {{"version": "2.0"}}, "scene": 0, "scenes": [{{"nodes": [0]}}],
            "nodes": [{{"translation": [1, 2, 3], "rotation": [0, 0, {h}, {h}], "children": [1]}},
                      {{"scale": [2, 1, 1], "mesh": 0}}],
            "meshes": [{{"primitives": [
                {{"attributes": {{"POSITION": 0}}, "indices": 1}},
                {{"attributes": {{"POSITION": 2, "NORMAL": 3}}}}]}}],
            "buffers": [{{"byteLength": 144, "uri": "m.bin"}}],
            "bufferViews": [{{"buffer": 0, "byteOffset": 0, "byteLength": 60}},
                            {{"buffer": 0, "byteOffset": 60, "byteLength": 12}},
                            {{"buffer": 0, "byteOffset": 72, "byteLength": 36}},
                            {{"buffer": 0, "byteOffset": 108, "byteLength": 36}}],
            "accessors": [
                {{"bufferView": 0, "componentType": 5126, "count": 5, "type": "VEC3", "min": [0, 0, 0], "max": [7, 7, 7]}},
                {{"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"}},
                {{"bufferView": 2, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 1], "max": [0, 2, 3]}},
                {{"bufferView": 3, "componentType": 5126, "count": 3, "type": "VEC3"}}]}}"#
        );
        std::fs::write(dir.join("m.gltf"), gltf).unwrap();
        let scene = mesh_scene(&dir, "path = \"m.gltf\"");
        // Scaled by (2, 1, 1), turned 90 degrees about z, then moved (the
        // f32 quaternion is within 1e-7 of the exact turn).
        let place = |p: [f32; 3]| {
            let [x, y, z] = p.map(f64::from);
            DVec3::new(1.0 - y, 2.0 + 2.0 * x, 3.0 + z)
        };
        let turn = |n: [f32; 3]| {
            let [x, y, z] = n.map(f64::from);
            DVec3::new(-y, x / 2.0, z).normalize()
        };
        let near = |got: DVec3, want: DVec3| (got - want).abs().max_element() < 1e-6;
        let check = |t: &Triangle, vertices: [DVec3; 3], normals: Option<[DVec3; 3]>| {
            for (got, want) in t.vertices.iter().zip(vertices) {
                assert!(near(*got, want), "got {got}, want {want}");
            }
            let got_normals = scene.normals_of(t);
            assert_eq!(got_normals.is_some(), normals.is_some(), "{t:?}");
            if let (Some(got), Some(want)) = (got_normals, normals) {
                for (g, w) in got.iter().zip(want) {
                    assert!(near(*g, w), "normal {g}, want {w}");
                }
            }
        };
        assert_eq!(scene.triangles.len(), 3);
        let p = first.map(place);
        check(&scene.triangles[0], [p[0], p[1], p[2]], None);
        check(&scene.triangles[1], [p[0], p[2], p[3]], None);
        check(
            &scene.triangles[2],
            second.map(place),
            Some(normals.map(turn)),
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
}
