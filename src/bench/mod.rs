//! `kdray bench` and `kdray generate`: the seed study's two experiments
//! (render time against the number of objects for the naive loop, its
//! figure 7; k-d tree against the naive loop on random scenes, its figure 9),
//! reproduced on the GPU at up to a million objects, and the matrix of the
//! k-d tree's builds and walks (`--build`, `--traversal`, `--suite`).
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
//! report, a Markdown summary with a table per scene, three log-log plots
//! and an SVG plot per scene.
//!
//! The files, in the order a run uses them:
//! - [`options`]: [`BenchConfig`], the one options type, its defaults and checks;
//! - [`bench_case`]: one scene to measure and where it comes from;
//! - [`cases`](mod@cases): loading a case, and the scenes a configuration measures;
//! - `run`: the sweep over cases, cells and brute force;
//! - `measure`: one run's warm-up and timed frames;
//! - `budget`: when brute force is skipped;
//! - [`record`]: one run as recorded; `progress`: what stderr shows;
//! - [`report`]: the whole run as `bench.json`; [`host`]: the machine and the date;
//! - [`fit`]: least-squares fits; [`csv`], [`summary`], [`numbers`]: the text outputs;
//! - [`plots`], [`matrix_plot`]: the pictures; [`outputs`]: the output folder and `--replot`;
//! - [`random_scene`](mod@random_scene), [`generate`]: the random scenes and `kdray generate`;
//! - [`suite`]: the four scenes of `--suite`; [`named`]: choices in JSON by name;
//! - [`wavefront_bound`]: `--wavefront-bound`, the path tracer's kernel shape measured.

pub mod bench_case;
mod budget;
pub mod cases;
pub mod csv;
pub mod fit;
pub mod generate;
pub mod host;
pub mod matrix_plot;
mod measure;
pub mod named;
pub mod numbers;
pub mod options;
pub mod outputs;
pub mod plots;
mod progress;
pub mod wavefront_bound;
pub use kdray_core::random_scene;
pub mod record;
pub mod report;
mod run;
pub mod suite;
pub mod summary;

pub use bench_case::{BenchCase, CaseSource};
pub use cases::{cases, scene_slug};
pub use generate::write_random_scene;
pub use options::{BenchConfig, BenchMode, MAX_OBJECTS};
pub use outputs::{output_files, replot, BenchOutcome};
pub use random_scene::{random_scene, RandomSceneSpec, SceneKind, DEFAULT_SEED};
pub use record::{RunRecord, RunStatus};
pub use run::run_bench;
