//! A network's weights laid out for shaders/denoise/conv.wgsl and uploaded
//! once: for each layer and each group of eight output channels, a block
//! of the group's biases and weights that the convolution binds as a
//! uniform buffer of [`BLOCK_BYTES`] at the block's offset (two blocks a
//! dispatch: sixteen outputs). All blocks of a
//! network share one buffer (about 3.7 MB for OIDN's RT networks).

use kdray_core::denoise::{ConvWeights, Weights};

use super::kernels::CONV_GROUP;
use crate::error::{Error, Result};
use crate::gpu::context::buffer_holding;
use crate::gpu::GpuContext;

/// The size of conv.wgsl's uniform weights array (4096 vec4s): WebGPU's
/// smallest guaranteed uniform binding.
pub const BLOCK_BYTES: u64 = 64 << 10;

/// One layer's groups: where each group's block starts, in bytes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LayerBlocks {
    pub out_channels: u32,
    pub in_channels: u32,
    pub group_offsets: Vec<u64>,
}

/// The output channel groups of a layer of `out_channels`.
pub fn groups(out_channels: usize) -> usize {
    out_channels.div_ceil(CONV_GROUP)
}

/// Appends one layer's blocks to `floats`, each starting at a multiple of
/// `align` bytes: for group g, the biases of outputs 8g..8g+7, then for
/// input channel i and tap t their eight weights (zero past the last
/// output). Fails if a block would not fit [`BLOCK_BYTES`].
pub fn append_layer(floats: &mut Vec<f32>, conv: &ConvWeights, align: u64) -> Result<LayerBlocks> {
    let (oc, ic) = (conv.out_channels, conv.in_channels);
    let block_floats = CONV_GROUP * (1 + ic * 9);
    if (block_floats * 4) as u64 > BLOCK_BYTES {
        return Err(Error::Gpu(format!(
            "a convolution reading {ic} channels needs {} bytes of weights per group, over {BLOCK_BYTES}",
            block_floats * 4
        )));
    }
    let align_floats = (align.max(16) / 4) as usize;
    let mut group_offsets = Vec::new();
    for g in 0..groups(oc) {
        floats.resize(floats.len().div_ceil(align_floats) * align_floats, 0.0);
        group_offsets.push(floats.len() as u64 * 4);
        let output = |k: usize| g * CONV_GROUP + k;
        for k in 0..CONV_GROUP {
            floats.push(conv.bias.get(output(k)).copied().unwrap_or(0.0));
        }
        for i in 0..ic {
            for t in 0..9 {
                for k in 0..CONV_GROUP {
                    let o = output(k);
                    floats.push(if o < oc {
                        conv.weight[(o * ic + i) * 9 + t]
                    } else {
                        0.0
                    });
                }
            }
        }
    }
    Ok(LayerBlocks {
        out_channels: oc as u32,
        in_channels: ic as u32,
        group_offsets,
    })
}

/// A network's weights as they are uploaded: the bytes of the one buffer
/// (every block at a multiple of the alignment, and room for the last
/// block's whole binding) and each layer's block offsets. The web page's
/// `denoise.bin` is these bytes for WebGPU's largest offset alignment.
#[derive(Clone, Debug, PartialEq)]
pub struct WeightsLayout {
    pub bytes: Vec<u8>,
    pub layers: Vec<LayerBlocks>,
}

impl WeightsLayout {
    /// `convs` laid out with blocks at multiples of `align` bytes.
    pub fn new(convs: &[ConvWeights], align: u64) -> Result<Self> {
        let mut floats = Vec::new();
        let layers = convs
            .iter()
            .map(|conv| append_layer(&mut floats, conv, align))
            .collect::<Result<Vec<_>>>()?;
        // The last block's binding is BLOCK_BYTES long too.
        let end = layers
            .iter()
            .flat_map(|l| l.group_offsets.iter())
            .max()
            .map_or(0, |o| o + BLOCK_BYTES);
        floats.resize(floats.len().max((end / 4) as usize), 0.0);
        Ok(WeightsLayout {
            bytes: bytemuck::cast_slice(&floats).to_vec(),
            layers,
        })
    }
}

