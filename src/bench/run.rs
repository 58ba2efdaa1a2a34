//! The sweep ([`run_bench`]): for each case, the scene is made once; for
//! each build the k-d tree is built and uploaded once and every walk is
//! measured on it; brute force then runs once, unless its budget says to
//! skip it, and every k-d image is compared with its image. Each finished
//! run is recorded, and the report rewritten, at once.

use std::time::Instant;

use super::bench_case::BenchCase;
use super::budget::brute_skip_reason;
use super::cases::{cases, scene_slug};
use super::host::{peak_host_mib, reset_peak_host_memory};
use super::measure::{ms_since, FrameTimer};
use super::options::{BenchConfig, BenchMode};
use super::outputs::{prepare_output_folder, write_outputs, write_scene, BenchOutcome};
use super::progress::{run_line, Progress};
use super::record::{RunRecord, RunStatus};
use super::report::BenchReport;
use super::suite;
use crate::error::{Error, Result};
use crate::gpu::{Accel, GpuContext, GpuScene, PreparedScene, Renderer, TilePlan};
use crate::kdtree::{BuildStrategy, Traversal};
use crate::scene::Scene;

/// Runs the benchmark on `ctx` and writes every output into `config.out`.
/// `config` is taken as [`BenchConfig::validated`] left it.
pub fn run_bench(ctx: &GpuContext, config: &BenchConfig) -> Result<BenchOutcome> {
    prepare_output_folder(&config.out)?;
    let cases = cases(config);
    let mut sweep = Sweep::new(ctx, config, cases.len())?;
    for case in &cases {
        sweep.measure_case(case)?;
    }
    sweep.finish()
}

/// A sweep in progress: what it measures with, and what it has measured.
struct Sweep<'a> {
    config: &'a BenchConfig,
    timer: FrameTimer<'a>,
    progress: Progress,
    report: BenchReport,
    /// Largest storage binding of the device, for the dispatch plan.
    max_binding: u64,
    /// Measured brute-force frames: (objects x primary rays, ms), for the
    /// budget's prediction.
    brute_times: Vec<(usize, f64)>,
    /// Files written so far (the saved images).
    files: Vec<std::path::PathBuf>,
}

/// One loaded case: its label, size and set-up, shared by its runs.
struct LoadedCase {
    label: String,
    /// Objects.
    n: usize,
    /// Objects x primary rays: brute force's work per frame.
    work: usize,
    scene_ms: f64,
    /// The scene as written for peers (with `write_scenes`).
    scene_file: Option<String>,
    /// The same dispatch plan as `kdray render`.
    plan: TilePlan,
}

impl LoadedCase {
    /// A record of a run of `accel` on this case, nothing measured yet.
    fn record(&self, scene: &Scene, accel: Accel) -> RunRecord {
        RunRecord {
            scene_file: self.scene_file.clone(),
            ..RunRecord::empty(&self.label, scene, accel, self.scene_ms)
        }
    }
}

impl<'a> Sweep<'a> {
    fn new(ctx: &'a GpuContext, config: &'a BenchConfig, cases: usize) -> Result<Self> {
        let cells = config.builds.len() * config.traversals.len();
        let runs_per_case: usize = config
            .accels
            .iter()
            .map(|a| if *a == Accel::Kdtree { cells } else { 1 })
            .sum();
        let report = BenchReport::new(ctx, config);
        let progress = Progress::new((cases * runs_per_case) as u64);
        let timer = FrameTimer {
            ctx,
            renderer: Renderer::new(ctx)?,
            repeat: config.repeat,
            budget_s: config.budget_s,
        };
        Ok(Sweep {
            config,
            timer,
            progress,
            report,
            max_binding: crate::gpu::max_binding_bytes(&ctx.device.limits()),
            brute_times: Vec::new(),
            files: Vec::new(),
        })
    }

