//! The medium inside a transmissive object: `KHR_materials_volume` in glTF,
//! `attenuation_color` and `attenuation_distance` in a scene file, and the
//! absorption coefficient the path tracer reads from them.

use super::authored_gltf::*;
use super::*;
use kdray_core::scene::scene_text;
use kdray_core::scene::Volume;
use serde_json::json;

const SCENE: &str =
    "[camera]\nposition = [0, 0, 5]\nlook_at = [0, 0, 0]\n\n[[lights]]\nposition = [0, 5, 5]\n\n";

fn glass(keys: &str) -> String {
    format!("{SCENE}[materials.glass]\ndiffuse = [1, 1, 1]\ntransmission = 1\n{keys}\n[[spheres]]\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"glass\"\n")
}

#[test]
fn a_gltf_volume_is_the_materials_medium_without_a_warning() {
    let dir = TempDir::new("gltf-volume");
    let mut material = json!({"pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1]}});
    material["extensions"] = json!({
        "KHR_materials_transmission": {"transmissionFactor": 1.0},
        "KHR_materials_volume": {"thicknessFactor": 0.2, "attenuationColor": [0.5, 0.8, 1.0], "attenuationDistance": 2.0}
    });
    let mut doc = triangle_document(material);
    doc["extensionsUsed"] = json!(["KHR_materials_transmission", "KHR_materials_volume"]);
    let mesh = read_document(&dir, "volume.gltf", &doc);
    assert!(mesh.warnings.is_empty(), "{:?}", mesh.warnings);
    let volume = mesh.materials[0].physical.volume.expect("a volume");
    assert_eq!(
        volume.attenuation_color,
        DVec3::new(0.5, 0.8f32 as f64, 1.0)
    );
    assert_eq!(volume.attenuation_distance, 2.0);
    // glTF's default distance is infinite: no absorption.
    let mut plain = json!({});
    plain["extensions"] = json!({"KHR_materials_volume": {"attenuationColor": [0.5, 0.5, 0.5]}});
    let mut doc = triangle_document(plain);
    doc["extensionsUsed"] = json!(["KHR_materials_volume"]);
    let mesh = read_document(&dir, "default.gltf", &doc);
    let volume = mesh.materials[0].physical.volume.expect("a volume");
    assert_eq!(volume.absorption(), DVec3::ZERO);
}

#[test]
fn the_absorption_coefficient_is_minus_the_log_of_the_colour_over_the_distance() {
    let v = Volume {
        attenuation_color: DVec3::new(0.5, 1.0, 0.0),
        attenuation_distance: 2.0,
    };
    let a = v.absorption();
    assert!((a.x - std::f64::consts::LN_2 / 2.0).abs() < 1e-15);
    assert_eq!(a.y, 0.0, "a channel of colour 1 is clear");
    assert_eq!(
        a.z,
        Volume::MAX_ABSORPTION,
        "a channel of colour 0 is opaque"
    );
    // After the distance, white light is the colour.
    assert!(((-a.x * 2.0).exp() - 0.5).abs() < 1e-15);
}

#[test]
fn scene_files_give_a_medium_and_write_it_back() {
    let scene = parse_ok(
        &glass("attenuation_color = [0.25, 0.5, 1]\nattenuation_distance = 3\n"),
        SceneFormat::Toml,
    );
    let volume = scene.materials[0].physical.volume.expect("a volume");
    assert_eq!(volume.attenuation_color, DVec3::new(0.25, 0.5, 1.0));
    assert_eq!(volume.attenuation_distance, 3.0);
    let text = scene_text(&scene, SceneFormat::Toml).unwrap();
    let again = parse_ok(&text, SceneFormat::Toml);
    assert_eq!(again.materials[0].physical.volume, Some(volume));
    // Without the keys the inside is clear.
    let clear = parse_ok(&glass(""), SceneFormat::Toml);
    assert_eq!(clear.materials[0].physical.volume, None);
}

#[test]
fn a_bad_attenuation_is_a_one_line_error_naming_its_key() {
    for (keys, key, words) in [
        (
            "attenuation_color = [0.5, 1.5, 1]\n",
            "materials.glass.attenuation_color",
            &["[0, 1]"][..],
        ),
        (
            "attenuation_color = [0.5, -1, 1]\n",
            "materials.glass.attenuation_color",
            &[][..],
        ),
        (
            "attenuation_distance = 0\n",
            "materials.glass.attenuation_distance",
            &["> 0"][..],
        ),
        (
            "attenuation_distance = -2\n",
            "materials.glass.attenuation_distance",
            &["> 0"][..],
        ),
    ] {
        let text = glass(keys);
        let e = parse_err(&text, SceneFormat::Toml);
        let line = text
            .lines()
            .position(|l| l.starts_with(keys.split(' ').next().unwrap()))
            .unwrap()
            + 1;
        assert_error(&e, file_of(SceneFormat::Toml), Some(line), Some(key), words);
    }
}
