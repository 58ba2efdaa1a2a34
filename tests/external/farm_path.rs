//! `kdray farm` with the path tracer: animations frame by frame, stills in
//! bands of rows, and stills split by samples (`--split samples`), each
//! against `kdray render` of the same scene on the same adapter. Images
//! are 64x48 with few samples, so that each test takes seconds.

use std::path::Path;
use std::process::Command;

use crate::common;
use crate::farm::{cluster, farm, mtime, repo, single_frames, single_render, top_level_pngs, SIZE};

use common::{run_kdray, TempDir};
use kdray::output::exr::read_exr_rgb;
use kdray::output::read_png_rgb;

/// `kdray render SCENE -o single.exr` at 64x48 with `extra` flags: the
/// linear radiance.
fn single_exr(dir: &TempDir, scene: &str, extra: &[&str]) -> (u32, u32, Vec<f32>) {
    let out = dir.join("single.exr");
    let mut args = vec!["render", scene, "-o", out.to_str().unwrap()];
    args.extend(SIZE);
    args.extend(extra);
    let run = run_kdray(&dir.path, &args, &[]);
    assert_eq!(run.code, 0, "{run:#?}");
    let image = read_exr_rgb(&out).unwrap();
    std::fs::remove_file(out).unwrap();
    image
}

/// Runs DIR's array script for each task index, then its finishing script,
/// by hand (no Slurm), asserting that each succeeds.
fn run_by_hand(out: &Path, tasks: u32) {
    for i in 0..tasks {
        let task = Command::new("sh")
            .arg(out.join("render.sbatch"))
            .arg(i.to_string())
            .env_remove("SLURM_ARRAY_TASK_ID")
            .env_remove("JOB_COMPLETION_INDEX")
            .output()
            .unwrap();
        assert!(task.status.success(), "task {i}: {task:?}");
    }
    let finish = Command::new("sh")
        .arg(out.join("finish.sbatch"))
        .output()
        .unwrap();
    assert!(finish.status.success(), "{finish:?}");
}

/// The largest `|a - b| / (tolerance(b))` over every value, with `tolerance
/// = 1e-5 * |b| + 1e-7`: below 1 when every value agrees within float
/// rounding.
fn worst_relative_difference(a: &[f32], b: &[f32]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(&x, &y)| (x as f64 - y as f64).abs() / (1e-5 * (y as f64).abs() + 1e-7))
        .fold(0.0, f64::max)
}

/// The largest difference of one channel between two 8-bit images.
fn max_level_difference(a: &[u8], b: &[u8]) -> u8 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(x, y)| x.abs_diff(*y))
        .max()
        .unwrap_or(0)
}

const PATH: [&str; 6] = ["--integrator", "path", "--samples", "8", "--seed", "7"];

#[test]
fn a_path_traced_orbit_of_five_frames_in_three_tasks_on_slurm_equals_render_frame_by_frame() {
    let cluster = cluster();
    let tmp = TempDir::new("farm-path-frames");
    let out = tmp.join("out");
    let text = std::fs::read_to_string(repo("scenes/orbit.toml")).unwrap();
    let five = text.replace("frames = 48", "frames = 5");
    assert_ne!(five, text, "scenes/orbit.toml's frames line");
    let scene = tmp.write("orbit.toml", &five);
    let scene = scene.to_str().unwrap();
    let mut args = vec!["--tasks", "3", "--submit", "--wait"];
    args.extend(PATH);
    let run = farm(&tmp.path, &cluster, scene, &out, &args);
    assert_eq!(run.code, 0, "{run:#?}");
    assert!(
        run.stdout.contains("5 frames of 64x48, 3 tasks"),
        "{run:#?}"
    );
    let frames: Vec<String> = (0..5).map(|k| format!("{k:04}.png")).collect();
    assert_eq!(top_level_pngs(&out), frames);
    let singles = single_frames(&tmp, scene, frames.len(), &PATH);
    for (k, (name, single)) in frames.iter().zip(singles).enumerate() {
        assert_eq!(read_png_rgb(&out.join(name)).unwrap(), single, "frame {k}");
    }
    // The plan carried the integrator and the seed: the Whitted frame and
    // the path tracer's with another seed differ.
    let farmed = read_png_rgb(&out.join("0000.png")).unwrap();
    assert_ne!(farmed, single_render(&tmp, scene, &[]), "Whitted frame 0");
    let mut other_seed = PATH;
    other_seed[5] = "8";
    assert_ne!(
        farmed,
        single_render(&tmp, scene, &other_seed),
        "frame 0 with seed 8"
    );
}

