//! The `kdray` command line: `render` (to a PNG, or `--window`), `inspect`, `info`,
//! `bench`, `generate`, `web`, `denoise` and `farm` (with its hidden `farm-task` and
//! `farm-finish`).

mod args;
mod bench;
mod denoise;
mod farm;

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use args::{Cli, Command, InspectArgs, RenderArgs};
use clap::Parser;
use kdray::gpu::GpuContext;
use kdray::output::denoised::NoisyImage;
use kdray::render::StreamOptions;
use kdray::{Error, Result};

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Render(RenderArgs {
            scene,
            image,
            stats,
            window: true,
            frames,
            screenshot,
            play,
            denoise,
            ..
        }) => kdray::window::run(kdray::window::WindowOptions {
            scene,
            flags: image.into(),
            frames,
            screenshot,
            stats,
            play,
            denoise,
        }),
        Command::Render(args) => render(args),
        Command::Inspect(args) => inspect(args),
        Command::Info => info(),
        Command::Bench(args) => bench::bench(args),
        Command::Generate(args) => bench::generate(args),
        Command::Web(args) => kdray::web::export_site(&args.scene, &args.output),
        Command::Denoise(args) => denoise::denoise(args),
        Command::Farm(args) => farm::farm(args),
        Command::FarmTask(args) => farm::farm_task(args),
        Command::FarmFinish(args) => farm::farm_finish(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("kdray: {e}");
            ExitCode::from(e.exit_code() as u8)
        }
    }
}

/// The scene file, or the model file seen through `camera`; `--camera
/// default` names a model's view, so a scene file with it is a usage error.
fn load_viewed(path: &Path, camera: kdray::scene::ModelCamera) -> Result<kdray::scene::Scene> {
    use kdray::scene::ModelCamera;
    if camera == ModelCamera::File {
        return Ok(kdray::scene::load_scene(path)?);
    }
    if kdray::scene::mesh_file::MeshFormat::of_path(path).is_none() {
        return Err(Error::Usage(format!(
            "--camera {}: {} is a scene file, which states its camera; the flag is for a model file (.obj, .gltf, .glb)",
            kdray::choice::Choice::name(camera),
            path.display()
        )));
    }
    Ok(kdray::scene::model_scene_viewed(
        path,
        camera,
        &mut |_| {},
        &mut kdray::scene::print_warning,
    )?)
}

fn render(args: RenderArgs) -> Result<()> {
    let RenderArgs {
        scene: scene_path,
        output,
        image,
        stats,
        heatmap,
        heatmap_max,
        frame,
        all_frames,
        camera,
        denoise,
        ..
    } = args;
    let scene_path = scene_path.as_path();
    let heatmap = heatmap.map(|path| (path, heatmap_max));
    let mut scene = load_viewed(scene_path, camera)?;
    let flags: kdray::render::RenderFlags = image.into();
    flags.check()?;
    flags.apply(&mut scene)?;
    apply_denoise(&mut scene.render, denoise)?;
    if all_frames {
        let Some(dir) = output else {
            return Err(Error::Usage("--all-frames needs -o DIR".into()));
        };
        return render_all_frames(scene, &dir, &flags, stats);
    }
    let frame = frame.unwrap_or(0);
    if frame >= scene.frame_count() {
        return Err(Error::Usage(format!(
            "--frame: the scene has frames 0..{}, got {frame}",
            scene.frame_count()
        )));
    }
    let shown = scene.frame(frame);
    (scene.camera, scene.lights) = (shown.camera, shown.lights);
    let output = output.unwrap_or_else(|| {
        let stem = scene_path
            .file_stem()
            .map_or("out".into(), |s| s.to_string_lossy().into_owned());
        PathBuf::from(format!("{stem}.png"))
    });
    if let Some((path, _)) = &heatmap {
        if same_file(path, &output) {
            return Err(Error::Usage(format!(
                "--heatmap: {} is also the image's output",
                path.display()
            )));
        }
    }

    // Rows stream from the GPU into the PNG (memory holds one band); the
    // file appears only once complete, and a failure leaves no trace. An
    // EXR, and a denoised image, are written whole at the end.
    let mut image = ImageOut::create(&output, &scene.render)?;
    let ctx = GpuContext::new()?;
    let progress = progress_bar(scene.render.height as u64, "rendering {pos}/{len} rows")?;
    let (width, height) = (scene.render.width, scene.render.height);
    let uploaded = kdray::gpu::GpuScene::upload(
        &ctx,
        kdray::gpu::PreparedScene::built_by(scene, flags.accel, flags.build),
    )?;
    // The heatmap's scale needs every pixel: its costs are kept whole (4
    // bytes per pixel), unlike the image.
    let mut work: Vec<u32> = Vec::new();
    let (figures, _) = kdray::render::render_streaming(
        &ctx,
        &uploaded,
        None,
        StreamOptions {
            with_cost: stats || heatmap.is_some(),
            radiance: image.wants_radiance(),
            features: image.wants_features(),
            ..StreamOptions::new(flags.traversal)
        },
        &mut |band| {
            progress.inc(band.rows as u64);
            if let (Some(_), Some(costs)) = (&heatmap, band.costs) {
                work.extend(costs.iter().map(|c| c.work()));
            }
            image.write_band(&band)
        },
    )?;
    progress.finish_and_clear();
    if let Some((path, max)) = &heatmap {
        kdray::output::heatmap::write_heatmap(path, &work, width, height, *max)?;
    }
    image.finish(&ctx, &mut None)?;
    if let Some(warning) = figures.loop_limit_warning() {
        eprintln!("kdray: {warning}");
    }
    if stats {
        println!("{}", serde_json::to_string(&figures)?);
    }
    Ok(())
}

