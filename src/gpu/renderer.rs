//! The trace pipeline and its tiled dispatch: each tile is one dispatch of
//! one invocation per pixel, copied back and packed into an 8-bit RGB image.

use std::time::Instant;

use super::bindings;
use super::context::GpuContext;
use super::gpu_timer::GpuTimer;
use super::scene_buffers::SceneBuffers;
use super::tile_plan::{PixelOutput, TilePlan};
use super::{KernelVariant, TracePipelines};
use crate::error::Result;
use crate::gpu::{FrameParams, RayCounters};
use crate::kdtree::traverse::WalkCost;
use crate::layout::INTEGRATOR_PATH;
use crate::scene::{RenderSettings, ToneMap};

/// Rows `y..y + rows` of the image, 8-bit RGB, as they come off the GPU.
pub struct RowBand<'a> {
    pub y: u32,
    pub rows: u32,
    pub rgb: &'a [u8],
    /// Each pixel's walk cost over all its rays, row-major, when the render
    /// was asked for it ([`Renderer::render_bands_with_cost`]).
    pub costs: Option<&'a [WalkCost]>,
    /// Each pixel's mean linear radiance (r, g, b), row-major: path frames,
    /// and frames of a renderer made [`Renderer::with_radiance`].
    pub radiance: Option<&'a [f32]>,
    /// The denoiser's feature images, as `radiance`: each pixel's mean
    /// albedo and mean shading normal (world space) over its samples, for
    /// path frames of a renderer made [`Renderer::with_features`].
    pub features: Option<Features<'a>>,
}

/// A band's feature images (shaders/path.wgsl, "Features"): three floats a
/// pixel each, row-major.
#[derive(Clone, Copy)]
pub struct Features<'a> {
    pub albedo: &'a [f32],
    pub normal: &'a [f32],
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
    /// Path samples dropped because their radiance was not finite.
    pub nonfinite: u64,
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
        self.nonfinite += c.nonfinite as u64;
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
    pipelines: std::sync::Arc<TracePipelines>,
    /// Every frame with the general variant (tests).
    general: bool,
    params_buffer: wgpu::Buffer,
    /// Whether Whitted frames also come back as radiance (EXR output).
    radiance: bool,
    /// Whether path frames also come back with their feature images.
    features: bool,
    /// How a path frame's radiance becomes its 8-bit colour: the curve and
    /// the scale 2^exposure.
    tone_map: (ToneMap, f32),
    /// Radiance frames trace only samples `first .. first + count` of each
    /// pixel (`None`: all of them); see [`Renderer::with_sample_range`].
    sample_range: Option<(u32, u32)>,
}

impl Renderer {
    /// Each frame runs a pipeline specialised for its scene and walk.
    pub fn new(ctx: &GpuContext) -> Result<Self> {
        let pipelines = ctx.trace_pipelines(bindings::RENDER_TILE)?;
        let params_buffer = FrameParams::uniform_buffer(ctx, "frame params")?;
        Ok(Renderer {
            pipelines,
            general: false,
            params_buffer,
            radiance: false,
            features: false,
            tone_map: (ToneMap::default(), 1.0),
            sample_range: None,
        })
    }

    /// This renderer with `render`'s tone map for path frames (the default
    /// curve at exposure 0 unless set).
    pub fn with_settings(self, render: &RenderSettings) -> Self {
        Renderer {
            tone_map: (render.tone_map, render.exposure.exp2() as f32),
            ..self
        }
    }

    /// This renderer with every frame's radiance read back
    /// (`RowBand::radiance`), Whitted frames' too (each sample unclamped).
    pub fn with_radiance(self) -> Self {
        Renderer {
            radiance: true,
            ..self
        }
    }

    /// This renderer with path frames' feature images read back
    /// (`RowBand::features`): each pixel's mean albedo and normal, for the
    /// denoiser. Its pipelines are the feature variant (`FEATURE_OUTPUT`);
    /// the radiance is the plain variant's.
    pub fn with_features(self) -> Self {
        Renderer {
            features: true,
            ..self
        }
    }

