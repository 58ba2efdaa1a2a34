//! The title bar: what it says (progress, speed, the render settings the
//! keys change, reload status) and how often it changes. Free of winit.

use std::time::{Duration, Instant};

use super::inspect_lines::Totals;
use crate::gpu::Accel;
use crate::kdtree::{BuildStrategy, Traversal};

/// Shortest interval between two title changes made by frames.
pub const TITLE_INTERVAL: Duration = Duration::from_millis(250);

/// How far the picture is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Progress {
    /// The camera moves: previews at 1/`scale` of the resolution.
    Moving { scale: u32 },
    /// `passes` of `samples` samples per pixel (path samples if `path`).
    Refining {
        passes: u32,
        samples: u32,
        path: bool,
    },
}

/// What inspection mode (X) shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum InspectTitle<'a> {
    /// On, nothing inspected yet.
    Waiting,
    /// The last click fell outside the image.
    Outside,
    /// The inspection failed (the reason, one line).
    Failed(&'a str),
    /// `pixel`'s rays and their summed work; `path`: the window traces the
    /// path integrator, and the rays are its first path sample's.
    Shown {
        pixel: (u32, u32),
        totals: Totals,
        path: bool,
    },
}

impl InspectTitle<'_> {
    fn text(&self) -> String {
        match *self {
            InspectTitle::Waiting => "INSPECT: click a pixel".into(),
            InspectTitle::Outside => "INSPECT: click inside the image".into(),
            InspectTitle::Failed(why) => format!("INSPECT FAILED: {why}"),
            InspectTitle::Shown {
                pixel: (x, y),
                totals: t,
                path,
            } => format!(
                "INSPECT {x},{y}{}: {} rays, {} nodes, {} leaves, {} tests, {} restarts",
                if path { " (path sample)" } else { "" },
                t.rays,
                t.nodes,
                t.leaves,
                t.tests,
                t.restarts
            ),
        }
    }
}

/// What denoising (N) is doing, while it is on or was asked for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DenoiseTitle {
    /// On, nothing denoised yet: the first denoise comes at `at` samples
    /// per pixel.
    Waiting { at: u32 },
    /// The image shown is denoised, from `samples` samples per pixel.
    Shown { samples: u32 },
    /// A denoise of `samples` samples per pixel is `percent` done; the
    /// image shown is denoised from `shown` samples, if it is.
    Running {
        samples: u32,
        percent: u32,
        shown: Option<u32>,
    },
    /// On, or N pressed, while the Whitted integrator traces.
    NeedsPath,
}

impl DenoiseTitle {
    fn text(&self) -> String {
        match *self {
            DenoiseTitle::Waiting { at } => format!("denoise at {at} spp"),
            DenoiseTitle::Shown { samples } => format!("DENOISED at {samples} spp"),
            DenoiseTitle::Running {
                samples,
                percent,
                shown,
            } => {
                let shown = shown.map_or_else(String::new, |s| format!("DENOISED at {s} spp, "));
                format!("{shown}denoising {samples} spp: {percent}%")
            }
            DenoiseTitle::NeedsPath => "denoising needs the path tracer (I)".into(),
        }
    }
}

/// Everything the title says.
#[derive(Debug, Clone, Copy)]
pub struct TitleFacts<'a> {
    /// The scene's file name.
    pub name: &'a str,
    pub progress: Progress,
    /// Smoothed frame time and primary rays per second (millions).
    pub frame_ms: f64,
    pub mrays: f64,
    pub accel: Accel,
    /// The k-d walk and build (named with the k-d tree only).
    pub traversal: Traversal,
    pub build: BuildStrategy,
    pub max_depth: u32,
    /// The cost heatmap is shown, with this top of scale (work per sample).
    pub heatmap: Option<u32>,
    /// An animation's shown frame (0-based), its frame count, and whether
    /// it plays.
    pub animation: Option<(u32, u32, bool)>,
    /// Inspection mode, while it is on.
    pub inspect: Option<InspectTitle<'a>>,
    /// Denoising, while it is on or was asked for.
    pub denoise: Option<DenoiseTitle>,
}

/// The title bar's state: when it may change next, and the reload status
/// it shows.
#[derive(Debug, Clone)]
pub struct TitleBar {
    next_at: Instant,
    /// A frame was made since the title was last set.
    stale: bool,
    /// A reload is being prepared on the worker thread.
    pub reloading: bool,
    /// Why the last reload failed, if it did.
    pub reload_error: Option<String>,
}

impl TitleBar {
    pub fn new(now: Instant) -> Self {
        TitleBar {
            next_at: now,
            stale: false,
            reloading: false,
            reload_error: None,
        }
    }

