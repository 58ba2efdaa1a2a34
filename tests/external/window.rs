//! The interactive window (`kdray render SCENE --window`), run for real
//! under Xvfb: its screenshot after refining to k * k samples (or path
//! samples) matches the headless render (for an animated scene, of its
//! frame's lights too), and
//! hot reload picks up edits of the scene file and of an OBJ it uses and
//! survives a broken file. The camera controls are unit
//! tests in src/window/camera_controller.rs (the same code path the event
//! loop feeds).
//!
//! Each test starts its own Xvfb (`x_window`) on a free display and stops
//! it when done. Without Xvfb installed the tests fail, saying what to
//! install (CI's .ci/run installs it).

use crate::common;

use std::path::Path;
use std::process::{Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

use super::x_window::{kdray, read, temp_dir, RunningWindow, Xvfb, H, SAMPLES, TIMEOUT, W};
use common::{compare, repo_path};

/// Mean FLIP error and share of pixels allowed to differ by more than 2
/// levels, as in the golden tests.
const MAX_MEAN_FLIP: f32 = 0.01;
const MAX_PIXELS_OVER_PER_MILLE: usize = 1;
/// Runs to completion within [`TIMEOUT`]: (status, stdout, stderr).
fn run(mut command: Command) -> (ExitStatus, String, String) {
    let mut child = command
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let deadline = Instant::now() + TIMEOUT;
    while child.try_wait().unwrap().is_none() {
        if Instant::now() > deadline {
            let _ = child.kill();
            let out = child.wait_with_output().unwrap();
            panic!(
                "timed out after {TIMEOUT:?}; stderr:\n{}",
                String::from_utf8_lossy(&out.stderr)
            );
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let out = child.wait_with_output().unwrap();
    (
        out.status,
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// `kdray render SCENE --samples 4 -o OUT` at the tests' size, with
/// `extra` flags.
fn headless_with(dir: &Path, scene: &Path, out: &Path, extra: &[&str]) -> Vec<u8> {
    let mut command = kdray(dir);
    command
        .args(["render".as_ref(), scene.as_os_str()])
        .args(extra)
        .args([
            "--width",
            &W.to_string(),
            "--height",
            &H.to_string(),
            "--samples",
            SAMPLES,
            "-o",
        ]);
    command.arg(out);
    let (status, _, stderr) = run(command);
    assert!(status.success(), "headless render failed: {stderr}");
    read(out)
}

fn headless(dir: &Path, scene: &Path, out: &Path) -> Vec<u8> {
    headless_with(dir, scene, out, &[])
}

fn window_args(scene: &Path, screenshot: &Path) -> Vec<std::ffi::OsString> {
    let mut args: Vec<std::ffi::OsString> = vec!["render".into(), scene.into(), "--window".into()];
    for a in [
        "--width",
        &W.to_string(),
        "--height",
        &H.to_string(),
        "--samples",
        SAMPLES,
    ] {
        args.push(a.into());
    }
    args.push("--screenshot".into());
    args.push(screenshot.into());
    args
}

/// Whether `a` matches `b` within the golden tests' budget.
fn check_match(what: &str, a: &[u8], b: &[u8]) -> Result<(), String> {
    let d = compare(a, b, W, H, 2);
    let budget = (W * H) as usize * MAX_PIXELS_OVER_PER_MILLE / 1000;
    if d.mean_flip > MAX_MEAN_FLIP || d.pixels_over > budget {
        return Err(format!(
            "{what}: {d:?} (budget: FLIP {MAX_MEAN_FLIP}, {budget} pixels)"
        ));
    }
    Ok(())
}

/// Whether `a` and `b` clearly differ (over 1% of the pixels by more than
/// 2 levels).
fn clearly_differ(a: &[u8], b: &[u8]) -> bool {
    compare(a, b, W, H, 2).pixels_over > (W * H) as usize / 100
}

/// Whitted scenes, a path-traced one, and a Whitted scene path traced by
/// flag: the window's picture after 4 samples (a k x k grid, or 4 path
/// samples tone-mapped by the present pass) is the headless render's.
#[test]
fn still_window_screenshot_matches_the_headless_render() {
    let x = Xvfb::start();
    let dir = temp_dir("match");
    let mut failures = Vec::new();
    let cases: [(&str, &str, &[&str]); 4] = [
        ("seed", "seed", &[]),
        ("torus", "torus", &[]),
        ("cornell_box", "cornell_box", &[]),
        ("seed-path", "seed", &["--integrator", "path"]),
    ];
    for (name, file, extra) in cases {
        let scene = repo_path(&format!("scenes/{file}.toml"));
        let expected = headless_with(
            &dir,
            &scene,
            &dir.join(format!("{name}-headless.png")),
            extra,
        );
        // A preview frame, then the 4 samples, then the finished image
        // presented again. A pass is one frame, or on a slow (loaded)
        // machine bands of at least 8 rows: at most 4 x 8 frames.
        let shot = dir.join(format!("{name}-window.png"));
        let mut command = x.kdray(&dir);
        command
            .args(window_args(&scene, &shot))
            .args(extra)
            .args(["--frames", "40", "--stats"]);
        let (status, stdout, stderr) = run(command);
        assert!(status.success(), "{name}: the window failed: {stderr}");
        assert!(
            stderr.contains(&format!("{file}.toml: {W}x{H} window on")),
            "{name}: {stderr}"
        );
        // The figures count those frames: every frame but the first (which
        // has no interval to time) is a still or an idle one.
        let stats: serde_json::Value = serde_json::from_str(stdout.trim())
            .unwrap_or_else(|e| panic!("{name}: --stats printed {stdout:?}: {e}"));
        for (key, value) in [
            ("frames", 40),
            ("width", W),
            ("height", H),
            ("samples", 4),
            ("moving_frames", 0),
        ] {
            assert_eq!(stats[key], value, "{name}: {key} in {stats}");
        }
        let count = |key: &str| stats[key].as_u64().unwrap();
        assert_eq!(
            count("still_frames") + count("idle_frames"),
            39,
            "{name}: {stats}"
        );
        assert!((4..=32).contains(&count("still_frames")), "{name}: {stats}");
        assert!(
            stats["refine_seconds"].as_f64().is_some(),
            "{name}: {stats}"
        );
        if let Err(e) = check_match(name, &read(&shot), &expected) {
            failures.push(e);
        }
        // The first frame is the reduced-resolution preview, not yet the
        // refined image.
        let first = dir.join(format!("{name}-first.png"));
        let mut command = x.kdray(&dir);
        command
            .args(window_args(&scene, &first))
            .args(extra)
            .args(["--frames", "1"]);
        let (status, _, stderr) = run(command);
        assert!(status.success(), "{name}: the window failed: {stderr}");
        let d = compare(&read(&first), &expected, W, H, 0);
        if d.pixels_over == 0 {
            failures.push(format!("{name}: one frame already shows all 4 samples"));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A sphere of colour `diffuse` and the triangle of models/tri.obj.
fn reload_scene(diffuse: &str) -> String {
    format!(
        r#"[camera]
position = [0.0, 0.0, 4.0]
look_at  = [0.0, 0.0, 0.0]
vfov     = 40.0

[render]
background = [0.1, 0.1, 0.1]

[[lights]]
position = [2.0, 3.0, 4.0]

[materials.paint]
ambient = [0.1, 0.1, 0.1]
diffuse = {diffuse}

[materials.tri]
diffuse = [0.8, 0.8, 0.2]

[[spheres]]
center   = [-0.5, 0.0, 0.0]
radius   = 0.7
material = "paint"

[[meshes]]
path     = "models/tri.obj"
material = "tri"
"#
    )
}

const TRIANGLE: &str = "v 0.2 -0.8 0.5\nv 1.4 -0.8 0.5\nv 0.8 0.4 0.5\nf 1 2 3\n";
// The edits change the files' sizes too, so even a file system with coarse
// modification times shows them.
const BIGGER_TRIANGLE: &str = "v 0.2 -0.8 0.5\nv 1.4 -0.8 0.5\nv 0.8 1.05 0.5\nf 1 2 3\n";
const RED: &str = "[0.8, 0.1, 0.1]";
const BLUE: &str = "[0.1, 0.1, 0.85]";

#[test]
fn hot_reload_follows_the_scene_and_its_obj_and_survives_a_broken_file() {
    let x = Xvfb::start();
    let dir = temp_dir("reload");
    std::fs::create_dir_all(dir.join("models")).unwrap();
    let scene = dir.join("scene.toml");
    let obj = dir.join("models/tri.obj");
    std::fs::write(&obj, TRIANGLE).unwrap();
    std::fs::write(&scene, reload_scene(RED)).unwrap();
    let shot = dir.join("window.png");

    let mut command = x.kdray(&dir);
    command.args(window_args(&scene, &shot));
    let mut window = RunningWindow::spawn(command);
    window.line_with("window on");
    // A changed colour in the scene file.
    std::fs::write(&scene, reload_scene(BLUE)).unwrap();
    window.line_with("reloaded");
    // A changed OBJ.
    std::fs::write(&obj, BIGGER_TRIANGLE).unwrap();
    window.line_with("reloaded");
    // A broken scene file: reported, and the window goes on.
    std::fs::write(&scene, reload_scene("[0.1, 0.1")).unwrap();
    window.line_with(&format!("kdray: {}:", scene.display()));
    // Time to finish refining the last good scene (4 frames).
    std::thread::sleep(Duration::from_millis(1500));
    assert!(
        window.running(),
        "the window exited after the broken file; stderr:\n{}",
        window.seen.join("\n")
    );
    // Closed as Esc closes it, saving --screenshot.
    let (status, stderr) = window.close();
    assert!(status.success(), "exit {status}; stderr:\n{stderr}");
    let prefix = format!("kdray: {}:", scene.display());
    let names_line = stderr.lines().any(|l| {
        l.strip_prefix(&prefix).is_some_and(|rest| {
            let digits = rest.chars().take_while(char::is_ascii_digit).count();
            digits > 0 && rest[digits..].starts_with(": ")
        })
    });
    assert!(
        names_line,
        "the parse error should name the file and line:\n{stderr}"
    );
    let window = read(&shot);

    // Headless renders of the three versions.
    let refs = dir.join("refs");
    std::fs::create_dir_all(refs.join("models")).unwrap();
    let version = |name: &str, diffuse: &str, triangle: &str| {
        std::fs::write(refs.join("models/tri.obj"), triangle).unwrap();
        let path = refs.join(format!("{name}.toml"));
        std::fs::write(&path, reload_scene(diffuse)).unwrap();
        headless(&dir, &path, &refs.join(format!("{name}.png")))
    };
    let red = version("red", RED, TRIANGLE);
    let blue = version("blue", BLUE, TRIANGLE);
    let last = version("last", BLUE, BIGGER_TRIANGLE);
    assert!(clearly_differ(&red, &blue) && clearly_differ(&blue, &last));
    check_match("last good scene", &window, &last).unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn window_flags_are_checked() {
    let dir = temp_dir("flags");
    let seed = repo_path("scenes/seed.toml");
    let cases: [(&[&str], &str); 5] = [
        (&["--frames", "3"], "--window"),
        (&["--screenshot", "x.png"], "--window"),
        (&["--window", "-o", "x.png"], "--output"),
        (&["--window", "--frames", "0"], "--frames"),
        // The seed is Whitted: refused as `render --denoise` refuses it.
        (
            &["--window", "--denoise"],
            "--denoise: the denoiser needs the path tracer",
        ),
    ];
    for (args, mentions) in cases {
        let mut command = kdray(&dir);
        command.arg("render").arg(&seed).args(args);
        let (status, _, stderr) = run(command);
        assert_eq!(status.code(), Some(2), "{args:?}: {stderr}");
        assert!(stderr.contains(mentions), "{args:?}: {stderr}");
    }
    // A bad scene is reported before any window opens.
    let broken = dir.join("broken.toml");
    std::fs::write(&broken, "[camera]\nposition = [0, 0, 1]\n").unwrap();
    let mut command = kdray(&dir);
    command.arg("render").arg(&broken).arg("--window");
    let (status, _, stderr) = run(command);
    assert_eq!(status.code(), Some(2), "{stderr}");
    assert!(
        stderr.starts_with("kdray: ") && stderr.contains("broken.toml"),
        "{stderr}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Without `XDG_RUNTIME_DIR` (or with a relative one, which libwayland
/// calls invalid), Mesa's Vulkan device-selection layer makes libwayland
/// print `error: XDG_RUNTIME_DIR is invalid or not set in the environment.`
/// when the window's instance lists devices; the window gives Mesa a
/// private runtime folder first, as the headless path does.
#[test]
fn the_window_prints_no_xdg_runtime_dir_error_without_the_variable() {
    let x = Xvfb::start();
    let dir = temp_dir("xdg");
    let scene = repo_path("scenes/seed.toml");
    for value in [None, Some("relative/runtime")] {
        let shot = dir.join("shot.png");
        let mut command = x.kdray(&dir);
        command
            .env_remove("XDG_RUNTIME_DIR")
            // The private folder goes here, not in the shared /tmp.
            .env("TMPDIR", &dir)
            .args(window_args(&scene, &shot))
            .args(["--frames", "1"]);
        if let Some(value) = value {
            command.env("XDG_RUNTIME_DIR", value);
        }
        let (status, _, stderr) = run(command);
        assert!(status.success(), "XDG_RUNTIME_DIR={value:?}: {stderr}");
        assert!(
            !stderr.contains("XDG_RUNTIME_DIR"),
            "XDG_RUNTIME_DIR={value:?}: the window printed\n{stderr}"
        );
        assert!(shot.exists(), "XDG_RUNTIME_DIR={value:?}: no screenshot");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn no_display_is_one_clear_error() {
    let dir = temp_dir("nodisplay");
    let mut command = kdray(&dir);
    command
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .arg("render")
        .arg(repo_path("scenes/seed.toml"))
        .arg("--window");
    let (status, _, stderr) = run(command);
    assert_eq!(status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("kdray: cannot open a window"), "{stderr}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `--play` starts the scene's animation: the camera moves frame after
/// frame (the window traces previews, counted as moving frames), and the
/// last frame shows another view than the still window's, which stays on
/// frame 0 and refines it.
#[test]
fn play_moves_the_camera_through_the_animation() {
    let x = Xvfb::start();
    let dir = temp_dir("play");
    let scene = repo_path("scenes/orbit.toml");
    let mut shots = Vec::new();
    let mut moving = Vec::new();
    for play in [false, true] {
        let shot = dir.join(format!("orbit-play-{play}.png"));
        let mut command = x.kdray(&dir);
        command
            .args(window_args(&scene, &shot))
            .args(["--frames", "30", "--stats"]);
        if play {
            command.arg("--play");
        }
        let (status, stdout, stderr) = run(command);
        assert!(status.success(), "play {play}: the window failed: {stderr}");
        let stats: serde_json::Value = serde_json::from_str(stdout.trim())
            .unwrap_or_else(|e| panic!("play {play}: --stats printed {stdout:?}: {e}"));
        moving.push(stats["moving_frames"].as_u64().unwrap());
        shots.push(read(&shot));
    }
    assert_eq!(moving[0], 0, "the still window never moves");
    assert!(moving[1] > 0, "playing moves the camera: {moving:?}");
    assert!(
        clearly_differ(&shots[0], &shots[1]),
        "the playing window ends on another view than frame 0"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A window on a scene whose light 0 is keyed at frame 0 (another place and
/// colour than its `[[lights]]` entry) shows frame 0's lights: its
/// screenshot matches the headless render of frame 0 and clearly differs
/// from the same scene without that key.
#[test]
fn the_window_shows_the_lights_of_its_frame() {
    let x = Xvfb::start();
    let dir = temp_dir("lights");
    let plain = repo_path("tests/scenes/moving_lights.toml");
    let text = std::fs::read_to_string(&plain).unwrap();
    let first_key = "[[animation.light_keys]]";
    let key_at_0 = "frame = 0\nlight = 0\nposition = [-4.0, 1.0, 3.0]\ncolor = [0.3, 0.6, 1.0]\n";
    let keyed = text.replacen(
        first_key,
        &format!("{first_key}\n{key_at_0}\n{first_key}"),
        1,
    );
    assert_ne!(keyed, text, "the scene's light keys");
    let scene = dir.join("keyed.toml");
    std::fs::write(&scene, keyed).unwrap();
    let expected = headless(&dir, &scene, &dir.join("keyed-headless.png"));
    let unkeyed = headless(&dir, &plain, &dir.join("plain-headless.png"));
    assert!(
        clearly_differ(&expected, &unkeyed),
        "the key at frame 0 changes the image"
    );
    let shot = dir.join("keyed-window.png");
    let mut command = x.kdray(&dir);
    command
        .args(window_args(&scene, &shot))
        .args(["--frames", "40"]);
    let (status, _, stderr) = run(command);
    assert!(status.success(), "the window failed: {stderr}");
    if let Err(e) = check_match("frame 0's lights", &read(&shot), &expected) {
        panic!("{e}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
