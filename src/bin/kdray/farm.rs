//! `kdray farm` (plan, write the batch scripts, `--submit`, `--wait`) and
//! the two hidden commands the scripts run on the cluster: `farm-task`
//! (one array task) and `farm-finish` (the finishing job).

use std::path::PathBuf;

use kdray::farm::{self, plan, FarmRequest, Finished, RenderFlags, Work};
use kdray::gpu::Accel;
use kdray::kdtree::{BuildStrategy, Traversal};
use kdray::{Error, Result};

use crate::args::choice;

#[derive(clap::Args)]
pub struct FarmArgs {
    /// The scene file.
    pub scene: PathBuf,
    /// The farm's folder: plan, batch scripts, the result, and parts/ (bands, logs).
    #[arg(long)]
    pub out: PathBuf,
    /// Image width in pixels (overrides the scene's [render] width).
    #[arg(long)]
    pub width: Option<u32>,
    /// Image height in pixels (overrides the scene's [render] height).
    #[arg(long)]
    pub height: Option<u32>,
    /// Samples per pixel, a perfect square (overrides the scene's [render] samples).
    #[arg(long)]
    pub samples: Option<u32>,
    /// Nearest-hit search in the shader.
    #[arg(long, value_parser = choice::<Accel>(), default_value = "kdtree")]
    pub accel: Accel,
    /// The kernel's k-d walk (with --accel kdtree).
    #[arg(long, value_parser = choice::<Traversal>(), default_value = "short-stack")]
    pub traversal: Traversal,
    /// How the k-d tree is built (with --accel kdtree).
    #[arg(long, value_parser = choice::<BuildStrategy>(), default_value = "sah")]
    pub build: BuildStrategy,
    /// Render a still of this frame of the scene's animation (0-based)
    /// instead of every frame.
    #[arg(long, value_name = "N")]
    pub frame: Option<u32>,
    /// Cut the still into N bands of rows, one array task each [default: 1].
    #[arg(long, value_name = "N")]
    pub tiles: Option<u32>,
    /// The job array's tasks, each rendering a contiguous share of the bands
    /// or frames [default: one per band; one per 50 frames].
    #[arg(long, value_name = "K")]
    pub tasks: Option<u32>,
    /// An sbatch option for both scripts, one per flag, e.g.
    /// --sbatch=--gres=gpu:1 --sbatch=--time=01:00:00 --sbatch=--partition=gpu.
    #[arg(long, value_name = "ARG", allow_hyphen_values = true)]
    pub sbatch: Vec<String>,
    /// Submit the array and the finishing job with sbatch and print their ids.
    #[arg(long)]
    pub submit: bool,
    /// With --submit: return when both jobs are done; exit 0 when everything
    /// is there, else name the failed tasks and their logs.
    #[arg(long, requires = "submit")]
    pub wait: bool,
    /// Discard the images of another render planned in --out and start again.
    #[arg(long)]
    pub force: bool,
}

#[derive(clap::Args)]
pub struct FarmTaskArgs {
    /// The farm's folder.
    pub dir: PathBuf,
    /// The task's index [default: $SLURM_ARRAY_TASK_ID, else $JOB_COMPLETION_INDEX].
    pub index: Option<u32>,
}

#[derive(clap::Args)]
pub struct FarmFinishArgs {
    /// The farm's folder.
    pub dir: PathBuf,
}

