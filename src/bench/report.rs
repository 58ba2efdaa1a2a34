//! The bench's report, [`BenchReport`]: the configuration, the machine,
//! every run, the fits, and Embree's figures for the same scenes when
//! measured beside it. It is written as `bench.json`, `bench.csv` and
//! `summary.md` atomically ([`BenchReport::write_data`], in
//! [`outputs`](super::outputs)), and rewritten after every run so that an
//! interrupted sweep keeps what it measured;
//! `--replot` reads it back ([`BenchReport::read`]), taking in
//! `embree.json` (scripts/peers/bench_embree.py).

use std::path::Path;

use serde::{Deserialize, Serialize};

use super::fit::{fit, Fit};
use super::host::{load_average, utc_now_iso, Machine};
use super::options::BenchConfig;
use super::record::RunRecord;
use crate::error::{Error, Result};
use crate::gpu::{Accel, GpuContext};
use crate::kdtree::{BuildStrategy, Traversal};

pub const JSON_FILE: &str = "bench.json";
/// Embree's results for the same scenes (scripts/peers/bench_embree.py).
pub const EMBREE_FILE: &str = "embree.json";

/// Everything `bench.json` holds.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct BenchReport {
    pub kdray_version: String,
    /// UTC start time, ISO 8601.
    pub date_utc: String,
    pub command: String,
    pub machine: Machine,
    pub config: BenchConfig,
    pub runs: Vec<RunRecord>,
    pub fits: Vec<Fit>,
    /// Remarks on what ran (which real mesh the suite measured).
    #[serde(default)]
    pub notes: Vec<String>,
    /// Embree on the same scenes, merged from `embree.json` by `--replot`.
    #[serde(default)]
    pub embree: Option<EmbreeResults>,
    /// Wall time of the whole sweep so far, seconds.
    pub elapsed_s: f64,
    #[serde(skip)]
    started: Option<std::time::Instant>,
}

/// What scripts/peers/bench_embree.py measured: Embree 4 (embreex) on one
/// thread, tracing the primary and shadow rays of the scenes the bench
/// wrote (`scenes/`), in the same session.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct EmbreeResults {
    #[serde(default)]
    pub date_utc: Option<String>,
    #[serde(default)]
    pub command: Option<String>,
    #[serde(default)]
    pub uptime_before: Option<String>,
    #[serde(default)]
    pub uptime_after: Option<String>,
    #[serde(default)]
    pub embreex_version: Option<String>,
    pub scenes: Vec<EmbreeScene>,
}

/// Embree on one scene, or why not.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct EmbreeScene {
    /// The bench's scene label and object count, which name the run.
    pub scene: String,
    pub n: usize,
    #[serde(default)]
    pub primary_rays: Option<u64>,
    #[serde(default)]
    pub shadow_rays: Option<u64>,
    #[serde(default)]
    pub build_s: Option<f64>,
    #[serde(default)]
    pub repeat: Option<u32>,
    #[serde(default)]
    pub seconds_median: Option<f64>,
    /// (primary + shadow rays) / median seconds, in millions.
    #[serde(default)]
    pub mrays_per_s_median: Option<f64>,
    /// Why there is no figure (spheres: embreex has no sphere geometry).
    #[serde(default)]
    pub unsupported: Option<String>,
}

impl BenchReport {
    /// An empty report of a sweep of `config` on `ctx`, starting now.
    pub fn new(ctx: &GpuContext, config: &BenchConfig) -> Self {
        BenchReport {
            kdray_version: env!("CARGO_PKG_VERSION").to_string(),
            date_utc: utc_now_iso(),
            command: config.command.clone(),
            machine: Machine::of(ctx),
            config: config.clone(),
            runs: Vec::new(),
            fits: Vec::new(),
            notes: Vec::new(),
            embree: None,
            elapsed_s: 0.0,
            started: Some(std::time::Instant::now()),
        }
    }

