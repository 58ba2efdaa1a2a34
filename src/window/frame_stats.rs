//! Frame figures: frames of each kind, their rate, their rays, the longest
//! of each (a stall shows there), the smoothed figures of the title bar,
//! and what the window reports on exit (one line on stderr, and with
//! `--stats` one JSON object on stdout). Free of winit and wgpu.
//!
//! A frame's time is the interval since the previous frame: frames are
//! paced by the swapchain, so in a steady stream it is the GPU's time per
//! frame. The first frame after a pause (the window idled) has no time.

use std::time::Instant;

use serde::Serialize;

use super::refinement::FrameKind;

/// Frames of one kind.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct KindStats {
    pub frames: u32,
    pub seconds: f64,
    pub primary_rays: u64,
    /// The longest of these frames, ms.
    pub longest_ms: f64,
}

impl KindStats {
    pub fn fps(&self) -> f64 {
        self.frames as f64 / self.seconds.max(1e-9)
    }
    pub fn ms(&self) -> f64 {
        self.seconds * 1e3 / (self.frames.max(1) as f64)
    }
    pub fn mrays(&self) -> f64 {
        self.primary_rays as f64 / self.seconds.max(1e-9) * 1e-6
    }
}

/// What `--window --stats` prints on exit.
#[derive(Debug, Serialize)]
pub struct WindowStats {
    adapter: String,
    backend: String,
    width: u32,
    height: u32,
    samples: u32,
    frames: u32,
    seconds: f64,
    still_frames: u32,
    still_fps: f64,
    still_ms: f64,
    still_mrays_per_s: f64,
    still_longest_ms: f64,
    moving_frames: u32,
    moving_fps: f64,
    moving_ms: f64,
    moving_mrays_per_s: f64,
    moving_longest_ms: f64,
    /// Resolution divisor while moving, at exit.
    moving_scale: u32,
    idle_frames: u32,
    /// Seconds the last full refinement took (from the restart to the
    /// submission of its last pass), if one finished.
    refine_seconds: Option<f64>,
}

/// What the report says about the rest of the window.
#[derive(Debug, Clone)]
pub struct ReportContext {
    /// The scene's file name.
    pub name: String,
    pub adapter: String,
    pub backend: String,
    /// Window size, physical pixels.
    pub width: u32,
    pub height: u32,
    pub samples: u32,
    pub moving_scale: u32,
    pub refine_seconds: Option<f64>,
}

/// The figures of every frame presented since the window opened.
#[derive(Debug, Clone)]
pub struct FrameStats {
    opened: Instant,
    presented: u32,
    /// When the previous frame of an uninterrupted stream was made, and
    /// its kind.
    last_frame: Option<(Instant, FrameKind)>,
    still: KindStats,
    moving: KindStats,
    idle: KindStats,
    /// Smoothed frame time and primary rays per second (ms, millions).
    frame_ms: f64,
    mrays: f64,
}

impl FrameStats {
    pub fn new(opened: Instant) -> Self {
        FrameStats {
            opened,
            presented: 0,
            last_frame: None,
            still: KindStats::default(),
            moving: KindStats::default(),
            idle: KindStats::default(),
            frame_ms: 0.0,
            mrays: 0.0,
        }
    }

    /// Frames presented so far.
    pub fn presented(&self) -> u32 {
        self.presented
    }

    pub fn kind(&self, kind: FrameKind) -> &KindStats {
        match kind {
            FrameKind::Still => &self.still,
            FrameKind::Moving => &self.moving,
            FrameKind::Idle => &self.idle,
        }
    }

    /// Smoothed frame time (ms) and primary rays per second (millions,
    /// over the frames that trace), for the title bar.
    pub fn smoothed(&self) -> (f64, f64) {
        (self.frame_ms, self.mrays)
    }

    /// The window idled: the next frame's interval is not a frame time.
    pub fn pause(&mut self) {
        self.last_frame = None;
    }

