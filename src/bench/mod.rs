//! `kdray bench` and `kdray generate`: the seed study's two experiments
//! (render time against the number of objects for the naive loop, its
//! figure 7; k-d tree against the naive loop on random scenes, its figure 9),
//! reproduced on the GPU at up to a million objects, and the matrix of
//! builds and walks of issue 9 §5 (`--build`, `--traversal`, `--suite`).
//!
//! For each scene (a random scene of size N, [`random_scene()`], a scene
//! file, or the [`suite`]'s four) the k-d tree is built once per build
//! strategy and uploaded once per build; each walk then gets one warm-up
//! frame, which also counts the walk's work (nodes, leaves and objects per
//! ray, as `render --stats`) and gives the image, and `repeat` timed frames
//! without counting, whose median GPU time is reported. Brute force runs
//! once per scene and every k-d cell's image is compared with its image.
//! Brute force is skipped, and the skip recorded, when a linear
//! extrapolation of its measured frames (the seed's own model, in objects x
//! primary rays) exceeds the per-frame budget. Results go to a CSV, a JSON
//! summary, a Markdown summary with a table per scene, three log-log plots
//! and an SVG plot per scene ([`report`], [`plots`], [`matrix_plot`]).

pub mod matrix_plot;
pub mod named;
pub mod plots;
pub mod random_scene;
pub mod report;
pub mod suite;

use std::path::{Path, PathBuf};
use std::time::Instant;

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::gpu::{Accel, GpuContext, PreparedScene, Renderer, SceneBuffers, TilePlan};
use crate::kdtree::{BuildStrategy, Traversal};
use crate::layout::FrameParams;
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
    /// The k-d tree's builds, in order [default: the default build].
    pub builds: Vec<BuildStrategy>,
    /// The k-d walks, in order [default: the default walk].
    pub traversals: Vec<Traversal>,
    /// Measure the [`suite`]'s four scenes (instead of `sizes` or `scenes`).
    pub suite: bool,
    /// Write each measured scene as JSON into `out/scenes/` (always with `suite`).
    pub write_scenes: bool,
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
    /// Image size written into `[render]`.
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
    /// The four scenes of [`suite`].
    Suite,
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
    /// The k-d tree's builds and walks: every (build, walk) is a cell.
    #[serde(with = "named::list", default = "default_builds")]
    pub builds: Vec<BuildStrategy>,
    #[serde(default = "default_traversals")]
    pub traversals: Vec<Traversal>,
    pub out: PathBuf,
    pub save_images: bool,
    /// Write each measured scene (after the size and depth overrides) as
    /// JSON into `out/scenes/`, for peers to trace the same rays
    /// (scripts/peers/bench_embree.py); on with `--suite`.
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

/// `list` without repeats, in first-seen order; `default` when empty.
fn distinct<T: PartialEq + Copy>(list: &[T], default: T) -> Vec<T> {
    let mut out = Vec::new();
    for &v in list {
        if !out.contains(&v) {
            out.push(v);
        }
    }
    if out.is_empty() {
        out.push(default);
    }
    out
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
        if args.suite && !args.scenes.is_empty() {
            return Err(Error::Usage(
                "--suite: measures its own scenes; leave out --scene".into(),
            ));
        }
        let mut sizes = args.sizes.clone();
        if args.suite {
            sizes.clear();
        } else if args.scenes.is_empty() {
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
        let mode = if args.suite {
            BenchMode::Suite
        } else if args.scenes.is_empty() {
            BenchMode::Random
        } else {
            BenchMode::Scenes
        };
        Ok(BenchConfig {
            mode,
            kind: (mode == BenchMode::Random).then_some(args.kind),
            sizes,
            seed: args.seed,
            scenes: args.scenes.clone(),
            width: args.width,
            height: args.height,
            max_depth: args.max_depth,
            repeat: args.repeat,
            budget_s: args.budget_s,
            accels,
            builds: distinct(&args.builds, BuildStrategy::default()),
            traversals: distinct(&args.traversals, Traversal::default()),
            out: args.out.clone(),
            save_images: args.save_images,
            write_scenes: args.suite || args.write_scenes,
            command,
        })
    }
}

