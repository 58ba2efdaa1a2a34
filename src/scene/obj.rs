//! A small hand-written Wavefront OBJ + MTL reader.
//!
//! Only what a ray tracer of triangles needs is kept: vertex positions,
//! vertex normals (`vn`, for smooth shading), faces (fan-triangulated) and,
//! on request, the Phong colours of the MTL materials the faces use.
//! Everything else in the formats (texture coordinates, groups, smoothing
//! groups, maps, ...) is ignored.
//!
//! Every fault is a [`SceneError`] naming the file (the OBJ or the MTL), the
//! 1-based line and the statement at fault. No input makes this module panic.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use glam::DVec3;

use super::mesh::{mesh_index, Mesh, MeshMaterial, MeshTriangle, NO_INDEX};
use super::obj_chunks;
use super::SceneError;

/// Reads an OBJ file. With `with_materials` false (the scene overrides the material) mtllib/usemtl are ignored entirely (an MTL file need not exist).
/// A file that is not UTF-8 text, or that has no face with an area, is an
/// error: it would draw nothing (a binary file read as OBJ is all unknown
/// statements).
pub fn load_obj(path: &Path, with_materials: bool) -> Result<Mesh, SceneError> {
    load_obj_observed(path, with_materials, &mut |_| {})
}

/// [`load_obj`], calling `on_read` with the OBJ and each MTL file just before
/// reading it.
pub fn load_obj_observed(
    path: &Path,
    with_materials: bool,
    on_read: &mut dyn FnMut(&Path),
) -> Result<Mesh, SceneError> {
    on_read(path);
    let bytes = super::input_file::read_input_file(path).map_err(|e| {
        SceneError::new(path, None, None, format!("cannot read OBJ file: {e}")).with_source(e)
    })?;
    let mut faces = 0usize;
    let mesh = parse_obj_bytes(&bytes, path, with_materials, on_read, &mut faces)?;
    crate::huge_pages::free_in_background(bytes);
    if mesh.triangles.is_empty() {
        let message = if faces == 0 {
            "no faces: the file has no `f` statement, so the mesh would draw nothing".to_string()
        } else {
            format!("all {faces} faces have zero area, so the mesh would draw nothing")
        };
        return Err(SceneError::new(path, None, None, message));
    }
    Ok(mesh)
}

/// Parses OBJ text already read (for tests and fuzzing); `path` is only used for error messages and to resolve mtllib paths relative to its folder.
/// Unlike [`load_obj`], a text without faces is an empty mesh.
pub fn parse_obj(text: &str, path: &Path, with_materials: bool) -> Result<Mesh, SceneError> {
    parse_obj_counting(text, path, with_materials, &mut |_| {}, &mut 0)
}

/// The parser of a text; `faces` counts the `f` statements.
pub(super) fn parse_obj_counting(
    text: &str,
    path: &Path,
    with_materials: bool,
    on_read: &mut dyn FnMut(&Path),
    faces: &mut usize,
) -> Result<Mesh, SceneError> {
    parse_obj_bytes(text.as_bytes(), path, with_materials, on_read, faces)
}

/// The parser of a file's bytes; `faces` counts the `f` statements. The
/// fast path (`obj_chunks`: one chunk per core, each chunk's UTF-8 checked
/// on its thread) parses the file; it leaves every error, invalid UTF-8
/// included, and the forms it does not handle, to the reference parser
/// below, so messages come from one place.
fn parse_obj_bytes(
    bytes: &[u8],
    path: &Path,
    with_materials: bool,
    on_read: &mut dyn FnMut(&Path),
    faces: &mut usize,
) -> Result<Mesh, SceneError> {
    let body = bytes.strip_prefix("\u{feff}".as_bytes()).unwrap_or(bytes);
    let materials = with_materials.then_some(obj_chunks::MaterialFiles {
        path,
        on_read: &mut *on_read,
    });
    let mtl_reads = match obj_chunks::parse(body, obj_chunks::threads_for(body.len()), materials) {
        obj_chunks::Outcome::Mesh(mesh, statements) => {
            *faces = statements;
            return Ok(mesh);
        }
        obj_chunks::Outcome::Declined { mtl_reads } => mtl_reads,
    };
    // The reference parser reads the same MTL files first: the observer
    // has been told of them already.
    let mut told = 0usize;
    let mut on_read_rest = |p: &Path| {
        if told < mtl_reads {
            told += 1;
        } else {
            on_read(p);
        }
    };
    let text = utf8_text(bytes, path, "OBJ")?;
    parse_reference(text, path, with_materials, &mut on_read_rest, faces)
}

