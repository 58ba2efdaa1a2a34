//! The denoiser's WGSL kernels against the CPU reference
//! (kdray_core::denoise): each layer kind on pseudo-random tensors, the
//! whole network on a small tensor, and a whole denoise of a small image
//! with the shipped networks, with and without albedo and normal, run
//! whole and a few units at a time.

use crate::common;

use kdray::denoise::{shipped_weights, Denoiser};
use kdray_core::denoise::cpu_net::run_network;
use kdray_core::denoise::layers::{conv3x3, max_pool2, upsample2, Tensor};
use kdray_core::denoise::{denoise_cpu, ConvWeights, DenoiseImages, Weights};

/// Values in [-1, 1) from a fixed xorshift sequence.
fn pseudo(n: usize, seed: u32) -> Vec<f32> {
    let mut s = seed.wrapping_mul(2_654_435_761) | 1;
    (0..n)
        .map(|_| {
            s ^= s << 13;
            s ^= s >> 17;
            s ^= s << 5;
            (s >> 8) as f32 / (1u32 << 23) as f32 - 1.0
        })
        .collect()
}

fn tensor(channels: usize, height: usize, width: usize, seed: u32) -> Tensor {
    Tensor {
        channels,
        height,
        width,
        data: pseudo(channels * height * width, seed),
    }
}

/// Every value of `gpu` within `rel` of `cpu`'s, relative to the largest
/// magnitude of `cpu` (sums of hundreds of terms in another order).
fn assert_close(gpu: &[f32], cpu: &[f32], rel: f32, what: &str) {
    assert_eq!(gpu.len(), cpu.len(), "{what}: lengths");
    let scale = cpu.iter().fold(0.0f32, |m, v| m.max(v.abs())).max(1e-12);
    let (worst, at) = gpu
        .iter()
        .zip(cpu)
        .map(|(g, c)| (g - c).abs())
        .enumerate()
        .fold(
            (0.0f32, 0),
            |(w, wi), (i, d)| if d > w { (d, i) } else { (w, wi) },
        );
    assert!(
        worst <= rel * scale,
        "{what}: value {at} is {} on the GPU and {} on the CPU (scale {scale})",
        gpu[at],
        cpu[at]
    );
}

#[test]
fn convolutions_equal_the_cpu_reference() {
    let denoiser = Denoiser::new(common::gpu()).unwrap();
    // Odd sizes (partial workgroups and partial runs of eight pixels), a
    // partial output group (11 of 16), a last group of eight alone (20),
    // with and without a skip input, with and without ReLU.
    for (src_c, skip_c, out_c, h, w, relu) in [
        (5, 0, 11, 13, 9, true),
        (3, 2, 20, 5, 70, true),
        (7, 4, 8, 6, 17, false),
        (32, 9, 64, 16, 16, true),
        (1, 1, 3, 1, 1, false),
    ] {
        let src = tensor(src_c, h, w, 1 + src_c as u32);
        let skip = (skip_c > 0).then(|| tensor(skip_c, h, w, 99));
        let weights = ConvWeights {
            out_channels: out_c,
            in_channels: src_c + skip_c,
            weight: pseudo(out_c * (src_c + skip_c) * 9, 7),
            bias: pseudo(out_c, 8),
        };
        let cpu = conv3x3(&src, skip.as_ref(), &weights, relu);
        let gpu = denoiser
            .gpu_conv3x3(&src, skip.as_ref(), &weights, relu)
            .unwrap();
        assert_eq!((gpu.channels, gpu.height, gpu.width), (out_c, h, w));
        assert_close(
            &gpu.data,
            &cpu.data,
            1e-4,
            &format!("conv {src_c}+{skip_c}->{out_c} {w}x{h}"),
        );
        if relu {
            assert!(cpu.data.contains(&0.0), "ReLU clipped nothing");
        }
    }
}

#[test]
fn pooling_and_upsampling_equal_the_cpu_reference() {
    let denoiser = Denoiser::new(common::gpu()).unwrap();
    for (c, h, w) in [(3, 10, 14), (17, 32, 8), (1, 2, 2)] {
        let src = tensor(c, h, w, 5);
        let pooled = denoiser.gpu_max_pool2(&src).unwrap();
        assert_eq!(pooled, max_pool2(&src), "pool {c}x{h}x{w}");
        let up = denoiser.gpu_upsample2(&src).unwrap();
        assert_eq!(up, upsample2(&src), "upsample {c}x{h}x{w}");
    }
}