pub fn accel_name(accel: Accel) -> &'static str {
    crate::choice::Choice::name(accel)
}

/// One (scene, acceleration[, build, walk]) measurement, or the record of
/// why there is none.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct RunRecord {
    /// `spheres`, `triangles`, `mixed`, `gears`, the scene file's name, or
    /// `generated-mesh` (the suite's stand-in for the bunny).
    pub scene: String,
    /// Objects (spheres + triangles).
    pub n: usize,
    pub spheres: usize,
    pub triangles: usize,
    pub accel: Accel,
    /// The k-d tree's build (kdtree runs).
    #[serde(default, with = "named::option")]
    pub build: Option<BuildStrategy>,
    /// The k-d walk (kdtree runs).
    #[serde(default)]
    pub traversal: Option<Traversal>,
    /// The scene as measured, written for peers (relative to the output
    /// folder; with `write_scenes`).
    #[serde(default)]
    pub scene_file: Option<String>,
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
    /// The walk's work per ray (all rays of the warm-up frame, as
    /// `render --stats` counts them).
    #[serde(default)]
    pub nodes_visited_per_ray: Option<f64>,
    #[serde(default)]
    pub leaves_visited_per_ray: Option<f64>,
    #[serde(default)]
    pub objects_tested_per_ray: Option<f64>,
    /// Brute runs: the most pixels by which any k-d cell's image of this
    /// scene differs from brute force's.
    pub pixels_differing_from_kdtree: Option<u64>,
    /// Kdtree runs: pixels whose colour differs from brute force's image.
    #[serde(default)]
    pub pixels_differing_from_brute: Option<u64>,
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
            build: None,
            traversal: None,
            scene_file: None,
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
            nodes_visited_per_ray: None,
            leaves_visited_per_ray: None,
            objects_tested_per_ray: None,
            pixels_differing_from_kdtree: None,
            pixels_differing_from_brute: None,
            loop_limited_pixels: None,
        }
    }

    /// `kdtree sah/ropes`, `brute`: the run's acceleration and cell.
    pub fn cell_name(&self) -> String {
        match (self.build, self.traversal) {
            (Some(b), Some(t)) => format!(
                "{} {}/{}",
                accel_name(self.accel),
                crate::choice::Choice::name(b),
                t.name()
            ),
            _ => accel_name(self.accel).to_string(),
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
    let head = format!("{} N={:>8} {:<24}", r.scene, r.n, r.cell_name());
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
            if let Some(d) = r.pixels_differing_from_brute {
                s.push_str(&format!(", {d} px differ from brute"));
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

/// Where a measured scene comes from.
#[derive(Debug, Clone)]
pub enum CaseSource {
    Random(RandomSceneSpec),
    File(PathBuf),
    /// A scene file compiled into the binary (the suite's), read as if
    /// from `path`.
    Text {
        label: String,
        path: PathBuf,
        text: &'static str,
    },
    /// The suite's stand-in for the bunny ([`suite::generated_mesh_scene`]).
    GeneratedMesh,
}

/// One scene to measure, with the image size and depth it is measured at
/// (None: the scene's own).
#[derive(Debug, Clone)]
pub struct BenchCase {
    pub source: CaseSource,
    pub width: Option<u32>,
    pub height: Option<u32>,
    pub max_depth: Option<u32>,
}

impl BenchCase {
    /// What the progress line says while the scene is made.
    fn describe(&self) -> String {
        match &self.source {
            CaseSource::Random(spec) => format!("generating {} {}", spec.count, spec.kind.name()),
            CaseSource::File(p) | CaseSource::Text { path: p, .. } => {
                format!("loading {}", p.display())
            }
            CaseSource::GeneratedMesh => "generating a mesh in the bunny's place".into(),
        }
    }

    /// The scene's label and the scene, with the overrides applied.
    pub fn load(&self) -> Result<(String, Scene)> {
        let (label, mut scene) = match &self.source {
            CaseSource::Random(spec) => (spec.kind.name().to_string(), random_scene(spec)),
            CaseSource::File(path) => (
                path.file_name().map_or_else(
                    || path.display().to_string(),
                    |f| f.to_string_lossy().into_owned(),
                ),
                crate::scene::load_scene(path)?,
            ),
            CaseSource::Text { label, path, text } => {
                (label.clone(), suite::parse_text(path, text)?)
            }
            CaseSource::GeneratedMesh => (
                suite::GENERATED_MESH.to_string(),
                suite::generated_mesh_scene()?,
            ),
        };
        scene.render.width = self.width.unwrap_or(scene.render.width);
        scene.render.height = self.height.unwrap_or(scene.render.height);
        if let Some(d) = self.max_depth {
            scene.render.max_depth = d;
        }
        Ok((label, scene))
    }
}

/// The cases `config` asks for.
pub fn cases(config: &BenchConfig) -> Vec<BenchCase> {
    match config.mode {
        BenchMode::Suite => suite::suite_cases(config.seed, Path::new(suite::BUNNY_OBJ)),
        BenchMode::Scenes => config
            .scenes
            .iter()
            .map(|p| BenchCase {
                source: CaseSource::File(p.clone()),
                width: config.width,
                height: config.height,
                max_depth: config.max_depth,
            })
            .collect(),
        BenchMode::Random => {
            let kind = config.kind.unwrap_or(SceneKind::Spheres);
            config
                .sizes
                .iter()
                .map(|&n| BenchCase {
                    source: CaseSource::Random(RandomSceneSpec {
                        kind,
                        count: n,
                        seed: config.seed,
                        width: config.width.unwrap_or(random_scene::DEFAULT_WIDTH),
                        height: config.height.unwrap_or(random_scene::DEFAULT_HEIGHT),
                    }),
                    width: None,
                    height: None,
                    max_depth: config.max_depth,
                })
                .collect()
        }
    }
}

/// `label-n`, in the characters a file name may safely hold.
pub fn scene_slug(label: &str, n: usize) -> String {
    let clean: String = label
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() {
                c.to_ascii_lowercase()
            } else {
                '-'
            }
        })
        .collect();
    format!("{clean}-{n}")
}

/// Loop iterations llvmpipe lets one invocation run (`GpuContext::has_loop_limit`).
const LLVMPIPE_LOOP_LIMIT: usize = 65_535;

/// Folder (in the output folder) of the scenes written for peers.
pub const SCENES_DIR: &str = "scenes";

/// Runs the benchmark on `ctx` and writes every output into `config.out`.
pub fn run_bench(ctx: &GpuContext, config: &BenchConfig) -> Result<BenchOutcome> {
    std::fs::create_dir_all(&config.out).map_err(|source| Error::File {
        path: config.out.clone(),
        what: "cannot create the folder",
        source,
    })?;
    // A peer's results belong to the run they were measured beside.
    let stale = config.out.join(report::EMBREE_FILE);
    if stale.is_file() {
        eprintln!(
            "kdray: removing {} of an earlier run (scripts/peers/bench_embree.py measures it again)",
            stale.display()
        );
        let _ = std::fs::remove_file(&stale);
    }
    let cases = cases(config);
    let cells = config.builds.len() * config.traversals.len();
    let runs_per_case: usize = config
        .accels
        .iter()
        .map(|a| if *a == Accel::Kdtree { cells } else { 1 })
        .sum();

    let mut report = report::BenchReport::new(ctx, config);
    let progress = Progress::new((cases.len() * runs_per_case) as u64);
    let renderer = Renderer::new(ctx)?;
    let max_binding = crate::gpu::max_binding_bytes(&ctx.device.limits());
    // Measured brute-force frames: (objects x primary rays, ms), for the
    // budget's prediction.
    let mut brute_times: Vec<(usize, f64)> = Vec::new();
    let mut files = Vec::new();

    for case in &cases {
        progress.message(case.describe());
        reset_peak_host_memory();
        let started = Instant::now();
        let (label, mut scene) = case.load()?;
        let scene_ms = ms_since(started);
        let n = scene.object_count();
        if config.mode == BenchMode::Suite && label == suite::GENERATED_MESH {
            report.notes.push(format!(
                "Real mesh: {} is missing, so a generated mesh of {} triangles stood in for the bunny \
                 (`apt-get install glmark2-data` installs it).",
                suite::BUNNY_OBJ,
                scene.triangles.len()
            ));
        } else if config.mode == BenchMode::Suite && label == "bunny.toml" {
            report.notes.push(format!(
                "Real mesh: the Stanford bunny ({}, {}), {} triangles with the floor and mirror.",
                suite::BUNNY_SCENE,
                suite::BUNNY_OBJ,
                scene.triangles.len()
            ));
        }
        let scene_file = if config.write_scenes {
            Some(write_scene(&config.out, &label, &scene)?)
        } else {
            None
        };
        let r = &scene.render;
        let work = n * (r.width as usize * r.height as usize * r.samples as usize);
        // The same dispatch plan as `kdray render`.
        let plan = TilePlan::new(
            r.width,
            r.height,
            TilePlan::DEFAULT_MAX_TILE_PIXELS,
            max_binding,
        );
        // Each k-d cell's image and its record's index, for brute force.
        let mut kd_images: Vec<(usize, Vec<u8>)> = Vec::new();
        let new_record = |scene: &Scene, accel| RunRecord {
            scene_file: scene_file.clone(),
            ..RunRecord::empty(&label, scene, accel, scene_ms)
        };

        for &accel in &config.accels {
            if accel == Accel::Kdtree {
                for &build in &config.builds {
                    progress.message(format!(
                        "{label} N={n}: building ({})",
                        crate::choice::Choice::name(build)
                    ));
                    let prepared = PreparedScene::built_by(scene, accel, build);
                    progress.message(format!("{label} N={n}: uploading"));
                    let t = Instant::now();
                    let buffers = prepared.upload(ctx);
                    let upload_ms = prepared.flatten_ms + ms_since(t);
                    let stats = prepared.tree.stats();
                    for &traversal in &config.traversals {
                        let mut record = RunRecord {
                            build: Some(build),
                            traversal: Some(traversal),
                            build_ms: Some(prepared.build_ms),
                            kd_nodes: Some(stats.nodes),
                            kd_leaves: Some(stats.leaves),
                            kd_max_depth: Some(stats.max_depth),
                            kd_refs_per_leaf: Some(stats.refs_per_leaf),
                            upload_ms: Some(upload_ms),
                            gpu_scene_bytes: Some(prepared.arrays.byte_size()),
                            ..new_record(&prepared.scene, accel)
                        };
                        let result = match &buffers {
                            Ok(buffers) => measure(
                                ctx,
                                &renderer,
                                &prepared.scene,
                                buffers,
                                prepared
                                    .frame_params(buffers, accel)
                                    .with_traversal(traversal),
                                plan,
                                config,
                                &progress,
                                &mut record,
                            ),
                            Err(e) => Err(Error::Output(e.to_string())),
                        };
                        match result {
                            Ok(rgb) => {
                                if config.save_images {
                                    let path = config.out.join(format!(
                                        "render-{}-{}-{}.png",
                                        scene_slug(&label, n),
                                        crate::choice::Choice::name(build),
                                        traversal.name()
                                    ));
                                    let r = &prepared.scene.render;
                                    crate::output::write_png_atomic(
                                        &path, r.width, r.height, &rgb,
                                    )?;
                                    files.push(path);
                                }
                                kd_images.push((report.runs.len(), rgb));
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
                    drop(buffers);
                    scene = prepared.into_scene();
                }
                continue;
            }

            let mut record = new_record(&scene, accel);
            if ctx.has_loop_limit() && n >= LLVMPIPE_LOOP_LIMIT {
                // Every primary ray alone would loop over more objects than
                // llvmpipe lets an invocation run: the image would be wrong.
                record.status = RunStatus::Skipped;
                record.note = Some(format!(
                    "{n} objects: one ray's loop over them passes llvmpipe's limit of \
                     {LLVMPIPE_LOOP_LIMIT} iterations per pixel"
                ));
                progress.line(describe_run(&record));
                report.push(record);
                report.write_data(&config.out)?;
                progress.step();
                continue;
            }
            if let Some((predicted, how)) = predict_brute_ms(&brute_times, work) {
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
            progress.message(format!("{label} N={n} brute: preparing"));
            let prepared = PreparedScene::new(scene, accel);
            let result = prepared.upload(ctx).and_then(|buffers| {
                measure(
                    ctx,
                    &renderer,
                    &prepared.scene,
                    &buffers,
                    prepared.frame_params(&buffers, accel),
                    plan,
                    config,
                    &progress,
                    &mut record,
                )
            });
            record.upload_ms = Some(prepared.flatten_ms);
            record.gpu_scene_bytes = Some(prepared.arrays.byte_size());
            scene = prepared.into_scene();
            match result {
                Ok(rgb) => {
                    brute_times.extend(record.gpu_ms.map(|ms| (work, ms)));
                    let mut most = None;
                    for (index, kd) in &kd_images {
                        let differing = kd
                            .chunks_exact(3)
                            .zip(rgb.chunks_exact(3))
                            .filter(|(a, b)| a != b)
                            .count() as u64;
                        report.runs[*index].pixels_differing_from_brute = Some(differing);
                        most = Some(most.map_or(differing, |m: u64| m.max(differing)));
                    }
                    record.pixels_differing_from_kdtree = most;
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
    files.extend(matrix_plot::write_matrix_plots(&report, &config.out)?);
    progress.finish();
    Ok(BenchOutcome { report, files })
}

/// Writes `scene` as JSON into `out/scenes/`; returns its path relative to `out`.
fn write_scene(out: &Path, label: &str, scene: &Scene) -> Result<String> {
    let dir = out.join(SCENES_DIR);
    std::fs::create_dir_all(&dir).map_err(|source| Error::File {
        path: dir.clone(),
        what: "cannot create the folder",
        source,
    })?;
    let name = format!("{}.json", scene_slug(label, scene.object_count()));
    let text = random_scene::scene_file_text(scene, random_scene::FileFormat::Json, "")
        .map_err(|e| Error::Output(format!("{label}: cannot write the scene: {e}")))?;
    crate::output::write_file_atomic(&dir.join(&name), text.as_bytes())?;
    Ok(format!("{SCENES_DIR}/{name}"))
}

/// Predicted brute-force frame time for `work` (objects x primary rays)
/// from the frames measured so far, and how it was obtained. Brute force
/// costs a + b N per frame at a given image size (the seed's linear model),
/// taken here as a + b W in W = N x primary rays so that scenes of other
/// sizes and images can be compared: with two or more measured, a and b
/// come from the two largest; with one, the frame is scaled by W / W0,
/// which overestimates (it scales the fixed cost too) and so errs towards
/// skipping.
pub fn predict_brute_ms(measured: &[(usize, f64)], work: usize) -> Option<(f64, String)> {
    let mut pts: Vec<(usize, f64)> = measured.iter().copied().filter(|p| p.1 > 0.0).collect();
    pts.sort_by_key(|p| p.0);
    pts.dedup_by_key(|p| p.0);
    match pts.as_slice() {
        [] => None,
        [(w0, ms0)] => Some((
            ms0 * work as f64 / (*w0).max(1) as f64,
            format!("{:.3} s at N x rays = {w0} scaled", ms0 * 1e-3),
        )),
        [.., (w0, ms0), (w1, ms1)] => {
            let b = ((ms1 - ms0) / (*w1 as f64 - *w0 as f64)).max(0.0);
            let a = (ms1 - b * *w1 as f64).max(0.0);
            let predicted = if b > 0.0 {
                a + b * work as f64
            } else {
                ms1 * work as f64 / (*w1).max(1) as f64
            };
            Some((
                predicted,
                format!(
                    "line through {:.3} s at N x rays = {w0} and {:.3} s at {w1}",
                    ms0 * 1e-3,
                    ms1 * 1e-3
                ),
            ))
        }
    }
}

/// Renders one frame, counting the walk's work, and returns its image and
/// summary.
fn counted_frame(
    ctx: &GpuContext,
    renderer: &Renderer,
    buffers: &SceneBuffers,
    params: FrameParams,
    plan: TilePlan,
) -> Result<(Vec<u8>, crate::gpu::RenderSummary)> {
    let mut rgb = Vec::with_capacity(params.width as usize * params.height as usize * 3);
    let summary =
        renderer.render_bands_with_cost(ctx, buffers, params, plan, true, &mut |band| {
            rgb.extend_from_slice(band.rgb);
            Ok(())
        })?;
    Ok((rgb, summary))
}

/// Renders one uploaded run: a warm-up frame that counts the walk's work
/// (and gives the image), then `repeat` timed frames of a pipeline without
/// the counters (`KernelVariant::count_costs`);
/// fills `record` and returns the image.
#[allow(clippy::too_many_arguments)]
fn measure(
    ctx: &GpuContext,
    renderer: &Renderer,
    scene: &Scene,
    buffers: &SceneBuffers,
    params: FrameParams,
    plan: TilePlan,
    config: &BenchConfig,
    progress: &Progress,
    record: &mut RunRecord,
) -> Result<Vec<u8>> {
    let what = format!("{} N={} {}", record.scene, record.n, record.cell_name());
    progress.message(format!("{what}: warm-up frame"));
    let t = Instant::now();
    let (rgb, first) = counted_frame(ctx, renderer, buffers, params, plan)?;
    let warmup_wall = ms_since(t);
    if let Some(cost) = first.cost {
        let rays = first.rays.total().max(1) as f64;
        record.nodes_visited_per_ray = Some(cost.nodes_visited as f64 / rays);
        record.leaves_visited_per_ray = Some(cost.leaves_visited as f64 / rays);
        record.objects_tested_per_ray = Some(cost.objects_tested as f64 / rays);
    }
    let mut samples = Vec::new();
    let mut walls = Vec::new();
    let budget_ms = config.budget_s * 1e3;
    if record.accel == Accel::Brute && first.gpu_ms > budget_ms {
        // Already over budget: the warm-up frame is the only measurement.
        samples.push(first.gpu_ms);
        walls.push(warmup_wall);
        record.note = Some(format!(
            "warm-up frame {:.1} s > budget {} s: it is the only sample",
            first.gpu_ms * 1e-3,
            config.budget_s
        ));
    } else {
        // The timed frames' pipeline counts nothing, unlike the warm-up's:
        // compile it first, so that the first timed frame does not include that.
        renderer.compile(ctx, buffers, params, false)?;
        for k in 0..config.repeat {
            progress.message(format!("{what}: frame {}/{}", k + 1, config.repeat));
            let t = Instant::now();
            let image = renderer.render(ctx, buffers, params, plan)?;
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
    Ok(rgb)
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
/// `dir/bench.json`, in `dir`, taking in the Embree results of
/// `dir/embree.json` when there are (scripts/peers/bench_embree.py).
pub fn replot(dir: &Path) -> Result<BenchOutcome> {
    let path = dir.join(report::JSON_FILE);
    let text = std::fs::read_to_string(&path)
        .map_err(|e| Error::Usage(format!("{}: cannot read: {e}", path.display())))?;
    let mut report: report::BenchReport = serde_json::from_str(&text)
        .map_err(|e| Error::Usage(format!("{}: not a kdray bench report: {e}", path.display())))?;
    let embree = dir.join(report::EMBREE_FILE);
    if embree.is_file() {
        let text = std::fs::read_to_string(&embree)
            .map_err(|e| Error::Usage(format!("{}: cannot read: {e}", embree.display())))?;
        report.embree = Some(serde_json::from_str(&text).map_err(|e| {
            Error::Usage(format!("{}: not an Embree result: {e}", embree.display()))
        })?);
    }
    report.refresh();
    let mut files = report.write_data(dir)?;
    files.extend(plots::write_plots(&report, dir)?);
    files.extend(matrix_plot::write_matrix_plots(&report, dir)?);
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
        assert!(how.contains("= 10 ") && how.contains("at 100"), "{how}");
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