/// Every frame of `scene`'s animation into `dir` (created if missing) as
/// [`kdray::farm::plan::frame_file_name`]s, from one tree and one upload
/// (each frame rewrites only the lights buffer); one progress bar counts the
/// rows of all frames.
fn render_all_frames(
    scene: kdray::scene::Scene,
    dir: &Path,
    flags: &kdray::render::RenderFlags,
    stats: bool,
) -> Result<()> {
    let frames = scene.frame_count();
    std::fs::create_dir_all(dir)
        .map_err(|e| Error::Output(format!("{}: cannot create the folder: {e}", dir.display())))?;
    let path = scene.frame_path();
    let height = scene.render.height;
    let render = scene.render;
    let ctx = GpuContext::new()?;
    let progress = progress_bar(
        frames as u64 * height as u64,
        "rendering {pos}/{len} rows of all frames",
    )?;
    let uploaded = kdray::gpu::GpuScene::upload(
        &ctx,
        kdray::gpu::PreparedScene::built_by(scene, flags.accel, flags.build),
    )?;
    // Made once, at the first frame that needs it: its kernels and weights
    // serve every frame.
    let mut denoiser = None;
    for k in 0..frames {
        let file = dir.join(kdray::farm::plan::frame_file_name(k, frames));
        let mut image = ImageOut::create(&file, &render)?;
        let part = kdray::render::FramePart {
            frame: path.frame(k),
            rows: (0, height),
            samples: None,
        };
        let (figures, _) = kdray::render::render_streaming(
            &ctx,
            &uploaded,
            Some(&part),
            StreamOptions {
                features: image.wants_features(),
                ..StreamOptions::new(flags.traversal)
            },
            &mut |band| {
                progress.inc(band.rows as u64);
                image.write_band(&band)
            },
        )?;
        image.finish(&ctx, &mut denoiser)?;
        if let Some(warning) = figures.loop_limit_warning() {
            eprintln!("kdray: frame {k}: {warning}");
        }
        if stats {
            println!("{}", serde_json::to_string(&figures)?);
        }
    }
    progress.finish_and_clear();
    Ok(())
}

/// A progress bar on stderr over `len` steps, described by `what` (an
/// indicatif template of `{pos}` and `{len}`).
fn progress_bar(len: u64, what: &str) -> Result<indicatif::ProgressBar> {
    Ok(
        indicatif::ProgressBar::with_draw_target(
            Some(len),
            indicatif::ProgressDrawTarget::stderr(),
        )
        .with_style(
            indicatif::ProgressStyle::with_template(&format!(
                "{{spinner}} {what} [{{bar:40}}] {{elapsed}} (eta {{eta}})"
            ))
            .map_err(|e| Error::Output(e.to_string()))?
            .progress_chars("=> "),
        ),
    )
}

/// Whether two paths name the same file (the same path, or both existing
/// and one file).
fn same_file(a: &Path, b: &Path) -> bool {
    a == b
        || matches!(
            (std::fs::canonicalize(a), std::fs::canonicalize(b)),
            (Ok(x), Ok(y)) if x == y
        )
}

/// `kdray inspect`: the pixel's rays as one line of JSON on stdout.
fn inspect(args: InspectArgs) -> Result<()> {
    let request = kdray::inspect::InspectRequest {
        pixel: kdray::inspect::parse_pixel(&args.pixel)?,
        frame: args.frame.unwrap_or(0),
        flags: args.image.into(),
        source: match &args.walk_source {
            Some(name) => kdray::inspect::WalkSource::parse(name)?,
            None => kdray::inspect::WalkSource::default(),
        },
    };
    let inspection = kdray::inspect::inspect_file(&args.scene, &request)?;
    println!("{}", serde_json::to_string(&inspection)?);
    Ok(())
}

fn info() -> Result<()> {
    let (adapters, pick) = kdray::gpu::context::ranked_adapters();
    if adapters.is_empty() {
        return Err(Error::Gpu(kdray::gpu::context::NO_ADAPTER_HELP.to_string()));
    }
    for (i, a) in adapters.iter().enumerate() {
        let marker = if Some(i) == pick { "*" } else { " " };
        println!("{marker} {}", kdray::gpu::context::describe(&a.get_info()));
    }
    match pick {
        Some(_) => println!("(* = the adapter kdray uses)"),
        None => println!("no adapter matches WGPU_ADAPTER_NAME"),
    }
    Ok(())
}

