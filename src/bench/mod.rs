//! `kdray bench` and `kdray generate`: the seed study's two experiments
//! (render time against the number of objects for the naive loop, its
//! figure 7; k-d tree against the naive loop on random scenes, its figure 9),
//! reproduced on the GPU at up to a million objects.
//!
//! For each size N a deterministic random scene ([`random_scene`]) is built
//! once, then rendered with the k-d tree and with brute force: upload once,
//! one warm-up frame, then `repeat` timed frames whose median GPU time is
//! reported. Brute force is skipped, and the skip recorded, when a linear
//! extrapolation of its last measured frame (the seed's own model) exceeds
//! the per-frame budget. Results go to a CSV, a JSON summary, a Markdown
//! table and three log-log plots ([`report`], [`plots`]).

pub mod plots;
pub mod random_scene;
pub mod report;

use std::path::{Path, PathBuf};
use std::time::Instant;

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::gpu::{Accel, GpuContext, PreparedScene, Renderer, TilePlan};
use crate::scene::Scene;

pub use random_scene::{random_scene, RandomSceneSpec, SceneKind, DEFAULT_SEED};

/// Default sizes of `kdray bench`.
pub const DEFAULT_SIZES: &str = "1,10,100,1000,10000,100000,1000000";

/// What `kdray bench` is asked to do (the command line's `BenchArgs`,
/// mapped onto library types).
#[derive(Debug, Clone)]
pub struct BenchOptions {
    /// Object counts of the random scenes.
    pub sizes: Vec<usize>,
    /// What the random scenes are made of.
    pub kind: SceneKind,
    /// Seed of the random scenes.
    pub seed: u64,
    /// Scene files to measure instead of random scenes; N is each scene's
    /// object count.
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
    pub accel: Vec<Accel>,
    /// Output folder (created if missing).
    pub out: PathBuf,
    /// Also save the k-d tree's image of every run.
    pub save_images: bool,
    /// Measure nothing: rewrite the outputs of the run recorded in this folder.
    pub replot: Option<PathBuf>,
}

/// What `kdray generate` is asked to write.
#[derive(Debug, Clone)]
pub struct GenerateOptions {
    pub kind: SceneKind,
    /// Number of objects.
    pub count: usize,
    pub seed: u64,
    /// Image size written into [render].
    pub width: u32,
    pub height: u32,
    /// The scene file to write: .json for JSON, anything else TOML.
    pub output: PathBuf,
}

/// Largest random scene the bench or the generator accepts.
pub const MAX_OBJECTS: usize = 20_000_000;

fn check_side(flag: &str, value: Option<u32>) -> Result<()> {
    let max = crate::scene::MAX_IMAGE_SIDE;
    match value {
        Some(v) if !(1..=max).contains(&v) => Err(Error::Usage(format!(
            "{flag}: must be in 1..={max}, got {v}"
        ))),
        _ => Ok(()),
    }
}

fn check_count(flag: &str, n: usize) -> Result<()> {
    if !(1..=MAX_OBJECTS).contains(&n) {
        return Err(Error::Usage(format!(
            "{flag}: must be in 1..={MAX_OBJECTS}, got {n}"
        )));
    }
    Ok(())
}

/// `kdray generate`: writes one random scene as a scene file.
pub fn generate_cli(args: &GenerateOptions) -> Result<()> {
    check_count("--count", args.count)?;
    check_side("--width", Some(args.width))?;
    check_side("--height", Some(args.height))?;
    let spec = RandomSceneSpec {
        kind: args.kind,
        count: args.count,
        seed: args.seed,
        width: args.width,
        height: args.height,
    };
    let scene = random_scene(&spec);
    let header = format!(
        "A random scene of kdray's benchmark, written by:\n  kdray generate --kind {} --count {} --seed {} --width {} --height {}\n\
         {} objects (centres uniform in [-2, 2]^3, sizes ~ 1/cbrt(N)); one light; a quarter are half mirrors.",
        args.kind.name(),
        args.count,
        args.seed,
        args.width,
        args.height,
        args.count
    );
    let format = random_scene::FileFormat::from_path(&args.output);
    let text = random_scene::scene_file_text(&scene, format, &header).map_err(Error::Output)?;
    crate::output::write_file_atomic(&args.output, text.as_bytes())?;
    eprintln!(
        "kdray: wrote {} ({} spheres, {} triangles)",
        args.output.display(),
        scene.spheres.len(),
        scene.triangles.len()
    );
    if format == random_scene::FileFormat::Toml && args.count >= BIG_TOML_OBJECTS {
        eprintln!(
            "kdray: note: a TOML scene this big loads slowly and needs about 30 bytes of memory \
             per byte of file; a name ending in .json writes JSON, which loads in one pass"
        );
    }
    Ok(())
}

