//! When the window denoises its still image (N): after a few samples per
//! pixel, then again as samples accumulate, and always once the image is
//! finished. Free of winit and wgpu.
//!
//! A denoise runs a few units a frame beside refinement, but its work
//! still costs the window's GPU (on lavapipe, tens of seconds for a
//! window-sized image), so a repeat waits until the samples have grown by
//! [`GROWTH`] and refining has gone on for [`COST_MULTIPLE`] times the last
//! denoise's measured cost (the time its units ran): the denoiser then
//! takes at most about 1 / (1 + [`COST_MULTIPLE`]) of the window's time.

use std::time::{Duration, Instant};

/// Samples per pixel of the first denoised image (or all of them, if the
/// image has fewer).
pub const FIRST_DENOISE_SAMPLES: u32 = 4;
/// A repeat waits for at least this many times the samples of the last.
pub const GROWTH: u32 = 2;
/// ... and for this many times the last denoise's cost since it ended.
pub const COST_MULTIPLE: u32 = 4;

/// The last denoise of the current image.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct LastDenoise {
    /// Samples per pixel it denoised.
    samples: u32,
    cost: Duration,
    ended: Instant,
}

/// The schedule of one image's denoises; [`Self::restart`] when the image
/// starts again.
#[derive(Debug, Clone, Default)]
pub struct DenoiseSchedule {
    last: Option<LastDenoise>,
}

impl DenoiseSchedule {
    /// The image started again: nothing denoised yet.
    pub fn restart(&mut self) {
        self.last = None;
    }

    /// Samples per pixel of the denoised image of this refinement, if one
    /// was made.
    pub fn denoised_samples(&self) -> Option<u32> {
        self.last.map(|l| l.samples)
    }

    /// Samples per pixel at which the first denoise of an image of
    /// `samples` samples happens.
    pub fn first_at(samples: u32) -> u32 {
        FIRST_DENOISE_SAMPLES.min(samples)
    }

    /// Whether to denoise at `now`, when every pixel holds `passes` of the
    /// image's `samples` samples.
    pub fn due(&self, passes: u32, samples: u32, now: Instant) -> bool {
        let Some(last) = self.last else {
            return passes >= Self::first_at(samples);
        };
        if passes <= last.samples {
            return false;
        }
        if passes >= samples {
            return true;
        }
        passes >= last.samples.saturating_mul(GROWTH)
            && now.saturating_duration_since(last.ended) >= last.cost * COST_MULTIPLE
    }

    /// A denoise of `samples` samples per pixel took `cost` and ended at
    /// `ended`.
    pub fn denoised(&mut self, samples: u32, cost: Duration, ended: Instant) {
        self.last = Some(LastDenoise {
            samples,
            cost,
            ended,
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const MS: Duration = Duration::from_millis(1);

    #[test]
    fn the_first_denoise_comes_after_a_few_samples() {
        let t = Instant::now();
        let s = DenoiseSchedule::default();
        assert_eq!(s.denoised_samples(), None);
        for passes in 0..FIRST_DENOISE_SAMPLES {
            assert!(!s.due(passes, 256, t), "{passes}");
        }
        assert!(s.due(FIRST_DENOISE_SAMPLES, 256, t));
        // An image of fewer samples is denoised once finished.
        assert!(!s.due(1, 2, t));
        assert!(s.due(2, 2, t));
        assert_eq!(DenoiseSchedule::first_at(2), 2);
    }

    #[test]
    fn repeats_wait_for_twice_the_samples_and_four_times_the_cost() {
        let t = Instant::now();
        let mut s = DenoiseSchedule::default();
        // A 500 ms denoise of 4 samples, ended at t.
        s.denoised(4, 500 * MS, t);
        assert_eq!(s.denoised_samples(), Some(4));
        let later = t + 2000 * MS;
        // Doubled samples but not yet 4 x 500 ms since: wait.
        assert!(!s.due(8, 256, t + 1999 * MS));
        // 2 s since, but the samples have not doubled: wait.
        assert!(!s.due(7, 256, later));
        assert!(s.due(8, 256, later));
        assert!(s.due(20, 256, later));
        // A cheap denoise repeats at doubled samples, no sooner.
        s.denoised(8, Duration::ZERO, later);
        assert!(!s.due(8, 256, later) && !s.due(15, 256, later));
        assert!(s.due(16, 256, later));
    }

    #[test]
    fn the_finished_image_is_always_denoised_once() {
        let t = Instant::now();
        let mut s = DenoiseSchedule::default();
        s.denoised(128, 10_000 * MS, t);
        // Neither doubled nor past the cost: only because it is finished.
        assert!(!s.due(255, 256, t));
        assert!(s.due(256, 256, t));
        s.denoised(256, 10_000 * MS, t + 10_000 * MS);
        assert!(!s.due(256, 256, t + 100_000 * MS));
    }

    #[test]
    fn a_restart_forgets_the_last_denoise() {
        let t = Instant::now();
        let mut s = DenoiseSchedule::default();
        s.denoised(64, 10_000 * MS, t);
        assert!(!s.due(4, 256, t));
        s.restart();
        assert_eq!(s.denoised_samples(), None);
        assert!(s.due(4, 256, t));
    }
}
