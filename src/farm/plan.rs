//! The farm's plan, recorded as DIR/farm.json: what is rendered (a still
//! in bands of rows, or an animation's frames), with which flags, from
//! which input files (their hashes), how the work is shared among the
//! array's tasks, and where each file of DIR lives.

use std::ops::Range;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::fingerprint::InputFile;
use crate::error::{Error, Result};
pub use crate::render::RenderFlags;

/// The plan's file in DIR.
pub const PLAN_FILE: &str = "farm.json";
/// The array job's batch script in DIR.
pub const ARRAY_SCRIPT: &str = "render.sbatch";
/// The finishing job's batch script in DIR.
pub const FINISH_SCRIPT: &str = "finish.sbatch";
/// The subfolder of DIR for bands, logs and the finishing job's marker.
pub const PARTS_DIR: &str = "parts";

/// What the farm renders: its work items are a still's bands of rows, a
/// path-traced still's shares of its samples, or an animation's frames.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Work {
    /// One image (frame `frame` of the scene's animation, frame 0 without
    /// one) in `tiles` bands of rows, band `t` being rows
    /// `t * height / tiles .. (t + 1) * height / tiles`.
    Still { frame: u32, tiles: u32 },
    /// One path-traced image (frame `frame`) whose `samples` per pixel are
    /// cut into `shares` contiguous ranges, share `t` being samples
    /// `t * samples / shares .. (t + 1) * samples / shares` of every pixel
    /// (see [`super::samples`]).
    Samples {
        frame: u32,
        shares: u32,
        samples: u32,
    },
    /// Every frame of the scene's animation, frame `k` written as
    /// DIR/`k`.png (zero-padded to at least four digits).
    Frames { frames: u32, fps: f64 },
}

/// Everything a task or the finishing job needs to know, and what a re-run
/// compares against.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FarmPlan {
    /// The scene file, absolute.
    pub scene: PathBuf,
    /// The kdray binary the scripts run, absolute: every task the same.
    pub kdray: PathBuf,
    pub flags: RenderFlags,
    /// The image size after the flags' overrides.
    pub width: u32,
    pub height: u32,
    pub work: Work,
    /// The array's tasks; task `i` renders items [`FarmPlan::task_items`].
    pub tasks: u32,
    /// The scene file and every file it loads, with their hashes.
    pub inputs: Vec<InputFile>,
    /// Options passed through to sbatch (`#SBATCH` lines of both scripts).
    pub sbatch: Vec<String>,
    /// The image is denoised (`[render] denoise`, or `--denoise`): a still
    /// split by samples once, by the finishing job, from the shares'
    /// averaged radiance, albedo and normal; a still in one band or each
    /// frame of an animation by the task that renders it. A plan written
    /// without the key denoises nothing.
    #[serde(default)]
    pub denoise: bool,
}

impl FarmPlan {
    /// Work items: bands of the still, or frames.
    pub fn items(&self) -> u32 {
        match self.work {
            Work::Still { tiles, .. } => tiles,
            Work::Samples { shares, .. } => shares,
            Work::Frames { frames, .. } => frames,
        }
    }

    /// The frame of a still (`None` for an animation's frames).
    pub fn still_frame(&self) -> Option<u32> {
        match self.work {
            Work::Still { frame, .. } | Work::Samples { frame, .. } => Some(frame),
            Work::Frames { .. } => None,
        }
    }

    /// The samples of share `share` of a split by samples, as (first
    /// sample index, count); `None` for other work.
    pub fn sample_range(&self, part: u32) -> Option<(u32, u32)> {
        match self.work {
            Work::Samples {
                shares, samples, ..
            } => {
                let range = share(samples, shares, part);
                Some((range.start, range.len() as u32))
            }
            _ => None,
        }
    }

    /// The items of task `task`: a contiguous share, the shares' sizes
    /// differing by one at most ([`share`]).
    pub fn task_items(&self, task: u32) -> Range<u32> {
        share(self.items(), self.tasks, task)
    }

    /// The task that renders `item`.
    pub fn task_of(&self, item: u32) -> u32 {
        (0..self.tasks)
            .find(|&t| self.task_items(t).contains(&item))
            .unwrap_or(0)
    }