/// From this many objects `kdray generate` suggests JSON over TOML
/// (docs/scene-format.md: 3.1 GB and 8.5 s to load a million spheres as
/// TOML, 267 MB and 5.5 s as JSON).
const BIG_TOML_OBJECTS: usize = 100_000;

/// What the bench measures.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum BenchMode {
    /// Random scenes of the given sizes.
    Random,
    /// Scene files.
    Scenes,
}

/// How a run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum RunStatus {
    Ok,
    /// Over the brute-force budget: not run.
    Skipped,
    Failed,
}

impl RunStatus {
    pub fn name(self) -> &'static str {
        match self {
            RunStatus::Ok => "ok",
            RunStatus::Skipped => "skipped",
            RunStatus::Failed => "failed",
        }
    }
}

/// Everything the run loop needs, resolved from the options.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct BenchConfig {
    pub mode: BenchMode,
    pub kind: Option<SceneKind>,
    pub sizes: Vec<usize>,
    pub seed: u64,
    pub scenes: Vec<PathBuf>,
    pub width: Option<u32>,
    pub height: Option<u32>,
    pub max_depth: Option<u32>,
    pub repeat: u32,
    pub budget_s: f64,
    pub accels: Vec<Accel>,
    pub out: PathBuf,
    pub save_images: bool,
    /// The command line, for the report.
    pub command: String,
}

impl BenchConfig {
    pub fn from_options(args: &BenchOptions, command: String) -> Result<Self> {
        check_side("--width", args.width)?;
        check_side("--height", args.height)?;
        if let Some(d) = args.max_depth {
            if !(1..=64).contains(&d) {
                return Err(Error::Usage(format!(
                    "--max-depth: must be in 1..=64, got {d}"
                )));
            }
        }
        if args.repeat == 0 {
            return Err(Error::Usage("--repeat: must be at least 1".into()));
        }
        if args.budget_s.is_nan() || args.budget_s <= 0.0 {
            return Err(Error::Usage(format!(
                "--budget-s: must be > 0, got {}",
                args.budget_s
            )));
        }
        let mut sizes = args.sizes.clone();
        if args.scenes.is_empty() {
            if sizes.is_empty() {
                return Err(Error::Usage("--sizes: give at least one size".into()));
            }
            for &n in &sizes {
                check_count("--sizes", n)?;
            }
            sizes.sort_unstable();
            sizes.dedup();
        } else {
            sizes.clear();
        }
        let mut accels = Vec::new();
        for &a in &args.accel {
            if !accels.contains(&a) {
                accels.push(a);
            }
        }
        Ok(BenchConfig {
            mode: if args.scenes.is_empty() {
                BenchMode::Random
            } else {
                BenchMode::Scenes
            },
            kind: args.scenes.is_empty().then_some(args.kind),
            sizes,
            seed: args.seed,
            scenes: args.scenes.clone(),
            width: args.width,
            height: args.height,
            max_depth: args.max_depth,
            repeat: args.repeat,
            budget_s: args.budget_s,
            accels,
            out: args.out.clone(),
            save_images: args.save_images,
            command,
        })
    }
}

pub fn accel_name(accel: Accel) -> &'static str {
    crate::choice::Choice::name(accel)
}

