//! The command line's own types: clap's view of the flags, each mapped onto
//! the library's options in one place ([`BenchArgs::config`],
//! [`GenerateArgs::spec`]). The library knows nothing of clap; its named
//! choices ([`kdray::choice::Choice`]) give the flags their values and help,
//! and its defaults the flags' defaults.

use std::path::PathBuf;

use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
use clap::{Parser, Subcommand};
use kdray::bench::options::{
    BenchConfig, BenchMode, DEFAULT_ACCELS, DEFAULT_BUDGET_S, DEFAULT_OUT, DEFAULT_REPEAT,
    DEFAULT_SIZES,
};
use kdray::bench::random_scene::{DEFAULT_HEIGHT, DEFAULT_WIDTH};
use kdray::bench::{RandomSceneSpec, SceneKind, DEFAULT_SEED};
use kdray::choice::Choice;
use kdray::farm::Split;
use kdray::gpu::Accel;
use kdray::kdtree::{BuildStrategy, Traversal};
use kdray::render::RenderFlags;
use kdray::scene::Integrator;
use kdray::scene::ModelCamera;

#[derive(Parser)]
#[command(
    name = "kdray",
    version,
    about = "GPU ray tracer with a CPU-built k-d tree (wgpu compute shaders)"
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Subcommand)]
pub enum Command {
    /// Render a scene file (.toml or .json) to a PNG.
    Render(RenderArgs),
    /// Print every ray one pixel's first sample traces, with the k-d walk of
    /// each, step by step, as one JSON document (the Whitted integrator).
    Inspect(InspectArgs),
    /// List the adapters wgpu sees and the one kdray picks.
    Info,
    /// Benchmark the k-d tree against brute force on random scenes of growing size
    /// (or on scene files): CSV, JSON, Markdown and log-log plots.
    Bench(BenchArgs),
    /// Write one of the bench's random scenes as a scene file.
    Generate(GenerateArgs),
    /// Write a static site that traces the scene in a browser with WebGPU.
    Web(WebArgs),
    /// Denoise an HDR image (OpenEXR), with or without albedo and normal, by
    /// Open Image Denoise's trained network run in kdray's GPU kernels.
    Denoise(crate::denoise::DenoiseArgs),
    /// Render on a cluster: write a Slurm job array and a finishing job into
    /// --out (a still in bands of rows, or an animation's frames), and
    /// optionally submit them and wait.
    Farm(FarmArgs),
    /// Run one task of a farm (what its batch script runs).
    #[command(hide = true)]
    FarmTask(FarmTaskArgs),
    /// Finish a farm: bands into one PNG, or frames checked and encoded.
    #[command(hide = true)]
    FarmFinish(FarmFinishArgs),
}

#[derive(clap::Args)]
pub struct WebArgs {
    /// The scene file.
    pub scene: PathBuf,
    /// The site's folder: new, empty, or a site written before.
    #[arg(short, long)]
    pub output: PathBuf,
}

/// A flag whose values are a library [`Choice`]: clap lists the names and
/// their help, and an unknown name is a usage error (exit 2) naming them.
pub fn choice<T: Choice + Clone>() -> impl TypedValueParser<Value = T> {
    PossibleValuesParser::new(
        T::ALL
            .iter()
            .map(|c| PossibleValue::new(c.name()).help(c.help())),
    )
    .try_map(|name| T::from_name(&name).ok_or("not one of the possible values"))
}

/// One value of a list flag that also takes `all`.
#[derive(Clone, Copy)]
pub enum OrAll<T> {
    One(T),
    All,
}

/// A list flag's value: one of a [`Choice`]'s names or `all` (every
/// value); clap lists them, and an unknown name is exit 2 naming them.
fn choice_or_all<T: Choice + Clone>() -> impl TypedValueParser<Value = OrAll<T>> {
    PossibleValuesParser::new(
        T::ALL
            .iter()
            .map(|c| PossibleValue::new(c.name()).help(c.help()))
            .chain(std::iter::once(
                PossibleValue::new("all").help("every value"),
            )),
    )
    .try_map(|name| match name.as_str() {
        "all" => Ok(OrAll::All),
        _ => T::from_name(&name)
            .map(OrAll::One)
            .ok_or("not one of the possible values"),
    })
}

/// The values a list flag names, `all` expanded, in order.
fn expand<T: Choice>(list: &[OrAll<T>]) -> Vec<T> {
    let mut out = Vec::new();
    for v in list {
        match v {
            OrAll::One(c) => out.push(*c),
            OrAll::All => out.extend_from_slice(T::ALL),
        }
    }
    out
}

