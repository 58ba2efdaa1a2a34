//! Denoising in the window (N; the path tracer only): the feature images
//! gathered beside the refined image, and the denoiser
//! ([`crate::denoise::Denoiser`]) run on them when the
//! [`DenoiseSchedule`] says so: the sums of a finished pass read back
//! (waited for without blocking), then a [`DenoiseRun`] on their means
//! advanced a few units a frame, as the [`DenoiseBudget`] allows, so that
//! the window keeps presenting frames (and answering keys) while it
//! denoises.
//!
//! The accumulation's pass (`accumulate_tile`) keeps colour sums only. The
//! sums the denoiser reads come from the headless kernel instead:
//! `render_tile` with `FEATURE_OUTPUT`, the pipeline `kdray render
//! --denoise` runs, tracing one sample per pass over the same band with
//! the same parameters. The kernel adds to the sums of a tile buffer
//! indexed from the tile's origin, so each band's sums are copied from a
//! whole-image store into that buffer and back. The colour, albedo and
//! normal sums are thus those of the headless render, added in the same
//! order, and their means the images `render --denoise` denoises. The
//! colour is traced twice while denoising (here and by the accumulation,
//! whose sums the present pass shows until the first denoise).

use std::sync::Arc;
use std::time::{Duration, Instant};

use super::denoise_budget::{DenoiseBudget, MAX_UNIT_COST};
use super::denoise_schedule::DenoiseSchedule;
use crate::denoise::{DenoiseRun, Denoiser};
use crate::error::{Error, Result};
use crate::gpu::{
    bindings, max_binding_bytes, FrameParams, GpuContext, KernelVariant, RayCounters, SceneBuffers,
    TraceBindGroup, TracePipelines,
};
use crate::scene::Integrator;

/// Bytes of a pixel's sums with `FEATURE_OUTPUT` (shaders/trace.wgsl,
/// `add_radiance`): colour, albedo and normal, three f32 and an unused
/// word each.
const FEATURE_TEXEL: u64 = 48;
/// Bytes of the tile buffer's header, the ray counters, before its pixels.
const HEADER_BYTES: u64 = std::mem::size_of::<RayCounters>() as u64;

fn buffer(
    device: &wgpu::Device,
    label: &str,
    size: u64,
    usage: wgpu::BufferUsages,
) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: size.max(4),
        usage,
        mapped_at_creation: false,
    })
}

/// The feature pass's buffers for one scene.
struct FeaturePass {
    /// `render_tile`, one pipeline per kernel variant.
    pipelines: Arc<TracePipelines>,
    params: wgpu::Buffer,
    /// Every pixel's sums, row-major, the image's width wide.
    store: wgpu::Buffer,
    store_pixels: u64,
    /// The kernel's output: the header, then one band's sums.
    tile: wgpu::Buffer,
    tile_pixels: u64,
    group: TraceBindGroup,
}

impl FeaturePass {
    fn new(ctx: &GpuContext, scene: &SceneBuffers, pixels: u64, band: u64) -> Result<Self> {
        let pipelines = ctx.trace_pipelines(bindings::RENDER_TILE)?;
        let params = FrameParams::uniform_buffer(ctx, "window feature params")?;
        let limit = max_binding_bytes(&ctx.device.limits());
        if HEADER_BYTES + band * FEATURE_TEXEL > limit {
            return Err(Error::Gpu(format!(
                "a band of {band} pixels is too big to denoise on this device"
            )));
        }
        use wgpu::BufferUsages as U;
        ctx.checked("allocating the denoiser's feature buffers", |device| {
            // One word: the pass counts no costs.
            let costs = buffer(device, "feature costs", 4, U::STORAGE);
            let store = buffer(
                device,
                "feature sums",
                pixels * FEATURE_TEXEL,
                U::COPY_SRC | U::COPY_DST,
            );
            let tile = buffer(
                device,
                "feature tile",
                HEADER_BYTES + band * FEATURE_TEXEL,
                U::STORAGE | U::COPY_SRC | U::COPY_DST,
            );
            // RENDER_TILE's outputs: the tile's output, then its costs.
            let group = pipelines.bind_group(device, &params, scene, &[&tile, &costs]);
            FeaturePass {
                pipelines: pipelines.clone(),
                params,
                store,
                store_pixels: pixels,
                tile,
                tile_pixels: band,
                group,
            }
        })
    }

