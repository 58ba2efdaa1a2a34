//! One tile size's buffers and bind groups, and the run of the network on
//! one tile: the tile's source pixels uploaded, packed, the 24 steps of
//! [`kdray_core::denoise::network::STEPS`] dispatched as the rows of
//! [`super::dispatches::network_dispatches`] (one buffer per slot, each
//! sized for the most that slot ever holds), the output rectangle unpacked
//! and read back. The run is the list of [`super::work_units`]: all in one
//! compute pass, or a range at a time ([`TileRun::run_units`]). Every tile of a plan has the same size, so a
//! plan makes its buffers once.

use bytemuck::{Pod, Zeroable};
use kdray_core::denoise::layers::Tensor;
use kdray_core::denoise::network::{slot_index, tensor_floats, Slot, OUTPUT_CHANNELS, OUTPUT_SLOT};

use std::ops::Range;

use super::dispatches::{network_dispatches, ConvParams, DenoiseKernel, StepDispatch};
use super::gpu_weights::{GpuWeights, BLOCK_BYTES};
use super::kernels::{Kernels, WORKGROUP};
use super::work_units::{tile_units, UnitKind, WorkUnit};
use crate::error::{Error, Result};
use crate::gpu::context::buffer_holding;
use crate::gpu::{max_binding_bytes, GpuContext};

/// pack.wgsl's `PackParams`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct PackParams {
    pub tile_width: u32,
    pub tile_height: u32,
    pub src_width: u32,
    pub src_height: u32,
    pub offset_x: u32,
    pub offset_y: u32,
    pub channels: u32,
    pub out_x: u32,
    pub out_y: u32,
    pub out_width: u32,
    pub out_height: u32,
    pub input_scale: f32,
    pub output_scale: f32,
    pub pu_norm: f32,
    pub pu_max: f32,
    pub pad: u32,
}

/// One dispatch: its pipeline, bind group and workgroup counts (the
/// unpacking's depend on the tile: [`Dispatch::record_with`]).
struct Dispatch {
    pipeline: wgpu::ComputePipeline,
    group: wgpu::BindGroup,
    workgroups: [u32; 3],
}

impl Dispatch {
    fn record(&self, pass: &mut wgpu::ComputePass<'_>) {
        self.record_with(pass, self.workgroups);
    }

    fn record_with(&self, pass: &mut wgpu::ComputePass<'_>, [x, y, z]: [u32; 3]) {
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &self.group, &[]);
        pass.dispatch_workgroups(x, y, z);
    }
}

pub struct TileRun {
    pub tile_height: usize,
    pub tile_width: usize,
    input_channels: usize,
    slots: Vec<wgpu::Buffer>,
    images: wgpu::Buffer,
    out: wgpu::Buffer,
    readback: wgpu::Buffer,
    pack_params: wgpu::Buffer,
    pack: Dispatch,
    /// The run's units, and the dispatch of each network unit (a band of
    /// a convolution has its own parameters), in order: each made when
    /// it first runs, so that making a run cut into many units costs no
    /// frame a burst of bind groups.
    units: Vec<WorkUnit>,
    steps: Vec<Option<Dispatch>>,
    unpack: Dispatch,
    /// What the network's dispatches are made from.
    table: Vec<StepDispatch>,
    kernels: [wgpu::ComputePipeline; 3],
    weights: wgpu::Buffer,
}

fn storage(
    device: &wgpu::Device,
    label: &str,
    floats: usize,
    extra: wgpu::BufferUsages,
) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: (floats.max(1) * 4) as u64,
        usage: wgpu::BufferUsages::STORAGE | extra,
        mapped_at_creation: false,
    })
}

fn uniform<T: Pod>(device: &wgpu::Device, value: &T) -> wgpu::Buffer {
    buffer_holding(
        device,
        "denoise step parameters",
        bytemuck::bytes_of(value),
        wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
    )
}

fn bind(
    device: &wgpu::Device,
    pipeline: &wgpu::ComputePipeline,
    buffers: &[&wgpu::Buffer],
) -> wgpu::BindGroup {
    bind_resources(
        device,
        pipeline,
        buffers.iter().map(|b| b.as_entire_binding()),
    )
}

