//! What the extensions kdray reads change in a document, done on its JSON
//! before the `gltf` crate validates it (the crate knows none of them and
//! would refuse what they make valid), and the `EXT_meshopt_compression`
//! buffer views decoded once the buffers are read:
//! - a required extension kdray does not read is an error naming it;
//! - `EXT_texture_webp`: the texture's WebP image replaces its `source`
//!   (which may be absent); a texture whose only image is in another
//!   format's extension (`KHR_texture_basisu`'s KTX2) is an error naming it;
//! - an accessor with neither `bufferView` nor `sparse` (zeros, or what
//!   `KHR_draco_mesh_compression` decodes) gets a placeholder view for the
//!   crate and is read as having none;
//! - a buffer that only holds the uncompressed data of meshopt-compressed
//!   views (`fallback: true`, or no URI and referenced by those views only)
//!   is a placeholder: never read, its views decoded from the extension's
//!   bytes instead.

use std::collections::HashSet;

use gltf::json;
use serde_json::Value;

use super::meshopt::{self, Filter, Mode};
use super::unsupported::{conversion_hint, required_extension_error};

const MESHOPT: &str = "EXT_meshopt_compression";

/// What [`prepare`] found.
#[derive(Debug, Default)]
pub(super) struct Prepared {
    /// Accessors given a placeholder buffer view: read as having none.
    pub viewless: HashSet<usize>,
    /// Buffers standing in for meshopt-decoded views: not read.
    pub placeholders: HashSet<usize>,
}

/// Applies the extensions to `root` (see the module's comment).
pub(super) fn prepare(root: &mut json::Root) -> Result<Prepared, String> {
    if let Some(message) = required_extension_error(root) {
        return Err(message);
    }
    for (i, texture) in root.textures.iter_mut().enumerate() {
        let others = texture.extensions.as_ref().map(|e| &e.others);
        let webp = others
            .and_then(|o| o.get("EXT_texture_webp"))
            .and_then(|w| w.get("source"));
        if let Some(source) = webp {
            let source = source
                .as_u64()
                .and_then(|s| u32::try_from(s).ok())
                .filter(|&s| s != u32::MAX)
                .ok_or_else(|| {
                    format!("textures[{i}].extensions.EXT_texture_webp.source: not an image index: {source}")
                })?;
            texture.source = json::Index::new(source);
        } else if texture.source.value() == u32::MAX as usize {
            // No source: the image is only in an extension kdray does not read.
            if let Some(name) = others.and_then(|o| o.keys().next()) {
                return Err(format!(
                    "textures[{i}]: its image is given only by the extension {name}, which kdray does not read; {}",
                    conversion_hint(name)
                ));
            }
        }
    }
    let mut prepared = Prepared::default();
    let has_views = !root.buffer_views.is_empty();
    for (i, accessor) in root.accessors.iter_mut().enumerate() {
        if accessor.buffer_view.is_none() && accessor.sparse.is_none() && has_views {
            accessor.buffer_view = Some(json::Index::new(0));
            prepared.viewless.insert(i);
        }
    }
    prepared.placeholders = placeholder_buffers(root);
    Ok(prepared)
}

/// The `EXT_meshopt_compression` object of a buffer view or buffer.
fn meshopt_of(others: Option<&serde_json::Map<String, Value>>) -> Option<&Value> {
    others.and_then(|o| o.get(MESHOPT))
}

/// Buffers marked `fallback`, and buffers without a URI that only
/// meshopt-compressed views refer to (nothing else, not even as the
/// compressed data's buffer).
fn placeholder_buffers(root: &json::Root) -> HashSet<usize> {
    let mut out = HashSet::new();
    for (b, buffer) in root.buffers.iter().enumerate() {
        let flagged = meshopt_of(buffer.extensions.as_ref().map(|e| &e.others))
            .and_then(|m| m.get("fallback"))
            .and_then(Value::as_bool)
            == Some(true);
        if flagged {
            out.insert(b);
        } else if buffer.uri.is_none() {
            let mut compressed_views = 0;
            let mut other_uses = 0;
            for view in &root.buffer_views {
                let ext = meshopt_of(view.extensions.as_ref().map(|e| &e.others));
                if ext.and_then(|m| m.get("buffer")).and_then(Value::as_u64) == Some(b as u64) {
                    other_uses += 1;
                }
                if view.buffer.value() == b {
                    if ext.is_some() {
                        compressed_views += 1;
                    } else {
                        other_uses += 1;
                    }
                }
            }
            if compressed_views > 0 && other_uses == 0 {
                out.insert(b);
            }
        }
    }
    out
}

/// Every meshopt-compressed buffer view decoded (None for the others),
/// its layout checked against the view's.
pub(super) fn decode_meshopt_views(
    document: &gltf::Document,
    buffers: &[Vec<u8>],
) -> Result<Vec<Option<Vec<u8>>>, String> {
    document
        .views()
        .map(|view| {
            let Some(ext) = view.extension_value(MESHOPT) else {
                return Ok(None);
            };
            decode_view(&view, ext, buffers)
                .map(Some)
                .map_err(|e| format!("buffer view {}: {MESHOPT}: {e}", view.index()))
        })
        .collect()
}

fn decode_view(
    view: &gltf::buffer::View,
    ext: &Value,
    buffers: &[Vec<u8>],
) -> Result<Vec<u8>, String> {
    let number = |key: &str, default: Option<u64>| -> Result<usize, String> {
        match ext.get(key) {
            Some(v) => v
                .as_u64()
                .and_then(|n| usize::try_from(n).ok())
                .ok_or_else(|| format!("{key} is not a count: {v}")),
            None => default
                .map(|d| d as usize)
                .ok_or_else(|| format!("no {key}")),
        }
    };
    let buffer = number("buffer", None)?;
    let offset = number("byteOffset", Some(0))?;
    let length = number("byteLength", None)?;
    let stride = number("byteStride", None)?;
    let count = number("count", None)?;
    let mode = match ext.get("mode").and_then(Value::as_str) {
        Some("ATTRIBUTES") => Mode::Attributes,
        Some("TRIANGLES") => Mode::Triangles,
        Some("INDICES") => Mode::Indices,
        other => {
            return Err(format!(
                "mode {other:?} is not ATTRIBUTES, TRIANGLES or INDICES"
            ))
        }
    };
    let filter = match ext.get("filter").and_then(Value::as_str) {
        None | Some("NONE") => Filter::None,
        Some("OCTAHEDRAL") => Filter::Octahedral,
        Some("QUATERNION") => Filter::Quaternion,
        Some("EXPONENTIAL") => Filter::Exponential,
        Some(other) => return Err(format!("unknown filter {other:?}")),
    };
    if count.checked_mul(stride) != Some(view.length()) {
        return Err(format!(
            "{count} elements of {stride} bytes do not make the view's byteLength {}",
            view.length()
        ));
    }
    if view.stride().is_some_and(|s| s != stride) {
        return Err(format!(
            "byteStride {stride} differs from the view's {}",
            view.stride().unwrap_or(0)
        ));
    }
    let bytes = buffers
        .get(buffer)
        .and_then(|b| b.get(offset..offset.checked_add(length)?))
        .ok_or_else(|| {
            format!("the compressed bytes {offset}..+{length} lie outside buffer {buffer}")
        })?;
    meshopt::decode(bytes, count, stride, mode, filter)
}
