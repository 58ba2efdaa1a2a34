//! One chunk of an OBJ file, parsed from its bytes on its own thread: its
//! `v`, `vn` and `f` statements (face indices as written, since a chunk
//! does not know how many vertices the chunks before it define) and its
//! material statements; then, once every chunk is parsed, its faces
//! resolved and fan-triangulated exactly as the reference parser does.

use glam::DVec3;

use super::tokens::strip_comment;
use crate::scene::mesh::{mesh_index, MeshTriangle, NO_INDEX};

/// One face corner as written: the 1-based or negative vertex index, and the
/// normal index (0: none).
#[derive(Debug, Clone, Copy)]
pub(super) struct Corner {
    v: i32,
    vn: i32,
}

/// One `f` statement: where its corners end in `Chunk::corners`, and how
/// many vertices and normals the chunk had defined before it.
#[derive(Debug, Clone, Copy)]
pub(super) struct Face {
    corners_end: u32,
    positions_before: u32,
    normals_before: u32,
}

/// A material statement (only read when materials are asked for), with
/// its line as the reference parser sees it (no `\r`, no comment).
#[derive(Debug, Clone, Copy)]
pub(super) enum Event<'a> {
    Mtllib(&'a str),
    Usemtl(&'a str),
}

/// What one chunk of the file defines, indices unresolved.
#[derive(Debug, Default)]
pub(super) struct Chunk<'a> {
    pub(super) positions: Vec<DVec3>,
    pub(super) normals: Vec<DVec3>,
    pub(super) corners: Vec<Corner>,
    pub(super) faces: Vec<Face>,
    pub(super) face_statements: usize,
    /// Whether it has a `vt` statement.
    pub(super) has_texture_coordinates: bool,
    /// Material statements, each with the number of faces before it.
    pub(super) events: Vec<(usize, Event<'a>)>,
}

impl<'a> Chunk<'a> {
    /// Parses whole lines; None at the first statement the fast path leaves
    /// to the reference parser.
    pub(super) fn parse(text: &'a str, with_materials: bool) -> Option<Chunk<'a>> {
        let mut chunk = Chunk::default();
        let mut line = Line { text, at: 0 };
        while line.at < text.len() {
            let line_start = line.at;
            match line.keyword() {
                Some("v") => {
                    let mut xyz = [0.0f64; 3];
                    let mut count = 0usize;
                    while let Some(value) = line.number() {
                        if count < 3 {
                            xyz[count] = value?;
                        } else {
                            value?;
                        }
                        count += 1;
                    }
                    if count < 3 {
                        return None;
                    }
                    chunk.positions.push(DVec3::from_array(xyz));
                }
                Some("vn") => {
                    let mut xyz = [0.0f64; 3];
                    let mut count = 0usize;
                    while let Some(value) = line.number() {
                        if count == 3 {
                            return None;
                        }
                        xyz[count] = value?;
                        count += 1;
                    }
                    if count != 3 {
                        return None;
                    }
                    chunk.normals.push(DVec3::from_array(xyz));
                }
                Some("f") => {
                    chunk.face_statements += 1;
                    let first = chunk.corners.len();
                    while let Some(corner) = line.corner() {
                        chunk.corners.push(corner?);
                    }
                    if chunk.corners.len() - first < 3 {
                        return None;
                    }
                    chunk.faces.push(Face {
                        corners_end: u32::try_from(chunk.corners.len()).ok()?,
                        positions_before: u32::try_from(chunk.positions.len()).ok()?,
                        normals_before: u32::try_from(chunk.normals.len()).ok()?,
                    });
                }
                Some(keyword @ ("mtllib" | "usemtl")) if with_materials => {
                    line.next_line();
                    let raw = text[line_start..line.at]
                        .strip_suffix('\n')
                        .unwrap_or(&text[line_start..line.at]);
                    let statement = strip_comment(raw);
                    let event = match keyword {
                        "mtllib" => Event::Mtllib(statement),
                        _ => Event::Usemtl(statement),
                    };
                    chunk.events.push((chunk.faces.len(), event));
                    continue;
                }
                // Texture coordinates are read by the reference parser
                // alone, for a file with a textured material (`fast`).
                Some("vt") => chunk.has_texture_coordinates = true,
                // Everything the reference parser ignores.
                _ => {}
            }
            line.next_line();
        }
        Some(chunk)
    }
}

/// A cursor over `text` that reads one line's statement token by token: the
/// tokens `str::split_ascii_whitespace` gives of the line up to its first
/// `#`, as the reference parser reads it.
struct Line<'a> {
    text: &'a str,
    at: usize,
}

impl<'a> Line<'a> {
    /// The next token of the current line's statement, or None at its end
    /// (the '\n', a '#' or the end of the text), where the cursor stays.
    fn token(&mut self) -> Option<&'a str> {
        self.skip_blanks();
        let start = self.at;
        while !self.ends_token_at(self.at) {
            self.at += 1;
        }
        // Both ends are next to ASCII bytes or at the text's ends: char boundaries.
        (self.at > start).then(|| &self.text[start..self.at])
    }

    /// The statement's first token, as [`Line::token`] reads it; a line
    /// that starts `v`, `vn` or `f` and a blank (nearly every line of a
    /// mesh) is told by its first bytes.
    fn keyword(&mut self) -> Option<&'a str> {
        let bytes = self.text.as_bytes();
        let at = self.at;
        let blank = |i: usize| matches!(bytes.get(i), Some(b' ' | b'\t'));
        let (keyword, len) = match (bytes.get(at), bytes.get(at + 1)) {
            (Some(b'v'), _) if blank(at + 1) => ("v", 1),
            (Some(b'f'), _) if blank(at + 1) => ("f", 1),
            (Some(b'v'), Some(b'n')) if blank(at + 2) => ("vn", 2),
            _ => return self.token(),
        };
        self.at = at + len;
        Some(keyword)
    }

    /// The next token as a number ([`number`]): None at the statement's
    /// end, Some(None) for a token that is not a finite number. A plain
    /// decimal is read as the cursor passes over it, each byte looked at
    /// once (the 1.1 M bunny's load 0.180 -> 0.165 s with the corners
    /// below, on two threads), anything else as a token.
    fn number(&mut self) -> Option<Option<f64>> {
        self.skip_blanks();
        let bytes = self.text.as_bytes();
        let start = self.at;
        let mut at = start;
        let negative = bytes.get(at) == Some(&b'-');
        at += usize::from(negative);
        let (mut mantissa, mut digits, mut point) = (0u64, 0usize, None);
        while let Some(&b) = bytes.get(at) {
            match b {
                b'0'..=b'9' if digits < 15 => {
                    mantissa = mantissa * 10 + u64::from(b - b'0');
                    digits += 1;
                }
                b'.' if point.is_none() => point = Some(digits),
                _ => break,
            }
            at += 1;
        }
        if digits > 0 && self.ends_token_at(at) {
            self.at = at;
            let value = mantissa as f64 / POWERS_OF_TEN[digits - point.unwrap_or(digits)];
            return Some(Some(if negative { -value } else { value }));
        }
        // A sign, an exponent, a 16th digit, junk: the whole token's way.
        Some(number(self.token()?))
    }

    /// The next token as a face corner ([`corner`]): None at the
    /// statement's end, Some(None) for a token that is not one. The forms
    /// `v`, `v/vt`, `v//vn` and `v/vt/vn` with plain digits are read as the
    /// cursor passes over them, anything else as a token.
    fn corner(&mut self) -> Option<Option<Corner>> {
        self.skip_blanks();
        let start = self.at;
        let fused = self.fused_corner();
        if fused.is_none() {
            self.at = start;
            return Some(corner(self.token()?));
        }
        fused.map(Some)
    }

    /// [`Line::corner`]'s reading as it passes; None (the cursor anywhere)
    /// where the token is not in one of its plain forms.
    fn fused_corner(&mut self) -> Option<Corner> {
        let v = self.plain_index()?;
        let mut vn = 0;
        if self.text.as_bytes().get(self.at) == Some(&b'/') {
            self.at += 1;
            while self
                .text
                .as_bytes()
                .get(self.at)
                .is_some_and(u8::is_ascii_digit)
            {
                self.at += 1;
            }
            if self.text.as_bytes().get(self.at) == Some(&b'/') {
                self.at += 1;
                vn = self.plain_index()?;
            }
        }
        self.ends_token_at(self.at).then_some(Corner { v, vn })
    }

    /// An index of 1 to 9 digits, optionally `-`, at the cursor (then past
    /// it); None for anything else, also for 0 ([`index`] reads the rest).
    fn plain_index(&mut self) -> Option<i32> {
        let bytes = self.text.as_bytes();
        let negative = bytes.get(self.at) == Some(&b'-');
        let first = self.at + usize::from(negative);
        let mut at = first;
        let mut value = 0i32;
        while let Some(&b) = bytes.get(at).filter(|b| b.is_ascii_digit()) {
            if at - first == 9 {
                return None;
            }
            value = value * 10 + i32::from(b - b'0');
            at += 1;
        }
        if value == 0 {
            return None;
        }
        self.at = at;
        Some(if negative { -value } else { value })
    }

    /// Skips the blanks before the statement's next token (never a '\n').
    fn skip_blanks(&mut self) {
        let bytes = self.text.as_bytes();
        while self.at < bytes.len()
            && bytes[self.at] != b'\n'
            && bytes[self.at].is_ascii_whitespace()
        {
            self.at += 1;
        }
    }

    /// Whether a token ends at `at`: the text's end, a blank, a '\n' or a
    /// '#', as [`Line::token`] ends one.
    fn ends_token_at(&self, at: usize) -> bool {
        self.text
            .as_bytes()
            .get(at)
            .is_none_or(|&b| b.is_ascii_whitespace() || b == b'#')
    }

    /// Moves past the current line's '\n' (past a comment first).
    fn next_line(&mut self) {
        let bytes = self.text.as_bytes();
        self.at = match bytes[self.at..].iter().position(|&b| b == b'\n') {
            Some(offset) => self.at + offset + 1,
            None => bytes.len(),
        };
    }
}

