//! The fuzzers' corpora and every input they ever crashed on, replayed as
//! ordinary tests (no fuzzer needed): nothing may panic. See docs/testing.md.

use std::path::Path;

use kdray::scene::SceneFormat;

fn inputs(target: &str) -> Vec<std::path::PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("fuzz");
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
            kdray::fuzz_support::scene(text, SceneFormat::Toml);
        }
    });
}

#[test]
fn scene_json_corpus() {
    replay("scene_json", |data| {
        if let Ok(text) = std::str::from_utf8(data) {
            kdray::fuzz_support::scene(text, SceneFormat::Json);
        }
    });
}

#[test]
fn obj_corpus() {
    replay("obj", kdray::fuzz_support::obj);
}

#[test]
fn gltf_corpus() {
    replay("gltf", kdray::fuzz_support::gltf);
}

/// Without a fuzzer at hand: every prefix of the GLB and glTF seeds, and
/// every single-bit flip of the GLB, must not panic either.
#[test]
fn gltf_truncations_and_bit_flips() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("fuzz/corpus/gltf");
    for name in ["tetra.glb", "tetra_embedded.gltf"] {
        let data = std::fs::read(root.join(name)).unwrap();
        for end in 0..data.len() {
            let input = &data[..end];
            let result = std::panic::catch_unwind(|| kdray::fuzz_support::gltf(input));
            assert!(result.is_ok(), "{name} cut at {end} panics");
        }
    }
    let data = std::fs::read(root.join("tetra.glb")).unwrap();
    for at in 0..data.len() {
        for bit in 0..8 {
            let mut input = data.clone();
            input[at] ^= 1 << bit;
            let result = std::panic::catch_unwind(|| kdray::fuzz_support::gltf(&input));
            assert!(
                result.is_ok(),
                "tetra.glb with bit {bit} of byte {at} flipped panics"
            );
        }
    }
}
