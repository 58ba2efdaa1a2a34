//! The bench's outputs: `bench.csv` (one row per run), `bench.json` (the
//! configuration, the machine, every run, fits and targets) and `summary.md`
//! (a table per scene: rows build x walk, and brute force; then the
//! speed-ups, fits and targets). All are written atomically, and rewritten
//! after every run so that an interrupted sweep keeps what it measured.
//! `embree.json` (scripts/peers/bench_embree.py) adds Embree's rays/s and
//! kdray's ratio to it, on `--replot`.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::{accel_name, BenchConfig, RunRecord};
use crate::error::Result;
use crate::gpu::{Accel, GpuContext};
use crate::kdtree::{BuildStrategy, Traversal};
use crate::output::write_file_atomic;

pub const CSV_FILE: &str = "bench.csv";
pub const JSON_FILE: &str = "bench.json";
pub const SUMMARY_FILE: &str = "summary.md";
/// Embree's results for the same scenes (scripts/peers/bench_embree.py).
pub const EMBREE_FILE: &str = "embree.json";

/// The CSV's columns, in order (the fields of [`RunRecord`] but the samples).
pub const CSV_COLUMNS: [&str; 39] = [
    "scene",
    "n",
    "spheres",
    "triangles",
    "accel",
    "build",
    "traversal",
    "status",
    "note",
    "width",
    "height",
    "samples",
    "max_depth",
    "scene_ms",
    "build_ms",
    "kd_nodes",
    "kd_leaves",
    "kd_max_depth",
    "kd_refs_per_leaf",
    "upload_ms",
    "gpu_scene_bytes",
    "gpu_ms",
    "gpu_ms_min",
    "gpu_ms_max",
    "repeats",
    "gpu_time_source",
    "frame_wall_ms",
    "primary_rays",
    "shadow_rays",
    "reflection_rays",
    "total_rays",
    "mrays_per_s",
    "peak_host_mib",
    "pixels_differing_from_kdtree",
    "loop_limited_pixels",
    "nodes_visited_per_ray",
    "leaves_visited_per_ray",
    "objects_tested_per_ray",
    "pixels_differing_from_brute",
];

/// Least-squares fits of the measured GPU times.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Fit {
    pub accel: Accel,
    /// Sizes used (N >= 100, where fixed costs no longer dominate).
    pub points: usize,
    /// Slope of log(ms) against log(N): 1 is linear, 0 constant.
    pub loglog_slope: Option<f64>,
    /// ms = intercept + per_object * N (the seed's figure 7 fit), all sizes,
    /// fitted to relative error (each point weighted by 1 / ms^2), so that
    /// the small sizes count as much as the large ones on a log-log plot.
    pub linear_intercept_ms: Option<f64>,
    pub linear_per_object_ms: Option<f64>,
    pub linear_r2: Option<f64>,
}

/// A target of the issue, as a ratio measured in this run.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Target {
    pub name: String,
    /// The measured ratio, if both ends were measured.
    pub value: Option<f64>,
    /// "at least" or "at most".
    pub comparison: String,
    pub goal: f64,
    pub met: Option<bool>,
    pub detail: String,
}

#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Machine {
    pub adapter: String,
    pub adapter_line: String,
    pub backend: String,
    pub timestamps: bool,
    pub host_cpu: Option<String>,
    pub host_threads: Option<usize>,
    pub os: String,
    /// 1-minute load average when the sweep started and when it last
    /// recorded a run (Linux): a software adapter shares the CPU with
    /// whatever else runs, so a busy machine shows up here.
    pub load_average_start: Option<f64>,
    pub load_average_end: Option<f64>,
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

    /// Whether `r` belongs to the size series of `accel` (for the k-d
    /// tree: the first cell measured, see `primary_cell`).
    pub fn in_series(&self, r: &RunRecord, accel: Accel) -> bool {
        in_series(&self.runs, r, accel)
    }

    /// The runs of one scene, in order.
    pub fn runs_of<'a>(&'a self, scene: &'a str, n: usize) -> impl Iterator<Item = &'a RunRecord> {
        self.runs
            .iter()
            .filter(move |r| r.scene == scene && r.n == n)
    }
}