/// One (scene, acceleration) measurement, or the record of why there is none.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct RunRecord {
    /// `spheres`, `triangles`, `mixed`, or the scene file's name.
    pub scene: String,
    /// Objects (spheres + triangles).
    pub n: usize,
    pub spheres: usize,
    pub triangles: usize,
    pub accel: Accel,
    pub status: RunStatus,
    /// Why it was skipped or failed.
    pub note: Option<String>,
    pub width: u32,
    pub height: u32,
    pub samples: u32,
    pub max_depth: u32,
    /// Generating (random) or loading (file) the scene.
    pub scene_ms: f64,
    /// Building the k-d tree (kdtree runs only).
    pub build_ms: Option<f64>,
    pub kd_nodes: Option<usize>,
    pub kd_leaves: Option<usize>,
    pub kd_max_depth: Option<u32>,
    pub kd_refs_per_leaf: Option<f64>,
    /// Flattening into GPU arrays and creating the storage buffers.
    pub upload_ms: Option<f64>,
    pub gpu_scene_bytes: Option<u64>,
    /// Median GPU time of the timed frames.
    pub gpu_ms: Option<f64>,
    pub gpu_ms_min: Option<f64>,
    pub gpu_ms_max: Option<f64>,
    /// Every timed frame's GPU time, in order.
    pub gpu_ms_samples: Vec<f64>,
    pub gpu_time_source: Option<crate::gpu::GpuTimeSource>,
    /// Median host wall time of one `Renderer::render` call (dispatch + readback + packing).
    pub frame_wall_ms: Option<f64>,
    pub primary_rays: Option<u64>,
    pub shadow_rays: Option<u64>,
    pub reflection_rays: Option<u64>,
    pub total_rays: Option<u64>,
    /// All rays per second of median GPU time, in millions.
    pub mrays_per_s: Option<f64>,
    /// Primary rays per second of median GPU time, in millions.
    pub primary_mrays_per_s: Option<f64>,
    /// Peak resident host memory during this run, MiB (VmHWM; Linux only).
    pub peak_host_mib: Option<f64>,
    /// Pixels whose colour differs from the k-d tree's image (brute runs).
    pub pixels_differing_from_kdtree: Option<u64>,
    /// Pixels whose loops reached llvmpipe's 65,535-iteration limit (and may
    /// be wrong); counted on llvmpipe only, null elsewhere.
    pub loop_limited_pixels: Option<u64>,
}

impl RunRecord {
    fn empty(scene: &str, s: &Scene, accel: Accel, scene_ms: f64) -> Self {
        RunRecord {
            scene: scene.to_string(),
            n: s.object_count(),
            spheres: s.spheres.len(),
            triangles: s.triangles.len(),
            accel,
            status: RunStatus::Ok,
            note: None,
            width: s.render.width,
            height: s.render.height,
            samples: s.render.samples,
            max_depth: s.render.max_depth,
            scene_ms,
            build_ms: None,
            kd_nodes: None,
            kd_leaves: None,
            kd_max_depth: None,
            kd_refs_per_leaf: None,
            upload_ms: None,
            gpu_scene_bytes: None,
            gpu_ms: None,
            gpu_ms_min: None,
            gpu_ms_max: None,
            gpu_ms_samples: Vec::new(),
            gpu_time_source: None,
            frame_wall_ms: None,
            primary_rays: None,
            shadow_rays: None,
            reflection_rays: None,
            total_rays: None,
            mrays_per_s: None,
            primary_mrays_per_s: None,
            peak_host_mib: None,
            pixels_differing_from_kdtree: None,
            loop_limited_pixels: None,
        }
    }

    pub fn is_ok(&self) -> bool {
        self.status == RunStatus::Ok
    }
}

/// Peak resident memory of this process so far, in MiB (Linux: VmHWM).
pub fn peak_host_mib() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib / 1024.0)
}

/// Resets the peak to the current resident size, so the next reading is
/// this run's own peak (Linux >= 4.0; harmless where unsupported).
fn reset_peak_host_memory() {
    let _ = std::fs::write("/proc/self/clear_refs", "5");
}

fn ms_since(t: Instant) -> f64 {
    t.elapsed().as_secs_f64() * 1e3
}

