//! What runs on the cluster: one array task ([`run_task`]: its share of
//! the bands, shares of samples or frames, skipping those already written,
//! the tree built and uploaded once; a denoised plan's frames, or its still
//! in one band, denoised by the task) and the finishing job ([`finish`]:
//! the still's bands streamed into one PNG, the shares of samples averaged
//! (and denoised) into its PNG and EXR, or every frame checked and the MP4
//! encoded).

use std::path::Path;
use std::time::Instant;

use serde::Serialize;

use super::plan::{self, FarmPlan, Finished, Work};
use super::scripts::INDEX_VARIABLES;
use crate::denoise::Denoiser;
use crate::error::{Error, Result};
use crate::gpu::{GpuContext, GpuScene, PreparedScene};
use crate::output::denoised::NoisyImage;
use crate::output::PngStream;
use crate::render::FramePart;
use crate::render::StreamOptions;
use crate::scene::{Frame, Scene};

/// What a task did and what it cost, printed as one JSON line into its log
/// (the figures docs/farm.md's costs are measured from).
#[derive(Debug, Clone, Serialize)]
pub struct TaskReport {
    pub task: u32,
    /// The items (bands, shares of samples or frames) of its share.
    pub items: Vec<u32>,
    /// Those it rendered (the others were there already).
    pub rendered: Vec<u32>,
    /// Reading the plan and the scene, and checking the inputs' hashes.
    pub load_ms: f64,
    /// Opening the adapter (device and queue).
    pub adapter_ms: f64,
    /// Building the tree, flattening and uploading it, and compiling the
    /// kernel its frames run.
    pub prepare_ms: f64,
    /// Rendering and writing the items, all together.
    pub render_ms: f64,
    pub adapter: String,
}

/// The task index: `given`, else the first of [`INDEX_VARIABLES`] set.
pub fn task_index(given: Option<u32>) -> Result<u32> {
    if let Some(i) = given {
        return Ok(i);
    }
    for var in INDEX_VARIABLES {
        if let Ok(text) = std::env::var(var) {
            return text
                .trim()
                .parse()
                .map_err(|_| Error::Usage(format!("{var}={text:?}: not a task index")));
        }
    }
    Err(Error::Usage(format!(
        "no task index: give it as an argument or set {}",
        INDEX_VARIABLES.join(" or ")
    )))
}

/// Reads DIR's plan, or says there is none.
pub fn plan_of(dir: &Path) -> Result<FarmPlan> {
    plan::read_plan(dir)?.ok_or_else(|| {
        Error::Usage(format!(
            "{}: no {} (write one with kdray farm SCENE --out {})",
            dir.display(),
            plan::PLAN_FILE,
            dir.display()
        ))
    })
}

/// Loads the plan's scene with its flags (and its denoising), refusing
/// inputs that changed since the plan was written (their images would not
/// match the others').
pub fn load_planned_scene(plan: &FarmPlan, dir: &Path) -> Result<Scene> {
    let (mut scene, inputs) = super::fingerprint::load_and_fingerprint(&plan.scene)?;
    if let Some(what) = super::fingerprint::difference(&plan.inputs, &inputs) {
        return Err(Error::Usage(format!(
            "{}: {what} since this farm was planned; run kdray farm again (--force to start over)",
            dir.join(plan::PLAN_FILE).display()
        )));
    }
    plan.flags.apply(&mut scene)?;
    scene.render.denoise = plan.denoise;
    Ok(scene)
}

/// Renders task `task`'s share of DIR's plan: every item of it not yet
/// written, each written atomically (a killed task leaves no half file).
pub fn run_task(dir: &Path, task: u32) -> Result<TaskReport> {
    let started = Instant::now();
    let plan = plan_of(dir)?;
    if task >= plan.tasks {
        return Err(Error::Usage(format!(
            "task {task}: the plan in {} has tasks 0..{}",
            dir.display(),
            plan.tasks
        )));
    }
    let items: Vec<u32> = plan.task_items(task).collect();
    let todo: Vec<u32> = items
        .iter()
        .copied()
        .filter(|&i| !plan.item_done(dir, i))
        .collect();
    let mut report = TaskReport {
        task,
        items: items.clone(),
        rendered: Vec::new(),
        load_ms: 0.0,
        adapter_ms: 0.0,
        prepare_ms: 0.0,
        render_ms: 0.0,
        adapter: String::new(),
    };
    if todo.is_empty() {
        return Ok(report);
    }
    let scene = load_planned_scene(&plan, dir)?;
    report.load_ms = ms_since(started);

    let t = Instant::now();
    let ctx = GpuContext::new()?;
    report.adapter_ms = ms_since(t);
    report.adapter = ctx.info.name.clone();

    let t = Instant::now();
    let still_frame = plan.still_frame();
    // Only the camera and lights change between frames: one tree serves
    // them all.
    let path = scene.frame_path();
    let render = scene.render;
    let frames: Vec<Frame> = todo
        .iter()
        .map(|&i| path.frame(still_frame.unwrap_or(i)))
        .collect();
    let uploaded = GpuScene::upload(
        &ctx,
        PreparedScene::built_by(scene, plan.flags.accel, plan.flags.build),
    )?;
    if let Some(first) = frames.first() {
        let samples = matches!(plan.work, Work::Samples { .. });
        crate::render::compile_for_output(
            &ctx,
            &uploaded,
            &first.camera,
            plan.flags.traversal,
            samples || plan.denoise,
            plan.denoise,
        )?;
    }
    report.prepare_ms = ms_since(t);

    let t = Instant::now();
    // Made once, at the first image that needs it: its kernels and weights
    // serve every frame.
    let mut denoiser = None;
    for (&item, frame) in todo.iter().zip(frames) {
        if let Work::Samples { .. } = plan.work {
            super::samples::render_share(&ctx, &uploaded, &plan, dir, item, frame)?;
            report.rendered.push(item);
            continue;
        }
        if plan.denoise {
            let noisy = render_noisy(&ctx, &uploaded, &plan, frame)?;
            let denoiser = match &mut denoiser {
                Some(denoiser) => denoiser,
                None => denoiser.insert(Denoiser::new(&ctx)?),
            };
            let denoised = noisy.denoise(denoiser)?;
            noisy.write(&denoised, &plan.item_path(dir, item), &render)?;
            report.rendered.push(item);
            continue;
        }
        let rows = plan.band_rows(item);
        let path = plan.item_path(dir, item);
        let mut png = PngStream::create(&path, plan.width, rows.1 - rows.0)?;
        let part = FramePart {
            frame,
            rows,
            samples: None,
        };
        crate::render::render_streaming(
            &ctx,
            &uploaded,
            Some(&part),
            StreamOptions::new(plan.flags.traversal),
            &mut |band| png.write_rows(band.rgb),
        )?;
        png.finish()?;
        report.rendered.push(item);
    }
    report.render_ms = ms_since(t);
    Ok(report)
}

