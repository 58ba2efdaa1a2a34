//! `kdray farm` end to end: on a real one-node Slurm cluster started by
//! scripts/slurm_cluster.sh (in a temporary folder, on a free port, stopped
//! by pid when the last test using it ends, on failure too), and by hand
//! without Slurm. Images are 64x48 so that the whole file takes seconds.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Mutex;
use std::time::SystemTime;

use crate::common;

use common::{run_kdray, Run, TempDir};
use kdray::output::read_png_rgb;

pub(crate) const SIZE: [&str; 4] = ["--width", "64", "--height", "48"];

pub(crate) fn repo(relative: &str) -> String {
    format!("{}/{relative}", env!("CARGO_MANIFEST_DIR"))
}

/// A running cluster: its folder and slurm.conf.
struct Cluster {
    dir: TempDir,
}

impl Cluster {
    fn conf(&self) -> PathBuf {
        self.dir.join("slurm.conf")
    }

    fn stop(&self) {
        let status = Command::new("bash")
            .arg(repo("scripts/slurm_cluster.sh"))
            .arg("stop")
            .arg(&self.dir.path)
            .status();
        if !matches!(status, Ok(s) if s.success()) {
            eprintln!(
                "stopping the Slurm cluster in {}: {status:?}",
                self.dir.path.display()
            );
        }
    }
}

/// The cluster and how many tests hold it; started by the first, stopped
/// (under the lock, so that no test starts another meanwhile) by the last.
static CLUSTER: Mutex<(Option<Cluster>, usize)> = Mutex::new((None, 0));

/// A test's hold on the cluster: dropped, also while a failed test
/// unwinds, it lets go, and the last one out stops the daemons by pid.
pub(crate) struct ClusterUse {
    conf: PathBuf,
}

impl Drop for ClusterUse {
    fn drop(&mut self) {
        let mut shared = CLUSTER.lock().unwrap_or_else(|e| e.into_inner());
        shared.1 -= 1;
        if shared.1 == 0 {
            if let Some(cluster) = shared.0.take() {
                cluster.stop();
            }
        }
    }
}

/// Two free neighbouring ports (slurmctld's and slurmd's).
fn free_port_pair() -> u16 {
    for _ in 0..50 {
        let a = std::net::TcpListener::bind(("0.0.0.0", 0)).unwrap();
        let port = a.local_addr().unwrap().port();
        if port < u16::MAX && std::net::TcpListener::bind(("0.0.0.0", port + 1)).is_ok() {
            return port;
        }
    }
    panic!("no two free neighbouring ports");
}

pub(crate) fn cluster() -> ClusterUse {
    let mut shared = CLUSTER.lock().unwrap_or_else(|e| e.into_inner());
    if shared.0.is_none() {
        let dir = TempDir::new("slurm");
        let port = free_port_pair();
        let out = Command::new("bash")
            .arg(repo("scripts/slurm_cluster.sh"))
            .arg("start")
            .arg(&dir.path)
            .env("SLURM_CLUSTER_PORT", port.to_string())
            .output()
            .expect("cannot run scripts/slurm_cluster.sh");
        let cluster = Cluster { dir };
        if !out.status.success() {
            cluster.stop();
            panic!(
                "the farm tests need a one-node Slurm cluster (as root, with Debian's \
                 slurmctld slurmd slurm-client munge: scripts/test.sh installs them): {}",
                String::from_utf8_lossy(&out.stderr)
            );
        }
        shared.0 = Some(cluster);
    }
    shared.1 += 1;
    ClusterUse {
        conf: shared.0.as_ref().unwrap().conf(),
    }
}

/// `kdray farm SCENE --out OUT` at 64x48 with `extra` flags, on `cluster`.
pub(crate) fn farm(
    dir: &Path,
    cluster: &ClusterUse,
    scene: &str,
    out: &Path,
    extra: &[&str],
) -> Run {
    let mut args = vec!["farm", scene, "--out", out.to_str().unwrap()];
    args.extend(SIZE);
    args.extend(extra);
    run_kdray(
        dir,
        &args,
        &[("SLURM_CONF", cluster.conf.to_str().unwrap())],
    )
}

/// The single-machine render of `scene` at 64x48 (`extra`: more flags).
pub(crate) fn single_render(dir: &TempDir, scene: &str, extra: &[&str]) -> (u32, u32, Vec<u8>) {
    let out = dir.join("single.png");
    let mut args = vec!["render", scene, "-o", out.to_str().unwrap()];
    args.extend(SIZE);
    args.extend(extra);
    let run = run_kdray(&dir.path, &args, &[]);
    assert_eq!(run.code, 0, "{run:#?}");
    let image = read_png_rgb(&out).unwrap();
    std::fs::remove_file(out).unwrap();
    image
}

