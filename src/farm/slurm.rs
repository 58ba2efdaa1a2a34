//! Talking to Slurm: submitting the array (only its tasks with work left)
//! and the finishing job that depends on it, and waiting for both by
//! polling `squeue`. Without accounting storage (`sacct`) a finished job
//! leaves no record to ask, so the outcome is judged by the files: every
//! part, and the finishing job's marker.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

use super::plan::{self, FarmPlan, ARRAY_SCRIPT, FINISH_SCRIPT};
use crate::error::{Error, Result};

/// The job ids of a submission.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Submission {
    /// The array job, with the tasks it runs; `None` when every part was
    /// there and only the finishing job was submitted.
    pub array: Option<(String, Vec<u32>)>,
    pub finish: String,
}

/// The one-line error for a machine without sbatch: how to run the
/// written scripts by hand, or where to get Slurm.
pub fn no_sbatch_error(dir: &Path, plan: &FarmPlan) -> Error {
    let d = dir.display();
    Error::Output(format!(
        "sbatch not found on the PATH: run the scripts by hand (for i in $(seq 0 {}); do sh {d}/{ARRAY_SCRIPT} $i; done; sh {d}/{FINISH_SCRIPT}), \
         under a scheduler that sets SLURM_ARRAY_TASK_ID or JOB_COMPLETION_INDEX, \
         or install Slurm's client (Debian: apt-get install slurm-client) and point it at a cluster",
        plan.tasks - 1
    ))
}

/// Submits the array job for `tasks` (none: only the finishing job) and
/// the finishing job, which runs once every task has succeeded
/// (`afterok`) and is cancelled when one fails (`--kill-on-invalid-dep`:
/// without it, it would pend forever).
pub fn submit(dir: &Path, plan: &FarmPlan, tasks: &[u32]) -> Result<Submission> {
    let sbatch = super::find_on_path("sbatch").ok_or_else(|| no_sbatch_error(dir, plan))?;
    let array = match tasks.is_empty() {
        true => None,
        false => {
            let id = run_sbatch(
                &sbatch,
                &[
                    format!("--array={}", index_list(tasks)),
                    dir.join(ARRAY_SCRIPT).to_string_lossy().into_owned(),
                ],
            )?;
            Some((id, tasks.to_vec()))
        }
    };
    let mut args = Vec::new();
    if let Some((id, _)) = &array {
        args.push(format!("--dependency=afterok:{id}"));
        args.push("--kill-on-invalid-dep=yes".into());
    }
    args.push(dir.join(FINISH_SCRIPT).to_string_lossy().into_owned());
    let finish = run_sbatch(&sbatch, &args)?;
    Ok(Submission { array, finish })
}

/// DIR/parts/submission.json: the last submission's job ids, so that a
/// later `--wait` without `--submit` waits for them.
fn submission_file(dir: &Path) -> PathBuf {
    plan::parts_dir(dir).join("submission.json")
}

/// Records `submission` in DIR (atomically).
pub fn record(dir: &Path, submission: &Submission) -> Result<()> {
    let mut text = serde_json::to_string_pretty(submission)?;
    text.push('\n');
    crate::output::write_file_atomic(&submission_file(dir), text.as_bytes())
}

/// The submission recorded in DIR, if any (an unreadable record counts as none).
pub fn recorded(dir: &Path) -> Option<Submission> {
    let text = std::fs::read_to_string(submission_file(dir)).ok()?;
    serde_json::from_str(&text).ok()
}

/// Runs `sbatch --parsable ARGS` and returns the job id it prints
/// (`ID` or `ID;CLUSTER`).
fn run_sbatch(sbatch: &Path, args: &[String]) -> Result<String> {
    let out = Command::new(sbatch)
        .arg("--parsable")
        .args(args)
        .output()
        .map_err(|e| Error::Output(format!("cannot run {}: {e}", sbatch.display())))?;
    let stdout = String::from_utf8_lossy(&out.stdout);
    let id = stdout
        .trim()
        .split(';')
        .next()
        .unwrap_or("")
        .trim()
        .to_string();
    if !out.status.success() || id.is_empty() || !id.chars().all(|c| c.is_ascii_digit()) {
        return Err(Error::Output(format!(
            "sbatch {} failed ({}): {}",
            args.join(" "),
            out.status,
            String::from_utf8_lossy(&out.stderr).trim()
        )));
    }
    Ok(id)
}

