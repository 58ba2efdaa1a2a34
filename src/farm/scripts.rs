//! The two batch scripts a farm writes into DIR: the array job
//! (render.sbatch: task `I` renders its share of the plan) and the
//! finishing job (finish.sbatch: the still's bands into one PNG, or every
//! frame checked and encoded). Both are plain `sh` scripts whose `#SBATCH`
//! lines Slurm reads and any other shell skips, so they also run by hand
//! and under any scheduler that hands out an index.

use std::path::Path;

use super::plan::{finish_log, logs_dir, FarmPlan, ARRAY_SCRIPT, FINISH_SCRIPT};
use crate::error::{Error, Result};

/// The environment variables a task takes its index from, in order, when
/// no index is given as its argument: Slurm's job arrays, then Kubernetes
/// Indexed Jobs.
pub const INDEX_VARIABLES: [&str; 2] = ["SLURM_ARRAY_TASK_ID", "JOB_COMPLETION_INDEX"];

/// The array job's script.
pub fn array_script(plan: &FarmPlan, dir: &Path) -> Result<String> {
    check_dir(dir)?;
    let kdray = quoted(&plan.kdray)?;
    let quoted_dir = quoted(dir)?;
    let last = plan.tasks - 1;
    let mut s = String::new();
    s.push_str("#!/bin/sh\n");
    s.push_str(&format!(
        "# kdray farm: task I of 0..{last} renders its share of {} (see farm.json).\n",
        dir.display()
    ));
    s.push_str("# The index comes from the first argument, else SLURM_ARRAY_TASK_ID (Slurm\n");
    s.push_str("# job arrays), else JOB_COMPLETION_INDEX (Kubernetes Indexed Jobs). By hand:\n");
    s.push_str(&format!(
        "#   for i in $(seq 0 {last}); do sh {}/{ARRAY_SCRIPT} $i; done; sh {}/{FINISH_SCRIPT}\n",
        quoted_dir, quoted_dir
    ));
    s.push_str(&format!("#SBATCH --job-name=kdray-{}\n", plan.stem()));
    s.push_str(&format!("#SBATCH --array=0-{last}\n"));
    s.push_str(&format!(
        "#SBATCH --output={}\n",
        directive_path(&logs_dir(dir).join("task-%a.log"))
    ));
    push_user_options(&mut s, &plan.sbatch)?;
    s.push_str(&format!("exec {kdray} farm-task {quoted_dir} \"$@\"\n"));
    Ok(s)
}

/// The finishing job's script.
pub fn finish_script(plan: &FarmPlan, dir: &Path) -> Result<String> {
    check_dir(dir)?;
    let kdray = quoted(&plan.kdray)?;
    let quoted_dir = quoted(dir)?;
    let mut s = String::new();
    s.push_str("#!/bin/sh\n");
    s.push_str(&format!(
        "# kdray farm: once every task of {ARRAY_SCRIPT} has succeeded, checks every\n\
         # part of {} and makes the result ({}).\n",
        dir.display(),
        plan.final_path(dir).display()
    ));
    s.push_str(&format!(
        "#SBATCH --job-name=kdray-{}-finish\n",
        plan.stem()
    ));
    s.push_str(&format!(
        "#SBATCH --output={}\n",
        directive_path(&finish_log(dir))
    ));
    push_user_options(&mut s, &plan.sbatch)?;
    s.push_str(&format!("exec {kdray} farm-finish {quoted_dir}\n"));
    Ok(s)
}

/// Both scripts into DIR, atomically.
pub fn write_scripts(plan: &FarmPlan, dir: &Path) -> Result<()> {
    for (name, text) in [
        (ARRAY_SCRIPT, array_script(plan, dir)?),
        (FINISH_SCRIPT, finish_script(plan, dir)?),
    ] {
        let path = dir.join(name);
        crate::output::write_file_atomic(&path, text.as_bytes())?;
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o755)).map_err(
                |source| Error::File {
                    path: path.clone(),
                    what: "cannot make executable",
                    source,
                },
            )?;
        }
    }
    Ok(())
}