    /// The report recorded in `dir/bench.json`, with Embree's results of
    /// `dir/embree.json` when there are, its fits recomputed (the machine
    /// and timing fields stay as recorded).
    pub fn read(dir: &Path) -> Result<Self> {
        let path = dir.join(JSON_FILE);
        let text = std::fs::read_to_string(&path)
            .map_err(|e| Error::Usage(format!("{}: cannot read: {e}", path.display())))?;
        let mut report: BenchReport = serde_json::from_str(&text).map_err(|e| {
            Error::Usage(format!("{}: not a kdray bench report: {e}", path.display()))
        })?;
        let embree = dir.join(EMBREE_FILE);
        if embree.is_file() {
            let text = std::fs::read_to_string(&embree)
                .map_err(|e| Error::Usage(format!("{}: cannot read: {e}", embree.display())))?;
            report.embree = Some(serde_json::from_str(&text).map_err(|e| {
                Error::Usage(format!("{}: not an Embree result: {e}", embree.display()))
            })?);
        }
        report.refresh();
        Ok(report)
    }

    pub fn push(&mut self, record: RunRecord) {
        self.runs.push(record);
        self.update();
    }

    /// Recomputes the fits and the elapsed time.
    pub fn finish(&mut self) {
        self.update();
    }

    /// Recomputes the fits.
    fn refresh(&mut self) {
        self.fits = [Accel::Kdtree, Accel::Brute]
            .into_iter()
            .filter_map(|a| fit(a, &self.series(a)))
            .collect();
    }

    fn update(&mut self) {
        self.elapsed_s = self.started.map_or(0.0, |t| t.elapsed().as_secs_f64());
        self.machine.load_average_end = load_average();
        self.refresh();
    }

    /// Embree's result for a scene, if measured.
    pub fn embree_for(&self, scene: &str, n: usize) -> Option<&EmbreeScene> {
        self.embree
            .as_ref()?
            .scenes
            .iter()
            .find(|e| e.scene == scene && e.n == n)
    }

    /// The measured scenes, (label, N), in the order they ran.
    pub fn scenes(&self) -> Vec<(String, usize)> {
        let mut out: Vec<(String, usize)> = Vec::new();
        for r in &self.runs {
            if !out.iter().any(|(s, n)| *s == r.scene && *n == r.n) {
                out.push((r.scene.clone(), r.n));
            }
        }
        out
    }

    /// The runs of one scene, in order.
    pub fn runs_of<'a>(&'a self, scene: &'a str, n: usize) -> impl Iterator<Item = &'a RunRecord> {
        self.runs
            .iter()
            .filter(move |r| r.scene == scene && r.n == n)
    }

    /// The k-d cell the size series and fits follow: the default build
    /// and walk where they were measured, else the first cell measured.
    pub fn primary_cell(&self) -> (Option<BuildStrategy>, Option<Traversal>) {
        let default = (Some(BuildStrategy::default()), Some(Traversal::default()));
        let kd = || self.runs.iter().filter(|r| r.accel == Accel::Kdtree);
        if kd().any(|r| (r.build, r.traversal) == default) {
            return default;
        }
        kd().next().map_or((None, None), |r| (r.build, r.traversal))
    }

    /// Whether `r` belongs to the size series of `accel`: of `accel` and,
    /// for the k-d tree, of the primary cell.
    pub fn in_series(&self, r: &RunRecord, accel: Accel) -> bool {
        r.accel == accel
            && (accel != Accel::Kdtree || (r.build, r.traversal) == self.primary_cell())
    }

    /// Measured (N, gpu ms) of one acceleration's series, in run order.
    pub fn series(&self, accel: Accel) -> Vec<(usize, f64)> {
        self.runs
            .iter()
            .filter(|r| self.in_series(r, accel) && r.is_ok())
            .filter_map(|r| Some((r.n, r.gpu_ms?)))
            .collect()
    }
}
