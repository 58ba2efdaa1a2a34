//! The fuzzers' corpora and every input they ever crashed on, replayed as
//! ordinary tests (no fuzzer needed): nothing may panic. See docs/testing.md.

#[path = "common/mod.rs"]
mod common;

use kdray_core::scene::SceneFormat;

fn inputs(target: &str) -> Vec<std::path::PathBuf> {
    let root = common::repo_path("fuzz");
    let mut files = Vec::new();
    for dir in [
        root.join("corpus").join(target),
        root.join("regressions").join(target),
    ] {
        if let Ok(entries) = std::fs::read_dir(&dir) {
            files.extend(entries.map(|e| e.unwrap().path()).filter(|p| p.is_file()));
        }
    }
    files.sort();
    files
}

fn replay(target: &str, check: impl Fn(&[u8])) {
    let files = inputs(target);
    assert!(
        !files.is_empty(),
        "no corpus for {target} in fuzz/corpus/{target}"
    );
    for file in files {
        // A running fuzzer replaces corpus files: skip one that just vanished.
        let Ok(data) = std::fs::read(&file) else {
            continue;
        };
        // A panic names the input that caused it.
        let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| check(&data)));
        assert!(result.is_ok(), "{} panics", file.display());
    }
}

#[test]
fn scene_toml_corpus() {
    replay("scene_toml", |data| {
        if let Ok(text) = std::str::from_utf8(data) {
            kdray_core::fuzz_support::scene(text, SceneFormat::Toml);
        }
    });
}

#[test]
fn scene_json_corpus() {
    replay("scene_json", |data| {
        if let Ok(text) = std::str::from_utf8(data) {
            kdray_core::fuzz_support::scene(text, SceneFormat::Json);
        }
    });
}

#[test]
fn obj_corpus() {
    replay("obj", kdray_core::fuzz_support::obj);
}

#[test]
fn mtl_corpus() {
    replay("mtl", kdray_core::fuzz_support::mtl);
}

#[test]
fn gltf_corpus() {
    replay("gltf", kdray_core::fuzz_support::gltf);
}

/// Without a fuzzer at hand: every prefix of the GLB and glTF seeds, and
/// every single-bit flip of the GLB, must not panic either.
#[test]
fn gltf_truncations_and_bit_flips() {
    let root = common::repo_path("fuzz/corpus/gltf");
    for name in ["tetra.glb", "tetra_embedded.gltf"] {
        let data = std::fs::read(root.join(name)).unwrap();
        for end in 0..data.len() {
            let input = &data[..end];
            let result = std::panic::catch_unwind(|| kdray_core::fuzz_support::gltf(input));
            assert!(result.is_ok(), "{name} cut at {end} panics");
        }
    }
    let data = std::fs::read(root.join("tetra.glb")).unwrap();
    for at in 0..data.len() {
        for bit in 0..8 {
            let mut input = data.clone();
            input[at] ^= 1 << bit;
            let result = std::panic::catch_unwind(|| kdray_core::fuzz_support::gltf(&input));
            assert!(
                result.is_ok(),
                "tetra.glb with bit {bit} of byte {at} flipped panics"
            );
        }
    }
}

/// What a fuzzer cannot easily reach: an image whose header claims a huge
/// size in a file of a few hundred bytes. The decoder must refuse it from
/// its header (the image crate's allocation limit) rather than allocate
/// for it. Allocations are counted per thread by the allocator below.
mod huge_images {
    use std::alloc::{GlobalAlloc, Layout, System};
    use std::cell::Cell;

    use kdray_core::scene::{MinFilter, Texture, TextureFilter, TextureWrap};

    /// System's allocator, counting what each thread holds and the most it
    /// has held.
    struct CountingAllocator;

    thread_local! {
        static HELD: Cell<isize> = const { Cell::new(0) };
        static PEAK: Cell<isize> = const { Cell::new(0) };
    }

    fn note(delta: isize) {
        // try_with: allocations while a thread's locals are torn down go uncounted.
        let _ = HELD.try_with(|held| {
            let now = held.get() + delta;
            held.set(now);
            let _ = PEAK.try_with(|peak| peak.set(peak.get().max(now)));
        });
    }

