//! The trace pipeline and its tiled dispatch: each tile is one dispatch of
//! one invocation per pixel, copied back and packed into an 8-bit RGB image.

use std::time::Instant;

use super::bindings;
use super::context::GpuContext;
use super::scene_buffers::SceneBuffers;
use super::{KernelVariant, TracePipelines};
use crate::error::{Error, Result};
use crate::kdtree::traverse::WalkCost;
use crate::gpu::{FrameParams, RayCounters};

/// How the image is cut into dispatches: bands of whole rows, each band one
/// or more tiles of at most `tile_width` x `max_rows` pixels. Band heights
/// adapt so that one dispatch takes about `target_dispatch_ms` (real GPUs
/// reset dispatches that run for seconds); buffers never exceed the
/// adapter's storage binding size. `rows` (all by default) limits the
/// render to rows `rows.0..rows.1` of the image, whose pixels are those of
/// the whole image's render (a farm task's band).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TilePlan {
    pub tile_width: u32,
    pub max_rows: u32,
    pub target_dispatch_ms: f64,
    pub rows: (u32, u32),
}

impl TilePlan {
    /// Default bound on one dispatch's pixels (about one megapixel).
    pub const DEFAULT_MAX_TILE_PIXELS: u64 = 1 << 20;
    /// Default time one dispatch should take.
    pub const DEFAULT_TARGET_DISPATCH_MS: f64 = 250.0;
    /// Pixels in the first band, which measures the adapter's speed.
    const FIRST_BAND_PIXELS: u64 = 1 << 16;

    pub fn new(width: u32, height: u32, max_tile_pixels: u64, max_binding_bytes: u64) -> Self {
        // The output buffer holds the ray counters, then 4 bytes per pixel;
        // the cost buffer (when asked for) 12 bytes per pixel.
        let max_pixels = max_tile_pixels
            .min(max_binding_bytes.saturating_sub(64) / COST_BYTES_PER_PIXEL)
            .max(1);
        let tile_width = width.min(max_pixels as u32).max(1);
        let max_rows = (max_pixels / tile_width as u64).clamp(1, height.max(1) as u64) as u32;
        TilePlan {
            tile_width,
            max_rows,
            target_dispatch_ms: Self::DEFAULT_TARGET_DISPATCH_MS,
            rows: (0, u32::MAX),
        }
    }

    /// This plan for rows `first..end` of the image only.
    pub fn with_rows(self, first: u32, end: u32) -> Self {
        TilePlan {
            rows: (first, end),
            ..self
        }
    }

    /// Rows of the first band: small, to measure before committing to more.
    fn first_band_rows(&self, width: u32) -> u32 {
        ((Self::FIRST_BAND_PIXELS / width.max(1) as u64) as u32).clamp(1, self.max_rows)
    }

    /// Rows of the next band, given how long the last one took per row.
    #[allow(clippy::neg_cmp_op_on_partial_ord)] // NaN counts as not positive
    fn next_band_rows(&self, ms_per_row: f64) -> u32 {
        if !(ms_per_row > 0.0) {
            return self.max_rows;
        }
        ((self.target_dispatch_ms / ms_per_row) as u64).clamp(1, self.max_rows as u64) as u32
    }
}

/// Rows `y..y + rows` of the image, 8-bit RGB, as they come off the GPU.
pub struct RowBand<'a> {
    pub y: u32,
    pub rows: u32,
    pub rgb: &'a [u8],
    /// Each pixel's walk cost over all its rays, row-major, when the render
    /// was asked for it ([`Renderer::render_bands_with_cost`]).
    pub costs: Option<&'a [WalkCost]>,
}

/// Bytes per pixel of the cost output (`bindings::PIXEL_COSTS`).
const COST_BYTES_PER_PIXEL: u64 = bindings::COST_WORDS as u64 * 4;

/// The walk's work over the whole image (every ray of every pixel), summed
/// from the per-pixel costs.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize)]
pub struct CostTotals {
    pub nodes_visited: u64,
    pub leaves_visited: u64,
    pub objects_tested: u64,
}

