//! Renders a scene file into an RGB image in memory through the library:
//! load the scene, open the GPU, render, and (when asked) save a PNG.
//!
//! ```sh
//! cargo run --release --example render_to_image -- [SCENE [OUT.png [WIDTH]]]
//! ```
//!
//! SCENE defaults to scenes/seed.toml; without OUT.png the example prints the
//! image's size and mean colour. WIDTH (pixels) overrides the scene's width
//! and keeps its aspect ratio. tests/gpu/examples.rs calls [`render`] and
//! compares the image with a golden one.

use std::path::{Path, PathBuf};

use image::RgbImage;
use kdray::gpu::{Accel, GpuContext, TilePlan};

/// Loads the scene file at `path` and renders it on `gpu` with the k-d
/// tree, `width` pixels wide when given (the height follows the scene's
/// aspect ratio), into an 8-bit RGB image.
pub fn render(gpu: &GpuContext, path: &Path, width: Option<u32>) -> kdray::Result<RgbImage> {
    let mut scene = kdray::scene::load_scene(path)?;
    if let Some(width) = width {
        let aspect = scene.render.height as f64 / scene.render.width as f64;
        scene.render.width = width;
        scene.render.height = ((width as f64 * aspect).round() as u32).max(1);
    }
    let (image, _stats) = kdray::render::render_scene(
        gpu,
        &scene,
        Accel::Kdtree,
        TilePlan::DEFAULT_MAX_TILE_PIXELS,
    )?;
    let (width, height) = (image.width, image.height);
    Ok(RgbImage::from_raw(width, height, image.rgb)
        .expect("the renderer returns width x height RGB pixels"))
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let scene = args
        .next()
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/seed.toml"));
    let output = args.next().map(PathBuf::from);
    let width = args.next().map(|w| w.parse::<u32>()).transpose()?;

    let gpu = GpuContext::new()?;
    let image = render(&gpu, &scene, width)?;
    match output {
        Some(path) => {
            image.save(&path)?;
            println!(
                "{}: {}x{} pixels",
                path.display(),
                image.width(),
                image.height()
            );
        }
        None => {
            let pixels = image.pixels().len() as f64;
            let mut mean = [0.0f64; 3];
            for pixel in image.pixels() {
                for (sum, channel) in mean.iter_mut().zip(pixel.0) {
                    *sum += channel as f64 / pixels;
                }
            }
            println!(
                "{}: {}x{} pixels, mean colour {:.1} {:.1} {:.1} (of 255)",
                scene.display(),
                image.width(),
                image.height(),
                mean[0],
                mean[1],
                mean[2]
            );
        }
    }
    Ok(())
}
