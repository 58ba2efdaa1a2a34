//! The OBJ reader's fast path: the text cut at line boundaries into one
//! chunk per thread, each chunk's `v`, `vn` and `f` statements parsed from
//! its bytes without allocating per line, then the faces resolved and
//! fan-triangulated on the same threads into one `Mesh`. Material
//! statements (`mtllib`, `usemtl`) are kept per chunk and replayed in file
//! order on one thread between the two.
//!
//! It gives exactly the mesh of the reference parser ([`reference`](super::reference))
//! or declines: on any statement it does not handle the same way (an error
//! of any kind, an index written with ten digits) the caller runs the
//! reference parser, which then reports the error with its file, line and
//! key. So errors keep one implementation, and the fast path only has to be
//! right on valid input; `fast_path_equivalence` compares the two on generated files, bit
//! for bit, with and without materials.
//!
//! Indices are resolved after every chunk is parsed, since a chunk does not
//! know how many vertices the chunks before it define: each face keeps the
//! raw OBJ indices and the chunk's own vertex and normal counts at the face.

use std::mem::MaybeUninit;

use glam::DVec3;

use super::chunk::{Chunk, Resolved};
use super::material_replay::{MaterialFiles, MaterialRuns, MaterialState};
use crate::scene::mesh::{Mesh, MeshMaterial, MeshTriangle};

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

/// What the fast path made of a file.
pub(super) enum Outcome {
    /// The mesh (boxed: it outweighs `Declined` many times) and the number
    /// of `f` statements.
    Mesh(Box<Mesh>, usize),
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
    let Some(mut chunks) = parse_chunks(text, threads, materials.is_some()) else {
        return declined;
    };
    let (positions, normals, starts) = join_vertices(&mut chunks);
    let face_statements = chunks.iter().map(|c| c.face_statements).sum();
    let file = Resolved {
        positions: &positions,
    };
    let jobs: Vec<_> = chunks.iter().zip(&starts).collect();
    let Some(rooms) = part_rooms(&file, &jobs, materials.is_some()) else {
        return declined;
    };
    let (runs, materials, mtl_reads) = match replay_materials(materials, &chunks) {
        Ok(replayed) => replayed,
        Err(mtl_reads) => return Outcome::Declined { mtl_reads },
    };

    // Texture coordinates matter only for a textured material: such a
    // file is the reference parser's.
    if materials.iter().any(|m| m.texture.is_some())
        && chunks.iter().any(|c| c.has_texture_coordinates)
    {
        return Outcome::Declined { mtl_reads };
    }
    let Some(triangles) = write_triangles(&file, jobs, &runs, &rooms) else {
        return Outcome::Declined { mtl_reads };
    };

    let mesh = Mesh {
        positions,
        normals,
        uvs: Vec::new(),
        second_uvs: Vec::new(),
        colours: Vec::new(),
        tangents: Vec::new(),
        triangles,
        materials,
        warnings: Vec::new(),
        camera: None,
        lights: Vec::new(),
        instanced: Vec::new(),
    };
    let parsed: Vec<_> = chunks
        .into_iter()
        .map(|c| (c.positions, c.normals, c.corners, c.faces))
        .collect();
    crate::huge_pages::free_in_background(parsed);
    Outcome::Mesh(Box::new(mesh), face_statements)
}

/// `text` cut at line ends into `threads` chunks, each parsed on a thread
/// of its own; None where a chunk is left to the reference parser.
fn parse_chunks(text: &[u8], threads: usize, with_materials: bool) -> Option<Vec<Chunk<'_>>> {
    // Each chunk's UTF-8 is checked on its thread (the pieces end at line
    // ends, so the whole text is valid where they all are): checked whole
    // on one thread, the bunny's 43 MB took 3 - 7 ms.
    on_threads(split_at_lines(text, threads), |piece| {
        Chunk::parse(std::str::from_utf8(piece).ok()?, with_materials)
    })
    .into_iter()
    .collect()
}

/// The file's vertices and normals: the first chunk's, which usually
/// holds them all (exporters write vertices first), extended by the
/// others'; and where each chunk's start (vertex, normal).
fn join_vertices(chunks: &mut [Chunk]) -> (Vec<DVec3>, Vec<DVec3>, Vec<(usize, usize)>) {
    let mut starts = Vec::with_capacity(chunks.len());
    let mut positions = std::mem::take(&mut chunks[0].positions);
    let mut normals = std::mem::take(&mut chunks[0].normals);
    starts.push((0, 0));
    for chunk in &chunks[1..] {
        starts.push((positions.len(), normals.len()));
        positions.extend_from_slice(&chunk.positions);
        normals.extend_from_slice(&chunk.normals);
    }
    (positions, normals, starts)
}

