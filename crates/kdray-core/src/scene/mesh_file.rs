//! A mesh file read by the reader its extension names: `.obj` (with its
//! MTL files) by [`obj`](super::obj), `.gltf` and `.glb` by
//! [`gltf`](super::gltf). Kept apart from [`Mesh`], the
//! type both readers produce, so that the type depends on no reader.

use std::path::Path;

use super::error::SceneError;
use super::mesh::Mesh;

/// The mesh formats, by extension (case-insensitive).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MeshFormat {
    Obj,
    /// `.gltf` (JSON) and `.glb` (binary): the reader tells them apart by content.
    Gltf,
}

impl MeshFormat {
    pub fn of_path(path: &Path) -> Option<Self> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "obj" => Some(MeshFormat::Obj),
            "gltf" | "glb" => Some(MeshFormat::Gltf),
            _ => None,
        }
    }
}

/// Reads a mesh file (and its MTL libraries or glTF buffers), calling
/// `on_read` with each file just before it is read. With `with_materials`
/// false (the scene overrides the material) the file's materials are not
/// read. A file with no triangle at all is an error: it would render nothing.
pub fn load_mesh(
    path: &Path,
    with_materials: bool,
    on_read: &mut dyn FnMut(&Path),
) -> Result<Mesh, SceneError> {
    load_mesh_with(path, with_materials, false, on_read)
}

/// [`load_mesh`]; with `instancing`, a glTF file's meshes placed several
/// times are read once into [`Mesh::instanced`]
/// ([`load_gltf_with`](super::gltf::load_gltf_with)).
pub fn load_mesh_with(
    path: &Path,
    with_materials: bool,
    instancing: bool,
    on_read: &mut dyn FnMut(&Path),
) -> Result<Mesh, SceneError> {
    let Some(format) = MeshFormat::of_path(path) else {
        on_read(path);
        let message = match path.extension() {
            Some(ext) => format!(
                "unknown mesh file extension \".{}\"; kdray reads .obj, .gltf and .glb",
                ext.to_string_lossy()
            ),
            None => "no mesh file extension; kdray reads .obj, .gltf and .glb".to_string(),
        };
        return Err(SceneError::new(path, None, None, message));
    };
    match format {
        MeshFormat::Obj => super::obj::load_obj_observed(path, with_materials, on_read),
        MeshFormat::Gltf => super::gltf::load_gltf_with(path, with_materials, instancing, on_read),
    }
}
