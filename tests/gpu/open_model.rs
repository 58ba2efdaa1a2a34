//! A model file given to the `kdray` binary in place of a scene file
//! (`kdray render bunny.obj`) renders as a scene of its own: the model framed
//! in the middle of the image, standing on a ground plane.

use std::path::Path;

use crate::common;

use common::{run_kdray, TempDir};
use kdray::output::read_png_rgb;

/// The Stanford bunny of Debian's glmark2-data (scripts/test.sh installs
/// it; scenes/bunny.toml uses it too). It has no usemtl, so it is drawn in
/// the default grey, with one warning.
const BUNNY: &str = "/usr/share/glmark2/models/bunny.obj";

/// Whether a pixel is the bunny's: the default grey under the rig's white
/// lights is neutral (r = g = b) in the Whitted view, and not black.
fn model_grey([r, g, b]: [i32; 3]) -> bool {
    (r - g).abs() <= 2 && (g - b).abs() <= 2 && r > 8
}

#[test]
fn rendering_a_model_file_frames_it_in_the_middle_on_a_ground_plane() {
    assert!(
        Path::new(BUNNY).exists(),
        "{BUNNY} is missing: apt-get install glmark2-data"
    );
    let dir = TempDir::new("open-model");
    let (width, height) = (96usize, 72usize);
    let run = run_kdray(
        &dir.path,
        &[
            "render",
            BUNNY,
            "--width",
            &width.to_string(),
            "--height",
            &height.to_string(),
            "-o",
            "bunny.png",
        ],
        &[],
    );
    assert_eq!(run.code, 0, "{run:#?}");
    // The one warning: its faces have no material.
    let warnings: Vec<&String> = run
        .stderr
        .iter()
        .filter(|l| l.contains("warning:"))
        .collect();
    assert_eq!(warnings.len(), 1, "{run:#?}");
    assert!(
        warnings[0].starts_with(&format!("{BUNNY}:")),
        "{}",
        warnings[0]
    );
    assert!(warnings[0].contains("default grey"), "{}", warnings[0]);

    let (w, h, rgb) = read_png_rgb(&dir.path.join("bunny.png")).unwrap();
    assert_eq!((w as usize, h as usize), (width, height));
    let pixel = |x: usize, y: usize| {
        let i = 3 * (y * width + x);
        [rgb[i], rgb[i + 1], rgb[i + 2]].map(i32::from)
    };
    // The ground is blue-grey, the background a darker blue: neither is
    // the model's neutral grey.
    let ground_like = |[r, _, b]: [i32; 3]| b > r + 6;
    let (mut count, mut sum_x, mut sum_y) = (0usize, 0usize, 0usize);
    for y in 0..height {
        for x in 0..width {
            if model_grey(pixel(x, y)) {
                count += 1;
                sum_x += x;
                sum_y += y;
            }
        }
    }
    // Not blank: the bunny covers a good part of the image.
    let area = width * height;
    assert!(count > area / 20, "only {count} model pixels of {area}");
    assert!(
        count < area * 3 / 4,
        "{count} model pixels of {area}: not a model"
    );
    // Centred: the model pixels' centroid lies near the middle.
    let (cx, cy) = (sum_x as f64 / count as f64, sum_y as f64 / count as f64);
    let (mx, my) = (width as f64 / 2.0, height as f64 / 2.0);
    assert!(
        (cx - mx).abs() < 0.15 * width as f64 && (cy - my).abs() < 0.15 * height as f64,
        "model centroid ({cx:.1}, {cy:.1}), image centre ({mx}, {my})"
    );
    // The ground: the bottom rows, below the model, are mostly ground.
    let bottom: Vec<[i32; 3]> = (height - 4..height)
        .flat_map(|y| (0..width).map(move |x| (x, y)))
        .map(|(x, y)| pixel(x, y))
        .collect();
    let ground = bottom.iter().filter(|&&p| ground_like(p)).count();
    assert!(
        ground > bottom.len() / 2,
        "{ground} of {} bottom pixels are ground",
        bottom.len()
    );
}

/// `render MODEL --integrator INTEGRATOR -o OUT` at 96x72, 16 samples.
fn render_model(dir: &Path, model: &str, integrator: &str, out: &str) {
    let run = run_kdray(
        dir,
        &[
            "render",
            model,
            "--integrator",
            integrator,
            "--samples",
            "16",
            "--width",
            "96",
            "--height",
            "72",
            "-o",
            out,
        ],
        &[],
    );
    assert_eq!(run.code, 0, "{run:#?}");
}

/// The mean radiance (over r, g and b) of `render MODEL --integrator
/// INTEGRATOR` over the pixels of `mask`, from its EXR output.
fn model_radiance(dir: &Path, model: &str, integrator: &str, mask: &[bool]) -> f64 {
    let out = format!("{integrator}.exr");
    render_model(dir, model, integrator, &out);
    let (_, _, rgb) = kdray::output::exr::read_exr_rgb(&dir.join(&out)).unwrap();
    let picked: Vec<f64> = rgb
        .chunks_exact(3)
        .zip(mask)
        .filter(|(_, &m)| m)
        .map(|(p, _)| p.iter().map(|&x| x as f64).sum::<f64>() / 3.0)
        .collect();
    picked.iter().sum::<f64>() / picked.len() as f64
}

/// A model opened on its own and path traced is lit as the Whitted
/// integrator lights it: the rig's lights, which fall off in the path
/// tracer, carry their distance to the model as their reference distance.
/// So the model's radiance is about the same in the two integrators (the
/// path tracer adds the light the ground bounces and leaves out the
/// Whitted ambient term), and the path-traced model is the same at a
/// thousand times the size.
#[test]
fn a_model_path_traced_is_lit_like_the_whitted_view_at_any_scale() {
    assert!(
        Path::new(BUNNY).exists(),
        "{BUNNY} is missing: apt-get install glmark2-data"
    );
    let dir = TempDir::new("open-model-path");
    // The model's pixels: neutral grey in the Whitted view.
    render_model(&dir.path, BUNNY, "whitted", "mask.png");
    let (_, _, rgb) = read_png_rgb(&dir.path.join("mask.png")).unwrap();
    let mask: Vec<bool> = rgb
        .chunks_exact(3)
        .map(|p| model_grey([p[0], p[1], p[2]].map(i32::from)))
        .collect();
    assert!(mask.iter().filter(|&&m| m).count() > 96 * 72 / 20);
    let whitted = model_radiance(&dir.path, BUNNY, "whitted", &mask);
    let path = model_radiance(&dir.path, BUNNY, "path", &mask);
    let ratio = path / whitted;
    assert!(
        (0.6..1.6).contains(&ratio),
        "the path-traced model's radiance {path:.3} against the Whitted view's {whitted:.3}"
    );
    // The bunny a thousand times larger: the rig scales with it.
    let text = std::fs::read_to_string(BUNNY).unwrap();
    let scaled: String = text
        .lines()
        .map(|line| match line.strip_prefix("v ") {
            Some(xyz) => {
                let v: Vec<String> = xyz
                    .split_whitespace()
                    .map(|x| (x.parse::<f64>().unwrap() * 1000.0).to_string())
                    .collect();
                format!("v {}\n", v.join(" "))
            }
            None => format!("{line}\n"),
        })
        .collect();
    let big = dir.path.join("big.obj");
    std::fs::write(&big, scaled).unwrap();
    let big_path = model_radiance(&dir.path, big.to_str().unwrap(), "path", &mask);
    assert!(
        (big_path - path).abs() < 0.02 * path,
        "the bunny at a thousand times the size: {big_path:.3}, at its own: {path:.3}"
    );
}
