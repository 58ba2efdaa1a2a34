//! A path-traced still split by samples (`--split samples`): share `t` of
//! `S` renders samples `t * N / S .. (t + 1) * N / S` of every pixel (the
//! same sample indices, so the same random numbers, as the single render)
//! and writes their mean radiance as parts/samples-T.exr (denoised, first
//! its mean albedo and normal as parts/samples-T.albedo.exr and
//! parts/samples-T.normal.exr); the finishing job averages the shares
//! weighted by their sample counts, `sum(mean_t * count_t) / N` in f64
//! ([`WeightedMean`]), into the still's EXR (linear radiance) and PNG
//! (tone-mapped as `kdray render` does), denoising them first from the
//! averaged albedo and normal when the plan says so. The kernel adds a
//! pixel's samples one by one into an f32 sum: a share's sum starts from
//! zero where the single render's carries on, so the two agree within f32
//! rounding (radiance is never negative, so relative error stays of the
//! order of the samples' count times 2^-24), not bit for bit.

use std::path::{Path, PathBuf};

use super::plan::{share_feature_paths, FarmPlan, Finished};
use crate::denoise::Denoiser;
use crate::error::{Error, Result};
use crate::gpu::{GpuContext, GpuScene};
use crate::output::denoised::NoisyImage;
use crate::output::exr::{read_exr_rgb, write_exr_atomic};
use crate::render::FramePart;
use crate::render::StreamOptions;
use crate::scene::{Frame, RenderSettings};

/// Renders share `share` of the plan's samples of `frame` and writes its
/// per-pixel mean radiance (linear RGB, f32) atomically as the share's EXR;
/// for a denoised plan, its mean albedo and normal before it
/// ([`super::plan::share_feature_paths`]), so that the radiance's file
/// is there only once the share is whole.
pub fn render_share(
    ctx: &GpuContext,
    uploaded: &GpuScene,
    plan: &FarmPlan,
    dir: &Path,
    share: u32,
    frame: Frame,
) -> Result<()> {
    let range = plan.sample_range(share).ok_or_else(|| {
        Error::Output(format!(
            "{}: not a split by samples",
            dir.join(super::plan::PLAN_FILE).display()
        ))
    })?;
    let pixels = plan.width as usize * plan.height as usize;
    let mut rgb: Vec<f32> = Vec::with_capacity(pixels * 3);
    let features = plan.denoise;
    let feature_len = if features { pixels * 3 } else { 0 };
    let (mut albedo, mut normal) = (
        Vec::with_capacity(feature_len),
        Vec::with_capacity(feature_len),
    );
    let part = FramePart {
        frame,
        rows: (0, plan.height),
        samples: Some(range),
    };
    crate::render::render_streaming(
        ctx,
        uploaded,
        Some(&part),
        StreamOptions {
            radiance: true,
            features,
            ..StreamOptions::new(plan.flags.traversal)
        },
        &mut |band| {
            let radiance = band.radiance.ok_or_else(|| {
                Error::Output("the renderer returned no radiance for a share of samples".into())
            })?;
            rgb.extend_from_slice(radiance);
            if features {
                let f = band.features.ok_or_else(|| {
                    Error::Output("the renderer returned no albedo and normal to denoise".into())
                })?;
                albedo.extend_from_slice(f.albedo);
                normal.extend_from_slice(f.normal);
            }
            Ok(())
        },
    )?;
    let path = plan.item_path(dir, share);
    if features {
        let [albedo_path, normal_path] = share_feature_paths(&path);
        write_exr_atomic(&albedo_path, plan.width, plan.height, &albedo)?;
        write_exr_atomic(&normal_path, plan.width, plan.height, &normal)?;
    }
    write_exr_atomic(&path, plan.width, plan.height, &rgb)
}

/// Per-value means over all samples from the means of shares of them:
/// `sum(mean_t * count_t) / sum(count_t)`, summed in f64 and rounded once
/// to f32, so that the result is the mean one render of every sample
/// gives (within that render's own f32 rounding).
#[derive(Debug, Clone)]
pub struct WeightedMean {
    sums: Vec<f64>,
    samples: u64,
}

impl WeightedMean {
    /// Nothing added yet, for `values` values (three a pixel).
    pub fn new(values: usize) -> Self {
        WeightedMean {
            sums: vec![0.0; values],
            samples: 0,
        }
    }

    /// Adds a share's means over its `samples` samples; `means` must have
    /// the length given to [`WeightedMean::new`].
    pub fn add(&mut self, samples: u32, means: &[f32]) {
        debug_assert_eq!(means.len(), self.sums.len());
        for (s, &m) in self.sums.iter_mut().zip(means) {
            *s += m as f64 * samples as f64;
        }
        self.samples += samples as u64;
    }

    /// The means over every sample added (zeros when none was).
    pub fn mean(&self) -> Vec<f32> {
        let total = self.samples.max(1) as f64;
        self.sums.iter().map(|s| (s / total) as f32).collect()
    }
}