/// The 1-minute load average (Linux /proc/loadavg).
pub fn load_average() -> Option<f64> {
    std::fs::read_to_string("/proc/loadavg")
        .ok()?
        .split_whitespace()
        .next()?
        .parse()
        .ok()
}

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
    pub targets: Vec<Target>,
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

fn host_cpu() -> Option<String> {
    let info = std::fs::read_to_string("/proc/cpuinfo").ok()?;
    let line = info.lines().find(|l| l.starts_with("model name"))?;
    Some(line.split_once(':')?.1.trim().to_string())
}

/// `2026-11-21T05:20:04Z` from the system clock (no date crate needed).
pub fn utc_now_iso() -> String {
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    iso_from_unix(secs)
}

/// ISO 8601 UTC of a Unix time in seconds.
pub fn iso_from_unix(secs: u64) -> String {
    let (days, rem) = ((secs / 86_400) as i64, secs % 86_400);
    // Howard Hinnant's civil_from_days.
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(m <= 2);
    format!(
        "{y:04}-{m:02}-{d:02}T{:02}:{:02}:{:02}Z",
        rem / 3600,
        rem % 3600 / 60,
        rem % 60
    )
}

impl BenchReport {
    pub fn new(ctx: &GpuContext, config: &BenchConfig) -> Self {
        BenchReport {
            kdray_version: env!("CARGO_PKG_VERSION").to_string(),
            date_utc: utc_now_iso(),
            command: config.command.clone(),
            machine: Machine {
                adapter: ctx.info.name.clone(),
                adapter_line: ctx.adapter_line(),
                backend: format!("{:?}", ctx.info.backend),
                timestamps: ctx.has_timestamps,
                host_cpu: host_cpu(),
                host_threads: std::thread::available_parallelism().ok().map(|n| n.get()),
                os: std::env::consts::OS.to_string(),
                load_average_start: load_average(),
                load_average_end: None,
            },
            config: config.clone(),
            runs: Vec::new(),
            fits: Vec::new(),
            targets: Vec::new(),
            notes: Vec::new(),
            embree: None,
            elapsed_s: 0.0,
            started: Some(std::time::Instant::now()),
        }
    }

    pub fn push(&mut self, record: RunRecord) {
        self.runs.push(record);
        self.update();
    }

    /// Recomputes fits, targets and the elapsed time.
    pub fn finish(&mut self) {
        self.update();
    }

    /// Recomputes fits and targets of a report read back from JSON (the
    /// machine and timing fields stay as recorded).
    pub fn refresh(&mut self) {
        self.fits = [Accel::Kdtree, Accel::Brute]
            .into_iter()
            .filter_map(|a| fit(&self.runs, a))
            .collect();
        self.targets = targets(&self.runs);
    }

    fn update(&mut self) {
        self.elapsed_s = self.started.map_or(0.0, |t| t.elapsed().as_secs_f64());
        self.machine.load_average_end = load_average();
        self.refresh();
    }

    /// Measured (N, gpu ms) of one acceleration, in run order.
    pub fn series(&self, accel: Accel) -> Vec<(usize, f64)> {
        series(&self.runs, accel)
    }

    /// Writes bench.csv, bench.json and summary.md; returns their paths.
    pub fn write_data(&self, out: &Path) -> Result<Vec<PathBuf>> {
        let csv = out.join(CSV_FILE);
        write_file_atomic(&csv, csv_text(&self.runs).as_bytes())?;
        let json = out.join(JSON_FILE);
        let text = serde_json::to_string_pretty(self)?;
        write_file_atomic(&json, (text + "\n").as_bytes())?;
        let md = out.join(SUMMARY_FILE);
        write_file_atomic(&md, markdown_summary(self).as_bytes())?;
        Ok(vec![csv, json, md])
    }
}

