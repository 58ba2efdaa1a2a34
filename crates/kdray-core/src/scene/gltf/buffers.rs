//! A glTF file's buffers: the GLB binary chunk, `data:` URIs (base64) and
//! files named by a relative path, each checked against its declared length.

use std::collections::HashSet;
use std::path::{Path, PathBuf};

use crate::scene::error::SceneError;

/// Every buffer's bytes, checked to be at least its declared `byteLength`;
/// `placeholders` (meshopt fallback buffers) are left empty, unread.
pub(super) fn load_buffers(
    document: &gltf::Document,
    blob: Option<&[u8]>,
    path: &Path,
    read_buffer: &mut dyn FnMut(&Path) -> std::io::Result<Vec<u8>>,
    placeholders: &HashSet<usize>,
) -> Result<Vec<Vec<u8>>, SceneError> {
    let base = path.parent().unwrap_or(Path::new(""));
    let mut out = Vec::new();
    for buffer in document.buffers() {
        let i = buffer.index();
        if placeholders.contains(&i) {
            out.push(Vec::new());
            continue;
        }
        let err = |message: String| SceneError::new(path, None, None, message);
        let data = match buffer.source() {
            gltf::buffer::Source::Bin => blob
                .ok_or_else(|| {
                    err(format!(
                        "buffer {i} refers to the GLB binary chunk, which the file does not have"
                    ))
                })?
                .to_vec(),
            gltf::buffer::Source::Uri(uri) => {
                let shown: String = uri.chars().take(60).collect();
                if let Some(data) = uri.strip_prefix("data:") {
                    decode_data_uri(data)
                        .map_err(|m| err(format!("buffer {i}: data URI \"{shown}...\": {m}")))?
                } else {
                    let file = buffer_path(base, uri)
                        .map_err(|m| err(format!("buffer {i}: URI \"{shown}\": {m}")))?;
                    read_buffer(&file).map_err(|e| {
                        err(format!(
                            "buffer {i}: cannot read {} (URI \"{shown}\"): {e}",
                            file.display()
                        ))
                        .with_source(e)
                    })?
                }
            }
        };
        if data.len() < buffer.length() {
            return Err(err(format!(
                "buffer {i} is truncated: byteLength {} but {} bytes present",
                buffer.length(),
                data.len()
            )));
        }
        out.push(data);
    }
    Ok(out)
}

/// A buffer URI that is a relative (or absolute) file path, percent-decoded,
/// against the glTF file's folder. URIs with a scheme (http:, file:, ...)
/// are refused: kdray reads only local files named by path.
pub(super) fn buffer_path(base: &Path, uri: &str) -> Result<PathBuf, String> {
    let scheme = uri.split_once(':').map(|(s, _)| s);
    if let Some(s) = scheme {
        let is_scheme = s.len() > 1
            && s.starts_with(|c: char| c.is_ascii_alphabetic())
            && s.chars()
                .all(|c| c.is_ascii_alphanumeric() || "+-.".contains(c));
        if is_scheme {
            return Err(format!(
                "a \"{s}:\" URI; kdray reads buffers only from files named by a relative path, or from data: URIs"
            ));
        }
    }
    let decoded = percent_decode(uri)?;
    if decoded.is_empty() {
        return Err("an empty URI".to_string());
    }
    Ok(base.join(decoded))
}

fn percent_decode(uri: &str) -> Result<String, String> {
    let bytes = uri.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            let hex = bytes
                .get(i + 1..i + 3)
                .and_then(|h| std::str::from_utf8(h).ok())
                .and_then(|h| u8::from_str_radix(h, 16).ok())
                .ok_or_else(|| "a % not followed by two hex digits".to_string())?;
            out.push(hex);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    String::from_utf8(out).map_err(|_| "not UTF-8 once percent-decoded".to_string())
}

/// The bytes of a `data:` URI (what follows `data:`): only base64 payloads,
/// as glTF writers produce.
pub(super) fn decode_data_uri(data: &str) -> Result<Vec<u8>, String> {
    let Some((header, payload)) = data.split_once(',') else {
        return Err("no comma before the data".to_string());
    };
    if !header.ends_with(";base64") {
        return Err("not base64 (only base64 data URIs are read)".to_string());
    }
    decode_base64(payload)
}

/// Standard base64 (RFC 4648), `=` padding optional.
fn decode_base64(text: &str) -> Result<Vec<u8>, String> {
    let text = text.trim_end_matches('=');
    let mut out = Vec::with_capacity(text.len() / 4 * 3 + 3);
    let mut bits = 0u32;
    let mut held = 0u32;
    for (at, c) in text.bytes().enumerate() {
        let value = match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' => 62,
            b'/' => 63,
            _ => return Err(format!("invalid base64 character at offset {at}")),
        };
        bits = (bits << 6) | u32::from(value);
        held += 6;
        if held >= 8 {
            held -= 8;
            out.push((bits >> held) as u8);
            bits &= (1 << held) - 1;
        }
    }
    if held >= 6 {
        return Err("truncated base64 (one character too many)".to_string());
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_decodes_with_and_without_padding() {
        assert_eq!(decode_base64("").unwrap(), b"");
        assert_eq!(decode_base64("TQ==").unwrap(), b"M");
        assert_eq!(decode_base64("TWE=").unwrap(), b"Ma");
        assert_eq!(decode_base64("TWFu").unwrap(), b"Man");
        assert_eq!(decode_base64("TWE").unwrap(), b"Ma");
        assert_eq!(decode_base64("/+9A").unwrap(), [0xff, 0xef, 0x40]);
        assert!(decode_base64("T").is_err());
        assert!(decode_base64("TW#u").is_err());
    }

    #[test]
    fn data_uris_and_paths() {
        assert_eq!(
            decode_data_uri("application/octet-stream;base64,TWFu").unwrap(),
            b"Man"
        );
        assert!(decode_data_uri("text/plain,Man").is_err());
        assert!(decode_data_uri("application/octet-stream;base64").is_err());
        let base = Path::new("models");
        assert_eq!(
            buffer_path(base, "my%20mesh.bin").unwrap(),
            Path::new("models/my mesh.bin")
        );
        assert_eq!(
            buffer_path(base, "sub/a.bin").unwrap(),
            Path::new("models/sub/a.bin")
        );
        for bad in ["http://example.com/a.bin", "file:///a.bin", "", "a%2.bin"] {
            assert!(buffer_path(base, bad).is_err(), "{bad}");
        }
    }
}
