//! `kdray farm`'s first step: the scene is loaded and its input files
//! hashed, the plan and both scripts written into DIR, and what is still
//! missing worked out. A DIR planned for another render (a changed scene,
//! file it loads, or flag) is refused unless `force`, which discards that
//! render's images first.

use std::path::{Path, PathBuf};

use super::plan::{self, FarmPlan, RenderFlags, Work};
use crate::choice::Choice;
use crate::error::{Error, Result};
use crate::scene::{Integrator, Scene};

/// How a still is cut into work items (`--split`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Split {
    /// Bands of rows, each traced with every sample: any integrator.
    #[default]
    Rows,
    /// Shares of the path tracer's samples, each traced over the whole
    /// image, averaged by the finishing job.
    Samples,
}

impl Choice for Split {
    const ALL: &'static [Self] = &[Self::Rows, Self::Samples];

    fn name(self) -> &'static str {
        match self {
            Self::Rows => "rows",
            Self::Samples => "samples",
        }
    }

    fn help(self) -> &'static str {
        match self {
            Self::Rows => "bands of rows, each with all samples (any integrator)",
            Self::Samples => {
                "shares of the path tracer's samples over the whole image, averaged at the end"
            }
        }
    }
}

/// Frames per task when `--tasks` is not given: enough that a task's fixed
/// cost (start-up, adapter, tree build and upload) is small beside its
/// frames (docs/farm.md), few enough that a lost task costs little.
pub const DEFAULT_FRAMES_PER_TASK: u32 = 50;

/// What `kdray farm` was asked for.
#[derive(Debug, Clone)]
pub struct FarmRequest {
    pub scene: PathBuf,
    pub out: PathBuf,
    pub flags: RenderFlags,
    /// `--denoise[=BOOL]` over the scene's `[render] denoise`.
    pub denoise: Option<bool>,
    /// A still of this frame of the scene's animation.
    pub frame: Option<u32>,
    /// A still in this many parts (one task each by default): bands of
    /// rows, or shares of the samples with [`Split::Samples`].
    pub tiles: Option<u32>,
    /// How a still is cut.
    pub split: Split,
    /// The array's tasks [default: one per band for a still; one per
    /// [`DEFAULT_FRAMES_PER_TASK`] frames for an animation].
    pub tasks: Option<u32>,
    /// Options for both scripts' `#SBATCH` lines.
    pub sbatch: Vec<String>,
    /// Discard the images of another render planned in DIR.
    pub force: bool,
    /// The kdray binary the scripts run (this one).
    pub kdray: PathBuf,
}

/// DIR ready to submit.
#[derive(Debug, Clone)]
pub struct Prepared {
    /// DIR, absolute.
    pub dir: PathBuf,
    pub plan: FarmPlan,
    /// The tasks with parts still missing, in order.
    pub pending_tasks: Vec<u32>,
    /// Every part and the finishing job's result are there: nothing to do.
    pub complete: bool,
    /// What `force` discarded: the earlier render's difference.
    pub discarded: Option<String>,
}

/// Loads the scene, writes DIR's plan and scripts, and says what is left.
pub fn prepare(request: &FarmRequest) -> Result<Prepared> {
    request.flags.check()?;
    let scene_path = absolute(&request.scene)?;
    let (mut scene, inputs) = super::fingerprint::load_and_fingerprint(&scene_path)?;
    request.flags.apply(&mut scene)?;
    scene.render.denoise = denoise_of(&scene, request.denoise)?;
    let work = work_for(&scene, request)?;
    let dir = absolute(&request.out)?;
    let mut plan = FarmPlan {
        scene: scene_path,
        kdray: request.kdray.clone(),
        flags: request.flags.clone(),
        width: scene.render.width,
        height: scene.render.height,
        work,
        tasks: 1,
        inputs,
        sbatch: request.sbatch.clone(),
        denoise: scene.render.denoise,
    };
    let items = plan.items();
    plan.tasks = match (request.tasks, &plan.work) {
        (Some(t), _) => t,
        (None, Work::Frames { frames, .. }) => frames.div_ceil(DEFAULT_FRAMES_PER_TASK),
        (None, _) => items,
    };
    if !(1..=items).contains(&plan.tasks) {
        return Err(Error::Usage(format!(
            "--tasks: must be in 1..={items} (one {} at least per task), got {}",
            plan.item_word(),
            plan.tasks
        )));
    }
    // The scripts are checked (DIR's path, the options) before DIR is touched.
    super::scripts::array_script(&plan, &dir)?;
    super::scripts::finish_script(&plan, &dir)?;

    let mut discarded = None;
    if let Some(old) = plan::read_plan(&dir)? {
        if let Some(difference) = old.render_difference(&plan) {
            if !request.force {
                return Err(Error::Usage(format!(
                    "{}: planned for another render ({difference}): its images would not match; \
                     pass --force to discard them and start again, or pick another --out",
                    dir.display()
                )));
            }
            discard(&old, &dir)?;
            discarded = Some(difference);
        }
    }
    let logs = plan::logs_dir(&dir);
    std::fs::create_dir_all(&logs).map_err(|source| Error::File {
        path: logs,
        what: "cannot create the folder",
        source,
    })?;
    plan::write_plan(&dir, &plan)?;
    super::scripts::write_scripts(&plan, &dir)?;

    let pending_tasks: Vec<u32> = (0..plan.tasks)
        .filter(|&t| plan.task_items(t).any(|i| !plan.item_done(&dir, i)))
        .collect();
    let result_there = match plan.work {
        Work::Still { .. } | Work::Samples { .. } => {
            plan.final_files(&dir).iter().all(|f| f.is_file())
        }
        Work::Frames { .. } => true,
    };
    let complete =
        pending_tasks.is_empty() && result_there && plan::finished_marker(&dir).is_file();
    Ok(Prepared {
        dir,
        plan,
        pending_tasks,
        complete,
        discarded,
    })
}

