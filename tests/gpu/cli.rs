//! End-to-end tests of the `kdray` binary: exit codes, the `--stats` JSON,
//! one-line errors naming file, line and key, atomic output, adapter choice.
//!
//! Every test runs the built binary in a fresh temporary folder at a small
//! image size.

use std::path::Path;

use crate::common;

use common::{run_kdray, Run, TempDir};
use kdray::output::read_png_rgb;

/// Runs `kdray ARGS` in `dir` with extra environment variables.
fn kdray_env(dir: &Path, args: &[&str], env: &[(&str, &str)]) -> Run {
    run_kdray(dir, args, env)
}

fn kdray(dir: &Path, args: &[&str]) -> Run {
    kdray_env(dir, args, &[])
}

fn scene_path(name: &str) -> String {
    format!("{}/scenes/{name}", env!("CARGO_MANIFEST_DIR"))
}

const SMALL: [&str; 4] = ["--width", "64", "--height", "36"];

/// `render SCENE` at the small size, followed by `extra`.
fn render_args<'a>(scene: &'a str, extra: &[&'a str]) -> Vec<&'a str> {
    let mut args = vec!["render", scene];
    args.extend(SMALL);
    args.extend(extra);
    args
}

fn parse_stats(run: &Run) -> serde_json::Value {
    assert_eq!(run.code, 0, "{run:#?}");
    assert!(run.stdout.ends_with('\n'), "{run:#?}");
    assert_eq!(run.stdout.lines().count(), 1, "stdout: {:?}", run.stdout);
    serde_json::from_str(run.stdout.trim_end()).expect("stdout is not JSON")
}

fn u64_field(stats: &serde_json::Value, key: &str) -> u64 {
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
fn out_of_range_size_and_bad_accel_are_usage_errors() {
    let dir = TempDir::new("usage");
    let seed = scene_path("seed.toml");
    for width in ["0", "16385"] {
        let run = kdray(
            &dir.path,
            &[
                "render", &seed, "-o", "out.png", "--width", width, "--height", "36",
            ],
        );
        assert_eq!(run.code, 2, "--width {width}: {run:#?}");
        let line = run.one_error_line();
        assert!(line.contains("--width"), "{line}");
        assert!(line.contains(width), "{line}");
    }
    let run = kdray(
        &dir.path,
        &render_args(&seed, &["-o", "out.png", "--accel", "nonsense"]),
    );
    assert_eq!(run.code, 2, "{run:#?}");
    assert!(!run.panicked(), "{run:#?}");
    assert!(!dir.join("out.png").exists());
}

/// A small valid scene; the cases below each break one part of it.
const BASE_SCENE: &str = r#"[camera]
position = [0.0, 0.0, 3.0]
look_at  = [0.0, 0.0, 0.0]

[[lights]]
position = [2.0, 2.0, 2.0]

[materials.red]
diffuse = [0.8, 0.1, 0.1]

[[spheres]]
center   = [0.0, 0.0, 0.0]
radius   = 1.0
material = "red"
"#;

const BASE_JSON: &str = r#"{
  "camera": { "position": [0.0, 0.0, 3.0], "look_at": [0.0, 0.0, 0.0] },
  "lights": [ { "position": [2.0, 2.0, 2.0] } ],
  "materials": { "red": { "diffuse": [0.8, 0.1, 0.1] } },
  "spheres": [
    {
      "center": [0.0, 0.0, 0.0],
      "radius": 1.0,
      "material": "red"
    }
  ]
}
"#;

/// `BASE_SCENE` with `from` replaced by `to` (which must occur).
fn base_with(from: &str, to: &str) -> String {
    assert!(BASE_SCENE.contains(from), "{from:?} not in the base scene");
    BASE_SCENE.replacen(from, to, 1)
}

/// 1-based line of the first line of `text` containing `needle`.
fn line_of(text: &str, needle: &str) -> usize {
    text.lines()
        .position(|l| l.contains(needle))
        .unwrap_or_else(|| panic!("{needle:?} not in {text}"))
        + 1
}

struct BadScene {
    name: &'static str,
    /// None: the file does not exist.
    text: Option<String>,
    /// The line of the fault, found by this text in the scene.
    line_of: Option<&'static str>,
    /// Further text the error line must contain (keys, file names).
    mentions: &'static [&'static str],
    /// The error is about another file (an OBJ) and names the scene's line
    /// in a trailing note, `(from KEY in SCENE:LINE)`, not as `SCENE:LINE:`.
    line_in_note: bool,
}

