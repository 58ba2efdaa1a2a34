//! A tile's buffers on the GPU (the kernel's output and costs, the
//! readback they are copied to, their bind group) and a band's pixels on
//! the host, filled from each tile's read-back bytes.

use super::bindings;
use super::context::GpuContext;
use super::kernel_io::RayCounters;
use super::render_summary::CostTotals;
use super::scene_buffers::SceneBuffers;
use super::tile_plan::PixelOutput;
use super::trace_pipelines::{TraceBindGroup, TracePipelines};
use crate::error::Result;
use crate::kdtree::traverse::WalkCost;
use crate::scene::ToneMap;

/// Bytes per pixel of the cost output (`bindings::PIXEL_COSTS`).
const COST_BYTES_PER_PIXEL: u64 = bindings::COST_WORDS as u64 * 4;

/// Bytes before the pixels in the output buffer (the ray counters).
const OUTPUT_HEADER_BYTES: u64 = std::mem::size_of::<RayCounters>() as u64;

/// Pixels `x..x + w` of rows `y..y + h`: one tile.
#[derive(Debug, Clone, Copy)]
pub(super) struct TileArea {
    pub(super) x: u32,
    pub(super) y: u32,
    pub(super) w: u32,
    pub(super) h: u32,
}

impl TileArea {
    pub(super) fn pixels(&self) -> u64 {
        self.w as u64 * self.h as u64
    }
}

/// One tile's buffers on the GPU: the kernel's output and costs, the
/// readback they are copied to, and their bind group.
pub(super) struct TileBuffers {
    output: wgpu::Buffer,
    costs: wgpu::Buffer,
    pub(super) readback: wgpu::Buffer,
    pub(super) bind_group: TraceBindGroup,
}

impl TileBuffers {
    /// The buffers for tiles of up to `tile_pixels` pixels, bound with
    /// `params` and `scene` for `pipelines`.
    pub(super) fn new(
        ctx: &GpuContext,
        pipelines: &TracePipelines,
        params: &wgpu::Buffer,
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
            let bind_group = pipelines.bind_group(device, params, scene, &[&output, &costs]);
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
    pub(super) fn clear(
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

    pub(super) fn copy_to_readback(
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

    pub(super) fn read_bytes(&self, area: TileArea, costs: bool, output: PixelOutput) -> u64 {
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
pub(super) struct BandBuffers {
    pub(super) rgb: Vec<u8>,
    pub(super) costs: Vec<WalkCost>,
    /// Mean linear RGB per pixel (radiance output).
    pub(super) radiance: Vec<f32>,
    /// Mean albedo and normal per pixel (feature output).
    pub(super) albedo: Vec<f32>,
    pub(super) normal: Vec<f32>,
    /// The last tile's ray counters.
    pub(super) counters: RayCounters,
}

impl BandBuffers {
    pub(super) fn reset(&mut self, width: u32, rows: u32, costs: bool, output: PixelOutput) {
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
    pub(super) fn take_tile(
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
    pub(super) fn take_costs(
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