    /// Every run of one case: the k-d cells and brute force, in the
    /// configuration's order of accelerations (brute force compares its
    /// image with the cells measured before it).
    fn measure_case(&mut self, case: &BenchCase) -> Result<()> {
        let (loaded, mut scene) = self.load(case)?;
        // Each k-d cell's image and its record's index, for brute force.
        let mut kd_images: Vec<(usize, Vec<u8>)> = Vec::new();
        for &accel in &self.config.accels {
            scene = match accel {
                Accel::Kdtree => self.measure_kd_cells(&loaded, scene, &mut kd_images)?,
                Accel::Brute => self.measure_brute(&loaded, scene, &kd_images)?,
            };
        }
        Ok(())
    }

    /// Makes the case's scene, notes which mesh the suite measured, and
    /// writes the scene for peers when asked.
    fn load(&mut self, case: &BenchCase) -> Result<(LoadedCase, Scene)> {
        self.progress.message(case.describe());
        reset_peak_host_memory();
        let started = Instant::now();
        let (label, scene) = case.load()?;
        let scene_ms = ms_since(started);
        if self.config.mode == BenchMode::Suite {
            self.note_suite_mesh(&label, &scene);
        }
        let scene_file = if self.config.write_scenes {
            Some(write_scene(&self.config.out, &label, &scene)?)
        } else {
            None
        };
        let r = &scene.render;
        let n = scene.object_count();
        let loaded = LoadedCase {
            work: n * (r.width as usize * r.height as usize * r.samples as usize),
            plan: TilePlan::new(
                r.width,
                r.height,
                TilePlan::DEFAULT_MAX_TILE_PIXELS,
                self.max_binding,
            ),
            label,
            n,
            scene_ms,
            scene_file,
        };
        Ok((loaded, scene))
    }

    /// The report's note on the suite's mesh: the bunny, or its stand-in.
    fn note_suite_mesh(&mut self, label: &str, scene: &Scene) {
        if label == suite::GENERATED_MESH {
            self.report.notes.push(format!(
                "Real mesh: {} is missing, so a generated mesh of {} triangles stood in for the bunny \
                 (`apt-get install glmark2-data` installs it).",
                suite::BUNNY_OBJ,
                scene.triangles.len()
            ));
        } else if label == "bunny.toml" {
            self.report.notes.push(format!(
                "Real mesh: the Stanford bunny ({}, {}), {} triangles with the floor and mirror.",
                suite::BUNNY_SCENE,
                suite::BUNNY_OBJ,
                scene.triangles.len()
            ));
        }
    }