#[derive(clap::Args)]
pub struct RenderArgs {
    /// The scene file.
    pub scene: PathBuf,
    /// Output image: PNG, or OpenEXR (.exr: linear radiance as 32-bit floats)
    /// [default: the scene's file name with .png, in the current folder].
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Denoise the path-traced image (OIDN's network with its albedo and
    /// normal) before writing it; with -o X.exr also write X.noisy.exr,
    /// X.albedo.exr and X.normal.exr. --denoise=false turns off the scene's
    /// [render] denoise = true. With --window: start with denoising on (N toggles it).
    #[arg(long, value_name = "BOOL", num_args = 0..=1, require_equals = true,
          default_missing_value = "true")]
    pub denoise: Option<bool>,
    #[command(flatten)]
    pub image: ImageFlags,
    /// A model file opened as a scene (.obj, .gltf, .glb): which camera to look through.
    #[arg(long, value_parser = choice::<ModelCamera>(), default_value = "file", conflicts_with = "window")]
    pub camera: ModelCamera,
    /// Print one JSON object of figures on stdout (with --window: frame rates, on exit).
    #[arg(long)]
    pub stats: bool,
    /// Also write a heatmap of the work per pixel (k-d nodes visited plus objects
    /// tested, over all the pixel's rays) as a PNG, with its colour bar and scale.
    #[arg(long, value_name = "PATH", conflicts_with = "window")]
    pub heatmap: Option<PathBuf>,
    /// The heatmap's top of scale, in work units [default: the image's largest];
    /// fix it to compare runs.
    #[arg(long, value_name = "N", requires = "heatmap", value_parser = clap::value_parser!(u32).range(1..))]
    pub heatmap_max: Option<u32>,
    /// Render this frame of the scene's animation (0-based) [default: 0].
    #[arg(long, value_name = "N", conflicts_with = "window")]
    pub frame: Option<u32>,
    /// Render every frame of the scene's animation into the folder --output
    /// names (0000.png, 0001.png, ...), building the tree once.
    #[arg(long, requires = "output", conflicts_with_all = ["window", "frame", "heatmap"])]
    pub all_frames: bool,
    /// Open an interactive window instead of writing a PNG (see the README's controls).
    #[arg(long, conflicts_with = "output")]
    pub window: bool,
    /// With --window: present this many frames, then exit.
    #[arg(long, requires = "window", value_parser = clap::value_parser!(u32).range(1..))]
    pub frames: Option<u32>,
    /// With --window: on exit, save the last presented frame as a PNG here.
    #[arg(long, requires = "window")]
    pub screenshot: Option<PathBuf>,
    /// With --window: start playing the scene's animation (Space pauses).
    #[arg(long, requires = "window")]
    pub play: bool,
}

#[derive(clap::Args)]
pub struct InspectArgs {
    /// The scene file.
    pub scene: PathBuf,
    /// The pixel: column X, row Y, from the top-left (0,0).
    #[arg(long, value_name = "X,Y", allow_hyphen_values = true)]
    pub pixel: String,
    #[command(flatten)]
    pub image: ImageFlags,
    /// The frame of the scene's animation (0-based) [default: 0].
    #[arg(long, value_name = "N")]
    pub frame: Option<u32>,
    /// Where the rays and walks come from: `kernel` (logged by the GPU
    /// kernel as it traces the pixel; either integrator) or `cpu` (the CPU
    /// reference tracer and walk mirrors; Whitted only) [default: kernel].
    #[arg(long, value_name = "kernel|cpu")]
    pub walk_source: Option<String>,
}

/// The flags `render`, `farm` and `inspect` share: the scene's `[render]` overrides
/// and the search, as the library's [`RenderFlags`].
#[derive(clap::Args)]
pub struct ImageFlags {
    /// Image width in pixels (overrides the scene's [render] width).
    #[arg(long)]
    pub width: Option<u32>,
    /// Image height in pixels (overrides the scene's [render] height).
    #[arg(long)]
    pub height: Option<u32>,
    /// Samples per pixel: a perfect square for the Whitted integrator, any count
    /// for the path tracer (overrides the scene's [render] samples).
    #[arg(long)]
    pub samples: Option<u32>,
    /// The light transport (overrides the scene's [render] integrator).
    #[arg(long, value_parser = choice::<Integrator>())]
    pub integrator: Option<Integrator>,
    /// The path tracer's random seed (overrides the scene's [render] seed).
    #[arg(long)]
    pub seed: Option<u32>,
    /// Nearest-hit search in the shader.
    #[arg(long, value_parser = choice::<Accel>(), default_value = "kdtree")]
    pub accel: Accel,
    /// The kernel's k-d walk (with --accel kdtree; the window starts with it, T cycles them).
    #[arg(long, value_parser = choice::<Traversal>(), default_value = "short-stack")]
    pub traversal: Traversal,
    /// How the k-d tree is built (with --accel kdtree; the window starts with it, K cycles them).
    #[arg(long, value_parser = choice::<BuildStrategy>(), default_value = "sah")]
    pub build: BuildStrategy,
}