/// Indices as Slurm's `--array` list: runs as ranges (`0-2,5,7-8`).
pub fn index_list(indices: &[u32]) -> String {
    let mut parts = Vec::new();
    let mut i = 0;
    while i < indices.len() {
        let start = indices[i];
        let mut end = start;
        while i + 1 < indices.len() && indices[i + 1] == end + 1 {
            end += 1;
            i += 1;
        }
        parts.push(match start == end {
            true => start.to_string(),
            false => format!("{start}-{end}"),
        });
        i += 1;
    }
    parts.join(",")
}

/// Waits until none of the submission's jobs is queued or running, polling
/// `squeue` every half second at first, then less often (at most every 5 s).
pub fn wait_for_jobs(submission: &Submission) -> Result<()> {
    let squeue = super::find_on_path("squeue")
        .ok_or_else(|| Error::Output("squeue not found on the PATH: cannot wait".into()))?;
    let mut ids: Vec<&str> = vec![submission.finish.as_str()];
    if let Some((id, _)) = &submission.array {
        ids.push(id);
    }
    let mut delay = Duration::from_millis(500);
    let mut failures = 0;
    loop {
        match queued_jobs(&squeue) {
            Ok(jobs) => {
                failures = 0;
                if !jobs.iter().any(|j| ids.contains(&j.as_str())) {
                    return Ok(());
                }
            }
            // slurmctld may be busy for a moment; a minute of errors is not.
            Err(e) => {
                failures += 1;
                if failures >= 12 {
                    return Err(e);
                }
            }
        }
        std::thread::sleep(delay);
        delay = (delay * 5 / 4).min(Duration::from_secs(5));
    }
}

/// The ids of every job in the queue (pending, running, completing): for an
/// array task its array's id (`%F`), for other jobs their own (`%A`).
fn queued_jobs(squeue: &Path) -> Result<Vec<String>> {
    let out = Command::new(squeue)
        .args(["-h", "-o", "%F %A"])
        .output()
        .map_err(|e| Error::Output(format!("cannot run {}: {e}", squeue.display())))?;
    if !out.status.success() {
        return Err(Error::Output(format!(
            "squeue failed ({}): {}",
            out.status,
            String::from_utf8_lossy(&out.stderr).trim()
        )));
    }
    Ok(String::from_utf8_lossy(&out.stdout)
        .split_whitespace()
        .map(str::to_string)
        .collect())
}

/// A failed task: the parts it did not write, and its log.
#[derive(Debug, Clone, PartialEq)]
pub struct FailedTask {
    pub task: u32,
    pub missing: Vec<u32>,
    pub log: PathBuf,
}

/// The outcome as the files tell it: the tasks whose parts are missing,
/// and whether the finishing job completed (its marker).
pub fn outcome(dir: &Path, plan: &FarmPlan) -> (Vec<FailedTask>, bool) {
    let failed = (0..plan.tasks)
        .filter_map(|task| {
            let missing: Vec<u32> = plan
                .task_items(task)
                .filter(|&i| !plan.item_done(dir, i))
                .collect();
            (!missing.is_empty()).then(|| FailedTask {
                task,
                missing,
                log: plan::task_log(dir, task),
            })
        })
        .collect();
    (failed, plan::finished_marker(dir).is_file())
}

/// The error `--wait` ends with when something is missing: each failed
/// task with its log, or the finishing job's log.
pub fn failure_report(dir: &Path, failed: &[FailedTask], finished: bool) -> Option<Error> {
    if failed.is_empty() && finished {
        return None;
    }
    let mut lines = Vec::new();
    for f in failed {
        let log = match f.log.is_file() {
            true => f.log.display().to_string(),
            false => format!("{} (absent: the task did not start)", f.log.display()),
        };
        lines.push(format!(
            "task {} failed ({} of its parts missing), log {log}",
            f.task,
            f.missing.len()
        ));
    }
    if !finished {
        let log = plan::finish_log(dir);
        lines.push(match (failed.is_empty(), log.is_file()) {
            (false, _) => "the finishing job was cancelled: a task it depends on failed".into(),
            (true, true) => format!("the finishing job failed, log {}", log.display()),
            (true, false) => "the finishing job did not run".into(),
        });
    }
    Some(Error::Output(format!(
        "{}: {}; run the same kdray farm command again to render only what is missing",
        dir.display(),
        lines.join("; ")
    )))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn index_lists_are_written_as_ranges() {
        assert_eq!(index_list(&[0, 1, 2, 5, 7, 8]), "0-2,5,7-8");
        assert_eq!(index_list(&[3]), "3");
        assert_eq!(index_list(&[]), "");
    }
}
