//! The network's dispatches on a tile, as a table: for each of
//! [`kdray_core::denoise::network::STEPS`] in turn, its kernel, the slots
//! it reads and writes, its parameters and, for a convolution, one row per
//! sixteen outputs with the byte offsets of their two weights blocks. Sizes are relative to the tile: a row's image is the tile's size
//! divided by 2^level. [`super::tile_run::TileRun`] records its pass from
//! this table, and `kdray web` writes the same table into the site's
//! contract for the page, so the two run the same dispatches.

use bytemuck::{Pod, Zeroable};
use kdray_core::denoise::network::{step_channels, Slot, Step, STEPS};

use super::gpu_weights::LayerBlocks;
use super::kernels::{CONV_GROUP, CONV_OUTPUTS, CONV_PIXELS, WORKGROUP};

/// conv.wgsl's `ConvParams`.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct ConvParams {
    pub width: u32,
    pub height: u32,
    pub src_channels: u32,
    pub skip_channels: u32,
    pub out_channels: u32,
    pub first_output: u32,
    pub relu: u32,
    /// The first row of the band a dispatch computes (0: from the top).
    pub first_row: u32,
}

/// resample.wgsl's `ResampleParams` (the output's size).
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct ResampleParams {
    pub width: u32,
    pub height: u32,
    pub channels: u32,
    pub pad: u32,
}

/// The kernel of a dispatch (shaders/denoise/).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DenoiseKernel {
    /// conv.wgsl's `conv3x3`.
    Conv,
    /// resample.wgsl's `max_pool2`.
    Pool,
    /// resample.wgsl's `upsample2`.
    Upsample,
}

impl DenoiseKernel {
    /// The WGSL entry point.
    pub fn entry_point(self) -> &'static str {
        match self {
            DenoiseKernel::Conv => "conv3x3",
            DenoiseKernel::Pool => "max_pool2",
            DenoiseKernel::Upsample => "upsample2",
        }
    }

    /// Its file of shaders/denoise/, by name: `conv` or `resample`.
    pub fn shader(self) -> &'static str {
        match self {
            DenoiseKernel::Conv => "conv",
            _ => "resample",
        }
    }
}

/// One dispatch of the network.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StepDispatch {
    pub kernel: DenoiseKernel,
    /// The step of [`STEPS`] it belongs to.
    pub step: usize,
    /// What it writes is the tile's size divided by 2^level.
    pub level: u32,
    pub src: Slot,
    /// A convolution's second input (None: `src` is bound in its place).
    pub skip: Option<Slot>,
    pub dst: Slot,
    /// Channels read from `src` and `skip` (a convolution).
    pub src_channels: u32,
    pub skip_channels: u32,
    /// Channels written: a convolution's layer's outputs (all groups), a
    /// resampling's channels.
    pub out_channels: u32,
    /// A convolution's layer, its first output (a multiple of sixteen) and
    /// where the weights blocks of its two groups of eight outputs start in
    /// the weights buffer (bytes; the same block twice where the layer's
    /// last group is alone: its second half is padding).
    pub layer: usize,
    pub first_output: u32,
    pub weights_offsets: [u64; 2],
    pub relu: bool,
}

impl StepDispatch {
    /// The size (width, height) it writes for a tile of `tile_width` x
    /// `tile_height`.
    pub fn size(&self, tile_width: usize, tile_height: usize) -> (u32, u32) {
        (
            (tile_width >> self.level) as u32,
            (tile_height >> self.level) as u32,
        )
    }

    /// conv.wgsl's parameters (a convolution).
    pub fn conv_params(&self, tile_width: usize, tile_height: usize) -> ConvParams {
        let (width, height) = self.size(tile_width, tile_height);
        ConvParams {
            width,
            height,
            src_channels: self.src_channels,
            skip_channels: self.skip_channels,
            out_channels: self.out_channels,
            first_output: self.first_output,
            relu: u32::from(self.relu),
            first_row: 0,
        }
    }

    /// resample.wgsl's parameters (a pooling or an upsampling).
    pub fn resample_params(&self, tile_width: usize, tile_height: usize) -> ResampleParams {
        let (width, height) = self.size(tile_width, tile_height);
        ResampleParams {
            width,
            height,
            channels: self.out_channels,
            pad: 0,
        }
    }

    /// Pixels of a row one invocation writes: a convolution's
    /// [`CONV_PIXELS`], a resampling's one.
    pub fn columns_per_invocation(&self) -> u32 {
        match self.kernel {
            DenoiseKernel::Conv => CONV_PIXELS,
            _ => 1,
        }
    }