pub fn farm(args: FarmArgs) -> Result<()> {
    let kdray = std::env::current_exe()
        .map_err(|e| Error::Output(format!("cannot find kdray's own binary: {e}")))?;
    let request = FarmRequest {
        scene: args.scene,
        out: args.out,
        flags: RenderFlags {
            width: args.width,
            height: args.height,
            samples: args.samples,
            accel: args.accel,
            traversal: args.traversal,
            build: args.build,
        },
        frame: args.frame,
        tiles: args.tiles,
        tasks: args.tasks,
        sbatch: args.sbatch,
        force: args.force,
        kdray,
    };
    let prepared = farm::prepare(&request)?;
    let (dir, plan) = (&prepared.dir, &prepared.plan);
    if let Some(difference) = &prepared.discarded {
        eprintln!(
            "kdray: {}: discarded the earlier render ({difference})",
            dir.display()
        );
    }
    let what = match plan.work {
        Work::Still { frame, tiles } => format!(
            "a {}x{} still (frame {frame}) in {tiles} bands",
            plan.width, plan.height
        ),
        Work::Frames { frames, .. } => {
            format!("{frames} frames of {}x{}", plan.width, plan.height)
        }
    };
    println!(
        "{}: {what}, {} tasks, {} with work left{}",
        dir.display(),
        plan.tasks,
        prepared.pending_tasks.len(),
        match prepared.pending_tasks.is_empty() {
            true => String::new(),
            false => format!(" ({})", farm::slurm::index_list(&prepared.pending_tasks)),
        }
    );
    if prepared.complete {
        println!("complete, nothing to do: {}", result_name(dir, plan));
        return Ok(());
    }
    if !args.submit {
        println!(
            "submit with the same command and --submit, or by hand: sbatch --array={} {d}/{} \
             and then sbatch --dependency=afterok:ARRAY_JOB_ID --kill-on-invalid-dep=yes {d}/{}",
            farm::slurm::index_list(&prepared.pending_tasks),
            plan::ARRAY_SCRIPT,
            plan::FINISH_SCRIPT,
            d = dir.display()
        );
        return Ok(());
    }
    // A marker from an earlier finish must not pass for this one's.
    let marker = plan::finished_marker(dir);
    if let Err(e) = std::fs::remove_file(&marker) {
        if e.kind() != std::io::ErrorKind::NotFound {
            return Err(Error::File {
                path: marker,
                what: "cannot remove",
                source: e,
            });
        }
    }
    let submission = farm::slurm::submit(dir, plan, &prepared.pending_tasks)?;
    match &submission.array {
        Some((id, tasks)) => println!(
            "submitted array job {id} (tasks {}) and finishing job {}",
            farm::slurm::index_list(tasks),
            submission.finish
        ),
        None => println!("submitted finishing job {}", submission.finish),
    }
    if !args.wait {
        return Ok(());
    }
    farm::slurm::wait_for_jobs(&submission)?;
    let (failed, finished) = farm::slurm::outcome(dir, plan);
    if let Some(error) = farm::slurm::failure_report(dir, &failed, finished) {
        return Err(error);
    }
    println!("done: {}", result_name(dir, plan));
    Ok(())
}

/// The result in words: the still's PNG, or the frames (and their MP4).
fn result_name(dir: &std::path::Path, plan: &farm::FarmPlan) -> String {
    match plan.work {
        Work::Still { .. } => plan.final_path(dir).display().to_string(),
        Work::Frames { frames, .. } => {
            let video = plan.final_path(dir);
            format!(
                "{frames} frames in {}{}",
                dir.display(),
                match video.is_file() {
                    true => format!(", {}", video.display()),
                    false => String::new(),
                }
            )
        }
    }
}

pub fn farm_task(args: FarmTaskArgs) -> Result<()> {
    let index = farm::task_index(args.index)?;
    let report = farm::run_task(&args.dir, index)?;
    println!("{}", serde_json::to_string(&report)?);
    Ok(())
}

pub fn farm_finish(args: FarmFinishArgs) -> Result<()> {
    match farm::finish(&args.dir)? {
        Finished::Image(path) => println!("wrote {}", path.display()),
        Finished::Frames {
            frames,
            video: Some(video),
            ..
        } => println!("{frames} frames checked; wrote {}", video.display()),
        Finished::Frames {
            frames,
            video: None,
            ffmpeg_command,
        } => println!(
            "{frames} frames checked; ffmpeg is not installed: encode them with {ffmpeg_command}"
        ),
    }
    Ok(())
}
