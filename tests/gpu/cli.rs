//! End-to-end tests of the `kdray` binary: exit codes, the `--stats` JSON,
//! the output's path, an unwritable output, adapter choice; and the helpers
//! the other `cli_*` modules run it with (bad input: cli_bad_input.rs; the
//! cost heatmap: cli_heatmap.rs; animations: cli_animation.rs).
//!
//! Every test runs the built binary in a fresh temporary folder at a small
//! image size.

use std::path::Path;

use crate::common;

use common::{run_kdray, Run, TempDir};
use kdray::output::read_png_rgb;

/// Runs `kdray ARGS` in `dir` with extra environment variables.
pub(crate) fn kdray_env(dir: &Path, args: &[&str], env: &[(&str, &str)]) -> Run {
    run_kdray(dir, args, env)
}

pub(crate) fn kdray(dir: &Path, args: &[&str]) -> Run {
    kdray_env(dir, args, &[])
}

pub(crate) fn scene_path(name: &str) -> String {
    format!("{}/scenes/{name}", env!("CARGO_MANIFEST_DIR"))
}

pub(crate) const SMALL: [&str; 4] = ["--width", "64", "--height", "36"];

/// `render SCENE` at the small size, followed by `extra`.
pub(crate) fn render_args<'a>(scene: &'a str, extra: &[&'a str]) -> Vec<&'a str> {
    let mut args = vec!["render", scene];
    args.extend(SMALL);
    args.extend(extra);
    args
}

pub(crate) fn parse_stats(run: &Run) -> serde_json::Value {
    assert_eq!(run.code, 0, "{run:#?}");
    assert!(run.stdout.ends_with('\n'), "{run:#?}");
    assert_eq!(run.stdout.lines().count(), 1, "stdout: {:?}", run.stdout);
    serde_json::from_str(run.stdout.trim_end()).expect("stdout is not JSON")
}

pub(crate) fn u64_field(stats: &serde_json::Value, key: &str) -> u64 {
    stats[key]
        .as_u64()
        .unwrap_or_else(|| panic!("{key} is not an unsigned integer: {stats}"))
}

#[test]
fn render_with_stats_writes_png_and_one_json_line() {
    let dir = TempDir::new("stats");
    let seed = scene_path("seed.toml");
    let run = kdray(
        &dir.path,
        &render_args(&seed, &["-o", "out.png", "--stats"]),
    );
    let stats = parse_stats(&run);
    for key in [
        "adapter",
        "backend",
        "width",
        "height",
        "samples",
        "spheres",
        "triangles",
        "kd_nodes",
        "kd_leaves",
        "kd_max_depth",
        "kd_refs_per_leaf",
        "build_ms",
        "upload_ms",
        "gpu_ms",
        "total_ms",
        "primary_rays",
        "mrays_per_s",
    ] {
        assert!(stats.get(key).is_some(), "no {key} in {stats}");
    }
    assert!(stats["adapter"].is_string() && stats["backend"].is_string());
    assert_eq!(u64_field(&stats, "width"), 64);
    assert_eq!(u64_field(&stats, "height"), 36);
    assert_eq!(u64_field(&stats, "samples"), 1);
    assert_eq!(u64_field(&stats, "spheres"), 4);
    assert_eq!(u64_field(&stats, "triangles"), 0);
    assert_eq!(u64_field(&stats, "primary_rays"), 64 * 36);
    assert!(stats["gpu_ms"].as_f64().unwrap() > 0.0, "{stats}");

    let (w, h, rgb) = read_png_rgb(&dir.join("out.png")).unwrap();
    assert_eq!((w, h), (64, 36));
    assert_eq!(rgb.len(), 64 * 36 * 3);
    assert!(dir.temp_files().is_empty(), "{:?}", dir.temp_files());
}

#[test]
fn default_output_is_scene_stem_in_current_folder() {
    let dir = TempDir::new("default-output");
    let seed = scene_path("seed.toml");
    let run = kdray(&dir.path, &render_args(&seed, &[]));
    assert_eq!(run.code, 0, "{run:#?}");
    assert!(
        run.stdout.is_empty(),
        "no --stats, yet stdout: {:?}",
        run.stdout
    );
    let (w, h, _) = read_png_rgb(&dir.join("seed.png")).unwrap();
    assert_eq!((w, h), (64, 36));
    assert!(dir.temp_files().is_empty(), "{:?}", dir.temp_files());
}

#[test]
fn samples_flag_is_used_and_checked() {
    let dir = TempDir::new("samples");
    let seed = scene_path("seed.toml");
    let run = kdray(
        &dir.path,
        &render_args(&seed, &["-o", "out.png", "--stats", "--samples", "4"]),
    );
    let stats = parse_stats(&run);
    assert_eq!(u64_field(&stats, "samples"), 4);
    assert_eq!(u64_field(&stats, "primary_rays"), 64 * 36 * 4);

    let run = kdray(
        &dir.path,
        &render_args(&seed, &["-o", "bad.png", "--samples", "3"]),
    );
    assert_eq!(run.code, 2, "{run:#?}");
    assert!(run.one_error_line().contains("--samples"), "{run:#?}");
    assert!(!dir.join("bad.png").exists());
}

#[test]
fn unwritable_output_exits_1_without_panic() {
    let dir = TempDir::new("unwritable");
    let seed = scene_path("seed.toml");
    let target = "/nonexistent-kdray-dir/x.png";
    let run = kdray(&dir.path, &render_args(&seed, &["-o", target]));
    assert_eq!(run.code, 1, "{run:#?}");
    let line = run.one_error_line();
    assert!(line.contains(target), "{line}");
    assert!(!Path::new(target).exists());
}

#[test]
fn info_lists_adapters_and_marks_the_chosen_one() {
    let dir = TempDir::new("info");
    let run = kdray(&dir.path, &["info"]);
    assert_eq!(run.code, 0, "{run:#?}");
    let adapters: Vec<&str> = run
        .stdout
        .lines()
        .filter(|l| l.starts_with("* ") || l.starts_with("  "))
        .collect();
    assert!(!adapters.is_empty(), "no adapter lines: {:?}", run.stdout);
    let chosen = adapters.iter().filter(|l| l.starts_with("* ")).count();
    assert_eq!(chosen, 1, "want one chosen adapter: {:?}", run.stdout);
}

#[test]
fn absent_backend_exits_1_and_says_what_to_install() {
    let dir = TempDir::new("no-backend");
    let seed = scene_path("seed.toml");
    let run = kdray_env(
        &dir.path,
        &render_args(&seed, &["-o", "out.png"]),
        &[("WGPU_BACKEND", "metal")],
    );
    assert_eq!(run.code, 1, "{run:#?}");
    let line = run.one_error_line();
    assert!(line.contains("mesa-vulkan-drivers"), "{line}");
    assert!(!dir.join("out.png").exists());
    assert!(dir.temp_files().is_empty(), "{:?}", dir.temp_files());
}

/// Brute force, the SAH tree, the binned one and the seed's median tree
/// (`--build median`) give the same pixels.
#[test]
fn brute_force_and_kdtree_images_agree() {
    let dir = TempDir::new("accel");
    let mixed = scene_path("mixed.toml");
    let mut images = Vec::new();
    for (name, flags) in [
        ("brute", ["--accel", "brute", "--build", "sah"]),
        ("sah", ["--accel", "kdtree", "--build", "sah"]),
        ("binned", ["--accel", "kdtree", "--build", "binned"]),
        ("median", ["--accel", "kdtree", "--build", "median"]),
    ] {
        let png = format!("{name}.png");
        let mut args = vec![
            "render", &mixed, "-o", &png, "--width", "64", "--height", "48",
        ];
        args.extend(flags);
        let run = kdray(&dir.path, &args);
        assert_eq!(run.code, 0, "{name}: {run:#?}");
        let (w, h, rgb) = read_png_rgb(&dir.join(&png)).unwrap();
        assert_eq!((w, h), (64, 48));
        images.push((name, rgb));
    }
    for (name, rgb) in &images[1..] {
        assert!(
            *rgb == images[0].1,
            "{name}: the PNG's pixels differ from brute force's"
        );
    }
    let run = kdray(
        &dir.path,
        &["render", &mixed, "-o", "x.png", "--build", "fastest"],
    );
    assert_eq!(run.code, 2, "{run:#?}");
    assert!(run.stderr.join("\n").contains("median"), "{:?}", run.stderr);
    assert!(!dir.join("x.png").exists());
}

/// On a headless machine without `XDG_RUNTIME_DIR` (or with a relative one,
/// which libwayland calls invalid), Mesa's Vulkan device-selection layer
/// makes libwayland print `error: XDG_RUNTIME_DIR is invalid or not set in
/// the environment.` unless kdray gives Mesa a private runtime folder first.
/// Runs the binary directly: `run_kdray` sets the variable and hides that
/// line.
#[test]
fn render_and_info_print_no_xdg_runtime_dir_error_without_the_variable() {
    let dir = TempDir::new("xdg");
    let seed = scene_path("seed.toml");
    let render = render_args(&seed, &["-o", "out.png"]);
    for value in [None, Some("relative/runtime")] {
        for args in [&render[..], &["info"][..]] {
            let mut command = std::process::Command::new(env!("CARGO_BIN_EXE_kdray"));
            command
                .args(args)
                .current_dir(&dir.path)
                // The private folder goes here, not in the shared /tmp.
                .env("TMPDIR", &dir.path)
                .env_remove("XDG_RUNTIME_DIR");
            if let Some(value) = value {
                command.env("XDG_RUNTIME_DIR", value);
            }
            let out = command.output().expect("cannot run kdray");
            let stderr = String::from_utf8_lossy(&out.stderr);
            assert!(
                out.status.success(),
                "kdray {args:?} (XDG_RUNTIME_DIR={value:?}): {stderr}"
            );
            assert!(
                !stderr.contains("XDG_RUNTIME_DIR"),
                "kdray {args:?} (XDG_RUNTIME_DIR={value:?}) printed:\n{stderr}"
            );
        }
    }
    assert!(dir.join("out.png").exists());
}

/// `--stats` names the textures' share of the scene's buffers: none for
/// the seed; for scenes/textured.toml its one 64 x 64 image and its mip
/// levels down to 1 x 1 (a word a texel), the header word and one 7-word
/// texture header, its level table (7 levels of 3 words), and the two
/// floor triangles' texture coordinates (6 words each).
#[test]
fn stats_count_the_texture_bytes() {
    let dir = TempDir::new("texture-bytes");
    let texels = 64 * 64 + 32 * 32 + 16 * 16 + 8 * 8 + 4 * 4 + 2 * 2 + 1;
    // The prefix, one texture's header and level table, two records.
    let textured_words = texels + 5 + 7 + 7 * 3 + 2 * 6;
    for (scene, words) in [("seed.toml", 0), ("textured.toml", textured_words)] {
        let path = scene_path(scene);
        let run = kdray(
            &dir.path,
            &render_args(&path, &["-o", "out.png", "--stats"]),
        );
        let stats = parse_stats(&run);
        assert_eq!(u64_field(&stats, "texture_bytes"), words * 4, "{scene}");
        assert!(u64_field(&stats, "gpu_scene_bytes") > words * 4, "{scene}");
    }
}