#[test]
fn bad_scenes_exit_2_with_one_line_and_leave_output_alone() {
    let dir = TempDir::new("bad-scenes");
    let cases = [
        BadScene {
            name: "missing.toml",
            text: None,
            line_of: None,
            mentions: &[],
            line_in_note: false,
        },
        BadScene {
            name: "malformed.toml",
            text: Some(base_with("radius   = 1.0", "radius   = = 1.0")),
            line_of: Some("radius"),
            mentions: &[],
            line_in_note: false,
        },
        BadScene {
            name: "unknown_key.toml",
            text: Some(base_with("radius   = 1.0", "radius   = 1.0\ncolour   = 3")),
            line_of: Some("colour"),
            mentions: &["spheres[0].colour"],
            line_in_note: false,
        },
        BadScene {
            name: "negative_radius.toml",
            text: Some(base_with("radius   = 1.0", "radius   = -1.0")),
            line_of: Some("radius"),
            mentions: &["spheres[0].radius"],
            line_in_note: false,
        },
        BadScene {
            name: "unknown_material.toml",
            text: Some(base_with("material = \"red\"", "material = \"blue\"")),
            line_of: Some("\"blue\""),
            mentions: &["spheres[0].material", "blue"],
            line_in_note: false,
        },
        BadScene {
            name: "nan.toml",
            text: Some(base_with("radius   = 1.0", "radius   = nan")),
            line_of: Some("nan"),
            mentions: &["spheres[0].radius"],
            line_in_note: false,
        },
        BadScene {
            name: "samples.toml",
            text: Some(format!("{BASE_SCENE}\n[render]\nsamples = 3\n")),
            line_of: Some("samples"),
            mentions: &["render.samples"],
            line_in_note: false,
        },
        BadScene {
            name: "missing_obj.toml",
            text: Some(format!(
                "{BASE_SCENE}\n[[meshes]]\npath = \"no-such-mesh.obj\"\nmaterial = \"red\"\n"
            )),
            line_of: Some("no-such-mesh.obj"),
            mentions: &["no-such-mesh.obj", "meshes[0].path"],
            line_in_note: true,
        },
        BadScene {
            name: "unknown_shape.toml",
            text: Some(format!(
                "{BASE_SCENE}\n[shapes.tri]\ntriangles = [[[0, 0, 0], [1, 0, 0], [0, 1, 0]]]\nmaterial = \"red\"\n[[instances]]\nshape = \"tree\"\n"
            )),
            line_of: Some("\"tree\""),
            mentions: &["instances[0].shape", "tree"],
            line_in_note: false,
        },
        BadScene {
            name: "singular_instance.toml",
            text: Some(format!(
                "{BASE_SCENE}\n[shapes.tri]\ntriangles = [[[0, 0, 0], [1, 0, 0], [0, 1, 0]]]\nmaterial = \"red\"\n[[instances]]\nshape = \"tri\"\nmatrix = [[1, 0, 0, 0], [1, 0, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]\n"
            )),
            line_of: Some("matrix"),
            mentions: &["instances[0].matrix", "singular"],
            line_in_note: false,
        },
        BadScene {
            name: "wrong_type.json",
            text: Some(BASE_JSON.replacen("\"radius\": 1.0", "\"radius\": \"big\"", 1)),
            line_of: Some("\"big\""),
            mentions: &["spheres[0].radius"],
            line_in_note: false,
        },
    ];

    let out = dir.join("out.png");
    let original = b"not a PNG, and must stay as it is".to_vec();
    std::fs::write(&out, &original).unwrap();
    for case in cases {
        let scene = match &case.text {
            Some(text) => dir.write(case.name, text),
            None => dir.join(case.name),
        };
        let scene = scene.to_str().unwrap();
        let run = kdray(&dir.path, &render_args(scene, &["-o", "out.png"]));
        assert_eq!(run.code, 2, "{}: {run:#?}", case.name);
        let line = run.one_error_line();
        assert!(
            line.contains(scene),
            "{}: no scene path in {line}",
            case.name
        );
        if let (Some(text), Some(needle)) = (&case.text, case.line_of) {
            let n = line_of(text, needle);
            let want = if case.line_in_note {
                format!("{scene}:{n})")
            } else {
                format!("{scene}:{n}:")
            };
            assert!(line.contains(&want), "{}: want {want} in {line}", case.name);
        }
        for m in case.mentions {
            assert!(line.contains(m), "{}: want {m} in {line}", case.name);
        }
        assert_eq!(std::fs::read(&out).unwrap(), original, "{}", case.name);
        assert!(
            dir.temp_files().is_empty(),
            "{}: {:?}",
            case.name,
            dir.temp_files()
        );
    }
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

/// Mesh files that cannot be drawn (binary data, no faces, a cut or corrupt
/// glTF, an unknown extension, a buffer outside the folder) are errors that
/// name the mesh file, never an empty mesh and a picture without the model.
#[test]
fn bad_mesh_files_exit_2_with_one_line_and_write_nothing() {
    let dir = TempDir::new("bad-meshes");
    let models = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/models");
    let glb = std::fs::read(models.join("tetra.glb")).unwrap();
    let external = std::fs::read_to_string(models.join("tetra_external.gltf")).unwrap();
    let binary: Vec<u8> = (0..=255).collect();
    let files: [(&str, Vec<u8>, &str); 8] = [
        ("binary.glb", binary.clone(), "not a valid glTF 2.0 file"),
        ("binary.obj", binary, "not a text OBJ file"),
        ("empty.obj", Vec::new(), "no faces"),
        (
            "points.obj",
            b"v 0 0 0\nv 1 0 0\nv 0 1 0\n".to_vec(),
            "no faces",
        ),
        ("cut.glb", glb[..600].to_vec(), "truncated GLB"),
        (
            "corrupt.gltf",
            b"{\"asset\": ".to_vec(),
            "not a valid glTF 2.0 file",
        ),
        (
            "model.ply",
            b"ply\n".to_vec(),
            "unknown mesh file extension",
        ),
        (
            "outside.gltf",
            external
                .replace("tetra.bin", "../../no/such/tetra.bin")
                .into_bytes(),
            "buffer 0: cannot read",
        ),
    ];
    for (name, bytes, words) in files {
        std::fs::write(dir.join(name), &bytes).unwrap();
        let scene = dir.write(
            "scene.toml",
            &format!("{BASE_SCENE}\n[[meshes]]\npath = \"{name}\"\nmaterial = \"red\"\n"),
        );
        let run = kdray(
            &dir.path,
            &render_args(scene.to_str().unwrap(), &["-o", "out.png"]),
        );
        assert_eq!(run.code, 2, "{name}: {run:#?}");
        let line = run.one_error_line();
        let file = dir.join(name);
        assert!(
            line.contains(&file.display().to_string()) && line.contains(words),
            "{name}: want {} and {words:?} in {line}",
            file.display()
        );
        assert!(
            !dir.join("out.png").exists(),
            "{name}: an image was written"
        );
        assert!(
            dir.temp_files().is_empty(),
            "{name}: {:?}",
            dir.temp_files()
        );
    }
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

/// `render --all-frames -o DIR` writes every frame of the animation, each
/// the image `render --frame k` writes, and one frame past the last is
/// refused.
#[test]
fn all_frames_writes_each_frame_as_render_frame_k_does() {
    let dir = TempDir::new("all-frames");
    let seed = std::fs::read_to_string(scene_path("seed.toml")).expect("seed scene");
    let scene = dir.path.join("turn.toml");
    std::fs::write(
        &scene,
        format!("{seed}\n[animation]\nframes = 3\norbit = 90\n"),
    )
    .expect("write scene");
    let scene = scene.to_str().expect("utf-8 path");
    let run = kdray(
        &dir.path,
        &render_args(scene, &["--all-frames", "-o", "frames"]),
    );
    assert_eq!(run.code, 0, "{run:#?}");
    let mut names: Vec<String> = std::fs::read_dir(dir.path.join("frames"))
        .expect("frames folder")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names, ["0000.png", "0001.png", "0002.png"]);
    let mut images = Vec::new();
    for (k, name) in names.iter().enumerate() {
        let one = format!("frame{k}.png");
        let run = kdray(
            &dir.path,
            &render_args(scene, &["--frame", &k.to_string(), "-o", &one]),
        );
        assert_eq!(run.code, 0, "{run:#?}");
        let single = std::fs::read(dir.path.join(&one)).expect("single frame");
        let from_all = std::fs::read(dir.path.join("frames").join(name)).expect("frame");
        assert!(
            single == from_all,
            "frame {k} differs from render --frame {k}"
        );
        images.push(single);
    }
    assert!(images[0] != images[1], "the orbit moves the camera");
    let run = kdray(
        &dir.path,
        &render_args(scene, &["--frame", "3", "-o", "x.png"]),
    );
    assert_eq!(run.code, 2, "{run:#?}");
    assert!(!dir.path.join("x.png").exists());
}

/// tests/scenes/moving_lights.toml: its lights move and change colour.
fn moving_lights_path() -> String {
    format!(
        "{}/tests/scenes/moving_lights.toml",
        env!("CARGO_MANIFEST_DIR")
    )
}

/// The moving-lights scene's frame `k` written as a still scene (its frame's
/// camera and lights, no animation) into `dir`/`name`; with `lights_of`
/// another frame, that frame's lights instead.
fn write_still_frame(dir: &Path, name: &str, k: u32, lights_of: u32) -> String {
    let mut scene =
        kdray::scene::load_scene(Path::new(&moving_lights_path())).expect("moving lights scene");
    scene.camera = scene.frame(k).camera;
    scene.lights = scene.frame(lights_of).lights;
    scene.animation = None;
    let text = kdray::scene::scene_text(&scene, kdray::scene::SceneFormat::Toml).expect("text");
    let path = dir.join(name);
    std::fs::write(&path, text).expect("write still scene");
    path.to_str().expect("utf-8 path").to_string()
}

/// `render --frame k` of a scene whose lights have keys is, pixel for pixel,
/// the render of a still scene with the camera and lights of frame k (at a
/// key, between keys, before a light's first key, after its last); the
/// frame's lights matter (frame 0's lights give another image), and
/// `--all-frames` writes the same frames from its one tree.
#[test]
fn moving_lights_render_each_frame_as_a_still_scene_with_that_frames_lights() {
    let dir = TempDir::new("moving-lights");
    let scene = moving_lights_path();
    let run = kdray(
        &dir.path,
        &render_args(&scene, &["--all-frames", "-o", "frames"]),
    );
    assert_eq!(run.code, 0, "{run:#?}");
    // The decoded pixels of `render --frame k`, and of a still scene.
    let frame_rgb = |k: u32| {
        let one = format!("frame{k}.png");
        let run = kdray(
            &dir.path,
            &render_args(&scene, &["--frame", &k.to_string(), "-o", &one]),
        );
        assert_eq!(run.code, 0, "{run:#?}");
        read_png_rgb(&dir.path.join(&one)).expect("single frame").2
    };
    // The still scenes are read back from their files and rendered in this
    // process at the same size, with the kernel variants compiled once
    // here rather than once per process.
    let still_rgb = |still: &str| {
        let mut scene = kdray::scene::load_scene(Path::new(still)).expect("still scene");
        scene.render.width = SMALL[1].parse().unwrap();
        scene.render.height = SMALL[3].parse().unwrap();
        common::render(&scene, kdray::gpu::Accel::Kdtree).rgb
    };
    for k in [2u32, 5, 8, 10, 11] {
        let animated = frame_rgb(k);
        let still = write_still_frame(&dir.path, &format!("still{k}.toml"), k, k);
        assert!(
            animated == still_rgb(&still),
            "frame {k} differs from the still scene of its camera and lights"
        );
        let (_, _, from_all) = read_png_rgb(&dir.path.join("frames").join(format!("{k:04}.png")))
            .expect("frame of --all-frames");
        assert!(
            animated == from_all,
            "--all-frames' frame {k} differs from --frame {k}"
        );
        let unlit = write_still_frame(&dir.path, &format!("unlit{k}.toml"), k, 0);
        assert!(
            animated != still_rgb(&unlit),
            "frame {k}: the lights of frame 0 gave the same image"
        );
    }
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
