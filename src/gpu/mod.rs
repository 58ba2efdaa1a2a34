//! Everything that talks to wgpu, one file each:
//!
//! - [`bindings`]: the host-shader contract (bindings, entry points,
//!   shared constants) and the WGSL it generates; the split arrays'
//!   bindings in `bindings/split_arrays.rs`, the inspect log's codes in
//!   `bindings/walk_codes.rs`.
//! - [`shaders`]: the WGSL sources assembled with that generated text.
//! - `kernel_io`: what the kernel reads and writes besides the scene's
//!   arrays (frame uniform, ray counters, ray queries, present parameters).
//! - `layout_check` (tests only): the `#[repr(C)]` types against naga's
//!   layout of the WGSL structs.
//! - [`context`]: the adapter and device.
//! - [`pipeline_cache`]: compiled pipelines kept between processes where
//!   the driver keeps them.
//! - [`scene_buffers`]: the scene's arrays in the GPU layout
//!   ([`SceneArrays`]) cut into chunks for their bindings, checked against
//!   the adapter and uploaded ([`SceneBuffers`]); [`ArrayBindings`]: the
//!   arrays by binding, for the web export and the limits check.
//! - `gpu_scene`: a scene prepared on the CPU ([`PreparedScene`]),
//!   uploaded ([`GpuScene`]).
//! - `frame_params`: the kernel's per-frame uniform, built.
//! - [`kernel_variant`]: the override-specialised kernel variants.
//! - `trace_pipelines`: the one place a compute pipeline is assembled
//!   (module, layout from the contract, bind groups, a pipeline per variant).
//! - [`renderer`]: the tiled trace dispatch with readback.
//! - `tile_buffers`: a tile's buffers on the GPU and a band's pixels on the
//!   host, filled from each tile's readback.
//! - `render_summary`: what a render measured besides its pixels (rays by
//!   kind, the walk's work, GPU time).
//! - `tile_plan`: how an image is cut into dispatches (binding size, a
//!   GPU's watchdog).
//! - `gpu_timer`: a tile's GPU time from timestamp queries, and the
//!   context's waits and readbacks.
//! - [`accumulate`]: the window's progressive accumulation.
//! - `ray_query`: the debug entry point, rays in and hits out.
//! - [`walk_log`]: the inspect kernel, one pixel's rays and walk steps
//!   logged and decoded.
//!
//! [`SceneArrays`], [`PreparedScene`] and [`Accel`] are the core's
//! (`kdray_core::layout`, `kdray_core::prepare`), re-exported here beside
//! the types that upload and trace them.

pub mod accumulate;
pub mod bindings;
pub mod context;
mod frame_params;
mod gpu_scene;
mod gpu_timer;
mod kernel_io;
pub mod kernel_variant;
#[cfg(test)]
mod layout_check;
pub mod pipeline_cache;
mod ray_query;
mod render_summary;
pub mod renderer;
pub mod scene_buffers;
pub mod shaders;
pub mod specialise;
mod tile_buffers;
mod tile_plan;
mod trace_pipelines;
pub mod walk_log;

pub use crate::layout::SceneArrays;
pub use crate::prepare::{Accel, PreparedScene};
pub use accumulate::{Accumulation, Target};
pub use bindings::{PRESENT_ACES, PRESENT_CLAMP_SRGB, PRESENT_QUANTISE};
pub use context::{max_binding_bytes, GpuContext};
pub use gpu_scene::{GpuScene, UploadFailed};
pub use kernel_io::{FrameParams, GpuQueryHit, GpuQueryRay, PresentParams, RayCounters};
pub use kernel_variant::KernelVariant;
pub use ray_query::{RayQueries, RayQuery};
pub use render_summary::{CostTotals, GpuTimeSource, RayTotals, RenderSummary};
pub use renderer::{Features, RenderedImage, Renderer, RowBand, SAMPLES_PER_DISPATCH};
pub use scene_buffers::{ArrayBindings, SceneBuffers};
pub use tile_plan::TilePlan;
pub use trace_pipelines::{TraceBindGroup, TracePipeline, TracePipelines};
pub use walk_log::{RecordedHit, RecordedRay, WalkLog, WalkRecorder};