    /// Rows `first..end` of band `band` of a still (the whole image for a
    /// share of the samples or a frame of an animation).
    pub fn band_rows(&self, band: u32) -> (u32, u32) {
        match self.work {
            Work::Still { tiles, .. } => {
                let rows = share(self.height, tiles, band);
                (rows.start, rows.end)
            }
            Work::Samples { .. } | Work::Frames { .. } => (0, self.height),
        }
    }

    /// Where item `item` is written: a band (PNG) or a share of the
    /// samples (EXR of mean radiance) in the parts folder, or a frame at
    /// DIR's top level.
    pub fn item_path(&self, dir: &Path, item: u32) -> PathBuf {
        match self.work {
            Work::Still { .. } => parts_dir(dir).join(format!("band-{item:04}.png")),
            Work::Samples { .. } => parts_dir(dir).join(format!("samples-{item:04}.exr")),
            Work::Frames { frames, .. } => dir.join(frame_file_name(item, frames)),
        }
    }

    /// Every file item `item` writes: its [`FarmPlan::item_path`] and, for
    /// a share of the samples of a denoised still, the share's mean albedo
    /// and normal ([`share_feature_paths`]). The item path is written last,
    /// so an item is done when all of them are there.
    pub fn item_files(&self, dir: &Path, item: u32) -> Vec<PathBuf> {
        let path = self.item_path(dir, item);
        match self.work {
            Work::Samples { .. } if self.denoise => {
                let [albedo, normal] = share_feature_paths(&path);
                vec![albedo, normal, path]
            }
            _ => vec![path],
        }
    }

    /// Whether every file of item `item` is there.
    pub fn item_done(&self, dir: &Path, item: u32) -> bool {
        self.item_files(dir, item).iter().all(|p| p.is_file())
    }

    /// What the finishing job makes: the still's one PNG at DIR's top
    /// level, or the animation's MP4 (when ffmpeg is installed).
    pub fn final_path(&self, dir: &Path) -> PathBuf {
        let ext = match self.work {
            Work::Still { .. } | Work::Samples { .. } => "png",
            Work::Frames { .. } => "mp4",
        };
        dir.join(format!("{}.{ext}", self.stem()))
    }

    /// The finishing job's EXR of linear radiance beside the PNG, made by
    /// a split by samples only.
    pub fn final_exr_path(&self, dir: &Path) -> Option<PathBuf> {
        matches!(self.work, Work::Samples { .. }).then(|| dir.join(format!("{}.exr", self.stem())))
    }

    /// Every file the finishing job writes at DIR's top level: the
    /// still's PNG, its EXR (split by samples) and, denoised, the
    /// denoiser's three inputs beside the EXR
    /// ([`crate::output::denoised::denoise_input_paths`]); an animation's MP4.
    pub fn final_files(&self, dir: &Path) -> Vec<PathBuf> {
        let mut files = vec![self.final_path(dir)];
        if let Some(exr) = self.final_exr_path(dir) {
            if self.denoise {
                files.extend(crate::output::denoised::denoise_input_paths(&exr));
            }
            files.push(exr);
        }
        files
    }

    /// What a work item is called in messages: band, share or frame.
    pub fn item_word(&self) -> &'static str {
        match self.work {
            Work::Still { .. } => "band",
            Work::Samples { .. } => "share",
            Work::Frames { .. } => "frame",
        }
    }

    /// The scene file's name without its extension.
    pub fn stem(&self) -> String {
        self.scene
            .file_stem()
            .map_or("out".into(), |s| s.to_string_lossy().into_owned())
    }

    /// The first difference between the renders of two plans (flags, image
    /// size, work, input files, denoising), or `None` when they make the same images;
    /// tasks and sbatch options may differ.
    pub fn render_difference(&self, other: &FarmPlan) -> Option<String> {
        if self.scene != other.scene {
            return Some(format!(
                "the scene was {}, now {}",
                self.scene.display(),
                other.scene.display()
            ));
        }
        if self.flags != other.flags || (self.width, self.height) != (other.width, other.height) {
            return Some("the render flags changed".into());
        }
        if self.work != other.work {
            return Some("the work (--tiles, --split, --frame or the animation) changed".into());
        }
        super::fingerprint::difference(&self.inputs, &other.inputs).or_else(|| {
            (self.denoise != other.denoise)
                .then(|| "the denoising (--denoise or [render] denoise) changed".into())
        })
    }
}

