//! The CPU reference of each layer kind, in plain f32: slow and simple,
//! the yardstick for the GPU kernels and for the whole network on small
//! images. Tensors are planar CHW (`data[(c * height + y) * width + x]`).

use super::weights::ConvWeights;

/// A stack of `channels` planes of `height` x `width` floats.
#[derive(Clone, Debug, PartialEq)]
pub struct Tensor {
    pub channels: usize,
    pub height: usize,
    pub width: usize,
    pub data: Vec<f32>,
}

impl Tensor {
    pub fn zeros(channels: usize, height: usize, width: usize) -> Self {
        Tensor {
            channels,
            height,
            width,
            data: vec![0.0; channels * height * width],
        }
    }

    pub fn at(&self, c: usize, y: usize, x: usize) -> f32 {
        self.data[(c * self.height + y) * self.width + x]
    }

    fn plane(&self, c: usize) -> &[f32] {
        let n = self.height * self.width;
        &self.data[c * n..(c + 1) * n]
    }
}

/// The channels of `a` followed by those of `b` (same height and width).
pub fn concat(a: &Tensor, b: &Tensor) -> Tensor {
    assert_eq!((a.height, a.width), (b.height, b.width), "concat sizes");
    let mut data = a.data.clone();
    data.extend_from_slice(&b.data);
    Tensor {
        channels: a.channels + b.channels,
        height: a.height,
        width: a.width,
        data,
    }
}

/// 3x3 convolution, zero padding of one pixel, stride 1, plus bias, then
/// ReLU if `relu`. The input is `src`'s channels followed by `skip`'s (a
/// concatenation never stored); `w.in_channels` must be their sum.
pub fn conv3x3(src: &Tensor, skip: Option<&Tensor>, w: &ConvWeights, relu: bool) -> Tensor {
    let (h, wd) = (src.height, src.width);
    let inputs: Vec<&[f32]> = (0..src.channels)
        .map(|c| src.plane(c))
        .chain(skip.into_iter().flat_map(|s| {
            assert_eq!((s.height, s.width), (h, wd), "skip sizes");
            (0..s.channels).map(move |c| s.plane(c))
        }))
        .collect();
    assert_eq!(inputs.len(), w.in_channels, "input channels");
    let mut out = Tensor::zeros(w.out_channels, h, wd);
    let n = h * wd;
    for (o, plane) in out.data.chunks_exact_mut(n).enumerate() {
        plane.fill(w.bias[o]);
        for (i, input) in inputs.iter().enumerate() {
            for ky in 0..3 {
                for kx in 0..3 {
                    let k = w.weight[((o * w.in_channels + i) * 3 + ky) * 3 + kx];
                    // Output pixels whose tap (y + ky - 1, x + kx - 1) is inside.
                    let (y0, y1) = (1usize.saturating_sub(ky), (h + 1 - ky).min(h));
                    let (x0, x1) = (1usize.saturating_sub(kx), (wd + 1 - kx).min(wd));
                    for y in y0..y1 {
                        let sy = y + ky - 1;
                        let row = &input[sy * wd + x0 + kx - 1..sy * wd + x1 + kx - 1];
                        for (d, s) in plane[y * wd + x0..y * wd + x1].iter_mut().zip(row) {
                            *d += k * s;
                        }
                    }
                }
            }
        }
        if relu {
            plane.iter_mut().for_each(|v| *v = v.max(0.0));
        }
    }
    out
}

/// 2x2 max pooling with stride 2 (height and width even).
pub fn max_pool2(src: &Tensor) -> Tensor {
    let (h, w) = (src.height / 2, src.width / 2);
    let mut out = Tensor::zeros(src.channels, h, w);
    for c in 0..src.channels {
        for y in 0..h {
            for x in 0..w {
                let m = src
                    .at(c, 2 * y, 2 * x)
                    .max(src.at(c, 2 * y, 2 * x + 1))
                    .max(src.at(c, 2 * y + 1, 2 * x))
                    .max(src.at(c, 2 * y + 1, 2 * x + 1));
                out.data[(c * h + y) * w + x] = m;
            }
        }
    }
    out
}

