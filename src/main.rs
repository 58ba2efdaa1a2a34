//! The `kdray` command line: `render` (to a PNG, or `--window`), `info`,
//! `bench` and `generate`.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Parser, Subcommand};
use kdray::gpu::{Accel, GpuContext, TilePlan};
use kdray::{Error, Result};

#[derive(Parser)]
#[command(
    name = "kdray",
    version,
    about = "GPU ray tracer with a CPU-built k-d tree (wgpu compute shaders)"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Render a scene file (.toml or .json) to a PNG.
    Render {
        /// The scene file.
        scene: PathBuf,
        /// Output PNG [default: the scene's file name with .png, in the current folder].
        #[arg(short, long)]
        output: Option<PathBuf>,
        /// Image width in pixels (overrides the scene's [render] width).
        #[arg(long)]
        width: Option<u32>,
        /// Image height in pixels (overrides the scene's [render] height).
        #[arg(long)]
        height: Option<u32>,
        /// Samples per pixel, a perfect square (overrides the scene's [render] samples).
        #[arg(long)]
        samples: Option<u32>,
        /// Nearest-hit search in the shader.
        #[arg(long, value_enum, default_value_t = Accel::Kdtree)]
        accel: Accel,
        /// Print one JSON object of figures on stdout (with --window: frame rates, on exit).
        #[arg(long)]
        stats: bool,
        /// Open an interactive window instead of writing a PNG (see the README's controls).
        #[arg(long, conflicts_with = "output")]
        window: bool,
        /// With --window: present this many frames, then exit.
        #[arg(long, requires = "window", value_parser = clap::value_parser!(u32).range(1..))]
        frames: Option<u32>,
        /// With --window: on exit, save the last presented frame as a PNG here.
        #[arg(long, requires = "window")]
        screenshot: Option<PathBuf>,
    },
    /// List the adapters wgpu sees and the one kdray picks.
    Info,
    /// Benchmark the k-d tree against brute force on random scenes of growing size
    /// (or on scene files): CSV, JSON, Markdown and log-log plots.
    Bench(kdray::bench::BenchArgs),
    /// Write one of the bench's random scenes as a scene file.
    Generate(kdray::bench::GenerateArgs),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Render {
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
        } => kdray::window::run(kdray::window::WindowOptions {
            scene,
            width,
            height,
            samples,
            accel,
            frames,
            screenshot,
            stats,
        }),
        Command::Render {
            scene,
            output,
            width,
            height,
            samples,
            accel,
            stats,
            ..
        } => render(&scene, output, width, height, samples, accel, stats),
        Command::Info => info(),
        Command::Bench(args) => kdray::bench::bench_cli(&args),
        Command::Generate(args) => kdray::bench::generate_cli(&args),
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
    accel: Accel,
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
    let (figures, _) = kdray::render::render_scene_streaming(
        &ctx,
        &scene,
        accel,
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
        println!(
            "{}",
            serde_json::to_string(&figures).map_err(|e| Error::Output(e.to_string()))?
        );
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
