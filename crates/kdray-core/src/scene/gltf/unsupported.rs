//! What a glTF file asks for that kdray does not do, found before or after
//! reading it: the 1.0 format (refused, by name), a required extension
//! kdray does not read (refused, by name, with a way to convert the file),
//! extensions only used and texture slots (each kind one warning).

use std::path::Path;

use crate::scene::warning::Warning;

/// The error for a glTF 1.0 file: its schema differs throughout (objects
/// keyed by name instead of arrays), so the 2.0 parser's complaint would
/// say nothing useful.
pub(super) const GLTF_1_UNSUPPORTED: &str =
    "glTF 1.0 is not supported; convert it to 2.0 (for example with the Khronos glTF 1.0 to 2.0 converter)";

/// A glTF 1.0 file: a binary glTF of version 1, or JSON with an asset
/// version 1.x, or (1.0's asset was optional) no asset and its
/// dictionaries of named objects where 2.0 has arrays.
pub(super) fn is_gltf_1(bytes: &[u8]) -> bool {
    if let Some(header) = bytes.strip_prefix(b"glTF") {
        return header.get(..4) == Some(&1u32.to_le_bytes()[..]);
    }
    let Ok(serde_json::Value::Object(root)) = serde_json::from_slice(bytes) else {
        return false;
    };
    match root.get("asset") {
        Some(asset) => asset
            .get("version")
            .and_then(|v| v.as_str())
            .is_some_and(|v| v.starts_with('1')),
        None => {
            root.contains_key("version")
                || ["meshes", "accessors", "bufferViews", "buffers", "nodes"]
                    .iter()
                    .any(|k| root.get(*k).is_some_and(|v| v.is_object()))
        }
    }
}

/// The glTF extensions kdray reads: four material extensions (onto a
/// material's transmission, ior, emission and the medium inside it), punctual lights, texture
/// transforms (texture_transform.rs), quantized and compressed geometry
/// (`accessors`, `meshopt`, `draco`) and WebP textures (`images`).
pub(super) const SUPPORTED_EXTENSIONS: [&str; 11] = [
    "EXT_mesh_gpu_instancing",
    "KHR_materials_transmission",
    "KHR_materials_ior",
    "KHR_materials_emissive_strength",
    "KHR_materials_volume",
    "KHR_lights_punctual",
    "KHR_texture_transform",
    "KHR_mesh_quantization",
    "EXT_meshopt_compression",
    "KHR_draco_mesh_compression",
    "EXT_texture_webp",
];

/// How to turn a file needing an extension kdray does not read into one
/// it does, where a command is known (glTF Transform's CLI, version 4).
pub(super) fn conversion_hint(extension: &str) -> &'static str {
    match extension {
        "KHR_texture_basisu" => {
            "convert its KTX2 textures to PNG, for example with `gltf-transform ktxdecompress in.glb out.glb`"
        }
        "EXT_texture_avif" => {
            "convert its AVIF textures to PNG, for example with `gltf-transform png in.glb out.glb --formats avif`"
        }
        "KHR_meshopt_compression" => {
            "decompress it, for example with `gltf-transform copy in.glb out.glb`, or compress it with EXT_meshopt_compression (`gltf-transform meshopt in.glb out.glb`)"
        }
        _ => "convert the file to one that does not need it (for example with glTF Transform's CLI, `gltf-transform`)",
    }
}

/// The error for a file that requires (`extensionsRequired`) an extension
/// kdray does not read: the model cannot be drawn as meant without it.
pub(super) fn required_extension_error(root: &gltf::json::Root) -> Option<String> {
    let name = root
        .extensions_required
        .iter()
        .find(|n| !SUPPORTED_EXTENSIONS.contains(&n.as_str()))?;
    Some(format!(
        "the file requires the glTF extension {name}, which kdray does not read; {}",
        conversion_hint(name)
    ))
}

/// One warning naming every extension the file uses (`extensionsUsed`)
/// that kdray does not implement, so the model may look other than its
/// author meant. (A required one is an error, found before.)
pub(super) fn extensions_warning(root: &gltf::json::Root, path: &Path) -> Option<Warning> {
    let names: Vec<&str> = root
        .extensions_used
        .iter()
        .map(String::as_str)
        .filter(|n| !SUPPORTED_EXTENSIONS.contains(n))
        .collect();
    if names.is_empty() {
        return None;
    }
    Some(Warning::new(
        path,
        None,
        format!(
            "ignores the glTF extensions {}: kdray does not implement them, so the model may look different",
            names.join(", ")
        ),
    ))
}
