//! The whole denoise on the CPU: the network's steps ([`super::network`])
//! run with the reference layers, and the tiles of an image packed, run
//! and unpacked. Slow (about 125,000 multiply-adds a pixel in f32): the
//! yardstick for the GPU on small images, not a way to denoise.

use super::layers::{conv3x3, max_pool2, upsample2, Tensor};
use super::network::{slot_index, Step, OUTPUT_SLOT, STEPS};
use super::pack::{pack_tile, unpack_tile, DenoiseImages};
use super::tiling::TilePlan;
use super::transfer::autoexposure;
use super::weights::Weights;

/// The network's output for `input` (a packed tile: `weights.input_channels`
/// channels, height and width multiples of 16).
/// The slots it reads are the constant `STEPS`' own, each written by an
/// earlier step (`network::tests::the_steps_wire_oidns_unet`), so the
/// `expect`s below cannot fail on any input.
pub fn run_network(weights: &Weights, input: Tensor) -> Tensor {
    assert_eq!(input.channels, weights.input_channels, "input channels");
    let mut slots: Vec<Option<Tensor>> = vec![None; 6];
    slots[slot_index(super::network::Slot::Input)] = Some(input);
    for step in STEPS {
        let get = |slots: &[Option<Tensor>], s| -> Tensor {
            slots[slot_index(s)].clone().expect("a slot written before")
        };
        let out = match step {
            Step::Conv {
                layer,
                src,
                skip,
                relu,
                ..
            } => {
                let skip = skip.map(|s| get(&slots, s));
                conv3x3(
                    &get(&slots, src),
                    skip.as_ref(),
                    &weights.convs[layer],
                    relu,
                )
            }
            Step::Pool { src, .. } => max_pool2(&get(&slots, src)),
            Step::Upsample { src, .. } => upsample2(&get(&slots, src)),
        };
        slots[slot_index(step.dst())] = Some(out);
    }
    slots[slot_index(OUTPUT_SLOT)].take().expect("the output")
}

/// The input scale of `images`: `given`, or OIDN's autoexposure of the colour.
pub fn input_scale(images: &DenoiseImages<'_>, given: Option<f32>) -> f32 {
    given.unwrap_or_else(|| autoexposure(images.width, images.height, images.color))
}

/// Runs `network` on each tile of `plan` and gathers the denoised image
/// (three floats a pixel).
pub fn denoise_tiles(
    images: &DenoiseImages<'_>,
    plan: &TilePlan,
    input_scale: f32,
    mut network: impl FnMut(Tensor) -> Tensor,
) -> Vec<f32> {
    let mut out = vec![0.0; images.width * images.height * 3];
    for tile in &plan.tiles {
        let input = pack_tile(images, input_scale, tile, plan.tile_height, plan.tile_width);
        let output = network(input);
        unpack_tile(&output, input_scale, tile, images.width, &mut out);
    }
    out
}

/// The denoised image on the CPU, tiles within `max_tensor_bytes`.
pub fn denoise_cpu(
    images: &DenoiseImages<'_>,
    weights: &Weights,
    given_scale: Option<f32>,
    max_tensor_bytes: u64,
) -> Result<Vec<f32>, String> {
    images.check()?;
    if images.input_channels() != weights.input_channels {
        return Err(format!(
            "the images give {} channels, the weights read {}",
            images.input_channels(),
            weights.input_channels
        ));
    }
    let plan = TilePlan::new(
        images.width,
        images.height,
        weights.input_channels,
        max_tensor_bytes,
    );
    let scale = input_scale(images, given_scale);
    Ok(denoise_tiles(images, &plan, scale, |t| {
        run_network(weights, t)
    }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::denoise::layers::concat;
    use crate::denoise::pack::pack_color;

    fn pseudo_tensor(channels: usize, height: usize, width: usize, seed: u32) -> Tensor {
        let mut t = Tensor::zeros(channels, height, width);
        let mut s = seed.wrapping_mul(2_654_435_761) | 1;
        for v in &mut t.data {
            s ^= s << 13;
            s ^= s >> 17;
            s ^= s << 5;
            *v = (s >> 8) as f32 / (1u32 << 24) as f32;
        }
        t
    }

    /// The steps compute OIDN's model.py forward pass, written out here on
    /// its own with stored concatenations.
    #[test]
    fn the_steps_are_the_models_forward_pass() {
        for input_channels in [3, 9] {
            let w = Weights::pseudo_random(input_channels, 11);
            let input = pseudo_tensor(input_channels, 32, 48, 3);
            let conv = |x: &Tensor, i: usize| conv3x3(x, None, &w.convs[i], true);
            let x = conv(&input, 0);
            let pool1 = max_pool2(&conv(&x, 1));
            let pool2 = max_pool2(&conv(&pool1, 2));
            let pool3 = max_pool2(&conv(&pool2, 3));
            let x = max_pool2(&conv(&pool3, 4));
            let x = conv(&conv(&x, 5), 6);
            let x = conv(&conv(&concat(&upsample2(&x), &pool3), 7), 8);
            let x = conv(&conv(&concat(&upsample2(&x), &pool2), 9), 10);
            let x = conv(&conv(&concat(&upsample2(&x), &pool1), 11), 12);
            let x = conv(&conv(&concat(&upsample2(&x), &input), 13), 14);
            let expected = conv3x3(&x, None, &w.convs[15], false);
            let got = run_network(&w, input);
            assert_eq!((got.channels, got.height, got.width), (3, 32, 48));
            assert_eq!(got, expected);
            assert!(
                got.data.iter().any(|&v| v < 0.0),
                "the last layer has no ReLU"
            );
        }
    }

    /// Through a network that returns its colour channels, a tiled
    /// denoise gives the image back: every pixel packed, placed and
    /// unpacked once.
    #[test]
    fn tiles_carry_every_pixel_through() {
        let (w, h) = (700, 330);
        let color: Vec<f32> = (0..w * h * 3)
            .map(|i| ((i * 31) % 97) as f32 * 0.05)
            .collect();
        let images = DenoiseImages {
            width: w,
            height: h,
            color: &color,
            albedo: None,
            normal: None,
        };
        let plan = TilePlan::new(w, h, 3, 20 << 20);
        assert!(plan.tiles.len() >= 3, "{} tiles", plan.tiles.len());
        let scale = input_scale(&images, None);
        let mut runs = 0;
        let out = denoise_tiles(&images, &plan, scale, |t| {
            runs += 1;
            Tensor {
                channels: 3,
                data: t.data[..3 * t.height * t.width].to_vec(),
                ..t
            }
        });
        assert_eq!(runs, plan.tiles.len());
        for (o, c) in out.iter().zip(&color) {
            assert!((o - c).abs() <= 3e-4 * c + 1e-6, "{o} vs {c}");
        }
        assert!(pack_color(1.0, scale) > 0.0);
    }

    #[test]
    fn the_weights_must_match_the_images() {
        let color = vec![0.5f32; 16 * 16 * 3];
        let images = DenoiseImages {
            width: 16,
            height: 16,
            color: &color,
            albedo: None,
            normal: None,
        };
        let w = Weights::pseudo_random(9, 1);
        let error = denoise_cpu(&images, &w, None, u64::MAX).unwrap_err();
        assert!(error.contains("3 channels"), "{error}");
        let w = Weights::pseudo_random(3, 1);
        let out = denoise_cpu(&images, &w, None, u64::MAX).unwrap();
        assert_eq!(out.len(), color.len());
        assert!(out.iter().all(|v| v.is_finite() && *v >= 0.0));
    }
}