    /// Whether the title should be set at `now`: always if `force`d, else
    /// at most once per [`TITLE_INTERVAL`] (a change held back makes the
    /// title stale).
    pub fn due(&mut self, now: Instant, force: bool) -> bool {
        if !force && now < self.next_at {
            self.stale = true;
            return false;
        }
        self.next_at = now + TITLE_INTERVAL;
        self.stale = false;
        true
    }

    /// Whether a change was held back since the title was last set.
    pub fn is_stale(&self) -> bool {
        self.stale
    }

    pub fn text(&self, facts: &TitleFacts) -> String {
        let progress = match facts.progress {
            Progress::Moving { scale } => format!("moving, 1/{scale} resolution"),
            Progress::Refining {
                passes,
                samples,
                path: false,
            } => format!("{passes}/{samples} spp"),
            Progress::Refining {
                passes,
                samples,
                path: true,
            } => format!("path traced, {passes}/{samples} spp"),
        };
        let accel = match facts.accel {
            Accel::Kdtree => format!("kdtree {} {}", facts.build, facts.traversal),
            Accel::Brute => "brute".to_string(),
        };
        let progress = match facts.denoise {
            Some(d) => format!("{progress} - {}", d.text()),
            None => progress,
        };
        let mut title = format!(
            "{} - {progress} - {:.1} ms - {:.2} Mrays/s - {accel} - depth {}",
            facts.name, facts.frame_ms, facts.mrays, facts.max_depth
        );
        if let Some((frame, frames, playing)) = facts.animation {
            let state = if playing { "playing" } else { "paused" };
            title.push_str(&format!(" - frame {frame}/{frames} {state}"));
        }
        if let Some(max) = facts.heatmap {
            title.push_str(&format!(
                " - HEATMAP: nodes + objects per sample, 0 to {max}"
            ));
        }
        if let Some(inspect) = facts.inspect {
            title.push_str(" - ");
            title.push_str(&inspect.text());
        }
        if self.reloading {
            title.push_str(" - reloading");
        }
        if let Some(e) = &self.reload_error {
            title.push_str(" - RELOAD FAILED: ");
            title.push_str(e);
        }
        title
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_title_says_progress_speed_settings_and_reloads() {
        let mut bar = TitleBar::new(Instant::now());
        let mut facts = TitleFacts {
            name: "seed.toml",
            progress: Progress::Refining {
                passes: 3,
                samples: 16,
                path: false,
            },
            frame_ms: 12.345,
            mrays: 1.5,
            accel: Accel::Kdtree,
            traversal: Traversal::Ropes,
            build: BuildStrategy::Sah,
            max_depth: 5,
            heatmap: None,
            animation: None,
            inspect: None,
            denoise: None,
        };
        assert_eq!(
            bar.text(&facts),
            "seed.toml - 3/16 spp - 12.3 ms - 1.50 Mrays/s - kdtree sah ropes - depth 5"
        );
        facts.traversal = Traversal::ShortStack;
        facts.build = BuildStrategy::Median;
        facts.heatmap = Some(120);
        assert_eq!(
            bar.text(&facts),
            "seed.toml - 3/16 spp - 12.3 ms - 1.50 Mrays/s - kdtree median short-stack - depth 5 \
             - HEATMAP: nodes + objects per sample, 0 to 120"
        );
        facts.heatmap = None;
        facts.animation = Some((12, 48, true));
        assert_eq!(
            bar.text(&facts),
            "seed.toml - 3/16 spp - 12.3 ms - 1.50 Mrays/s - kdtree median short-stack - depth 5 \
             - frame 12/48 playing"
        );
        facts.animation = None;
        facts.progress = Progress::Refining {
            passes: 7,
            samples: 256,
            path: true,
        };
        assert_eq!(
            bar.text(&facts),
            "seed.toml - path traced, 7/256 spp - 12.3 ms - 1.50 Mrays/s - kdtree median \
             short-stack - depth 5"
        );
        facts.progress = Progress::Moving { scale: 4 };
        facts.accel = Accel::Brute;
        bar.reloading = true;
        bar.reload_error = Some("scene.toml:3: camera.position: expected 3 numbers".into());
        assert_eq!(
            bar.text(&facts),
            "seed.toml - moving, 1/4 resolution - 12.3 ms - 1.50 Mrays/s - brute - depth 5 \
             - reloading - RELOAD FAILED: scene.toml:3: camera.position: expected 3 numbers"
        );
    }

    #[test]
    fn the_title_says_what_inspection_mode_shows() {
        let bar = TitleBar::new(Instant::now());
        let mut facts = TitleFacts {
            name: "seed.toml",
            progress: Progress::Refining {
                passes: 4,
                samples: 4,
                path: false,
            },
            frame_ms: 2.0,
            mrays: 3.0,
            accel: Accel::Brute,
            traversal: Traversal::Ropes,
            build: BuildStrategy::Sah,
            max_depth: 5,
            heatmap: None,
            animation: None,
            inspect: Some(InspectTitle::Waiting),
            denoise: None,
        };
        let start = "seed.toml - 4/4 spp - 2.0 ms - 3.00 Mrays/s - brute - depth 5 - ";
        let says = |facts: &TitleFacts| bar.text(facts).strip_prefix(start).unwrap().to_string();
        assert_eq!(says(&facts), "INSPECT: click a pixel");
        facts.inspect = Some(InspectTitle::Outside);
        assert_eq!(says(&facts), "INSPECT: click inside the image");
        facts.inspect = Some(InspectTitle::Failed("no device"));
        assert_eq!(says(&facts), "INSPECT FAILED: no device");
        let totals = Totals {
            rays: 3,
            nodes: 40,
            leaves: 12,
            tests: 9,
            restarts: 1,
        };
        facts.inspect = Some(InspectTitle::Shown {
            pixel: (12, 34),
            totals,
            path: false,
        });
        assert_eq!(
            says(&facts),
            "INSPECT 12,34: 3 rays, 40 nodes, 12 leaves, 9 tests, 1 restarts"
        );
        facts.inspect = Some(InspectTitle::Shown {
            pixel: (0, 7),
            totals,
            path: true,
        });
        assert_eq!(
            says(&facts),
            "INSPECT 0,7 (path sample): 3 rays, 40 nodes, 12 leaves, 9 tests, 1 restarts"
        );
    }

    #[test]
    fn the_title_says_whether_the_image_shown_is_denoised() {
        let bar = TitleBar::new(Instant::now());
        let mut facts = TitleFacts {
            name: "cornell_box.toml",
            progress: Progress::Refining {
                passes: 2,
                samples: 256,
                path: true,
            },
            frame_ms: 2.0,
            mrays: 3.0,
            accel: Accel::Brute,
            traversal: Traversal::Ropes,
            build: BuildStrategy::Sah,
            max_depth: 5,
            heatmap: None,
            animation: None,
            inspect: None,
            denoise: Some(DenoiseTitle::Waiting { at: 4 }),
        };
        let says = |facts: &TitleFacts| {
            let text = bar.text(facts);
            let end = text.find(" - 2.0 ms").unwrap();
            text["cornell_box.toml - ".len()..end].to_string()
        };
        assert_eq!(says(&facts), "path traced, 2/256 spp - denoise at 4 spp");
        facts.progress = Progress::Refining {
            passes: 9,
            samples: 256,
            path: true,
        };
        facts.denoise = Some(DenoiseTitle::Shown { samples: 8 });
        assert_eq!(says(&facts), "path traced, 9/256 spp - DENOISED at 8 spp");
        facts.denoise = Some(DenoiseTitle::Running {
            samples: 16,
            percent: 40,
            shown: Some(8),
        });
        assert_eq!(
            says(&facts),
            "path traced, 9/256 spp - DENOISED at 8 spp, denoising 16 spp: 40%"
        );
        facts.denoise = Some(DenoiseTitle::Running {
            samples: 4,
            percent: 0,
            shown: None,
        });
        assert_eq!(says(&facts), "path traced, 9/256 spp - denoising 4 spp: 0%");
        facts.progress = Progress::Moving { scale: 2 };
        facts.denoise = Some(DenoiseTitle::Waiting { at: 4 });
        assert_eq!(says(&facts), "moving, 1/2 resolution - denoise at 4 spp");
        facts.progress = Progress::Refining {
            passes: 1,
            samples: 16,
            path: false,
        };
        facts.denoise = Some(DenoiseTitle::NeedsPath);
        assert_eq!(
            says(&facts),
            "1/16 spp - denoising needs the path tracer (I)"
        );
        facts.denoise = None;
        assert_eq!(says(&facts), "1/16 spp");
    }

    #[test]
    fn the_title_changes_at_most_every_interval_unless_forced() {
        let t = Instant::now();
        let mut bar = TitleBar::new(t);
        assert!(bar.due(t, false));
        assert!(!bar.is_stale());
        let soon = t + TITLE_INTERVAL / 2;
        assert!(!bar.due(soon, false));
        assert!(bar.is_stale());
        assert!(bar.due(soon, true));
        assert!(!bar.is_stale());
        // The interval counts from the last change.
        assert!(!bar.due(t + TITLE_INTERVAL, false));
        assert!(bar.due(soon + TITLE_INTERVAL, false));
    }
}