    /// Counts a frame of `kind`, presented at `now`, that traced `rays`
    /// primary rays. Returns its time in ms if it follows a frame of the
    /// same kind: then its time is the time of such frames alone, which is
    /// what estimates may learn from.
    pub fn record(&mut self, now: Instant, kind: FrameKind, rays: u64) -> Option<f64> {
        self.presented += 1;
        let previous = self.last_frame.replace((now, kind));
        let (before, previous_kind) = previous?;
        let seconds = now.duration_since(before).as_secs_f64();
        let stats = match kind {
            FrameKind::Still => &mut self.still,
            FrameKind::Moving => &mut self.moving,
            FrameKind::Idle => &mut self.idle,
        };
        stats.frames += 1;
        stats.seconds += seconds;
        stats.primary_rays += rays;
        let ms = seconds * 1e3;
        stats.longest_ms = stats.longest_ms.max(ms);
        let mrays = rays as f64 / seconds.max(1e-9) * 1e-6;
        let a = if self.frame_ms == 0.0 { 1.0 } else { 0.2 };
        self.frame_ms += a * (ms - self.frame_ms);
        if kind != FrameKind::Idle {
            self.mrays += a * (mrays - self.mrays);
        }
        (previous_kind == kind).then_some(ms)
    }

    /// The report at `now`: the line for stderr and the `--stats` object;
    /// None if no frame was presented.
    pub fn report(&self, now: Instant, about: ReportContext) -> Option<(String, WindowStats)> {
        if self.presented == 0 {
            return None;
        }
        let seconds = now.duration_since(self.opened).as_secs_f64();
        let mut line = format!(
            "kdray: {}: {} frames in {seconds:.1} s",
            about.name, self.presented
        );
        for (label, kind) in [("still", FrameKind::Still), ("moving", FrameKind::Moving)] {
            let k = self.kind(kind);
            if k.frames > 0 {
                line.push_str(&format!(
                    "; {label}: {} frames at {:.1} fps ({:.1} ms, {:.2} Mrays/s)",
                    k.frames,
                    k.fps(),
                    k.ms(),
                    k.mrays()
                ));
            }
        }
        if let Some(t) = about.refine_seconds {
            line.push_str(&format!(
                "; {} samples per pixel in {t:.1} s",
                about.samples
            ));
        }
        let stats = WindowStats {
            adapter: about.adapter,
            backend: about.backend,
            width: about.width,
            height: about.height,
            samples: about.samples,
            frames: self.presented,
            seconds,
            still_frames: self.still.frames,
            still_fps: self.still.fps(),
            still_ms: self.still.ms(),
            still_mrays_per_s: self.still.mrays(),
            still_longest_ms: self.still.longest_ms,
            moving_frames: self.moving.frames,
            moving_fps: self.moving.fps(),
            moving_ms: self.moving.ms(),
            moving_mrays_per_s: self.moving.mrays(),
            moving_longest_ms: self.moving.longest_ms,
            moving_scale: about.moving_scale,
            idle_frames: self.idle.frames,
            refine_seconds: about.refine_seconds,
        };
        Some((line, stats))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    const MS: Duration = Duration::from_millis(1);

    fn about(refine_seconds: Option<f64>) -> ReportContext {
        ReportContext {
            name: "seed.toml".into(),
            adapter: "llvmpipe".into(),
            backend: "Vulkan".into(),
            width: 96,
            height: 64,
            samples: 4,
            moving_scale: 3,
            refine_seconds,
        }
    }

    #[test]
    fn frames_count_from_the_second_of_a_stream() {
        let t = Instant::now();
        let mut s = FrameStats::new(t);
        // The first frame has no interval; the next ones are timed, and
        // learnable only after a frame of their own kind.
        assert_eq!(s.record(t + 250 * MS, FrameKind::Moving, 1000), None);
        assert_eq!(s.record(t + 500 * MS, FrameKind::Moving, 1000), Some(250.0));
        assert_eq!(s.record(t + 1000 * MS, FrameKind::Still, 4000), None);
        assert_eq!(s.record(t + 1125 * MS, FrameKind::Still, 4000), Some(125.0));
        s.pause();
        assert_eq!(s.record(t + 5000 * MS, FrameKind::Idle, 0), None);
        assert_eq!(s.record(t + 5250 * MS, FrameKind::Idle, 0), Some(250.0));
        assert_eq!(s.presented(), 6);
        assert_eq!(
            *s.kind(FrameKind::Moving),
            KindStats {
                frames: 1,
                seconds: 0.25,
                primary_rays: 1000,
                longest_ms: 250.0
            }
        );
        assert_eq!(
            *s.kind(FrameKind::Still),
            KindStats {
                frames: 2,
                seconds: 0.625,
                primary_rays: 8000,
                longest_ms: 500.0
            }
        );
        assert_eq!(s.kind(FrameKind::Idle).frames, 1);
        let still = s.kind(FrameKind::Still);
        assert_eq!(still.fps(), 3.2);
        assert_eq!(still.ms(), 312.5);
        assert!((still.mrays() - 0.0128).abs() < 1e-15, "{}", still.mrays());
    }

    #[test]
    fn the_title_figures_are_smoothed_and_skip_idle_rays() {
        let t = Instant::now();
        let mut s = FrameStats::new(t);
        s.record(t, FrameKind::Still, 0);
        // The first timed frame sets them: 500 ms, 2 Mrays/s.
        s.record(t + 500 * MS, FrameKind::Still, 1_000_000);
        assert_eq!(s.smoothed(), (500.0, 2.0));
        // Then a fifth of the way toward each frame's figures; idle frames
        // move the frame time only.
        s.record(t + 1000 * MS, FrameKind::Idle, 0);
        assert_eq!(s.smoothed(), (500.0, 2.0));
        // 250 ms, 1 Mrays/s.
        s.record(t + 1250 * MS, FrameKind::Moving, 250_000);
        assert_eq!(s.smoothed(), (450.0, 1.8));
    }

    #[test]
    fn the_report_line_and_json() {
        let t = Instant::now();
        let mut s = FrameStats::new(t);
        assert!(s.report(t, about(None)).is_none());
        s.record(t, FrameKind::Moving, 0);
        s.record(t + 500 * MS, FrameKind::Moving, 1_000_000);
        s.record(t + 1000 * MS, FrameKind::Still, 0);
        s.record(t + 1250 * MS, FrameKind::Still, 500_000);
        let (line, stats) = s.report(t + 2000 * MS, about(Some(0.7))).unwrap();
        assert_eq!(
            line,
            "kdray: seed.toml: 4 frames in 2.0 s; \
             still: 2 frames at 2.7 fps (375.0 ms, 0.67 Mrays/s); \
             moving: 1 frames at 2.0 fps (500.0 ms, 2.00 Mrays/s); \
             4 samples per pixel in 0.7 s"
        );
        let json: serde_json::Value = serde_json::to_value(&stats).unwrap();
        assert_eq!(json["frames"], 4);
        assert_eq!(json["seconds"], 2.0);
        assert_eq!(json["still_frames"], 2);
        assert_eq!(json["still_longest_ms"], 500.0);
        assert_eq!(json["moving_frames"], 1);
        assert_eq!(json["moving_ms"], 500.0);
        assert_eq!(json["moving_scale"], 3);
        assert_eq!(json["idle_frames"], 0);
        assert_eq!(json["refine_seconds"], 0.7);
        assert_eq!(json["width"], 96);
        assert_eq!(json["height"], 64);
        assert_eq!(json.as_object().unwrap().len(), 20);
        // Without a finished refinement the line says nothing of it.
        let (line, stats) = s.report(t + 2000 * MS, about(None)).unwrap();
        assert!(line.ends_with("(500.0 ms, 2.00 Mrays/s)"), "{line}");
        assert_eq!(
            serde_json::to_value(&stats).unwrap()["refine_seconds"],
            serde_json::Value::Null
        );
    }
}