#[test]
fn a_path_traced_still_split_by_samples_on_slurm_equals_the_single_render_within_rounding() {
    let cluster = cluster();
    let tmp = TempDir::new("farm-path-samples");
    let out = tmp.join("out");
    let scene = repo("scenes/cornell_box.toml");
    // 40 samples in shares of 13, 13 and 14: unequal weights, and shares
    // that start inside the single render's dispatches of 16 samples.
    let args = [
        "--samples",
        "40",
        "--split",
        "samples",
        "--parts",
        "3",
        "--submit",
        "--wait",
    ];
    let run = farm(&tmp.path, &cluster, &scene, &out, &args);
    assert_eq!(run.code, 0, "{run:#?}");
    assert!(
        run.stdout
            .contains("a 64x48 still (frame 0) of 40 samples in 3 shares, 3 tasks"),
        "{run:#?}"
    );
    assert_eq!(top_level_pngs(&out), ["cornell_box.png"]);
    let share = |i: u32| out.join(format!("parts/samples-{i:04}.exr"));

    let single = single_exr(&tmp, &scene, &["--samples", "40"]);
    let farmed = read_exr_rgb(&out.join("cornell_box.exr")).unwrap();
    assert_eq!((farmed.0, farmed.1), (64, 48));
    let worst = worst_relative_difference(&farmed.2, &single.2);
    eprintln!("split by samples: worst difference {worst:.3} of 1e-5 relative + 1e-7");
    assert!(worst <= 1.0, "the farm's EXR differs by {worst} tolerances");
    // Each share alone is a noisier image of fewer samples.
    for i in 0..3 {
        let (_, _, part) = read_exr_rgb(&share(i)).unwrap();
        assert!(
            worst_relative_difference(&part, &single.2) > 1e3,
            "share {i} is not the whole render"
        );
    }
    let single_png = single_render(&tmp, &scene, &["--samples", "40"]);
    let farmed_png = read_png_rgb(&out.join("cornell_box.png")).unwrap();
    assert_eq!((farmed_png.0, farmed_png.1), (single_png.0, single_png.1));
    let levels = max_level_difference(&farmed_png.2, &single_png.2);
    eprintln!("split by samples: the PNGs differ by {levels} levels at most");
    assert!(levels <= 1, "the farm's PNG differs by {levels} levels");
    assert!(tmp.temp_files().is_empty());

    // A re-run renders only the missing share.
    std::fs::remove_file(share(1)).unwrap();
    std::fs::remove_file(out.join("cornell_box.exr")).unwrap();
    let kept = [0, 2].map(|i| mtime(&share(i)));
    let run = farm(&tmp.path, &cluster, &scene, &out, &args);
    assert_eq!(run.code, 0, "{run:#?}");
    assert!(run.stdout.contains("(tasks 1)"), "{run:#?}");
    assert_eq!(kept, [0, 2].map(|i| mtime(&share(i))));
    let again = read_exr_rgb(&out.join("cornell_box.exr")).unwrap();
    assert_eq!(again, farmed, "the re-run's average is the first one's");
}

#[test]
fn a_path_traced_still_in_bands_equals_the_single_render() {
    let tmp = TempDir::new("farm-path-bands");
    let out = tmp.join("out");
    let scene = repo("scenes/cornell_box.toml");
    let mut args = vec!["farm", &scene, "--out", out.to_str().unwrap()];
    args.extend(SIZE);
    args.extend(["--samples", "8", "--tiles", "3"]);
    let run = run_kdray(&tmp.path, &args, &[]);
    assert_eq!(run.code, 0, "{run:#?}");
    run_by_hand(&out, 3);
    assert_eq!(top_level_pngs(&out), ["cornell_box.png"]);
    assert_eq!(
        read_png_rgb(&out.join("cornell_box.png")).unwrap(),
        single_render(&tmp, &scene, &["--samples", "8"])
    );
}