impl CostTotals {
    pub fn add(&mut self, c: &WalkCost) {
        self.nodes_visited += c.nodes_visited as u64;
        self.leaves_visited += c.leaves_visited as u64;
        self.objects_tested += c.objects_tested as u64;
    }
}

/// Rays the shader traced, by kind, summed over tiles.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize)]
pub struct RayTotals {
    /// One per sample: width * height * samples.
    pub primary: u64,
    /// One per light tested from a hit (L.N > 0), shadow mode permitting.
    pub shadow: u64,
    /// Mirror continuations after the primary hit.
    pub reflection: u64,
    /// Invocations whose loops came near llvmpipe's limit of 65,535
    /// iterations per invocation (see `GpuContext::has_loop_limit`).
    pub loop_limited: u64,
}

/// Where `gpu_ms` comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum GpuTimeSource {
    /// GPU timestamp queries around each tile's compute pass.
    Timestamp,
    /// Wall time from submit to readback (adapters without timestamps).
    Wall,
}

impl GpuTimeSource {
    pub fn name(self) -> &'static str {
        match self {
            GpuTimeSource::Timestamp => "timestamp",
            GpuTimeSource::Wall => "wall",
        }
    }
}

/// What a render measured besides its pixels.
#[derive(Debug, Clone, Copy)]
pub struct RenderSummary {
    /// Sum over tiles of GPU time (timestamp queries) or of submit-to-done wall time.
    pub gpu_ms: f64,
    pub gpu_time_source: GpuTimeSource,
    pub rays: RayTotals,
    /// The walk's work, when the render was asked for per-pixel costs.
    pub cost: Option<CostTotals>,
}

impl RayTotals {
    fn add(&mut self, c: &RayCounters) {
        self.primary += c.primary as u64;
        self.shadow += c.shadow as u64;
        self.reflection += c.reflection as u64;
        self.loop_limited += c.loop_limited as u64;
    }

    /// Primary, shadow and reflection rays together.
    pub fn total(&self) -> u64 {
        self.primary + self.shadow + self.reflection
    }
}

/// Bytes before the pixels in the output buffer (the ray counters).
const OUTPUT_HEADER_BYTES: u64 = std::mem::size_of::<RayCounters>() as u64;

/// A rendered image and how long the GPU took.
pub struct RenderedImage {
    pub width: u32,
    pub height: u32,
    /// 8-bit RGB, row-major, top row first.
    pub rgb: Vec<u8>,
    /// Sum over tiles of GPU time (timestamp queries) or of submit-to-done wall time.
    pub gpu_ms: f64,
    pub gpu_time_source: GpuTimeSource,
    pub rays: RayTotals,
}

pub struct Renderer {
    /// `render_tile`, one pipeline per kernel variant.
    pipelines: TracePipelines,
    /// Every frame with the general variant (tests).
    general: bool,
    params_buffer: wgpu::Buffer,
}

impl Renderer {
    /// Each frame runs a pipeline specialised for its scene and walk.
    pub fn new(ctx: &GpuContext) -> Result<Self> {
        let pipelines = TracePipelines::new(ctx, bindings::RENDER_TILE)?;
        let params_buffer = FrameParams::uniform_buffer(ctx, "frame params")?;
        Ok(Renderer {
            pipelines,
            general: false,
            params_buffer,
        })
    }

    /// A renderer whose every frame runs the general variant, which reads
    /// the walk and the scene's kinds from the frame's uniforms: for tests
    /// that hold the specialised pipelines to it.
    pub fn general(ctx: &GpuContext) -> Result<Self> {
        Ok(Renderer {
            general: true,
            ..Self::new(ctx)?
        })
    }

    /// The variant a frame of `scene` with `params` runs; `with_cost`: one
    /// that counts the walks' work.
    pub fn variant_for(
        &self,
        scene: &SceneBuffers,
        params: &FrameParams,
        with_cost: bool,
    ) -> KernelVariant {
        match self.general {
            true => KernelVariant::GENERAL,
            false => KernelVariant::for_frame(scene, params, with_cost),
        }
    }