    /// Every (build, walk) cell: each build is made and uploaded once and
    /// measured with every walk. Returns the scene for the next runs.
    fn measure_kd_cells(
        &mut self,
        case: &LoadedCase,
        scene: Scene,
        kd_images: &mut Vec<(usize, Vec<u8>)>,
    ) -> Result<Scene> {
        let accel = Accel::Kdtree;
        let mut scene = scene;
        for &build in &self.config.builds {
            let (label, n) = (&case.label, case.n);
            self.progress
                .message(format!("{label} N={n}: building ({})", build.name()));
            let prepared = PreparedScene::built_by(scene, accel, build);
            self.progress.message(format!("{label} N={n}: uploading"));
            let flatten_ms = prepared.flatten_ms;
            let uploaded = GpuScene::try_upload(self.timer.ctx, prepared);
            let (prepared, upload_ms) = match &uploaded {
                Ok(gpu) => (gpu.prepared(), flatten_ms + gpu.upload_ms()),
                Err(failed) => (&*failed.prepared, flatten_ms),
            };
            let stats = prepared.tree.stats();
            for &traversal in &self.config.traversals {
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
                    ..case.record(&prepared.scene, accel)
                };
                let result = match &uploaded {
                    Ok(gpu) => self.timer.measure(
                        gpu,
                        gpu.frame_params().with_traversal(traversal),
                        case.plan,
                        &self.progress,
                        &mut record,
                    ),
                    Err(failed) => Err(Error::Output(failed.error.to_string())),
                };
                match result {
                    Ok(rgb) => {
                        if self.config.save_images {
                            self.save_image(case, &prepared.scene, build, traversal, &rgb)?;
                        }
                        kd_images.push((self.report.runs.len(), rgb));
                    }
                    Err(e) => {
                        record.status = RunStatus::Failed;
                        record.note = Some(e.to_string());
                    }
                }
                record.peak_host_mib = peak_host_mib();
                self.finish_run(record)?;
            }
            scene = match uploaded {
                Ok(gpu) => gpu.into_prepared(),
                Err(failed) => *failed.prepared,
            }
            .into_scene();
        }
        Ok(scene)
    }

    /// Writes one k-d cell's image as `render-<scene>-<build>-<walk>.png`.
    fn save_image(
        &mut self,
        case: &LoadedCase,
        scene: &Scene,
        build: BuildStrategy,
        traversal: Traversal,
        rgb: &[u8],
    ) -> Result<()> {
        let path = self.config.out.join(format!(
            "render-{}-{}-{}.png",
            scene_slug(&case.label, case.n),
            build.name(),
            traversal.name()
        ));
        let r = &scene.render;
        crate::output::write_png_atomic(&path, r.width, r.height, rgb)?;
        self.files.push(path);
        Ok(())
    }

    /// Brute force, unless its budget says to skip it; its image is the
    /// reference every k-d cell of the case is compared with. Returns the
    /// scene for the next runs.
    fn measure_brute(
        &mut self,
        case: &LoadedCase,
        scene: Scene,
        kd_images: &[(usize, Vec<u8>)],
    ) -> Result<Scene> {
        let accel = Accel::Brute;
        let mut record = case.record(&scene, accel);
        if let Some(note) = brute_skip_reason(
            self.timer.ctx.has_loop_limit(),
            case.n,
            case.work,
            &self.brute_times,
            self.config.budget_s,
        ) {
            record.status = RunStatus::Skipped;
            record.note = Some(note);
            self.finish_run(record)?;
            return Ok(scene);
        }
        self.progress
            .message(format!("{} N={} brute: preparing", case.label, case.n));
        let prepared = PreparedScene::new(scene, accel);
        let flatten_ms = prepared.flatten_ms;
        record.gpu_scene_bytes = Some(prepared.arrays.byte_size());
        let (result, prepared) = match GpuScene::try_upload(self.timer.ctx, prepared) {
            Ok(gpu) => {
                let result = self.timer.measure(
                    &gpu,
                    gpu.frame_params(),
                    case.plan,
                    &self.progress,
                    &mut record,
                );
                (result, gpu.into_prepared())
            }
            Err(failed) => (Err(failed.error), *failed.prepared),
        };
        record.upload_ms = Some(flatten_ms);
        let scene = prepared.into_scene();
        match result {
            Ok(rgb) => {
                self.brute_times
                    .extend(record.gpu_ms.map(|ms| (case.work, ms)));
                record.pixels_differing_from_kdtree = self.compare_with_kd_cells(&rgb, kd_images);
            }
            Err(e) => {
                record.status = RunStatus::Failed;
                record.note = Some(e.to_string());
            }
        }
        record.peak_host_mib = peak_host_mib();
        self.finish_run(record)?;
        Ok(scene)
    }

    /// Records in each k-d cell's run how many pixels differ from brute
    /// force's image; returns the most.
    fn compare_with_kd_cells(
        &mut self,
        brute_rgb: &[u8],
        kd_images: &[(usize, Vec<u8>)],
    ) -> Option<u64> {
        let mut most = None;
        for (index, kd) in kd_images {
            let differing = kd
                .chunks_exact(3)
                .zip(brute_rgb.chunks_exact(3))
                .filter(|(a, b)| a != b)
                .count() as u64;
            self.report.runs[*index].pixels_differing_from_brute = Some(differing);
            most = Some(most.map_or(differing, |m: u64| m.max(differing)));
        }
        most
    }

    /// Reports a finished (or skipped) run on stderr, adds it to the
    /// report and rewrites the report's data files.
    fn finish_run(&mut self, record: RunRecord) -> Result<()> {
        self.progress.line(run_line(&record));
        self.report.push(record);
        self.report.write_data(&self.config.out)?;
        self.progress.step();
        Ok(())
    }

    /// Recomputes the report and writes every output.
    fn finish(mut self) -> Result<BenchOutcome> {
        self.progress.message("plotting".into());
        self.report.finish();
        let mut files = self.files;
        files.extend(write_outputs(&self.report, &self.config.out)?);
        self.progress.finish();
        Ok(BenchOutcome {
            report: self.report,
            files,
        })
    }
}
