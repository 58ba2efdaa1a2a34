//! glTF `KHR_lights_punctual`: point, spot and directional lights placed by
//! their nodes' world transforms (position: the node's origin; direction:
//! its -Z axis), colour x intensity as kdray's radiometric units one for one,
//! replacing the light rig of a model opened on its own.

use super::authored_gltf::*;
use super::*;
use kdray_core::scene::{model_scene_viewed, ModelCamera};
use serde_json::json;

/// The triangle and three lights: a point light under a translated parent,
/// a spot turned 90 degrees about +x (its -Z goes to -Y: pointing down) and
/// a directional light turned 90 degrees about +y (-Z to -X).
fn lit_document() -> serde_json::Value {
    let mut doc = triangle_document(json!({}));
    let s = std::f64::consts::FRAC_1_SQRT_2;
    doc["extensionsUsed"] = json!(["KHR_lights_punctual"]);
    doc["extensions"] = json!({"KHR_lights_punctual": {"lights": [
        {"type": "point", "color": [1.0, 0.5, 0.25], "intensity": 8.0, "range": 3.0},
        {"type": "spot", "intensity": 20.0,
         "spot": {"innerConeAngle": 0.25, "outerConeAngle": 0.5}},
        {"type": "directional", "color": [0.5, 0.5, 1.0], "intensity": 2.0}
    ]}});
    doc["scenes"] = json!([{"nodes": [0, 1, 3, 4]}]);
    doc["nodes"] = json!([
        {"mesh": 0},
        {"translation": [0, 2, 0], "children": [2]},
        {"translation": [1, 0, 0], "extensions": {"KHR_lights_punctual": {"light": 0}}},
        {"translation": [0, 3, 1], "rotation": [-s, 0, 0, s], "scale": [2, 2, 2],
         "extensions": {"KHR_lights_punctual": {"light": 1}}},
        {"translation": [5, 5, 5], "rotation": [0, s, 0, s],
         "extensions": {"KHR_lights_punctual": {"light": 2}}}
    ]);
    doc
}

#[track_caller]
fn assert_near(got: DVec3, want: DVec3) {
    assert!((got - want).length() < 1e-6, "{got} is not {want}");
}

#[test]
fn punctual_lights_load_with_their_positions_directions_and_intensities() {
    let dir = TempDir::new("gltf-lights");
    let mesh = read_document(&dir, "lit.gltf", &lit_document());
    assert!(mesh.warnings.is_empty(), "{:?}", mesh.warnings);
    let lights = &mesh.lights;
    assert_eq!(lights.len(), 3);

    assert_eq!(lights[0].kind, LightKind::Point);
    assert_near(lights[0].position, DVec3::new(1.0, 2.0, 0.0));
    assert_eq!(lights[0].diffuse, DVec3::new(8.0, 4.0, 2.0));
    assert_eq!(lights[0].specular, lights[0].diffuse);
    assert_eq!(lights[0].ambient, DVec3::ZERO);

    let LightKind::Spot {
        direction,
        inner_degrees,
        outer_degrees,
    } = lights[1].kind
    else {
        panic!("{:?}", lights[1].kind);
    };
    assert_near(lights[1].position, DVec3::new(0.0, 3.0, 1.0));
    assert_near(direction, DVec3::NEG_Y); // unit, whatever the node's scale
    assert!((inner_degrees - 0.25f64.to_degrees()).abs() < 1e-5);
    assert!((outer_degrees - 0.5f64.to_degrees()).abs() < 1e-5);
    assert_eq!(lights[1].diffuse, DVec3::splat(20.0)); // colour defaults to white

    let LightKind::Directional { direction } = lights[2].kind else {
        panic!("{:?}", lights[2].kind);
    };
    assert_near(direction, DVec3::NEG_X);
    assert_eq!(lights[2].diffuse, DVec3::new(1.0, 1.0, 2.0));
}

#[test]
fn a_models_punctual_lights_replace_the_light_rig() {
    let dir = TempDir::new("gltf-lights-model");
    let path = write_document(&dir, "lit.gltf", &lit_document());
    let scene = model_scene_viewed(&path, ModelCamera::File, &mut |_| {}, &mut |_| {}).unwrap();
    assert_eq!(
        scene.lights,
        read_document(&dir, "lit.gltf", &lit_document()).lights
    );
    // Without lights the rig of three is used.
    let plain = write_document(&dir, "plain.gltf", &triangle_document(json!({})));
    let scene = model_scene_viewed(&plain, ModelCamera::File, &mut |_| {}, &mut |_| {}).unwrap();
    assert_eq!(scene.lights.len(), 3);
    assert!(scene.lights.iter().all(|l| l.kind == LightKind::Point));
}

#[test]
fn a_spot_cone_outside_the_gltf_range_is_refused_naming_the_node_and_light() {
    let dir = TempDir::new("gltf-lights-bad-cone");
    for (inner, outer) in [(0.5, 0.25), (0.1, 2.0)] {
        let mut doc = lit_document();
        doc["extensions"]["KHR_lights_punctual"]["lights"][1]["spot"] =
            json!({"innerConeAngle": inner, "outerConeAngle": outer});
        let path = write_document(&dir, "bad.gltf", &doc);
        let e = kdray_core::scene::gltf::load_gltf(&path, true, &mut |_| {}).unwrap_err();
        assert_error(&e, &path, None, None, &["node 3 light 1", "outerConeAngle"]);
    }
}

#[test]
fn a_node_naming_a_light_that_is_not_there_is_an_error_not_a_panic() {
    let dir = TempDir::new("gltf-lights-missing");
    let mut beyond = lit_document();
    beyond["nodes"][2]["extensions"]["KHR_lights_punctual"]["light"] = json!(7);
    let mut none_declared = lit_document();
    none_declared.as_object_mut().unwrap().remove("extensions");
    for (name, doc) in [("beyond.gltf", beyond), ("undeclared.gltf", none_declared)] {
        let path = write_document(&dir, name, &doc);
        let e = kdray_core::scene::gltf::load_gltf(&path, true, &mut |_| {}).unwrap_err();
        assert_error(&e, &path, None, None, &["not a valid glTF 2.0 file"]);
    }
}
