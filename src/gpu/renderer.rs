//! The headless renderer: the trace pipeline's tiled dispatch, band by band
//! of whole rows. Each tile is traced in dispatches of one invocation per
//! pixel, copied back into its buffers (`tile_buffers.rs`) and handed on in
//! bands of 8-bit RGB rows (with radiance, costs or feature images when
//! asked for); what the render measured is a [`RenderSummary`].

use std::time::Instant;

use super::bindings;
use super::context::GpuContext;
use super::gpu_timer::GpuTimer;
use super::render_summary::{CostTotals, GpuTimeSource, RayTotals, RenderSummary};
use super::scene_buffers::SceneBuffers;
use super::tile_buffers::{BandBuffers, TileArea, TileBuffers};
use super::tile_plan::{PixelOutput, TilePlan};
use super::{KernelVariant, TracePipeline, TracePipelines};
use crate::error::Result;
use crate::gpu::FrameParams;
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
    /// dispatch (gpu/trace_pipelines.rs), which would otherwise fall
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
        let tile = TileBuffers::new(
            ctx,
            &self.pipelines,
            &self.params_buffer,
            scene,
            tile_pixels,
            with_cost,
            output,
        )?;
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
                    pipeline: &pipeline,
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
            self.pipelines.record_pass(
                &mut encoder,
                "trace tile",
                run.pipeline,
                run.bind_group,
                tile_params.tile_size,
                run.timer.map(|t| t.writes()),
            );
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

/// What every dispatch of a frame's tiles uses.
struct TileRun<'a> {
    pipeline: &'a TracePipeline,
    bind_group: &'a wgpu::BindGroup,
    timer: Option<&'a GpuTimer>,
    tile: &'a TileBuffers,
    params: FrameParams,
    with_cost: bool,
    output: PixelOutput,
}