    /// Workgroups (8 x 8 x 1 invocations each): the image it writes, and
    /// for a resampling one layer per channel.
    pub fn workgroups(&self, tile_width: usize, tile_height: usize) -> [u32; 3] {
        let (width, height) = self.size(tile_width, tile_height);
        let z = match self.kernel {
            DenoiseKernel::Conv => 1,
            _ => self.out_channels,
        };
        let columns = WORKGROUP * self.columns_per_invocation();
        [width.div_ceil(columns), height.div_ceil(WORKGROUP), z]
    }
}

/// The dispatches of the network reading `input_channels`, its weights
/// laid out as `layers` say.
pub fn network_dispatches(layers: &[LayerBlocks], input_channels: usize) -> Vec<StepDispatch> {
    let mut held = [0usize; Slot::ALL.len()];
    held[Slot::Input as usize] = input_channels;
    let mut out = Vec::new();
    for (index, (step, channels)) in STEPS.iter().zip(step_channels(input_channels)).enumerate() {
        let row = |kernel, src: Slot| StepDispatch {
            kernel,
            step: index,
            level: step.level(),
            src,
            skip: None,
            dst: step.dst(),
            src_channels: held[src as usize] as u32,
            skip_channels: 0,
            out_channels: channels as u32,
            layer: 0,
            first_output: 0,
            weights_offsets: [0, 0],
            relu: false,
        };
        match *step {
            Step::Conv {
                layer,
                src,
                skip,
                relu,
                ..
            } => {
                let blocks = &layers[layer];
                let pairs = blocks.group_offsets.chunks(CONV_OUTPUTS / CONV_GROUP);
                for (k, pair) in pairs.enumerate() {
                    out.push(StepDispatch {
                        skip,
                        skip_channels: skip.map_or(0, |s| held[s as usize]) as u32,
                        out_channels: blocks.out_channels,
                        layer,
                        first_output: (k * CONV_OUTPUTS) as u32,
                        weights_offsets: [pair[0], pair[pair.len() - 1]],
                        relu,
                        ..row(DenoiseKernel::Conv, src)
                    });
                }
            }
            Step::Pool { src, .. } => out.push(row(DenoiseKernel::Pool, src)),
            Step::Upsample { src, .. } => out.push(row(DenoiseKernel::Upsample, src)),
        }
        held[step.dst() as usize] = channels;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use kdray_core::denoise::network::{conv_input_channels, CONV_LAYERS};

    /// Every layer's groups run in order at its step, reading the channels
    /// OIDN's model gives the layer, and each resampling keeps its channels.
    #[test]
    fn the_table_runs_every_group_of_every_step() {
        let layers: Vec<LayerBlocks> = CONV_LAYERS
            .iter()
            .zip(conv_input_channels(9))
            .map(|(l, ic)| LayerBlocks {
                out_channels: l.out_channels as u32,
                in_channels: ic as u32,
                group_offsets: (0..l.out_channels.div_ceil(8))
                    .map(|g| 1000 * g as u64)
                    .collect(),
            })
            .collect();
        let table = network_dispatches(&layers, 9);
        let pairs: usize = CONV_LAYERS
            .iter()
            .map(|l| l.out_channels.div_ceil(16))
            .sum();
        assert_eq!(
            table.len(),
            pairs + 8,
            "16 layers' sixteen-output dispatches, 4 pools, 4 upsamplings"
        );
        for d in &table {
            if d.kernel == DenoiseKernel::Conv {
                assert_eq!(
                    d.src_channels + d.skip_channels,
                    layers[d.layer].in_channels,
                    "{d:?}"
                );
                assert_eq!(d.first_output % 16, 0, "{d:?}");
                let lo = d.first_output as usize / 8;
                let last = layers[d.layer].group_offsets.len() - 1;
                let expected = [1000 * lo as u64, 1000 * (lo + 1).min(last) as u64];
                assert_eq!(d.weights_offsets, expected, "{d:?}");
                assert_eq!(d.relu, d.layer != 15);
            } else {
                assert_eq!(d.src_channels, d.out_channels, "{d:?}");
            }
        }
        let steps: Vec<usize> = table.iter().map(|d| d.step).collect();
        assert!(steps.windows(2).all(|w| w[1] == w[0] || w[1] == w[0] + 1));
        assert_eq!(steps.last(), Some(&(STEPS.len() - 1)));
        let pool = table
            .iter()
            .find(|d| d.kernel == DenoiseKernel::Pool)
            .unwrap();
        assert_eq!(pool.workgroups(64, 48), [4, 3, 32]);
        let conv = &table[0];
        assert_eq!(
            conv.workgroups(64, 48),
            [1, 6, 1],
            "eight pixels an invocation"
        );
        assert_eq!(conv.workgroups(80, 48), [2, 6, 1]);
    }
}
