//! The refinement scheduler: which image each frame of the window traces,
//! free of winit and wgpu so that its decisions are unit-tested with exact
//! numbers.
//!
//! While the camera moves (and for [`SETTLE`] after its last change) a frame
//! traces the *preview*: a fresh single-sample image at 1/s of the
//! resolution, `s` in 1..=[`MAX_MOVING_SCALE`] adapted so a frame takes about
//! [`MOVING_BUDGET_MS`]. While it is still, each frame adds a sample to each
//! pixel of the *image* (sample `n` in pass `n`, the headless kernel's
//! order: a cell of the k x k grid for Whitted frames, a path sample for
//! path-traced ones) until every pixel holds all its [`Samples`]; then the
//! window idles. A pass that would take longer than [`STILL_BUDGET_MS`] is
//! spread over several frames, a band of rows each, and the present pass
//! shows the preview where the image has no sample yet. Any change restarts
//! the refinement after one preview frame.

use std::time::{Duration, Instant};

/// The camera counts as moving until this long after its last change.
pub const SETTLE: Duration = Duration::from_millis(150);
/// Frame time aimed at while the camera moves.
pub const MOVING_BUDGET_MS: f64 = 50.0;
/// Longest frame while refining: a sample pass that would take longer is
/// spread over several frames, a band of rows each, so the window stays
/// responsive (the accumulation counts samples per pixel, so a partly
/// finished pass shows correctly).
pub const STILL_BUDGET_MS: f64 = 80.0;
/// Coarsest resolution divisor while moving.
pub const MAX_MOVING_SCALE: u32 = 8;
/// Resolution divisor of the first moving frames, before any measurement.
const FIRST_MOVING_SCALE: u32 = 2;
/// Band of the first still frames, before any measurement: about this many
/// pixels.
const FIRST_BAND_PIXELS: u32 = 65536;

/// Which work a frame does.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FrameKind {
    /// A full-resolution sample (or a band of one) added to the still image.
    Still,
    /// A reduced-resolution image of a moving camera (the preview).
    Moving,
    /// The finished image presented again.
    Idle,
}

/// One accumulation pass over a band of rows of an image.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Pass {
    /// The whole image the band belongs to, in pixels.
    pub image: (u32, u32),
    /// k of the k x k sample grid, and the cell this pass traces.
    pub samples_per_axis: u32,
    pub sample_index: u32,
    /// The band: its first row and its number of rows.
    pub first_row: u32,
    pub rows: u32,
}

impl Pass {
    /// Pixels (primary rays) the band traces.
    pub fn pixels(&self) -> u64 {
        self.image.0 as u64 * self.rows as u64
    }
}

/// What one frame does: trace (part of) the preview or the image, then
/// present.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FramePlan {
    pub kind: FrameKind,
    /// Zero the buffer the pass writes (the preview for a moving frame,
    /// else the image) before the pass.
    pub clear: bool,
    pub pass: Option<Pass>,
    /// Sizes of the image and the preview that the present pass reads.
    pub image: (u32, u32),
    pub preview: (u32, u32),
}

impl FramePlan {
    /// Size of the buffer the pass writes.
    pub fn target_size(&self) -> (u32, u32) {
        match self.kind {
            FrameKind::Moving => self.preview,
            FrameKind::Still | FrameKind::Idle => self.image,
        }
    }
}

/// The samples a pixel of the finished image holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Samples {
    /// Whitted: the cells of a k x k grid, one a pass (k = `per_axis`).
    Grid { per_axis: u32 },
    /// Path traced: `count` samples at random positions, sample n in pass n.
    Random { count: u32 },
}