    // SAFETY: every call is passed on to System unchanged; the counting
    // touches only const-initialised thread locals, which never allocate.
    unsafe impl GlobalAlloc for CountingAllocator {
        unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
            let p = System.alloc(layout);
            if !p.is_null() {
                note(layout.size() as isize);
            }
            p
        }
        unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
            let p = System.alloc_zeroed(layout);
            if !p.is_null() {
                note(layout.size() as isize);
            }
            p
        }
        unsafe fn dealloc(&self, p: *mut u8, layout: Layout) {
            System.dealloc(p, layout);
            note(-(layout.size() as isize));
        }
        unsafe fn realloc(&self, p: *mut u8, layout: Layout, size: usize) -> *mut u8 {
            let q = System.realloc(p, layout, size);
            if !q.is_null() {
                note(size as isize - layout.size() as isize);
            }
            q
        }
    }

    #[global_allocator]
    static ALLOCATOR: CountingAllocator = CountingAllocator;

    /// Runs `f` and returns its result with the most bytes this thread
    /// held at once beyond what it held before.
    fn peak_bytes<T>(f: impl FnOnce() -> T) -> (T, usize) {
        let start = HELD.with(Cell::get);
        PEAK.with(|p| p.set(start));
        let out = f();
        (out, (PEAK.with(Cell::get) - start) as usize)
    }

    fn crc32(bytes: &[u8]) -> u32 {
        let mut crc = !0u32;
        for &b in bytes {
            crc ^= u32::from(b);
            for _ in 0..8 {
                crc = (crc >> 1) ^ (0xEDB8_8320 & (crc & 1).wrapping_neg());
            }
        }
        !crc
    }

    /// A PNG whose header says `width` x `height` RGBA8 texels, with one
    /// stored (uncompressed) zlib block holding its first row only.
    fn png_claiming(width: u32, height: u32) -> Vec<u8> {
        fn chunk(out: &mut Vec<u8>, kind: &[u8; 4], body: &[u8]) {
            out.extend((body.len() as u32).to_be_bytes());
            let typed: Vec<u8> = kind.iter().chain(body).copied().collect();
            out.extend(&typed);
            out.extend(crc32(&typed).to_be_bytes());
        }
        let mut header = Vec::new();
        header.extend(width.to_be_bytes());
        header.extend(height.to_be_bytes());
        header.extend([8, 6, 0, 0, 0]);
        let row = vec![0u8; 1 + 4 * 16];
        let mut idat = vec![0x78, 0x01, 0x01];
        idat.extend((row.len() as u16).to_le_bytes());
        idat.extend((!(row.len() as u16)).to_le_bytes());
        idat.extend(&row);
        idat.extend(1u32.wrapping_add(row.len() as u32 * 65536).to_be_bytes()); // adler32 of zeros
        let mut out = b"\x89PNG\r\n\x1a\n".to_vec();
        chunk(&mut out, b"IHDR", &header);
        chunk(&mut out, b"IDAT", &idat);
        chunk(&mut out, b"IEND", &[]);
        out
    }

    /// A 2 x 2 baseline JPEG with its frame header (SOF0) then saying
    /// `side` x `side`.
    fn jpeg_claiming(side: u16) -> Vec<u8> {
        let image = image::RgbImage::from_pixel(2, 2, image::Rgb([200, 30, 90]));
        let mut jpeg = Vec::new();
        image::codecs::jpeg::JpegEncoder::new(&mut jpeg)
            .encode_image(&image)
            .unwrap();
        let sof = jpeg.windows(2).position(|w| w == [0xFF, 0xC0]).unwrap();
        jpeg[sof + 5..sof + 7].copy_from_slice(&side.to_be_bytes());
        jpeg[sof + 7..sof + 9].copy_from_slice(&side.to_be_bytes());
        jpeg
    }

    /// Standard base64 with padding, as data URIs carry it.
    fn base64(bytes: &[u8]) -> String {
        const DIGITS: &[u8; 64] =
            b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
        let mut out = String::new();
        for group in bytes.chunks(3) {
            let n = group
                .iter()
                .enumerate()
                .fold(0u32, |n, (i, &b)| n | u32::from(b) << (16 - 8 * i));
            for k in 0..4 {
                if k <= group.len() {
                    out.push(DIGITS[(n >> (18 - 6 * k) & 63) as usize] as char);
                } else {
                    out.push('=');
                }
            }
        }
        out
    }

    fn decode(bytes: &[u8]) -> Result<Texture, String> {
        Texture::decode(
            "test",
            bytes,
            TextureFilter::Bilinear,
            MinFilter::TRILINEAR,
            [TextureWrap::Repeat; 2],
        )
    }

    /// Headers of 60000 x 60000 texels (14.4 GB as RGBA8) are refused
    /// with an error while the decoder holds under 1 MB; a real 1024 x 1024
    /// image, decoded the same way, is counted at its size at least (the
    /// counting sees the decoder's allocations).
    #[test]
    fn an_image_claiming_huge_dimensions_is_refused_without_allocating_for_it() {
        let small = png_claiming(16, 1);
        let (texture, _) = peak_bytes(|| decode(&small));
        let texture = texture.unwrap_or_else(|e| panic!("the 16 x 1 PNG must decode: {e}"));
        assert_eq!((texture.width, texture.height), (16, 1));

        let big = image::RgbaImage::from_pixel(1024, 1024, image::Rgba([1, 2, 3, 255]));
        let mut png = std::io::Cursor::new(Vec::new());
        big.write_to(&mut png, image::ImageFormat::Png).unwrap();
        let (texture, peak) = peak_bytes(|| decode(png.get_ref()));
        assert_eq!(texture.unwrap().texels.len(), 1024 * 1024);
        assert!(
            peak >= 4 << 20,
            "1024 x 1024 decoded with a peak of {peak} bytes"
        );

        for (kind, bytes) in [
            ("PNG", png_claiming(60_000, 60_000)),
            ("JPEG", jpeg_claiming(60_000)),
        ] {
            let (result, peak) = peak_bytes(|| decode(&bytes));
            let error = result.err().unwrap_or_else(|| panic!("the {kind} decoded"));
            assert!(!error.contains('\n'), "{kind}: {error}");
            assert!(peak < 1 << 20, "{kind}: {peak} bytes held; {error}");
        }
    }

    /// The same PNG as a glTF material's texture: a warning naming the
    /// image; the mesh loads, its material untextured.
    #[test]
    fn a_gltf_texture_claiming_huge_dimensions_is_a_warning() {
        // The PNG seed's image, a data URI, replaced by the huge one.
        let root = crate::common::repo_path("fuzz/corpus/gltf");
        let seed = std::fs::read_to_string(root.join("seed_texture_png_data_uri.gltf")).unwrap();
        let prefix = "data:image/png;base64,";
        let start = seed.find(prefix).unwrap() + prefix.len();
        let end = start + seed[start..].find('"').unwrap();
        let text = format!(
            "{}{}{}",
            &seed[..start],
            base64(&png_claiming(60_000, 60_000)),
            &seed[end..]
        );
        let path = std::path::Path::new("/nonexistent/huge.gltf");
        let (mesh, peak) = peak_bytes(|| {
            kdray_core::scene::gltf::parse_gltf(text.as_bytes(), path, true, &mut |_| {
                Err(std::io::ErrorKind::NotFound.into())
            })
        });
        let mesh = mesh.unwrap_or_else(|e| panic!("{e}"));
        assert!(mesh.materials.iter().all(|m| m.texture.is_none()));
        assert_eq!(mesh.warnings.len(), 1, "{:?}", mesh.warnings);
        let message = &mesh.warnings[0].message;
        assert!(
            message.contains("baseColorTexture image 0") && !message.contains('\n'),
            "{message}"
        );
        assert!(peak < 4 << 20, "{peak} bytes held");
    }
}