/// The reference parser, one line at a time: the meaning of every statement
/// and every error message. `faces` counts the `f` statements.
pub(super) fn parse_reference(
    text: &str,
    path: &Path,
    with_materials: bool,
    on_read: &mut dyn FnMut(&Path),
    faces: &mut usize,
) -> Result<Mesh, SceneError> {
    let mut mesh = Mesh::default();
    // Reused for every face so that faces allocate nothing: (v, vn) indices,
    // the normal's NO_INDEX where the corner names none.
    let mut face: Vec<(u32, u32)> = Vec::with_capacity(8);

    // Materials state (only touched when `with_materials`).
    let mut library: HashMap<String, MeshMaterial> = HashMap::new();
    let mut loaded_libraries: Vec<PathBuf> = Vec::new();
    let mut used: HashMap<String, usize> = HashMap::new();
    // The name and line of the last usemtl, and its index into
    // `mesh.materials` once a face has resolved it.
    let mut current: Option<(&str, usize)> = None;
    let mut current_index: Option<usize> = None;

    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    for (number, raw) in text.split('\n').enumerate() {
        let line_no = number + 1;
        let line = strip_comment(raw);
        let mut tokens = line.split_ascii_whitespace();
        let Some(keyword) = tokens.next() else {
            continue;
        };
        let err = |message: String| {
            SceneError::new(path, Some(line_no), Some(keyword.to_string()), message)
        };

        match keyword {
            "v" => {
                let mut xyz = [0.0f64; 3];
                let mut count = 0usize;
                for token in tokens {
                    // x y z [w]; anything past x y z (w, or the vertex colours
                    // some exporters write) must be numbers too but is unused.
                    let value = parse_number(token).map_err(err)?;
                    if count < 3 {
                        xyz[count] = value;
                    }
                    count += 1;
                }
                if count < 3 {
                    return Err(err(format!(
                        "expected 3 coordinates (x y z [w]), found {count}"
                    )));
                }
                mesh.positions.push(DVec3::from_array(xyz));
            }
            "vn" => {
                let mut xyz = [0.0f64; 3];
                let mut count = 0usize;
                for token in tokens {
                    let value = parse_number(token).map_err(err)?;
                    if count < 3 {
                        xyz[count] = value;
                    }
                    count += 1;
                }
                if count != 3 {
                    return Err(err(format!("expected 3 numbers (x y z), found {count}")));
                }
                mesh.normals.push(DVec3::from_array(xyz));
            }
            "f" => {
                *faces += 1;
                face.clear();
                for token in tokens {
                    let index = resolve_index(token, mesh.positions.len()).map_err(err)?;
                    let normal = resolve_normal(token, mesh.normals.len()).map_err(err)?;
                    face.push((
                        as_mesh_index(index, token, "vertex").map_err(err)?,
                        match normal {
                            Some(n) => as_mesh_index(n, token, "normal").map_err(err)?,
                            None => NO_INDEX,
                        },
                    ));
                }
                if face.len() < 3 {
                    return Err(err(format!(
                        "a face needs at least 3 vertices, found {}",
                        face.len()
                    )));
                }

                let material = if with_materials {
                    if current_index.is_none() {
                        let Some((name, usemtl_line)) = current else {
                            return Err(SceneError::new(
                                path,
                                Some(line_no),
                                Some("usemtl".to_string()),
                                "face has no material: no usemtl statement before it",
                            ));
                        };
                        let Some(found) = library.get(name) else {
                            let message = if loaded_libraries.is_empty() {
                                format!("material '{name}' is not defined: no mtllib statement loaded an MTL file")
                            } else {
                                format!(
                                    "material '{name}' is not defined in {}",
                                    loaded_libraries
                                        .iter()
                                        .map(|p| p.display().to_string())
                                        .collect::<Vec<_>>()
                                        .join(", ")
                                )
                            };
                            return Err(SceneError::new(
                                path,
                                Some(usemtl_line),
                                Some("usemtl".to_string()),
                                message,
                            ));
                        };
                        let index = *used.entry(name.to_string()).or_insert_with(|| {
                            mesh.materials.push(found.clone());
                            mesh.materials.len() - 1
                        });
                        current_index = Some(index);
                    }
                    current_index
                } else {
                    None
                };
                let material = match material {
                    Some(m) => as_mesh_index(m, "usemtl", "material").map_err(err)?,
                    None => NO_INDEX,
                };

                let first = face[0];
                for pair in face[1..].windows(2) {
                    let corners = [first, pair[0], pair[1]];
                    let [a, b, c] = corners.map(|(v, _)| mesh.positions[v as usize]);
                    // Skip zero-area triangles: they cannot be hit and have no
                    // normal. "Zero" is the cross product's f64 length, so a
                    // cross product so small that its squared length underflows
                    // counts as zero too (it could not be normalised).
                    if (b - a).cross(c - a).length() == 0.0 {
                        continue;
                    }
                    mesh.triangles.push(MeshTriangle {
                        corners: corners.map(|(v, _)| v),
                        normals: corners.map(|(_, n)| n),
                        material,
                    });
                }
            }
            "mtllib" if with_materials => {
                let mut any = false;
                for name in tokens {
                    any = true;
                    let mtl_path = path.parent().unwrap_or_else(|| Path::new("")).join(name);
                    if loaded_libraries.contains(&mtl_path) {
                        continue;
                    }
                    on_read(&mtl_path);
                    let mtl_text = super::input_file::read_input_file(&mtl_path).map_err(|e| {
                        err(format!("cannot read MTL file {}: {e}", mtl_path.display()))
                            .with_source(e)
                    })?;
                    parse_mtl(&String::from_utf8_lossy(&mtl_text), &mtl_path, &mut library)?;
                    loaded_libraries.push(mtl_path);
                }
                if !any {
                    return Err(err("expected the name of at least one MTL file".to_string()));
                }
                // A material that was undefined before may be defined now.
                current_index = None;
            }
            "usemtl" if with_materials => {
                let name = rest_of_line(line, keyword);
                if name.is_empty() {
                    return Err(err("expected a material name".to_string()));
                }
                current = Some((name, line_no));
                current_index = None;
            }
            // vt, vp, o, g, s, l, p, mtllib/usemtl without materials, and
            // anything unknown.
            _ => {}
        }
    }

    Ok(mesh)
}

