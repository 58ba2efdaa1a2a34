//! Any bytes as an OBJ file (with and without materials): no panic.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    kdray_core::fuzz_support::obj(data);
});
