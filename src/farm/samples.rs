//! A path-traced still split by samples (`--split samples`): share `t` of
//! `S` renders samples `t * N / S .. (t + 1) * N / S` of every pixel (the
//! same sample indices, so the same random numbers, as the single render)
//! and writes their mean radiance as parts/samples-T.exr; the finishing job
//! averages the shares weighted by their sample counts,
//! `sum(mean_t * count_t) / N` in f64, into the still's EXR (linear
//! radiance) and PNG (tone-mapped as `kdray render` does). The kernel adds
//! a pixel's samples one by one into an f32 sum: a share's sum starts from
//! zero where the single render's carries on, so the two agree within f32
//! rounding (radiance is never negative, so relative error stays of the
//! order of the samples' count times 2^-24), not bit for bit.

use std::path::Path;

use super::plan::{FarmPlan, Finished};
use crate::error::{Error, Result};
use crate::gpu::{GpuContext, GpuScene};
use crate::output::exr::{read_exr_rgb, write_exr_atomic};
use crate::render::FramePart;
use crate::render::StreamOptions;
use crate::scene::{Frame, RenderSettings};

/// Renders share `share` of the plan's samples of `frame` and writes its
/// per-pixel mean radiance (linear RGB, f32) atomically as the share's EXR.
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
            ..StreamOptions::new(plan.flags.traversal)
        },
        &mut |band| {
            let radiance = band.radiance.ok_or_else(|| {
                Error::Output("the renderer returned no radiance for a share of samples".into())
            })?;
            rgb.extend_from_slice(radiance);
            Ok(())
        },
    )?;
    write_exr_atomic(&plan.item_path(dir, share), plan.width, plan.height, &rgb)
}

/// The shares' means weighted by their sample counts: each pixel's mean
/// over all the plan's samples (f64 sums, rounded once to f32). Checks
/// every share's size.
pub fn average_shares(plan: &FarmPlan, dir: &Path) -> Result<Vec<f32>> {
    let values = plan.width as usize * plan.height as usize * 3;
    let mut sums = vec![0.0f64; values];
    let mut total = 0u64;
    for share in 0..plan.items() {
        let (_, count) = plan.sample_range(share).unwrap_or((0, 0));
        let path = plan.item_path(dir, share);
        let (w, h, mean) = read_exr_rgb(&path)?;
        if (w, h) != (plan.width, plan.height) || mean.len() != values {
            return Err(Error::Output(format!(
                "{}: {w}x{h}, expected {}x{}",
                path.display(),
                plan.width,
                plan.height
            )));
        }
        for (s, m) in sums.iter_mut().zip(&mean) {
            *s += *m as f64 * count as f64;
        }
        total += count as u64;
    }
    let total = total.max(1) as f64;
    Ok(sums.iter().map(|s| (s / total) as f32).collect())
}

/// The finishing job of a split by samples: the shares averaged
/// ([`average_shares`]) into the still's EXR, and its PNG tone-mapped with
/// `render`'s `tone_map` and `exposure`, both written atomically.
pub fn finish_shares(plan: &FarmPlan, dir: &Path, render: &RenderSettings) -> Result<Finished> {
    let radiance = average_shares(plan, dir)?;
    let exr = plan
        .final_exr_path(dir)
        .ok_or_else(|| Error::Output(format!("{}: not a split by samples", dir.display())))?;
    write_exr_atomic(&exr, plan.width, plan.height, &radiance)?;
    let scale = render.exposure.exp2() as f32;
    let rgb: Vec<u8> = radiance
        .iter()
        .map(|&m| render.tone_map.to_srgb8(m, scale))
        .collect();
    let png = plan.final_path(dir);
    crate::output::write_png_atomic(&png, plan.width, plan.height, &rgb)?;
    Ok(Finished::Averaged {
        shares: plan.items(),
        png,
        exr,
    })
}
