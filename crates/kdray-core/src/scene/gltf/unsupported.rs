//! What a glTF file asks for that kdray does not do, found before or after
//! reading it: the 1.0 format (refused, by name), extensions and texture
//! slots (each kind one warning).

use std::path::Path;

use crate::scene::Warning;

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

/// The glTF extensions kdray reads (onto a material's transmission and ior).
pub(super) const SUPPORTED_EXTENSIONS: [&str; 2] =
    ["KHR_materials_transmission", "KHR_materials_ior"];

/// One warning naming every extension the file uses or requires that kdray
/// does not implement, so the model may look other than its author meant.
pub(super) fn extensions_warning(root: &gltf::json::Root, path: &Path) -> Option<Warning> {
    let mut names: Vec<&str> = root
        .extensions_used
        .iter()
        .map(String::as_str)
        .filter(|n| !SUPPORTED_EXTENSIONS.contains(n))
        .collect();
    for required in &root.extensions_required {
        if !names.contains(&required.as_str()) && !SUPPORTED_EXTENSIONS.contains(&required.as_str())
        {
            names.push(required);
        }
    }
    if names.is_empty() {
        return None;
    }
    let required: Vec<&str> = root
        .extensions_required
        .iter()
        .map(String::as_str)
        .filter(|n| !SUPPORTED_EXTENSIONS.contains(n))
        .collect();
    let required = if required.is_empty() {
        String::new()
    } else {
        format!(" (required: {})", required.join(", "))
    };
    Some(Warning::new(
        path,
        None,
        format!(
            "ignores the glTF extensions {}{required}: kdray does not implement them, so the model may look different",
            names.join(", ")
        ),
    ))
}

/// One warning naming the texture slots other than the base colour that
/// the materials fill: kdray reads only base-colour textures, so those
/// surfaces show their other factors only.
pub(super) fn textures_warning(document: &gltf::Document, path: &Path) -> Option<Warning> {
    let mut slots: Vec<&str> = Vec::new();
    let mut textured = 0usize;
    for material in document.materials() {
        let pbr = material.pbr_metallic_roughness();
        let filled = [
            (
                "metallicRoughnessTexture",
                pbr.metallic_roughness_texture().is_some(),
            ),
            ("normalTexture", material.normal_texture().is_some()),
            ("occlusionTexture", material.occlusion_texture().is_some()),
            ("emissiveTexture", material.emissive_texture().is_some()),
        ];
        let mut any = false;
        for (slot, is_filled) in filled {
            if is_filled {
                any = true;
                if !slots.contains(&slot) {
                    slots.push(slot);
                }
            }
        }
        textured += usize::from(any);
    }
    if slots.is_empty() {
        return None;
    }
    let plural = if textured == 1 { "" } else { "s" };
    Some(Warning::new(
        path,
        None,
        format!(
            "{textured} material{plural} use textures ({}), which kdray does not read: they show their factors only",
            slots.join(", ")
        ),
    ))
}
