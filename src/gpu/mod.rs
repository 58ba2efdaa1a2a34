//! Everything that talks to wgpu: the adapter and device ([`context`]), the
//! scene's storage buffers ([`scene_buffers`]), the shaders ([`shaders`]),
//! the trace kernel's specialised pipelines ([`kernel_variant`]) and the
//! tiled trace dispatch with readback ([`renderer`]).

pub mod bindings;
pub mod context;
mod frame_params;
pub mod kernel_variant;
mod prepared_scene;
mod ray_query;
pub mod renderer;
pub mod scene_buffers;
pub mod shaders;
mod trace_pipelines;

pub use context::{max_binding_bytes, GpuContext};
pub use frame_params::Accel;
pub use kernel_variant::KernelVariant;
pub use prepared_scene::PreparedScene;
pub use ray_query::{RayQueries, RayQuery};
pub use renderer::{
    CostTotals, GpuTimeSource, RayTotals, RenderSummary, RenderedImage, Renderer, RowBand, TilePlan,
};
pub use scene_buffers::{SceneArrays, SceneBuffers};
pub use trace_pipelines::TracePipelines;

/// Shaders compiled on their own (not part of the trace kernel), validated
/// by the same test.
pub const STANDALONE_SHADERS: [(&str, &str); 1] = [("present.wgsl", shaders::PRESENT_SOURCE)];
