//! Progressive accumulation on the GPU (the trace kernel's `accumulate_tile`
//! entry point), as the interactive window uses it: two accumulation
//! buffers, the image refined while the camera is still and the
//! reduced-resolution preview traced while it moves, each with its pixels'
//! walk costs, and the pass that adds one sample per pixel to one of them.
//! Showing them is the window's present pass (window/view.rs).

use super::bindings::{self, ACCUMULATE_TILE};
use super::trace_pipelines::TraceBindGroup;
use super::{GpuContext, KernelVariant, SceneBuffers, TracePipelines};
use crate::error::Result;
use crate::gpu::FrameParams;

/// Bytes per pixel of the accumulation buffers (a `vec4<f32>`: the sum of the
/// samples, clamped Whitted colours or path radiance, and their count).
pub const ACCUMULATION_TEXEL: u64 = 16;
/// Bytes per pixel of the cost buffers (`bindings::PIXEL_COSTS`).
pub const COST_TEXEL: u64 = bindings::COST_WORDS as u64 * 4;

/// The two accumulation buffers: the image refined while the camera is
/// still, and the reduced-resolution preview traced while it moves (which
/// the present pass shows where the image has no sample yet).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Target {
    Image,
    Preview,
}

/// One accumulation buffer, its costs, and the bind group that traces into
/// them.
struct TargetBuffers {
    colours: wgpu::Buffer,
    /// Each pixel's walk cost, summed over passes like the colour.
    costs: wgpu::Buffer,
    group: TraceBindGroup,
}

/// The accumulation pass and its buffers.
pub struct Accumulation {
    /// `accumulate_tile`, one pipeline per kernel variant.
    pipelines: std::sync::Arc<TracePipelines>,
    /// The kernel variant of the scene traced, its walk left to each pass.
    scene_variant: KernelVariant,
    params: wgpu::Buffer,
    image: TargetBuffers,
    preview: TargetBuffers,
    /// Pixels each buffer holds.
    capacity: u64,
}

/// A storage buffer of `bytes` that passes clear, copy into and read back.
fn storage_buffer(device: &wgpu::Device, label: &str, bytes: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: bytes,
        usage: wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_DST
            | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    })
}

impl Accumulation {
    /// The pass and buffers for images of up to `pixels` pixels of `scene`.
    pub fn new(ctx: &GpuContext, scene: &SceneBuffers, pixels: u64) -> Result<Self> {
        let pipelines = ctx.trace_pipelines(ACCUMULATE_TILE)?;
        let params = FrameParams::uniform_buffer(ctx, "window frame params")?;
        let pixels = pixels.max(1);
        let [image, preview] = ctx.checked("allocating the accumulation buffers", |device| {
            Self::targets(device, &pipelines, &params, scene, pixels)
        })?;
        Ok(Accumulation {
            scene_variant: KernelVariant::for_scene(scene),
            pipelines,
            params,
            image,
            preview,
            capacity: pixels,
        })
    }

    /// The image's and the preview's buffers for `pixels` pixels, bound
    /// with `scene`.
    fn targets(
        device: &wgpu::Device,
        pipelines: &TracePipelines,
        params: &wgpu::Buffer,
        scene: &SceneBuffers,
        pixels: u64,
    ) -> [TargetBuffers; 2] {
        ["accumulation", "preview"].map(|label| {
            let colours = storage_buffer(device, label, pixels * ACCUMULATION_TEXEL);
            let costs = storage_buffer(device, &format!("{label} costs"), pixels * COST_TEXEL);
            let group = pipelines.bind_group(device, params, scene, &[&colours, &costs]);
            TargetBuffers {
                colours,
                costs,
                group,
            }
        })
    }

    /// Traces `scene` from now on (the buffers are kept).
    pub fn set_scene(&mut self, ctx: &GpuContext, scene: &SceneBuffers) -> Result<()> {
        self.scene_variant = KernelVariant::for_scene(scene);
        let groups = ctx.checked("binding the scene", |device| {
            [&self.image, &self.preview].map(|t| {
                self.pipelines
                    .bind_group(device, &self.params, scene, &[&t.colours, &t.costs])
            })
        })?;
        let [image, preview] = groups;
        self.image.group = image;
        self.preview.group = preview;
        Ok(())
    }

