//! The `kdray` command line: `render` (to a PNG, or `--window`), `info`,
//! `bench` and `generate`.

mod args;

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use args::{Cli, Command, RenderArgs};
use clap::Parser;
use kdray::gpu::{Accel, GpuContext, TilePlan};
use kdray::{Error, Result};

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Render(RenderArgs {
            scene,
            width,
            height,
            samples,
            accel,
            stats,
            window: true,
            frames,
            screenshot,
            ..
        }) => kdray::window::run(kdray::window::WindowOptions {
            scene,
            width,
            height,
            samples,
            accel,
            frames,
            screenshot,
            stats,
        }),
        Command::Render(RenderArgs {
            scene,
            output,
            width,
            height,
            samples,
            accel,
            traversal,
            stats,
            ..
        }) => render(
            &scene,
            output,
            width,
            height,
            samples,
            (accel, traversal),
            stats,
        ),
        Command::Info => info(),
        Command::Bench(args) => kdray::bench::bench_cli(&args.into()),
        Command::Generate(args) => kdray::bench::generate_cli(&args.into()),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("kdray: {e}");
            ExitCode::from(e.exit_code() as u8)
        }
    }
}

fn render(
    scene_path: &Path,
    output: Option<PathBuf>,
    width: Option<u32>,
    height: Option<u32>,
    samples: Option<u32>,
    (accel, traversal): (Accel, kdray::kdtree::Traversal),
    stats: bool,
) -> Result<()> {
    let mut scene = kdray::scene::load_scene(scene_path)?;
    kdray::render::check_render_flags(width, height, samples)?;
    scene.render.samples = samples.unwrap_or(scene.render.samples);
    scene.render.width = width.unwrap_or(scene.render.width);
    scene.render.height = height.unwrap_or(scene.render.height);
    let output = output.unwrap_or_else(|| {
        let stem = scene_path
            .file_stem()
            .map_or("out".into(), |s| s.to_string_lossy().into_owned());
        PathBuf::from(format!("{stem}.png"))
    });

    // Rows stream from the GPU into the PNG (memory holds one band); the
    // file appears only once complete, and a failure leaves no trace.
    let mut png =
        kdray::output::PngStream::create(&output, scene.render.width, scene.render.height)?;
    let ctx = GpuContext::new()?;
    let progress = indicatif::ProgressBar::with_draw_target(
        Some(scene.render.height as u64),
        indicatif::ProgressDrawTarget::stderr(),
    )
    .with_style(
        indicatif::ProgressStyle::with_template(
            "{spinner} rendering {pos}/{len} rows [{bar:40}] {elapsed} (eta {eta})",
        )
        .map_err(|e| Error::Output(e.to_string()))?
        .progress_chars("=> "),
    );
    let prepared = kdray::gpu::PreparedScene::new(scene, accel);
    let (figures, _) = kdray::render::render_scene_streaming(
        &ctx,
        &prepared,
        accel,
        traversal,
        TilePlan::DEFAULT_MAX_TILE_PIXELS,
        &mut |band| {
            progress.inc(band.rows as u64);
            png.write_rows(band.rgb)
        },
    )?;
    progress.finish_and_clear();
    png.finish()?;
    if let Some(warning) = figures.loop_limit_warning() {
        eprintln!("kdray: {warning}");
    }
    if stats {
        println!("{}", serde_json::to_string(&figures)?);
    }
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