/// A network's weights on the GPU.
pub struct GpuWeights {
    pub input_channels: usize,
    pub layers: Vec<LayerBlocks>,
    pub buffer: wgpu::Buffer,
}

impl GpuWeights {
    pub fn upload(ctx: &GpuContext, weights: &Weights) -> Result<Self> {
        Self::upload_layers(ctx, weights.input_channels, &weights.convs)
    }

    /// One layer alone (the layer tests).
    pub fn upload_layer(ctx: &GpuContext, conv: &ConvWeights) -> Result<Self> {
        Self::upload_layers(ctx, conv.in_channels, std::slice::from_ref(conv))
    }

    fn upload_layers(
        ctx: &GpuContext,
        input_channels: usize,
        convs: &[ConvWeights],
    ) -> Result<Self> {
        let limits = ctx.device.limits();
        if limits.max_uniform_buffer_binding_size < BLOCK_BYTES {
            return Err(Error::Gpu(format!(
                "the denoiser binds {BLOCK_BYTES}-byte uniform buffers; the device allows {}",
                limits.max_uniform_buffer_binding_size
            )));
        }
        let align = u64::from(limits.min_uniform_buffer_offset_alignment);
        let WeightsLayout { bytes, layers } = WeightsLayout::new(convs, align)?;
        let buffer = ctx.checked("uploading the denoiser's weights", |device| {
            buffer_holding(
                device,
                "denoise weights",
                &bytes,
                wgpu::BufferUsages::UNIFORM,
            )
        })?;
        Ok(GpuWeights {
            input_channels,
            layers,
            buffer,
        })
    }

    /// The uniform binding of the block at byte `offset` (one of the
    /// layers' `group_offsets`).
    pub fn block(&self, offset: u64) -> wgpu::BindingResource<'_> {
        wgpu::BindingResource::Buffer(wgpu::BufferBinding {
            buffer: &self.buffer,
            offset,
            size: std::num::NonZeroU64::new(BLOCK_BYTES),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each weight lands where conv.wgsl reads it, padding outputs are
    /// zero, and blocks start aligned.
    #[test]
    fn weights_are_grouped_by_eight_outputs() {
        let conv = ConvWeights {
            out_channels: 11,
            in_channels: 2,
            weight: (0..11 * 2 * 9).map(|i| i as f32 + 1.0).collect(),
            bias: (0..11).map(|i| -(i as f32)).collect(),
        };
        let mut floats = vec![0.0; 4];
        let blocks = append_layer(&mut floats, &conv, 256).unwrap();
        assert_eq!(blocks.group_offsets, [256, 256 + 768]);
        let at = |g: usize, vec4: usize, lane: usize| {
            floats[blocks.group_offsets[g] as usize / 4 + vec4 * 4 + lane]
        };
        for o in 0..11 {
            let (g, k) = (o / 8, o % 8);
            assert_eq!(at(g, k / 4, k % 4), conv.bias[o]);
            for i in 0..2 {
                for t in 0..9 {
                    // conv.wgsl: vec4s 2 + (i * 9 + t) * 2 and the next.
                    let v = 2 + (i * 9 + t) * 2 + k / 4;
                    assert_eq!(at(g, v, k % 4), conv.weight[(o * 2 + i) * 9 + t]);
                }
            }
        }
        assert_eq!(at(1, 2 + 17 * 2 + 1, 3), 0.0, "output 15 is padding");
        assert_eq!(at(1, 1, 3), 0.0);
        let too_wide = ConvWeights {
            out_channels: 8,
            in_channels: 300,
            weight: vec![0.0; 8 * 300 * 9],
            bias: vec![0.0; 8],
        };
        assert!(append_layer(&mut floats, &too_wide, 256).is_err());
    }
}
