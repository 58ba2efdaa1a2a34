//! glTF alpha: alphaMode and alphaCutoff (default 0.5) and the base
//! colour's alpha become a material's `alpha`; BLEND warns once per file;
//! an alphaCutoff that is not a number >= 0 is a one-line error naming the
//! material and the key.

use super::authored_gltf::*;
use super::*;
use kdray_core::scene::{Alpha, AlphaMode};
use serde_json::json;

fn alpha_of(dir: &TempDir, name: &str, material: serde_json::Value) -> (Alpha, usize) {
    let mesh = read_document(dir, name, &triangle_document(material));
    (mesh.materials[0].alpha, mesh.warnings.len())
}

fn error_of(dir: &TempDir, name: &str, material: serde_json::Value) -> String {
    let path = write_document(dir, name, &triangle_document(material));
    match kdray_core::scene::gltf::load_gltf(&path, true, &mut |_| {}) {
        Ok(_) => panic!("{name}: expected an error"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn alpha_mode_cutoff_and_the_base_colour_alpha_are_read() {
    let dir = TempDir::new("gltf-alpha");
    let (opaque, warnings) = alpha_of(&dir, "opaque.gltf", json!({}));
    assert_eq!(opaque, Alpha::OPAQUE);
    assert_eq!(warnings, 0);
    let (mask, _) = alpha_of(
        &dir,
        "mask.gltf",
        json!({"alphaMode": "MASK", "alphaCutoff": 0.25,
               "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 0.75]}}),
    );
    assert_eq!(mask.mode, AlphaMode::Mask);
    assert_eq!(mask.cutoff, 0.25);
    assert_eq!(mask.factor, 0.75);
    let (default_cutoff, _) = alpha_of(&dir, "default.gltf", json!({"alphaMode": "MASK"}));
    assert_eq!(default_cutoff.cutoff, 0.5);
    // A cutoff above 1 is valid glTF: every point is a hole.
    let (high, _) = alpha_of(
        &dir,
        "high.gltf",
        json!({"alphaMode": "MASK", "alphaCutoff": 2}),
    );
    assert_eq!(high.cutoff, 2.0);
}

#[test]
fn blend_is_read_and_warned_about_once_per_file() {
    let dir = TempDir::new("gltf-alpha-blend");
    let mut doc = triangle_document(json!({"alphaMode": "BLEND"}));
    // Two BLEND materials, each used by a primitive: one warning.
    doc["materials"] = json!([{"alphaMode": "BLEND"}, {"alphaMode": "BLEND", "name": "b"}]);
    doc["meshes"][0]["primitives"] = json!([
        {"attributes": {"POSITION": 0}, "material": 0},
        {"attributes": {"POSITION": 0}, "material": 1}
    ]);
    let mesh = read_document(&dir, "blend.gltf", &doc);
    assert!(mesh
        .materials
        .iter()
        .all(|m| m.alpha.mode == AlphaMode::Blend));
    assert_eq!(mesh.materials.len(), 2);
    assert_eq!(mesh.warnings.len(), 1, "{:?}", mesh.warnings);
    assert!(
        mesh.warnings[0].message.contains("BLEND"),
        "{:?}",
        mesh.warnings
    );
}

#[test]
fn an_alpha_cutoff_that_is_negative_or_not_a_number_is_an_error_naming_the_key() {
    let dir = TempDir::new("gltf-alpha-bad");
    for (name, cutoff) in [
        ("negative.gltf", json!(-0.5)),
        ("string.gltf", json!("half")),
        ("list.gltf", json!([0.5])),
    ] {
        let e = error_of(
            &dir,
            name,
            json!({"alphaMode": "MASK", "alphaCutoff": cutoff}),
        );
        assert!(
            e.contains(name) && e.contains("materials[0].alphaCutoff") && e.contains(">= 0"),
            "{name}: {e}"
        );
        assert_eq!(e.lines().count(), 1, "{e}");
    }
    let e = error_of(&dir, "mode.gltf", json!({"alphaMode": "CLIP"}));
    assert!(e.contains("alphaMode"), "{e}");
    assert_eq!(e.lines().count(), 1, "{e}");
}