/// Exact powers of ten: 10^k is an f64 exactly for k <= 22.
const POWERS_OF_TEN: [f64; 16] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
];

/// A finite number, exactly as `str::parse::<f64>` reads it; None where that
/// is not a finite number.
///
/// Plain decimals of at most 15 digits (`-0.296502`, `12`, `.5`, `3.`) take
/// Clinger's fast path: the digits as an integer `m < 10^15 < 2^53` and
/// `10^k` (k <= 15) are both exact in f64, so `m / 10^k` is one correctly
/// rounded operation on the exact decimal value, which is what the standard
/// library's correctly rounded parse returns. Anything else (exponents, more
/// digits, `inf`, junk) is left to `str::parse`.
pub(super) fn number(token: &str) -> Option<f64> {
    fast_decimal(token.as_bytes())
        .or_else(|| token.parse::<f64>().ok())
        .filter(|v| v.is_finite())
}

/// Clinger's fast path over `[+-]digits[.digits]`, at most 15 digits in
/// all and at least one; None for anything else.
fn fast_decimal(bytes: &[u8]) -> Option<f64> {
    let (negative, digits) = match bytes.first() {
        Some(b'-') => (true, &bytes[1..]),
        Some(b'+') => (false, &bytes[1..]),
        _ => (false, bytes),
    };
    let mut mantissa = 0u64;
    let mut count = 0usize;
    let mut fraction: Option<usize> = None;
    for &b in digits {
        match b {
            b'0'..=b'9' => {
                mantissa = mantissa * 10 + u64::from(b - b'0');
                count += 1;
                if count > 15 {
                    return None;
                }
            }
            b'.' if fraction.is_none() => fraction = Some(count),
            _ => return None,
        }
    }
    if count == 0 {
        return None;
    }
    let scale = count - fraction.unwrap_or(count);
    let value = mantissa as f64 / POWERS_OF_TEN[scale];
    Some(if negative { -value } else { value })
}

