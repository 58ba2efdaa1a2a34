//! Where each key of a scene document sits in its text, so that errors found
//! after deserialising (a negative radius, an unknown material) can still
//! name their line, and errors reported by byte offset can name their key.
//!
//! Paths look like `camera.position`, `spheres[2].radius`,
//! `materials.red.diffuse`: the same for TOML and JSON. A loader holds a
//! [`LazySourceMap`], which makes the map on the first error only.

use std::cell::OnceCell;
use std::ops::Range;

use super::scene_format::SceneFormat;

struct Entry {
    path: String,
    span: Range<usize>,
}

pub(crate) struct SourceMap {
    entries: Vec<Entry>,
    line_starts: Vec<usize>,
}

impl SourceMap {
    fn new(text: &str) -> Self {
        let mut line_starts = vec![0];
        line_starts.extend(text.match_indices('\n').map(|(i, _)| i + 1));
        SourceMap {
            entries: Vec::new(),
            line_starts,
        }
    }

    /// 1-based line of a byte offset.
    pub fn line_of_offset(&self, offset: usize) -> usize {
        self.line_starts
            .partition_point(|&start| start <= offset)
            .max(1)
    }

    /// Line of the first place that mentions `path` (its key, or its value).
    pub fn line_of_path(&self, path: &str) -> Option<usize> {
        self.entries
            .iter()
            .find(|e| e.path == path)
            .map(|e| self.line_of_offset(e.span.start))
    }

    /// The innermost key path whose key or value contains the byte at `offset`.
    pub fn path_at(&self, offset: usize) -> Option<&str> {
        self.path_at_span(offset..offset + 1)
    }

    /// The innermost key path whose key or value contains all of `span`. An
    /// error about a whole table (a missing field) thus names that table, and
    /// one about the whole document (the toml crate gives those an empty span
    /// at 0) names no key. Spans are half-open: the byte just past a value
    /// (the closing `}` of the object around it) is not part of it.
    pub fn path_at_span(&self, span: Range<usize>) -> Option<&str> {
        if span.is_empty() {
            return None;
        }
        // Children are recorded after their parents, so among equal spans
        // (a TOML array of tables and its first table can share one) the
        // last is the innermost.
        self.entries
            .iter()
            .rev()
            .filter(|e| e.span.start <= span.start && span.end <= e.span.end)
            .min_by_key(|e| e.span.end - e.span.start)
            .map(|e| e.path.as_str())
    }

    fn push(&mut self, path: &str, span: Range<usize>) {
        self.entries.push(Entry {
            path: path.to_string(),
            span,
        });
    }

    /// Map of a TOML document; None when it does not parse (the deserialiser
    /// reports that error itself).
    pub fn toml(text: &str) -> Option<Self> {
        use toml::de::{DeTable, DeValue};
        fn walk(map: &mut SourceMap, path: &str, value: &toml::Spanned<DeValue<'_>>) {
            map.push(path, value.span());
            match value.get_ref() {
                DeValue::Table(table) => walk_table(map, path, table),
                DeValue::Array(items) => {
                    for (i, item) in items.iter().enumerate() {
                        walk(map, &format!("{path}[{i}]"), item);
                    }
                }
                _ => {}
            }
        }
        fn walk_table(map: &mut SourceMap, prefix: &str, table: &DeTable<'_>) {
            for (key, value) in table.iter() {
                let path = if prefix.is_empty() {
                    key.get_ref().to_string()
                } else {
                    format!("{prefix}.{}", key.get_ref())
                };
                map.push(&path, key.span());
                walk(map, &path, value);
            }
        }
        let root = DeTable::parse(text).ok()?;
        let mut map = SourceMap::new(text);
        walk_table(&mut map, "", root.get_ref());
        Some(map)
    }

    /// Map of a JSON document; None when it does not parse.
    pub fn json(text: &str) -> Option<Self> {
        let mut map = SourceMap::new(text);
        let mut scanner = JsonScanner {
            bytes: text.as_bytes(),
            pos: 0,
        };
        scanner.value(&mut map, "", 0)?;
        Some(map)
    }
}

/// A minimal JSON reader that records spans; it trusts serde_json to judge
/// validity and only needs to find its way through valid documents.
struct JsonScanner<'a> {
    bytes: &'a [u8],
    pos: usize,
}

