//! The denoiser on the GPU: Open Image Denoise 1.4.3's RT filter (its U-Net
//! and trained weights, Apache-2.0, assets/denoise/) run in kdray's own
//! WGSL kernels (shaders/denoise/), f32 throughout, for HDR images with or
//! without albedo and normal.
//!
//! The GPU-free half (weights, wiring, CPU reference, autoexposure,
//! transfer function, tiling) is [`kdray_core::denoise`]. Here:
//! `kernels` (the modules and pipelines), `gpu_weights` (weights laid out
//! for the convolution and uploaded once per [`Denoiser`]), `tile_run`
//! (one tile's buffers and its pass: pack, the network's steps, unpack),
//! `dispatches` (those steps as a table of dispatches, which the web page
//! reads too),
//! `work_units` (a tile's run as units of bounded work), `image_run`
//! ([`DenoiseRun`]: an image's tiles' units, run all at once or a few at a
//! time), `layer_ops` (each layer kind alone, for tests) and [`Denoiser`],
//! which cuts an image into tiles and runs them.

mod denoiser;
mod dispatches;
mod gpu_weights;
mod image_run;
mod kernels;
mod layer_ops;
mod tile_run;
mod work_units;

pub use denoiser::{shipped_weights, Denoiser};
pub use dispatches::{network_dispatches, ConvParams, DenoiseKernel, ResampleParams, StepDispatch};
pub use gpu_weights::{GpuWeights, LayerBlocks, WeightsLayout, BLOCK_BYTES};
pub use image_run::DenoiseRun;
pub use kernels::{CONV_WGSL, PACK_WGSL, RESAMPLE_WGSL, WORKGROUP};
pub use tile_run::PackParams;
pub use work_units::{tile_units, UnitKind, WorkUnit};
