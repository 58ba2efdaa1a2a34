//! The toml and serde_json crates' errors (syntax, or a value of the wrong
//! type) as a [`SceneError`]: located by byte span or line and column,
//! named by the key at that place, and worded for a scene author (a NaN in
//! JSON, an overflowing number, a repeated key).

use std::path::Path;

use super::error::SceneError;
use super::source_map::SourceMap;

/// A syntax or schema error from the toml crate, located by its byte span.
pub(super) fn toml_error(
    e: toml::de::Error,
    text: &str,
    map: Option<&SourceMap>,
    path: &Path,
) -> SceneError {
    let span = e.span();
    let (line, key) = match (map, span) {
        // The document parsed, so this is a schema error. An empty span is
        // how the toml crate reports one about the whole document (a missing
        // top-level table): it has no line and no key.
        (Some(_), Some(s)) if s.is_empty() => (None, None),
        (Some(m), Some(s)) => (
            Some(m.line_of_offset(s.start)),
            m.path_at_span(s).map(str::to_string),
        ),
        // A syntax error: count lines ourselves (no map without a parse).
        (None, Some(s)) => {
            let before = &text.as_bytes()[..s.start.min(text.len())];
            (
                Some(before.iter().filter(|&&b| b == b'\n').count() + 1),
                None,
            )
        }
        (_, None) => (None, None),
    };
    let mut message = e.message().to_string();
    if message == "floating-point number overflowed" {
        // 1e999: the same rule as nan and inf.
        message.push_str(": must be a finite number");
    } else if message == "duplicate key" {
        // Say which: the span is the repeated key.
        if let Some(name) = span_text(text, e.span()) {
            message = format!("duplicate key `{name}`");
        }
    }
    SceneError::new(path, line, key, message).with_source(e)
}

/// The run of letters, digits, `+`, `-` and `.` around byte `offset`.
fn word_at(text: &str, offset: usize) -> &str {
    let bytes = text.as_bytes();
    let is_word = |b: u8| b.is_ascii_alphanumeric() || b"+-.".contains(&b);
    let offset = offset.min(bytes.len());
    let start = bytes[..offset]
        .iter()
        .rposition(|&b| !is_word(b))
        .map_or(0, |i| i + 1);
    let end = bytes[offset..]
        .iter()
        .position(|&b| !is_word(b))
        .map_or(bytes.len(), |i| offset + i);
    // `offset` itself may be inside a multi-byte character.
    text.get(start..end).unwrap_or("")
}

fn span_text(text: &str, span: Option<std::ops::Range<usize>>) -> Option<&str> {
    let name = text.get(span?)?.trim();
    (!name.is_empty() && !name.contains('\n')).then_some(name)
}

/// A syntax or schema error from serde_json, located by its line and column
/// (the column of the last character it read).
pub(super) fn json_error(
    e: serde_json::Error,
    text: &str,
    map: Option<&SourceMap>,
    path: &Path,
) -> SceneError {
    // The byte serde_json stopped at (its column counts bytes, from 1).
    let line_start = match e.line() {
        0 | 1 => Some(0),
        n => text.match_indices('\n').nth(n - 2).map(|(i, _)| i + 1),
    };
    let mut offset = line_start.map(|start| start + e.column().saturating_sub(1));
    // For an array or object of the wrong type serde_json has not yet read
    // its `[` or `{`: it reports the byte before it. Name the value itself.
    let message = e.to_string();
    if message.starts_with("invalid type: sequence") || message.starts_with("invalid type: map") {
        offset = offset.map(|o| {
            let rest = text.as_bytes().get(o + 1..).unwrap_or_default();
            o + 1 + rest.iter().take_while(|b| b.is_ascii_whitespace()).count()
        });
    }
    let key = map
        .zip(offset)
        .and_then(|(m, o)| m.path_at(o))
        .map(str::to_string);
    // serde_json appends " at line L column C"; the line is ours to print.
    let mut message = message
        .rsplit_once(" at line ")
        .map_or(message.as_str(), |(m, _)| m)
        .to_string();
    if message == "number out of range" {
        // 1e999 and the like: JSON has no inf, and serde_json will not round.
        message.push_str(": must be a finite number");
    } else if e.is_syntax() {
        // NaN and Infinity are not JSON; say so rather than just "expected value".
        let word = offset.map_or("", |o| word_at(text, o));
        if ["nan", "infinity", "-infinity", "inf", "-inf"]
            .contains(&word.to_ascii_lowercase().as_str())
        {
            message.push_str(&format!(
                ": `{word}` is not a JSON number (JSON has no NaN or infinity; numbers must be finite)"
            ));
        }
    }
    // A schema error outside every key is about the whole document (a
    // missing top-level table); serde_json puts it at the closing brace,
    // which is no help, so name no line.
    let whole_document = e.is_data() && key.is_none();
    let line = (e.line() > 0 && !whole_document).then_some(e.line());
    SceneError::new(path, line, key, message).with_source(e)
}