impl JsonScanner<'_> {
    const MAX_NESTING: usize = 128;

    fn skip_ws(&mut self) {
        while self.pos < self.bytes.len() && self.bytes[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
    }

    fn peek(&self) -> Option<u8> {
        self.bytes.get(self.pos).copied()
    }

    /// Reads a string and returns its raw contents (escapes left as they are:
    /// scene keys have none).
    fn string(&mut self) -> Option<Range<usize>> {
        let start = self.pos;
        self.pos += 1;
        while let Some(&b) = self.bytes.get(self.pos) {
            self.pos += 1;
            match b {
                b'\\' => self.pos += 1,
                b'"' => return Some(start..self.pos),
                _ => {}
            }
        }
        None
    }

    fn value(&mut self, map: &mut SourceMap, path: &str, depth: usize) -> Option<()> {
        if depth > Self::MAX_NESTING {
            return None;
        }
        self.skip_ws();
        let start = self.pos;
        match self.peek()? {
            b'{' => {
                self.pos += 1;
                loop {
                    self.skip_ws();
                    match self.peek()? {
                        b'}' => {
                            self.pos += 1;
                            break;
                        }
                        b',' => self.pos += 1,
                        b'"' => {
                            let key_span = self.string()?;
                            let key = std::str::from_utf8(
                                &self.bytes[key_span.start + 1..key_span.end - 1],
                            )
                            .ok()?;
                            let child = if path.is_empty() {
                                key.to_string()
                            } else {
                                format!("{path}.{key}")
                            };
                            let member_start = key_span.start;
                            map.push(&child, key_span);
                            self.skip_ws();
                            if self.peek()? != b':' {
                                return None;
                            }
                            self.pos += 1;
                            self.value(map, &child, depth + 1)?;
                            // The whole member too: serde_json reports some
                            // bad values (`"vfov": [60]`) at the blank just
                            // before them, between the key and the value.
                            map.push(&child, member_start..self.pos);
                        }
                        _ => return None,
                    }
                }
            }
            b'[' => {
                self.pos += 1;
                let mut index = 0;
                loop {
                    self.skip_ws();
                    match self.peek()? {
                        b']' => {
                            self.pos += 1;
                            break;
                        }
                        b',' => self.pos += 1,
                        _ => {
                            self.value(map, &format!("{path}[{index}]"), depth + 1)?;
                            index += 1;
                        }
                    }
                }
            }
            b'"' => {
                self.string()?;
            }
            _ => {
                while let Some(b) = self.peek() {
                    if b == b',' || b == b'}' || b == b']' || b.is_ascii_whitespace() {
                        break;
                    }
                    self.pos += 1;
                }
                if self.pos == start {
                    return None;
                }
            }
        }
        if !path.is_empty() {
            map.push(path, start..self.pos);
        }
        Some(())
    }
}

/// Where each key of the text is, for error messages. Made on the first
/// error only: a scene that loads never needs it, and for a big scene it
/// would cost a second parse and an entry per key (100 MB of TOML with a
/// million spheres: seconds, and gigabytes of memory).
pub(super) struct LazySourceMap<'a> {
    pub(super) text: &'a str,
    pub(super) format: SceneFormat,
    pub(super) map: OnceCell<Option<SourceMap>>,
}

impl LazySourceMap<'_> {
    /// The map of no text, for a scene made without a scene file.
    pub(super) fn empty(format: SceneFormat) -> Self {
        LazySourceMap {
            text: "",
            format,
            map: OnceCell::new(),
        }
    }

    /// The map; None if the text does not parse as TOML or JSON.
    pub(super) fn get(&self) -> Option<&SourceMap> {
        self.map
            .get_or_init(|| match self.format {
                SceneFormat::Toml => SourceMap::toml(self.text),
                SceneFormat::Json => SourceMap::json(self.text),
            })
            .as_ref()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn toml_paths_have_lines() {
        let text =
            "[camera]\nposition = [0, 0, 1]\n\n[[spheres]]\ncenter = [0, 0, 0]\nradius = -1\n";
        let map = SourceMap::toml(text).unwrap();
        assert_eq!(map.line_of_path("camera.position"), Some(2));
        assert_eq!(map.line_of_path("spheres[0].radius"), Some(6));
        let offset = text.find("-1").unwrap();
        assert_eq!(map.path_at(offset), Some("spheres[0].radius"));
    }

    #[test]
    fn json_paths_have_lines() {
        let text = "{\n \"camera\": {\"position\": [0, 0, 1]},\n \"spheres\": [\n  {\"radius\": 2},\n  {\"radius\": -1}\n ]\n}";
        let map = SourceMap::json(text).unwrap();
        assert_eq!(map.line_of_path("camera.position"), Some(2));
        assert_eq!(map.line_of_path("spheres[1].radius"), Some(5));
        assert_eq!(
            map.path_at(text.find("-1").unwrap()),
            Some("spheres[1].radius")
        );
    }

    #[test]
    fn json_scanner_gives_up_on_garbage_without_panicking() {
        for text in [
            "",
            "{",
            "[1,",
            "{\"a\" 1}",
            "{\"a\":",
            "\"abc",
            &"[".repeat(1000),
        ] {
            let _ = SourceMap::json(text);
        }
    }
}
