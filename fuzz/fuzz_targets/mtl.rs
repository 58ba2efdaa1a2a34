//! Any bytes as an MTL material library: no panic, no endless read.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    kdray_core::fuzz_support::mtl(data);
});