impl From<ImageFlags> for RenderFlags {
    fn from(f: ImageFlags) -> RenderFlags {
        let ImageFlags {
            width,
            height,
            samples,
            integrator,
            seed,
            accel,
            traversal,
            build,
        } = f;
        RenderFlags {
            width,
            height,
            samples,
            accel,
            traversal,
            build,
            integrator,
            seed,
        }
    }
}

/// The library's default sizes as `--sizes` writes them (comma separated).
fn default_sizes() -> &'static str {
    static TEXT: std::sync::OnceLock<String> = std::sync::OnceLock::new();
    TEXT.get_or_init(|| DEFAULT_SIZES.map(|n| n.to_string()).join(","))
}

#[derive(clap::Args)]
pub struct BenchArgs {
    /// Object counts of the random scenes, comma separated.
    #[arg(long, value_delimiter = ',', default_value = default_sizes())]
    pub sizes: Vec<usize>,
    /// What the random scenes are made of.
    #[arg(long, value_parser = choice::<SceneKind>(), default_value = "spheres")]
    pub kind: SceneKind,
    /// Seed of the random scenes.
    #[arg(long, default_value_t = DEFAULT_SEED)]
    pub seed: u64,
    /// Scene files to measure instead of random scenes (repeatable); N is
    /// each scene's object count.
    #[arg(long = "scene", value_name = "SCENE")]
    pub scenes: Vec<PathBuf>,
    /// Image width [default: 640 for random scenes, the scene's own for --scene].
    #[arg(long)]
    pub width: Option<u32>,
    /// Image height [default: 480 for random scenes, the scene's own for --scene].
    #[arg(long)]
    pub height: Option<u32>,
    /// Override render.max_depth (1 = primary hits only, no reflections).
    #[arg(long)]
    pub max_depth: Option<u32>,
    /// Timed frames per run, after one warm-up frame; the median is reported.
    #[arg(long, default_value_t = DEFAULT_REPEAT)]
    pub repeat: u32,
    /// Per-frame budget for brute force, in seconds: a size whose predicted
    /// brute-force frame exceeds it is skipped (and reported as skipped).
    #[arg(long, default_value_t = DEFAULT_BUDGET_S)]
    pub budget_s: f64,
    /// Which accelerations to run.
    #[arg(long, value_parser = choice::<Accel>(), value_delimiter = ',', default_values = DEFAULT_ACCELS.map(Choice::name))]
    pub accel: Vec<Accel>,
    /// The k-d tree's builds, comma separated, or `all`: each build is made
    /// and uploaded once and measured with every --traversal [default: sah].
    #[arg(long, value_name = "LIST", value_parser = choice_or_all::<BuildStrategy>(), value_delimiter = ',')]
    pub build: Vec<OrAll<BuildStrategy>>,
    /// The k-d walks, comma separated, or `all` [default: short-stack].
    #[arg(long, value_name = "LIST", value_parser = choice_or_all::<Traversal>(), value_delimiter = ',')]
    pub traversal: Vec<OrAll<Traversal>>,
    /// Measure the study's four scenes (random spheres, random triangles,
    /// the bunny or a generated mesh, the seed scene; sizes in
    /// docs/benchmarks.md) instead of --sizes or --scene, and write them
    /// into OUT/scenes/ for scripts/peers/bench_embree.py.
    #[arg(long, conflicts_with_all = ["scenes", "sizes", "kind", "width", "height", "max_depth"])]
    pub suite: bool,
    /// Write each measured scene (with the size and depth overrides) as JSON
    /// into OUT/scenes/, for scripts/peers/bench_embree.py (always with --suite).
    #[arg(long)]
    pub write_scenes: bool,
    /// Output folder (created if missing).
    #[arg(long, default_value = DEFAULT_OUT)]
    pub out: PathBuf,
    /// Also save the k-d tree's image of every run as render-*.png in the output folder.
    #[arg(long)]
    pub save_images: bool,
    /// Measure nothing: read DIR/bench.json from an earlier run and rewrite
    /// its summary, fits and plots in DIR.
    #[arg(long, value_name = "DIR", conflicts_with_all = ["scenes", "save_images", "suite", "write_scenes"])]
    pub replot: Option<PathBuf>,
    /// Path trace each --scene (one sample a pixel) with every walk, and
    /// trace the same kind of rays from a queue alone: how much a wavefront
    /// path tracer could gain on this adapter at most. Writes
    /// OUT/wavefront-bound.json.
    #[arg(long, requires = "scenes", conflicts_with_all = ["suite", "replot"])]
    pub wavefront_bound: bool,
}

