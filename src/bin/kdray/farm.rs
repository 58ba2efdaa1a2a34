//! `kdray farm` (plan, write the batch scripts, `--submit`, `--wait`) and
//! the two hidden commands the scripts run on the cluster: `farm-task`
//! (one array task) and `farm-finish` (the finishing job).

use kdray::farm::{self, plan, FarmRequest, Finished, Work};
use kdray::{Error, Result};

use crate::args::{FarmArgs, FarmFinishArgs, FarmTaskArgs};

pub fn farm(args: FarmArgs) -> Result<()> {
    let kdray = std::env::current_exe()
        .map_err(|e| Error::Output(format!("cannot find kdray's own binary: {e}")))?;
    let request = FarmRequest {
        scene: args.scene,
        out: args.out,
        flags: args.image.into(),
        denoise: args.denoise,
        frame: args.frame,
        tiles: args.tiles,
        split: args.split,
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
    let mut what = match plan.work {
        Work::Still { frame, tiles } => format!(
            "a {}x{} still (frame {frame}) in {tiles} bands",
            plan.width, plan.height
        ),
        Work::Samples {
            frame,
            shares,
            samples,
        } => format!(
            "a {}x{} still (frame {frame}) of {samples} samples in {shares} shares",
            plan.width, plan.height
        ),
        Work::Frames { frames, .. } => {
            format!("{frames} frames of {}x{}", plan.width, plan.height)
        }
    };
    if plan.denoise {
        what.push_str(", denoised");
    }
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
    if !args.submit && args.wait {
        let submission = farm::slurm::recorded(dir).ok_or_else(|| {
            Error::Usage(format!(
                "{}: no submission recorded to wait for: add --submit",
                dir.display()
            ))
        })?;
        println!("waiting for {}", jobs_in_words(&submission));
        return wait_and_report(dir, plan, &submission);
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
    farm::slurm::record(dir, &submission)?;
    println!("submitted {}", jobs_in_words(&submission));
    if !args.wait {
        return Ok(());
    }
    wait_and_report(dir, plan, &submission)
}

/// "array job ID (tasks LIST) and finishing job ID", or the finishing job alone.
fn jobs_in_words(submission: &farm::slurm::Submission) -> String {
    match &submission.array {
        Some((id, tasks)) => format!(
            "array job {id} (tasks {}) and finishing job {}",
            farm::slurm::index_list(tasks),
            submission.finish
        ),
        None => format!("finishing job {}", submission.finish),
    }
}

/// Waits until the submission's jobs have left the queue, then judges by
/// the files: Ok when everything is there, else the failed tasks and logs.
fn wait_and_report(
    dir: &std::path::Path,
    plan: &farm::FarmPlan,
    submission: &farm::slurm::Submission,
) -> Result<()> {
    farm::slurm::wait_for_jobs(submission)?;
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
        Work::Samples { .. } => match plan.final_exr_path(dir) {
            Some(exr) => format!(
                "{} and {}{}",
                plan.final_path(dir).display(),
                exr.display(),
                match plan.denoise {
                    true => " (denoised, beside its noisy, albedo and normal EXRs)",
                    false => "",
                }
            ),
            None => plan.final_path(dir).display().to_string(),
        },
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
        Finished::Averaged {
            shares,
            denoised,
            png,
            exr,
        } => println!(
            "{shares} shares of samples averaged{}; wrote {} and {}",
            match denoised {
                true => " and denoised",
                false => "",
            },
            png.display(),
            exr.display()
        ),
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