/// The scheduler's state: the image being refined and what the frames so
/// far taught about the device's speed.
#[derive(Debug, Clone)]
pub struct Refinement {
    target: Samples,
    /// Most pixels one accumulation buffer holds on the device.
    max_pixels: u64,
    /// Size of the image being refined.
    image: (u32, u32),
    /// Size of the preview, and whether it shows the current view.
    preview: (u32, u32),
    preview_fresh: bool,
    /// Samples per pixel accumulated in the image (complete passes).
    passes: u32,
    /// First row of the current pass still to trace.
    row: u32,
    /// The image must start again (after a preview frame, unless moving).
    restart: bool,
    /// When the image was last restarted, and how long its last full
    /// refinement took (to the planning of its last band).
    refine_started: Option<Instant>,
    refine_seconds: Option<f64>,
    last_change: Option<Instant>,
    /// Smoothed time per traced pixel of still frames (0: not measured yet).
    ms_per_pixel: f64,
    /// Rows a still frame can trace within [`STILL_BUDGET_MS`], as measured
    /// (0: not measured yet).
    band_rows: u32,
    /// Resolution divisor of the preview while moving.
    moving_scale: u32,
}

impl Refinement {
    /// Refining to `samples` per pixel in images of at most `max_pixels`
    /// pixels; the first frame is a preview.
    pub fn new(samples: Samples, max_pixels: u64) -> Self {
        Refinement {
            target: samples,
            max_pixels,
            image: (0, 0),
            preview: (0, 0),
            preview_fresh: false,
            passes: 0,
            row: 0,
            restart: true,
            refine_started: None,
            refine_seconds: None,
            last_change: None,
            ms_per_pixel: 0.0,
            band_rows: 0,
            moving_scale: FIRST_MOVING_SCALE,
        }
    }

    /// A new sample count (a reload, another integrator); call
    /// [`Self::invalidate`] too.
    pub fn set_samples(&mut self, samples: Samples) {
        self.target = samples;
    }

    /// Samples per pixel of the finished image.
    pub fn samples(&self) -> u32 {
        match self.target {
            Samples::Grid { per_axis } => per_axis * per_axis,
            Samples::Random { count } => count,
        }
    }

    /// Samples per pixel in the image so far (complete passes).
    pub fn passes(&self) -> u32 {
        self.passes
    }

    pub fn moving_scale(&self) -> u32 {
        self.moving_scale
    }

    /// Seconds the last full refinement took, if one finished.
    pub fn refine_seconds(&self) -> Option<f64> {
        self.refine_seconds
    }

    /// Something that changes the image (not the camera's motion):
    /// refinement restarts, after one preview frame.
    pub fn invalidate(&mut self) {
        self.restart = true;
        self.preview_fresh = false;
    }

    /// The camera changed at `now`, in a window of `window` pixels.
    pub fn camera_moved(&mut self, now: Instant, window: (u32, u32)) {
        if !self.is_moving(now) && self.ms_per_pixel > 0.0 {
            // Starting to move: the resolution divisor that the still
            // frames' speed predicts fits the moving budget.
            let pixels = window.0 as f64 * window.1 as f64;
            let s = (pixels * self.ms_per_pixel / MOVING_BUDGET_MS)
                .sqrt()
                .ceil();
            self.moving_scale = (s as u32).clamp(1, MAX_MOVING_SCALE);
        }
        self.last_change = Some(now);
        self.invalidate();
    }

    pub fn is_moving(&self, now: Instant) -> bool {
        self.last_change
            .is_some_and(|t| now.duration_since(t) < SETTLE)
    }

    /// Whether a frame at `now` has something to trace (else the image is
    /// finished and the window may idle).
    pub fn has_work(&self, now: Instant) -> bool {
        self.restart || self.passes < self.samples() || self.is_moving(now)
    }

    /// The image's size in a `w` x `h` window: the window's, or smaller if
    /// the device cannot hold that many pixels in one buffer.
    pub fn image_size(&self, (w, h): (u32, u32)) -> (u32, u32) {
        let mut s = 1;
        while (w.div_ceil(s) as u64) * (h.div_ceil(s) as u64) > self.max_pixels {
            s += 1;
        }
        (w.div_ceil(s), h.div_ceil(s))
    }

