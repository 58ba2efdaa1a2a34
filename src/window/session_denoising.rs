//! The session's denoising (N; the path tracer only): turning it on and
//! off, what the title says of it, and each frame's share of it: the
//! feature pass beside the accumulation's, a denoise begun when one is due,
//! and the units of the denoise in progress that the frame runs
//! ([`Denoising`](super::denoising::Denoising) holds the mechanism).

use std::time::Instant;

use super::denoise_schedule::DenoiseSchedule;
use super::refinement::{FrameKind, FramePlan};
use super::session::Session;
use super::title::DenoiseTitle;
use super::view::FrameWork;
use crate::error::Result;
use crate::scene::Integrator;

impl Session {
    /// N: denoising on or off, with the path tracer; with the Whitted
    /// integrator only the title's notice that it needs the path tracer.
    pub(super) fn toggle_denoise(&mut self) {
        if self.integrator != Integrator::Path {
            self.denoising.refused = true;
            eprintln!("kdray: N: denoising needs the path tracer (I switches to it)");
            return;
        }
        self.denoising.refused = false;
        self.denoising.on = !self.denoising.on;
        let state = if self.denoising.on { "on" } else { "off" };
        eprintln!("kdray: denoising {state}");
        // The feature sums start with the image.
        self.denoising.abandon();
        self.viewer.hide_denoised();
        self.refinement.invalidate();
    }

    /// Samples per pixel of the denoised image shown, if one is.
    pub(super) fn shown_denoised(&self) -> Option<u32> {
        self.denoising
            .schedule
            .denoised_samples()
            .filter(|_| self.viewer.shows_denoised())
    }

    /// What the title says of denoising.
    pub(super) fn denoise_title(&self) -> Option<DenoiseTitle> {
        let d = &self.denoising;
        if self.integrator != Integrator::Path {
            return (d.on || d.refused).then_some(DenoiseTitle::NeedsPath);
        }
        if !self.denoises() {
            return None;
        }
        let shown = self.shown_denoised();
        Some(match (self.denoising.progress(), shown) {
            (Some((samples, percent)), shown) => DenoiseTitle::Running {
                samples,
                percent,
                shown,
            },
            (None, Some(samples)) => DenoiseTitle::Shown { samples },
            (None, None) => DenoiseTitle::Waiting {
                at: DenoiseSchedule::first_at(self.refinement.samples()),
            },
        })
    }

    /// Whether this frame's passes gather the denoiser's features.
    pub(super) fn denoises(&self) -> bool {
        self.denoising.active(self.integrator) && !self.heatmap
    }

    /// The denoiser's share of a frame planned as `plan`: the feature pass
    /// beside the accumulation's pass `work.pass`; once the image's
    /// samples so far are complete (this frame's pass completed them, or
    /// the image is finished) and a denoise is due, a denoise begun on
    /// them; then this frame's units of the denoise in progress. When its
    /// last unit runs, this frame's present shows the denoised image.
    /// Whether this frame ran units of a denoise.
    pub(super) fn denoise_frame(&mut self, plan: &FramePlan, work: &FrameWork) -> Result<bool> {
        if plan.kind == FrameKind::Moving || plan.clear {
            self.denoising.schedule.restart();
            self.denoising.abandon();
            self.viewer.hide_denoised();
        }
        if !self.denoises() {
            self.denoising.abandon();
            return Ok(false);
        }
        let complete = match (plan.kind, plan.pass, work.pass) {
            (FrameKind::Still, Some(pass), Some(params)) => {
                self.denoising
                    .trace(self.ctx, self.scene.buffers(), &params, plan.clear)?;
                (pass.first_row + pass.rows >= pass.image.1)
                    .then_some((pass.image, pass.sample_index + 1))
            }
            (FrameKind::Idle, _, _) => Some((plan.image, self.refinement.passes())),
            _ => None,
        };
        if let Some((image, passes)) = complete {
            let samples = self.refinement.samples();
            let due = self.denoising.schedule.due(passes, samples, Instant::now());
            if due && !self.denoising.is_running() {
                self.denoising.start(self.ctx, image, passes)?;
            }
        }
        if !self.denoising.is_running() {
            return Ok(false);
        }
        let Some(done) = self.denoising.advance(self.ctx)? else {
            return Ok(true);
        };
        self.viewer.show_denoised(self.ctx, &done.rgb)?;
        self.denoising
            .schedule
            .denoised(done.samples, done.busy, Instant::now());
        eprintln!(
            "kdray: denoised at {} spp in {:.1} s over {} frames ({:.1} s of denoiser work, longest frame {:.0} ms)",
            done.samples,
            done.elapsed.as_secs_f64(),
            done.frames,
            done.busy.as_secs_f64(),
            done.longest_frame.as_secs_f64() * 1e3
        );
        Ok(true)
    }

    /// Whether the finished image waits for its denoise (frames must come
    /// to run it).
    pub(super) fn denoise_pending(&self, now: Instant) -> bool {
        let samples = self.refinement.samples();
        self.denoises()
            && !self.refinement.has_work(now)
            && self
                .denoising
                .schedule
                .due(self.refinement.passes(), samples, now)
    }
}
