//! The OBJ reader's fast path: the text cut at line boundaries into one
//! chunk per thread, each chunk's `v`, `vn` and `f` statements parsed from
//! its bytes without allocating per line, then the faces resolved and
//! fan-triangulated on the same threads into one `Mesh`. Material
//! statements (`mtllib`, `usemtl`) are kept per chunk and replayed in file
//! order on one thread between the two.
//!
//! It gives exactly the mesh of the reference parser (`obj::parse_reference`)
//! or declines: on any statement it does not handle the same way (an error
//! of any kind, an index written with ten digits) the caller runs the
//! reference parser, which then reports the error with its file, line and
//! key. So errors keep one implementation, and the fast path only has to be
//! right on valid input; `tests` compares the two on generated files, bit
//! for bit, with and without materials.
//!
//! Indices are resolved after every chunk is parsed, since a chunk does not
//! know how many vertices the chunks before it define: each face keeps the
//! raw OBJ indices and the chunk's own vertex and normal counts at the face.

use std::collections::HashMap;
use std::mem::MaybeUninit;
use std::path::{Path, PathBuf};

use glam::DVec3;

use super::mesh::{mesh_index, Mesh, MeshMaterial, MeshTriangle, NO_INDEX};
use super::obj;

/// Smallest chunk worth a thread: below this a thread's start and the merge
/// cost more than they save (one thread parses 1 MiB in about 3 ms: the 43 MB
/// bunny in 0.125 s).
const MIN_CHUNK_BYTES: usize = 1 << 20;

/// Threads to parse `len` bytes with: one per core, at most one per
/// `MIN_CHUNK_BYTES`.
pub(super) fn threads_for(len: usize) -> usize {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    cores.min(len / MIN_CHUNK_BYTES).max(1)
}

/// Where the materials of a file come from: the OBJ's path (MTL files are
/// relative to its folder) and the observer told of each MTL file just
/// before it is read.
pub(super) struct MaterialFiles<'p> {
    pub path: &'p Path,
    pub on_read: &'p mut dyn FnMut(&Path),
}

/// What the fast path made of a file.
pub(super) enum Outcome {
    /// The mesh and the number of `f` statements.
    Mesh(Mesh, usize),
    /// Left to the reference parser, after telling the observer of
    /// `mtl_reads` MTL files: the reference parser tells it of the same
    /// files first, in the same order (see `parse`).
    Declined { mtl_reads: usize },
}