impl BenchArgs {
    /// The library's options for these flags (but `--replot`, which
    /// measures nothing); `command` is the command line, for the report.
    pub fn config(&self, command: String) -> BenchConfig {
        BenchConfig {
            mode: if self.suite {
                BenchMode::Suite
            } else if self.scenes.is_empty() {
                BenchMode::Random
            } else {
                BenchMode::Scenes
            },
            kind: Some(self.kind),
            sizes: self.sizes.clone(),
            seed: self.seed,
            scenes: self.scenes.clone(),
            width: self.width,
            height: self.height,
            max_depth: self.max_depth,
            repeat: self.repeat,
            budget_s: self.budget_s,
            accels: self.accel.clone(),
            builds: expand(&self.build),
            traversals: expand(&self.traversal),
            out: self.out.clone(),
            save_images: self.save_images,
            write_scenes: self.write_scenes,
            command,
        }
    }
}

#[derive(clap::Args)]
pub struct GenerateArgs {
    /// What the objects are.
    #[arg(long, value_parser = choice::<SceneKind>(), default_value = "spheres")]
    pub kind: SceneKind,
    /// Number of objects.
    #[arg(long)]
    pub count: usize,
    /// Random seed (the bench's default gives the bench's scenes).
    #[arg(long, default_value_t = DEFAULT_SEED)]
    pub seed: u64,
    /// Image width written into [render].
    #[arg(long, default_value_t = DEFAULT_WIDTH)]
    pub width: u32,
    /// Image height written into [render].
    #[arg(long, default_value_t = DEFAULT_HEIGHT)]
    pub height: u32,
    /// The scene file to write: .json for JSON, anything else TOML.
    #[arg(short, long)]
    pub output: PathBuf,
}

impl GenerateArgs {
    /// The random scene these flags ask for.
    pub fn spec(&self) -> RandomSceneSpec {
        RandomSceneSpec {
            kind: self.kind,
            count: self.count,
            seed: self.seed,
            width: self.width,
            height: self.height,
        }
    }
}

#[derive(clap::Args)]
pub struct FarmArgs {
    /// The scene file.
    pub scene: PathBuf,
    /// The farm's folder: plan, batch scripts, the result, and parts/ (bands, logs).
    #[arg(long)]
    pub out: PathBuf,
    #[command(flatten)]
    pub image: ImageFlags,
    /// Denoise the path-traced images as `render --denoise` does: a still
    /// split by samples once, by the finishing job, from the shares'
    /// averaged radiance, albedo and normal (its EXR beside the three);
    /// each frame by its task. --denoise=false turns off the scene's
    /// [render] denoise = true.
    #[arg(long, value_name = "BOOL", num_args = 0..=1, require_equals = true,
          default_missing_value = "true")]
    pub denoise: Option<bool>,
    /// Render a still of this frame of the scene's animation (0-based)
    /// instead of every frame.
    #[arg(long, value_name = "N")]
    pub frame: Option<u32>,
    /// Cut the still into N parts, one array task each [default: 1]: bands
    /// of rows, or with --split samples shares of the samples.
    #[arg(long, visible_alias = "parts", value_name = "N")]
    pub tiles: Option<u32>,
    /// How a still is cut into parts: bands of rows, or (path tracer only)
    /// contiguous shares of each pixel's samples, averaged by the finishing
    /// job into the still's PNG and EXR.
    #[arg(long, value_parser = choice::<Split>(), default_value = "rows")]
    pub split: Split,
    /// The job array's tasks, each rendering a contiguous share of the bands,
    /// shares of samples or frames [default: one per part; one per 50 frames].
    #[arg(long, value_name = "K")]
    pub tasks: Option<u32>,
    /// An sbatch option for both scripts, one per flag, e.g.
    /// --sbatch=--gres=gpu:1 --sbatch=--time=01:00:00 --sbatch=--partition=gpu.
    #[arg(long, value_name = "ARG", allow_hyphen_values = true)]
    pub sbatch: Vec<String>,
    /// Submit the array and the finishing job with sbatch and print their ids.
    #[arg(long)]
    pub submit: bool,
    /// Return when the jobs are done (with --submit, the jobs it submits;
    /// alone, the last ones submitted for --out); exit 0 when everything
    /// is there, else name the failed tasks and their logs.
    #[arg(long)]
    pub wait: bool,
    /// Discard the images of another render planned in --out and start again.
    #[arg(long)]
    pub force: bool,
}

#[derive(clap::Args)]
pub struct FarmTaskArgs {
    /// The farm's folder.
    pub dir: PathBuf,
    /// The task's index [default: $SLURM_ARRAY_TASK_ID, else $JOB_COMPLETION_INDEX].
    pub index: Option<u32>,
}

#[derive(clap::Args)]
pub struct FarmFinishArgs {
    /// The farm's folder.
    pub dir: PathBuf,
}
