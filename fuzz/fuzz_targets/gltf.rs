//! Any bytes as a glTF or GLB file (with and without materials): no panic.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    kdray_core::fuzz_support::gltf(data);
});
