//! Rendering on a cluster (`kdray farm`): kdray writes batch scripts for
//! the cluster's own scheduler (Slurm: a job array and a dependent
//! finishing job) instead of distributing work itself.
//!
//! DIR (`--out`) holds:
//! - farm.json, the plan ([`plan`]): scene, flags, the input files' hashes
//!   ([`fingerprint`]), the work items (a still's bands of rows, or an
//!   animation's frames) and their share among the tasks;
//! - render.sbatch and finish.sbatch ([`scripts`]);
//! - the result: a still's one PNG (and, split by samples, its EXR), or the
//!   frames 0000.png, 0001.png, ... (and an MP4, [`video`]); denoised when
//!   the plan says so ([`crate::output::denoised`]);
//! - parts/: the still's bands or shares of samples ([`samples`]), every
//!   job's log, the finishing job's marker.
//!
//! [`prepare`](mod@prepare) writes the plan and scripts and works out what is missing;
//! [`slurm`] submits and waits; [`task`] is what runs on the nodes. Every
//! file is written atomically, so a killed task leaves no half file and a
//! re-run renders only what is missing.

pub mod fingerprint;
pub mod plan;
pub mod prepare;
pub mod samples;
pub mod scripts;
pub mod slurm;
pub mod task;
pub mod video;

use std::path::{Path, PathBuf};

pub use plan::Finished;
pub use plan::{FarmPlan, RenderFlags, Work};
pub use prepare::Split;
pub use prepare::{prepare, FarmRequest, Prepared};
pub use slurm::Submission;
pub use task::{finish, run_task, task_index, TaskReport};

/// The executable `name` in the PATH's folders, if any.
pub fn find_on_path(name: &str) -> Option<PathBuf> {
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path)
        .map(|dir| dir.join(name))
        .find(|p| is_executable(p))
}

fn is_executable(path: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        std::fs::metadata(path).is_ok_and(|m| m.is_file() && m.permissions().mode() & 0o111 != 0)
    }
    #[cfg(not(unix))]
    {
        path.is_file()
    }
}

/// Missing items in words, with the tasks that render them: "band 2
/// (task 2), band 3 (task 3)", the first few only.
pub(crate) fn missing_summary(plan: &FarmPlan, dir: &Path, missing: &[u32]) -> String {
    const SHOWN: usize = 5;
    let what = plan.item_word();
    let mut parts: Vec<String> = missing
        .iter()
        .take(SHOWN)
        .map(|&i| {
            let task = plan.task_of(i);
            format!(
                "{what} {i} (task {task}, log {})",
                plan::task_log(dir, task).display()
            )
        })
        .collect();
    if missing.len() > SHOWN {
        parts.push(format!("{} more", missing.len() - SHOWN));
    }
    parts.join(", ")
}