    /// Makes room for images of `pixels` pixels of `scene`; whether the
    /// buffers were made anew (their contents lost, the old ones gone).
    pub fn reserve(&mut self, ctx: &GpuContext, scene: &SceneBuffers, pixels: u64) -> Result<bool> {
        if pixels <= self.capacity {
            return Ok(false);
        }
        let [image, preview] = ctx.checked("allocating the accumulation buffers", |device| {
            Self::targets(device, &self.pipelines, &self.params, scene, pixels)
        })?;
        (self.image, self.preview, self.capacity) = (image, preview, pixels);
        Ok(true)
    }

    /// Largest image an accumulation buffer may hold on this device.
    pub fn max_pixels(ctx: &GpuContext) -> u64 {
        // The accumulation texel is the largest of the buffers' texels.
        super::max_binding_bytes(&ctx.device.limits()) / ACCUMULATION_TEXEL
    }

    /// Pixels each buffer holds.
    pub fn capacity(&self) -> u64 {
        self.capacity
    }

    fn target(&self, target: Target) -> &TargetBuffers {
        match target {
            Target::Image => &self.image,
            Target::Preview => &self.preview,
        }
    }

    /// `target`'s accumulated colours (the present pass reads them).
    pub fn colours(&self, target: Target) -> &wgpu::Buffer {
        &self.target(target).colours
    }

    /// Records into `encoder`: zeroing the first `clear_pixels` pixels of
    /// `target` (colours and costs), then one pass of `pass` into it. The
    /// uniforms are written now; submit before the next call. The pass's
    /// pipeline is the scene's variant with the pass's walk, made the first
    /// time it is needed (a new scene, or a walk chosen by key).
    pub fn encode(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        target: Target,
        clear_pixels: Option<u64>,
        pass: Option<&FrameParams>,
    ) -> Result<()> {
        let t = self.target(target);
        if let Some(pixels) = clear_pixels {
            let pixels = pixels.clamp(1, self.capacity);
            encoder.clear_buffer(&t.colours, 0, Some(pixels * ACCUMULATION_TEXEL));
            encoder.clear_buffer(&t.costs, 0, Some(pixels * COST_TEXEL));
        }
        if let Some(params) = pass {
            let variant = KernelVariant {
                integrator: params.integrator,
                ..self.scene_variant.with_walk_of(params)
            };
            self.pipelines.encode_tile(
                ctx,
                encoder,
                "accumulate",
                variant,
                &t.group,
                (&self.params, params),
            )?;
        }
        Ok(())
    }

    /// The first `pixels` pixels of `target` read back: their colours (a
    /// `vec4<f32>` each) and their costs ([`bindings::COST_WORDS`] words each).
    pub fn read_back(
        &self,
        ctx: &GpuContext,
        target: Target,
        pixels: u64,
    ) -> Result<(Vec<[f32; 4]>, Vec<u32>)> {
        let t = self.target(target);
        let (colour_bytes, cost_bytes) = (pixels * ACCUMULATION_TEXEL, pixels * COST_TEXEL);
        let readback = ctx.checked("reading back the accumulation", |device| {
            let readback = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("accumulation readback"),
                size: colour_bytes + cost_bytes,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            let mut encoder = device.create_command_encoder(&Default::default());
            encoder.copy_buffer_to_buffer(&t.colours, 0, &readback, 0, colour_bytes);
            encoder.copy_buffer_to_buffer(&t.costs, 0, &readback, colour_bytes, cost_bytes);
            ctx.queue.submit([encoder.finish()]);
            readback
        })?;
        let bytes = ctx.read_buffer(&readback, colour_bytes + cost_bytes)?;
        let (colours, costs) = bytes.split_at(colour_bytes as usize);
        Ok((
            bytemuck::cast_slice(colours).to_vec(),
            bytemuck::cast_slice(costs).to_vec(),
        ))
    }

    /// The kernel variant of the scene traced.
    #[cfg(test)]
    pub(crate) fn scene_variant(&self) -> KernelVariant {
        self.scene_variant
    }

    /// The variants made so far.
    #[cfg(test)]
    pub(crate) fn variants(&self) -> Vec<KernelVariant> {
        self.pipelines.variants()
    }
}
