//! The reference OBJ parser, one line at a time: the meaning of every
//! statement and every error message. The fast path ([`fast`](super::fast))
//! hands it every file it declines, and tests compare the two.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::str::SplitAsciiWhitespace;

use glam::{DVec2, DVec3};

use super::mtl::parse_mtl;
use super::tokens::{first_three_numbers, parse_number, rest_of_line, statement_error, statements};
use crate::scene::error::SceneError;
use crate::scene::mesh::{mesh_index, Mesh, MeshMaterial, MeshTriangle, NO_INDEX};
use crate::scene::warning::Warning;

/// The reference parser, one line at a time: the meaning of every statement
/// and every error message. `faces` counts the `f` statements.
pub(in crate::scene) fn parse_reference(
    text: &str,
    path: &Path,
    with_materials: bool,
    on_read: &mut dyn FnMut(&Path),
    faces: &mut usize,
) -> Result<Mesh, SceneError> {
    let mut mesh = Mesh::default();
    // Reused for every face so that faces allocate nothing: (v, vn, vt)
    // indices, the normal's and texture coordinate's NO_INDEX where the
    // corner names none.
    let mut face: Vec<(u32, u32, u32)> = Vec::with_capacity(8);

    // Materials state (only touched when `with_materials`).
    let mut library: HashMap<String, MeshMaterial> = HashMap::new();
    let mut materials = UsedMaterials::default();
    // The name and line of the last usemtl, and its index into
    // `mesh.materials` once a face has resolved it.
    let mut current: Option<(&str, usize)> = None;
    let mut current_index: Option<usize> = None;

    for (line_no, line, keyword, tokens) in statements(text) {
        let err = statement_error(path, line_no, keyword);

        match keyword {
            "v" => mesh.positions.push(vertex_position(tokens).map_err(err)?),
            "vn" => mesh.normals.push(vertex_normal(tokens).map_err(err)?),
            "vt" if with_materials => mesh.uvs.push(texture_coordinates(tokens)),
            "f" => {
                *faces += 1;
                face_corners(tokens, &mesh, &mut face).map_err(err)?;

                let material = if with_materials {
                    if current_index.is_none() {
                        current_index = Some(face_material(
                            current,
                            &library,
                            &mut materials,
                            &mut mesh,
                            path,
                            line_no,
                        ));
                    }
                    current_index
                } else {
                    None
                };
                let material = match material {
                    Some(m) => as_mesh_index(m, "usemtl", "material").map_err(err)?,
                    None => NO_INDEX,
                };

                push_fan(&mut mesh, &face, material);
            }
            "mtllib" if with_materials => {
                let any = read_mtllib(
                    tokens,
                    path,
                    line_no,
                    on_read,
                    &mut library,
                    &mut materials,
                    &mut mesh,
                )?;
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
            // vp, o, g, s, l, p, vt/mtllib/usemtl without materials, and
            // anything unknown.
            _ => {}
        }
    }

    // Texture coordinates matter only for a textured material.
    if !mesh.materials.iter().any(|m| m.texture.is_some()) {
        mesh.uvs.clear();
        for t in &mut mesh.triangles {
            t.uvs = [NO_INDEX; 3];
        }
    }
    Ok(mesh)
}

/// A `v` statement's position: x y z [w]; anything past x y z (w, or the
/// vertex colours some exporters write) must be numbers too but is unused.
fn vertex_position(tokens: SplitAsciiWhitespace) -> Result<DVec3, String> {
    let (xyz, count) = first_three_numbers(tokens)?;
    if count < 3 {
        return Err(format!("expected 3 coordinates (x y z [w]), found {count}"));
    }
    Ok(DVec3::from_array(xyz))
}

/// A `vn` statement's normal: exactly x y z.
fn vertex_normal(tokens: SplitAsciiWhitespace) -> Result<DVec3, String> {
    let (xyz, count) = first_three_numbers(tokens)?;
    if count != 3 {
        return Err(format!("expected 3 numbers (x y z), found {count}"));
    }
    Ok(DVec3::from_array(xyz))
}

/// A `vt` statement's coordinates: u [v [w]], read leniently as before
/// texture coordinates were read at all: a statement that is not numbers
/// gives coordinates no triangle takes (NaN: its corners stay untextured).
/// OBJ's v runs up from the image's bottom row; the result's runs down.
fn texture_coordinates(tokens: SplitAsciiWhitespace) -> DVec2 {
    let mut uv = [0.0f64; 2];
    let mut count = 0usize;
    let mut readable = true;
    for token in tokens {
        match parse_number(token) {
            Ok(value) if count < 2 => uv[count] = value,
            Ok(_) => {}
            Err(_) => readable = false,
        }
        count += 1;
    }
    if readable && count >= 1 {
        DVec2::new(uv[0], 1.0 - uv[1])
    } else {
        DVec2::NAN
    }
}

/// An `f` statement's corners into `face` (cleared first) as (v, vn, vt)
/// mesh indices, resolved against what `mesh` defines so far; at least 3.
fn face_corners(
    tokens: SplitAsciiWhitespace,
    mesh: &Mesh,
    face: &mut Vec<(u32, u32, u32)>,
) -> Result<(), String> {
    face.clear();
    for token in tokens {
        let index = resolve_index(token, mesh.positions.len())?;
        let normal = resolve_normal(token, mesh.normals.len())?;
        face.push((
            as_mesh_index(index, token, "vertex")?,
            match normal {
                Some(n) => as_mesh_index(n, token, "normal")?,
                None => NO_INDEX,
            },
            texture_coordinate(token, &mesh.uvs),
        ));
    }
    if face.len() < 3 {
        return Err(format!(
            "a face needs at least 3 vertices, found {}",
            face.len()
        ));
    }
    Ok(())
}

/// The face's fan triangles (around its first corner) appended to `mesh`
/// with `material`, zero-area ones skipped.
fn push_fan(mesh: &mut Mesh, face: &[(u32, u32, u32)], material: u32) {
    let first = face[0];
    for pair in face[1..].windows(2) {
        let corners = [first, pair[0], pair[1]];
        let [a, b, c] = corners.map(|(v, _, _)| mesh.positions[v as usize]);
        // Skip zero-area triangles: they cannot be hit and have no
        // normal. "Zero" is the cross product's f64 length, so a
        // cross product so small that its squared length underflows
        // counts as zero too (it could not be normalised).
        if (b - a).cross(c - a).length() == 0.0 {
            continue;
        }
        mesh.triangles.push(MeshTriangle {
            corners: corners.map(|(v, _, _)| v),
            normals: corners.map(|(_, n, _)| n),
            uvs: corners.map(|(_, _, t)| t),
            material,
        });
    }
}

/// An `mtllib` statement on line `line_no` of the OBJ file `path`: each
/// MTL file it names (beside the OBJ file) not read before is read into
/// `library`, `on_read` told first; one that cannot be read is a warning,
/// and its faces get the default grey. Whether the statement names any
/// file; an error in an MTL file is the error.
fn read_mtllib(
    tokens: SplitAsciiWhitespace,
    path: &Path,
    line_no: usize,
    on_read: &mut dyn FnMut(&Path),
    library: &mut HashMap<String, MeshMaterial>,
    materials: &mut UsedMaterials,
    mesh: &mut Mesh,
) -> Result<bool, SceneError> {
    let mut any = false;
    for name in tokens {
        any = true;
        let mtl_path = path.parent().unwrap_or_else(|| Path::new("")).join(name);
        if materials.loaded.contains(&mtl_path) || materials.unreadable.contains(&mtl_path) {
            continue;
        }
        on_read(&mtl_path);
        match crate::scene::input_file::read_input_file(&mtl_path) {
            Ok(mtl_text) => {
                parse_mtl(
                    &super::text_of(&mtl_text),
                    &mtl_path,
                    library,
                    &mut mesh.warnings,
                )?;
                materials.loaded.push(mtl_path);
            }
            Err(e) => {
                mesh.warnings.push(Warning::new(
                    path,
                    Some(line_no),
                    format!(
                        "cannot read MTL file {}: {e}; faces using its materials get the default grey material",
                        mtl_path.display()
                    ),
                ));
                materials.unreadable.push(mtl_path);
            }
        }
    }
    Ok(any)
}

/// What the reference parser knows of the materials its faces use.
#[derive(Default)]
struct UsedMaterials {
    /// MTL files read, and those that could not be.
    loaded: Vec<PathBuf>,
    unreadable: Vec<PathBuf>,
    /// Index in `Mesh::materials` of each material used so far, by name.
    used: HashMap<String, usize>,
    /// Index in `Mesh::materials` of the default grey, once a face uses it.
    default_grey: Option<usize>,
    /// A face without any usemtl has been warned about.
    warned_no_usemtl: bool,
    /// Undefined material names warned about.
    warned_undefined: Vec<String>,
}

/// The index in `mesh.materials` of the material of a face on line
/// `line_no` after the usemtl `current` (name, line): the MTL material it
/// names, added at its first use, or the default grey with one warning per
/// cause (no usemtl at all; each undefined name, unless an MTL file could
/// not be read, which was warned about already).
fn face_material(
    current: Option<(&str, usize)>,
    library: &HashMap<String, MeshMaterial>,
    materials: &mut UsedMaterials,
    mesh: &mut Mesh,
    path: &Path,
    line_no: usize,
) -> usize {
    match current {
        None => {
            if !std::mem::replace(&mut materials.warned_no_usemtl, true) {
                mesh.warnings.push(Warning::new(
                    path,
                    Some(line_no),
                    "face has no material (no usemtl statement before it); it gets the default grey material",
                ));
            }
        }
        Some((name, usemtl_line)) => {
            if let Some(found) = library.get(name) {
                return *materials.used.entry(name.to_string()).or_insert_with(|| {
                    mesh.materials.push(found.clone());
                    mesh.materials.len() - 1
                });
            }
            let warned = materials.warned_undefined.iter().any(|w| w == name);
            if !warned && materials.unreadable.is_empty() {
                let defined_in = if materials.loaded.is_empty() {
                    "no mtllib statement loaded an MTL file".to_string()
                } else {
                    let files: Vec<String> = materials
                        .loaded
                        .iter()
                        .map(|p| p.display().to_string())
                        .collect();
                    format!("not in {}", files.join(", "))
                };
                mesh.warnings.push(Warning::new(
                    path,
                    Some(usemtl_line),
                    format!(
                        "material '{name}' is not defined ({defined_in}); its faces get the default grey material"
                    ),
                ));
            }
            if !warned {
                materials.warned_undefined.push(name.to_string());
            }
        }
    }
    *materials.default_grey.get_or_insert_with(|| {
        mesh.materials.push(MeshMaterial::default_grey());
        mesh.materials.len() - 1
    })
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

/// The index into `uvs` of a face token's texture coordinates (`v/vt` or
/// `v/vt/vn`), or NO_INDEX: where the token names none, or one that is out
/// of range or unreadable (texture coordinates were ignored before they were
/// read, so a bad one leaves the corner untextured rather than failing).
fn texture_coordinate(token: &str, uvs: &[DVec2]) -> u32 {
    let Some(vt) = token.split('/').nth(1).filter(|t| !t.is_empty()) else {
        return NO_INDEX;
    };
    resolve(vt, token, "texture coordinate", uvs.len())
        .ok()
        .filter(|&i| uvs[i].is_finite())
        .and_then(mesh_index)
        .unwrap_or(NO_INDEX)
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
