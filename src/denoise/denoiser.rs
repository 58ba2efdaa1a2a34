//! [`Denoiser`]: an image in, the denoised image out, tile by tile on the
//! GPU. The two shipped networks are built into the binary and uploaded
//! the first time an image needs them; a denoiser serves any number of
//! images on its context.

use std::collections::HashMap;
use std::sync::{Arc, Mutex};

use kdray_core::denoise::cpu_net::input_scale;
use kdray_core::denoise::layers::Tensor;
use kdray_core::denoise::{DenoiseImages, TilePlan, Weights};

use super::gpu_weights::GpuWeights;
use super::image_run::DenoiseRun;
use super::kernels::Kernels;
use super::tile_run::TileRun;
use crate::error::{Error, Result};
use crate::gpu::{max_binding_bytes, GpuContext};

/// OIDN's `rt_hdr` (colour) and `rt_hdr_alb_nrm` (colour, albedo, normal).
const SHIPPED: [(usize, &str, &[u8]); 2] = [
    (
        3,
        "assets/denoise/rt_hdr.tza",
        include_bytes!("../../assets/denoise/rt_hdr.tza"),
    ),
    (
        9,
        "assets/denoise/rt_hdr_alb_nrm.tza",
        include_bytes!("../../assets/denoise/rt_hdr_alb_nrm.tza"),
    ),
];

/// The shipped network reading `input_channels` (3: colour; 9: colour,
/// albedo and normal).
pub fn shipped_weights(input_channels: usize) -> Result<Weights> {
    let Some((_, name, bytes)) = SHIPPED.iter().find(|(c, _, _)| *c == input_channels) else {
        return Err(Error::Usage(match input_channels {
            6 => "an albedo without a normal is not supported (kdray ships OIDN's networks for colour alone and for colour, albedo and normal)".into(),
            n => format!("no denoising network reads {n} channels"),
        }));
    };
    Weights::from_tza(bytes, &format!("{name} (built in)"))
        .map_err(|e| Error::Output(e.to_string()))
}

pub struct Denoiser<'a> {
    pub(super) ctx: &'a GpuContext,
    pub(super) kernels: Kernels,
    /// The shipped networks uploaded so far, by input channels.
    networks: Mutex<HashMap<usize, Arc<GpuWeights>>>,
}

impl<'a> Denoiser<'a> {
    /// The denoiser's pipelines on `ctx` (no weights uploaded yet).
    pub fn new(ctx: &'a GpuContext) -> Result<Self> {
        Ok(Denoiser {
            ctx,
            kernels: Kernels::new(ctx)?,
            networks: Mutex::new(HashMap::new()),
        })
    }

    /// `weights` on this denoiser's GPU.
    pub fn upload(&self, weights: &Weights) -> Result<GpuWeights> {
        GpuWeights::upload(self.ctx, weights)
    }

    fn shipped(&self, input_channels: usize) -> Result<Arc<GpuWeights>> {
        let mut networks = self
            .networks
            .lock()
            .map_err(|_| Error::Gpu("the denoiser's lock was poisoned".into()))?;
        if let Some(network) = networks.get(&input_channels) {
            return Ok(network.clone());
        }
        let network = Arc::new(self.upload(&shipped_weights(input_channels)?)?);
        networks.insert(input_channels, network.clone());
        Ok(network)
    }

    /// `images` denoised by the shipped network for their channels;
    /// `input_scale` as OIDN's `inputScale` (autoexposure when `None`).
    pub fn denoise(&self, images: &DenoiseImages<'_>, scale: Option<f32>) -> Result<Vec<f32>> {
        images.check().map_err(Error::Usage)?;
        let network = self.shipped(images.input_channels())?;
        self.denoise_with(images, &network, scale)
    }

    /// `images` denoised by `network` (three floats a pixel): a
    /// [`DenoiseRun`] run whole, tile by tile.
    pub fn denoise_with(
        &self,
        images: &DenoiseImages<'_>,
        network: &GpuWeights,
        scale: Option<f32>,
    ) -> Result<Vec<f32>> {
        if images.width == 0 || images.height == 0 {
            images.check().map_err(Error::Usage)?;
            return Ok(Vec::new());
        }
        let mut run = self.start_with(images, network, scale, None)?;
        while !run.is_finished() {
            run.advance(self.ctx, images, usize::MAX)?;
        }
        run.into_output()
    }

    /// The denoise of `images` by the shipped network for their channels,
    /// begun (nothing run yet), its convolutions cut into units of at
    /// most `max_unit_cost` (see [`super::work_units`]).
    pub fn start(
        &self,
        images: &DenoiseImages<'_>,
        scale: Option<f32>,
        max_unit_cost: Option<u64>,
    ) -> Result<DenoiseRun> {
        images.check().map_err(Error::Usage)?;
        let network = self.shipped(images.input_channels())?;
        self.start_with(images, &network, scale, max_unit_cost)
    }

    /// The denoise of `images` by `network`, begun (see [`Self::start`]).
    pub fn start_with(
        &self,
        images: &DenoiseImages<'_>,
        network: &GpuWeights,
        scale: Option<f32>,
        max_unit_cost: Option<u64>,
    ) -> Result<DenoiseRun> {
        images.check().map_err(Error::Usage)?;
        if images.input_channels() != network.input_channels {
            return Err(Error::Usage(format!(
                "the images give {} channels, the network reads {}",
                images.input_channels(),
                network.input_channels
            )));
        }
        let (width, height) = (images.width, images.height);
        let limit = max_binding_bytes(&self.ctx.device.limits());
        let plan = TilePlan::new(width, height, network.input_channels, limit);
        let run = TileRun::new(
            self.ctx,
            &self.kernels,
            network,
            (plan.tile_width, plan.tile_height),
            max_unit_cost,
        )?;
        Ok(DenoiseRun::new(
            (width, height),
            network.input_channels,
            plan,
            run,
            input_scale(images, scale),
        ))
    }

    /// The network alone on a packed input tensor (height and width
    /// multiples of 16): its raw output, as
    /// [`kdray_core::denoise::cpu_net::run_network`] gives it.
    pub fn gpu_network(&self, network: &GpuWeights, input: &Tensor) -> Result<Tensor> {
        let size = (input.width, input.height);
        let mut run = TileRun::new(self.ctx, &self.kernels, network, size, None)?;
        run.run_tensor(self.ctx, input)
    }
}
