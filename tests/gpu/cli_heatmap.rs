//! `kdray render --heatmap` through the binary: the cost picture beside the
//! image, the walk's counters in `--stats`, `--heatmap-max`'s fixed scale,
//! and its bad flags.

use crate::cli::{kdray, parse_stats, render_args, scene_path, u64_field};
use crate::common;

use common::TempDir;
use kdray::output::read_png_rgb;

fn f64_field(stats: &serde_json::Value, key: &str) -> f64 {
    stats[key]
        .as_f64()
        .unwrap_or_else(|| panic!("{key} is not a number: {stats}"))
}

/// `--heatmap` writes the cost picture beside the image: the image's size
/// plus the bar's rows, not one colour, and `--stats` gains the walk's
/// counters, consistent with each other and with the rays.
#[test]
fn heatmap_writes_the_cost_picture_and_stats_count_the_walk() {
    let dir = TempDir::new("heatmap");
    let mixed = scene_path("mixed.toml");
    let run = kdray(
        &dir.path,
        &render_args(
            &mixed,
            &["-o", "out.png", "--heatmap", "cost.png", "--stats"],
        ),
    );
    let stats = parse_stats(&run);
    let (w, h, _) = read_png_rgb(&dir.join("out.png")).unwrap();
    assert_eq!((w, h), (64, 36));
    let bar = kdray::output::heatmap::BAR_ROWS;
    let (hw, hh, heat) = read_png_rgb(&dir.join("cost.png")).unwrap();
    assert_eq!((hw, hh), (64, 36 + bar));
    let mut colours: Vec<&[u8]> = heat[..64 * 36 * 3].chunks_exact(3).collect();
    colours.sort_unstable();
    colours.dedup();
    assert!(
        colours.len() >= 8,
        "the heatmap is nearly uniform: {colours:?}"
    );
    assert!(dir.temp_files().is_empty(), "{:?}", dir.temp_files());

    let rays = ["primary_rays", "shadow_rays", "reflection_rays"]
        .iter()
        .map(|k| u64_field(&stats, k))
        .sum::<u64>();
    let nodes = u64_field(&stats, "nodes_visited");
    let leaves = u64_field(&stats, "leaves_visited");
    let objects = u64_field(&stats, "objects_tested");
    assert!(0 < leaves && leaves <= nodes, "{stats}");
    assert!(objects > 0, "{stats}");
    for (total, key) in [
        (nodes, "nodes_visited_per_ray"),
        (leaves, "leaves_visited_per_ray"),
        (objects, "objects_tested_per_ray"),
    ] {
        let per_ray = f64_field(&stats, key);
        assert!(
            (per_ray - total as f64 / rays as f64).abs() <= 1e-9 * per_ray,
            "{key}: {stats}"
        );
    }

    // Brute force reads no node; each nearest-hit ray tests every object,
    // a shadow ray stops at its first blocker.
    let run = kdray(
        &dir.path,
        &render_args(&mixed, &["-o", "brute.png", "--accel", "brute", "--stats"]),
    );
    let brute = parse_stats(&run);
    let n = u64_field(&brute, "spheres") + u64_field(&brute, "triangles");
    let nearest_rays = u64_field(&brute, "primary_rays") + u64_field(&brute, "reflection_rays");
    let shadow_rays = u64_field(&brute, "shadow_rays");
    assert_eq!(u64_field(&brute, "nodes_visited"), 0, "{brute}");
    assert_eq!(u64_field(&brute, "leaves_visited"), 0, "{brute}");
    let tested = u64_field(&brute, "objects_tested");
    assert!(
        (n * nearest_rays..=n * (nearest_rays + shadow_rays)).contains(&tested),
        "{tested} objects tested, {n} objects: {brute}"
    );
    // Without --stats or --heatmap nothing is counted or printed.
    let run = kdray(&dir.path, &render_args(&mixed, &["-o", "plain.png"]));
    assert_eq!((run.code, run.stdout.as_str()), (0, ""), "{run:#?}");
}

/// `--heatmap-max` fixes the scale: with a top of 1 every pixel that did any
/// work shows the top colour, the others the bottom one.
#[test]
fn heatmap_max_fixes_the_scale() {
    let dir = TempDir::new("heatmap-max");
    let mixed = scene_path("mixed.toml");
    let run = kdray(
        &dir.path,
        &render_args(
            &mixed,
            &[
                "-o",
                "out.png",
                "--heatmap",
                "cost.png",
                "--heatmap-max",
                "1",
            ],
        ),
    );
    assert_eq!(run.code, 0, "{run:#?}");
    let (_, _, heat) = read_png_rgb(&dir.join("cost.png")).unwrap();
    let (bottom, top) = (
        kdray::output::heatmap::colour(0.0),
        kdray::output::heatmap::colour(1.0),
    );
    let pixels: Vec<&[u8]> = heat[..64 * 36 * 3].chunks_exact(3).collect();
    assert!(pixels.iter().all(|p| *p == bottom || *p == top));
    assert!(pixels.iter().any(|p| *p == top));
}

/// Bad heatmap flags are usage errors (exit 2, one line naming the flag,
/// nothing written); an unwritable heatmap path exits 1 and leaves no image.
#[test]
fn bad_heatmap_flags_exit_2_and_write_nothing() {
    let dir = TempDir::new("heatmap-usage");
    let seed = scene_path("seed.toml");
    for (extra, flag) in [
        (vec!["--heatmap-max", "10"], "--heatmap"),
        (
            vec!["--heatmap", "cost.png", "--heatmap-max", "0"],
            "--heatmap-max",
        ),
        (
            vec!["--heatmap", "cost.png", "--heatmap-max", "x"],
            "--heatmap-max",
        ),
        (vec!["--heatmap", "out.png"], "--heatmap"),
    ] {
        let mut args = vec!["-o", "out.png"];
        args.extend(&extra);
        let run = kdray(&dir.path, &render_args(&seed, &args));
        assert_eq!(run.code, 2, "{extra:?}: {run:#?}");
        assert!(!run.panicked(), "{run:#?}");
        assert!(
            run.stderr.iter().any(|l| l.contains(flag)),
            "{extra:?}: {run:#?}"
        );
        assert!(
            std::fs::read_dir(&dir.path).unwrap().next().is_none(),
            "{extra:?} wrote {:?}",
            dir.temp_files()
        );
    }
    let target = "/nonexistent-kdray-dir/cost.png";
    let run = kdray(
        &dir.path,
        &render_args(&seed, &["-o", "out.png", "--heatmap", target]),
    );
    assert_eq!(run.code, 1, "{run:#?}");
    assert!(run.one_error_line().contains(target), "{run:#?}");
    assert!(!dir.join("out.png").exists());
    assert!(dir.temp_files().is_empty(), "{:?}", dir.temp_files());
}