/// `--denoise[=BOOL]` over the scene's `[render] denoise`; either asking
/// for the denoiser with the Whitted integrator is a usage error.
fn apply_denoise(render: &mut kdray::scene::RenderSettings, flag: Option<bool>) -> Result<()> {
    render.denoise = flag.unwrap_or(render.denoise);
    if render.denoise && render.integrator != kdray::scene::Integrator::Path {
        return Err(Error::Usage(match flag {
            Some(_) => "--denoise: the denoiser needs the path tracer (--integrator path or [render] integrator = \"path\")".into(),
            None => "--integrator whitted: the scene's [render] denoise = true needs the path tracer (--denoise=false turns it off)".into(),
        }));
    }
    Ok(())
}

/// Where `render` writes its image: a PNG fed band by band, an EXR of
/// linear radiance written whole once the last band is in, or either
/// denoised ([`Denoised`]).
enum ImageOut {
    /// Boxed: the encoder's state is large beside the other variant.
    Png(Box<kdray::output::PngStream>),
    Exr {
        path: PathBuf,
        width: u32,
        height: u32,
        rgb: Vec<f32>,
    },
    Denoised(Denoised),
}

/// A path-traced image to denoise: its radiance, albedo and normal
/// gathered whole, then denoised and written with its inputs
/// ([`NoisyImage::write`]).
struct Denoised {
    path: PathBuf,
    /// The PNG's tone map and exposure.
    render: kdray::scene::RenderSettings,
    image: NoisyImage,
}

impl ImageOut {
    fn create(path: &Path, render: &kdray::scene::RenderSettings) -> Result<Self> {
        let (width, height) = (render.width, render.height);
        let pixels = width as usize * height as usize * 3;
        if render.denoise {
            let png = !kdray::output::exr::is_exr_path(path);
            if png {
                // Fails early, as a streamed PNG does, on an unwritable folder.
                drop(kdray::output::PngStream::create(path, width, height)?);
            }
            return Ok(ImageOut::Denoised(Denoised {
                path: path.to_path_buf(),
                render: *render,
                image: NoisyImage {
                    width,
                    height,
                    color: Vec::with_capacity(pixels),
                    albedo: Vec::with_capacity(pixels),
                    normal: Vec::with_capacity(pixels),
                },
            }));
        }
        if kdray::output::exr::is_exr_path(path) {
            return Ok(ImageOut::Exr {
                path: path.to_path_buf(),
                width,
                height,
                rgb: Vec::with_capacity(pixels),
            });
        }
        Ok(ImageOut::Png(Box::new(kdray::output::PngStream::create(
            path, width, height,
        )?)))
    }

    fn wants_radiance(&self) -> bool {
        !matches!(self, ImageOut::Png(_))
    }

    fn wants_features(&self) -> bool {
        matches!(self, ImageOut::Denoised(_))
    }

    fn write_band(&mut self, band: &kdray::gpu::RowBand<'_>) -> Result<()> {
        let radiance = || {
            band.radiance.ok_or_else(|| {
                Error::Output("the renderer returned no radiance for the EXR".into())
            })
        };
        match self {
            ImageOut::Png(png) => png.write_rows(band.rgb),
            ImageOut::Exr { rgb, .. } => {
                rgb.extend_from_slice(radiance()?);
                Ok(())
            }
            ImageOut::Denoised(d) => {
                let features = band.features.ok_or_else(|| {
                    Error::Output("the renderer returned no albedo and normal to denoise".into())
                })?;
                d.image.color.extend_from_slice(radiance()?);
                d.image.albedo.extend_from_slice(features.albedo);
                d.image.normal.extend_from_slice(features.normal);
                Ok(())
            }
        }
    }

    /// Writes the image; a denoised one with `denoiser`, made here on `ctx`
    /// if it is `None`.
    fn finish<'a>(
        self,
        ctx: &'a GpuContext,
        denoiser: &mut Option<kdray::denoise::Denoiser<'a>>,
    ) -> Result<()> {
        match self {
            ImageOut::Png(png) => png.finish(),
            ImageOut::Exr {
                path,
                width,
                height,
                rgb,
            } => kdray::output::exr::write_exr_atomic(&path, width, height, &rgb),
            ImageOut::Denoised(d) => {
                let denoiser = match denoiser {
                    Some(denoiser) => denoiser,
                    None => denoiser.insert(kdray::denoise::Denoiser::new(ctx)?),
                };
                d.finish(denoiser)
            }
        }
    }
}

impl Denoised {
    fn finish(self, denoiser: &kdray::denoise::Denoiser<'_>) -> Result<()> {
        let denoised = self.image.denoise(denoiser)?;
        self.image.write(&denoised, &self.path, &self.render)
    }
}
