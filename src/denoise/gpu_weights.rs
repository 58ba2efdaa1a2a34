//! A network's weights laid out for shaders/denoise/conv.wgsl and uploaded
//! once: every layer's weights grouped by eight output channels (the
//! invocation's vec4 pair), its biases after them, all layers in one
//! storage buffer (about 3.7 MB for OIDN's RT networks).

use kdray_core::denoise::{ConvWeights, Weights};

use super::kernels::CONV_GROUP;
use crate::error::{Error, Result};
use crate::gpu::context::buffer_holding;
use crate::gpu::{max_binding_bytes, GpuContext};

/// Where one layer's weights and biases start in the buffer, in vec4s.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LayerOffsets {
    pub weight_offset: u32,
    pub bias_offset: u32,
    pub out_channels: u32,
    pub in_channels: u32,
}

/// The output channel groups of a layer of `out_channels`.
pub fn groups(out_channels: usize) -> usize {
    out_channels.div_ceil(CONV_GROUP)
}

/// Appends one layer in conv.wgsl's order to `floats` (whose length is a
/// multiple of 4) and returns its offsets: for group g, input channel i,
/// tap t, the eight weights of outputs 8g..8g+7 (zero past the last),
/// then the biases likewise.
pub fn append_layer(floats: &mut Vec<f32>, conv: &ConvWeights) -> LayerOffsets {
    let (oc, ic) = (conv.out_channels, conv.in_channels);
    let weight_offset = floats.len() / 4;
    for g in 0..groups(oc) {
        for i in 0..ic {
            for t in 0..9 {
                for k in 0..CONV_GROUP {
                    let o = g * CONV_GROUP + k;
                    floats.push(if o < oc {
                        conv.weight[(o * ic + i) * 9 + t]
                    } else {
                        0.0
                    });
                }
            }
        }
    }
    let bias_offset = floats.len() / 4;
    for o in 0..groups(oc) * CONV_GROUP {
        floats.push(conv.bias.get(o).copied().unwrap_or(0.0));
    }
    LayerOffsets {
        weight_offset: weight_offset as u32,
        bias_offset: bias_offset as u32,
        out_channels: oc as u32,
        in_channels: ic as u32,
    }
}

/// A network's weights on the GPU.
pub struct GpuWeights {
    pub input_channels: usize,
    pub layers: Vec<LayerOffsets>,
    pub buffer: wgpu::Buffer,
}

impl GpuWeights {
    pub fn upload(ctx: &GpuContext, weights: &Weights) -> Result<Self> {
        let mut floats = Vec::new();
        let layers: Vec<LayerOffsets> = weights
            .convs
            .iter()
            .map(|conv| append_layer(&mut floats, conv))
            .collect();
        Self::upload_floats(ctx, weights.input_channels, layers, &floats)
    }

    /// One layer alone (the layer tests).
    pub fn upload_layer(ctx: &GpuContext, conv: &ConvWeights) -> Result<Self> {
        let mut floats = Vec::new();
        let layer = append_layer(&mut floats, conv);
        Self::upload_floats(ctx, conv.in_channels, vec![layer], &floats)
    }

    fn upload_floats(
        ctx: &GpuContext,
        input_channels: usize,
        layers: Vec<LayerOffsets>,
        floats: &[f32],
    ) -> Result<Self> {
        let bytes: &[u8] = bytemuck::cast_slice(floats);
        let limit = max_binding_bytes(&ctx.device.limits());
        if bytes.len() as u64 > limit {
            return Err(Error::Gpu(format!(
                "the denoiser's weights take {} bytes, over the device's largest storage binding ({limit})",
                bytes.len()
            )));
        }
        let buffer = ctx.checked("uploading the denoiser's weights", |device| {
            buffer_holding(
                device,
                "denoise weights",
                bytes,
                wgpu::BufferUsages::STORAGE,
            )
        })?;
        Ok(GpuWeights {
            input_channels,
            layers,
            buffer,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each weight lands where conv.wgsl reads it, padding outputs are
    /// zero, and layers follow each other.
    #[test]
    fn weights_are_grouped_by_eight_outputs() {
        let conv = ConvWeights {
            out_channels: 11,
            in_channels: 2,
            weight: (0..11 * 2 * 9).map(|i| i as f32 + 1.0).collect(),
            bias: (0..11).map(|i| -(i as f32)).collect(),
        };
        let mut floats = vec![0.0; 4];
        let offsets = append_layer(&mut floats, &conv);
        assert_eq!(offsets.weight_offset, 1);
        let at = |g: usize, i: usize, t: usize, k: usize| {
            floats[offsets.weight_offset as usize * 4 + ((g * 2 + i) * 9 + t) * 8 + k]
        };
        for o in 0..11 {
            for i in 0..2 {
                for t in 0..9 {
                    assert_eq!(at(o / 8, i, t, o % 8), conv.weight[(o * 2 + i) * 9 + t]);
                }
            }
        }
        assert_eq!(at(1, 1, 8, 3), 0.0, "output 11 is padding");
        let bias = offsets.bias_offset as usize * 4;
        assert_eq!(bias, 4 + 2 * 2 * 9 * 8);
        assert_eq!(floats[bias + 10], -10.0);
        assert_eq!(floats[bias + 15], 0.0);
        assert_eq!(floats.len(), bias + 16);
    }
}
