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
    // The model is the default grey under white lights: its pixels are
    // neutral (r = g = b). The ground is blue-grey, the background a
    // darker blue: neither is neutral.
    let neutral = |[r, g, b]: [i32; 3]| (r - g).abs() <= 2 && (g - b).abs() <= 2 && r > 8;
    let ground_like = |[r, _, b]: [i32; 3]| b > r + 6;
    let (mut count, mut sum_x, mut sum_y) = (0usize, 0usize, 0usize);
    for y in 0..height {
        for x in 0..width {
            if neutral(pixel(x, y)) {
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