/// The 24 steps on the GPU, in one pass over the slot buffers, give the CPU
/// network's output, for both input widths.
#[test]
fn the_whole_network_equals_the_cpu_reference() {
    let denoiser = Denoiser::new(common::gpu()).unwrap();
    for input_channels in [3, 9] {
        let weights = Weights::pseudo_random(input_channels, 3);
        let mut input = tensor(input_channels, 32, 48, 4);
        input.data.iter_mut().for_each(|v| *v = v.abs());
        let cpu = run_network(&weights, input.clone());
        let network = denoiser.upload(&weights).unwrap();
        let gpu = denoiser.gpu_network(&network, &input).unwrap();
        assert_close(
            &gpu.data,
            &cpu.data,
            1e-4,
            &format!("network of {input_channels}"),
        );
    }
}

/// A small noisy HDR image (gradients and a bright spot), and a plausible
/// albedo and normal.
fn test_images(w: usize, h: usize) -> [Vec<f32>; 3] {
    let noise = pseudo(w * h * 3, 21);
    let mut color = Vec::new();
    let mut albedo = Vec::new();
    let mut normal = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let (u, v) = (x as f32 / w as f32, y as f32 / h as f32);
            let spot = if (x as i32 - 9).abs() < 3 && (y as i32 - 7).abs() < 3 {
                40.0
            } else {
                0.0
            };
            for c in 0..3 {
                let base = 0.2 + 0.6 * u * (c as f32 + 1.0) / 3.0 + 0.3 * v;
                let i = (y * w + x) * 3 + c;
                color.push((base * (1.0 + 0.8 * noise[i]) + spot).max(0.0));
                albedo.push(0.3 + 0.4 * u);
            }
            let n = [u - 0.5, v - 0.5, 0.7f32];
            let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
            normal.extend(n.iter().map(|c| c / len));
        }
    }
    [color, albedo, normal]
}

/// The whole denoise with the shipped OIDN networks (packing with
/// autoexposure and PU, the network, unpacking) equals the CPU's.
#[test]
fn a_small_image_denoises_as_on_the_cpu() {
    let denoiser = Denoiser::new(common::gpu()).unwrap();
    let (w, h) = (40, 27);
    let [color, albedo, normal] = test_images(w, h);
    for aux in [false, true] {
        let images = DenoiseImages {
            width: w,
            height: h,
            color: &color,
            albedo: aux.then_some(&albedo[..]),
            normal: aux.then_some(&normal[..]),
        };
        let weights = shipped_weights(images.input_channels()).unwrap();
        let cpu = denoise_cpu(&images, &weights, None, u64::MAX).unwrap();
        let gpu = denoiser.denoise(&images, None).unwrap();
        assert_close(
            &gpu,
            &cpu,
            1e-4,
            &format!("denoise, albedo and normal: {aux}"),
        );
    }
}

/// The window's run, its convolutions cut into bands of rows and run a
/// few units at a time, gives the whole run's image exactly.
#[test]
fn a_denoise_run_a_few_units_at_a_time_equals_the_whole_run() {
    let ctx = common::gpu();
    let denoiser = Denoiser::new(ctx).unwrap();
    let (w, h) = (40, 27);
    let [color, albedo, normal] = test_images(w, h);
    let images = DenoiseImages {
        width: w,
        height: h,
        color: &color,
        albedo: Some(&albedo),
        normal: Some(&normal),
    };
    let whole = denoiser.denoise(&images, None).unwrap();
    // 64 Ki multiply-adds: a workgroup row (8 rows) a unit at full size.
    let mut run = denoiser.start(&images, None, Some(1 << 16)).unwrap();
    let units = run.next_costs().count();
    let uncut = denoiser.start(&images, None, None).unwrap();
    assert!(
        units > uncut.next_costs().count() + 40,
        "{units} units: the convolutions were not cut into bands"
    );
    let mut advances = 0;
    while !run.is_finished() {
        let (done, total) = run.progress();
        assert!(done < total);
        run.advance(ctx, &images, 3).unwrap();
        advances += 1;
    }
    let (done, total) = run.progress();
    assert_eq!(done, total);
    assert_eq!(advances, units.div_ceil(3), "three units an advance");
    assert!(run.into_output().unwrap() == whole, "the cut run differs");
}

#[test]
fn mismatched_images_are_usage_errors() {
    let denoiser = Denoiser::new(common::gpu()).unwrap();
    let color = vec![0.5f32; 4 * 4 * 3];
    let short = vec![0.5f32; 3 * 4 * 3];
    let images = DenoiseImages {
        width: 4,
        height: 4,
        color: &color,
        albedo: Some(&short),
        normal: Some(&color),
    };
    let error = denoiser.denoise(&images, None).unwrap_err();
    assert_eq!(error.exit_code(), 2, "{error}");
    let albedo_only = DenoiseImages {
        albedo: Some(&color),
        normal: None,
        ..images
    };
    let error = denoiser.denoise(&albedo_only, None).unwrap_err();
    assert!(
        error.to_string().contains("albedo without a normal"),
        "{error}"
    );
}