#[test]
fn a_split_by_samples_of_a_whitted_scene_or_into_too_many_parts_exits_2() {
    let tmp = TempDir::new("farm-split-refused");
    let out = tmp.join("out");
    let plan = |scene: &str, extra: &[&str]| {
        let mut args = vec!["farm", scene, "--out", out.to_str().unwrap()];
        args.extend(SIZE);
        args.extend(["--split", "samples"]);
        args.extend(extra);
        run_kdray(&tmp.path, &args, &[])
    };
    let whitted = plan(&repo("scenes/seed.toml"), &["--parts", "2"]);
    assert_eq!(whitted.code, 2, "{whitted:#?}");
    let line = whitted.one_error_line();
    assert!(line.contains("--split samples"), "{line}");
    assert!(line.contains("--integrator path"), "{line}");

    let cornell = repo("scenes/cornell_box.toml");
    let many = plan(&cornell, &["--samples", "4", "--parts", "5"]);
    assert_eq!(many.code, 2, "{many:#?}");
    assert!(many.one_error_line().contains("--parts"), "{many:#?}");
    let tasks = plan(
        &cornell,
        &["--samples", "4", "--parts", "2", "--tasks", "3"],
    );
    assert_eq!(tasks.code, 2, "{tasks:#?}");
    assert!(tasks.one_error_line().contains("--tasks"), "{tasks:#?}");
    assert!(!out.join("farm.json").exists(), "nothing planned");
}

/// The largest difference between two images of floats, absolute.
fn max_abs_difference(a: &[f32], b: &[f32]) -> f32 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f32::max)
}

#[test]
fn a_denoised_still_split_by_samples_on_slurm_equals_render_denoise_within_a_level() {
    let cluster = cluster();
    let tmp = TempDir::new("farm-denoise-samples");
    let out = tmp.join("out");
    let scene = repo("scenes/cornell_box.toml");
    let args = [
        "--samples",
        "4",
        "--split",
        "samples",
        "--parts",
        "2",
        "--denoise",
        "--submit",
        "--wait",
    ];
    let run = farm(&tmp.path, &cluster, &scene, &out, &args);
    assert_eq!(run.code, 0, "{run:#?}");
    assert!(
        run.stdout
            .contains("a 64x48 still (frame 0) of 4 samples in 2 shares, denoised, 2 tasks"),
        "{run:#?}"
    );
    assert_eq!(top_level_pngs(&out), ["cornell_box.png"]);
    let share = |i: u32, ext: &str| out.join(format!("parts/samples-{i:04}.{ext}"));
    for i in 0..2 {
        for ext in ["exr", "albedo.exr", "normal.exr"] {
            assert!(share(i, ext).is_file(), "share {i}'s {ext}");
        }
    }

    // The single machine's render --denoise -o single.exr and its inputs.
    let single = tmp.join("single.exr");
    let mut render = vec!["render", &scene, "-o", single.to_str().unwrap()];
    render.extend(SIZE);
    render.extend(["--samples", "4", "--denoise"]);
    let run = run_kdray(&tmp.path, &render, &[]);
    assert_eq!(run.code, 0, "{run:#?}");
    let exr = |path: &Path| read_exr_rgb(path).unwrap().2;
    let farmed = |ext: &str| exr(&out.join(format!("cornell_box.{ext}")));
    let single_of = |ext: &str| exr(&tmp.join(&format!("single.{ext}")));

    // The denoiser's inputs: the averaged radiance within f32 rounding of
    // the single render's, the averaged albedo and normal (means of
    // values in [-1, 1]) within 1e-6.
    let noisy = farmed("noisy.exr");
    let worst = worst_relative_difference(&noisy, &single_of("noisy.exr"));
    assert!(
        worst <= 1.0,
        "the noisy radiance differs by {worst} tolerances"
    );
    for feature in ["albedo.exr", "normal.exr"] {
        let d = max_abs_difference(&farmed(feature), &single_of(feature));
        eprintln!("denoised split by samples: {feature} differs by {d:e} at most");
        assert!(d <= 1e-6, "{feature} differs by {d}");
    }
    let denoised = farmed("exr");
    let single_denoised = single_of("exr");
    let worst = worst_relative_difference(&denoised, &single_denoised);
    eprintln!("denoised split by samples: the denoised EXRs differ by {worst:.3} tolerances");
    assert!(
        worst <= 1.0,
        "the denoised EXR differs by {worst} tolerances"
    );
    assert!(
        worst_relative_difference(&denoised, &noisy) > 1e3,
        "the farm's EXR is not denoised"
    );
    // The PNG: the single render's denoised radiance tone-mapped as the
    // scene says, within one level.
    let settings = kdray::scene::load_scene(Path::new(&scene)).unwrap().render;
    let scale = settings.exposure.exp2() as f32;
    let single_png: Vec<u8> = single_denoised
        .iter()
        .map(|&v| settings.tone_map.to_srgb8(v, scale))
        .collect();
    let (w, h, farmed_png) = read_png_rgb(&out.join("cornell_box.png")).unwrap();
    assert_eq!((w, h), (64, 48));
    let levels = max_level_difference(&farmed_png, &single_png);
    eprintln!("denoised split by samples: the PNGs differ by {levels} levels at most");
    assert!(levels <= 1, "the farm's PNG differs by {levels} levels");
    assert!(tmp.temp_files().is_empty());

    // A share that lost its normal is not done: the finishing job refuses
    // to average without it, naming the share and its task, and a re-run
    // would render that share alone (planned only, not submitted: the
    // re-rendering itself is the split by samples' test above).
    std::fs::remove_file(share(1, "normal.exr")).unwrap();
    std::fs::remove_file(out.join("cornell_box.exr")).unwrap();
    let finish = Command::new("sh")
        .arg(out.join("finish.sbatch"))
        .output()
        .unwrap();
    assert!(!finish.status.success(), "{finish:?}");
    let stderr = String::from_utf8_lossy(&finish.stderr);
    assert!(stderr.contains("share 1 (task 1"), "{stderr}");
    let replan = farm(&tmp.path, &cluster, &scene, &out, &args[..7]);
    assert_eq!(replan.code, 0, "{replan:#?}");
    assert!(
        replan.stdout.contains("2 tasks, 1 with work left (1)"),
        "{replan:#?}"
    );
}