/// 2x nearest-neighbour upsampling: each value becomes a 2x2 block.
pub fn upsample2(src: &Tensor) -> Tensor {
    let (h, w) = (src.height * 2, src.width * 2);
    let mut out = Tensor::zeros(src.channels, h, w);
    for c in 0..src.channels {
        for y in 0..h {
            for x in 0..w {
                out.data[(c * h + y) * w + x] = src.at(c, y / 2, x / 2);
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ramp(channels: usize, height: usize, width: usize) -> Tensor {
        let mut t = Tensor::zeros(channels, height, width);
        for (i, v) in t.data.iter_mut().enumerate() {
            *v = ((i * 7919) % 101) as f32 / 50.0 - 1.0;
        }
        t
    }

    /// A kernel that is 1 at the centre for (o, o) and 0 elsewhere.
    fn identity(channels: usize, bias: f32) -> ConvWeights {
        let mut weight = vec![0.0; channels * channels * 9];
        for o in 0..channels {
            weight[(o * channels + o) * 9 + 4] = 1.0;
        }
        ConvWeights {
            out_channels: channels,
            in_channels: channels,
            weight,
            bias: vec![bias; channels],
        }
    }

    #[test]
    fn an_identity_kernel_copies_its_input_plus_the_bias() {
        let src = ramp(3, 5, 7);
        let out = conv3x3(&src, None, &identity(3, 0.5), false);
        for (o, s) in out.data.iter().zip(&src.data) {
            assert_eq!(*o, s + 0.5);
        }
        let relu = conv3x3(&src, None, &identity(3, 0.0), true);
        for (o, s) in relu.data.iter().zip(&src.data) {
            assert_eq!(*o, s.max(0.0));
        }
    }

    /// A kernel of ones sums the 3x3 neighbourhood; at a corner only four
    /// pixels are inside (zero padding).
    #[test]
    fn a_box_kernel_sums_the_neighbourhood_with_zero_padding() {
        let src = Tensor {
            channels: 1,
            height: 3,
            width: 4,
            data: vec![1.0; 12],
        };
        let w = ConvWeights {
            out_channels: 1,
            in_channels: 1,
            weight: vec![1.0; 9],
            bias: vec![0.0],
        };
        let out = conv3x3(&src, None, &w, false);
        assert_eq!(out.at(0, 0, 0), 4.0);
        assert_eq!(out.at(0, 0, 1), 6.0);
        assert_eq!(out.at(0, 1, 1), 9.0);
        assert_eq!(out.at(0, 2, 3), 4.0);
    }

    /// A shifted tap moves the image by one pixel: the kernel's (ky, kx)
    /// index reads (y + ky - 1, x + kx - 1), as PyTorch's Conv2d does.
    #[test]
    fn a_tap_reads_the_neighbour_it_names() {
        let src = ramp(1, 4, 5);
        let mut weight = vec![0.0; 9];
        weight[5] = 1.0; // ky = 1, kx = 2: the right neighbour
        let w = ConvWeights {
            out_channels: 1,
            in_channels: 1,
            weight,
            bias: vec![0.0],
        };
        let out = conv3x3(&src, None, &w, false);
        for y in 0..4 {
            for x in 0..5 {
                let expected = if x + 1 < 5 { src.at(0, y, x + 1) } else { 0.0 };
                assert_eq!(out.at(0, y, x), expected);
            }
        }
    }

    /// Reading a skip tensor is the same as convolving the concatenation.
    #[test]
    fn a_skip_input_is_a_concatenation() {
        let (a, b) = (ramp(2, 6, 4), ramp(3, 6, 4));
        let w = ConvWeights {
            out_channels: 4,
            in_channels: 5,
            weight: (0..4 * 5 * 9).map(|i| (i as f32 * 0.37).sin()).collect(),
            bias: vec![0.1, -0.2, 0.3, 0.0],
        };
        let joined = concat(&a, &b);
        assert_eq!(joined.channels, 5);
        assert_eq!(joined.at(3, 2, 1), b.at(1, 2, 1));
        assert_eq!(
            conv3x3(&a, Some(&b), &w, true),
            conv3x3(&joined, None, &w, true)
        );
    }

    #[test]
    fn pooling_takes_each_blocks_maximum_and_upsampling_repeats_it() {
        let src = Tensor {
            channels: 1,
            height: 2,
            width: 4,
            data: vec![1.0, 5.0, -3.0, -4.0, 2.0, 0.0, -1.0, -2.0],
        };
        let pooled = max_pool2(&src);
        assert_eq!(pooled.data, [5.0, -1.0]);
        let up = upsample2(&pooled);
        assert_eq!((up.height, up.width), (2, 4));
        assert_eq!(up.data, [5.0, 5.0, -1.0, -1.0, 5.0, 5.0, -1.0, -1.0]);
        let back = max_pool2(&upsample2(&ramp(2, 3, 5)));
        assert_eq!(back, ramp(2, 3, 5));
    }
}