    /// Makes the pipeline that frames of `scene` with `params` run (counting
    /// their work if `with_cost`) and has the driver compile it, by tracing
    /// one workgroup's pixels: llvmpipe compiles a pipeline at its first
    /// dispatch (about 0.35 s, docs/design.md), which would otherwise fall
    /// into the next frame's GPU time. For timings.
    pub fn compile(
        &self,
        ctx: &GpuContext,
        scene: &SceneBuffers,
        params: FrameParams,
        with_cost: bool,
    ) -> Result<()> {
        let (w, h) = bindings::TRACE_WORKGROUP;
        let params = FrameParams {
            width: w.min(params.width),
            height: h.min(params.height),
            ..params
        };
        let plan = TilePlan::new(params.width, params.height, u64::MAX, u64::MAX);
        self.render_bands_with_cost(ctx, scene, params, plan, with_cost, &mut |_| Ok(()))?;
        Ok(())
    }

    /// Renders the whole image, tile by tile, and reads it back.
    pub fn render(
        &self,
        ctx: &GpuContext,
        scene: &SceneBuffers,
        params: FrameParams,
        plan: TilePlan,
    ) -> Result<RenderedImage> {
        let mut rgb = Vec::with_capacity(params.width as usize * params.height as usize * 3);
        let summary = self.render_bands(ctx, scene, params, plan, &mut |band| {
            rgb.extend_from_slice(band.rgb);
            Ok(())
        })?;
        Ok(RenderedImage {
            width: params.width,
            height: params.height,
            rgb,
            gpu_ms: summary.gpu_ms,
            gpu_time_source: summary.gpu_time_source,
            rays: summary.rays,
        })
    }

