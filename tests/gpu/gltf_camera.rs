//! A glTF model opened as a scene looks through the file's first camera:
//! it renders as the same scene with that camera stated by hand in TOML.

use crate::common;

use common::*;
use glam::DVec3;
use kdray::gpu::Accel;
use kdray::scene::{scene_text, Camera, SceneFormat};

/// One triangle facing +z, and a camera node at `eye` looking down -z with
/// a vertical field of view of `yfov` radians.
fn write_model(dir: &TempDir, eye: [f64; 3], yfov: f32) -> std::path::PathBuf {
    let corners: [f32; 9] = [-1.0, -1.0, 0.0, 1.0, -1.0, 0.0, 0.0, 1.0, 0.0];
    let bytes: Vec<u8> = corners.iter().flat_map(|x| x.to_le_bytes()).collect();
    std::fs::write(dir.join("tri.bin"), bytes).unwrap();
    let text = format!(
        r#"{{
  "asset": {{"version": "2.0"}},
  "scene": 0,
  "scenes": [{{"nodes": [0, 1]}}],
  "nodes": [{{"mesh": 0}}, {{"camera": 0, "translation": [{}, {}, {}]}}],
  "cameras": [{{"type": "perspective", "perspective": {{"yfov": {yfov}, "znear": 0.01}}}}],
  "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}}}]}}],
  "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                  "min": [-1, -1, 0], "max": [1, 1, 0]}}],
  "bufferViews": [{{"buffer": 0, "byteLength": 36}}],
  "buffers": [{{"uri": "tri.bin", "byteLength": 36}}]
}}"#,
        eye[0], eye[1], eye[2]
    );
    dir.write("model.gltf", &text)
}

#[test]
fn a_gltf_camera_renders_as_the_same_camera_stated_by_hand() {
    let dir = TempDir::new("gltf-camera-render");
    let (eye, yfov) = ([0.25, 0.125, 3.0], 0.75f32);
    let path = write_model(&dir, eye, yfov);
    // The default view's scene (ground, lights, model), its camera stated
    // by hand and written out as a TOML scene.
    let (from_file, mut by_hand) = model_and_default_view(&path, 48);
    let framed = by_hand.camera;
    by_hand.camera = Camera {
        position: DVec3::from_array(eye),
        look_at: DVec3::new(eye[0], eye[1], 0.0),
        up: DVec3::Y,
        vfov_degrees: f64::from(yfov).to_degrees(),
    };
    let toml = scene_text(&by_hand, SceneFormat::Toml).unwrap();
    let by_hand = scene_from_toml(&toml);

    let a = render(&from_file, Accel::Kdtree);
    let b = render(&by_hand, Accel::Kdtree);
    let d = compare(&a.rgb, &b.rgb, 48, 48, 0);
    assert_eq!(d.pixels_over, 0, "largest difference {}", d.largest);
    // Not the default view: that one sees the triangle elsewhere.
    let mut default_view = from_file.clone();
    default_view.camera = framed;
    let c = render(&default_view, Accel::Kdtree);
    assert!(compare(&a.rgb, &c.rgb, 48, 48, 8).pixels_over > 100);
}

#[test]
fn the_camera_flag_picks_a_models_view_and_is_refused_for_a_scene_file() {
    let dir = TempDir::new("gltf-camera-flag");
    write_model(&dir, [0.0, 0.0, 3.0], 0.75);
    let image = |view: &str| {
        let out = format!("{view}.png");
        let run = run_kdray(
            &dir.path,
            &[
                "render",
                "model.gltf",
                "--camera",
                view,
                "--width",
                "24",
                "--height",
                "24",
                "-o",
                &out,
            ],
            &[],
        );
        assert_eq!(run.code, 0, "{run:#?}");
        kdray::output::read_png_rgb(&dir.join(&out)).unwrap()
    };
    assert_ne!(image("file"), image("default"));
    let scene = dir.write(
        "scene.toml",
        "[camera]\nposition = [0, 0, 5]\nlook_at = [0, 0, 0]\n\n[[lights]]\nposition = [0, 5, 5]\n",
    );
    let run = run_kdray(
        &dir.path,
        &["render", scene.to_str().unwrap(), "--camera", "default"],
        &[],
    );
    assert_eq!(run.code, 2, "{run:#?}");
    let line = run.one_error_line();
    assert!(
        line.contains("--camera default") && line.contains("scene.toml"),
        "{line}"
    );
}