/// The k-d cell the size series, fits and targets follow: the default
/// build and walk where they were measured, else the first cell measured.
fn primary_cell(runs: &[RunRecord]) -> (Option<BuildStrategy>, Option<Traversal>) {
    let default = (Some(BuildStrategy::default()), Some(Traversal::default()));
    let kd = || runs.iter().filter(|r| r.accel == Accel::Kdtree);
    if kd().any(|r| (r.build, r.traversal) == default) {
        return default;
    }
    kd().next().map_or((None, None), |r| (r.build, r.traversal))
}

/// Whether `r` is of `accel` and, for the k-d tree, of the primary cell.
fn in_series(runs: &[RunRecord], r: &RunRecord, accel: Accel) -> bool {
    r.accel == accel && (accel != Accel::Kdtree || (r.build, r.traversal) == primary_cell(runs))
}

fn series(runs: &[RunRecord], accel: Accel) -> Vec<(usize, f64)> {
    runs.iter()
        .filter(|r| in_series(runs, r, accel) && r.is_ok())
        .filter_map(|r| Some((r.n, r.gpu_ms?)))
        .collect()
}

fn fit(runs: &[RunRecord], accel: Accel) -> Option<Fit> {
    let points = series(runs, accel);
    if points.is_empty() {
        return None;
    }
    let large: Vec<(f64, f64)> = points
        .iter()
        .filter(|(n, ms)| *n >= 100 && *ms > 0.0)
        .map(|&(n, ms)| ((n as f64).ln(), ms.ln()))
        .collect();
    let loglog_slope = least_squares(&large).map(|(_, b, _)| b);
    let linear: Vec<(f64, f64, f64)> = points
        .iter()
        .filter(|(_, ms)| *ms > 0.0)
        .map(|&(n, ms)| (n as f64, ms, 1.0 / (ms * ms)))
        .collect();
    let lin = weighted_least_squares(&linear);
    Some(Fit {
        accel,
        points: large.len(),
        loglog_slope,
        linear_intercept_ms: lin.map(|l| l.0),
        linear_per_object_ms: lin.map(|l| l.1),
        linear_r2: lin.and_then(|l| l.2),
    })
}

/// y = a + b x by least squares: (a, b, R^2); None under two distinct x.
pub fn least_squares(points: &[(f64, f64)]) -> Option<(f64, f64, Option<f64>)> {
    let weighted: Vec<_> = points.iter().map(|&(x, y)| (x, y, 1.0)).collect();
    weighted_least_squares(&weighted)
}

/// y = a + b x by least squares over (x, y, weight): (a, b, weighted R^2).
pub fn weighted_least_squares(points: &[(f64, f64, f64)]) -> Option<(f64, f64, Option<f64>)> {
    let w: f64 = points.iter().map(|p| p.2).sum();
    if points.len() < 2 || w.is_nan() || w <= 0.0 {
        return None;
    }
    let mx = points.iter().map(|p| p.2 * p.0).sum::<f64>() / w;
    let my = points.iter().map(|p| p.2 * p.1).sum::<f64>() / w;
    let sxx: f64 = points.iter().map(|p| p.2 * (p.0 - mx).powi(2)).sum();
    let sxy: f64 = points.iter().map(|p| p.2 * (p.0 - mx) * (p.1 - my)).sum();
    let syy: f64 = points.iter().map(|p| p.2 * (p.1 - my).powi(2)).sum();
    if sxx <= 0.0 || sxx.is_nan() {
        return None;
    }
    let b = sxy / sxx;
    let a = my - b * mx;
    let r2 = (syy > 0.0).then(|| (sxy * sxy) / (sxx * syy));
    Some((a, b, r2))
}

fn gpu_ms_at(runs: &[RunRecord], accel: Accel, n: usize) -> Option<&RunRecord> {
    runs.iter().find(|r| in_series(runs, r, accel) && r.n == n)
}

