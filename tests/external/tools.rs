//! The tier's tools are installed: each missing one fails here, by name,
//! with the command that installs it, before the tests that use it fail in
//! their own ways. (`scripts/test.sh external` installs them all.)

use std::path::{Path, PathBuf};

use crate::common::repo_path;

/// Where `program` is on PATH, if it is.
fn on_path(program: &str) -> Option<PathBuf> {
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path)
        .map(|dir| dir.join(program))
        .find(|p| p.is_file())
}

/// Fails naming every program of `programs` that is not on PATH.
fn require(programs: &[&str], used_by: &str, install: &str) {
    let missing: Vec<&str> = programs
        .iter()
        .copied()
        .filter(|p| on_path(p).is_none())
        .collect();
    assert!(
        missing.is_empty(),
        "{used_by} needs {}, not found on PATH: run scripts/test.sh external (or {install})",
        missing.join(", ")
    );
}

#[test]
fn chromium_node_and_the_page_driver_are_installed() {
    assert!(
        Path::new("/usr/bin/chromium").is_file(),
        "tests/external/web.rs needs Debian's Chromium at /usr/bin/chromium: run scripts/test.sh \
         external (or apt-get install chromium)"
    );
    require(&["node"], "tests/external/web.rs", "apt-get install nodejs");
    assert!(
        repo_path("tests/web/node_modules/playwright-core").is_dir(),
        "tests/external/web.rs needs tests/web's npm packages: run scripts/test.sh external (or \
         npm ci --prefix tests/web)"
    );
}

#[test]
fn slurm_and_munge_are_installed() {
    require(
        &["slurmctld", "slurmd", "sbatch", "squeue", "munged"],
        "tests/external/farm.rs",
        "apt-get install slurmctld slurmd slurm-client munge",
    );
}

#[test]
fn xvfb_is_installed() {
    require(
        &["Xvfb", "xauth"],
        "tests/external/window.rs",
        "apt-get install xvfb xauth",
    );
}

#[test]
fn a_c_compiler_is_installed() {
    require(
        &["cc"],
        "tests/external/gpu_memory.rs",
        "apt-get install gcc",
    );
}