/// Every frame of `scene`'s animation rendered on the single machine at
/// 64x48 (`extra`: more flags), in order: one `render --all-frames`, which
/// writes each frame as `render --frame k` does (tests/gpu/cli_animation.rs checks
/// that), so that the comparison costs one process, not one a frame.
pub(crate) fn single_frames(
    dir: &TempDir,
    scene: &str,
    frames: usize,
    extra: &[&str],
) -> Vec<(u32, u32, Vec<u8>)> {
    let out = dir.join("single-frames");
    let mut args = vec!["render", scene, "--all-frames", "-o", out.to_str().unwrap()];
    args.extend(SIZE);
    args.extend(extra);
    let run = run_kdray(&dir.path, &args, &[]);
    assert_eq!(run.code, 0, "{run:#?}");
    let names: Vec<String> = (0..frames).map(|k| format!("{k:04}.png")).collect();
    assert_eq!(top_level_pngs(&out), names, "render --all-frames");
    let images = names
        .iter()
        .map(|name| read_png_rgb(&out.join(name)).unwrap())
        .collect();
    std::fs::remove_dir_all(out).unwrap();
    images
}

/// The PNG files at the top level of `dir`, sorted.
pub(crate) fn top_level_pngs(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".png"))
        .collect();
    names.sort();
    names
}