/// The shares' files named by `file_of` (a share's path to its radiance,
/// albedo or normal) averaged weighted by their sample counts
/// ([`WeightedMean`]). Checks every file's size.
fn average_files(
    plan: &FarmPlan,
    dir: &Path,
    file_of: &dyn Fn(&Path) -> PathBuf,
) -> Result<Vec<f32>> {
    let values = plan.width as usize * plan.height as usize * 3;
    let mut mean = WeightedMean::new(values);
    for share in 0..plan.items() {
        let (_, count) = plan.sample_range(share).unwrap_or((0, 0));
        let path = file_of(&plan.item_path(dir, share));
        let (w, h, means) = read_exr_rgb(&path)?;
        if (w, h) != (plan.width, plan.height) || means.len() != values {
            return Err(Error::Output(format!(
                "{}: {w}x{h}, expected {}x{}",
                path.display(),
                plan.width,
                plan.height
            )));
        }
        mean.add(count, &means);
    }
    Ok(mean.mean())
}

/// The shares' mean radiance weighted by their sample counts: each pixel's
/// mean over all the plan's samples. Checks every share's size.
pub fn average_shares(plan: &FarmPlan, dir: &Path) -> Result<Vec<f32>> {
    average_files(plan, dir, &|share| share.to_path_buf())
}

/// The finishing job of a split by samples: the shares averaged
/// ([`average_shares`]) into the still's EXR, and its PNG tone-mapped with
/// `render`'s `tone_map` and `exposure`, both written atomically. A
/// denoised plan averages the shares' albedo and normal too and writes both
/// denoised, the EXR beside its three inputs, as `render --denoise` does.
pub fn finish_shares(plan: &FarmPlan, dir: &Path, render: &RenderSettings) -> Result<Finished> {
    let radiance = average_shares(plan, dir)?;
    let exr = plan
        .final_exr_path(dir)
        .ok_or_else(|| Error::Output(format!("{}: not a split by samples", dir.display())))?;
    let png = plan.final_path(dir);
    if plan.denoise {
        let [albedo, normal] = [0, 1]
            .map(|k| average_files(plan, dir, &|share| share_feature_paths(share)[k].clone()));
        let noisy = NoisyImage {
            width: plan.width,
            height: plan.height,
            color: radiance,
            albedo: albedo?,
            normal: normal?,
        };
        let ctx = GpuContext::new()?;
        let denoised = noisy.denoise(&Denoiser::new(&ctx)?)?;
        noisy.write(&denoised, &exr, render)?;
        noisy.write(&denoised, &png, render)?;
    } else {
        write_exr_atomic(&exr, plan.width, plan.height, &radiance)?;
        let scale = render.exposure.exp2() as f32;
        let rgb: Vec<u8> = radiance
            .iter()
            .map(|&m| render.tone_map.to_srgb8(m, scale))
            .collect();
        crate::output::write_png_atomic(&png, plan.width, plan.height, &rgb)?;
    }
    Ok(Finished::Averaged {
        shares: plan.items(),
        denoised: plan.denoise,
        png,
        exr,
    })
}

#[cfg(test)]
mod tests {
    use super::WeightedMean;

    /// Samples 0..n of one value as the shares `counts` cut them, each
    /// share's mean in f32 as a share writes it.
    fn share_means(samples: &[f32], counts: &[usize]) -> Vec<(u32, Vec<f32>)> {
        let mut at = 0;
        counts
            .iter()
            .map(|&n| {
                let sum: f32 = samples[at..at + n].iter().sum();
                at += n;
                (n as u32, vec![sum / n as f32])
            })
            .collect()
    }

    #[test]
    fn shares_of_unequal_size_average_to_the_mean_over_every_sample() {
        // Ten samples of one value in shares of 3, 3 and 4: an unweighted
        // mean of the three means would be 4.1667, the weighted one 4.5.
        let samples: Vec<f32> = (0..10).map(|s| s as f32).collect();
        let mut mean = WeightedMean::new(1);
        for (count, means) in share_means(&samples, &[3, 3, 4]) {
            mean.add(count, &means);
        }
        assert_eq!(mean.mean(), [4.5]);
    }

    #[test]
    fn albedo_and_normal_means_of_shares_equal_one_machines_means() {
        // Per-sample features of three pixels (albedo in [0, 1], normal
        // components in [-1, 1]) as the path tracer gathers them, 7
        // samples in shares of 2 and 5: the weighted mean of the shares'
        // means is the mean one machine gathers over all 7, within f32
        // rounding.
        let values = 9;
        let sample = |s: usize, v: usize| ((s * 7 + v * 13) % 17) as f32 / 8.0 - 1.0;
        let mut single = vec![0.0f32; values];
        for s in 0..7 {
            for (v, sum) in single.iter_mut().enumerate() {
                *sum += sample(s, v);
            }
        }
        let single: Vec<f32> = single.iter().map(|sum| sum / 7.0).collect();
        let mut mean = WeightedMean::new(values);
        for range in [0..2, 2..7] {
            let n = range.len() as f32;
            let share: Vec<f32> = (0..values)
                .map(|v| range.clone().map(|s| sample(s, v)).sum::<f32>() / n)
                .collect();
            mean.add(range.len() as u32, &share);
        }
        let farmed = mean.mean();
        for (v, (f, s)) in farmed.iter().zip(&single).enumerate() {
            assert!((f - s).abs() <= 1e-6, "value {v}: {f} vs {s}");
        }
        assert!(farmed.iter().any(|&f| f < 0.0), "normals may be negative");
    }

    #[test]
    fn no_share_averages_to_zeros() {
        assert_eq!(WeightedMean::new(3).mean(), [0.0; 3]);
    }
}
