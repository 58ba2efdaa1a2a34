//! The bench's one options type, [`BenchConfig`]: what `kdray bench`
//! measures and where it writes it. It holds the command line's defaults
//! ([`Default`]) and the checks and normalisation that make a user's choices
//! runnable ([`BenchConfig::validated`]). The command line maps its flags
//! onto it in one place (src/bin/kdray/args.rs), and `bench.json` records it
//! as the run's configuration.

use std::path::PathBuf;

use serde::{Deserialize, Serialize};

use super::named;
use super::random_scene::{SceneKind, DEFAULT_SEED};
use crate::error::{Error, Result};
use crate::gpu::Accel;
use crate::kdtree::{BuildStrategy, Traversal};

/// Object counts of the random scenes by default.
pub const DEFAULT_SIZES: [usize; 7] = [1, 10, 100, 1_000, 10_000, 100_000, 1_000_000];
/// Timed frames per run by default, after the warm-up frame.
pub const DEFAULT_REPEAT: u32 = 3;
/// Brute force's per-frame budget by default, in seconds.
pub const DEFAULT_BUDGET_S: f64 = 30.0;
/// The accelerations measured by default, in order.
pub const DEFAULT_ACCELS: [Accel; 2] = [Accel::Kdtree, Accel::Brute];
/// The output folder by default.
pub const DEFAULT_OUT: &str = "bench-results";

/// Largest random scene the bench or the generator accepts.
pub const MAX_OBJECTS: usize = 20_000_000;
/// Deepest `max_depth` override the bench accepts.
const MAX_DEPTH: u32 = 64;

/// What the bench measures.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum BenchMode {
    /// Random scenes of the given sizes.
    Random,
    /// Scene files.
    Scenes,
    /// The four scenes of [`super::suite`].
    Suite,
}

/// What `kdray bench` is asked to do. Build it from [`Default`] and pass it
/// through [`BenchConfig::validated`] before running it.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct BenchConfig {
    pub mode: BenchMode,
    /// What the random scenes are made of (random mode only; spheres when
    /// not given).
    pub kind: Option<SceneKind>,
    /// Object counts of the random scenes (random mode only).
    pub sizes: Vec<usize>,
    /// Seed of the random scenes.
    pub seed: u64,
    /// Scene files to measure (scenes mode); N is each scene's object count.
    pub scenes: Vec<PathBuf>,
    /// Image size [default: 640 x 480 for random scenes, the scene's own for files].
    pub width: Option<u32>,
    pub height: Option<u32>,
    /// Override of render.max_depth (1 = primary hits only).
    pub max_depth: Option<u32>,
    /// Timed frames per run, after one warm-up frame; the median is reported.
    pub repeat: u32,
    /// Per-frame budget for brute force, in seconds.
    pub budget_s: f64,
    /// Which accelerations to run, in order.
    pub accels: Vec<Accel>,
    /// The k-d tree's builds and walks: every (build, walk) is a cell.
    #[serde(with = "named::list", default = "default_builds")]
    pub builds: Vec<BuildStrategy>,
    #[serde(default = "default_traversals")]
    pub traversals: Vec<Traversal>,
    /// Output folder (created if missing).
    pub out: PathBuf,
    /// Also save the k-d tree's image of every run.
    pub save_images: bool,
    /// Write each measured scene (after the size and depth overrides) as
    /// JSON into `out/scenes/`, for peers to trace the same rays
    /// (scripts/peers/bench_embree.py); on with the suite.
    #[serde(default)]
    pub write_scenes: bool,
    /// The command line, for the report.
    pub command: String,
}

fn default_builds() -> Vec<BuildStrategy> {
    vec![BuildStrategy::default()]
}

fn default_traversals() -> Vec<Traversal> {
    vec![Traversal::default()]
}

impl Default for BenchConfig {
    fn default() -> Self {
        BenchConfig {
            mode: BenchMode::Random,
            kind: Some(SceneKind::Spheres),
            sizes: DEFAULT_SIZES.to_vec(),
            seed: DEFAULT_SEED,
            scenes: Vec::new(),
            width: None,
            height: None,
            max_depth: None,
            repeat: DEFAULT_REPEAT,
            budget_s: DEFAULT_BUDGET_S,
            accels: DEFAULT_ACCELS.to_vec(),
            builds: default_builds(),
            traversals: default_traversals(),
            out: PathBuf::from(DEFAULT_OUT),
            save_images: false,
            write_scenes: false,
            command: String::new(),
        }
    }
}

