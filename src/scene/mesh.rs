//! A mesh file in its own coordinates, whatever its format: triangles with
//! their shared-vertex indices and optional normals, and the materials they
//! use. `load_mesh` picks the reader by the file's extension.

use std::path::Path;

use glam::DVec3;

use super::SceneError;

/// A material of a mesh file, already in kdray's terms (for MTL: Ka, Kd, Ks,
/// Ns and no reflection; for glTF: the rule in docs/scene-format.md).
#[derive(Debug, Clone, PartialEq)]
pub struct MeshMaterial {
    pub name: String,
    pub ambient: DVec3,
    pub diffuse: DVec3,
    pub specular: DVec3,
    pub shininess: f64,
    pub reflection: f64,
}

/// One triangle in the file's coordinates (glTF: its scene's, node
/// transforms applied).
#[derive(Debug, Clone, PartialEq)]
pub struct MeshTriangle {
    pub vertices: [DVec3; 3],
    /// Which shared vertex each corner is, `0..Mesh::vertex_count`: corners
    /// with the same index are one vertex for computed smooth normals (OBJ:
    /// the `v` index; glTF: the index into a primitive's vertices).
    pub corners: [usize; 3],
    /// The file's own normal at each corner, where it gives one (not
    /// necessarily of unit length).
    pub normals: [Option<DVec3>; 3],
    /// Index into `Mesh::materials`; None when materials were not asked for.
    pub material: Option<usize>,
}

/// The triangles of a mesh file and the materials they use.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Mesh {
    pub triangles: Vec<MeshTriangle>,
    /// Deduplicated, in order of first use by a triangle; only materials some
    /// triangle uses are here.
    pub materials: Vec<MeshMaterial>,
    /// Number of distinct shared vertices the corners index.
    pub vertex_count: usize,
}

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
        MeshFormat::Gltf => super::gltf::load_gltf(path, with_materials, on_read),
    }
}