    /// Renders band after band of whole rows, top to bottom, handing each to
    /// `sink` as soon as it is read back: host memory holds one band, never
    /// the image.
    pub fn render_bands(
        &self,
        ctx: &GpuContext,
        scene: &SceneBuffers,
        params: FrameParams,
        plan: TilePlan,
        sink: &mut dyn FnMut(RowBand<'_>) -> Result<()>,
    ) -> Result<RenderSummary> {
        self.render_bands_with_cost(ctx, scene, params, plan, false, sink)
    }

    /// [`Renderer::render_bands`]; with `with_cost`, each band also carries
    /// every pixel's walk cost (`RowBand::costs`) and the summary their
    /// totals. Without, the kernel's cost buffer is one word, which it
    /// leaves alone, and nothing more is read back.
    pub fn render_bands_with_cost(
        &self,
        ctx: &GpuContext,
        scene: &SceneBuffers,
        params: FrameParams,
        plan: TilePlan,
        with_cost: bool,
        sink: &mut dyn FnMut(RowBand<'_>) -> Result<()>,
    ) -> Result<RenderSummary> {
        let (width, height) = (params.width, params.height);
        let device = &ctx.device;
        let pipeline = self
            .pipelines
            .get(ctx, self.variant_for(scene, &params, with_cost))?;
        let tile_pixels = plan.tile_width as u64 * plan.max_rows as u64;
        let tile_bytes = OUTPUT_HEADER_BYTES + tile_pixels * 4;
        let cost_bytes = match with_cost {
            true => tile_pixels * COST_BYTES_PER_PIXEL,
            false => 4,
        };
        let output_what = format!(
            "allocating the output buffers (2 x {})",
            super::scene_buffers::human_bytes(tile_bytes + cost_bytes)
        );
        let (output, costs, readback, bind_group) = ctx.checked(&output_what, |device| {
            let output = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("output pixels"),
                size: tile_bytes,
                usage: wgpu::BufferUsages::STORAGE
                    | wgpu::BufferUsages::COPY_SRC
                    | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            let costs = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("pixel costs"),
                size: cost_bytes,
                usage: wgpu::BufferUsages::STORAGE
                    | wgpu::BufferUsages::COPY_SRC
                    | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            // The tile's output, then (with_cost) its costs.
            let readback = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("readback"),
                size: tile_bytes + if with_cost { cost_bytes } else { 0 },
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            // RENDER_OUTPUTS: the tile's output, then its costs.
            let bind_group =
                self.pipelines
                    .bind_group(device, &self.params_buffer, scene, &[&output, &costs]);
            (output, costs, readback, bind_group)
        })?;
        let bind_group = bind_group.for_pipeline(ctx, &pipeline)?;
        let timer = match ctx.has_timestamps {
            true => Some(ctx.checked("creating the GPU timer", GpuTimer::new)?),
            false => None,
        };

        let mut band_rgb = Vec::with_capacity(width as usize * plan.max_rows as usize * 3);
        let mut band_costs: Vec<WalkCost> = Vec::new();
        let mut summary = RenderSummary {
            gpu_ms: 0.0,
            gpu_time_source: match timer {
                Some(_) => GpuTimeSource::Timestamp,
                None => GpuTimeSource::Wall,
            },
            rays: RayTotals::default(),
            cost: with_cost.then(CostTotals::default),
        };
        let (mut y, end) = (plan.rows.0, plan.rows.1.min(height));
        let mut rows = plan.first_band_rows(width);
        while y < end {
            let h = rows.min(end - y);
            band_rgb.clear();
            band_rgb.resize(width as usize * h as usize * 3, 0);
            if with_cost {
                band_costs.clear();
                band_costs.resize(width as usize * h as usize, WalkCost::default());
            }
            let mut band_ms = 0.0;
            let mut x = 0;
            while x < width {
                let w = plan.tile_width.min(width - x);
                let tile_params = FrameParams {
                    tile_origin: [x, y],
                    tile_size: [w, h],
                    ..params
                };
                ctx.queue
                    .write_buffer(&self.params_buffer, 0, bytemuck::bytes_of(&tile_params));
                let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                    label: Some("tile"),
                });
                encoder.clear_buffer(&output, 0, Some(OUTPUT_HEADER_BYTES));
                let used_costs = w as u64 * h as u64 * COST_BYTES_PER_PIXEL;
                if with_cost {
                    encoder.clear_buffer(&costs, 0, Some(used_costs));
                }
                {
                    let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                        label: Some("trace tile"),
                        timestamp_writes: timer.as_ref().map(|t| t.writes()),
                    });
                    pass.set_pipeline(&pipeline.pipeline);
                    pass.set_bind_group(0, &bind_group, &[]);
                    let (gx, gy) = self.pipelines.workgroups(w, h);
                    pass.dispatch_workgroups(gx, gy, 1);
                }
                let used = OUTPUT_HEADER_BYTES + w as u64 * h as u64 * 4;
                encoder.copy_buffer_to_buffer(&output, 0, &readback, 0, used);
                if with_cost {
                    encoder.copy_buffer_to_buffer(&costs, 0, &readback, used, used_costs);
                }
                if let Some(t) = &timer {
                    t.resolve(&mut encoder);
                }
                let started = Instant::now();
                ctx.queue.submit([encoder.finish()]);
                let read = used + if with_cost { used_costs } else { 0 };
                let bytes = ctx.read_buffer(&readback, read)?;
                let (bytes, cost_bytes) = bytes.split_at(used as usize);
                let wall_ms = started.elapsed().as_secs_f64() * 1e3;
                let tile_ms = match &timer {
                    Some(t) => t.read_ms(ctx)?,
                    None => wall_ms,
                };
                band_ms += tile_ms;
                let (header, pixels) = bytes.split_at(OUTPUT_HEADER_BYTES as usize);
                summary
                    .rays
                    .add(&bytemuck::pod_read_unaligned::<RayCounters>(header));
                let pixels: &[u32] = bytemuck::cast_slice(pixels);
                for row in 0..h as usize {
                    let start = (row * width as usize + x as usize) * 3;
                    let dst = &mut band_rgb[start..start + w as usize * 3];
                    for (d, p) in dst
                        .chunks_exact_mut(3)
                        .zip(&pixels[row * w as usize..(row + 1) * w as usize])
                    {
                        d.copy_from_slice(&p.to_le_bytes()[..3]);
                    }
                }
                if let Some(totals) = &mut summary.cost {
                    let words: &[u32] = bytemuck::cast_slice(cost_bytes);
                    let mut tile = words.chunks_exact(bindings::COST_WORDS);
                    for row in 0..h as usize {
                        let start = row * width as usize + x as usize;
                        for (d, c) in band_costs[start..start + w as usize]
                            .iter_mut()
                            .zip(&mut tile)
                        {
                            *d = WalkCost::from_words(c);
                            totals.add(d);
                        }
                    }
                }
                x += w;
            }
            summary.gpu_ms += band_ms;
            sink(RowBand {
                y,
                rows: h,
                rgb: &band_rgb,
                costs: with_cost.then_some(&band_costs[..]),
            })?;
            y += h;
            // Tiles of a band run one after another: size the next band so
            // that each of its dispatches takes about the target time.
            let tiles_per_band = width.div_ceil(plan.tile_width) as f64;
            rows = plan.next_band_rows(band_ms / tiles_per_band / h as f64);
        }
        ctx.check_health()?;
        Ok(summary)
    }
}

