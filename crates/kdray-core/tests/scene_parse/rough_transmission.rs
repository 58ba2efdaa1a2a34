//! The roughness of a transmission and thin walls: glTF's
//! `KHR_materials_transmission` with the material's roughness (thin-walled
//! unless `KHR_materials_volume` gives a thickness), and the scene file's
//! `transmission_roughness` and `thin_walled`, as the kernel reads them.

use super::authored_gltf::*;
use super::*;
use kdray_core::prepare::{Accel, PreparedScene};
use kdray_core::scene::scene_text;
use serde_json::json;

const SCENE: &str =
    "[camera]\nposition = [0, 0, 5]\nlook_at = [0, 0, 0]\n\n[[lights]]\nposition = [0, 5, 5]\n\n";

fn glass(keys: &str) -> String {
    format!("{SCENE}[materials.glass]\ndiffuse = [1, 1, 1]\ntransmission = 1\n{keys}\n[[spheres]]\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"glass\"\n")
}

/// A glTF material's roughness is its transmission's too, and reaches the
/// kernel's material record; without a volume (or with thickness 0) the
/// surface is thin-walled, with a thickness it bounds a volume. The
/// extensions raise no warning.
#[test]
fn gltf_transmission_takes_the_materials_roughness_and_is_thin_without_a_volume() {
    let dir = TempDir::new("gltf-rough-transmission");
    for (volume, thin) in [
        (None, true),
        (Some(json!({"thicknessFactor": 0.0})), true),
        (Some(json!({"thicknessFactor": 0.2})), false),
    ] {
        let mut material = json!({"pbrMetallicRoughness": {"roughnessFactor": 0.625}});
        material["extensions"] = json!({"KHR_materials_transmission": {"transmissionFactor": 1.0}});
        let mut used = vec!["KHR_materials_transmission"];
        if let Some(v) = volume {
            material["extensions"]["KHR_materials_volume"] = v;
            used.push("KHR_materials_volume");
        }
        let mut doc = triangle_document(material);
        doc["extensionsUsed"] = json!(used);
        let mesh = read_document(&dir, "frosted.gltf", &doc);
        assert!(
            mesh.warnings
                .iter()
                .all(|w| !w.to_string().contains("KHR_materials")),
            "{:?}",
            mesh.warnings
        );
        let physical = mesh.materials[0].physical;
        assert_eq!(physical.transmission_roughness, 0.625);
        assert_eq!(physical.thin_walled, thin);
    }
}

/// The scene file's keys reach the kernel's record and are written back.
#[test]
fn scene_files_give_a_rough_transmission_and_write_it_back() {
    let scene = parse_ok(
        &glass("transmission_roughness = 0.375\nthin_walled = true\n"),
        SceneFormat::Toml,
    );
    let physical = scene.materials[0].physical;
    assert_eq!(physical.transmission_roughness, 0.375);
    assert!(physical.thin_walled);
    let arrays = PreparedScene::new(scene.clone(), Accel::Kdtree).arrays;
    assert_eq!(arrays.materials[0].transmission_roughness, 0.375);
    assert_eq!(arrays.materials[0].thin_walled, 1);
    let text = scene_text(&scene, SceneFormat::Toml).unwrap();
    let again = parse_ok(&text, SceneFormat::Toml);
    assert_eq!(again.materials[0].physical, physical);
    // Without the keys: smooth glass around a volume.
    let plain = parse_ok(&glass(""), SceneFormat::Toml);
    assert_eq!(plain.materials[0].physical.transmission_roughness, 0.0);
    assert!(!plain.materials[0].physical.thin_walled);
}

#[test]
fn a_bad_transmission_roughness_is_a_one_line_error_naming_its_key() {
    for keys in [
        "transmission_roughness = 1.5\n",
        "transmission_roughness = -0.1\n",
    ] {
        let text = glass(keys);
        let e = parse_err(&text, SceneFormat::Toml);
        let line = text
            .lines()
            .position(|l| l.starts_with("transmission_roughness"))
            .unwrap()
            + 1;
        assert_error(
            &e,
            file_of(SceneFormat::Toml),
            Some(line),
            Some("materials.glass.transmission_roughness"),
            &["[0, 1]"],
        );
    }
}