/// Parses an MTL file into `library`. A material already in `library`
/// (defined by an earlier MTL file, or earlier in this one) keeps its first
/// definition.
pub(super) fn parse_mtl(
    text: &str,
    path: &Path,
    library: &mut HashMap<String, MeshMaterial>,
) -> Result<(), SceneError> {
    // The material being defined; added to the library when the next one
    // starts or the file ends.
    let mut current: Option<MeshMaterial> = None;
    fn finish(material: Option<MeshMaterial>, library: &mut HashMap<String, MeshMaterial>) {
        if let Some(material) = material {
            library.entry(material.name.clone()).or_insert(material);
        }
    }

    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    for (number, raw) in text.split('\n').enumerate() {
        let line_no = number + 1;
        let line = strip_comment(raw);
        let mut tokens = line.split_ascii_whitespace();
        let Some(keyword) = tokens.next() else {
            continue;
        };
        let err = |message: String| {
            SceneError::new(path, Some(line_no), Some(keyword.to_string()), message)
        };

        if keyword.eq_ignore_ascii_case("newmtl") {
            let name = rest_of_line(line, keyword);
            if name.is_empty() {
                return Err(err("expected a material name".to_string()));
            }
            finish(current.take(), library);
            current = Some(MeshMaterial {
                name: name.to_string(),
                ambient: DVec3::ZERO,
                diffuse: DVec3::ZERO,
                specular: DVec3::ZERO,
                shininess: 0.0,
                reflection: 0.0,
            });
            continue;
        }

        let is_colour = ["Ka", "Kd", "Ks"]
            .iter()
            .any(|k| keyword.eq_ignore_ascii_case(k));
        let is_shininess = keyword.eq_ignore_ascii_case("Ns");
        if !is_colour && !is_shininess {
            continue; // d, Tr, illum, Ni, Ke, map_*, ...
        }
        let Some(material) = current.as_mut() else {
            return Err(err("comes before any newmtl statement".to_string()));
        };

        let mut values = [0.0f64; 3];
        let mut count = 0usize;
        for token in tokens {
            let value = parse_number(token).map_err(err)?;
            if count < 3 {
                values[count] = value;
            }
            count += 1;
        }

        if is_shininess {
            if count != 1 {
                return Err(err(format!("expected 1 number, found {count}")));
            }
            if values[0] < 0.0 {
                return Err(err(format!("shininess must be >= 0, found {}", values[0])));
            }
            material.shininess = values[0];
        } else {
            let colour = match count {
                1 => DVec3::splat(values[0]),
                3 => DVec3::from_array(values),
                _ => {
                    return Err(err(format!(
                        "expected 3 numbers (r g b) or 1 (grey), found {count}"
                    )))
                }
            };
            match keyword.as_bytes()[1].to_ascii_lowercase() {
                b'a' => material.ambient = colour,
                b'd' => material.diffuse = colour,
                _ => material.specular = colour,
            }
        }
    }
    finish(current.take(), library);
    Ok(())
}

/// The file's `bytes` as UTF-8 text. Not UTF-8 is an error naming the line
/// of the first bad byte: it is how a binary file (a `.glb` misnamed
/// `.obj`, an image) shows, and reading it as text would silently give an
/// empty mesh.
fn utf8_text<'b>(bytes: &'b [u8], path: &Path, what: &str) -> Result<&'b str, SceneError> {
    std::str::from_utf8(bytes).map_err(|e| {
        let valid = &bytes[..e.valid_up_to()];
        let line = valid.iter().filter(|&&b| b == b'\n').count() + 1;
        let offset = valid.len();
        SceneError::new(
            path,
            Some(line),
            None,
            format!("not a text {what} file: invalid UTF-8 at byte {offset} (a binary file? kdray reads binary glTF as .glb)"),
        )
        .with_source(e)
    })
}

