//! Each layer kind on the GPU alone, on tensors of any size: what the GPU
//! tier compares with the CPU reference layers
//! ([`kdray_core::denoise::layers`]). A denoise never uses these (its
//! tiles run every step in one pass, `tile_run`); they dispatch the same
//! pipelines.

use kdray_core::denoise::layers::Tensor;
use kdray_core::denoise::ConvWeights;

use super::dispatches::{ConvParams, ResampleParams};
use super::gpu_weights::GpuWeights;
use super::kernels::{CONV_GROUP, CONV_OUTPUTS, CONV_PIXELS, WORKGROUP};
use super::tile_run::bind_resources;
use super::Denoiser;
use crate::error::{Error, Result};
use crate::gpu::context::buffer_holding;
use crate::gpu::GpuContext;

/// Uploads `inputs`, runs `pipeline` once per entry of `dispatches` (its
/// parameters and, for a convolution, its two weights blocks) with the
/// buffers in binding order (params, weights, the inputs, the output),
/// and reads the output (`out_floats`) back.
fn run_once(
    ctx: &GpuContext,
    pipeline: &wgpu::ComputePipeline,
    dispatches: Vec<(Vec<u8>, Vec<wgpu::BindingResource<'_>>)>,
    inputs: &[&[f32]],
    out_floats: usize,
    workgroups: [u32; 3],
) -> Result<Vec<f32>> {
    let size = (out_floats.max(1) * 4) as u64;
    let readback = ctx.checked("running a denoise layer", |device| {
        let inputs: Vec<wgpu::Buffer> = inputs
            .iter()
            .map(|data| {
                let bytes: &[u8] = bytemuck::cast_slice(data);
                let bytes = if bytes.is_empty() {
                    &[0u8; 4][..]
                } else {
                    bytes
                };
                buffer_holding(device, "layer input", bytes, wgpu::BufferUsages::STORAGE)
            })
            .collect();
        let out = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("layer output"),
            size,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let readback = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("layer readback"),
            size,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let groups: Vec<wgpu::BindGroup> = dispatches
            .into_iter()
            .map(|(params, weights)| {
                let params = buffer_holding(
                    device,
                    "layer parameters",
                    &params,
                    wgpu::BufferUsages::UNIFORM,
                );
                let resources: Vec<wgpu::BindingResource<'_>> =
                    std::iter::once(params.as_entire_binding())
                        .chain(weights)
                        .chain(inputs.iter().map(|b| b.as_entire_binding()))
                        .chain(std::iter::once(out.as_entire_binding()))
                        .collect();
                bind_resources(device, pipeline, resources)
            })
            .collect();
        let mut encoder = device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(pipeline);
            for group in &groups {
                pass.set_bind_group(0, group, &[]);
                pass.dispatch_workgroups(workgroups[0], workgroups[1], workgroups[2]);
            }
        }
        encoder.copy_buffer_to_buffer(&out, 0, &readback, 0, size);
        ctx.queue.submit([encoder.finish()]);
        readback
    })?;
    let bytes = ctx.read_buffer(&readback, size)?;
    Ok(bytemuck::cast_slice(&bytes)[..out_floats].to_vec())
}

fn workgroups(width: usize, height: usize, z: usize) -> [u32; 3] {
    let wg = WORKGROUP;
    [
        (width as u32).div_ceil(wg),
        (height as u32).div_ceil(wg),
        z as u32,
    ]
}

impl Denoiser<'_> {
    /// [`kdray_core::denoise::layers::conv3x3`] on the GPU.
    pub fn gpu_conv3x3(
        &self,
        src: &Tensor,
        skip: Option<&Tensor>,
        w: &ConvWeights,
        relu: bool,
    ) -> Result<Tensor> {
        let skip_channels = skip.map_or(0, |s| s.channels);
        if src.channels + skip_channels != w.in_channels
            || skip.is_some_and(|s| (s.height, s.width) != (src.height, src.width))
        {
            return Err(Error::Usage(
                "a convolution's inputs do not fit its weights".into(),
            ));
        }
        let weights = GpuWeights::upload_layer(self.ctx, w)?;
        let blocks = &weights.layers[0];
        let dispatches = blocks
            .group_offsets
            .chunks(CONV_OUTPUTS / CONV_GROUP)
            .enumerate()
            .map(|(k, pair)| {
                let params = ConvParams {
                    width: src.width as u32,
                    height: src.height as u32,
                    src_channels: src.channels as u32,
                    skip_channels: skip_channels as u32,
                    out_channels: blocks.out_channels,
                    first_output: (k * CONV_OUTPUTS) as u32,
                    relu: u32::from(relu),
                    first_row: 0,
                };
                (
                    bytemuck::bytes_of(&params).to_vec(),
                    vec![weights.block(pair[0]), weights.block(pair[pair.len() - 1])],
                )
            })
            .collect();
        let skip_data = skip.map_or(&src.data, |s| &s.data);
        let out_floats = w.out_channels * src.height * src.width;
        let data = run_once(
            self.ctx,
            &self.kernels.conv,
            dispatches,
            &[&src.data, skip_data],
            out_floats,
            [
                (src.width as u32).div_ceil(WORKGROUP * CONV_PIXELS),
                (src.height as u32).div_ceil(WORKGROUP),
                1,
            ],
        )?;
        Ok(Tensor {
            channels: w.out_channels,
            height: src.height,
            width: src.width,
            data,
        })
    }

    /// [`kdray_core::denoise::layers::max_pool2`] on the GPU.
    pub fn gpu_max_pool2(&self, src: &Tensor) -> Result<Tensor> {
        let (h, w) = (src.height / 2, src.width / 2);
        self.resample(&self.kernels.pool, src, h, w)
    }

    /// [`kdray_core::denoise::layers::upsample2`] on the GPU.
    pub fn gpu_upsample2(&self, src: &Tensor) -> Result<Tensor> {
        let (h, w) = (src.height * 2, src.width * 2);
        self.resample(&self.kernels.upsample, src, h, w)
    }

    fn resample(
        &self,
        pipeline: &wgpu::ComputePipeline,
        src: &Tensor,
        height: usize,
        width: usize,
    ) -> Result<Tensor> {
        let params = ResampleParams {
            width: width as u32,
            height: height as u32,
            channels: src.channels as u32,
            pad: 0,
        };
        let out_floats = src.channels * height * width;
        let data = run_once(
            self.ctx,
            pipeline,
            vec![(bytemuck::bytes_of(&params).to_vec(), Vec::new())],
            &[&src.data],
            out_floats,
            workgroups(width, height, src.channels),
        )?;
        Ok(Tensor {
            channels: src.channels,
            height,
            width,
            data,
        })
    }
}