    /// This renderer with radiance frames (path frames, and every frame
    /// after [`Renderer::with_radiance`]) tracing only samples `first ..
    /// first + count` of each pixel, with the random numbers the whole
    /// frame gives those sample indices: `RowBand::radiance` is their mean
    /// and `RowBand::rgb` its tone-mapped colour. A farm splits a still's
    /// samples this way; the means of the shares, weighted by their
    /// counts, are the whole frame's mean within float rounding. Frames
    /// without radiance output ignore it.
    pub fn with_sample_range(self, first: u32, count: u32) -> Self {
        Renderer {
            sample_range: Some((first, count)),
            ..self
        }
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
    /// dispatch (seconds: gpu/trace_pipelines.rs), which would otherwise fall
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
    /// leaves alone, and nothing more is read back. Path frames (and every
    /// frame of a renderer made [`Renderer::with_radiance`]) also carry
    /// each pixel's mean radiance (`RowBand::radiance`).
    pub fn render_bands_with_cost(
        &self,
        ctx: &GpuContext,
        scene: &SceneBuffers,
        params: FrameParams,
        plan: TilePlan,
        with_cost: bool,
        sink: &mut dyn FnMut(RowBand<'_>) -> Result<()>,
    ) -> Result<RenderSummary> {
        let width = params.width;
        let path = params.integrator == INTEGRATOR_PATH;
        let variant = KernelVariant {
            radiance_output: self.radiance || path,
            feature_output: self.features && path,
            ..self.variant_for(scene, &params, with_cost)
        };
        let output = match (variant.radiance_output, variant.feature_output) {
            (_, true) => PixelOutput::Features,
            (true, false) => PixelOutput::Radiance,
            (false, false) => PixelOutput::Rgb8,
        };
        let radiance = output.radiance();
        let plan = plan.fitting(
            output.bytes(),
            super::max_binding_bytes(&ctx.device.limits()),
        );
        let pipeline = self.pipelines.get(ctx, variant)?;
        let tile_pixels = plan.tile_width as u64 * plan.max_rows as u64;
        let tile = TileBuffers::new(ctx, self, scene, tile_pixels, with_cost, output)?;
        let bind_group = tile.bind_group.for_pipeline(ctx, &pipeline)?;
        let timer = match ctx.has_timestamps {
            true => Some(ctx.checked("creating the GPU timer", GpuTimer::new)?),
            false => None,
        };

        let mut band = BandBuffers::default();
        let mut summary = RenderSummary {
            gpu_ms: 0.0,
            gpu_time_source: match timer {
                Some(_) => GpuTimeSource::Timestamp,
                None => GpuTimeSource::Wall,
            },
            rays: RayTotals::default(),
            cost: with_cost.then(CostTotals::default),
        };
        let (first_sample, samples) = self.samples_of(&params, radiance);
        let (mut y, end) = (plan.rows.0, plan.rows.1.min(params.height));
        let mut rows = plan.first_band_rows(width);
        while y < end {
            let h = rows.min(end - y);
            band.reset(width, h, with_cost, output);
            let mut band_ms = 0.0;
            let mut x = 0;
            while x < width {
                let w = plan.tile_width.min(width - x);
                let area = TileArea { x, y, w, h };
                let run = TileRun {
                    pipeline: &pipeline.pipeline,
                    bind_group: &bind_group,
                    timer: timer.as_ref(),
                    tile: &tile,
                    params,
                    with_cost,
                    output,
                };
                let (ms, bytes) = self.trace_tile(ctx, &run, area, first_sample, samples)?;
                band_ms += ms;
                band.take_tile(
                    &bytes,
                    area,
                    width,
                    output,
                    samples.max(1) as f32,
                    self.tone_map,
                );
                summary.rays.add(&band.counters);
                if let Some(totals) = &mut summary.cost {
                    band.take_costs(&bytes, area, width, output, totals);
                }
                x += w;
            }
            summary.gpu_ms += band_ms;
            sink(RowBand {
                y,
                rows: h,
                rgb: &band.rgb,
                costs: with_cost.then_some(&band.costs[..]),
                radiance: radiance.then_some(&band.radiance[..]),
                features: (output == PixelOutput::Features).then_some(Features {
                    albedo: &band.albedo,
                    normal: &band.normal,
                }),
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

    /// Traces `area` of the frame: its buffers cleared, its `samples`
    /// samples from sample index `first_sample` on in dispatches of at most
    /// [`SAMPLES_PER_DISPATCH`] (short enough for a
    /// GPU's watchdog and llvmpipe's loop limit; the kernel adds them in
    /// order, so the sums do not depend on the split), the last one copied
    /// back. Returns the GPU time of its dispatches (timestamps, else wall
    /// time) and the read-back bytes.
    fn trace_tile(
        &self,
        ctx: &GpuContext,
        run: &TileRun<'_>,
        area: TileArea,
        first_sample: u32,
        samples: u32,
    ) -> Result<(f64, Vec<u8>)> {
        // The clear goes with the first dispatch: one submission a tile
        // where one dispatch traces all its samples.
        let mut cleared = device_encoder(ctx);
        run.tile
            .clear(&mut cleared, area, run.with_cost, run.output);
        let mut pending = Some(cleared);
        let mut ms = 0.0;
        let mut first = 0;
        loop {
            let count = samples.saturating_sub(first).min(SAMPLES_PER_DISPATCH);
            let last = first + count >= samples;
            let tile_params = FrameParams {
                tile_origin: [area.x, area.y],
                tile_size: [area.w, area.h],
                sample_index: first_sample + first,
                sample_count: count,
                ..run.params
            };
            ctx.queue
                .write_buffer(&self.params_buffer, 0, bytemuck::bytes_of(&tile_params));
            let mut encoder = pending.take().unwrap_or_else(|| device_encoder(ctx));
            {
                let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some("trace tile"),
                    timestamp_writes: run.timer.map(|t| t.writes()),
                });
                pass.set_pipeline(run.pipeline);
                pass.set_bind_group(0, run.bind_group, &[]);
                let (gx, gy) = self.pipelines.workgroups(area.w, area.h);
                pass.dispatch_workgroups(gx, gy, 1);
            }
            if last {
                run.tile
                    .copy_to_readback(&mut encoder, area, run.with_cost, run.output);
            }
            if let Some(t) = run.timer {
                t.resolve(&mut encoder);
            }
            let started = Instant::now();
            ctx.queue.submit([encoder.finish()]);
            let bytes = match last {
                true => Some(ctx.read_buffer(
                    &run.tile.readback,
                    run.tile.read_bytes(area, run.with_cost, run.output),
                )?),
                false => {
                    ctx.wait_idle()?;
                    None
                }
            };
            let wall_ms = started.elapsed().as_secs_f64() * 1e3;
            ms += match run.timer {
                Some(t) => t.read_ms(ctx)?,
                None => wall_ms,
            };
            if let Some(bytes) = bytes {
                return Ok((ms, bytes));
            }
            first += count;
        }
    }

    /// The first sample index and the samples a pixel of a frame with
    /// `params` takes: the path tracer's count, or the Whitted grid's k x k
    /// (radiance output traces the grid in one pass; 8-bit output ignores
    /// the count), or the renderer's sample range for radiance frames.
    fn samples_of(&self, params: &FrameParams, radiance: bool) -> (u32, u32) {
        if let (true, Some((first, count))) = (radiance, self.sample_range) {
            return (first, count);
        }
        let samples = match (params.integrator == INTEGRATOR_PATH, radiance) {
            (true, _) => params.samples.max(1),
            (false, true) => params.samples_per_axis * params.samples_per_axis,
            (false, false) => 1,
        };
        (0, samples)
    }
}

/// Samples of a pixel one dispatch traces, at most.
pub const SAMPLES_PER_DISPATCH: u32 = 16;

fn device_encoder(ctx: &GpuContext) -> wgpu::CommandEncoder {
    ctx.device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("tile"),
        })
}

/// Pixels `x..x + w` of rows `y..y + h`: one tile.
#[derive(Debug, Clone, Copy)]
struct TileArea {
    x: u32,
    y: u32,
    w: u32,
    h: u32,
}

impl TileArea {
    fn pixels(&self) -> u64 {
        self.w as u64 * self.h as u64
    }
}

/// What every dispatch of a frame's tiles uses.
struct TileRun<'a> {
    pipeline: &'a wgpu::ComputePipeline,
    bind_group: &'a wgpu::BindGroup,
    timer: Option<&'a GpuTimer>,
    tile: &'a TileBuffers,
    params: FrameParams,
    with_cost: bool,
    output: PixelOutput,
}

/// One tile's buffers on the GPU: the kernel's output and costs, the
/// readback they are copied to, and their bind group.
struct TileBuffers {
    output: wgpu::Buffer,
    costs: wgpu::Buffer,
    readback: wgpu::Buffer,
    bind_group: super::TraceBindGroup,
}

impl TileBuffers {
    fn new(
        ctx: &GpuContext,
        renderer: &Renderer,
        scene: &SceneBuffers,
        tile_pixels: u64,
        with_cost: bool,
        output: PixelOutput,
    ) -> Result<Self> {
        let tile_bytes = OUTPUT_HEADER_BYTES + tile_pixels * output.bytes();
        let cost_bytes = match with_cost {
            true => tile_pixels * COST_BYTES_PER_PIXEL,
            false => 4,
        };
        let what = format!(
            "allocating the output buffers (2 x {})",
            super::scene_buffers::human_bytes(tile_bytes + cost_bytes)
        );
        ctx.checked(&what, |device| {
            let storage = |label, size| {
                device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some(label),
                    size,
                    usage: wgpu::BufferUsages::STORAGE
                        | wgpu::BufferUsages::COPY_SRC
                        | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                })
            };
            let output = storage("output pixels", tile_bytes);
            let costs = storage("pixel costs", cost_bytes);
            // The tile's output, then (with_cost) its costs.
            let readback = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("readback"),
                size: tile_bytes + if with_cost { cost_bytes } else { 0 },
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            // RENDER_OUTPUTS: the tile's output, then its costs.
            let bind_group = renderer.pipelines.bind_group(
                device,
                &renderer.params_buffer,
                scene,
                &[&output, &costs],
            );
            TileBuffers {
                output,
                costs,
                readback,
                bind_group,
            }
        })
    }

    fn output_bytes(area: TileArea, output: PixelOutput) -> u64 {
        OUTPUT_HEADER_BYTES + area.pixels() * output.bytes()
    }

    /// Zeroes the counters (and the radiance sums, which the dispatches add
    /// to, and the costs).
    fn clear(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        area: TileArea,
        costs: bool,
        output: PixelOutput,
    ) {
        let cleared = match output.radiance() {
            true => Self::output_bytes(area, output),
            false => OUTPUT_HEADER_BYTES,
        };
        encoder.clear_buffer(&self.output, 0, Some(cleared));
        if costs {
            encoder.clear_buffer(&self.costs, 0, Some(area.pixels() * COST_BYTES_PER_PIXEL));
        }
    }

    fn copy_to_readback(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        area: TileArea,
        costs: bool,
        output: PixelOutput,
    ) {
        let used = Self::output_bytes(area, output);
        encoder.copy_buffer_to_buffer(&self.output, 0, &self.readback, 0, used);
        if costs {
            let cost_bytes = area.pixels() * COST_BYTES_PER_PIXEL;
            encoder.copy_buffer_to_buffer(&self.costs, 0, &self.readback, used, cost_bytes);
        }
    }

    fn read_bytes(&self, area: TileArea, costs: bool, output: PixelOutput) -> u64 {
        Self::output_bytes(area, output)
            + if costs {
                area.pixels() * COST_BYTES_PER_PIXEL
            } else {
                0
            }
    }
}