impl BenchConfig {
    /// Checks every value (a usage error names the flag) and normalises the
    /// rest: sizes sorted without repeats, lists without repeats in
    /// first-seen order (empty builds and walks: the defaults), what the
    /// mode does not use cleared, and scenes written with the suite.
    pub fn validated(mut self) -> Result<Self> {
        check_side("--width", self.width)?;
        check_side("--height", self.height)?;
        if let Some(d) = self.max_depth {
            if !(1..=MAX_DEPTH).contains(&d) {
                return Err(Error::Usage(format!(
                    "--max-depth: must be in 1..={MAX_DEPTH}, got {d}"
                )));
            }
        }
        if self.repeat == 0 {
            return Err(Error::Usage("--repeat: must be at least 1".into()));
        }
        if self.budget_s.is_nan() || self.budget_s <= 0.0 {
            return Err(Error::Usage(format!(
                "--budget-s: must be > 0, got {}",
                self.budget_s
            )));
        }
        match self.mode {
            BenchMode::Suite if !self.scenes.is_empty() => {
                return Err(Error::Usage(
                    "--suite: measures its own scenes; leave out --scene".into(),
                ));
            }
            BenchMode::Scenes if self.scenes.is_empty() => {
                return Err(Error::Usage("--scene: give at least one scene file".into()));
            }
            BenchMode::Random if !self.scenes.is_empty() => {
                return Err(Error::Usage(
                    "--scene: random scenes are measured instead of scene files".into(),
                ));
            }
            BenchMode::Random => {
                if self.sizes.is_empty() {
                    return Err(Error::Usage("--sizes: give at least one size".into()));
                }
                for &n in &self.sizes {
                    check_count("--sizes", n)?;
                }
                self.sizes.sort_unstable();
                self.sizes.dedup();
            }
            BenchMode::Scenes | BenchMode::Suite => self.sizes.clear(),
        }
        self.kind = match self.mode {
            BenchMode::Random => Some(self.kind.unwrap_or(SceneKind::Spheres)),
            BenchMode::Scenes | BenchMode::Suite => None,
        };
        self.accels = distinct(&self.accels);
        self.builds = distinct_or(&self.builds, BuildStrategy::default());
        self.traversals = distinct_or(&self.traversals, Traversal::default());
        self.write_scenes |= self.mode == BenchMode::Suite;
        Ok(self)
    }
}

/// A usage error unless an image side is in 1..=[`crate::scene::MAX_IMAGE_SIDE`].
pub(super) fn check_side(flag: &str, value: Option<u32>) -> Result<()> {
    let max = crate::scene::MAX_IMAGE_SIDE;
    match value {
        Some(v) if !(1..=max).contains(&v) => Err(Error::Usage(format!(
            "{flag}: must be in 1..={max}, got {v}"
        ))),
        _ => Ok(()),
    }
}

/// A usage error unless an object count is in 1..=[`MAX_OBJECTS`].
pub(super) fn check_count(flag: &str, n: usize) -> Result<()> {
    if !(1..=MAX_OBJECTS).contains(&n) {
        return Err(Error::Usage(format!(
            "{flag}: must be in 1..={MAX_OBJECTS}, got {n}"
        )));
    }
    Ok(())
}

/// `list` without repeats, in first-seen order.
fn distinct<T: PartialEq + Copy>(list: &[T]) -> Vec<T> {
    let mut out = Vec::new();
    for &v in list {
        if !out.contains(&v) {
            out.push(v);
        }
    }
    out
}

/// [`distinct`], or `default` alone when `list` is empty.
fn distinct_or<T: PartialEq + Copy>(list: &[T], default: T) -> Vec<T> {
    let out = distinct(list);
    if out.is_empty() {
        vec![default]
    } else {
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_defaults_are_valid_and_kept() {
        let config = BenchConfig::default().validated().unwrap();
        assert_eq!(config.mode, BenchMode::Random);
        assert_eq!(config.sizes, DEFAULT_SIZES);
        assert_eq!(config.accels, DEFAULT_ACCELS);
        assert_eq!(config.builds, [BuildStrategy::default()]);
        assert_eq!(config.traversals, [Traversal::default()]);
        assert!(!config.write_scenes);
    }

    #[test]
    fn validation_sorts_sizes_and_drops_repeats() {
        let config = BenchConfig {
            sizes: vec![100, 1, 100, 10],
            accels: vec![Accel::Brute, Accel::Kdtree, Accel::Brute],
            builds: Vec::new(),
            traversals: vec![Traversal::Ropes, Traversal::Ropes],
            ..BenchConfig::default()
        }
        .validated()
        .unwrap();
        assert_eq!(config.sizes, [1, 10, 100]);
        assert_eq!(config.accels, [Accel::Brute, Accel::Kdtree]);
        assert_eq!(config.builds, [BuildStrategy::default()]);
        assert_eq!(config.traversals, [Traversal::Ropes]);
    }

    #[test]
    fn the_suite_writes_its_scenes_and_takes_no_files() {
        let suite = BenchConfig {
            mode: BenchMode::Suite,
            ..BenchConfig::default()
        }
        .validated()
        .unwrap();
        assert!(suite.write_scenes && suite.sizes.is_empty() && suite.kind.is_none());
        let with_file = BenchConfig {
            mode: BenchMode::Suite,
            scenes: vec![PathBuf::from("scenes/seed.toml")],
            ..BenchConfig::default()
        };
        assert!(matches!(with_file.validated(), Err(Error::Usage(m)) if m.starts_with("--suite")));
    }

    #[test]
    fn out_of_range_values_name_their_flag() {
        let bad = [
            (
                "--sizes",
                BenchConfig {
                    sizes: vec![0, 10],
                    ..BenchConfig::default()
                },
            ),
            (
                "--repeat",
                BenchConfig {
                    repeat: 0,
                    ..BenchConfig::default()
                },
            ),
            (
                "--width",
                BenchConfig {
                    width: Some(0),
                    ..BenchConfig::default()
                },
            ),
            (
                "--budget-s",
                BenchConfig {
                    budget_s: -1.0,
                    ..BenchConfig::default()
                },
            ),
            (
                "--max-depth",
                BenchConfig {
                    max_depth: Some(65),
                    ..BenchConfig::default()
                },
            ),
        ];
        for (flag, config) in bad {
            match config.validated() {
                Err(Error::Usage(m)) => assert!(m.starts_with(flag), "{flag}: {m}"),
                other => panic!("{flag}: {other:?}"),
            }
        }
    }
}