/// The mesh of `text` (byte order mark already removed) parsed on `threads`
/// threads, with the materials of `materials` when given; or `Declined`
/// where the reference parser must decide (an error, or input the fast path
/// does not handle).
///
/// Every check that does not read an MTL file runs before the first is
/// read, so a file declined after reading some is refused by the reference
/// parser at an MTL statement, after it reads exactly the same files.
pub(super) fn parse(text: &[u8], threads: usize, materials: Option<MaterialFiles>) -> Outcome {
    let declined = Outcome::Declined { mtl_reads: 0 };
    let with_materials = materials.is_some();
    // Each chunk's UTF-8 is checked on its thread (the pieces end at line
    // ends, so the whole text is valid where they all are): checked whole
    // on one thread, the bunny's 43 MB took 3 - 7 ms.
    let Some(mut chunks) = on_threads(split_at_lines(text, threads), |piece| {
        Chunk::parse(std::str::from_utf8(piece).ok()?, with_materials)
    })
    .into_iter()
    .collect::<Option<Vec<Chunk>>>() else {
        return declined;
    };

    // The file's vertices and normals: the first chunk's, which usually
    // holds them all (exporters write vertices first), extended by the
    // others'; and where each chunk's start.
    let mut starts = Vec::with_capacity(chunks.len());
    let mut positions = std::mem::take(&mut chunks[0].positions);
    let mut normals = std::mem::take(&mut chunks[0].normals);
    starts.push((0, 0));
    for chunk in &chunks[1..] {
        starts.push((positions.len(), normals.len()));
        positions.extend_from_slice(&chunk.positions);
        normals.extend_from_slice(&chunk.normals);
    }
    let face_statements = chunks.iter().map(|c| c.face_statements).sum();
    let file = Resolved {
        positions: &positions,
    };
    let jobs: Vec<_> = chunks.iter().zip(&starts).collect();

    // The faces are resolved and written in place into one vector, each
    // chunk into its own part (writing a vector per chunk and appending
    // would copy half the mesh again). A part's room is the chunk's fan
    // triangles, `corners - 2` a face; zero-area ones are skipped, so a part
    // may end short and the next ones move down after. With materials, a
    // first pass counts the triangles exactly: it checks every index before
    // the first MTL file is read (see above). Without, one pass does: the
    // 1.1 M-triangle bunny's second pass took 20 ms of its 0.22 s load.
    let no_material = [(0, None)];
    let rooms: Vec<usize> = if materials.is_some() {
        let Some(counts) = on_threads(jobs.clone(), |(chunk, &start)| {
            let mut count = 0usize;
            file.triangles(chunk, start, &no_material, |_| count += 1)
                .map(|()| count)
        })
        .into_iter()
        .collect::<Option<Vec<usize>>>() else {
            return declined;
        };
        counts
    } else {
        chunks
            .iter()
            .map(|c| c.corners.len() - 2 * c.faces.len())
            .collect()
    };
    let room: usize = rooms.iter().sum();

    // Materials, in file order, reading the MTL files.
    let (runs, materials, mtl_reads) = match materials {
        None => (vec![no_material.to_vec(); chunks.len()], Vec::new(), 0),
        Some(files) => {
            let mut state = MaterialState::new(files);
            match state.runs(&chunks) {
                Some(runs) => (runs, state.used, state.reads),
                None => {
                    return Outcome::Declined {
                        mtl_reads: state.reads,
                    }
                }
            }
        }
    };

    let mut triangles: Vec<MeshTriangle> = Vec::with_capacity(room);
    crate::huge_pages::advise(&mut triangles);
    let mut parts = Vec::with_capacity(rooms.len());
    let mut rest = &mut triangles.spare_capacity_mut()[..room];
    for &part_room in &rooms {
        let (part, tail) = rest.split_at_mut(part_room);
        parts.push(part);
        rest = tail;
    }
    let written = on_threads(
        parts.into_iter().zip(jobs).zip(&runs).collect(),
        |((part, (chunk, &start)), runs): ((&mut [MaybeUninit<MeshTriangle>], _), &Vec<_>)| {
            let mut slots = part.iter_mut();
            let (mut emitted, mut written) = (0usize, 0usize);
            let resolved = file.triangles(chunk, start, runs, |t| {
                emitted += 1;
                if let Some(slot) = slots.next() {
                    slot.write(t);
                    written += 1;
                }
            });
            // A face gives at most `corners - 2` triangles, and with
            // materials the same faces and arithmetic as the count give the
            // same triangles; were a part ever to overflow, the reference
            // parser decides (the vector keeps length 0, so nothing
            // unwritten is read).
            resolved.filter(|()| emitted == written).map(|()| written)
        },
    );
    let Some(written) = written.into_iter().collect::<Option<Vec<usize>>>() else {
        return Outcome::Declined { mtl_reads };
    };
    // Each part's written triangles moved down to follow the previous
    // part's (none move when no triangle was skipped).
    let spare = triangles.spare_capacity_mut();
    let (mut part_start, mut total) = (0usize, 0usize);
    for (&part_room, &count) in rooms.iter().zip(&written) {
        if part_start != total {
            spare.copy_within(part_start..part_start + count, total);
        }
        part_start += part_room;
        total += count;
    }
    // SAFETY: the first `total` slots are all written: each part's first
    // `count` slots were written above (`written` counts the slots filled),
    // and the moves put the parts' written slots end to end from slot 0,
    // each moved before a later part can land on it. A panic in a thread
    // propagates before this line, leaving the length 0.
    unsafe { triangles.set_len(total) };

    let mesh = Mesh {
        positions,
        normals,
        triangles,
        materials,
    };
    let parsed: Vec<_> = chunks
        .into_iter()
        .map(|c| (c.positions, c.normals, c.corners, c.faces))
        .collect();
    crate::huge_pages::free_in_background(parsed);
    Outcome::Mesh(mesh, face_statements)
}

/// The materials of a chunk's faces: (first face, material) for each run of
/// faces with one material, the first run at face 0.
type MaterialRuns = Vec<(usize, Option<usize>)>;