/// The line without its `\r` and anything from `#` on.
pub(super) fn strip_comment(line: &str) -> &str {
    let line = line.strip_suffix('\r').unwrap_or(line);
    match line.find('#') {
        Some(at) => &line[..at],
        None => line,
    }
}

/// Everything after the keyword (the line's first token), trimmed: names may
/// contain spaces.
pub(super) fn rest_of_line<'a>(line: &'a str, keyword: &str) -> &'a str {
    let line = line.trim_start_matches(|c: char| c.is_ascii_whitespace());
    line.get(keyword.len()..).unwrap_or("").trim()
}

/// A finite f64.
fn parse_number(token: &str) -> Result<f64, String> {
    match token.parse::<f64>() {
        Ok(value) if value.is_finite() => Ok(value),
        Ok(_) => Err(format!("'{token}' is not a finite number")),
        Err(_) => Err(format!("'{token}' is not a number")),
    }
}

/// The 0-based vertex index of a face token `v`, `v/vt`, `v//vn` or
/// `v/vt/vn`, given the number of vertices defined so far.
fn resolve_index(token: &str, defined: usize) -> Result<usize, String> {
    let v = token.split('/').next().unwrap_or("");
    resolve(v, token, "vertex", defined)
}

/// The 0-based normal index of a face token (`v//vn` or `v/vt/vn`), None
/// for `v` and `v/vt`, given the number of normals defined so far.
fn resolve_normal(token: &str, defined: usize) -> Result<Option<usize>, String> {
    match token.split('/').nth(2) {
        None | Some("") => Ok(None),
        Some(vn) => resolve(vn, token, "normal", defined).map(Some),
    }
}

/// A resolved 0-based index as a mesh's u32 index; an error past what a
/// mesh can index (over four billion vertices, normals or materials: never
/// in a file that fits in memory, but never a panic either).
fn as_mesh_index(index: usize, token: &str, what: &str) -> Result<u32, String> {
    mesh_index(index).ok_or_else(|| {
        format!(
            "{what} index {} in '{token}' is beyond the {NO_INDEX} a mesh can index",
            index + 1
        )
    })
}

