//! Small glTF documents written by the tests themselves: one triangle (the
//! mesh of node 0) with an external buffer, and whatever each test adds to
//! the JSON (materials, cameras, lights, more nodes).

use super::*;
use serde_json::{json, Value};

/// The triangle's corners, in its node's coordinates.
pub const TRIANGLE: [[f32; 3]; 3] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];

/// A glTF document of one triangle (mesh 0, placed by node 0, the only node
/// of scene 0), its positions in `tri.bin`; `material` its one material.
pub fn triangle_document(material: Value) -> Value {
    json!({
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "material": 0}]}],
        "materials": [material],
        "accessors": [{
            "bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
            "min": [0, 0, 0], "max": [1, 1, 0]
        }],
        "bufferViews": [{"buffer": 0, "byteLength": 36}],
        "buffers": [{"uri": "tri.bin", "byteLength": 36}],
    })
}

/// Writes `doc` as `name` in `dir`, with the triangle's `tri.bin` beside
/// it; returns the glTF file's path.
pub fn write_document(dir: &TempDir, name: &str, doc: &Value) -> PathBuf {
    let bytes: Vec<u8> = TRIANGLE
        .iter()
        .flatten()
        .flat_map(|x| x.to_le_bytes())
        .collect();
    std::fs::write(dir.join("tri.bin"), bytes).unwrap();
    dir.write(name, &serde_json::to_string_pretty(doc).unwrap())
}

/// Reads a written document as a mesh, with its materials.
#[track_caller]
pub fn read_document(dir: &TempDir, name: &str, doc: &Value) -> kdray_core::scene::mesh::Mesh {
    let path = write_document(dir, name, doc);
    kdray_core::scene::gltf::load_gltf(&path, true, &mut |_| {})
        .unwrap_or_else(|e| panic!("{name}: {e}"))
}
