//! Any bytes as an OBJ file (with and without materials): no panic.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    kdray::scene::obj::fuzz_check(data);
});