/// `items` shared out among `tasks`: part `i` is `i * items / tasks ..
/// (i + 1) * items / tasks` (sizes differ by one at most).
pub fn share(items: u32, tasks: u32, i: u32) -> Range<u32> {
    let at = |i: u32| (i as u64 * items as u64 / tasks.max(1) as u64) as u32;
    at(i)..at(i + 1)
}

/// Frame `k`'s file name: at least four digits, more when the animation
/// has 10,000 frames or more, so that names sort in frame order.
pub fn frame_file_name(k: u32, frames: u32) -> String {
    format!("{k:0width$}.png", width = frame_digits(frames))
}

/// The digits of frame numbers: four, or those of the last frame.
pub fn frame_digits(frames: u32) -> usize {
    frames.saturating_sub(1).to_string().len().max(4)
}

/// A denoised share's mean albedo and normal beside its radiance
/// `parts/samples-T.exr`: `parts/samples-T.albedo.exr` and
/// `parts/samples-T.normal.exr`.
pub fn share_feature_paths(share: &Path) -> [PathBuf; 2] {
    ["albedo.exr", "normal.exr"].map(|e| share.with_extension(e))
}

/// DIR/parts: bands, logs, the finishing job's marker.
pub fn parts_dir(dir: &Path) -> PathBuf {
    dir.join(PARTS_DIR)
}

/// DIR/parts/logs: each task's and the finishing job's stdout and stderr.
pub fn logs_dir(dir: &Path) -> PathBuf {
    parts_dir(dir).join("logs")
}

/// Task `task`'s log (the array script's `--output`, `%a` the index).
pub fn task_log(dir: &Path, task: u32) -> PathBuf {
    logs_dir(dir).join(format!("task-{task}.log"))
}

/// The finishing job's log.
pub fn finish_log(dir: &Path) -> PathBuf {
    logs_dir(dir).join("finish.log")
}

/// Written by the finishing job once everything is there: what `--wait`
/// looks for (there is no accounting database to ask).
pub fn finished_marker(dir: &Path) -> PathBuf {
    parts_dir(dir).join("finished")
}

/// Reads DIR/farm.json, `None` when there is none.
pub fn read_plan(dir: &Path) -> Result<Option<FarmPlan>> {
    let path = dir.join(PLAN_FILE);
    let text = match std::fs::read_to_string(&path) {
        Ok(text) => text,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(source) => {
            return Err(Error::File {
                path,
                what: "cannot read the farm's plan",
                source,
            })
        }
    };
    serde_json::from_str(&text).map(Some).map_err(|e| {
        Error::Output(format!(
            "{}: not a kdray farm plan ({e}); remove it or pick another --out",
            path.display()
        ))
    })
}

/// Writes DIR/farm.json atomically.
pub fn write_plan(dir: &Path, plan: &FarmPlan) -> Result<()> {
    let mut text = serde_json::to_string_pretty(plan)?;
    text.push('\n');
    crate::output::write_file_atomic(&dir.join(PLAN_FILE), text.as_bytes())
}

/// What the finishing job made.
#[derive(Debug, Clone)]
pub enum Finished {
    /// The still's PNG.
    Image(PathBuf),
    /// A split by samples' shares averaged into the still's PNG (tone-mapped)
    /// and EXR (linear radiance), both denoised when `denoised` (the
    /// denoiser's inputs beside the EXR).
    Averaged {
        shares: u32,
        denoised: bool,
        png: PathBuf,
        exr: PathBuf,
    },
    /// Every frame checked; the MP4 when ffmpeg encoded it, else the
    /// command that would.
    Frames {
        frames: u32,
        video: Option<PathBuf>,
        ffmpeg_command: String,
    },
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shares_cover_every_item_once_in_order() {
        for items in 1..40 {
            for tasks in 1..=items {
                let parts: Vec<Range<u32>> = (0..tasks).map(|i| share(items, tasks, i)).collect();
                assert_eq!(parts[0].start, 0);
                assert_eq!(parts.last().unwrap().end, items);
                for w in parts.windows(2) {
                    assert_eq!(w[0].end, w[1].start);
                }
                let (min, max) = parts.iter().fold((u32::MAX, 0), |(a, b), p| {
                    (a.min(p.len() as u32), b.max(p.len() as u32))
                });
                assert!(max - min <= 1, "{items} items in {tasks} tasks: {parts:?}");
            }
        }
    }