/// An OBJ index (1-based, or negative: -1 is the last defined so far).
fn resolve(text: &str, token: &str, what: &str, defined: usize) -> Result<usize, String> {
    let Ok(index) = text.parse::<i64>() else {
        return Err(format!("'{token}' is not a {what} index"));
    };
    let resolved = if index > 0 {
        usize::try_from(index - 1).ok().filter(|&i| i < defined)
    } else if index < 0 {
        // -1 is the last vertex defined so far.
        usize::try_from(index.unsigned_abs())
            .ok()
            .and_then(|back| defined.checked_sub(back))
    } else {
        return Err(format!(
            "{what} index 0 in '{token}': OBJ indices start at 1"
        ));
    };
    resolved.ok_or_else(|| {
        let plural = if what == "vertex" {
            "vertices"
        } else {
            "normals"
        };
        format!(
            "{what} index {index} in '{token}' is out of range: {defined} {plural} defined so far"
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicUsize, Ordering};

    fn p() -> &'static Path {
        Path::new("mesh.obj")
    }

    fn parse(text: &str) -> Mesh {
        parse_obj(text, p(), false).unwrap_or_else(|e| panic!("parse failed: {e}"))
    }

    fn parse_err(text: &str, with_materials: bool) -> SceneError {
        match parse_obj(text, p(), with_materials) {
            Ok(mesh) => panic!("expected an error, got {mesh:?}"),
            Err(e) => e,
        }
    }

    fn assert_err(e: &SceneError, file: &Path, line: usize, key: &str) {
        assert_eq!(e.file, file, "{e}");
        assert_eq!(e.line, Some(line), "{e}");
        assert_eq!(e.key.as_deref(), Some(key), "{e}");
        assert!(!e.message.is_empty());
        assert!(!e.to_string().contains('\n'));
    }

    fn d(x: f64, y: f64, z: f64) -> DVec3 {
        DVec3::new(x, y, z)
    }

    /// The vertices of triangle `i` of `mesh`.
    fn vertices(mesh: &Mesh, i: usize) -> [DVec3; 3] {
        mesh.vertices(&mesh.triangles[i]).unwrap()
    }

    /// A fresh folder under the temp dir, unique per process and call.
    fn temp_dir(tag: &str) -> PathBuf {
        static COUNTER: AtomicUsize = AtomicUsize::new(0);
        let n = COUNTER.fetch_add(1, Ordering::Relaxed);
        let dir =
            std::env::temp_dir().join(format!("kdray-obj-test-{}-{tag}-{n}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    const SQUARE: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";

    #[test]
    fn single_triangle() {
        let mesh = parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
        assert_eq!(
            mesh.triangles,
            vec![MeshTriangle {
                corners: [0, 1, 2],
                normals: [NO_INDEX; 3],
                material: NO_INDEX
            }]
        );
        assert_eq!(
            mesh.positions,
            [d(0., 0., 0.), d(1., 0., 0.), d(0., 1., 0.)]
        );
        assert!(mesh.normals.is_empty());
        assert!(mesh.materials.is_empty());
    }

    #[test]
    fn w_coordinate_is_ignored() {
        let mesh = parse("v 0 0 0 1\nv 1 0 0 0.5\nv 0 1 0 2\nf 1 2 3\n");
        assert_eq!(
            vertices(&mesh, 0),
            [d(0., 0., 0.), d(1., 0., 0.), d(0., 1., 0.)]
        );
    }

    #[test]
    fn quad_is_fan_triangulated() {
        let mesh = parse(&format!("{SQUARE}f 1 2 3 4\n"));
        let [a, b, c, e] = [d(0., 0., 0.), d(1., 0., 0.), d(1., 1., 0.), d(0., 1., 0.)];
        assert_eq!(mesh.triangles.len(), 2);
        assert_eq!(vertices(&mesh, 0), [a, b, c]);
        assert_eq!(vertices(&mesh, 1), [a, c, e]);
    }

    #[test]
    fn pentagon_gives_three_triangles() {
        let text = "v 0 0 0\nv 2 0 0\nv 3 1 0\nv 1 2 0\nv -1 1 0\nf 1 2 3 4 5\n";
        let mesh = parse(text);
        let v = [
            d(0., 0., 0.),
            d(2., 0., 0.),
            d(3., 1., 0.),
            d(1., 2., 0.),
            d(-1., 1., 0.),
        ];
        let got: Vec<_> = (0..mesh.triangles.len())
            .map(|i| vertices(&mesh, i))
            .collect();
        assert_eq!(
            got,
            vec![[v[0], v[1], v[2]], [v[0], v[2], v[3]], [v[0], v[3], v[4]]]
        );
    }

    #[test]
    fn all_vertex_token_forms() {
        let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\n\
                    f 1 2 3\nf 1/1 2/2 3/3\nf 1//1 2//1 3//1\nf 1/1/1 2/2/1 3/3/1\n";
        let mesh = parse(text);
        assert_eq!(mesh.triangles.len(), 4);
        for i in 0..4 {
            assert_eq!(
                vertices(&mesh, i),
                [d(0., 0., 0.), d(1., 0., 0.), d(0., 1., 0.)]
            );
        }
        // Only the `v//vn` and `v/vt/vn` forms name normals.
        let normals: Vec<_> = mesh.triangles.iter().map(|t| t.normals).collect();
        assert_eq!(normals, [[NO_INDEX; 3], [NO_INDEX; 3], [0; 3], [0; 3]]);
    }

    #[test]
    fn negative_indices_are_relative_to_vertices_so_far() {
        // -1 is the last vertex defined before the face, not in the file.
        let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nv 5 5 5\nv 6 5 5\nvn 0 0 1\nf -5//1 -1//1 -2//1\n";
        let mesh = parse(text);
        assert_eq!(
            vertices(&mesh, 0),
            [d(0., 0., 0.), d(1., 0., 0.), d(0., 1., 0.)]
        );
        assert_eq!(
            vertices(&mesh, 1),
            [d(0., 0., 0.), d(6., 5., 5.), d(5., 5., 5.)]
        );
        assert_eq!(mesh.triangles[1].corners, [0, 4, 3]);
        assert_eq!(mesh.triangles[1].normals, [0; 3]);
    }

    #[test]
    fn zero_area_faces_are_skipped() {
        // Repeated vertex, collinear vertices; then a quad whose first fan
        // triangle is degenerate but whose second is not.
        let text = "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\n\
                    f 1 1 4\nf 1 2 3\nf 1 2 3 4\n";
        let mesh = parse(text);
        assert_eq!(mesh.triangles.len(), 1);
        assert_eq!(
            vertices(&mesh, 0),
            [d(0., 0., 0.), d(2., 0., 0.), d(0., 1., 0.)]
        );
        // Tiny but non-zero area is kept...
        let mesh = parse("v 0 0 0\nv 1e-10 0 0\nv 0 1e-10 0\nf 1 2 3\n");
        assert_eq!(mesh.triangles.len(), 1);
        // ...unless the cross product's length underflows to 0 in f64 (its
        // normal could not be computed either).
        let mesh = parse("v 0 0 0\nv 1e-100 0 0\nv 0 1e-100 0\nf 1 2 3\n");
        assert_eq!(mesh.triangles.len(), 0);
    }

    #[test]
    fn ignored_statements_comments_crlf_and_whitespace() {
        let text = "# a comment\r\n\r\n  \t \r\nmtllib nowhere.mtl\r\no thing\r\ng group\r\ns 1\r\ns off\r\n\
                    vt 0.5 0.5\r\nvn 0 0 1\r\nvp 0.1 0.2\r\nusemtl nothing\r\n\
                    v   0\t0   0   # trailing comment\r\nv 1 0 0#glued\r\nv 0 1 0\r\n\
                    l 1 2\r\np 1\r\ncstype bspline\r\nfoo bar baz\r\n\
                    f  1   2\t3  # the face\r\n#f 1 2\r\n";
        let mesh = parse(text);
        assert_eq!(mesh.triangles.len(), 1);
        assert_eq!(
            vertices(&mesh, 0),
            [d(0., 0., 0.), d(1., 0., 0.), d(0., 1., 0.)]
        );
    }

    #[test]
    fn byte_order_mark_is_skipped() {
        let mesh = parse("\u{feff}v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
        assert_eq!(mesh.triangles.len(), 1);
    }

    #[test]
    fn material_names_may_contain_spaces() {
        let dir = temp_dir("spaces");
        let obj = dir.join("m.obj");
        std::fs::write(
            &obj,
            "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl  my gold  # c\nf 1 2 3\n",
        )
        .unwrap();
        std::fs::write(
            dir.join("m.mtl"),
            "\u{feff}newmtl my gold\t\r\n  Kd 1 1 0\r\n",
        )
        .unwrap();
        let mesh = load_obj(&obj, true).unwrap();
        assert_eq!(mesh.materials[0].name, "my gold");
        assert_eq!(mesh.materials[0].diffuse, d(1., 1., 0.));
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn empty_input_is_an_empty_mesh() {
        assert_eq!(parse(""), Mesh::default());
        assert_eq!(parse("# nothing\n\n"), Mesh::default());
    }

    #[test]
    fn missing_mtl_is_fine_without_materials() {
        let dir = temp_dir("nomtl");
        let obj = dir.join("m.obj");
        std::fs::write(
            &obj,
            "mtllib missing.mtl\nusemtl gold\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
        )
        .unwrap();
        let mesh = load_obj(&obj, false).unwrap();
        assert_eq!(mesh.triangles.len(), 1);
        assert_eq!(mesh.triangles[0].material(), None);
        assert!(mesh.materials.is_empty());
        // With materials the missing file is an error at the mtllib line.
        let e = load_obj(&obj, true).unwrap_err();
        assert_err(&e, &obj, 1, "mtllib");
        assert!(e.message.contains("missing.mtl"), "{e}");
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn mtllib_is_relative_to_the_obj_folder() {
        let dir = temp_dir("mtl");
        std::fs::create_dir_all(dir.join("sub/mat")).unwrap();
        let obj = dir.join("sub/m.obj");
        std::fs::write(
            &obj,
            "mtllib mat/a.mtl  mat/b.mtl\r\n\
             v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n\
             usemtl teal\nf 1 2 3\nusemtl gold\nf 1 2 3 4\nusemtl teal\nf 2 4 3\n",
        )
        .unwrap();
        std::fs::write(
            dir.join("sub/mat/a.mtl"),
            "# materials\nnewmtl gold\nKa 0.1 0.08 0.02\nKd 0.75 0.6 0.15\nKs 0.6 0.55 0.4\nNs 128\n\
             illum 2\nd 1\nTr 0\nNi 1.5\nKe 0 0 0\nmap_Kd gold.png\n\nnewmtl unused\nKd 1\n",
        )
        .unwrap();
        std::fs::write(dir.join("sub/mat/b.mtl"), "newmtl teal\r\nKd 0.5\r\n").unwrap();

        let mesh = load_obj(&obj, true).unwrap();
        let names: Vec<_> = mesh.materials.iter().map(|m| m.name.as_str()).collect();
        // Deduplicated; only used ones, in order of first use.
        assert_eq!(names, ["teal", "gold"]);
        assert_eq!(
            mesh.materials[0],
            MeshMaterial {
                name: "teal".into(),
                ambient: DVec3::ZERO,
                diffuse: DVec3::splat(0.5),
                specular: DVec3::ZERO,
                shininess: 0.0,
                reflection: 0.0,
            }
        );
        assert_eq!(
            mesh.materials[1],
            MeshMaterial {
                name: "gold".into(),
                ambient: d(0.1, 0.08, 0.02),
                diffuse: d(0.75, 0.6, 0.15),
                specular: d(0.6, 0.55, 0.4),
                shininess: 128.0,
                reflection: 0.0,
            }
        );
        let used: Vec<_> = mesh.triangles.iter().map(|t| t.material()).collect();
        assert_eq!(used, [Some(0), Some(1), Some(1), Some(0)]);

        // Without materials, the same file gives the same triangles and no materials.
        let plain = load_obj(&obj, false).unwrap();
        assert!(plain.materials.is_empty());
        assert!(plain.triangles.iter().all(|t| t.material().is_none()));
        assert_eq!(plain.triangles.len(), 4);
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn mtl_errors_name_the_mtl_file_and_line() {
        let dir = temp_dir("mtlerr");
        let obj = dir.join("m.obj");
        let mtl = dir.join("m.mtl");
        std::fs::write(
            &obj,
            "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\n",
        )
        .unwrap();
        let cases: &[(&str, usize, &str)] = &[
            ("Kd 1 1 1\nnewmtl a\n", 1, "Kd"),
            ("# c\nNs 10\nnewmtl a\n", 2, "Ns"),
            ("newmtl a\nKd 1 x 1\n", 2, "Kd"),
            ("newmtl a\nKa 1 1\n", 2, "Ka"),
            ("newmtl a\nKs 1 1 1 1\n", 2, "Ks"),
            ("newmtl a\nKs\n", 2, "Ks"),
            ("newmtl a\n\nKd nan 0 0\n", 3, "Kd"),
            ("newmtl a\nKd inf 0 0\n", 2, "Kd"),
            ("newmtl a\nNs\n", 2, "Ns"),
            ("newmtl a\nNs 1 2\n", 2, "Ns"),
            ("newmtl a\nNs abc\n", 2, "Ns"),
            ("newmtl a\nNs -1\n", 2, "Ns"),
            ("newmtl\n", 1, "newmtl"),
        ];
        for &(text, line, key) in cases {
            std::fs::write(&mtl, text).unwrap();
            let e = load_obj(&obj, true).unwrap_err();
            assert_err(&e, &mtl, line, key);
        }
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn material_errors() {
        let dir = temp_dir("usemtl");
        let obj = dir.join("m.obj");
        std::fs::write(dir.join("m.mtl"), "newmtl a\nKd 1 0 0\n").unwrap();
        let tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";

        // A face before any usemtl: reported at the face.
        std::fs::write(&obj, format!("mtllib m.mtl\n{tri}f 1 2 3\n")).unwrap();
        let e = load_obj(&obj, true).unwrap_err();
        assert_err(&e, &obj, 5, "usemtl");

        // An unknown material: reported at the usemtl line, naming it.
        std::fs::write(
            &obj,
            format!("mtllib m.mtl\n{tri}usemtl a\nf 1 2 3\nusemtl nope\nf 1 2 3\n"),
        )
        .unwrap();
        let e = load_obj(&obj, true).unwrap_err();
        assert_err(&e, &obj, 7, "usemtl");
        assert!(e.message.contains("nope"), "{e}");

        // No mtllib at all.
        std::fs::write(&obj, format!("{tri}usemtl a\nf 1 2 3\n")).unwrap();
        let e = load_obj(&obj, true).unwrap_err();
        assert_err(&e, &obj, 4, "usemtl");
        assert!(e.message.contains('a'), "{e}");

        // An mtllib with no file name.
        std::fs::write(&obj, format!("mtllib\n{tri}")).unwrap();
        assert_err(&load_obj(&obj, true).unwrap_err(), &obj, 1, "mtllib");

        // A usemtl with no name.
        std::fs::write(&obj, format!("mtllib m.mtl\n{tri}usemtl   # none\n")).unwrap();
        assert_err(&load_obj(&obj, true).unwrap_err(), &obj, 5, "usemtl");

        // Without materials none of these matter.
        std::fs::write(&obj, format!("{tri}usemtl zzz\nf 1 2 3\nmtllib\nusemtl\n")).unwrap();
        assert_eq!(load_obj(&obj, false).unwrap().triangles.len(), 1);

        // mtllib after usemtl still resolves (the check happens at the face).
        std::fs::write(&obj, format!("usemtl a\nmtllib m.mtl\n{tri}f 1 2 3\n")).unwrap();
        let mesh = load_obj(&obj, true).unwrap();
        assert_eq!(mesh.materials.len(), 1);
        assert_eq!(mesh.materials[0].diffuse, d(1., 0., 0.));
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn unreadable_obj_file() {
        let missing = std::env::temp_dir().join(format!(
            "kdray-obj-test-{}-does-not-exist.obj",
            std::process::id()
        ));
        let e = load_obj(&missing, false).unwrap_err();
        assert_eq!(e.file, missing);
        assert_eq!(e.line, None);
        // The OS's text varies by platform; just make sure there is some.
        assert!(e.message.starts_with("cannot read OBJ file: "), "{e}");
        assert!(e.message.len() > "cannot read OBJ file: ".len(), "{e}");
    }

    #[test]
    fn vertex_errors() {
        let cases: &[(&str, usize)] = &[
            ("v 1 2\n", 1),
            ("v\n", 1),
            ("# c\nv 1 2 x\n", 2),
            ("v 0 0 0\nv 1 NaN 0\n", 2),
            ("v 1 2 inf\n", 1),
            ("v -infinity 2 3\n", 1),
            ("v 1e400 0 0\n", 1),
            ("v 1 2 3 w\n", 1),
            ("v 1,0 2 3\n", 1),
        ];
        for &(text, line) in cases {
            assert_err(&parse_err(text, false), p(), line, "v");
        }
    }

    #[test]
    fn face_errors() {
        let cases: &[(&str, usize)] = &[
            ("f 1 2 3\n", 1),                 // no vertices yet
            ("v 0 0 0\nv 1 0 0\nf 1 2\n", 3), // too few vertices
            ("v 0 0 0\nf\n", 2),
            ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", 4),
            ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", 4),
            ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n", 4),
            ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n", 4),
            ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3.0\n", 4),
            ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 //3\n", 4),
            (
                "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999999999999999999\n",
                4,
            ),
            (
                "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -99999999999999999999999999\n",
                4,
            ),
            ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9223372036854775807\n", 4),
            ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -9223372036854775808\n", 4),
            ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -0\n", 4),
        ];
        for &(text, line) in cases {
            assert_err(&parse_err(text, false), p(), line, "f");
        }
        // A face referring to a vertex defined after it is out of range.
        assert_err(
            &parse_err("v 0 0 0\nv 1 0 0\nf 1 2 3\nv 0 1 0\n", false),
            p(),
            3,
            "f",
        );
    }

    #[test]
    fn display_is_file_line_key_message() {
        let e = parse_err("v 0 0 0\n\nv 1 2\n", false);
        assert!(e.to_string().starts_with("mesh.obj:3: v: "), "{e}");
    }

    #[test]
    fn never_panics_on_odd_input() {
        let inputs = [
            "f",
            "f /",
            "f //",
            "f ///",
            "f 1/",
            "v",
            "v \u{0}",
            "usemtl",
            "mtllib",
            "f -",
            "f +",
            "v 1 2 3\nf -1 -1 -1",
            "\u{feff}v 1 2 3",
            "f 1 1 1 1 1 1 1 1 1",
            "\r\r\n\r",
            "#\n#\\\n",
            "v 0 0 0\nf 1 1 1\nf 1//",
        ];
        for text in inputs {
            for with_materials in [false, true] {
                let _ = parse_obj(text, p(), with_materials);
            }
        }
        // Every prefix of a small valid file.
        let full = "mtllib x.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1/1/1 2//2 -1\n";
        for end in 0..=full.len() {
            let _ = parse_obj(&full[..end], p(), false);
            let _ = parse_obj(&full[..end], p(), true);
        }
    }

    #[test]
    fn large_mesh_parses() {
        // A 200 x 200 grid of quads = 80,000 triangles.
        let n = 200usize;
        let mut text = String::new();
        for j in 0..=n {
            for i in 0..=n {
                text.push_str(&format!("v {i} {j} 0\n"));
            }
        }
        for j in 0..n {
            for i in 0..n {
                let a = j * (n + 1) + i + 1;
                text.push_str(&format!("f {} {} {} {}\n", a, a + 1, a + n + 2, a + n + 1));
            }
        }
        let mesh = parse(&text);
        assert_eq!(mesh.triangles.len(), 2 * n * n);
    }

    #[test]
    fn shipped_torus_model() {
        let obj = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/models/torus.obj");
        let mesh = load_obj(&obj, true).unwrap();
        assert_eq!(mesh.triangles.len(), 48 * 24 * 2);
        let mut names: Vec<_> = mesh.materials.iter().map(|m| m.name.as_str()).collect();
        names.sort();
        assert_eq!(names, ["gold", "teal"]);
        for t in &mesh.triangles {
            assert!(t.material().is_some());
            let vertices = mesh.vertices(t).unwrap();
            for v in vertices {
                // Inside the torus's bounding box, on its surface.
                let ring = (v.x * v.x + v.z * v.z).sqrt() - 1.0;
                let tube = (ring * ring + v.y * v.y).sqrt();
                assert!((tube - 0.35).abs() < 1e-5, "{v}");
            }
            // Outward winding: the normal points away from the tube's centre line.
            let [a, b, c] = vertices;
            let n = (b - a).cross(c - a);
            let centroid = (a + b + c) / 3.0;
            let on_ring = DVec3::new(centroid.x, 0.0, centroid.z).normalize();
            assert!(n.dot(centroid - on_ring) > 0.0);
        }
        assert!(std::fs::metadata(&obj).unwrap().len() < 200 * 1024);
    }
}