    /// Rows of the image one frame traces: all of them, or a band (a
    /// multiple of the workgroup's height) sized so that the pass's frames
    /// share it evenly within [`STILL_BUDGET_MS`].
    fn rows_per_frame(&self, (iw, ih): (u32, u32)) -> u32 {
        let step = crate::gpu::bindings::TRACE_WORKGROUP.1;
        let band = if self.band_rows == 0 {
            FIRST_BAND_PIXELS / iw.max(1)
        } else {
            self.band_rows
        };
        if band >= ih {
            return ih;
        }
        let frames = ih.div_ceil(band.max(1));
        ih.div_ceil(frames)
            .next_multiple_of(step)
            .clamp(step.min(ih), ih)
    }

    /// Plans the frame made at `now` in a `window`-sized window, and moves
    /// the refinement past it.
    pub fn plan(&mut self, now: Instant, window: (u32, u32)) -> FramePlan {
        if self.is_moving(now) || (self.restart && !self.preview_fresh) {
            // The preview: while moving, and once after any other change
            // (so that rows the first sample pass has not reached yet show
            // the new view, not the old one).
            let s = self.moving_scale;
            let full = self.image_size(window);
            let preview = (full.0.div_ceil(s), full.1.div_ceil(s));
            self.preview = preview;
            self.preview_fresh = true;
            self.restart = true;
            return FramePlan {
                kind: FrameKind::Moving,
                clear: true,
                pass: Some(Pass {
                    image: preview,
                    samples_per_axis: 1,
                    sample_index: 0,
                    first_row: 0,
                    rows: preview.1,
                }),
                image: self.image,
                preview,
            };
        }
        let image = self.image_size(window);
        let clear = self.restart || self.image != image;
        if clear {
            self.restart = false;
            self.image = image;
            self.passes = 0;
            self.row = 0;
            self.refine_started = Some(now);
        }
        let pass = (self.passes < self.samples()).then(|| self.next_band(now));
        FramePlan {
            kind: if pass.is_some() {
                FrameKind::Still
            } else {
                FrameKind::Idle
            },
            clear,
            pass,
            image,
            preview: self.preview,
        }
    }

    /// The next band of the current pass over the image.
    fn next_band(&mut self, now: Instant) -> Pass {
        let first_row = self.row;
        let rows = self
            .rows_per_frame(self.image)
            .min(self.image.1 - first_row);
        let pass = Pass {
            image: self.image,
            samples_per_axis: match self.target {
                Samples::Grid { per_axis } => per_axis,
                Samples::Random { .. } => 1,
            },
            sample_index: self.passes,
            first_row,
            rows,
        };
        self.row += rows;
        if self.row >= self.image.1 {
            self.row = 0;
            self.passes += 1;
            if self.passes == self.samples() {
                self.refine_seconds = self
                    .refine_started
                    .map(|t| now.duration_since(t).as_secs_f64());
            }
        }
        pass
    }

