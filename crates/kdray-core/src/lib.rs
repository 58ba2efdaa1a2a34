//! kdray's GPU-free core: everything between a scene file and the arrays a
//! kernel reads, with no GPU, window or report in its dependency tree.
//!
//! Data flows one way: [`scene`] (parse, validate, OBJ and glTF, animation)
//! -> [`geometry`] (the objects in f32, with the kernel's intersection
//! arithmetic) -> [`kdtree`] (build, ropes, the CPU walks and brute force)
//! -> [`layout`] (the `#[repr(C)]` types the kernel reads, and the scene
//! flattened into them) -> [`prepare`] (a scene with its tree and arrays,
//! ready to upload). The `kdray` crate uploads them and traces them on the
//! GPU. Beside them,
//! [`random_scene`] generates the deterministic random scenes of
//! `kdray bench` and `kdray generate` (and of the k-d tree's tests).

pub mod bsdf;
pub mod choice;
pub mod denoise;
pub mod geometry;
mod huge_pages;
pub mod kdtree;
pub mod layout;
pub mod prepare;
pub mod random_scene;
pub mod scene;
pub mod two_level;

/// The fuzz targets' entry points (`fuzz/`, `crates/kdray-core/tests/fuzz_regressions.rs`).
#[cfg(feature = "test-support")]
#[doc(hidden)]
pub mod fuzz_support;
/// The CPU mirror of the whole kernel, for checking GPU images and for
/// `kdray inspect`.
pub mod reference;