/// `frame` whole with the denoiser's inputs: its radiance, albedo and
/// normal (a denoised plan's frame, or its still in one band).
fn render_noisy(
    ctx: &GpuContext,
    uploaded: &GpuScene,
    plan: &FarmPlan,
    frame: Frame,
) -> Result<NoisyImage> {
    let values = plan.width as usize * plan.height as usize * 3;
    let mut noisy = NoisyImage {
        width: plan.width,
        height: plan.height,
        color: Vec::with_capacity(values),
        albedo: Vec::with_capacity(values),
        normal: Vec::with_capacity(values),
    };
    let part = FramePart {
        frame,
        rows: (0, plan.height),
        samples: None,
    };
    crate::render::render_streaming(
        ctx,
        uploaded,
        Some(&part),
        StreamOptions {
            radiance: true,
            features: true,
            ..StreamOptions::new(plan.flags.traversal)
        },
        &mut |band| {
            let (Some(radiance), Some(features)) = (band.radiance, band.features) else {
                return Err(Error::Output(
                    "the renderer returned no radiance, albedo and normal to denoise".into(),
                ));
            };
            noisy.color.extend_from_slice(radiance);
            noisy.albedo.extend_from_slice(features.albedo);
            noisy.normal.extend_from_slice(features.normal);
            Ok(())
        },
    )?;
    Ok(noisy)
}

/// The finishing job: checks that every item is there (naming the missing
/// ones and their tasks), then streams a still's bands into its one PNG,
/// holding one band in memory, or encodes the frames with ffmpeg when it
/// is installed; writes the marker `--wait` looks for last.
pub fn finish(dir: &Path) -> Result<Finished> {
    let plan = plan_of(dir)?;
    let missing: Vec<u32> = (0..plan.items())
        .filter(|&i| !plan.item_done(dir, i))
        .collect();
    if !missing.is_empty() {
        return Err(Error::Output(format!(
            "{}: {} of {} parts missing ({}); their tasks failed or did not run",
            dir.display(),
            missing.len(),
            plan.items(),
            super::missing_summary(&plan, dir, &missing)
        )));
    }
    let finished = match plan.work {
        Work::Still { .. } => {
            let out = plan.final_path(dir);
            let mut png = PngStream::create(&out, plan.width, plan.height)?;
            for band in 0..plan.items() {
                let path = plan.item_path(dir, band);
                let (w, h, rgb) = crate::output::read_png_rgb(&path)?;
                let (first, end) = plan.band_rows(band);
                if (w, h) != (plan.width, end - first) {
                    return Err(Error::Output(format!(
                        "{}: {w}x{h}, expected {}x{} (rows {first}..{end})",
                        path.display(),
                        plan.width,
                        end - first
                    )));
                }
                png.write_rows(&rgb)?;
            }
            png.finish()?;
            Finished::Image(out)
        }
        Work::Samples { .. } => {
            let scene = load_planned_scene(&plan, dir)?;
            super::samples::finish_shares(&plan, dir, &scene.render)?
        }
        Work::Frames { frames, fps } => {
            for k in 0..frames {
                check_frame(&plan.item_path(dir, k), plan.width, plan.height)?;
            }
            super::video::encode(&plan, dir, frames, fps)?
        }
    };
    crate::output::write_file_atomic(&plan::finished_marker(dir), b"finished\n")?;
    Ok(finished)
}

/// Checks a frame's PNG header: readable, and the plan's size.
fn check_frame(path: &Path, width: u32, height: u32) -> Result<()> {
    let file = std::fs::File::open(path).map_err(|source| Error::File {
        path: path.to_path_buf(),
        what: "cannot open",
        source,
    })?;
    let reader = png::Decoder::new(std::io::BufReader::new(file))
        .read_info()
        .map_err(|e| Error::Output(format!("{}: not a readable PNG: {e}", path.display())))?;
    let info = reader.info();
    if (info.width, info.height) != (width, height) {
        return Err(Error::Output(format!(
            "{}: {}x{}, expected {width}x{height}",
            path.display(),
            info.width,
            info.height
        )));
    }
    Ok(())
}

fn ms_since(t: Instant) -> f64 {
    t.elapsed().as_secs_f64() * 1e3
}
