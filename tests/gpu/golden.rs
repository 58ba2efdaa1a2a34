//! Golden images: every scene in scenes/ rendered small and compared with
//! tests/golden/<scene>.png by FLIP and a per-pixel budget. A missing golden
//! is a failure; `KDRAY_BLESS=1 cargo test --test golden` rewrites them.
//! On failure the actual image and a difference image land in
//! target/test-failures/.

use crate::common;

use common::*;
use kdray::gpu::Accel;
use kdray::output::{read_png_rgb, write_png_atomic};

/// Mean FLIP error allowed against the golden image.
const MAX_MEAN_FLIP: f32 = 0.01;
/// Pixels allowed to differ by more than 2 levels: 0.1% of the image.
const MAX_PIXELS_OVER_PER_MILLE: usize = 1;

#[test]
fn every_scene_matches_its_golden_image() {
    let bless = std::env::var_os("KDRAY_BLESS").is_some_and(|v| v == "1");
    let mut failures = Vec::new();
    for path in shipped_scenes() {
        let name = path.file_stem().unwrap().to_string_lossy().into_owned();
        let scene = small_scene(&path);
        let image = render(&scene, Accel::Kdtree);
        let golden_path = repo_path(&format!("tests/golden/{name}.png"));
        if bless {
            write_png_atomic(&golden_path, image.width, image.height, &image.rgb).unwrap();
            continue;
        }
        let (w, h, golden) = match read_png_rgb(&golden_path) {
            Ok(g) => g,
            Err(e) => {
                failures.push(format!("{name}: no golden image ({e}); run KDRAY_BLESS=1 cargo test --test golden and look at it"));
                continue;
            }
        };
        if (w, h) != (image.width, image.height) {
            failures.push(format!(
                "{name}: golden is {w}x{h}, render is {}x{}",
                image.width, image.height
            ));
            continue;
        }
        let d = compare(&golden, &image.rgb, w, h, 2);
        let budget = (w * h) as usize * MAX_PIXELS_OVER_PER_MILLE / 1000;
        if d.mean_flip > MAX_MEAN_FLIP || d.pixels_over > budget {
            let dir = failure_dir();
            write_png_atomic(&dir.join(format!("{name}-actual.png")), w, h, &image.rgb).unwrap();
            write_png_atomic(
                &dir.join(format!("{name}-diff.png")),
                w,
                h,
                &difference_image(&golden, &image.rgb),
            )
            .unwrap();
            failures.push(format!(
                "{name}: {d:?} (budget: FLIP {MAX_MEAN_FLIP}, {budget} pixels); see {}",
                dir.display()
            ));
        }
    }
    assert!(
        failures.is_empty(),
        "golden images differ:\n{}",
        failures.join("\n")
    );
}