#[test]
fn a_denoised_path_traced_animation_equals_render_all_frames_denoise() {
    let tmp = TempDir::new("farm-denoise-frames");
    let out = tmp.join("out");
    let text = std::fs::read_to_string(repo("scenes/orbit.toml")).unwrap();
    let two = text.replace("frames = 48", "frames = 2");
    assert_ne!(two, text, "scenes/orbit.toml's frames line");
    let scene = tmp.write("orbit.toml", &two);
    let scene = scene.to_str().unwrap();
    let flags = [
        "--integrator",
        "path",
        "--samples",
        "2",
        "--seed",
        "7",
        "--denoise",
    ];
    let mut args = vec!["farm", scene, "--out", out.to_str().unwrap()];
    args.extend(SIZE);
    args.extend(flags);
    let run = run_kdray(&tmp.path, &args, &[]);
    assert_eq!(run.code, 0, "{run:#?}");
    assert!(
        run.stdout.contains("2 frames of 64x48, denoised"),
        "{run:#?}"
    );
    run_by_hand(&out, 1);
    let singles = single_frames(&tmp, scene, 2, &flags);
    for (k, single) in singles.iter().enumerate() {
        let name = format!("{k:04}.png");
        assert_eq!(&read_png_rgb(&out.join(name)).unwrap(), single, "frame {k}");
    }
    let noisy = single_frames(&tmp, scene, 2, &flags[..6]);
    assert_ne!(singles[0], noisy[0], "frame 0 is denoised");
}

#[test]
fn a_denoised_farm_of_a_whitted_scene_or_of_a_still_in_bands_exits_2() {
    let tmp = TempDir::new("farm-denoise-refused");
    let out = tmp.join("out");
    let plan = |scene: &str, extra: &[&str]| {
        let mut args = vec!["farm", scene, "--out", out.to_str().unwrap()];
        args.extend(SIZE);
        args.extend(extra);
        run_kdray(&tmp.path, &args, &[])
    };
    let whitted = plan(&repo("scenes/seed.toml"), &["--denoise"]);
    assert_eq!(whitted.code, 2, "{whitted:#?}");
    let line = whitted.one_error_line();
    assert!(line.contains("--denoise"), "{line}");
    assert!(line.contains("path tracer"), "{line}");

    // The scene's own denoise = true, turned Whitted by the flag.
    let text = std::fs::read_to_string(repo("scenes/seed.toml")).unwrap();
    let path = text.replace(
        "[render]\n",
        "[render]\nintegrator = \"path\"\ndenoise = true\n",
    );
    assert_ne!(path, text, "scenes/seed.toml's [render] line");
    let path = tmp.write("seed_denoised.toml", &path);
    let flagged = plan(path.to_str().unwrap(), &["--integrator", "whitted"]);
    assert_eq!(flagged.code, 2, "{flagged:#?}");
    let line = flagged.one_error_line();
    assert!(line.contains("[render] denoise = true"), "{line}");
    assert!(line.contains("--denoise=false"), "{line}");

    let bands = plan(
        &repo("scenes/cornell_box.toml"),
        &["--denoise", "--tiles", "2"],
    );
    assert_eq!(bands.code, 2, "{bands:#?}");
    let line = bands.one_error_line();
    assert!(line.contains("--tiles 2"), "{line}");
    assert!(line.contains("--split samples"), "{line}");
    assert!(!out.join("farm.json").exists(), "nothing planned");
}
