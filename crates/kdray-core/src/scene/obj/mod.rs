//! The Wavefront OBJ + MTL reader.
//!
//! Only what a ray tracer of triangles needs is kept: vertex positions,
//! vertex normals (`vn`, for smooth shading), faces (fan-triangulated) and,
//! on request, the Phong colours and `map_Kd` textures of the MTL materials
//! the faces use, with the texture coordinates (`vt`) where a material has
//! a texture. Everything else in the formats (groups, smoothing groups,
//! other maps, ...) is ignored. A file with a textured material and `vt`
//! statements is read by the reference parser.
//!
//! Two parsers, one meaning. `fast` parses a file on all cores (one chunk
//! per core, see `chunk`) and handles every ordinary file; on anything
//! else (any error, an index written with ten digits) it declines, and
//! `reference`, one line at a time, reads the file instead: it alone
//! words the errors (file, 1-based line, statement), so their messages have
//! one implementation, and the fast path only has to be right on valid
//! input, which `fast_path_equivalence` checks against the reference bit
//! for bit on generated files. The reference is part of the product, not
//! just a test oracle: it is the error path of every malformed file.
//!
//! Every fault is a [`SceneError`] naming the file (the OBJ or the MTL), the
//! 1-based line and the statement at fault: a malformed number, an index out
//! of range, a non-finite value, a file with no faces. What a model from the
//! wild often lacks is not a fault: a face with no material (no `usemtl`, an
//! undefined name, an MTL file that cannot be read) gets
//! [`MeshMaterial::default_grey`](super::mesh::MeshMaterial::default_grey)
//! and MTL texture statements other than `map_Kd` are ignored, each cause with one
//! [`Warning`] on [`Mesh::warnings`] naming the file and
//! line. Only the reference parser words warnings; the fast path declines
//! any file that would have one. No input makes this module panic.

mod chunk;
mod fast;
#[cfg(test)]
mod fast_path_equivalence;
mod material_replay;
mod mtl;
mod reference;
mod tokens;

use std::collections::HashMap;
use std::path::Path;

use super::error::SceneError;
use super::mesh::{Mesh, MeshMaterial};
use super::warning::Warning;

/// Reads an OBJ file. With `with_materials` false (the scene overrides the
/// material) mtllib/usemtl are ignored entirely (an MTL file need not
/// exist); with it, every triangle has a material (the default grey where
/// the file gives none, with a warning).
/// A file that is not text (a NUL byte; UTF-16), or that has no face with
/// an area, is an error: it would draw nothing (a binary file read as OBJ
/// is all unknown statements). Text that is not UTF-8 is read as Latin-1.
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
    parse_obj_bytes(text.as_bytes(), path, with_materials, &mut |_| {}, &mut 0)
}

/// Parses MTL text already read (for fuzzing): its materials by name and
/// the warnings it raises. `path` names it in messages; its `map_Kd`
/// images are looked for beside it.
pub fn parse_mtl_library(
    text: &str,
    path: &Path,
) -> Result<(HashMap<String, MeshMaterial>, Vec<Warning>), SceneError> {
    let mut library = HashMap::new();
    let mut warnings = Vec::new();
    mtl::parse_mtl(text, path, &mut library, &mut warnings)?;
    Ok((library, warnings))
}

/// The parser of a file's bytes; `faces` counts the `f` statements. The
/// fast path ([`fast`]: one chunk per core, each chunk's UTF-8 checked
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
    let materials = with_materials.then_some(material_replay::MaterialFiles {
        path,
        on_read: &mut *on_read,
    });
    let mtl_reads = match fast::parse(body, fast::threads_for(body.len()), materials) {
        fast::Outcome::Mesh(mesh, statements) => {
            *faces = statements;
            return Ok(*mesh);
        }
        fast::Outcome::Declined { mtl_reads } => mtl_reads,
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
    let (text, latin1) = obj_text(bytes, path)?;
    let mut mesh =
        reference::parse_reference(&text, path, with_materials, &mut on_read_rest, faces)?;
    if let Some(warning) = latin1 {
        mesh.warnings.insert(0, warning);
    }
    Ok(mesh)
}

/// The line (1-based) and byte offset of the first byte of `bytes` that is
/// not UTF-8.
fn first_bad_byte(bytes: &[u8], e: &std::str::Utf8Error) -> (usize, usize) {
    let valid = &bytes[..e.valid_up_to()];
    (
        valid.iter().filter(|&&b| b == b'\n').count() + 1,
        valid.len(),
    )
}

/// The OBJ file's `bytes` as text: UTF-8; or, where they are not, Latin-1
/// (ISO 8859-1: each byte one character), as older exporters write names
/// and comments, with a warning. Names then match an MTL file's byte for
/// byte (MTL files are read by the same rule, [`text_of`]). A file with a
/// NUL byte is not text: an error naming the line of the first byte that
/// is not UTF-8, as a binary file (a `.glb` misnamed `.obj`, an image)
/// would otherwise give an empty mesh; a UTF-16 file (its byte order mark)
/// is an error that says so.
fn obj_text<'b>(
    bytes: &'b [u8],
    path: &Path,
) -> Result<(std::borrow::Cow<'b, str>, Option<Warning>), SceneError> {
    if bytes.starts_with(&[0xff, 0xfe]) || bytes.starts_with(&[0xfe, 0xff]) {
        return Err(SceneError::new(
            path,
            None,
            None,
            "a UTF-16 text file (its byte order mark); kdray reads OBJ files as UTF-8 or Latin-1: save it as UTF-8",
        ));
    }
    match std::str::from_utf8(bytes) {
        Ok(text) => Ok((text.into(), None)),
        Err(e) => {
            let (line, offset) = first_bad_byte(bytes, &e);
            if bytes.contains(&0) {
                return Err(SceneError::new(
                    path,
                    Some(line),
                    None,
                    format!("not a text OBJ file: invalid UTF-8 at byte {offset} (a binary file? kdray reads binary glTF as .glb)"),
                )
                .with_source(e));
            }
            let warning = Warning::new(
                path,
                Some(line),
                format!("not UTF-8 (byte {offset}): the file is read as Latin-1 (ISO 8859-1)"),
            );
            Ok((latin1(bytes).into(), Some(warning)))
        }
    }
}

/// An MTL file's bytes as text: UTF-8, or Latin-1 where they are not (see
/// [`obj_text`]).
pub(super) fn text_of(bytes: &[u8]) -> std::borrow::Cow<'_, str> {
    match std::str::from_utf8(bytes) {
        Ok(text) => text.into(),
        Err(_) => latin1(bytes).into(),
    }
}

/// Latin-1 bytes as text: byte b is the character U+00b.
fn latin1(bytes: &[u8]) -> String {
    bytes.iter().map(|&b| char::from(b)).collect()
}
