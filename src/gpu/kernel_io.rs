//! What the kernel reads and writes besides the scene's arrays: the frame's
//! uniform, the ray counters, the ray queries and the present pass's
//! parameters. `#[repr(C)]` Pod types that mirror shaders/types.wgsl and
//! shaders/present.wgsl byte for byte (checked in `layout_check`).

use bytemuck::{Pod, Zeroable};

use super::bindings::{PRESENT_ACES, PRESENT_CLAMP_SRGB, PRESENT_QUANTISE};

/// Everything one dispatch needs besides the scene buffers (a uniform).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct FrameParams {
    pub camera_position: [f32; 3],
    /// tan(vfov / 2).
    pub tan_half_vfov: f32,
    pub camera_forward: [f32; 3],
    /// width / height.
    pub aspect: f32,
    pub camera_right: [f32; 3],
    pub min_intensity: f32,
    pub camera_up: [f32; 3],
    pub max_depth: u32,
    pub background: [f32; 3],
    pub shadow_mode: u32,
    pub scene_min: [f32; 3],
    pub sphere_count: u32,
    pub scene_max: [f32; 3],
    pub object_count: u32,
    /// Full image size in pixels.
    pub width: u32,
    pub height: u32,
    /// k for k * k samples per pixel.
    pub samples_per_axis: u32,
    pub light_count: u32,
    /// Pixel of the image that this dispatch's invocation (0, 0) renders.
    pub tile_origin: [u32; 2],
    /// Size of this dispatch's tile; the output buffer is tile_size.x wide.
    pub tile_size: [u32; 2],
    pub accel: u32,
    /// 0 for an empty scene (nothing to traverse).
    pub node_count: u32,
    /// Whitted: which cell of the k x k sample grid `accumulate_tile`
    /// traces (row-major, taken modulo k * k), and the first cell
    /// `render_tile` traces with radiance output. Path: the first sample
    /// of the dispatch (each sample's random numbers follow from its index).
    pub sample_index: u32,
    /// Which k-d walk: `TRAVERSAL_RESTART`, `TRAVERSAL_ROPES` or `TRAVERSAL_SHORT_STACK`.
    pub traversal: u32,
    /// `INTEGRATOR_WHITTED` or `INTEGRATOR_PATH`.
    pub integrator: u32,
    /// The path tracer's random seed (`[render] seed`).
    pub seed: u32,
    /// Emissive objects in the lights buffer after the `light_count`
    /// point lights.
    pub emitter_count: u32,
    /// `render_tile` with radiance output: samples `sample_index ..
    /// sample_index + sample_count` of each pixel, added to its sums.
    pub sample_count: u32,
    /// Samples per pixel of the whole frame (`[render] samples`): the host's
    /// count of path samples to trace; the kernel reads `sample_count`.
    pub samples: u32,
    /// `[environment] image` in the `textures` buffer: its first word (the
    /// texels, then the sampling tables; `SceneArrays::environment`), its
    /// size in texels (width 0: no image, the sky is `background`), its
    /// intensity and the cosine and sine of its rotation about +y.
    pub env_offset: u32,
    pub env_width: u32,
    pub env_height: u32,
    pub env_intensity: f32,
    pub env_rotation_cos: f32,
    pub env_rotation_sin: f32,
    pub _pad0: u32,
}

/// The head of `render_tile`'s output buffer: rays traced by the dispatch.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct RayCounters {
    pub primary: u32,
    pub shadow: u32,
    pub reflection: u32,
    /// Invocations whose loops, all together, ran 32,768 iterations or more
    /// (half of llvmpipe's 65,535 per 8-wide SIMD group, which also counts
    /// its neighbours' divergent iterations):
    /// llvmpipe (lavapipe) silently cuts an invocation's loops off at 65,535.
    pub loop_limited: u32,
    /// Path samples whose radiance was not finite (NaN or infinite):
    /// dropped, so that no such value reaches a pixel.
    pub nonfinite: u32,
}

/// A ray for the kernel's `trace_rays` entry point (tests, debugging).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct GpuQueryRay {
    pub origin: [f32; 3],
    /// Nearest hit: t <= t_limit; any hit: t < t_limit.
    pub t_limit: f32,
    /// Unit length.
    pub dir: [f32; 3],
    /// 1: any-hit (shadow-ray) query; 0: nearest hit.
    pub any_hit: u32,
}

/// `trace_rays`' answer for one ray.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct GpuQueryHit {
    pub t: f32,
    /// GPU object id, or `gpu::bindings::NO_OBJECT`.
    pub object: u32,
}

/// The window's present pass parameters (a uniform of shaders/present.wgsl).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct PresentParams {
    /// Size of the image in the accumulation buffer.
    pub image_size: [u32; 2],
    /// Size of the render target.
    pub target_size: [u32; 2],
    /// Size of the preview (0 x 0: none).
    pub preview_size: [u32; 2],
    /// 0: show the preview only.
    pub show_image: u32,
    /// How a pixel's mean becomes the shown level: [`PRESENT_QUANTISE`]
    /// (Whitted colours and the heatmap, clamped), or [`PRESENT_ACES`] /
    /// [`PRESENT_CLAMP_SRGB`] (path radiance, as `ToneMap::to_srgb8`).
    pub tone_map: u32,
    /// 2^exposure, the factor applied to path radiance before its curve.
    pub exposure_scale: f32,
    pub _pad: u32,
}

impl PresentParams {
    /// The `tone_map` and `exposure_scale` that show frames of `render`
    /// traced with `integrator` as its PNG would be written.
    pub fn tone_of(
        integrator: crate::scene::Integrator,
        render: &crate::scene::RenderSettings,
    ) -> (u32, f32) {
        use crate::scene::{Integrator, ToneMap};
        match (integrator, render.tone_map) {
            (Integrator::Whitted, _) => (PRESENT_QUANTISE, 1.0),
            (Integrator::Path, ToneMap::Aces) => (PRESENT_ACES, render.exposure.exp2() as f32),
            (Integrator::Path, ToneMap::Clamp) => {
                (PRESENT_CLAMP_SRGB, render.exposure.exp2() as f32)
            }
        }
    }
}