    /// Whether it holds an image of `pixels` pixels and bands of `band`.
    fn fits(&self, pixels: u64, band: u64) -> bool {
        pixels <= self.store_pixels && band <= self.tile_pixels
    }

    /// Adds `params`' sample to its band's sums (zeroing the image's first
    /// if `clear`).
    fn trace(
        &self,
        ctx: &GpuContext,
        scene: &SceneBuffers,
        params: &FrameParams,
        clear: bool,
    ) -> Result<()> {
        let (width, first_row) = (params.width as u64, params.tile_origin[1] as u64);
        let band = params.tile_size[0] as u64 * params.tile_size[1] as u64;
        let (at, bytes) = (first_row * width * FEATURE_TEXEL, band * FEATURE_TEXEL);
        let params = FrameParams {
            sample_count: 1,
            ..*params
        };
        let variant = KernelVariant {
            radiance_output: true,
            feature_output: true,
            ..KernelVariant::for_frame(scene, &params, false)
        };
        let mut encoder = ctx
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("feature pass"),
            });
        if clear {
            let image = width * params.height as u64 * FEATURE_TEXEL;
            encoder.clear_buffer(&self.store, 0, Some(image));
        }
        encoder.clear_buffer(&self.tile, 0, Some(HEADER_BYTES));
        encoder.copy_buffer_to_buffer(&self.store, at, &self.tile, HEADER_BYTES, bytes);
        self.pipelines.encode_tile(
            ctx,
            &mut encoder,
            "feature pass",
            variant,
            &self.group,
            (&self.params, &params),
        )?;
        encoder.copy_buffer_to_buffer(&self.tile, HEADER_BYTES, &self.store, at, bytes);
        ctx.queue.submit([encoder.finish()]);
        Ok(())
    }

    /// Begins reading back the first `pixels` pixels' sums as they are
    /// after the work submitted so far (twelve words each): the readback
    /// buffer, and where its mapping's outcome arrives.
    fn begin_read(&self, ctx: &GpuContext, pixels: u64) -> Result<(wgpu::Buffer, MapOutcome)> {
        let size = pixels * FEATURE_TEXEL;
        let readback = ctx.checked("reading back the feature sums", |device| {
            let readback = buffer(
                device,
                "feature readback",
                size,
                wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            );
            let mut encoder = device.create_command_encoder(&Default::default());
            encoder.copy_buffer_to_buffer(&self.store, 0, &readback, 0, size);
            ctx.queue.submit([encoder.finish()]);
            readback
        })?;
        let (sender, receiver) = std::sync::mpsc::channel();
        readback
            .slice(..size)
            .map_async(wgpu::MapMode::Read, move |r| {
                let _ = sender.send(r);
            });
        Ok((readback, receiver))
    }
}

/// Where a buffer's mapping reports its outcome.
type MapOutcome = std::sync::mpsc::Receiver<std::result::Result<(), wgpu::BufferAsyncError>>;

/// A mapped buffer's words as floats, the buffer unmapped.
fn mapped_floats(buffer: &wgpu::Buffer) -> Result<Vec<f32>> {
    let floats = {
        let view = buffer
            .slice(..)
            .get_mapped_range()
            .map_err(|e| Error::Gpu(format!("reading back the feature sums failed: {e}")))?;
        view.chunks_exact(4)
            .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .collect()
    };
    buffer.unmap();
    Ok(floats)
}

/// The means of `sums` (twelve floats a pixel: colour, albedo and normal
/// sums, each with an unused fourth) over `samples`, as three images of
/// three floats a pixel, divided as the headless renderer divides them.
pub fn feature_means(sums: &[f32], samples: u32) -> [Vec<f32>; 3] {
    let n = samples.max(1) as f32;
    let pixels = sums.len() / 12;
    let mut images = [0, 1, 2].map(|_| Vec::with_capacity(pixels * 3));
    for texel in sums.chunks_exact(12) {
        for (k, image) in images.iter_mut().enumerate() {
            image.extend(texel[4 * k..4 * k + 3].iter().map(|s| s / n));
        }
    }
    images
}

/// A denoise begun: its feature sums on their way back from the GPU
/// (waited for without blocking, so that the frame that begins a denoise
/// does not wait for the GPU's queue).
struct Reading {
    readback: wgpu::Buffer,
    mapped: MapOutcome,
    size: (u32, u32),
    samples: u32,
    started: Instant,
}

