//! The memory policy for big vectors, in one place: every layer that makes
//! a vector of many megabytes (the scene's file bytes and triangles, the
//! geometry's primitives, the tree builder's lists) asks here for its room,
//! and hands big temporaries here to be freed; no other module calls the
//! kernel about memory.
//!
//! Room is backed by 2 MiB pages where the kernel allows it (Linux's
//! transparent huge pages, commonly enabled only on request): one page
//! fault per 2 MiB instead of one per 4 KiB as a fresh vector is first
//! written. The loader writes several such vectors of a big mesh: the
//! file's bytes, the parsed faces, the scene's f64 triangles and the f32
//! primitives (the 1.1 M-triangle bunny's load took 0.29 s before the
//! first, third and fourth were advised and the last made on all threads,
//! 0.22 s after). A hint: nothing changes where it is refused or on other
//! systems.

/// An empty vector with room for `capacity` elements, its room advised.
pub(crate) fn with_capacity<T>(capacity: usize) -> Vec<T> {
    let mut v = Vec::with_capacity(capacity);
    advise(&mut v);
    v
}

/// [`with_capacity`], or the allocator's refusal instead of a panic (for
/// room sized by an input file).
pub(crate) fn try_with_capacity<T>(
    capacity: usize,
) -> Result<Vec<T>, std::collections::TryReserveError> {
    let mut v = Vec::new();
    v.try_reserve_exact(capacity)?;
    advise(&mut v);
    Ok(v)
}

/// Drops `big` (vectors of many megabytes) on a thread of its own, so that
/// giving their pages back to the kernel does not hold up the caller: the
/// 1.1 M-triangle bunny's load freed about 9 ms worth of file, chunks and
/// mesh on the thread that went on to build the tree.
pub(crate) fn free_in_background<T: Send + 'static>(big: T) {
    // Where no thread can start, the caller frees it after all.
    let _ = std::thread::Builder::new()
        .name("kdray-free".into())
        .spawn(move || drop(big));
}

/// Asks the kernel to back the whole 2 MiB pages of `v`'s spare capacity
/// with huge pages. Measured when a triangle took 208 bytes (230 MB for a
/// million-triangle mesh): the scene's load 0.73 s -> 0.63 s (median of
/// eight).
#[cfg(target_os = "linux")]
pub(crate) fn advise<T>(v: &mut Vec<T>) {
    const HUGE_PAGE: usize = 2 << 20;
    let spare = v.spare_capacity_mut();
    let begin = spare.as_mut_ptr() as usize;
    let end = begin + std::mem::size_of_val(spare);
    let (first, last) = (
        begin.next_multiple_of(HUGE_PAGE),
        end / HUGE_PAGE * HUGE_PAGE,
    );
    if last > first {
        // SAFETY: [first, last) lies inside the vector's allocation, which
        // is borrowed mutably here; MADV_HUGEPAGE changes how its pages are
        // backed, never their contents. The result is ignored: it is a hint.
        unsafe {
            libc::madvise(
                first as *mut libc::c_void,
                last - first,
                libc::MADV_HUGEPAGE,
            );
        }
    }
}

#[cfg(not(target_os = "linux"))]
pub(crate) fn advise<T>(_: &mut Vec<T>) {}

#[cfg(test)]
mod tests {
    use super::with_capacity;

    /// The advice keeps what the vector holds and the room it has.
    #[test]
    fn advice_changes_no_contents() {
        let mut v: Vec<u64> = with_capacity(3 << 20);
        assert!(v.is_empty() && v.capacity() >= 3 << 20);
        let w: Vec<u64> = super::try_with_capacity(3 << 20).unwrap();
        assert!(w.is_empty() && w.capacity() >= 3 << 20);
        assert!(super::try_with_capacity::<u64>(usize::MAX / 4).is_err());
        v.extend(0..1000);
        super::advise(&mut v);
        assert!(v.iter().copied().eq(0..1000));
        assert!(v.capacity() >= 3 << 20);
        v.extend(1000..3 << 20);
        assert!(v.iter().copied().eq(0..3 << 20));
    }
}