    #[test]
    fn shares_of_samples_cover_every_sample_once_and_go_to_exr_parts() {
        let plan = FarmPlan {
            scene: "/scenes/cornell_box.toml".into(),
            kdray: "/bin/kdray".into(),
            flags: RenderFlags::no_overrides(),
            width: 64,
            height: 48,
            work: Work::Samples {
                frame: 0,
                shares: 3,
                samples: 40,
            },
            tasks: 3,
            inputs: vec![],
            sbatch: vec![],
            denoise: false,
        };
        let ranges: Vec<(u32, u32)> = (0..3).map(|t| plan.sample_range(t).unwrap()).collect();
        assert_eq!(ranges, [(0, 13), (13, 13), (26, 14)]);
        assert_eq!(plan.band_rows(2), (0, 48), "every share covers every row");
        let dir = Path::new("/farm");
        assert_eq!(
            plan.item_path(dir, 1),
            Path::new("/farm/parts/samples-0001.exr")
        );
        assert_eq!(plan.final_path(dir), Path::new("/farm/cornell_box.png"));
        assert_eq!(
            plan.final_exr_path(dir).unwrap(),
            Path::new("/farm/cornell_box.exr")
        );
        let json = serde_json::to_string(&plan.work).unwrap();
        assert_eq!(
            json,
            r#"{"kind":"samples","frame":0,"shares":3,"samples":40}"#
        );
        let still = FarmPlan {
            work: Work::Still { frame: 0, tiles: 3 },
            ..plan
        };
        assert_eq!(still.sample_range(0), None);
        assert_eq!(still.final_exr_path(dir), None);
    }

    #[test]
    fn a_denoised_share_writes_its_albedo_and_normal_before_its_radiance() {
        let plan = FarmPlan {
            scene: "/scenes/cornell_box.toml".into(),
            kdray: "/bin/kdray".into(),
            flags: RenderFlags::no_overrides(),
            width: 48,
            height: 48,
            work: Work::Samples {
                frame: 0,
                shares: 2,
                samples: 4,
            },
            tasks: 2,
            inputs: vec![],
            sbatch: vec![],
            denoise: true,
        };
        let dir = Path::new("/farm");
        let files = plan.item_files(dir, 1);
        assert_eq!(
            files,
            [
                "/farm/parts/samples-0001.albedo.exr",
                "/farm/parts/samples-0001.normal.exr",
                "/farm/parts/samples-0001.exr",
            ]
            .map(PathBuf::from)
        );
        assert_eq!(files.last(), Some(&plan.item_path(dir, 1)), "written last");
        assert_eq!(
            plan.final_files(dir),
            [
                "/farm/cornell_box.png",
                "/farm/cornell_box.noisy.exr",
                "/farm/cornell_box.albedo.exr",
                "/farm/cornell_box.normal.exr",
                "/farm/cornell_box.exr",
            ]
            .map(PathBuf::from)
        );
        let noisy = FarmPlan {
            denoise: false,
            ..plan.clone()
        };
        assert_eq!(noisy.item_files(dir, 1), [plan.item_path(dir, 1)]);
        assert_eq!(noisy.final_files(dir).len(), 2);
        assert_eq!(
            noisy.render_difference(&plan).as_deref(),
            Some("the denoising (--denoise or [render] denoise) changed")
        );
        // A plan written before the key existed reads as not denoised.
        let mut json: serde_json::Value = serde_json::to_value(&plan).unwrap();
        json.as_object_mut().unwrap().remove("denoise");
        let old: FarmPlan = serde_json::from_value(json).unwrap();
        assert_eq!(old, noisy);
    }

    #[test]
    fn frame_names_have_four_digits_or_those_of_the_last_frame() {
        assert_eq!(frame_file_name(7, 48), "0007.png");
        assert_eq!(frame_file_name(0, 10_000), "0000.png");
        assert_eq!(frame_file_name(12, 10_001), "00012.png");
        assert_eq!(frame_file_name(99_999, 100_000), "99999.png");
    }
}
