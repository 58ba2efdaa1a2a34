//! A glTF model with `KHR_lights_punctual` lights, opened as a scene, is
//! lit by them: it renders as the same scene with those lights (and its
//! camera) stated by hand.

use crate::common;

use common::*;
use glam::DVec3;
use kdray::gpu::Accel;
use kdray::scene::{scene_text, Camera, Light, LightKind, SceneFormat};

/// A 4 x 4 square at y = 0 (two triangles facing +y), a camera 6 above it
/// looking down (node turned -90 degrees about +x), a spot light 2 above
/// its centre pointing down (the same turn) and a directional light
/// shining straight down (the same turn, at a translation that means
/// nothing).
fn write_model(dir: &TempDir) -> std::path::PathBuf {
    let corners: [f32; 12] = [
        -2.0, 0.0, -2.0, -2.0, 0.0, 2.0, 2.0, 0.0, 2.0, 2.0, 0.0, -2.0,
    ];
    let indices: [u16; 6] = [0, 1, 2, 0, 2, 3];
    let mut bytes: Vec<u8> = corners.iter().flat_map(|x| x.to_le_bytes()).collect();
    bytes.extend(indices.iter().flat_map(|i| i.to_le_bytes()));
    std::fs::write(dir.join("square.bin"), bytes).unwrap();
    let down = "\"rotation\": [-0.70710678, 0, 0, 0.70710678]";
    let text = format!(
        r#"{{
  "asset": {{"version": "2.0"}},
  "extensionsUsed": ["KHR_lights_punctual"],
  "extensions": {{"KHR_lights_punctual": {{"lights": [
    {{"type": "spot", "color": [1.0, 0.8, 0.6], "intensity": 0.9,
      "spot": {{"innerConeAngle": 0.3, "outerConeAngle": 0.6}}}},
    {{"type": "directional", "color": [0.2, 0.2, 0.4], "intensity": 0.5}}
  ]}}}},
  "scene": 0,
  "scenes": [{{"nodes": [0, 1, 2, 3]}}],
  "nodes": [
    {{"mesh": 0}},
    {{"camera": 0, "translation": [0, 6, 0], {down}}},
    {{"translation": [0.5, 2, 0], {down}, "extensions": {{"KHR_lights_punctual": {{"light": 0}}}}}},
    {{"translation": [9, 9, 9], {down}, "extensions": {{"KHR_lights_punctual": {{"light": 1}}}}}}
  ],
  "cameras": [{{"type": "perspective", "perspective": {{"yfov": 0.8, "znear": 0.01}}}}],
  "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}, "indices": 1}}]}}],
  "accessors": [
    {{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
      "min": [-2, 0, -2], "max": [2, 0, 2]}},
    {{"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"}}
  ],
  "bufferViews": [{{"buffer": 0, "byteLength": 48}}, {{"buffer": 0, "byteOffset": 48, "byteLength": 12}}],
  "buffers": [{{"uri": "square.bin", "byteLength": 60}}]
}}"#
    );
    dir.write("lit.gltf", &text)
}

#[test]
fn gltf_punctual_lights_render_as_the_same_lights_stated_by_hand() {
    let dir = TempDir::new("gltf-lights-render");
    let path = write_model(&dir);
    let (from_file, mut by_hand) = model_and_default_view(&path, 48);
    by_hand.camera = Camera {
        position: DVec3::new(0.0, 6.0, 0.0),
        look_at: DVec3::ZERO,
        up: DVec3::NEG_Z,
        vfov_degrees: f64::from(0.8f32).to_degrees(),
    };
    let spot = DVec3::new(1.0, 0.8, 0.6) * 0.9;
    let sun = DVec3::new(0.2, 0.2, 0.4) * 0.5;
    by_hand.lights = vec![
        Light {
            position: DVec3::new(0.5, 2.0, 0.0),
            ambient: DVec3::ZERO,
            diffuse: spot,
            specular: spot,
            kind: LightKind::Spot {
                direction: DVec3::NEG_Y,
                inner_degrees: f64::from(0.3f32).to_degrees(),
                outer_degrees: f64::from(0.6f32).to_degrees(),
            },
            reference_distance: None,
        },
        Light {
            position: DVec3::ZERO,
            ambient: DVec3::ZERO,
            diffuse: sun,
            specular: sun,
            kind: LightKind::Directional {
                direction: DVec3::NEG_Y,
            },
            reference_distance: None,
        },
    ];
    let by_hand = scene_from_toml(&scene_text(&by_hand, SceneFormat::Toml).unwrap());

    let a = render(&from_file, Accel::Kdtree);
    let b = render(&by_hand, Accel::Kdtree);
    // The node rotations are f32 quaternions: directions agree to ~1e-8.
    let d = compare(&a.rgb, &b.rgb, 48, 48, 1);
    assert_eq!(d.pixels_over, 0, "largest difference {}", d.largest);
    // Lit by the spot (bright, warm) near the centre, by the sun alone at
    // the square's edge.
    let centre = pixel(&a, 24, 27);
    let edge = pixel(&a, 24, 8); // x = -1.64: on the square, outside the cone
    assert!(centre[0] > 200 && centre[0] > centre[2], "{centre:?}");
    assert_eq!(edge, quantize([0.1, 0.1, 0.2]), "the sun alone");
}