    /// Learns from a frame of `kind` that took `ms` and traced `rays`
    /// primary rays, following frames of the same kind (so its time is the
    /// time of such frames alone).
    pub fn learn(&mut self, kind: FrameKind, ms: f64, rays: u64) {
        if kind == FrameKind::Still && rays > 0 {
            let per_pixel = ms / rays as f64;
            let b = if self.ms_per_pixel == 0.0 { 1.0 } else { 0.3 };
            self.ms_per_pixel += b * (per_pixel - self.ms_per_pixel);
            // Band height: scale the rows just traced toward the budget
            // (frame overheads included), at most doubling or halving.
            let rows = (rays / self.image.0.max(1) as u64) as f64;
            let target = rows * STILL_BUDGET_MS / ms.max(1e-3);
            self.band_rows = target.clamp(rows * 0.5, rows * 2.0).max(1.0) as u32;
        }
        if kind == FrameKind::Moving {
            // Coarser when over budget; finer when the finer image would
            // still fit in it (pixels grow as the square of 1/s).
            let s = self.moving_scale as f64;
            if ms > 1.3 * MOVING_BUDGET_MS && self.moving_scale < MAX_MOVING_SCALE {
                self.moving_scale += 1;
            } else if self.moving_scale > 1 && ms * (s / (s - 1.0)).powi(2) < 0.8 * MOVING_BUDGET_MS
            {
                self.moving_scale -= 1;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gpu::bindings::TRACE_WORKGROUP;

    const MS: Duration = Duration::from_millis(1);

    /// Plans frames until one is not a still frame; returns the still ones.
    fn still_frames(r: &mut Refinement, now: Instant, window: (u32, u32)) -> Vec<FramePlan> {
        let mut frames = Vec::new();
        loop {
            let plan = r.plan(now, window);
            if plan.kind != FrameKind::Still {
                assert_eq!(plan.kind, FrameKind::Idle);
                return frames;
            }
            frames.push(plan);
        }
    }

    #[test]
    fn a_preview_then_k_by_k_whole_passes_then_idle() {
        let t = Instant::now();
        let mut r = Refinement::new(Samples::Grid { per_axis: 2 }, u64::MAX);
        assert!(r.has_work(t));
        let first = r.plan(t, (96, 64));
        // The default divisor before any measurement: 2.
        assert_eq!(
            first,
            FramePlan {
                kind: FrameKind::Moving,
                clear: true,
                pass: Some(Pass {
                    image: (48, 32),
                    samples_per_axis: 1,
                    sample_index: 0,
                    first_row: 0,
                    rows: 32,
                }),
                image: (0, 0),
                preview: (48, 32),
            }
        );
        assert_eq!(first.target_size(), (48, 32));
        // 96 x 64 is under the first band's 65,536 pixels: whole passes.
        let frames = still_frames(&mut r, t, (96, 64));
        let indices: Vec<u32> = frames
            .iter()
            .map(|p| p.pass.unwrap().sample_index)
            .collect();
        assert_eq!(indices, [0, 1, 2, 3]);
        assert!(frames[0].clear && frames[1..].iter().all(|p| !p.clear));
        for p in &frames {
            let pass = p.pass.unwrap();
            assert_eq!((pass.image, pass.first_row, pass.rows), ((96, 64), 0, 64));
            assert_eq!(pass.samples_per_axis, 2);
            assert_eq!((p.image, p.preview), ((96, 64), (48, 32)));
        }
        assert_eq!(r.passes(), 4);
        assert_eq!(r.refine_seconds(), Some(0.0));
        assert!(!r.has_work(t));
        let idle = r.plan(t, (96, 64));
        assert_eq!(
            (idle.kind, idle.clear, idle.pass),
            (FrameKind::Idle, false, None)
        );
    }

    /// Path-traced frames: any count of samples (here 5, not a square),
    /// sample n in pass n, and a new count takes effect on restart.
    #[test]
    fn path_samples_refine_to_any_count_then_idle() {
        let t = Instant::now();
        let mut r = Refinement::new(Samples::Random { count: 5 }, u64::MAX);
        assert_eq!(r.samples(), 5);
        assert_eq!(r.plan(t, (96, 64)).kind, FrameKind::Moving);
        let frames = still_frames(&mut r, t, (96, 64));
        let passes: Vec<(u32, u32)> = frames
            .iter()
            .map(|p| {
                let pass = p.pass.unwrap();
                (pass.sample_index, pass.samples_per_axis)
            })
            .collect();
        assert_eq!(passes, [(0, 1), (1, 1), (2, 1), (3, 1), (4, 1)]);
        assert!(!r.has_work(t));
        r.set_samples(Samples::Grid { per_axis: 3 });
        r.invalidate();
        assert_eq!(r.samples(), 9);
        assert!(r.has_work(t));
    }

    /// Refining k x k samples in a 1000 x 1000 window, past the first
    /// (preview) frame.
    fn large_window(k: u32) -> (Instant, Refinement) {
        assert_eq!(
            TRACE_WORKGROUP.1, 8,
            "the bands below are multiples of 8 rows"
        );
        let t = Instant::now();
        let mut r = Refinement::new(Samples::Grid { per_axis: k }, u64::MAX);
        assert_eq!(r.plan(t, (1000, 1000)).kind, FrameKind::Moving);
        (t, r)
    }

    #[test]
    fn a_large_pass_is_split_into_even_bands_of_whole_workgroups() {
        let (t, mut r) = large_window(1);
        // First band: 65,536 / 1000 = 65 rows, so 16 frames of
        // ceil(1000 / 16) = 63 rows, rounded up to 64 (whole workgroups);
        // the last frame traces the 40 rows left.
        let frames = still_frames(&mut r, t, (1000, 1000));
        let bands: Vec<(u32, u32)> = frames
            .iter()
            .map(|p| (p.pass.unwrap().first_row, p.pass.unwrap().rows))
            .collect();
        let mut expected: Vec<(u32, u32)> = (0..15).map(|i| (64 * i, 64)).collect();
        expected.push((960, 40));
        assert_eq!(bands, expected);
        assert!(frames.iter().all(|p| p.pass.unwrap().sample_index == 0));
        assert!(frames[0].clear && frames[1..].iter().all(|p| !p.clear));
        assert_eq!(r.passes(), 1);
    }

    #[test]
    fn bands_grow_toward_the_still_budget_at_most_twofold() {
        let (t, mut r) = large_window(4);
        let first = r.plan(t, (1000, 1000)).pass.unwrap();
        assert_eq!((first.first_row, first.rows), (0, 64));
        // 64 rows in 20 ms: 4x under the 80 ms budget, but a band at most
        // doubles: 128 rows, 8 frames of ceil(1000 / 8) = 125, so 128.
        r.learn(FrameKind::Still, 20.0, first.pixels());
        let second = r.plan(t, (1000, 1000)).pass.unwrap();
        assert_eq!((second.first_row, second.rows), (64, 128));
        // 128 rows in 160 ms: twice the budget, so 64 rows.
        r.learn(FrameKind::Still, 160.0, second.pixels());
        let third = r.plan(t, (1000, 1000)).pass.unwrap();
        assert_eq!((third.first_row, third.rows), (192, 64));
        // 64 rows in 64 ms: 80 rows would fit: 13 frames of 77, so 80.
        r.learn(FrameKind::Still, 64.0, third.pixels());
        let fourth = r.plan(t, (1000, 1000)).pass.unwrap();
        assert_eq!((fourth.first_row, fourth.rows), (256, 80));
    }

    #[test]
    fn moving_previews_then_one_restart_when_still() {
        let t = Instant::now();
        let mut r = Refinement::new(Samples::Grid { per_axis: 2 }, u64::MAX);
        r.plan(t, (96, 64));
        r.plan(t, (96, 64));
        assert_eq!(r.passes(), 1);
        r.camera_moved(t, (96, 64));
        for dt in [0, 50, 149] {
            assert!(r.is_moving(t + dt * MS));
            assert_eq!(r.plan(t + dt * MS, (96, 64)).kind, FrameKind::Moving);
        }
        // Settled: the image restarts from sample 0 (cleared), without
        // another preview.
        let settled = t + 150 * MS;
        assert!(!r.is_moving(settled) && r.has_work(settled));
        let plan = r.plan(settled, (96, 64));
        assert_eq!(plan.kind, FrameKind::Still);
        assert!(plan.clear);
        assert_eq!(plan.pass.unwrap().sample_index, 0);
        assert_eq!(r.refine_seconds(), None);
    }

    #[test]
    fn an_invalidation_shows_one_preview_then_restarts() {
        let t = Instant::now();
        let mut r = Refinement::new(Samples::Grid { per_axis: 1 }, u64::MAX);
        assert_eq!(r.plan(t, (96, 64)).kind, FrameKind::Moving);
        assert_eq!(r.plan(t, (96, 64)).kind, FrameKind::Still);
        assert_eq!(r.plan(t, (96, 64)).kind, FrameKind::Idle);
        r.invalidate();
        assert!(r.has_work(t));
        assert_eq!(r.plan(t, (96, 64)).kind, FrameKind::Moving);
        let plan = r.plan(t, (96, 64));
        assert_eq!((plan.kind, plan.clear), (FrameKind::Still, true));
        // A new window size restarts the image too, without a preview.
        let plan = r.plan(t, (50, 40));
        assert_eq!(
            (plan.kind, plan.clear, plan.image),
            (FrameKind::Still, true, (50, 40))
        );
    }

    #[test]
    fn the_image_shrinks_to_what_one_buffer_holds() {
        let r = Refinement::new(Samples::Grid { per_axis: 1 }, 1000);
        assert_eq!(r.image_size((40, 25)), (40, 25));
        // 41 x 25 is over 1,000 pixels: half the size (rounded up) fits.
        assert_eq!(r.image_size((41, 25)), (21, 13));
        assert_eq!(r.image_size((100, 100)), (25, 25));
    }

    #[test]
    fn the_moving_scale_follows_the_moving_budget() {
        let t = Instant::now();
        let mut r = Refinement::new(Samples::Grid { per_axis: 1 }, u64::MAX);
        assert_eq!(r.moving_scale(), 2);
        // Over 1.3 x 50 ms: coarser, up to 1/8.
        for expected in 3..=MAX_MOVING_SCALE {
            r.learn(FrameKind::Moving, 66.0, 1);
            assert_eq!(r.moving_scale(), expected);
        }
        r.learn(FrameKind::Moving, 1000.0, 1);
        assert_eq!(r.moving_scale(), MAX_MOVING_SCALE);
        // Within budget, but 1/7 would take 20 * (8/7)^2 = 26.1 ms: finer.
        r.learn(FrameKind::Moving, 20.0, 1);
        assert_eq!(r.moving_scale(), 7);
        // 1/6 would take 30 * (7/6)^2 = 40.8 ms, over 0.8 x 50: kept.
        r.learn(FrameKind::Moving, 30.0, 1);
        assert_eq!(r.moving_scale(), 7);
        // Still and idle frames do not change it.
        r.learn(FrameKind::Still, 1000.0, 1000);
        r.learn(FrameKind::Idle, 1000.0, 0);
        assert_eq!(r.moving_scale(), 7);
        // The preview is 1/7 of the image, rounded up.
        r.invalidate();
        let plan = r.plan(t, (70, 71));
        assert_eq!((plan.kind, plan.preview), (FrameKind::Moving, (10, 11)));
    }

    #[test]
    fn starting_to_move_picks_the_scale_the_still_speed_predicts() {
        let t = Instant::now();
        let mut r = Refinement::new(Samples::Grid { per_axis: 1 }, u64::MAX);
        r.plan(t, (400, 300));
        // 0.001 ms per pixel: 120,000 pixels take 120 ms, so 1/s of the
        // resolution takes 120 / s^2 ms; s = ceil(sqrt(120 / 50)) = 2...
        r.learn(FrameKind::Still, 120.0, 120_000);
        r.camera_moved(t, (400, 300));
        assert_eq!(r.moving_scale(), 2);
        // ...and the scale is not recomputed while the camera keeps moving.
        r.learn(FrameKind::Moving, 66.0, 1);
        r.camera_moved(t + 10 * MS, (400, 300));
        assert_eq!(r.moving_scale(), 3);
        // After settling, a fresh start: 0.6 ms per pixel (smoothed: 0.001
        // + 0.3 x (0.6 - 0.001) = 0.1807) gives ceil(sqrt(120000 x 0.1807
        // / 50)) = 21, clamped to 8.
        let later = t + 500 * MS;
        r.learn(FrameKind::Still, 60.0, 100);
        r.camera_moved(later, (400, 300));
        assert_eq!(r.moving_scale(), MAX_MOVING_SCALE);
    }
}