/// The reference parser's material statements replayed in file order:
/// `mtllib` reads MTL files into the library, `usemtl` names the material
/// of the faces after it, which becomes used at the first such face.
struct MaterialState<'p, 't> {
    files: MaterialFiles<'p>,
    library: HashMap<String, MeshMaterial>,
    loaded: Vec<PathBuf>,
    /// Index in `used` of each material used so far, by name.
    used_index: HashMap<String, usize>,
    used: Vec<MeshMaterial>,
    /// The last `usemtl`'s name, from the text.
    current: Option<&'t str>,
    current_index: Option<usize>,
    /// MTL files the observer was told of.
    reads: usize,
}

impl<'p, 't> MaterialState<'p, 't> {
    fn new(files: MaterialFiles<'p>) -> Self {
        MaterialState {
            files,
            library: HashMap::new(),
            loaded: Vec::new(),
            used_index: HashMap::new(),
            used: Vec::new(),
            current: None,
            current_index: None,
            reads: 0,
        }
    }

    /// Per chunk, the runs of its faces' material: (first face, material).
    /// None where the reference parser refuses a statement.
    fn runs(&mut self, chunks: &[Chunk<'t>]) -> Option<Vec<MaterialRuns>> {
        let mut all = Vec::with_capacity(chunks.len());
        for chunk in chunks {
            let mut runs = Vec::new();
            let mut next_face = 0usize;
            for &(faces_before, event) in &chunk.events {
                if faces_before > next_face {
                    runs.push((next_face, Some(self.face_material()?)));
                    next_face = faces_before;
                }
                match event {
                    Event::Mtllib(line) => self.mtllib(line)?,
                    Event::Usemtl(line) => {
                        let name = obj::rest_of_line(line, "usemtl");
                        if name.is_empty() {
                            return None;
                        }
                        self.current = Some(name);
                        self.current_index = None;
                    }
                }
            }
            if chunk.faces.len() > next_face {
                runs.push((next_face, Some(self.face_material()?)));
            }
            all.push(runs);
        }
        Some(all)
    }

    /// The material of a face: the last `usemtl`'s, in order of first use.
    fn face_material(&mut self) -> Option<usize> {
        if let Some(index) = self.current_index {
            return Some(index);
        }
        let name = self.current?;
        let found = self.library.get(name)?;
        let index = *self.used_index.entry(name.to_string()).or_insert_with(|| {
            self.used.push(found.clone());
            self.used.len() - 1
        });
        self.current_index = Some(index);
        Some(index)
    }

    /// Reads the MTL files of an `mtllib` statement not read yet.
    fn mtllib(&mut self, line: &str) -> Option<()> {
        let mut any = false;
        for name in line.split_ascii_whitespace().skip(1) {
            any = true;
            let folder = self.files.path.parent().unwrap_or_else(|| Path::new(""));
            let mtl_path = folder.join(name);
            if self.loaded.contains(&mtl_path) {
                continue;
            }
            (self.files.on_read)(&mtl_path);
            self.reads += 1;
            let text = super::input_file::read_input_file(&mtl_path).ok()?;
            obj::parse_mtl(
                &String::from_utf8_lossy(&text),
                &mtl_path,
                &mut self.library,
            )
            .ok()?;
            self.loaded.push(mtl_path);
        }
        // A material that was undefined before may be defined now.
        self.current_index = None;
        any.then_some(())
    }
}

/// `text` cut into `parts` pieces of about equal size, each ending just
/// after a newline (the last at the end of the text); some may be empty.
fn split_at_lines(bytes: &[u8], parts: usize) -> Vec<&[u8]> {
    let mut pieces = Vec::with_capacity(parts);
    let mut start = 0;
    for i in 1..parts.max(1) {
        let aim = (bytes.len() / parts * i).max(start);
        let end = match bytes[aim..].iter().position(|&b| b == b'\n') {
            Some(at) => aim + at + 1,
            None => bytes.len(),
        };
        pieces.push(&bytes[start..end]);
        start = end;
    }
    pieces.push(&bytes[start..]);
    pieces
}

/// Runs `f` on each job, the first on this thread and the others on threads
/// of their own; the results in the jobs' order. A panic in a job is
/// propagated.
fn on_threads<J: Send, R: Send>(jobs: Vec<J>, f: impl Fn(J) -> R + Sync) -> Vec<R> {
    let mut jobs = jobs.into_iter();
    let Some(first) = jobs.next() else {
        return Vec::new();
    };
    std::thread::scope(|scope| {
        let f = &f;
        let others: Vec<_> = jobs.map(|job| scope.spawn(move || f(job))).collect();
        let mut results = vec![f(first)];
        for handle in others {
            results.push(
                handle
                    .join()
                    .unwrap_or_else(|panic| std::panic::resume_unwind(panic)),
            );
        }
        results
    })
}

/// One face corner as written: the 1-based or negative vertex index, and the
/// normal index (0: none).
#[derive(Debug, Clone, Copy)]
struct Corner {
    v: i32,
    vn: i32,
}

/// One `f` statement: where its corners end in `Chunk::corners`, and how
/// many vertices and normals the chunk had defined before it.
#[derive(Debug, Clone, Copy)]
struct Face {
    corners_end: u32,
    positions_before: u32,
    normals_before: u32,
}

/// A material statement (only read when materials are asked for), with
/// its line as the reference parser sees it (no `\r`, no comment).
#[derive(Debug, Clone, Copy)]
enum Event<'a> {
    Mtllib(&'a str),
    Usemtl(&'a str),
}

/// What one chunk of the file defines, indices unresolved.
#[derive(Debug, Default)]
struct Chunk<'a> {
    positions: Vec<DVec3>,
    normals: Vec<DVec3>,
    corners: Vec<Corner>,
    faces: Vec<Face>,
    face_statements: usize,
    /// Material statements, each with the number of faces before it.
    events: Vec<(usize, Event<'a>)>,
}

impl<'a> Chunk<'a> {
    /// Parses whole lines; None at the first statement the fast path leaves
    /// to the reference parser.
    fn parse(text: &'a str, with_materials: bool) -> Option<Chunk<'a>> {
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
                    let statement = obj::strip_comment(raw);
                    let event = match keyword {
                        "mtllib" => Event::Mtllib(statement),
                        _ => Event::Usemtl(statement),
                    };
                    chunk.events.push((chunk.faces.len(), event));
                    continue;
                }
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
    /// below, docs/benchmarks.md), anything else as a token.
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
struct Resolved<'a> {
    positions: &'a [DVec3],
}

impl Resolved<'_> {
    /// Calls `emit` with each triangle of `chunk`'s faces, in order, exactly
    /// as the reference parser builds them (fan-triangulated, zero-area
    /// triangles skipped); `start` is where the chunk's vertices and normals
    /// begin in the file; `runs` the faces' materials as (first face,
    /// material), starting at face 0. None at an index out of range, or one
    /// a mesh cannot hold (`mesh_index`).
    fn triangles(
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::obj::{parse_obj, parse_obj_counting, parse_reference};
    use crate::scene::SceneError;
    use proptest::prelude::*;

    /// The reference parser's mesh and `f` count, or its error, as text:
    /// `{:?}` writes every f64 in its shortest round-trip form, so equal text
    /// is equal bits (it tells -0.0 from 0.0, which `==` does not).
    fn reference(text: &str) -> Result<(String, usize), String> {
        let mut faces = 0;
        parse_reference(text, Path::new("m.obj"), false, &mut |_| {}, &mut faces)
            .map(|mesh| (format!("{mesh:?}"), faces))
            .map_err(|e| e.to_string())
    }

    /// The fast path on `threads` chunks, as `reference` writes it; None
    /// where it leaves the text to the reference parser.
    fn fast(text: &str, threads: usize) -> Option<(String, usize)> {
        match parse(text.as_bytes(), threads, None) {
            Outcome::Mesh(mesh, faces) => Some((format!("{mesh:?}"), faces)),
            Outcome::Declined { mtl_reads } => {
                assert_eq!(mtl_reads, 0);
                None
            }
        }
    }

    /// Decimal numbers as exporters write them, and awkward ones: signs,
    /// no digits before or after the point, 15 and 16 digits (the fast
    /// path's limit), leading zeros, exponents, `inf`, `nan`, junk.
    fn number_text() -> impl Strategy<Value = String> {
        prop_oneof![
            4 => (
                prop::sample::select(vec!["", "-", "+"]),
                "[0-9]{0,9}",
                prop::option::of("[0-9]{0,9}"),
            )
                .prop_map(|(sign, int, frac)| match frac {
                    Some(frac) => format!("{sign}{int}.{frac}"),
                    None => format!("{sign}{int}"),
                }),
            1 => "[-+]?0*[0-9]{13,17}(\\.[0-9]{0,4})?",
            1 => "[-+]?[0-9]{0,3}\\.?[0-9]{0,3}[eE][-+]?[0-9]{1,3}",
            1 => "[-+.0-9eE]{1,6}",
            1 => prop::sample::select(vec![
                "inf", "-inf", "infinity", "NaN", "nan", "1e308", "1e309", "-0", "-0.0",
                "0.1", "0.2", "0.3", "9007199254740993", "999999999999999", "0.000000000000001",
                ".", "-.", "+.5", "5.", "1,5", "0x10", "１",
            ])
            .prop_map(str::to_string),
            1 => any::<f64>().prop_map(|v| v.to_string()),
            1 => any::<f32>().prop_map(|v| v.to_string()),
        ]
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(4096))]

        /// The fast number parser reads exactly what `str::parse` reads.
        #[test]
        fn numbers_parse_as_the_standard_library_parses(text in number_text()) {
            let want = text.parse::<f64>().ok().filter(|v| v.is_finite());
            let got = number(&text);
            prop_assert_eq!(got.map(f64::to_bits), want.map(f64::to_bits), "{:?}", text);
        }
    }

    /// One line of a generated OBJ file, its numbers still to be chosen
    /// (`Obj::text` resolves face corners against the vertices so far).
    #[derive(Debug, Clone)]
    enum Statement {
        Vertex(Vec<String>),
        Normal(Vec<String>),
        Texture,
        /// Corners: (vertex pick, normal pick, negative, form 0..4: `v`,
        /// `v/vt`, `v//vn`, `v/vt/vn`).
        Face(Vec<(usize, usize, bool, u8)>),
        /// Lines every reader ignores without materials, comments, blanks.
        Other(&'static str),
        /// A line the reference parser refuses or the fast path leaves to it.
        Odd(&'static str),
    }

    fn statement() -> impl Strategy<Value = Statement> {
        // Coordinates on a small grid, so that faces repeat vertices and lie
        // on lines (zero area), plus any number the number strategy makes.
        let coordinate = prop_oneof![
            6 => prop::sample::select(vec!["0", "1", "-1", "0.5", "-0", "2", "1e-200", "3.25"])
                .prop_map(str::to_string),
            1 => number_text(),
        ];
        prop_oneof![
            8 => prop::collection::vec(coordinate.clone(), 3..=4).prop_map(Statement::Vertex),
            3 => prop::collection::vec(coordinate, 3..=3).prop_map(Statement::Normal),
            1 => Just(Statement::Texture),
            8 => prop::collection::vec((0..64usize, 0..64usize, any::<bool>(), 0..4u8), 3..=6)
                .prop_map(Statement::Face),
            3 => prop::sample::select(vec![
                "", "   ", "# a comment", "#", "o thing", "g group", "s 1", "s off",
                "usemtl gold", "mtllib a.mtl", "vp 0.1 0.2", "l 1 2", "V 1 2 3", "v1 2 3 4",
                "F 1 2 3", "\t", "fo 1 2 3",
            ])
            .prop_map(Statement::Other),
            1 => prop::sample::select(vec![
                "v 1 2", "v 1 2 x", "vn 1 2", "vn 1 2 3 4", "f 1 2", "f 0 1 2", "f 1 2 x",
                "f 1 2 3.0", "f +1 +2 +3", "f 1 2 0000000003", "f 1 2 4294967299", "f -1 -2 -999", "f 1 2 99999",
                "f 1//9999 2 3", "v 1 2 3 \\", "f 1/1/1/1 2/2/2/2 3//-1", "f 1/x 2/y/ 3/z/",
                "v 1e400 0 0", "vn nan 0 0",
            ])
            .prop_map(Statement::Odd),
        ]
    }

    /// How a generated line is written around its statement.
    #[derive(Debug, Clone)]
    struct Layout {
        indent: &'static str,
        gap: &'static str,
        comment: &'static str,
        crlf: bool,
    }

    fn layout() -> impl Strategy<Value = Layout> {
        (
            prop::sample::select(vec!["", "", " ", "\t "]),
            prop::sample::select(vec![" ", " ", " ", "  ", "\t", " \x0c", "\r "]),
            prop::sample::select(vec!["", "", "", " # c", "#glued", " \t"]),
            any::<bool>(),
        )
            .prop_map(|(indent, gap, comment, crlf)| Layout {
                indent,
                gap,
                comment,
                crlf,
            })
    }

    /// A whole file: its lines, a byte order mark or not, a last newline or
    /// not. Half the files are kept valid (no odd lines, numbers that parse,
    /// no face before the first vertex), so that the fast path takes them.
    fn obj_text() -> impl Strategy<Value = String> {
        (
            prop::collection::vec((statement(), layout()), 0..60),
            any::<bool>(),
            any::<bool>(),
            any::<bool>(),
        )
            .prop_map(|(lines, bom, last_newline, valid)| {
                let (mut positions, mut normals) = (0usize, 0usize);
                let mut text = String::new();
                if bom {
                    text.push('\u{feff}');
                }
                let finite = |x: &String| match x.parse::<f64>() {
                    Ok(v) if v.is_finite() => x.clone(),
                    _ => "0".to_string(),
                };
                let lines: Vec<_> = lines
                    .into_iter()
                    .filter(|(s, _)| !valid || !matches!(s, Statement::Odd(_)))
                    .map(|(s, l)| match s {
                        Statement::Vertex(xyz) if valid => {
                            (Statement::Vertex(xyz.iter().map(finite).collect()), l)
                        }
                        Statement::Normal(xyz) if valid => {
                            (Statement::Normal(xyz.iter().map(finite).collect()), l)
                        }
                        s => (s, l),
                    })
                    .collect();
                for (i, (statement, l)) in lines.iter().enumerate() {
                    let body = match statement {
                        Statement::Vertex(xyz) => {
                            positions += 1;
                            format!("v{}{}", l.gap, xyz.join(l.gap))
                        }
                        Statement::Normal(xyz) => {
                            normals += 1;
                            format!("vn{}{}", l.gap, xyz.join(l.gap))
                        }
                        Statement::Texture => "vt 0.5 0.25".to_string(),
                        // A valid file has no face before its first vertex.
                        Statement::Face(_) if valid && positions == 0 => "# no face".to_string(),
                        Statement::Face(corners) => {
                            let tokens: Vec<String> = corners
                                .iter()
                                .map(|&(v, n, negative, form)| {
                                    // In range when anything is defined;
                                    // index 1 (out of range) when nothing is.
                                    let pick = |p: usize, defined: usize| match defined {
                                        0 => "1".to_string(),
                                        d if negative => format!("-{}", p % d + 1),
                                        d => format!("{}", p % d + 1),
                                    };
                                    let v = pick(v, positions);
                                    let n = pick(n, normals);
                                    // `v/vt` names no normal; a valid file
                                    // names one only once one is defined.
                                    match form {
                                        0 => v,
                                        _ if valid && normals == 0 => format!("{v}/3"),
                                        1 => format!("{v}/{n}"),
                                        2 => format!("{v}//{n}"),
                                        _ => format!("{v}/7/{n}"),
                                    }
                                })
                                .collect();
                            format!("f{}{}", l.gap, tokens.join(l.gap))
                        }
                        Statement::Other(s) | Statement::Odd(s) => s.to_string(),
                    };
                    text.push_str(l.indent);
                    text.push_str(&body);
                    text.push_str(l.comment);
                    if i + 1 < lines.len() || last_newline {
                        text.push_str(if l.crlf { "\r\n" } else { "\n" });
                    }
                }
                text
            })
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(1024))]

        /// On 1, 2, 3 and 5 chunks the fast path gives the reference
        /// parser's mesh bit for bit, or leaves the file to it; it never
        /// gives a mesh for a file the reference refuses. `parse_obj` (which
        /// picks the path) gives exactly the reference's mesh or error.
        #[test]
        fn fast_path_gives_the_reference_mesh(text in obj_text()) {
            let want = reference(&text);
            let body = text.strip_prefix('\u{feff}').unwrap_or(&text);
            for threads in [1, 2, 3, 5] {
                if let Some(got) = fast(body, threads) {
                    prop_assert_eq!(Ok(got), want.clone(), "{} threads", threads);
                }
            }
            let chosen = parse_obj(&text, Path::new("m.obj"), false)
                .map(|mesh| format!("{mesh:?}"))
                .map_err(|e| e.to_string());
            prop_assert_eq!(chosen, want.map(|(mesh, _)| mesh));
        }
    }

    /// A folder of MTL files for the material property: two that define
    /// `teal` (the first definition wins), one with an error. One folder
    /// for every run, so that runs leave nothing new behind; each file is
    /// renamed into place, so a run beside this one never reads half a file.
    fn mtl_folder() -> &'static Path {
        static FOLDER: std::sync::OnceLock<std::path::PathBuf> = std::sync::OnceLock::new();
        FOLDER.get_or_init(|| {
            let dir = std::env::temp_dir().join("kdray-obj-chunks-test");
            std::fs::create_dir_all(&dir).unwrap();
            let files = [
                (
                    "a.mtl",
                    "newmtl gold\nKd 1 0.8 0\nNs 20\nnewmtl teal\nKd 0 0.5 0.5\n",
                ),
                (
                    "b.mtl",
                    "newmtl teal\r\nKd 1 1 1\r\nnewmtl my red\nKa 1\nKd 1 0 0\n",
                ),
                ("bad.mtl", "newmtl x\nKd 1 1\n"),
            ];
            for (name, text) in files {
                let part = dir.join(format!("{name}.{}", std::process::id()));
                std::fs::write(&part, text).unwrap();
                std::fs::rename(&part, dir.join(name)).unwrap();
            }
            dir
        })
    }