/// A still (of `--frame`, in `--tiles` bands or, with `--split samples`,
/// shares of its samples) or, for a scene with an animation and none of
/// these flags, its frames.
fn work_for(scene: &Scene, request: &FarmRequest) -> Result<Work> {
    let animation = animation_of(scene);
    if let Some(frame) = request.frame {
        let frames = animation.map_or(1, |(frames, _)| frames);
        if frame >= frames {
            return Err(Error::Usage(format!(
                "--frame: the scene has frames 0..{frames}, got {frame}"
            )));
        }
    }
    if request.split == Split::Samples {
        return samples_work(scene, request);
    }
    match (animation, request.frame, request.tiles) {
        (Some((frames, fps)), None, None) => Ok(Work::Frames { frames, fps }),
        (_, frame, tiles) => {
            let tiles = tiles.unwrap_or(1);
            let height = scene.render.height;
            if !(1..=height).contains(&tiles) {
                return Err(Error::Usage(format!(
                    "--tiles: must be in 1..={height} (one row at least per band), got {tiles}"
                )));
            }
            if scene.render.denoise && tiles > 1 {
                return Err(Error::Usage(format!(
                    "--tiles {tiles}: a denoised still is denoised whole, not band by band: \
                     split it by samples (--split samples --parts {tiles}) or render it in one band \
                     (--denoise=false turns the denoiser off)"
                )));
            }
            Ok(Work::Still {
                frame: frame.unwrap_or(0),
                tiles,
            })
        }
    }
}

/// A path-traced still whose samples are cut into `--parts` shares.
fn samples_work(scene: &Scene, request: &FarmRequest) -> Result<Work> {
    if scene.render.integrator != Integrator::Path {
        return Err(Error::Usage(format!(
            "--split samples: {} is rendered by the {} integrator; the split by samples \
             needs the path tracer (integrator = \"path\" or --integrator path)",
            request.scene.display(),
            scene.render.integrator.name()
        )));
    }
    let samples = scene.render.samples;
    let shares = request.tiles.unwrap_or(1);
    if !(1..=samples).contains(&shares) {
        return Err(Error::Usage(format!(
            "--parts: must be in 1..={samples} (one sample at least per share), got {shares}"
        )));
    }
    Ok(Work::Samples {
        frame: request.frame.unwrap_or(0),
        shares,
        samples,
    })
}

/// Whether the farm denoises: `--denoise[=BOOL]` (`flag`) over the scene's
/// `[render] denoise`, refused with the Whitted integrator in the words
/// `kdray render` uses.
fn denoise_of(scene: &Scene, flag: Option<bool>) -> Result<bool> {
    let denoise = flag.unwrap_or(scene.render.denoise);
    if denoise && scene.render.integrator != Integrator::Path {
        return Err(Error::Usage(match flag {
            Some(_) => "--denoise: the denoiser needs the path tracer (--integrator path or [render] integrator = \"path\")".into(),
            None => "--integrator whitted: the scene's [render] denoise = true needs the path tracer (--denoise=false turns it off)".into(),
        }));
    }
    Ok(denoise)
}

/// The scene's animation as (frames, frames per second), if it has one.
fn animation_of(scene: &Scene) -> Option<(u32, f64)> {
    scene.animation.as_ref().map(|a| (a.frames, a.fps))
}

/// Removes what an earlier plan rendered into DIR: its parts folder (bands,
/// logs, marker), its frames and its result.
fn discard(old: &FarmPlan, dir: &Path) -> Result<()> {
    let remove = |path: &Path| match std::fs::remove_file(path) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => Err(Error::File {
            path: path.to_path_buf(),
            what: "cannot remove",
            source: e,
        }),
        _ => Ok(()),
    };
    if let Work::Frames { frames, .. } = old.work {
        for k in 0..frames {
            remove(&old.item_path(dir, k))?;
        }
    }
    for file in old.final_files(dir) {
        remove(&file)?;
    }
    let parts = plan::parts_dir(dir);
    match std::fs::remove_dir_all(&parts) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => Err(Error::File {
            path: parts,
            what: "cannot remove",
            source: e,
        }),
        _ => Ok(()),
    }
}

fn absolute(path: &Path) -> Result<PathBuf> {
    std::path::absolute(path).map_err(|source| Error::File {
        path: path.to_path_buf(),
        what: "cannot make the path absolute",
        source,
    })
}

#[cfg(test)]
mod tests {
    #[test]
    fn split_names_round_trip() {
        kdray_core::choice::assert_names_round_trip::<super::Split>();
    }
}
