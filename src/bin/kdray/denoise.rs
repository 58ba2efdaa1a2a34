//! `kdray denoise`: an HDR image (OpenEXR) denoised by the GPU denoiser
//! (OIDN 1.4.3's RT networks in kdray's kernels), written as OpenEXR or as
//! a PNG tone-mapped as `kdray render` maps radiance (ACES, then sRGB).

use std::path::{Path, PathBuf};
use std::time::Instant;

use kdray::denoise::Denoiser;
use kdray::gpu::GpuContext;
use kdray::output::exr::{is_exr_path, write_exr_atomic};
use kdray::output::write_png_atomic;
use kdray::scene::ToneMap;
use kdray::{Error, Result};
use kdray_core::denoise::{DenoiseImages, TilePlan};

#[derive(clap::Args)]
pub struct DenoiseArgs {
    /// The noisy image: OpenEXR, linear HDR colour.
    pub input: PathBuf,
    /// The albedo of the first surfaces seen (OpenEXR, same size; needs --normal).
    #[arg(long, value_name = "A.exr", requires = "normal")]
    pub albedo: Option<PathBuf>,
    /// Their normals, components in [-1, 1] (OpenEXR, same size; needs --albedo).
    #[arg(long, value_name = "N.exr", requires = "albedo")]
    pub normal: Option<PathBuf>,
    /// The colour is HDR: always so (kdray ships OIDN's HDR networks); accepted
    /// as OIDN's example tool takes it.
    #[arg(long)]
    pub hdr: bool,
    /// The denoised image: .exr (linear floats) or .png (ACES, then sRGB).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Print one JSON object of figures on stdout: the set-up (pipelines
    /// compiled and weights uploaded, by denoising a 16 x 16 image first) and
    /// the image's denoise, each in wall-clock milliseconds.
    #[arg(long)]
    pub stats: bool,
}

/// An OpenEXR file's RGB; anything wrong with it (missing, not OpenEXR,
/// truncated) is a usage error naming it.
fn read_exr(path: &Path) -> Result<(usize, usize, Vec<f32>)> {
    if !is_exr_path(path) {
        return Err(Error::Usage(format!(
            "{}: not an OpenEXR file (the denoiser reads .exr)",
            path.display()
        )));
    }
    let bytes = std::fs::read(path)
        .map_err(|e| Error::Usage(format!("{}: cannot read: {e}", path.display())))?;
    // The decoder is another crate's; a file that makes it panic is
    // reported as unreadable like any other bad file.
    let decoded = std::panic::catch_unwind(|| {
        image::load_from_memory_with_format(&bytes, image::ImageFormat::OpenExr)
    });
    let image = match decoded {
        Ok(Ok(image)) => image.to_rgb32f(),
        Ok(Err(e)) => {
            return Err(Error::Usage(format!(
                "{}: not a readable OpenEXR image: {e}",
                path.display()
            )))
        }
        Err(_) => {
            return Err(Error::Usage(format!(
                "{}: not a readable OpenEXR image",
                path.display()
            )))
        }
    };
    Ok((
        image.width() as usize,
        image.height() as usize,
        image.into_raw(),
    ))
}

/// Denoises a 16 x 16 image with the channels of `images` (compiling the
/// pipelines and uploading the network), and drops the result.
fn warm_up(denoiser: &Denoiser, images: &DenoiseImages) -> Result<()> {
    let pixels = vec![0.5f32; 16 * 16 * 3];
    let aux = |a: Option<&[f32]>| a.map(|_| pixels.as_slice());
    let small = DenoiseImages {
        width: 16,
        height: 16,
        color: &pixels,
        albedo: aux(images.albedo),
        normal: aux(images.normal),
    };
    denoiser.denoise(&small, None).map(drop)
}

pub fn denoise(args: DenoiseArgs) -> Result<()> {
    let DenoiseArgs {
        input,
        albedo,
        normal,
        hdr: _,
        output,
        stats,
    } = args;
    let png = output
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("png"));
    if !png && !is_exr_path(&output) {
        return Err(Error::Usage(format!(
            "{}: the output must be .exr or .png",
            output.display()
        )));
    }
    let (width, height, color) = read_exr(&input)?;
    let mut aux = Vec::new();
    for path in albedo.iter().chain(&normal) {
        let (w, h, pixels) = read_exr(path)?;
        if (w, h) != (width, height) {
            return Err(Error::Usage(format!(
                "{}: {w}x{h}, but the colour image {} is {width}x{height}",
                path.display(),
                input.display()
            )));
        }
        aux.push(pixels);
    }
    let images = DenoiseImages {
        width,
        height,
        color: &color,
        albedo: aux.first().map(Vec::as_slice),
        normal: aux.get(1).map(Vec::as_slice),
    };
    let ctx = GpuContext::new()?;
    let started = Instant::now();
    let denoiser = Denoiser::new(&ctx)?;
    if stats {
        // The pipelines compile at their first dispatch: a small image of
        // the same channels first, so the timed denoise is the image's own.
        warm_up(&denoiser, &images)?;
    }
    let set_up = started.elapsed();
    let started = Instant::now();
    let denoised = denoiser.denoise(&images, None)?;
    let denoise_time = started.elapsed();
    let (w, h) = (width as u32, height as u32);
    if stats {
        let limit = kdray::gpu::max_binding_bytes(&ctx.device.limits());
        let plan = TilePlan::new(width, height, images.input_channels(), limit);
        let figures = serde_json::json!({
            "adapter": ctx.info.name,
            "driver": ctx.info.driver_info,
            "width": width,
            "height": height,
            "input_channels": images.input_channels(),
            "tiles": plan.tiles.len(),
            "setup_ms": set_up.as_secs_f64() * 1e3,
            "denoise_ms": denoise_time.as_secs_f64() * 1e3,
        });
        println!("{figures}");
    }
    if png {
        let rgb: Vec<u8> = denoised
            .iter()
            .map(|&v| ToneMap::Aces.to_srgb8(v, 1.0))
            .collect();
        write_png_atomic(&output, w, h, &rgb)
    } else {
        write_exr_atomic(&output, w, h, &denoised)
    }
}