/// A bind group of `resources` at bindings 0, 1, ... of `pipeline`'s layout.
pub fn bind_resources<'a>(
    device: &wgpu::Device,
    pipeline: &wgpu::ComputePipeline,
    resources: impl IntoIterator<Item = wgpu::BindingResource<'a>>,
) -> wgpu::BindGroup {
    let layout = pipeline.get_bind_group_layout(0);
    let entries: Vec<wgpu::BindGroupEntry<'_>> = resources
        .into_iter()
        .enumerate()
        .map(|(i, resource)| wgpu::BindGroupEntry {
            binding: i as u32,
            resource,
        })
        .collect();
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("denoise step"),
        layout: &layout,
        entries: &entries,
    })
}

fn workgroups(width: usize, height: usize, z: usize) -> [u32; 3] {
    [
        (width as u32).div_ceil(WORKGROUP),
        (height as u32).div_ceil(WORKGROUP),
        z as u32,
    ]
}

impl TileRun {
    /// The buffers and bind groups for tiles of `tile_height` x
    /// `tile_width` (multiples of 16) through `weights`, the convolutions
    /// cut into units of at most `max_unit_cost` (see [`tile_units`]).
    /// Fails in one line if a tensor would exceed the device's largest
    /// storage binding.
    pub fn new(
        ctx: &GpuContext,
        kernels: &Kernels,
        weights: &GpuWeights,
        (tile_width, tile_height): (usize, usize),
        max_unit_cost: Option<u64>,
    ) -> Result<Self> {
        let input_channels = weights.input_channels;
        let (largest, per_slot) = tensor_floats(input_channels, tile_height, tile_width);
        let limit = max_binding_bytes(&ctx.device.limits());
        if largest as u64 * 4 > limit {
            return Err(Error::Gpu(format!(
                "a {tile_width}x{tile_height} denoise tile needs a {} byte tensor, over the device's largest storage binding ({limit})",
                largest * 4
            )));
        }
        ctx.checked("creating the denoiser's tile buffers", |device| {
            let slots: Vec<wgpu::Buffer> = per_slot
                .iter()
                .map(|&floats| {
                    storage(
                        device,
                        "denoise tensor",
                        floats,
                        wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
                    )
                })
                .collect();
            let pixels = tile_height * tile_width;
            let images = storage(
                device,
                "denoise tile images",
                9 * pixels,
                wgpu::BufferUsages::COPY_DST,
            );
            let out = storage(
                device,
                "denoise tile output",
                OUTPUT_CHANNELS * pixels,
                wgpu::BufferUsages::COPY_SRC,
            );
            let readback = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("denoise readback"),
                size: (per_slot[slot_index(OUTPUT_SLOT)].max(OUTPUT_CHANNELS * pixels) * 4) as u64,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            let pack_params = uniform(device, &PackParams::default());
            let slot = |s: Slot| &slots[slot_index(s)];
            let table = network_dispatches(&weights.layers, input_channels);
            let units = tile_units(
                &table,
                input_channels,
                tile_width,
                tile_height,
                max_unit_cost,
            );
            let network_units = units
                .iter()
                .filter(|u| matches!(u.kind, UnitKind::Dispatch { .. }))
                .count();
            let pack = Dispatch {
                pipeline: kernels.pack.clone(),
                group: bind(
                    device,
                    &kernels.pack,
                    &[&pack_params, &images, slot(Slot::Input)],
                ),
                workgroups: workgroups(tile_width, tile_height, 1),
            };
            let unpack = Dispatch {
                pipeline: kernels.unpack.clone(),
                group: bind(
                    device,
                    &kernels.unpack,
                    &[&pack_params, slot(OUTPUT_SLOT), &out],
                ),
                workgroups: [0, 0, 1],
            };
            TileRun {
                tile_height,
                tile_width,
                input_channels,
                slots,
                images,
                out,
                readback,
                pack_params,
                pack,
                units,
                steps: (0..network_units).map(|_| None).collect(),
                unpack,
                table,
                kernels: [
                    kernels.conv.clone(),
                    kernels.pool.clone(),
                    kernels.upsample.clone(),
                ],
                weights: weights.buffer.clone(),
            }
        })
    }