    /// A parse with materials of `text` as `m.obj` in `mtl_folder()`: the
    /// mesh or error as `reference` writes it, and the files the observer
    /// was told of.
    fn with_materials(
        text: &str,
        parser: impl FnOnce(&str, &Path, &mut dyn FnMut(&Path), &mut usize) -> Result<Mesh, SceneError>,
    ) -> (Result<(String, usize), String>, Vec<PathBuf>) {
        let mut read = Vec::new();
        let mut faces = 0;
        let path = mtl_folder().join("m.obj");
        let result = parser(text, &path, &mut |p| read.push(p.to_path_buf()), &mut faces)
            .map(|mesh| (format!("{mesh:?}"), faces))
            .map_err(|e| e.to_string());
        (result, read)
    }

    /// Generated files with material statements inserted at random lines.
    fn obj_text_with_materials() -> impl Strategy<Value = String> {
        let statement = prop_oneof![
            12 => prop::sample::select(vec![
                "usemtl gold", "usemtl teal", "usemtl  my red # c", "mtllib a.mtl",
                "mtllib b.mtl a.mtl", "mtllib  a.mtl\t# again",
            ]),
            1 => prop::sample::select(vec![
                "usemtl nope", "usemtl", "usemtl # none", "mtllib missing.mtl",
                "mtllib bad.mtl", "mtllib", "Usemtl gold",
            ]),
        ];
        (
            prop::bool::weighted(0.8),
            obj_text(),
            prop::collection::vec((any::<prop::sample::Index>(), statement), 0..8),
        )
            .prop_map(|(header, text, inserts)| {
                let mut lines: Vec<String> = text.split('\n').map(str::to_string).collect();
                for (at, statement) in inserts {
                    let at = at.index(lines.len() + 1);
                    lines.insert(at, statement.to_string());
                }
                let body = lines.join("\n");
                if header {
                    format!("mtllib a.mtl b.mtl\nusemtl gold\n{body}")
                } else {
                    body
                }
            })
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(512))]

        /// With materials too: the same mesh (materials in order of first
        /// use, each face's index), error, and MTL files read, in order, on
        /// 1, 2, 3 and 5 chunks and through `parse_obj_counting`.
        #[test]
        fn fast_path_gives_the_reference_mesh_with_materials(
            text in obj_text_with_materials()
        ) {
            let (want, want_read) = with_materials(&text, |t, p, r, f| {
                parse_reference(t, p, true, r, f)
            });
            let body = text.strip_prefix('\u{feff}').unwrap_or(&text).to_string();
            for threads in [1, 2, 3, 5] {
                let mut outcome = None;
                let (_, read) = with_materials(&body, |t, path, on_read, _| {
                    outcome = Some(parse(t.as_bytes(), threads, Some(MaterialFiles { path, on_read })));
                    Err(SceneError::new(path, None, None, "unused"))
                });
                match outcome.unwrap() {
                    Outcome::Mesh(mesh, faces) => {
                        prop_assert_eq!(Ok((format!("{mesh:?}"), faces)), want.clone());
                        prop_assert_eq!(&read, &want_read);
                    }
                    Outcome::Declined { mtl_reads } => {
                        prop_assert_eq!(mtl_reads, read.len());
                        prop_assert!(want_read.starts_with(&read));
                    }
                }
            }
            let chosen = with_materials(&text, |t, p, r, f| parse_obj_counting(t, p, true, r, f));
            prop_assert_eq!(chosen, (want, want_read));
        }
    }

    /// The generated files exercise both outcomes: the fast path takes many
    /// of them (so the property compares meshes), and the reference parser
    /// refuses many.
    #[test]
    fn generated_files_reach_both_paths() {
        use proptest::strategy::ValueTree;
        let mut runner = proptest::test_runner::TestRunner::deterministic();
        let (mut taken, mut refused, mut triangles) = (0, 0, 0);
        for _ in 0..400 {
            let text = obj_text().new_tree(&mut runner).unwrap().current();
            let body = text.strip_prefix('\u{feff}').unwrap_or(&text);
            if let Outcome::Mesh(mesh, _) = parse(body.as_bytes(), 2, None) {
                taken += 1;
                triangles += mesh.triangles.len();
            }
            refused += usize::from(reference(&text).is_err());
        }
        assert!(
            taken >= 100 && refused >= 100,
            "{taken} taken, {refused} refused"
        );
        assert!(triangles >= 1000, "{triangles} triangles");

        // With materials: meshes using two materials or more, and refusals
        // after an MTL file was read.
        let (mut mixed, mut refused_after_reading) = (0, 0);
        for _ in 0..400 {
            let text = obj_text_with_materials()
                .new_tree(&mut runner)
                .unwrap()
                .current();
            let body = text.strip_prefix('\u{feff}').unwrap_or(&text);
            let path = mtl_folder().join("m.obj");
            let files = MaterialFiles {
                path: &path,
                on_read: &mut |_| {},
            };
            match parse(body.as_bytes(), 2, Some(files)) {
                Outcome::Mesh(mesh, _) => mixed += usize::from(mesh.materials.len() >= 2),
                Outcome::Declined { mtl_reads } => {
                    refused_after_reading += usize::from(mtl_reads > 0)
                }
            }
        }
        assert!(mixed >= 30, "{mixed} meshes with two materials or more");
        assert!(
            refused_after_reading >= 20,
            "{refused_after_reading} refused after reading"
        );
    }

    /// The fast path does take the valid files it is meant for (else the
    /// property above would compare nothing): faces in every form, negative
    /// indices across a chunk boundary, comments, CRLF, ignored statements.
    #[test]
    fn fast_path_takes_ordinary_files() {
        let text = "# header\r\nmtllib a.mtl\r\nv 0 0 0\r\nv 1 0 0 1\nv 0 1 0\nv 1 1 0\n\
                    vn 0 0 1\nvt 0 0\nusemtl gold\n\n  f 1 2 3 # c\nf 1/1 2/1 3/1\n\
                    f 1//1 2//1 3//1\nf 1/1/1 -3/1/-1 -1/1/1 4/7/1\ng g\ns off\n\
                    v 2 2 0\nf -1 -2 -3\nf 1 2 2\n";
        let want = reference(text).unwrap();
        assert_eq!(want.1, 6);
        for threads in 1..=6 {
            assert_eq!(
                fast(text, threads).as_ref(),
                Some(&want),
                "{threads} threads"
            );
        }
    }

    /// Files the reference parser refuses, with the refusal in a later chunk
    /// than the vertices it is about, go to the reference parser.
    #[test]
    fn errors_are_left_to_the_reference_parser() {
        for text in [
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 4\n",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf -1 -2 -4\n",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//2\n",
            "v 0 0 0\nv 1 0 0\nf 1 2 3\nv 0 1 0\n",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 0\n",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nv 1 2\n",
        ] {
            assert!(reference(text).is_err(), "{text}");
            for threads in 1..=5 {
                assert_eq!(fast(text, threads), None, "{text}, {threads} threads");
            }
        }
    }

    #[test]
    fn chunks_end_after_newlines_and_cover_the_text() {
        let text = "v 1 2 3\r\nf 1 2 3\n\nvn 0 0 1\nx";
        for parts in 1..=8 {
            let pieces = split_at_lines(text.as_bytes(), parts);
            assert_eq!(pieces.len(), parts);
            assert_eq!(pieces.concat(), text.as_bytes());
            for (i, piece) in pieces.iter().enumerate() {
                let last = pieces[i + 1..].iter().all(|p| p.is_empty());
                assert!(last || piece.ends_with(b"\n"), "{pieces:?}");
            }
        }
        let none: [&[u8]; 3] = [b"", b"", b""];
        assert_eq!(split_at_lines(b"", 3), none);
    }
}
