//! Animations through the `kdray` binary: `render --all-frames` writes each
//! frame as `render --frame k` does, and a frame of moving lights is the
//! still scene with that frame's camera and lights.

use std::path::Path;

use crate::cli::{kdray, render_args, scene_path, SMALL};
use crate::common;

use common::TempDir;
use kdray::output::read_png_rgb;

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