pub(crate) fn mtime(path: &Path) -> SystemTime {
    std::fs::metadata(path)
        .and_then(|m| m.modified())
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn band(out: &Path, i: u32) -> PathBuf {
    out.join(format!("parts/band-{i:04}.png"))
}

#[test]
fn a_still_in_four_tiles_on_slurm_equals_the_single_machine_render() {
    let cluster = cluster();
    let tmp = TempDir::new("farm-still");
    let out = tmp.join("out");
    let scene = repo("scenes/seed.toml");
    let run = farm(
        &tmp.path,
        &cluster,
        &scene,
        &out,
        &["--tiles", "4", "--submit", "--wait"],
    );
    assert_eq!(run.code, 0, "{run:#?}");
    assert!(run.stdout.contains("submitted array job"), "{run:#?}");
    assert!(run.stdout.contains("(tasks 0-3)"), "{run:#?}");
    assert_eq!(
        top_level_pngs(&out),
        ["seed.png"],
        "exactly one PNG at the top"
    );
    for i in 0..4 {
        assert!(band(&out, i).is_file(), "band {i}");
        assert!(
            out.join(format!("parts/logs/task-{i}.log")).is_file(),
            "log {i}"
        );
    }
    assert_eq!(
        read_png_rgb(&out.join("seed.png")).unwrap(),
        single_render(&tmp, &scene, &[])
    );
    assert!(tmp.temp_files().is_empty());
}

#[test]
fn a_failing_task_fails_the_wait_naming_it_and_the_finishing_job_does_not_succeed() {
    let cluster = cluster();
    let tmp = TempDir::new("farm-fail");
    let out = tmp.join("out");
    let scene = repo("scenes/seed.toml");
    // A folder where band 2 goes: task 2 renders it but cannot rename it into place.
    std::fs::create_dir_all(band(&out, 2)).unwrap();
    let args = ["--tiles", "4", "--submit", "--wait"];
    let run = farm(&tmp.path, &cluster, &scene, &out, &args);
    assert_eq!(run.code, 1, "{run:#?}");
    let error = run.stderr_text();
    let log = out.join("parts/logs/task-2.log");
    assert!(error.contains("task 2 failed"), "{error}");
    assert!(error.contains(log.to_str().unwrap()), "{error}");
    assert!(!error.contains("task 1 failed"), "{error}");
    let task_log = std::fs::read_to_string(&log).unwrap();
    assert!(task_log.contains("band-0002.png"), "{task_log}");
    // The finishing job was cancelled: no image, no marker, no log.
    assert!(top_level_pngs(&out).is_empty());
    assert!(!out.join("parts/finished").exists());
    assert!(!out.join("parts/logs/finish.log").exists());
}

#[test]
fn wait_alone_waits_for_the_last_submission() {
    let cluster = cluster();
    let tmp = TempDir::new("farm-wait-alone");
    let out = tmp.join("out");
    let scene = repo("scenes/seed.toml");
    // The jobs start 3 s after submission, so the later --wait finds them queued.
    let run = |last: &str| {
        let args = ["--tiles", "2", "--sbatch=--begin=now+3", last];
        farm(&tmp.path, &cluster, &scene, &out, &args)
    };
    let nothing = run("--wait");
    assert_eq!(nothing.code, 2, "{nothing:#?}");
    let error = nothing.stderr_text();
    assert!(
        error.contains("no submission recorded to wait for"),
        "{error}"
    );
    let submitted = run("--submit");
    assert_eq!(submitted.code, 0, "{submitted:#?}");
    assert!(
        submitted.stdout.contains("submitted array job"),
        "{submitted:#?}"
    );
    assert!(top_level_pngs(&out).is_empty(), "not finished yet");
    let waited = run("--wait");
    assert_eq!(waited.code, 0, "{waited:#?}");
    assert!(
        waited.stdout.contains("waiting for array job"),
        "{waited:#?}"
    );
    assert!(waited.stdout.contains("done:"), "{waited:#?}");
    assert_eq!(
        read_png_rgb(&out.join("seed.png")).unwrap(),
        single_render(&tmp, &scene, &[])
    );
}

#[test]
fn a_rerun_renders_only_what_is_missing() {
    let cluster = cluster();
    let tmp = TempDir::new("farm-rerun");
    let out = tmp.join("out");
    let scene = repo("scenes/seed.toml");
    let args = ["--tiles", "4", "--submit", "--wait"];
    let run = farm(&tmp.path, &cluster, &scene, &out, &args);
    assert_eq!(run.code, 0, "{run:#?}");
    // Complete: nothing is submitted again.
    let again = farm(&tmp.path, &cluster, &scene, &out, &args);
    assert_eq!(again.code, 0, "{again:#?}");
    assert!(again.stdout.contains("nothing to do"), "{again:#?}");
    assert!(!again.stdout.contains("submitted"), "{again:#?}");

    std::fs::remove_file(band(&out, 1)).unwrap();
    std::fs::remove_file(out.join("seed.png")).unwrap();
    let kept: Vec<SystemTime> = [0, 2, 3].map(|i| mtime(&band(&out, i))).to_vec();
    let run = farm(&tmp.path, &cluster, &scene, &out, &args);
    assert_eq!(run.code, 0, "{run:#?}");
    assert!(run.stdout.contains("1 with work left (1)"), "{run:#?}");
    assert!(run.stdout.contains("(tasks 1)"), "{run:#?}");
    assert_eq!(kept, [0, 2, 3].map(|i| mtime(&band(&out, i))).to_vec());
    assert_eq!(
        read_png_rgb(&out.join("seed.png")).unwrap(),
        single_render(&tmp, &scene, &[])
    );
}

#[test]
fn a_changed_scene_file_it_loads_or_flag_is_refused_without_force() {
    let tmp = TempDir::new("farm-changed");
    let out = tmp.join("out");
    let text = std::fs::read_to_string(repo("scenes/torus.toml")).unwrap();
    let scene = tmp.write("torus.toml", &text);
    let scene = scene.to_str().unwrap();
    for model in ["torus.obj", "torus.mtl"] {
        let bytes = std::fs::read_to_string(repo(&format!("scenes/models/{model}"))).unwrap();
        tmp.write(&format!("models/{model}"), &bytes);
    }
    let mtl = tmp.join("models/torus.mtl");
    let plan = |extra: &[&str]| {
        let mut args = vec![
            "farm",
            scene,
            "--out",
            out.to_str().unwrap(),
            "--tiles",
            "2",
        ];
        args.extend(SIZE);
        args.extend(extra);
        run_kdray(&tmp.path, &args, &[])
    };
    let run = plan(&[]);
    assert_eq!(run.code, 0, "{run:#?}");
    // A band rendered by hand, as a task would.
    let task = Command::new("sh")
        .arg(out.join("render.sbatch"))
        .arg("0")
        .output()
        .unwrap();
    assert!(task.status.success(), "{task:?}");
    assert!(band(&out, 0).is_file());

    // Tasks and sbatch options may change; the images may not.
    assert_eq!(plan(&["--tasks", "1", "--sbatch=--time=5"]).code, 0);
    let flag = plan(&["--samples", "4"]);
    assert_eq!(flag.code, 2, "{flag:#?}");
    assert!(flag.one_error_line().contains("--force"), "{flag:#?}");

    let material = std::fs::read_to_string(&mtl).unwrap();
    std::fs::write(&mtl, format!("{material}\n# edited\n")).unwrap();
    let changed = plan(&[]);
    assert_eq!(changed.code, 2, "{changed:#?}");
    let line = changed.one_error_line();
    assert!(
        line.contains(&format!("{} changed", mtl.display())),
        "{line}"
    );
    // A task of the planned render refuses the changed input too (task 0
    // of one, since --tasks 1: band 1 is left to render).
    let task = Command::new("sh")
        .arg(out.join("render.sbatch"))
        .arg("0")
        .output()
        .unwrap();
    assert!(!task.status.success());
    assert!(
        String::from_utf8_lossy(&task.stderr).contains("torus.mtl changed"),
        "{task:?}"
    );
    std::fs::write(&mtl, material).unwrap();
    assert_eq!(plan(&[]).code, 0, "restored: the same render again");

    std::fs::write(scene, text.replace("vfov     = 45.0", "vfov     = 40.0")).unwrap();
    let changed = plan(&[]);
    assert_eq!(changed.code, 2, "{changed:#?}");
    let line = changed.one_error_line();
    assert!(line.contains(&format!("{scene} changed")), "{line}");
    assert!(band(&out, 0).is_file(), "refused: nothing discarded");

    let forced = plan(&["--force"]);
    assert_eq!(forced.code, 0, "{forced:#?}");
    assert!(forced.stderr_text().contains("discarded"), "{forced:#?}");
    assert!(!band(&out, 0).exists(), "the old render's band is gone");
}

#[test]
fn without_sbatch_the_scripts_run_by_hand_and_make_the_same_image() {
    let tmp = TempDir::new("farm-by-hand");
    let out = tmp.join("out");
    let scene = repo("scenes/torus.toml");
    let mut args = vec![
        "farm",
        &scene,
        "--out",
        out.to_str().unwrap(),
        "--tiles",
        "3",
        "--submit",
    ];
    args.extend(SIZE);
    let run = run_kdray(&tmp.path, &args, &[("PATH", "/nonexistent")]);
    assert_eq!(run.code, 1, "{run:#?}");
    let line = run.one_error_line();
    assert!(line.contains("sbatch not found"), "{line}");
    assert!(line.contains("render.sbatch"), "{line}");
    assert!(line.contains("install"), "{line}");

    // Each task takes its index from an argument, Slurm's variable or
    // Kubernetes' (Indexed Jobs).
    let script = out.join("render.sbatch");
    type Index<'a> = (&'a [&'a str], &'a [(&'a str, &'a str)]);
    let tasks: [Index; 3] = [
        (&["0"], &[]),
        (&[], &[("SLURM_ARRAY_TASK_ID", "1")]),
        (&[], &[("JOB_COMPLETION_INDEX", "2")]),
    ];
    for (index, env) in tasks {
        let task = Command::new("sh")
            .arg(&script)
            .args(index)
            .env_remove("SLURM_ARRAY_TASK_ID")
            .env_remove("JOB_COMPLETION_INDEX")
            .envs(env.iter().copied())
            .output()
            .unwrap();
        assert!(task.status.success(), "{task:?}");
    }
    let finish = Command::new("sh")
        .arg(out.join("finish.sbatch"))
        .output()
        .unwrap();
    assert!(finish.status.success(), "{finish:?}");
    assert_eq!(top_level_pngs(&out), ["torus.png"]);
    assert_eq!(
        read_png_rgb(&out.join("torus.png")).unwrap(),
        single_render(&tmp, &scene, &[])
    );
}

#[test]
fn an_orbit_of_eight_frames_in_three_tasks_equals_render_frame_by_frame() {
    let cluster = cluster();
    let tmp = TempDir::new("farm-frames");
    let out = tmp.join("out");
    let text = std::fs::read_to_string(repo("scenes/orbit.toml")).unwrap();
    let eight = text.replace("frames = 48", "frames = 8");
    assert_ne!(eight, text, "scenes/orbit.toml's frames line");
    let scene = tmp.write("orbit.toml", &eight);
    let scene = scene.to_str().unwrap();
    let run = farm(
        &tmp.path,
        &cluster,
        scene,
        &out,
        &["--tasks", "3", "--submit", "--wait"],
    );
    assert_eq!(run.code, 0, "{run:#?}");
    assert!(
        run.stdout.contains("8 frames of 64x48, 3 tasks"),
        "{run:#?}"
    );
    assert!(run.stdout.contains("(tasks 0-2)"), "{run:#?}");
    let frames: Vec<String> = (0..8).map(|k| format!("{k:04}.png")).collect();
    assert_eq!(top_level_pngs(&out), frames);
    let mut seen = Vec::new();
    let singles = single_frames(&tmp, scene, frames.len(), &[]);
    for (k, (name, single)) in frames.iter().zip(singles).enumerate() {
        let image = read_png_rgb(&out.join(name)).unwrap();
        assert_eq!(image, single, "frame {k}");
        assert!(!seen.contains(&image), "frame {k} repeats an earlier frame");
        seen.push(image);
    }
    // Shares of 2, 3 and 3 frames, each task's frames in its log.
    let log = std::fs::read_to_string(out.join("parts/logs/task-2.log")).unwrap();
    assert!(log.contains("\"rendered\":[5,6,7]"), "{log}");
    let finish = std::fs::read_to_string(out.join("parts/logs/finish.log")).unwrap();
    assert!(finish.contains("8 frames checked"), "{finish}");
    match kdray::farm::find_on_path("ffmpeg") {
        Some(_) => assert!(out.join("orbit.mp4").is_file()),
        None => assert!(finish.contains("ffmpeg -y"), "{finish}"),
    }
}

#[test]
fn a_still_of_one_frame_of_an_animation_equals_render_frame_and_bad_frames_exit_2() {
    let tmp = TempDir::new("farm-one-frame");
    let out = tmp.join("out");
    let scene = repo("scenes/orbit.toml");
    let mut args = vec!["farm", &scene, "--out", out.to_str().unwrap()];
    args.extend(SIZE);
    args.extend(["--frame", "30", "--tiles", "2"]);
    let run = run_kdray(&tmp.path, &args, &[]);
    assert_eq!(run.code, 0, "{run:#?}");
    for i in ["0", "1"] {
        let task = Command::new("sh")
            .arg(out.join("render.sbatch"))
            .arg(i)
            .output()
            .unwrap();
        assert!(task.status.success(), "{task:?}");
    }
    let finish = Command::new("sh")
        .arg(out.join("finish.sbatch"))
        .output()
        .unwrap();
    assert!(finish.status.success(), "{finish:?}");
    assert_eq!(top_level_pngs(&out), ["orbit.png"]);
    let frame_30 = single_render(&tmp, &scene, &["--frame", "30"]);
    assert_eq!(read_png_rgb(&out.join("orbit.png")).unwrap(), frame_30);
    assert_ne!(
        frame_30,
        single_render(&tmp, &scene, &[]),
        "frame 0 differs"
    );

    let render = run_kdray(&tmp.path, &["render", &scene, "--frame", "48"], &[]);
    assert_eq!(render.code, 2, "{render:#?}");
    assert!(render.one_error_line().contains("--frame"), "{render:#?}");
    let mut args = vec![
        "farm",
        &scene,
        "--out",
        out.to_str().unwrap(),
        "--frame",
        "48",
    ];
    args.extend(SIZE);
    let farm = run_kdray(&tmp.path, &args, &[]);
    assert_eq!(farm.code, 2, "{farm:#?}");
    assert!(farm.one_error_line().contains("--frame"), "{farm:#?}");
}

/// A farm of an animation whose lights move (tests/scenes/moving_lights.toml,
/// its 12 frames in 2 tasks run by hand, no Slurm) writes each frame as
/// `render --frame k` does: every task shows the lights of its frames.
#[test]
fn farm_frames_of_moving_lights_equal_render_frame_by_frame() {
    let tmp = TempDir::new("farm-moving-lights");
    let out = tmp.join("out");
    let scene = repo("tests/scenes/moving_lights.toml");
    let mut args = vec!["farm", &scene, "--out", out.to_str().unwrap()];
    args.extend(SIZE);
    args.extend(["--tasks", "2"]);
    let run = run_kdray(&tmp.path, &args, &[]);
    assert_eq!(run.code, 0, "{run:#?}");
    for i in ["0", "1"] {
        let task = Command::new("sh")
            .arg(out.join("render.sbatch"))
            .arg(i)
            .output()
            .unwrap();
        assert!(task.status.success(), "{task:?}");
    }
    let frames: Vec<String> = (0..12).map(|k| format!("{k:04}.png")).collect();
    assert_eq!(top_level_pngs(&out), frames);
    let singles = single_frames(&tmp, &scene, frames.len(), &[]);
    for (k, (name, single)) in frames.iter().zip(singles).enumerate() {
        assert_eq!(read_png_rgb(&out.join(name)).unwrap(), single, "frame {k}");
    }
}