pub fn median(values: &[f64]) -> Option<f64> {
    if values.is_empty() {
        return None;
    }
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    let m = v.len() / 2;
    Some(if v.len() % 2 == 1 {
        v[m]
    } else {
        0.5 * (v[m - 1] + v[m])
    })
}

/// Progress on stderr: a bar on a terminal, one line per finished run otherwise.
struct Progress {
    bar: indicatif::ProgressBar,
}

impl Progress {
    fn new(total: u64) -> Self {
        let bar = indicatif::ProgressBar::with_draw_target(
            Some(total),
            indicatif::ProgressDrawTarget::stderr(),
        );
        if let Ok(style) = indicatif::ProgressStyle::with_template(
            "{elapsed_precise} [{bar:30.cyan/blue}] {pos}/{len} runs  {msg}",
        ) {
            bar.set_style(style.progress_chars("=> "));
        }
        bar.enable_steady_tick(std::time::Duration::from_millis(250));
        Progress { bar }
    }

    fn message(&self, msg: String) {
        self.bar.set_message(msg);
    }

    fn line(&self, line: String) {
        if self.bar.is_hidden() {
            eprintln!("{line}");
        } else {
            self.bar.println(line);
        }
    }

    fn step(&self) {
        self.bar.inc(1);
    }

    fn finish(&self) {
        self.bar.finish_and_clear();
    }
}

/// One line about a finished run, for stderr.
fn describe_run(r: &RunRecord) -> String {
    let head = format!("N={:>8} {:<6}", r.n, accel_name(r.accel));
    match r.status {
        RunStatus::Ok => {
            let mut s = format!(
                "{head} gpu {:>10.2} ms (median of {}), {:>7.2} Mrays/s",
                r.gpu_ms.unwrap_or(f64::NAN),
                r.gpu_ms_samples.len(),
                r.mrays_per_s.unwrap_or(f64::NAN)
            );
            if let Some(b) = r.build_ms {
                s.push_str(&format!(", build {b:.1} ms"));
            }
            if let Some(u) = r.upload_ms {
                s.push_str(&format!(", upload {u:.1} ms"));
            }
            if let Some(m) = r.peak_host_mib {
                s.push_str(&format!(", peak {m:.0} MiB"));
            }
            if let Some(d) = r.pixels_differing_from_kdtree {
                s.push_str(&format!(", {d} px differ from kdtree"));
            }
            s
        }
        other => format!(
            "{head} {}: {}",
            other.name(),
            r.note.as_deref().unwrap_or("")
        ),
    }
}

/// What `kdray bench` measured, and where it wrote it.
#[derive(Debug, Clone)]
pub struct BenchOutcome {
    pub report: report::BenchReport,
    pub files: Vec<PathBuf>,
}

/// A scene to measure: its label and how to get it.
enum Case {
    Random(RandomSceneSpec),
    File(PathBuf),
}