/// A denoise in progress: its run and the images it denoises.
struct Running {
    run: DenoiseRun,
    size: (usize, usize),
    /// Colour, albedo and normal: the means of the sums it began with.
    images: [Vec<f32>; 3],
    samples: u32,
    started: Instant,
    /// Time spent running its units (waiting for the GPU included).
    busy: Duration,
    /// Frames that ran some of its units.
    frames: u32,
    /// When the last of them (or the frame that made the run) ran, and
    /// the longest interval between two of them (a frame's time while
    /// denoising).
    last_frame: Instant,
    longest_frame: Duration,
}

/// A finished denoise.
pub struct Denoised {
    /// Linear RGB, three floats a pixel, row-major.
    pub rgb: Vec<f32>,
    /// Samples per pixel it denoised.
    pub samples: u32,
    /// Time spent running its units, and since it began.
    pub busy: Duration,
    pub elapsed: Duration,
    /// Frames that ran its units, and the longest interval between two
    /// (from the frame that made its run).
    pub frames: u32,
    pub longest_frame: Duration,
}

/// The window's denoising: whether it is on, the feature pass, the
/// denoiser, the schedule of the image being refined and the denoise in
/// progress.
#[derive(Default)]
pub struct Denoising {
    /// N: show the denoised image while path tracing.
    pub on: bool,
    /// N was pressed while the Whitted integrator traces (the title says
    /// that the denoiser needs the path tracer).
    pub refused: bool,
    pub schedule: DenoiseSchedule,
    features: Option<FeaturePass>,
    /// Made at the first denoise; its kernels and weights serve the rest.
    denoiser: Option<Denoiser<'static>>,
    reading: Option<Reading>,
    running: Option<Running>,
    budget: DenoiseBudget,
}

impl Denoising {
    pub fn new(on: bool) -> Self {
        Denoising {
            on,
            ..Default::default()
        }
    }

    /// Whether frames of `integrator` gather features and denoise.
    pub fn active(&self, integrator: Integrator) -> bool {
        self.on && integrator == Integrator::Path
    }

    /// Another scene: the feature pass is made again for it.
    pub fn set_scene(&mut self) {
        self.features = None;
        self.abandon();
    }

    /// Adds the sample of the accumulation pass `params` (a band of the
    /// image) to the feature sums; `clear`: the image starts with it.
    pub fn trace(
        &mut self,
        ctx: &GpuContext,
        scene: &SceneBuffers,
        params: &FrameParams,
        clear: bool,
    ) -> Result<()> {
        let pixels = params.width as u64 * params.height as u64;
        let band = params.tile_size[0] as u64 * params.tile_size[1] as u64;
        if !self.features.as_ref().is_some_and(|f| f.fits(pixels, band)) {
            // Sized for whole-image bands, so a later band never outgrows it.
            let old = self.features.take();
            let (pixels, band) = old.map_or((pixels, pixels), |f| {
                (f.store_pixels.max(pixels), f.tile_pixels.max(pixels))
            });
            self.features = Some(FeaturePass::new(ctx, scene, pixels, band)?);
            if !clear {
                return Err(Error::Gpu(
                    "the denoiser's feature buffers were made mid-image".into(),
                ));
            }
        }
        match &self.features {
            Some(f) => f.trace(ctx, scene, params, clear),
            None => Ok(()),
        }
    }

    /// Whether a denoise is in progress.
    pub fn is_running(&self) -> bool {
        self.reading.is_some() || self.running.is_some()
    }

    /// The denoise in progress: its samples per pixel and the percentage
    /// of its work done.
    pub fn progress(&self) -> Option<(u32, u32)> {
        if let Some(r) = &self.reading {
            return Some((r.samples, 0));
        }
        self.running.as_ref().map(|r| {
            let (done, total) = r.run.progress();
            let percent = (done as f64 * 100.0 / total.max(1) as f64).floor();
            (r.samples, percent as u32)
        })
    }

    /// Drops the denoise in progress, if any (the image it denoises is
    /// gone).
    pub fn abandon(&mut self) {
        self.reading = None;
        self.running = None;
    }

    /// Begins the denoise of the image of `size` pixels, every pixel
    /// holding `samples` samples (the feature sums as the work submitted
    /// so far leaves them): their readback.
    pub fn start(&mut self, ctx: &GpuContext, size: (u32, u32), samples: u32) -> Result<()> {
        let Some(features) = &self.features else {
            return Err(Error::Gpu("no feature sums to denoise".into()));
        };
        let (readback, mapped) = features.begin_read(ctx, size.0 as u64 * size.1 as u64)?;
        self.running = None;
        self.reading = Some(Reading {
            readback,
            mapped,
            size,
            samples,
            started: Instant::now(),
        });
        Ok(())
    }