/// The room each chunk's part of the triangle vector needs.
///
/// The faces are resolved and written in place into one vector, each
/// chunk into its own part (writing a vector per chunk and appending
/// would copy half the mesh again). A part's room is the chunk's fan
/// triangles, `corners - 2` a face; zero-area ones are skipped, so a part
/// may end short and the next ones move down after. With materials, a
/// first pass counts the triangles exactly: it checks every index before
/// the first MTL file is read (see `parse`); None where one is out of
/// range. Without, one pass does: the 1.1 M-triangle bunny's second pass
/// took 20 ms of its 0.22 s load.
fn part_rooms(
    file: &Resolved,
    jobs: &[(&Chunk, &(usize, usize))],
    with_materials: bool,
) -> Option<Vec<usize>> {
    if !with_materials {
        return Some(
            jobs.iter()
                .map(|(c, _)| c.corners.len() - 2 * c.faces.len())
                .collect(),
        );
    }
    let no_material = [(0, None)];
    on_threads(jobs.to_vec(), |(chunk, &start)| {
        let mut count = 0usize;
        file.triangles(chunk, start, &no_material, |_| count += 1)
            .map(|()| count)
    })
    .into_iter()
    .collect()
}

/// The chunks' material runs, the materials used and the number of MTL
/// files read, replaying the material statements in file order (reading
/// the MTL files); without `materials`, one run of no material a chunk.
/// Declined: `Err` with the number of MTL files read.
fn replay_materials(
    materials: Option<MaterialFiles>,
    chunks: &[Chunk],
) -> Result<(Vec<MaterialRuns>, Vec<MeshMaterial>, usize), usize> {
    let Some(files) = materials else {
        return Ok((vec![vec![(0, None)]; chunks.len()], Vec::new(), 0));
    };
    let mut state = MaterialState::new(files);
    match state.runs(chunks) {
        Some(runs) => Ok((runs, state.used, state.reads)),
        None => Err(state.reads),
    }
}

/// Every chunk's triangles, resolved on its own thread into its part
/// (`rooms`, see [`part_rooms`]) of one vector, the parts then closed up;
/// None where a chunk's faces do not resolve, or overflow their part.
fn write_triangles(
    file: &Resolved,
    jobs: Vec<(&Chunk, &(usize, usize))>,
    runs: &[MaterialRuns],
    rooms: &[usize],
) -> Option<Vec<MeshTriangle>> {
    let room: usize = rooms.iter().sum();
    let mut triangles: Vec<MeshTriangle> = crate::huge_pages::with_capacity(room);
    let mut parts = Vec::with_capacity(rooms.len());
    let mut rest = &mut triangles.spare_capacity_mut()[..room];
    for &part_room in rooms {
        let (part, tail) = rest.split_at_mut(part_room);
        parts.push(part);
        rest = tail;
    }
    let written = on_threads(
        parts.into_iter().zip(jobs).zip(runs).collect(),
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
    let written = written.into_iter().collect::<Option<Vec<usize>>>()?;
    let total = close_gaps(triangles.spare_capacity_mut(), rooms, &written);
    // SAFETY: the first `total` slots are all written: each part's first
    // `count` slots were written above (`written` counts the slots filled),
    // and `close_gaps` put the parts' written slots end to end from slot 0,
    // each moved before a later part can land on it. A panic in a thread
    // propagates before this line, leaving the length 0.
    unsafe { triangles.set_len(total) };
    Some(triangles)
}

/// Moves each part's `written` slots down to follow the previous part's
/// (none move when no triangle was skipped); the parts start `rooms`
/// apart in `spare`. Returns the slots written in all.
fn close_gaps(
    spare: &mut [MaybeUninit<MeshTriangle>],
    rooms: &[usize],
    written: &[usize],
) -> usize {
    let (mut part_start, mut total) = (0usize, 0usize);
    for (&part_room, &count) in rooms.iter().zip(written) {
        if part_start != total {
            spare.copy_within(part_start..part_start + count, total);
        }
        part_start += part_room;
        total += count;
    }
    total
}

/// `text` cut into `parts` pieces of about equal size, each ending just
/// after a newline (the last at the end of the text); some may be empty.
pub(super) fn split_at_lines(bytes: &[u8], parts: usize) -> Vec<&[u8]> {
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