/// Runs the benchmark on `ctx` and writes every output into `config.out`.
pub fn run_bench(ctx: &GpuContext, config: &BenchConfig) -> Result<BenchOutcome> {
    std::fs::create_dir_all(&config.out).map_err(|source| Error::File {
        path: config.out.clone(),
        what: "cannot create the folder",
        source,
    })?;
    let cases: Vec<Case> = if config.scenes.is_empty() {
        let kind = config.kind.unwrap_or(SceneKind::Spheres);
        config
            .sizes
            .iter()
            .map(|&n| {
                Case::Random(RandomSceneSpec {
                    kind,
                    count: n,
                    seed: config.seed,
                    width: config.width.unwrap_or(random_scene::DEFAULT_WIDTH),
                    height: config.height.unwrap_or(random_scene::DEFAULT_HEIGHT),
                })
            })
            .collect()
    } else {
        config.scenes.iter().cloned().map(Case::File).collect()
    };

    let mut report = report::BenchReport::new(ctx, config);
    let progress = Progress::new((cases.len() * config.accels.len()) as u64);
    let renderer = Renderer::new(ctx)?;
    let max_binding = crate::gpu::max_binding_bytes(&ctx.device.limits());
    // Measured brute-force frames: (N, ms), for the budget's prediction.
    let mut brute_times: Vec<(usize, f64)> = Vec::new();
    let mut files = Vec::new();

    for case in &cases {
        progress.message(match case {
            Case::Random(spec) => format!("generating {} {}", spec.count, spec.kind.name()),
            Case::File(p) => format!("loading {}", p.display()),
        });
        reset_peak_host_memory();
        let started = Instant::now();
        let (label, mut scene) = match case {
            Case::Random(spec) => (spec.kind.name().to_string(), random_scene(spec)),
            Case::File(path) => (
                path.file_name().map_or_else(
                    || path.display().to_string(),
                    |f| f.to_string_lossy().into_owned(),
                ),
                crate::scene::load_scene(path)?,
            ),
        };
        if let Case::File(_) = case {
            scene.render.width = config.width.unwrap_or(scene.render.width);
            scene.render.height = config.height.unwrap_or(scene.render.height);
        }
        if let Some(d) = config.max_depth {
            scene.render.max_depth = d;
        }
        let scene_ms = ms_since(started);
        let n = scene.object_count();
        // The same dispatch plan as `kdray render`.
        let plan = TilePlan::new(
            scene.render.width,
            scene.render.height,
            TilePlan::DEFAULT_MAX_TILE_PIXELS,
            max_binding,
        );
        let mut kd_image: Option<Vec<u8>> = None;

        for &accel in &config.accels {
            let mut record = RunRecord::empty(&label, &scene, accel, scene_ms);
            let name = accel_name(accel);
            if accel == Accel::Brute {
                if let Some((predicted, how)) = predict_brute_ms(&brute_times, n) {
                    if predicted > config.budget_s * 1e3 {
                        record.status = RunStatus::Skipped;
                        record.note = Some(format!(
                            "predicted {:.1} s per frame ({how}) > budget {} s",
                            predicted * 1e-3,
                            config.budget_s
                        ));
                        progress.line(describe_run(&record));
                        report.push(record);
                        report.write_data(&config.out)?;
                        progress.step();
                        continue;
                    }
                }
            }
            progress.message(format!("N={n} {name}: building"));
            let prepared = PreparedScene::new(scene, accel);
            let result = measure(
                ctx,
                &renderer,
                &prepared,
                accel,
                plan,
                config,
                &progress,
                &mut record,
            );
            scene = prepared.into_scene();
            match result {
                Ok(rgb) => {
                    if accel == Accel::Brute {
                        brute_times.extend(record.gpu_ms.map(|ms| (n, ms)));
                        if let Some(kd) = &kd_image {
                            let differing = kd
                                .chunks_exact(3)
                                .zip(rgb.chunks_exact(3))
                                .filter(|(a, b)| a != b)
                                .count();
                            record.pixels_differing_from_kdtree = Some(differing as u64);
                        }
                    } else {
                        if config.save_images {
                            let path = config.out.join(format!("render-{label}-{n}.png"));
                            crate::output::write_png_atomic(
                                &path,
                                scene.render.width,
                                scene.render.height,
                                &rgb,
                            )?;
                            files.push(path);
                        }
                        kd_image = Some(rgb);
                    }
                }
                Err(e) => {
                    record.status = RunStatus::Failed;
                    record.note = Some(e.to_string());
                }
            }
            record.peak_host_mib = peak_host_mib();
            progress.line(describe_run(&record));
            report.push(record);
            report.write_data(&config.out)?;
            progress.step();
        }
    }
    progress.message("plotting".into());
    report.finish();
    files.extend(report.write_data(&config.out)?);
    files.extend(plots::write_plots(&report, &config.out)?);
    progress.finish();
    Ok(BenchOutcome { report, files })
}