    /// Makes the run once the sums are back (false: not yet).
    fn make_run(&mut self, ctx: &'static GpuContext) -> Result<bool> {
        let Some(reading) = &self.reading else {
            return Ok(true);
        };
        ctx.device
            .poll(wgpu::PollType::Poll)
            .map_err(|e| Error::Gpu(format!("polling the GPU failed: {e}")))?;
        match reading.mapped.try_recv() {
            Err(std::sync::mpsc::TryRecvError::Empty) => return Ok(false),
            Err(std::sync::mpsc::TryRecvError::Disconnected) => {
                return Err(Error::Gpu("the feature sums never came back".into()))
            }
            Ok(Err(e)) => {
                return Err(Error::Gpu(format!(
                    "reading back the feature sums failed: {e}"
                )))
            }
            Ok(Ok(())) => {}
        }
        let Some(reading) = self.reading.take() else {
            return Ok(false);
        };
        let making = Instant::now();
        let (width, height) = (reading.size.0 as usize, reading.size.1 as usize);
        let mut sums = mapped_floats(&reading.readback)?;
        sums.truncate(width * height * 12);
        let images = feature_means(&sums, reading.samples);
        let denoiser = match &mut self.denoiser {
            Some(d) => d,
            None => self.denoiser.insert(Denoiser::new(ctx)?),
        };
        let [color, albedo, normal] = &images;
        let view = kdray_core::denoise::DenoiseImages {
            width,
            height,
            color,
            albedo: Some(albedo),
            normal: Some(normal),
        };
        let run = denoiser.start(&view, None, Some(MAX_UNIT_COST))?;
        self.running = Some(Running {
            run,
            size: (width, height),
            images,
            samples: reading.samples,
            started: reading.started,
            busy: making.elapsed(),
            frames: 0,
            last_frame: making,
            longest_frame: Duration::ZERO,
        });
        Ok(true)
    }

    /// Runs this frame's share of the denoise in progress: once its sums
    /// are back, the run made (in a frame of its own), then its units (see
    /// [`DenoiseBudget`]); the denoised image once its last unit has run.
    pub fn advance(&mut self, ctx: &'static GpuContext) -> Result<Option<Denoised>> {
        if self.reading.is_some() {
            // Made in this frame, the run's units begin in the next.
            self.make_run(ctx)?;
            return Ok(None);
        }
        let Some(running) = &mut self.running else {
            return Ok(None);
        };
        let units = self.budget.units(running.run.next_costs());
        let began = Instant::now();
        running.longest_frame = running.longest_frame.max(began - running.last_frame);
        running.last_frame = began;
        let [color, albedo, normal] = &running.images;
        let images = kdray_core::denoise::DenoiseImages {
            width: running.size.0,
            height: running.size.1,
            color,
            albedo: Some(albedo),
            normal: Some(normal),
        };
        let cost = running.run.advance(ctx, &images, units)?;
        let took = began.elapsed();
        self.budget.learn(cost, took.as_secs_f64());
        running.busy += took;
        running.frames += 1;
        if !running.run.is_finished() {
            return Ok(None);
        }
        let Some(done) = self.running.take() else {
            return Ok(None);
        };
        Ok(Some(Denoised {
            samples: done.samples,
            busy: done.busy,
            elapsed: done.started.elapsed(),
            frames: done.frames,
            longest_frame: done.longest_frame,
            rgb: done.run.into_output()?,
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn feature_means_split_the_sums_into_three_images() {
        // Two pixels: colour, albedo and normal sums of 4 samples, each
        // with an unused word that must not leak into the images.
        let sums = [
            4.0, 8.0, 12.0, 99.0, 2.0, 2.0, 2.0, 99.0, -4.0, 0.0, 4.0, 99.0, //
            0.0, 1.0, 2.0, 99.0, 3.0, 4.0, 5.0, 99.0, 6.0, 7.0, 8.0, 99.0,
        ];
        let [color, albedo, normal] = feature_means(&sums, 4);
        assert_eq!(color, [1.0, 2.0, 3.0, 0.0, 0.25, 0.5]);
        assert_eq!(albedo, [0.5, 0.5, 0.5, 0.75, 1.0, 1.25]);
        assert_eq!(normal, [-1.0, 0.0, 1.0, 1.5, 1.75, 2.0]);
    }
}