/// One `#SBATCH` line per `--sbatch` option. Slurm reads each line's
/// words itself, so an option is one word: no white space or quotes.
fn push_user_options(s: &mut String, options: &[String]) -> Result<()> {
    for option in options {
        if option.is_empty()
            || option
                .chars()
                .any(|c| c.is_whitespace() || c == '"' || c == '\'' || c.is_control())
        {
            return Err(Error::Usage(format!(
                "--sbatch {option:?}: one option per --sbatch, without spaces or quotes \
                 (for example --sbatch=--time=01:00:00)"
            )));
        }
        s.push_str(&format!("#SBATCH {option}\n"));
    }
    Ok(())
}

/// Checks that DIR can be named on an `#SBATCH` line: no white space,
/// quotes, backslashes or `%` (Slurm's file name patterns).
fn check_dir(dir: &Path) -> Result<()> {
    let text = dir.to_string_lossy();
    let bad = |c: char| c.is_whitespace() || c.is_control() || matches!(c, '"' | '\'' | '\\' | '%');
    match text.chars().any(bad) {
        true => Err(Error::Usage(format!(
            "--out {}: the folder's path must not hold spaces, quotes, backslashes or %, \
             which batch scripts cannot carry",
            dir.display()
        ))),
        false => Ok(()),
    }
}

/// A path in a checked DIR, for an `#SBATCH` line.
fn directive_path(path: &Path) -> String {
    path.to_string_lossy().into_owned()
}

/// `path` in single quotes for `sh` (a `'` inside as `'\''`).
fn quoted(path: &Path) -> Result<String> {
    let text = path.to_str().ok_or_else(|| {
        Error::Usage(format!(
            "{}: not UTF-8, which the batch scripts cannot name",
            path.display()
        ))
    })?;
    Ok(format!("'{}'", text.replace('\'', r"'\''")))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::farm::plan::{RenderFlags, Work};

    fn plan(sbatch: &[&str]) -> FarmPlan {
        FarmPlan {
            scene: "/scenes/seed.toml".into(),
            kdray: "/opt/kdray/bin/kdray".into(),
            flags: RenderFlags::no_overrides(),
            width: 64,
            height: 48,
            work: Work::Still { frame: 0, tiles: 4 },
            tasks: 4,
            inputs: vec![],
            sbatch: sbatch.iter().map(|s| s.to_string()).collect(),
            denoise: false,
        }
    }

    #[test]
    fn the_array_script_names_its_tasks_logs_and_options() {
        let s = array_script(
            &plan(&["--gres=gpu:1", "--time=10"]),
            Path::new("/farm/out"),
        )
        .unwrap();
        assert!(s.starts_with("#!/bin/sh\n"));
        assert!(s.contains("#SBATCH --array=0-3\n"));
        assert!(s.contains("#SBATCH --output=/farm/out/parts/logs/task-%a.log\n"));
        assert!(s.contains("#SBATCH --gres=gpu:1\n#SBATCH --time=10\n"));
        assert!(s.ends_with("exec '/opt/kdray/bin/kdray' farm-task '/farm/out' \"$@\"\n"));
        // Slurm stops reading directives at the first command.
        let first_command = s.lines().position(|l| !l.starts_with('#')).unwrap();
        let lines: Vec<&str> = s.lines().collect();
        let last_directive = lines
            .iter()
            .rposition(|l| l.starts_with("#SBATCH"))
            .unwrap();
        assert!(last_directive < first_command);
    }

    #[test]
    fn options_with_spaces_and_folders_with_percent_are_refused() {
        let e = array_script(&plan(&["--time 10"]), Path::new("/farm")).unwrap_err();
        assert!(e.to_string().contains("--sbatch"), "{e}");
        let e = finish_script(&plan(&[]), Path::new("/farm/100%")).unwrap_err();
        assert!(e.to_string().contains("--out"), "{e}");
    }

    #[test]
    fn quotes_in_paths_are_escaped_for_sh() {
        assert_eq!(quoted(Path::new("/a'b")).unwrap(), r"'/a'\''b'");
    }
}