/// One band's pixels on the host, filled tile by tile.
#[derive(Default)]
struct BandBuffers {
    rgb: Vec<u8>,
    costs: Vec<WalkCost>,
    /// Mean linear RGB per pixel (radiance output).
    radiance: Vec<f32>,
    /// Mean albedo and normal per pixel (feature output).
    albedo: Vec<f32>,
    normal: Vec<f32>,
    /// The last tile's ray counters.
    counters: RayCounters,
}

impl BandBuffers {
    fn reset(&mut self, width: u32, rows: u32, costs: bool, output: PixelOutput) {
        let pixels = width as usize * rows as usize;
        self.rgb.clear();
        self.rgb.resize(pixels * 3, 0);
        self.costs.clear();
        if costs {
            self.costs.resize(pixels, WalkCost::default());
        }
        let floats = |v: &mut Vec<f32>, wanted: bool| {
            v.clear();
            if wanted {
                v.resize(pixels * 3, 0.0);
            }
        };
        floats(&mut self.radiance, output.radiance());
        floats(&mut self.albedo, output == PixelOutput::Features);
        floats(&mut self.normal, output == PixelOutput::Features);
    }

    /// Takes a tile's counters and pixels from its read-back bytes: 8-bit
    /// colour as it is, or radiance sums divided by `samples` and
    /// tone-mapped into `rgb` (and the feature sums divided alike).
    fn take_tile(
        &mut self,
        bytes: &[u8],
        area: TileArea,
        width: u32,
        output: PixelOutput,
        samples: f32,
        tone_map: (ToneMap, f32),
    ) {
        let (header, pixels) = bytes.split_at(OUTPUT_HEADER_BYTES as usize);
        self.counters = bytemuck::pod_read_unaligned::<RayCounters>(header);
        let words: Vec<u32> = pixels[..(area.pixels() * output.bytes()) as usize]
            .chunks_exact(4)
            .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .collect();
        let (w, width) = (area.w as usize, width as usize);
        for row in 0..area.h as usize {
            let start = (row * width + area.x as usize) * 3;
            let dst = &mut self.rgb[start..start + w * 3];
            if !output.radiance() {
                for (d, p) in dst.chunks_exact_mut(3).zip(&words[row * w..(row + 1) * w]) {
                    d.copy_from_slice(&p.to_le_bytes()[..3]);
                }
                continue;
            }
            let stride = output.words();
            let mean = &mut self.radiance[start..start + w * 3];
            let sums = &words[row * w * stride..(row + 1) * w * stride];
            for ((m, d), sum) in mean
                .chunks_exact_mut(3)
                .zip(dst.chunks_exact_mut(3))
                .zip(sums.chunks_exact(stride))
            {
                for c in 0..3 {
                    m[c] = f32::from_bits(sum[c]) / samples;
                    d[c] = tone_map.0.to_srgb8(m[c], tone_map.1);
                }
            }
            if output != PixelOutput::Features {
                continue;
            }
            let albedo = &mut self.albedo[start..start + w * 3];
            let normal = &mut self.normal[start..start + w * 3];
            for ((a, n), sum) in albedo
                .chunks_exact_mut(3)
                .zip(normal.chunks_exact_mut(3))
                .zip(sums.chunks_exact(stride))
            {
                for c in 0..3 {
                    a[c] = f32::from_bits(sum[4 + c]) / samples;
                    n[c] = f32::from_bits(sum[8 + c]) / samples;
                }
            }
        }
    }

    /// Takes a tile's walk costs, after its output in the read-back bytes.
    fn take_costs(
        &mut self,
        bytes: &[u8],
        area: TileArea,
        width: u32,
        output: PixelOutput,
        totals: &mut CostTotals,
    ) {
        let used = TileBuffers::output_bytes(area, output) as usize;
        let words: Vec<u32> = bytes[used..]
            .chunks_exact(4)
            .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .collect();
        let mut tile = words.chunks_exact(bindings::COST_WORDS);
        for row in 0..area.h as usize {
            let start = row * width as usize + area.x as usize;
            for (d, c) in self.costs[start..start + area.w as usize]
                .iter_mut()
                .zip(&mut tile)
            {
                *d = WalkCost::from_words(c);
                totals.add(d);
            }
        }
    }
}
