//! Helpers shared by every test binary of the workspace: the repository's
//! root, temporary folders, proptest's configuration; and ([`strategies`],
//! [`textured`]) the random scenes, rays and trees of the k-d tree's
//! property tests and the textured test models. GPU-free: kdray-core's tests
//! include it as `mod common;`, and kdray's tests (tests/common/mod.rs)
//! include it by path and add the GPU helpers.
#![allow(dead_code)]

pub mod masked;
pub mod strategies;
pub mod textured;

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

/// The workspace's root (the folder of Cargo.lock), whichever package's
/// tests ask.
pub fn repo_root() -> PathBuf {
    let mut dir = Path::new(env!("CARGO_MANIFEST_DIR")).to_path_buf();
    while !dir.join("Cargo.lock").is_file() {
        assert!(
            dir.pop(),
            "no Cargo.lock above {}",
            env!("CARGO_MANIFEST_DIR")
        );
    }
    dir
}

/// `relative` under the workspace's root.
pub fn repo_path(relative: &str) -> PathBuf {
    repo_root().join(relative)
}

/// proptest's configuration with `cases` cases, keeping the seeds of failed
/// cases in `FILE.proptest-regressions` beside the test's source file, from
/// which they are replayed first on every run. (proptest's default puts them
/// under a `proptest-regressions` folder beside the nearest `main.rs`'s
/// folder, where a test binary split into modules would not look for them.)
pub fn proptest_config(cases: u32) -> proptest::test_runner::Config {
    proptest::test_runner::Config {
        cases,
        failure_persistence: Some(Box::new(
            proptest::test_runner::FileFailurePersistence::WithSource("proptest-regressions"),
        )),
        ..proptest::test_runner::Config::default()
    }
}

/// A fresh folder under the system temp dir, removed on drop.
pub struct TempDir {
    pub path: PathBuf,
}

impl TempDir {
    /// `kdray-test-PID-TAG-N`: unique per process, tag and call.
    pub fn new(tag: &str) -> Self {
        static COUNTER: AtomicUsize = AtomicUsize::new(0);
        let n = COUNTER.fetch_add(1, Ordering::Relaxed);
        let path =
            std::env::temp_dir().join(format!("kdray-test-{}-{tag}-{n}", std::process::id()));
        let _ = std::fs::remove_dir_all(&path);
        std::fs::create_dir_all(&path).unwrap();
        TempDir { path }
    }

    pub fn join(&self, name: &str) -> PathBuf {
        self.path.join(name)
    }

    /// Writes `text` to `name` (relative; folders made as needed); returns its path.
    pub fn write(&self, name: &str, text: &str) -> PathBuf {
        let path = self.join(name);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(&path, text).unwrap();
        path
    }

    /// Leftover temporary files of atomic writes (`.NAME.tmp-PID`).
    pub fn temp_files(&self) -> Vec<String> {
        temp_files_in(&self.path)
    }
}

/// Leftover temporary files of atomic writes (`.NAME.tmp-PID`) in `dir`.
pub fn temp_files_in(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|name| name.contains(".tmp-"))
        .collect()
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.path);
    }
}