/// A face token `v`, `v/vt`, `v//vn` or `v/vt/vn` (parts past the third
/// ignored, the texture index never read, as the reference parser does).
fn corner(token: &str) -> Option<Corner> {
    let mut parts = token.as_bytes().splitn(4, |&b| b == b'/');
    let v = index(parts.next()?)?;
    let vn = match parts.nth(1) {
        None | Some([]) => 0,
        Some(vn) => index(vn)?,
    };
    Some(Corner { v, vn })
}

/// A non-zero OBJ index of at most 9 digits, optionally signed; None for
/// anything else (`str::parse::<i64>` decides those in the reference parser).
fn index(bytes: &[u8]) -> Option<i32> {
    let (negative, digits) = match bytes.first() {
        Some(b'-') => (true, &bytes[1..]),
        Some(b'+') => (false, &bytes[1..]),
        _ => (false, bytes),
    };
    if digits.is_empty() || digits.len() > 9 {
        return None;
    }
    let mut value = 0i32;
    for &b in digits {
        if !b.is_ascii_digit() {
            return None;
        }
        value = value * 10 + i32::from(b - b'0');
    }
    match value {
        0 => None,
        _ if negative => Some(-value),
        _ => Some(value),
    }
}

/// The whole file's vertices, for resolving faces (their normals are only
/// indexed, and the count at each face is kept in the chunk).
#[derive(Clone, Copy)]
pub(super) struct Resolved<'a> {
    pub(super) positions: &'a [DVec3],
}

