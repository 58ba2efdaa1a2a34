//! glTF emission: emissiveFactor times `KHR_materials_emissive_strength`'s
//! emissiveStrength is a material's `emission`.

use super::authored_gltf::*;
use super::*;
use serde_json::json;

fn emissive(factor: [f64; 3], strength: Option<f64>) -> serde_json::Value {
    let mut material = json!({"emissiveFactor": factor});
    if let Some(s) = strength {
        material["extensions"] =
            json!({"KHR_materials_emissive_strength": {"emissiveStrength": s}});
    }
    material
}

fn emission_of(dir: &TempDir, name: &str, material: serde_json::Value) -> DVec3 {
    let mut doc = triangle_document(material);
    doc["extensionsUsed"] = json!(["KHR_materials_emissive_strength"]);
    let mesh = read_document(dir, name, &doc);
    assert!(mesh.warnings.is_empty(), "{name}: {:?}", mesh.warnings);
    mesh.materials[0].physical.emission
}

#[test]
fn emissive_strength_multiplies_the_emissive_factor() {
    let dir = TempDir::new("emissive-strength");
    let factor = [1.0, 0.5, 0.25];
    let strong = emission_of(&dir, "strong.gltf", emissive(factor, Some(4.0)));
    assert_eq!(strong, DVec3::new(4.0, 2.0, 1.0));
    // Strength 4 of a quarter is strength 1 of the whole factor.
    let quarter = emission_of(
        &dir,
        "quarter.gltf",
        emissive([0.25, 0.125, 0.0625], Some(4.0)),
    );
    let whole = emission_of(&dir, "whole.gltf", emissive([1.0, 0.5, 0.25], Some(1.0)));
    assert_eq!(quarter, whole);
    assert_eq!(whole, DVec3::new(1.0, 0.5, 0.25));
    // Without the extension the strength is 1.
    let plain = emission_of(&dir, "plain.gltf", emissive(factor, None));
    assert_eq!(plain, DVec3::new(1.0, 0.5, 0.25));
}

#[test]
fn emissive_strength_reaches_the_scene_of_a_mesh_entry() {
    let dir = TempDir::new("emissive-strength-scene");
    let mut doc = triangle_document(emissive([0.5, 0.5, 0.5], Some(3.0)));
    doc["extensionsRequired"] = json!(["KHR_materials_emissive_strength"]);
    doc["extensionsUsed"] = json!(["KHR_materials_emissive_strength"]);
    write_document(&dir, "lamp.gltf", &doc);
    let scene = dir.write(
        "scene.toml",
        "[camera]\nposition = [0, 0, 5]\nlook_at = [0, 0, 0]\n\n[[lights]]\nposition = [0, 5, 5]\n\n[[meshes]]\npath = \"lamp.gltf\"\n",
    );
    let scene = load_ok(&scene);
    let emissions: Vec<DVec3> = scene
        .materials
        .iter()
        .map(|m| m.physical.emission)
        .collect();
    assert_eq!(emissions, vec![DVec3::splat(1.5)]);
}