/// Two timestamps around each tile's compute pass.
struct GpuTimer {
    queries: wgpu::QuerySet,
    resolved: wgpu::Buffer,
    readback: wgpu::Buffer,
}

impl GpuTimer {
    fn new(device: &wgpu::Device) -> Self {
        GpuTimer {
            queries: device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("tile time"),
                ty: wgpu::QueryType::Timestamp,
                count: 2,
            }),
            resolved: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("timestamps"),
                size: 16,
                usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            }),
            readback: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("timestamps readback"),
                size: 16,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
        }
    }

    fn writes(&self) -> wgpu::ComputePassTimestampWrites<'_> {
        wgpu::ComputePassTimestampWrites {
            query_set: &self.queries,
            beginning_of_pass_write_index: Some(0),
            end_of_pass_write_index: Some(1),
        }
    }

    fn resolve(&self, encoder: &mut wgpu::CommandEncoder) {
        encoder.resolve_query_set(&self.queries, 0..2, &self.resolved, 0);
        encoder.copy_buffer_to_buffer(&self.resolved, 0, &self.readback, 0, 16);
    }

    fn read_ms(&self, ctx: &GpuContext) -> Result<f64> {
        let bytes = ctx.read_buffer(&self.readback, 16)?;
        let ticks: &[u64] = bytemuck::cast_slice(&bytes);
        let ns = ticks[1].saturating_sub(ticks[0]) as f64 * ctx.queue.get_timestamp_period() as f64;
        Ok(ns * 1e-6)
    }
}

impl GpuContext {
    /// Maps `buffer` (after the last submission), copies out `size` bytes, unmaps.
    pub(crate) fn read_buffer(&self, buffer: &wgpu::Buffer, size: u64) -> Result<Vec<u8>> {
        let slice = buffer.slice(..size);
        let (sender, receiver) = std::sync::mpsc::channel();
        slice.map_async(wgpu::MapMode::Read, move |r| {
            let _ = sender.send(r);
        });
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| Error::Gpu(format!("waiting for the GPU failed: {e}")))?;
        self.check_health()?;
        match receiver.recv() {
            Ok(Ok(())) => {}
            Ok(Err(e)) => return Err(Error::Gpu(format!("reading back from the GPU failed: {e}"))),
            Err(_) => return Err(Error::Gpu("the GPU never finished the readback".into())),
        }
        let bytes = slice
            .get_mapped_range()
            .map_err(|e| Error::Gpu(format!("reading back from the GPU failed: {e}")))?
            .to_vec();
        buffer.unmap();
        Ok(bytes)
    }
}
