//! Any text as a JSON scene: parse and validate without panicking; a scene
//! that validates must also build its k-d tree and trace a ray.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        kdray_core::fuzz_support::scene(text, kdray_core::scene::SceneFormat::Json);
    }
});
