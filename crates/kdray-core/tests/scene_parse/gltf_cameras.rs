//! glTF cameras: a model opened on its own looks through the file's first
//! perspective camera, placed by its node's world transform (eye at the
//! node's origin, looking down -Z, +Y up), unless the default view is asked
//! for; an orthographic camera is ignored with a warning.

use super::authored_gltf::*;
use super::*;
use kdray_core::scene::{model_scene_viewed, ModelCamera, Warning};
use serde_json::json;

/// The triangle, plus a camera node (a child of a parent node, so that the
/// world transform is a product) and the camera `projection`.
fn with_camera(projection: serde_json::Value) -> serde_json::Value {
    let mut doc = triangle_document(json!({}));
    doc["scenes"] = json!([{"nodes": [0, 1]}]);
    let s = std::f64::consts::FRAC_1_SQRT_2;
    doc["nodes"] = json!([
        {"mesh": 0},
        {"translation": [0, 1, 0], "children": [2]},
        // Turned 90 degrees about +y: -Z goes to -X.
        {"camera": 0, "translation": [4, 0, 0.5], "rotation": [0, s, 0, s]}
    ]);
    doc["cameras"] = json!([projection]);
    doc
}

fn open(dir: &TempDir, doc: &serde_json::Value, view: ModelCamera) -> (Scene, Vec<Warning>) {
    let path = write_document(dir, "model.gltf", doc);
    let mut warnings = Vec::new();
    let scene = model_scene_viewed(&path, view, &mut |_| {}, &mut |w| warnings.push(w))
        .unwrap_or_else(|e| panic!("{e}"));
    (scene, warnings)
}

#[test]
fn a_model_looks_through_its_first_perspective_camera() {
    let dir = TempDir::new("gltf-camera");
    let doc =
        with_camera(json!({"type": "perspective", "perspective": {"yfov": 0.5, "znear": 0.1}}));
    let (scene, warnings) = open(&dir, &doc, ModelCamera::File);
    assert!(warnings.is_empty(), "{warnings:?}");
    let c = scene.camera;
    assert!(
        (c.position - DVec3::new(4.0, 1.0, 0.5)).length() < 1e-6,
        "{c:?}"
    );
    let forward = (c.look_at - c.position).normalize();
    assert!((forward - DVec3::NEG_X).length() < 1e-6, "{c:?}");
    assert!((c.up.normalize() - DVec3::Y).length() < 1e-6, "{c:?}");
    assert!((c.vfov_degrees - 0.5f64.to_degrees()).abs() < 1e-5, "{c:?}");
    // The default view ignores it.
    let (framed, _) = open(&dir, &doc, ModelCamera::Default);
    assert!((framed.camera.position - c.position).length() > 0.1);
    assert_eq!(framed.camera.vfov_degrees, 40.0);
}

#[test]
fn an_orthographic_camera_is_ignored_with_a_warning() {
    let dir = TempDir::new("gltf-ortho");
    let doc = with_camera(json!({
        "type": "orthographic",
        "orthographic": {"xmag": 1, "ymag": 1, "znear": 0.1, "zfar": 10}
    }));
    let (scene, warnings) = open(&dir, &doc, ModelCamera::File);
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert!(
        warnings[0].to_string().contains("orthographic"),
        "{}",
        warnings[0]
    );
    assert_eq!(scene.camera.vfov_degrees, 40.0);
}

#[test]
fn a_camera_whose_node_collapses_its_view_is_refused() {
    let dir = TempDir::new("gltf-camera-collapsed");
    let mut doc =
        with_camera(json!({"type": "perspective", "perspective": {"yfov": 0.5, "znear": 0.1}}));
    doc["nodes"][2] = json!({"camera": 0, "scale": [1, 1, 0]});
    let path = write_document(&dir, "model.gltf", &doc);
    let e = model_scene_viewed(&path, ModelCamera::File, &mut |_| {}, &mut |_| {}).unwrap_err();
    assert_error(&e, &path, None, None, &["node 2 camera 0", "collapses"]);
}
