//! Reading an input file (scene, mesh, MTL or glTF buffer) whole: only
//! regular files, at most [`MAX_INPUT_BYTES`], big ones in parts on all
//! cores, into memory advised for huge pages.

/// Largest scene, mesh, MTL or glTF buffer file read (bytes).
pub const MAX_INPUT_BYTES: u64 = 2 << 30;

/// Reads an input file: only regular files (a path like /dev/zero would be
/// read forever), at most MAX_INPUT_BYTES, into a vector of its size (one
/// byte more, where `read_to_end` sees the end) on huge pages.
pub(crate) fn read_input_file(path: &std::path::Path) -> std::io::Result<Vec<u8>> {
    use std::io::Read;
    use std::io::{Error, ErrorKind};
    let meta = std::fs::metadata(path)?;
    if !meta.is_file() {
        return Err(Error::new(ErrorKind::InvalidInput, "not a regular file"));
    }
    if meta.len() > MAX_INPUT_BYTES {
        return Err(Error::new(
            ErrorKind::InvalidInput,
            format!("larger than {} GiB", MAX_INPUT_BYTES >> 30),
        ));
    }
    let mut file = std::fs::File::open(path)?;
    let room = usize::try_from(meta.len() + 1).unwrap_or(usize::MAX);
    let mut bytes = crate::huge_pages::try_with_capacity(room)
        .map_err(|e| Error::new(ErrorKind::OutOfMemory, e.to_string()))?;
    #[cfg(unix)]
    if meta.len() >= PARALLEL_READ_BYTES {
        use std::io::{Seek, SeekFrom};
        let len = room - 1;
        read_on_threads(&file, &mut bytes.spare_capacity_mut()[..len])?;
        // SAFETY: `read_on_threads` returned Ok, so it wrote all of the
        // first `len` bytes of the spare capacity.
        unsafe { bytes.set_len(len) };
        // Then on, as for any file: what it has past that size, if it grew.
        file.seek(SeekFrom::Start(meta.len()))?;
    }
    file.read_to_end(&mut bytes)?;
    Ok(bytes)
}

/// Files of at least this many bytes are read in parts on all cores: the
/// kernel's copy from its cache into fresh memory runs at about 1.5 GB/s
/// on one core of the project's machine (the 43 MB OBJ of the 1.1
/// M-triangle bunny took 28 ms).
#[cfg_attr(not(unix), allow(dead_code))]
const PARALLEL_READ_BYTES: u64 = 8 << 20;

/// Fills `room` with the file's first bytes, one part per core, each part
/// written by its own thread. An error where the file is shorter than
/// `room` (it shrank since its size was read).
#[cfg(unix)]
fn read_on_threads(
    file: &std::fs::File,
    room: &mut [std::mem::MaybeUninit<u8>],
) -> std::io::Result<()> {
    use std::os::unix::fs::FileExt;
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let part = room.len().div_ceil(cores).max(1);
    let read_part = |(i, part_room): (usize, &mut [std::mem::MaybeUninit<u8>])| {
        part_room.fill(std::mem::MaybeUninit::new(0));
        // SAFETY: every byte of the part was just written.
        let part_bytes =
            unsafe { &mut *(part_room as *mut [std::mem::MaybeUninit<u8>] as *mut [u8]) };
        file.read_exact_at(part_bytes, (i * part) as u64)
    };
    let mut parts = room.chunks_mut(part).enumerate();
    let first = parts.next();
    std::thread::scope(|scope| {
        let others: Vec<_> = parts.map(|p| scope.spawn(move || read_part(p))).collect();
        let first_result = first.map_or(Ok(()), read_part);
        others.into_iter().try_fold(first_result?, |(), handle| {
            handle
                .join()
                .unwrap_or_else(|panic| std::panic::resume_unwind(panic))
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A file of `len` bytes, each telling its position apart from its
    /// neighbours' (so that a part read to the wrong place shows).
    fn numbered_file(name: &str, len: usize) -> (std::path::PathBuf, Vec<u8>) {
        let bytes: Vec<u8> = (0..len)
            .map(|i| (i % 251) as u8 ^ (i >> 16) as u8)
            .collect();
        let path = std::env::temp_dir().join(format!("kdray-read-{}-{name}", std::process::id()));
        std::fs::write(&path, &bytes).unwrap();
        (path, bytes)
    }

    /// A file past the size read on threads comes back byte for byte, the
    /// last byte included (a size not a multiple of the parts'); so do the
    /// small ones read in one piece, and an empty one.
    #[test]
    fn input_files_are_read_whole_on_threads_or_not() {
        for (name, len) in [
            ("big", PARALLEL_READ_BYTES as usize + 12_345),
            ("small", 1000),
            ("empty", 0),
        ] {
            let (path, want) = numbered_file(name, len);
            let got = read_input_file(&path).unwrap();
            std::fs::remove_file(&path).unwrap();
            assert!(got == want, "{name}: {} bytes read of {len}", got.len());
        }
    }

    /// The parts, whatever their number, cover the room exactly; a file
    /// shorter than the room is an error, not bytes left unwritten.
    #[cfg(unix)]
    #[test]
    fn reading_in_parts_fills_the_room_or_fails() {
        let (path, want) = numbered_file("parts", 10_007);
        let file = std::fs::File::open(&path).unwrap();
        for len in [1, 2, 3, 10_006, 10_007] {
            let mut v: Vec<u8> = Vec::with_capacity(len);
            read_on_threads(&file, &mut v.spare_capacity_mut()[..len]).unwrap();
            // SAFETY: read_on_threads filled the first `len` bytes.
            unsafe { v.set_len(len) };
            assert!(v[..] == want[..len], "{len} bytes");
        }
        let mut v: Vec<u8> = Vec::with_capacity(10_008);
        assert!(read_on_threads(&file, &mut v.spare_capacity_mut()[..10_008]).is_err());
        std::fs::remove_file(&path).unwrap();
    }
}