    /// The run's units, in order.
    pub fn units(&self) -> &[WorkUnit] {
        &self.units
    }

    /// Makes the dispatches of units `range` that have not been made.
    fn make_dispatches(&mut self, ctx: &GpuContext, range: Range<usize>) -> Result<()> {
        let first = self.units[..range.start]
            .iter()
            .filter(|u| matches!(u.kind, UnitKind::Dispatch { .. }))
            .count();
        let wanted: Vec<(usize, u32, u32)> = self.units[range]
            .iter()
            .filter_map(|u| match u.kind {
                UnitKind::Dispatch {
                    index,
                    first_row,
                    rows,
                } => Some((index, first_row, rows)),
                _ => None,
            })
            .collect();
        ctx.checked("making the denoise's dispatches", |device| {
            for (k, dispatch) in wanted.into_iter().enumerate() {
                self.make_dispatch(device, first + k, dispatch);
            }
        })
    }

    /// Makes network unit `step`'s dispatch, rows `first_row ..` (`rows`
    /// of them) of the table's dispatch `index`, unless it is made.
    fn make_dispatch(
        &mut self,
        device: &wgpu::Device,
        step: usize,
        (index, first_row, rows): (usize, u32, u32),
    ) {
        if self.steps[step].is_none() {
            let d = &self.table[index];
            let (tile_width, tile_height) = (self.tile_width, self.tile_height);
            let slot = |s: Slot| &self.slots[slot_index(s)];
            let [x, _, z] = d.workgroups(tile_width, tile_height);
            let workgroups = [x, rows.div_ceil(WORKGROUP), z];
            let [conv, pool, upsample] = &self.kernels;
            let made = match d.kernel {
                DenoiseKernel::Conv => {
                    let params = ConvParams {
                        first_row,
                        ..d.conv_params(tile_width, tile_height)
                    };
                    let params = uniform(device, &params);
                    let block = |offset| {
                        wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                            buffer: &self.weights,
                            offset,
                            size: std::num::NonZeroU64::new(BLOCK_BYTES),
                        })
                    };
                    let [lo, hi] = d.weights_offsets;
                    let resources = [
                        params.as_entire_binding(),
                        block(lo),
                        block(hi),
                        slot(d.src).as_entire_binding(),
                        slot(d.skip.unwrap_or(d.src)).as_entire_binding(),
                        slot(d.dst).as_entire_binding(),
                    ];
                    Dispatch {
                        pipeline: conv.clone(),
                        group: bind_resources(device, conv, resources),
                        workgroups,
                    }
                }
                DenoiseKernel::Pool | DenoiseKernel::Upsample => {
                    let pipeline = match d.kernel {
                        DenoiseKernel::Pool => pool,
                        _ => upsample,
                    };
                    let params = uniform(device, &d.resample_params(tile_width, tile_height));
                    Dispatch {
                        pipeline: pipeline.clone(),
                        group: bind(device, pipeline, &[&params, slot(d.src), slot(d.dst)]),
                        workgroups,
                    }
                }
            };
            self.steps[step] = Some(made);
        }
    }

    /// Runs units `range` of one tile in one submission and waits for
    /// them. A range that starts with the packing uploads `images` (the
    /// source rectangle of each input image in turn, three floats a pixel;
    /// ignored otherwise) and `params`; one
    /// that ends with the unpacking returns the output rectangle
    /// (`params.out_width` x `params.out_height`, three floats a pixel). The
    /// units before `range` must have run on this tile.
    pub fn run_units(
        &mut self,
        ctx: &GpuContext,
        range: Range<usize>,
        images: &[f32],
        params: &PackParams,
    ) -> Result<Option<Vec<f32>>> {
        let floats = params.out_width as usize * params.out_height as usize * OUTPUT_CHANNELS;
        let units = self.units[range.clone()].to_vec();
        let unpacks = units.last().is_some_and(|u| u.kind == UnitKind::Unpack);
        // Network units before the range: the index of its first dispatch.
        let first_step = self.units[..range.start]
            .iter()
            .filter(|u| matches!(u.kind, UnitKind::Dispatch { .. }))
            .count();
        self.make_dispatches(ctx, range)?;
        let count = units
            .iter()
            .filter(|u| matches!(u.kind, UnitKind::Dispatch { .. }))
            .count();
        let made: Vec<&Dispatch> = self.steps[first_step..first_step + count]
            .iter()
            .flatten()
            .collect();
        if made.len() != count {
            return Err(Error::Gpu(
                "a denoise unit's dispatch was not made before its run".into(),
            ));
        }
        let mut made = made.into_iter();
        ctx.checked("running a denoise tile", |device| {
            if units.first().is_some_and(|u| u.kind == UnitKind::Pack) {
                ctx.queue
                    .write_buffer(&self.images, 0, bytemuck::cast_slice(images));
                ctx.queue
                    .write_buffer(&self.pack_params, 0, bytemuck::bytes_of(params));
            }
            let mut encoder = device.create_command_encoder(&Default::default());
            {
                let mut pass = encoder.begin_compute_pass(&Default::default());
                for unit in &units {
                    match unit.kind {
                        UnitKind::Pack => self.pack.record(&mut pass),
                        UnitKind::Dispatch { .. } => {
                            if let Some(dispatch) = made.next() {
                                dispatch.record(&mut pass);
                            }
                        }
                        UnitKind::Unpack => {
                            let groups = workgroups(
                                params.out_width as usize,
                                params.out_height as usize,
                                1,
                            );
                            self.unpack.record_with(&mut pass, groups);
                        }
                    }
                }
            }
            if unpacks {
                encoder.copy_buffer_to_buffer(&self.out, 0, &self.readback, 0, (floats * 4) as u64);
            }
            ctx.queue.submit([encoder.finish()]);
        })?;
        if !unpacks {
            ctx.wait_idle()?;
            return Ok(None);
        }
        let bytes = ctx.read_buffer(&self.readback, (floats * 4) as u64)?;
        Ok(Some(bytemuck::cast_slice(&bytes).to_vec()))
    }

    /// The network alone on an already packed input tensor (tile-sized):
    /// its raw output, [`OUTPUT_CHANNELS`] planes.
    pub fn run_tensor(&mut self, ctx: &GpuContext, input: &Tensor) -> Result<Tensor> {
        if (input.channels, input.height, input.width)
            != (self.input_channels, self.tile_height, self.tile_width)
        {
            return Err(Error::Usage(format!(
                "a {}x{}x{} tensor for a {}x{}x{} network input",
                input.channels,
                input.height,
                input.width,
                self.input_channels,
                self.tile_height,
                self.tile_width
            )));
        }
        let floats = OUTPUT_CHANNELS * self.tile_height * self.tile_width;
        self.make_dispatches(ctx, 0..self.units.len())?;
        ctx.checked("running the denoise network", |device| {
            let input_slot = &self.slots[slot_index(Slot::Input)];
            ctx.queue
                .write_buffer(input_slot, 0, bytemuck::cast_slice(&input.data));
            let mut encoder = device.create_command_encoder(&Default::default());
            {
                let mut pass = encoder.begin_compute_pass(&Default::default());
                for step in self.steps.iter().flatten() {
                    step.record(&mut pass);
                }
            }
            let output = &self.slots[slot_index(OUTPUT_SLOT)];
            encoder.copy_buffer_to_buffer(output, 0, &self.readback, 0, (floats * 4) as u64);
            ctx.queue.submit([encoder.finish()]);
        })?;
        let bytes = ctx.read_buffer(&self.readback, (floats * 4) as u64)?;
        Ok(Tensor {
            channels: OUTPUT_CHANNELS,
            height: self.tile_height,
            width: self.tile_width,
            data: bytemuck::cast_slice(&bytes).to_vec(),
        })
    }
}