/// Predicted brute-force frame time at `n` objects from the frames measured
/// so far, and how it was obtained. Brute force costs a + b N per frame (the
/// seed's linear model): with two or more sizes measured, a and b come from
/// the two largest; with one, the frame is scaled by N / N0, which
/// overestimates (it scales the fixed cost too) and so errs towards skipping.
pub fn predict_brute_ms(measured: &[(usize, f64)], n: usize) -> Option<(f64, String)> {
    let mut pts: Vec<(usize, f64)> = measured.iter().copied().filter(|p| p.1 > 0.0).collect();
    pts.sort_by_key(|p| p.0);
    pts.dedup_by_key(|p| p.0);
    match pts.as_slice() {
        [] => None,
        [(n0, ms0)] => Some((
            ms0 * n as f64 / (*n0).max(1) as f64,
            format!("{:.3} s at N={n0} scaled by N", ms0 * 1e-3),
        )),
        [.., (n0, ms0), (n1, ms1)] => {
            let b = ((ms1 - ms0) / (*n1 as f64 - *n0 as f64)).max(0.0);
            let a = (ms1 - b * *n1 as f64).max(0.0);
            let predicted = if b > 0.0 {
                a + b * n as f64
            } else {
                ms1 * n as f64 / (*n1).max(1) as f64
            };
            Some((
                predicted,
                format!(
                    "line through {:.3} s at N={n0} and {:.3} s at N={n1}",
                    ms0 * 1e-3,
                    ms1 * 1e-3
                ),
            ))
        }
    }
}

/// Uploads and renders one prepared run; fills `record` and returns the
/// image of the first frame.
#[allow(clippy::too_many_arguments)]
fn measure(
    ctx: &GpuContext,
    renderer: &Renderer,
    prepared: &PreparedScene,
    accel: Accel,
    plan: TilePlan,
    config: &BenchConfig,
    progress: &Progress,
    record: &mut RunRecord,
) -> Result<Vec<u8>> {
    let scene = &prepared.scene;
    let n = scene.object_count();
    let name = accel_name(accel);
    if accel == Accel::Kdtree {
        record.build_ms = Some(prepared.build_ms);
        let stats = prepared.tree.stats();
        record.kd_nodes = Some(stats.nodes);
        record.kd_leaves = Some(stats.leaves);
        record.kd_max_depth = Some(stats.max_depth);
        record.kd_refs_per_leaf = Some(stats.refs_per_leaf);
    }

    progress.message(format!("N={n} {name}: uploading"));
    let t = Instant::now();
    let buffers = prepared.upload(ctx)?;
    record.upload_ms = Some(prepared.flatten_ms + ms_since(t));
    record.gpu_scene_bytes = Some(prepared.arrays.byte_size());
    let params = prepared.frame_params(&buffers, accel);

    progress.message(format!("N={n} {name}: warm-up frame"));
    let t = Instant::now();
    let first = renderer.render(ctx, &buffers, params, plan)?;
    let warmup_wall = ms_since(t);
    let mut samples = Vec::new();
    let mut walls = Vec::new();
    let budget_ms = config.budget_s * 1e3;
    if accel == Accel::Brute && first.gpu_ms > budget_ms {
        // Already over budget: the warm-up frame is the only measurement.
        samples.push(first.gpu_ms);
        walls.push(warmup_wall);
        record.note = Some(format!(
            "warm-up frame {:.1} s > budget {} s: it is the only sample",
            first.gpu_ms * 1e-3,
            config.budget_s
        ));
    } else {
        for k in 0..config.repeat {
            progress.message(format!("N={n} {name}: frame {}/{}", k + 1, config.repeat));
            let t = Instant::now();
            let image = renderer.render(ctx, &buffers, params, plan)?;
            walls.push(ms_since(t));
            samples.push(image.gpu_ms);
        }
    }
    let gpu_ms = median(&samples).unwrap_or(first.gpu_ms);
    let rays = first.rays;
    record.gpu_ms = Some(gpu_ms);
    record.gpu_ms_min = samples.iter().copied().reduce(f64::min);
    record.gpu_ms_max = samples.iter().copied().reduce(f64::max);
    record.gpu_ms_samples = samples;
    record.gpu_time_source = Some(first.gpu_time_source);
    record.frame_wall_ms = median(&walls);
    if ctx.has_loop_limit() {
        record.loop_limited_pixels = Some(rays.loop_limited);
        if rays.loop_limited > 0 {
            let note = format!(
                "{} pixels reached llvmpipe's loop limit: their colour (and this time) may be wrong",
                rays.loop_limited
            );
            record.note = Some(match record.note.take() {
                Some(n) => format!("{n}; {note}"),
                None => note,
            });
        }
    }
    let r = &scene.render;
    let primary = r.width as u64 * r.height as u64 * r.samples as u64;
    let per_us = (gpu_ms * 1e3).max(1e-9);
    record.primary_rays = Some(primary);
    record.primary_mrays_per_s = Some(primary as f64 / per_us);
    // The shader's counters are cleared per tile and summed: exact.
    if rays.primary == primary {
        record.shadow_rays = Some(rays.shadow);
        record.reflection_rays = Some(rays.reflection);
        record.total_rays = Some(rays.total());
        record.mrays_per_s = Some(rays.total() as f64 / per_us);
    }
    Ok(first.rgb)
}