impl Resolved<'_> {
    /// Calls `emit` with each triangle of `chunk`'s faces, in order, exactly
    /// as the reference parser builds them (fan-triangulated, zero-area
    /// triangles skipped); `start` is where the chunk's vertices and normals
    /// begin in the file; `runs` the faces' materials as (first face,
    /// material), starting at face 0. None at an index out of range, or one
    /// a mesh cannot hold (`mesh_index`).
    pub(super) fn triangles(
        &self,
        chunk: &Chunk,
        start: (usize, usize),
        runs: &[(usize, Option<usize>)],
        mut emit: impl FnMut(MeshTriangle),
    ) -> Option<()> {
        // (vertex, normal or NO_INDEX) of each corner of the current face.
        let mut face: Vec<(u32, u32)> = Vec::with_capacity(8);
        let mut corners_start = 0usize;
        let mut run = 0usize;
        for (i, f) in chunk.faces.iter().enumerate() {
            while run + 1 < runs.len() && runs[run + 1].0 <= i {
                run += 1;
            }
            let material = match runs[run].1 {
                Some(m) => mesh_index(m)?,
                None => NO_INDEX,
            };
            let defined = start.0 + f.positions_before as usize;
            let defined_normals = start.1 + f.normals_before as usize;
            let end = f.corners_end as usize;
            face.clear();
            for c in &chunk.corners[corners_start..end] {
                let v = mesh_index(resolve(c.v, defined)?)?;
                let vn = match c.vn {
                    0 => NO_INDEX,
                    vn => mesh_index(resolve(vn, defined_normals)?)?,
                };
                face.push((v, vn));
            }
            corners_start = end;

            let first = face[0];
            for pair in face[1..].windows(2) {
                let corners = [first, pair[0], pair[1]];
                let [a, b, c] = corners.map(|(v, _)| self.positions[v as usize]);
                // The reference parser's zero-area test, the same arithmetic.
                if (b - a).cross(c - a).length() == 0.0 {
                    continue;
                }
                emit(MeshTriangle {
                    corners: corners.map(|(v, _)| v),
                    normals: corners.map(|(_, n)| n),
                    uvs: [NO_INDEX; 3],
                    material,
                });
            }
        }
        Some(())
    }
}

/// A non-zero OBJ index (1-based, or negative: -1 is the last defined so
/// far) as a 0-based index, given how many are defined; None out of range.
fn resolve(index: i32, defined: usize) -> Option<usize> {
    let resolved = if index > 0 {
        index as usize - 1
    } else {
        defined.checked_sub(index.unsigned_abs() as usize)?
    };
    (resolved < defined).then_some(resolved)
}