/// The first two targets, where this run has the sizes for them.
fn targets(runs: &[RunRecord]) -> Vec<Target> {
    let mut out = Vec::new();
    let kind = runs.first().map_or("", |r| r.scene.as_str());
    if let (Some(kd), Some(brute)) = (
        gpu_ms_at(runs, Accel::Kdtree, 10_000),
        gpu_ms_at(runs, Accel::Brute, 10_000),
    ) {
        let value = match (brute.is_ok(), kd.gpu_ms, brute.gpu_ms) {
            (true, Some(k), Some(b)) if k > 0.0 => Some(b / k),
            _ => None,
        };
        out.push(Target {
            name: format!("k-d tree vs brute force, 10,000 random {kind}"),
            value,
            comparison: "at least".into(),
            goal: 300.0,
            met: value.map(|v| v >= 300.0),
            detail: match value {
                Some(_) => format!(
                    "brute {:.1} ms / k-d tree {:.2} ms (median GPU time)",
                    brute.gpu_ms.unwrap_or(f64::NAN),
                    kd.gpu_ms.unwrap_or(f64::NAN)
                ),
                None => format!(
                    "brute force {}: {}",
                    brute.status.name(),
                    brute.note.as_deref().unwrap_or("no time")
                ),
            },
        });
    }
    if let (Some(small), Some(large)) = (
        gpu_ms_at(runs, Accel::Kdtree, 1_000),
        gpu_ms_at(runs, Accel::Kdtree, 1_000_000),
    ) {
        let value = match (small.gpu_ms, large.gpu_ms) {
            (Some(a), Some(b)) if a > 0.0 => Some(b / a),
            _ => None,
        };
        out.push(Target {
            name: format!("k-d tree frame time growth, 1,000 -> 1,000,000 random {kind}"),
            value,
            comparison: "at most".into(),
            goal: 3.0,
            met: value.map(|v| v <= 3.0),
            detail: format!(
                "{:.2} ms -> {:.2} ms (median GPU time); rays {} -> {}",
                small.gpu_ms.unwrap_or(f64::NAN),
                large.gpu_ms.unwrap_or(f64::NAN),
                small.total_rays.unwrap_or(0),
                large.total_rays.unwrap_or(0)
            ),
        });
    }
    out
}

fn opt<T: std::fmt::Display>(v: Option<T>) -> String {
    v.map_or(String::new(), |v| v.to_string())
}

fn opt_f(v: Option<f64>, decimals: usize) -> String {
    v.map_or(String::new(), |v| format!("{v:.decimals$}"))
}

/// A CSV field, quoted when it must be (RFC 4180).
fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

pub fn csv_text(runs: &[RunRecord]) -> String {
    let mut out = CSV_COLUMNS.join(",");
    out.push('\n');
    for r in runs {
        let fields = [
            csv_field(&r.scene),
            r.n.to_string(),
            r.spheres.to_string(),
            r.triangles.to_string(),
            accel_name(r.accel).to_string(),
            r.build.map_or("", crate::choice::Choice::name).to_string(),
            r.traversal.map_or("", Traversal::name).to_string(),
            r.status.name().to_string(),
            csv_field(r.note.as_deref().unwrap_or("")),
            r.width.to_string(),
            r.height.to_string(),
            r.samples.to_string(),
            r.max_depth.to_string(),
            format!("{:.3}", r.scene_ms),
            opt_f(r.build_ms, 3),
            opt(r.kd_nodes),
            opt(r.kd_leaves),
            opt(r.kd_max_depth),
            opt_f(r.kd_refs_per_leaf, 3),
            opt_f(r.upload_ms, 3),
            opt(r.gpu_scene_bytes),
            opt_f(r.gpu_ms, 3),
            opt_f(r.gpu_ms_min, 3),
            opt_f(r.gpu_ms_max, 3),
            r.gpu_ms_samples.len().to_string(),
            r.gpu_time_source.map_or("", |s| s.name()).to_string(),
            opt_f(r.frame_wall_ms, 3),
            opt(r.primary_rays),
            opt(r.shadow_rays),
            opt(r.reflection_rays),
            opt(r.total_rays),
            opt_f(r.mrays_per_s, 3),
            opt_f(r.peak_host_mib, 1),
            opt(r.pixels_differing_from_kdtree),
            opt(r.loop_limited_pixels),
            opt_f(r.nodes_visited_per_ray, 3),
            opt_f(r.leaves_visited_per_ray, 3),
            opt_f(r.objects_tested_per_ray, 3),
            opt(r.pixels_differing_from_brute),
        ];
        debug_assert_eq!(fields.len(), CSV_COLUMNS.len());
        out.push_str(&fields.join(","));
        out.push('\n');
    }
    out
}