/// `kdray bench`: runs, writes the files, prints the summary on stdout.
pub fn bench_cli(args: &BenchOptions) -> Result<()> {
    if let Some(dir) = &args.replot {
        let outcome = replot(dir)?;
        println!("{}", report::markdown_summary(&outcome.report));
        println!("Files written:");
        for f in &outcome.files {
            println!("  {}", f.display());
        }
        return Ok(());
    }
    let command = std::iter::once("kdray".to_string())
        .chain(std::env::args().skip(1))
        .collect::<Vec<_>>()
        .join(" ");
    let config = BenchConfig::from_options(args, command)?;
    let ctx = GpuContext::new()?;
    let outcome = run_bench(&ctx, &config)?;
    println!("{}", report::markdown_summary(&outcome.report));
    println!("Files written:");
    for f in &outcome.files {
        println!("  {}", f.display());
    }
    Ok(())
}

/// Rewrites the summary, fits, targets and plots of the run recorded in
/// `dir/bench.json`, in `dir`.
pub fn replot(dir: &Path) -> Result<BenchOutcome> {
    let path = dir.join(report::JSON_FILE);
    let text = std::fs::read_to_string(&path)
        .map_err(|e| Error::Usage(format!("{}: cannot read: {e}", path.display())))?;
    let mut report: report::BenchReport = serde_json::from_str(&text)
        .map_err(|e| Error::Usage(format!("{}: not a kdray bench report: {e}", path.display())))?;
    report.refresh();
    let mut files = report.write_data(dir)?;
    files.extend(plots::write_plots(&report, dir)?);
    Ok(BenchOutcome { report, files })
}

/// The output folder's standard file names.
pub fn output_files(out: &Path) -> [PathBuf; 6] {
    [
        out.join(report::CSV_FILE),
        out.join(report::JSON_FILE),
        out.join(report::SUMMARY_FILE),
        out.join(plots::TIME_PLOT),
        out.join(plots::SPEEDUP_PLOT),
        out.join(plots::BUILD_PLOT),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn brute_prediction_uses_a_line_once_it_has_two_sizes() {
        assert!(predict_brute_ms(&[], 10).is_none());
        // One point: proportional (conservative).
        let (ms, how) = predict_brute_ms(&[(10, 50.0)], 1000).unwrap();
        assert!((ms - 5000.0).abs() < 1e-9, "{ms} {how}");
        // Two points on ms = 40 + 1 * N: the fixed cost is not scaled.
        let (ms, how) = predict_brute_ms(&[(10, 50.0), (100, 140.0)], 10_000).unwrap();
        assert!((ms - 10_040.0).abs() < 1e-6, "{ms}");
        assert!(how.contains("N=10 ") && how.contains("N=100"), "{how}");
        // Noise that makes the line fall is not extrapolated downwards.
        let (ms, _) = predict_brute_ms(&[(10, 60.0), (100, 50.0)], 1000).unwrap();
        assert!((ms - 500.0).abs() < 1e-9, "{ms}");
    }

    #[test]
    fn median_of_odd_and_even() {
        assert_eq!(median(&[]), None);
        assert_eq!(median(&[3.0, 1.0, 2.0]), Some(2.0));
        assert_eq!(median(&[4.0, 1.0, 2.0, 3.0]), Some(2.5));
    }
}
