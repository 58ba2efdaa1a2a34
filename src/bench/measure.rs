//! One run's frames: a warm-up frame that counts the walk's work and gives
//! the image, then the timed frames without the counters, whose median GPU
//! time is the run's figure ([`FrameTimer::measure`]).

use std::time::Instant;

use super::progress::Progress;
use super::record::RunRecord;
use crate::error::Result;
use crate::gpu::FrameParams;
use crate::gpu::{Accel, GpuContext, GpuScene, RenderSummary, Renderer, SceneBuffers, TilePlan};
use crate::render::millions_per_second;

/// What every run of a sweep is timed with: the GPU, the renderer and the
/// configuration's repeats and brute-force budget.
pub(super) struct FrameTimer<'a> {
    pub ctx: &'a GpuContext,
    pub renderer: Renderer,
    /// Timed frames per run.
    pub repeat: u32,
    /// Brute force's per-frame budget, seconds.
    pub budget_s: f64,
}

impl FrameTimer<'_> {
    /// Renders one uploaded run: a warm-up frame that counts the walk's work
    /// (and gives the image), then `repeat` timed frames of a pipeline without
    /// the counters (`KernelVariant::count_costs`);
    /// fills `record` and returns the image.
    pub fn measure(
        &self,
        gpu: &GpuScene,
        params: FrameParams,
        plan: TilePlan,
        progress: &Progress,
        record: &mut RunRecord,
    ) -> Result<Vec<u8>> {
        let what = format!("{} N={} {}", record.scene, record.n, record.cell_name());
        progress.message(format!("{what}: warm-up frame"));
        let t = Instant::now();
        let buffers = gpu.buffers();
        let (rgb, first) = self.counted_frame(buffers, params, plan)?;
        let warmup_wall = ms_since(t);
        if let Some(cost) = first.cost {
            let rays = first.rays.total().max(1) as f64;
            record.nodes_visited_per_ray = Some(cost.nodes_visited as f64 / rays);
            record.leaves_visited_per_ray = Some(cost.leaves_visited as f64 / rays);
            record.objects_tested_per_ray = Some(cost.objects_tested as f64 / rays);
        }
        let mut samples = Vec::new();
        let mut walls = Vec::new();
        let budget_ms = self.budget_s * 1e3;
        if record.accel == Accel::Brute && first.gpu_ms > budget_ms {
            // Already over budget: the warm-up frame is the only measurement.
            samples.push(first.gpu_ms);
            walls.push(warmup_wall);
            record.note = Some(format!(
                "warm-up frame {:.1} s > budget {} s: it is the only sample",
                first.gpu_ms * 1e-3,
                self.budget_s
            ));
        } else {
            // The timed frames' pipeline counts nothing, unlike the warm-up's:
            // compile it first, so that the first timed frame does not include that.
            self.renderer.compile(self.ctx, buffers, params, false)?;
            for k in 0..self.repeat {
                progress.message(format!("{what}: frame {}/{}", k + 1, self.repeat));
                let t = Instant::now();
                let image = self.renderer.render(self.ctx, buffers, params, plan)?;
                walls.push(ms_since(t));
                samples.push(image.gpu_ms);
            }
        }
        let gpu_ms = median(&samples).unwrap_or(first.gpu_ms);
        let rays = first.rays;
        record.gpu_ms = Some(gpu_ms);
        record.gpu_ms_min = samples.iter().copied().reduce(f64::min);
        record.gpu_ms_max = samples.iter().copied().reduce(f64::max);
        record.gpu_ms_samples = samples;
        record.gpu_time_source = Some(first.gpu_time_source);
        record.frame_wall_ms = median(&walls);
        if self.ctx.has_loop_limit() {
            record.loop_limited_pixels = Some(rays.loop_limited);
            if rays.loop_limited > 0 {
                let note = format!(
                    "{} pixels reached llvmpipe's loop limit: their colour (and this time) may be wrong",
                    rays.loop_limited
                );
                record.note = Some(match record.note.take() {
                    Some(n) => format!("{n}; {note}"),
                    None => note,
                });
            }
        }
        let r = &gpu.scene().render;
        let primary = r.width as u64 * r.height as u64 * r.samples as u64;
        record.primary_rays = Some(primary);
        record.primary_mrays_per_s = Some(millions_per_second(primary, gpu_ms));
        // The shader's counters are cleared per tile and summed: exact.
        if rays.primary == primary {
            record.shadow_rays = Some(rays.shadow);
            record.reflection_rays = Some(rays.reflection);
            record.total_rays = Some(rays.total());
            record.mrays_per_s = Some(millions_per_second(rays.total(), gpu_ms));
        }
        Ok(rgb)
    }

    /// Renders one frame, counting the walk's work, and returns its image and
    /// summary.
    fn counted_frame(
        &self,
        buffers: &SceneBuffers,
        params: FrameParams,
        plan: TilePlan,
    ) -> Result<(Vec<u8>, RenderSummary)> {
        let mut rgb = Vec::with_capacity(params.width as usize * params.height as usize * 3);
        let summary = self.renderer.render_bands_with_cost(
            self.ctx,
            buffers,
            params,
            plan,
            true,
            &mut |band| {
                rgb.extend_from_slice(band.rgb);
                Ok(())
            },
        )?;
        Ok((rgb, summary))
    }
}

/// Milliseconds since `t`.
pub(super) fn ms_since(t: Instant) -> f64 {
    t.elapsed().as_secs_f64() * 1e3
}

/// The median of `values`; None when empty.
pub fn median(values: &[f64]) -> Option<f64> {
    if values.is_empty() {
        return None;
    }
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    let m = v.len() / 2;
    Some(if v.len() % 2 == 1 {
        v[m]
    } else {
        0.5 * (v[m - 1] + v[m])
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_of_odd_and_even() {
        assert_eq!(median(&[]), None);
        assert_eq!(median(&[3.0, 1.0, 2.0]), Some(2.0));
        assert_eq!(median(&[4.0, 1.0, 2.0, 3.0]), Some(2.5));
    }
}