/// Milliseconds with about 3 significant digits.
fn ms(v: Option<f64>) -> String {
    match v {
        None => "-".into(),
        Some(v) if v >= 100.0 => format!("{v:.0}"),
        Some(v) if v >= 10.0 => format!("{v:.1}"),
        Some(v) => format!("{v:.2}"),
    }
}

/// `1234567` as `1,234,567`.
pub fn count(n: u64) -> String {
    let s = n.to_string();
    let mut out = String::new();
    for (i, c) in s.chars().enumerate() {
        if i > 0 && (s.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

/// A ratio with 3 significant digits down to 0.001 (`12.3x`, `1.23x`, `0.0412x`).
pub fn ratio_text(v: f64) -> String {
    if v >= 10.0 {
        format!("{v:.1}x")
    } else if v >= 1.0 {
        format!("{v:.2}x")
    } else if v >= 0.1 {
        format!("{v:.3}x")
    } else {
        format!("{v:.4}x")
    }
}

/// One scene's section of the summary: what was rendered, Embree's figure,
/// a row per run (build x walk, then brute force) and the scene's plot.
fn scene_table(s: &mut String, report: &BenchReport, scene: &str, n: usize) {
    let runs: Vec<&RunRecord> = report.runs_of(scene, n).collect();
    let Some(first) = runs.first() else {
        return;
    };
    let _ = writeln!(
        s,
        "\n### {scene}, N = {} ({} spheres, {} triangles)\n",
        count(n as u64),
        count(first.spheres as u64),
        count(first.triangles as u64)
    );
    let rays = runs.iter().find(|r| r.total_rays.is_some());
    let _ = writeln!(
        s,
        "{}x{}, {} sample(s), max_depth {}{}; rays per frame: {}.  ",
        first.width,
        first.height,
        first.samples,
        first.max_depth,
        if first.max_depth == 1 {
            " (primary + shadow)"
        } else {
            ""
        },
        rays.map_or("-".into(), |r| format!(
            "{} primary, {} shadow, {} reflection",
            count(r.primary_rays.unwrap_or(0)),
            count(r.shadow_rays.unwrap_or(0)),
            count(r.reflection_rays.unwrap_or(0))
        ))
    );
    let embree = report.embree_for(scene, n);
    let embree_mrays = embree.and_then(|e| e.mrays_per_s_median);
    if report.embree.is_some() {
        let line = match embree {
            None => "not measured".to_string(),
            Some(e) => match (e.mrays_per_s_median, &e.unsupported) {
                (Some(m), _) => format!(
                    "{m:.2} M rays/s ({} primary + {} shadow rays, median of {} runs {} ms; BVH build {} ms)",
                    count(e.primary_rays.unwrap_or(0)),
                    count(e.shadow_rays.unwrap_or(0)),
                    opt(e.repeat),
                    ms(e.seconds_median.map(|v| v * 1e3)),
                    ms(e.build_s.map(|v| v * 1e3))
                ),
                (None, Some(why)) => format!("n/a ({why})"),
                (None, None) => "no figure".into(),
            },
        };
        let _ = writeln!(s, "Embree (one thread): {line}.  ");
    }
    let brute_ms = runs
        .iter()
        .find(|r| r.accel == Accel::Brute && r.is_ok())
        .and_then(|r| r.gpu_ms);
    let _ = writeln!(
        s,
        "\n| accel | build | walk | build ms | nodes | depth | refs/leaf | GPU ms median (min-max) | Mrays/s | nodes/ray | leaves/ray | objects/ray | peak MiB | px differing from brute | vs brute | vs Embree |"
    );
    let _ = writeln!(
        s,
        "|---|---|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|"
    );
    for r in runs {
        let head = format!(
            "| {} | {} | {} |",
            accel_name(r.accel),
            r.build.map_or("", crate::choice::Choice::name),
            r.traversal.map_or("", Traversal::name)
        );
        if !r.is_ok() {
            let _ = writeln!(
                s,
                "{head} {} | {} | {} | {} | **{}**: {} | | | | | | | | |",
                ms(r.build_ms),
                r.kd_nodes.map_or(String::new(), |v| count(v as u64)),
                opt(r.kd_max_depth),
                opt_f(r.kd_refs_per_leaf, 2),
                r.status.name(),
                r.note.as_deref().unwrap_or("")
            );
            continue;
        }
        let ratio = |num: Option<f64>, den: Option<f64>| match (num, den) {
            (Some(a), Some(b)) if b > 0.0 => ratio_text(a / b),
            _ => "-".into(),
        };
        let _ = writeln!(
            s,
            "{head} {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            ms(r.build_ms),
            r.kd_nodes.map_or("-".into(), |v| count(v as u64)),
            opt(r.kd_max_depth),
            opt_f(r.kd_refs_per_leaf, 2),
            if r.gpu_ms_samples.len() > 1 {
                format!(
                    "{} ({}-{})",
                    ms(r.gpu_ms),
                    ms(r.gpu_ms_min),
                    ms(r.gpu_ms_max)
                )
            } else {
                ms(r.gpu_ms)
            },
            opt_f(r.mrays_per_s, 3),
            opt_f(r.nodes_visited_per_ray, 1),
            opt_f(r.leaves_visited_per_ray, 2),
            opt_f(r.objects_tested_per_ray, 1),
            opt_f(r.peak_host_mib, 0),
            match r.accel {
                Accel::Brute => "(reference)".into(),
                Accel::Kdtree => opt(r.pixels_differing_from_brute),
            },
            match r.accel {
                Accel::Brute => "1x".into(),
                Accel::Kdtree => ratio(brute_ms, r.gpu_ms),
            },
            ratio(r.mrays_per_s, embree_mrays),
        );
    }
    let _ = writeln!(
        s,
        "\n![rays per second, {scene}](./{})",
        super::matrix_plot::plot_file(scene, n)
    );
}

/// The report as Markdown: machine, a table per scene, speed-ups (of the
/// primary cell), fits, targets.
pub fn markdown_summary(report: &BenchReport) -> String {
    let mut s = String::new();
    let m = &report.machine;
    let _ = writeln!(s, "Command: `{}`  ", report.command);
    let _ = writeln!(s, "Adapter: `{}`  ", m.adapter_line);
    let _ = writeln!(
        s,
        "Host: {} ({} threads), {}, load average {} at start, {} at end; GPU time from {}; date {} (UTC); sweep {:.0} s\n",
        m.host_cpu.as_deref().unwrap_or("unknown CPU"),
        m.host_threads.map_or("?".into(), |t| t.to_string()),
        m.os,
        opt_f(m.load_average_start, 2),
        opt_f(m.load_average_end, 2),
        if m.timestamps { "timestamp queries" } else { "wall clock" },
        report.date_utc,
        report.elapsed_s
    );
    for note in &report.notes {
        let _ = writeln!(s, "{note}  ");
    }
    if let Some(e) = &report.embree {
        let _ = writeln!(
            s,
            "Embree: Embree 4 through embreex{}, one thread (`taskset -c 0`), primary + shadow rays of the same scene files, measured {}{}; uptime before: `{}`, after: `{}`  ",
            e.embreex_version.as_deref().map_or(String::new(), |v| format!(" {v}")),
            e.date_utc.as_deref().unwrap_or("?"),
            e.command.as_deref().map_or(String::new(), |c| format!(" by `{c}`")),
            e.uptime_before.as_deref().unwrap_or("?"),
            e.uptime_after.as_deref().unwrap_or("?"),
        );
    }
    for (scene, n) in report.scenes() {
        scene_table(&mut s, report, &scene, n);
    }
    // Speed-ups where both ran.
    let kd = report.series(Accel::Kdtree);
    let brute = report.series(Accel::Brute);
    let pairs: Vec<_> = kd
        .iter()
        .filter_map(|&(n, k)| brute.iter().find(|b| b.0 == n).map(|&(_, b)| (n, k, b)))
        .collect();
    // Across the suite's scenes (of different kinds and images) a series
    // in N means nothing: each scene's table has its own ratios.
    let series_make_sense = report.config.mode != super::BenchMode::Suite;
    if series_make_sense && !pairs.is_empty() {
        let cell = match primary_cell(&report.runs) {
            (Some(b), Some(t)) => format!(" ({}/{})", crate::choice::Choice::name(b), t.name()),
            _ => String::new(),
        };
        let _ = writeln!(s, "\n| N | k-d tree{cell} ms | brute ms | speed-up |");
        let _ = writeln!(s, "|--:|--:|--:|--:|");
        for (n, k, b) in pairs {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {:.1}x |",
                count(n as u64),
                ms(Some(k)),
                ms(Some(b)),
                b / k
            );
        }
    }
    if series_make_sense && !report.fits.is_empty() {
        let _ = writeln!(
            s,
            "\n| accel | log-log slope (N >= 100) | linear fit: ms = a + b N (relative error) | R^2 |"
        );
        let _ = writeln!(s, "|---|--:|---|--:|");
        for f in &report.fits {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} |",
                accel_name(f.accel),
                opt_f(f.loglog_slope, 2),
                match (f.linear_intercept_ms, f.linear_per_object_ms) {
                    (Some(a), Some(b)) => format!("{a:.3} + {b:.3e} N"),
                    _ => "-".into(),
                },
                opt_f(f.linear_r2, 4)
            );
        }
    }
    if !report.targets.is_empty() {
        let _ = writeln!(s, "\n| target | measured | goal | met |");
        let _ = writeln!(s, "|---|--:|---|---|");
        for t in &report.targets {
            let _ = writeln!(
                s,
                "| {} ({}) | {} | {} {} | {} |",
                t.name,
                t.detail,
                t.value
                    .map_or("not measured".into(), |v| format!("{v:.2}x")),
                t.comparison,
                t.goal,
                match t.met {
                    Some(true) => "yes",
                    Some(false) => "**no**",
                    None => "-",
                }
            );
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn least_squares_recovers_a_line() {
        let pts: Vec<(f64, f64)> = (0..5).map(|i| (i as f64, 2.0 + 3.0 * i as f64)).collect();
        let (a, b, r2) = least_squares(&pts).unwrap();
        assert!((a - 2.0).abs() < 1e-12 && (b - 3.0).abs() < 1e-12);
        assert!((r2.unwrap() - 1.0).abs() < 1e-12);
        assert!(least_squares(&[(1.0, 1.0)]).is_none());
        // Weights pull the fit towards the heavy points.
        let (a, b, _) =
            weighted_least_squares(&[(0.0, 0.0, 1.0), (1.0, 1.0, 1.0), (2.0, 4.0, 1e-9)]).unwrap();
        assert!(a.abs() < 1e-6 && (b - 1.0).abs() < 1e-6, "{a} {b}");
    }

    #[test]
    fn csv_fields_are_quoted_when_needed() {
        assert_eq!(csv_field("plain"), "plain");
        assert_eq!(csv_field("a, b"), "\"a, b\"");
        assert_eq!(csv_field("say \"x\""), "\"say \"\"x\"\"\"");
    }

    #[test]
    fn dates_are_iso() {
        let d = utc_now_iso();
        assert_eq!(d.len(), 20, "{d}");
        assert_eq!(iso_from_unix(0), "1970-01-01T00:00:00Z");
        assert_eq!(iso_from_unix(951_782_400), "2000-02-29T00:00:00Z");
        assert_eq!(iso_from_unix(1_700_000_000), "2023-11-14T22:13:20Z");
    }

    #[test]
    fn counts_get_thousands_separators() {
        assert_eq!(count(0), "0");
        assert_eq!(count(999), "999");
        assert_eq!(count(1000), "1,000");
        assert_eq!(count(1234567), "1,234,567");
    }
}
