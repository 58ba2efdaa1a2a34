//! Everything that talks to wgpu:
//!
//! - [`bindings`]: the host-shader contract (bindings, entry points,
//!   shared constants) and the WGSL it generates.
//! - [`shaders`]: the WGSL sources assembled with that generated text.
//! - [`context`]: the adapter and device.
//! - `scene_arrays`: the scene's arrays in the GPU layout ([`SceneArrays`]).
//! - [`scene_buffers`]: those arrays cut into chunks for their bindings,
//!   checked against the adapter and uploaded ([`SceneBuffers`]).
//! - `prepared_scene` and `gpu_scene`: a scene prepared on the CPU
//!   ([`PreparedScene`]), and the same uploaded ([`GpuScene`]).
//! - `frame_params`: the kernel's per-frame uniform.
//! - [`kernel_variant`]: the override-specialised kernel variants.
//! - `trace_pipelines`: the one place a compute pipeline is assembled
//!   (module, layout from the contract, bind groups, a pipeline per variant).
//! - [`renderer`]: the tiled trace dispatch with readback; `accumulate`:
//!   the window's progressive accumulation; `ray_query`: rays in, hits out.

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
mod prepared_scene;
mod ray_query;
pub mod renderer;
mod scene_arrays;
pub mod scene_buffers;
pub mod shaders;
mod tile_plan;
mod trace_pipelines;
pub mod walk_log;

pub use accumulate::{Accumulation, Target};
pub use bindings::{PRESENT_ACES, PRESENT_CLAMP_SRGB, PRESENT_QUANTISE};
pub use context::{max_binding_bytes, GpuContext};
pub use frame_params::Accel;
pub use gpu_scene::{GpuScene, UploadFailed};
pub use kernel_io::{FrameParams, GpuQueryHit, GpuQueryRay, PresentParams, RayCounters};
pub use kernel_variant::KernelVariant;
pub use prepared_scene::PreparedScene;
pub use ray_query::{RayQueries, RayQuery};
pub use renderer::{
    CostTotals, GpuTimeSource, RayTotals, RenderSummary, RenderedImage, Renderer, RowBand,
    SAMPLES_PER_DISPATCH,
};
pub use scene_arrays::SceneArrays;
pub use scene_buffers::SceneBuffers;
pub use tile_plan::TilePlan;
pub use trace_pipelines::{TraceBindGroup, TracePipeline, TracePipelines};
pub use walk_log::{RecordedHit, RecordedRay, WalkLog, WalkRecorder};
