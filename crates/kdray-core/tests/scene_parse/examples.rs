//! Complete scenes: the documented examples in TOML and JSON give the
//! documented values, and the same scene in both formats is equal.

use super::*;

/// The example of the contract, with the shipped torus as its mesh.
const EXAMPLE_TOML: &str = r#"
[camera]
position = [0.0, 0.0, 1.0]      # eye point, the origin of every primary ray
look_at  = [0.0, 0.0, 0.0]
up       = [0.0, 1.0, 0.0]
vfov     = 58.7155

[render]
width         = 1920
height        = 1080
min_intensity = 0.05
max_depth     = 10
background    = [0.0, 0.0, 0.0]
shadow_mode   = "ambient"
samples       = 1

[[lights]]
position = [5.0, 5.0, 5.0]
ambient  = [1.0, 1.0, 1.0]
diffuse  = [1.0, 1.0, 1.0]
specular = [1.0, 1.0, 1.0]

[materials.red]
ambient    = [0.1, 0.0, 0.0]
diffuse    = [0.7, 0.0, 0.0]
specular   = [1.0, 1.0, 1.0]
shininess  = 100.0
reflection = 0.5

[[spheres]]
center   = [-0.2, 0.0, -1.0]
radius   = 0.7
material = "red"

[[triangles]]
vertices = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
material = "red"

[[meshes]]
path      = "models/torus.obj"
material  = "red"
scale     = 1.0
rotate    = [0.0, 0.0, 0.0]
translate = [0.0, 0.0, 0.0]
"#;

const EXAMPLE_JSON: &str = r#"{
  "camera": {
"position": [0.0, 0.0, 1.0],
"look_at": [0.0, 0.0, 0.0],
"up": [0.0, 1.0, 0.0],
"vfov": 58.7155
  },
  "render": {
"width": 1920, "height": 1080, "min_intensity": 0.05, "max_depth": 10,
"background": [0.0, 0.0, 0.0], "shadow_mode": "ambient", "samples": 1
  },
  "lights": [
{"position": [5.0, 5.0, 5.0], "ambient": [1.0, 1.0, 1.0],
 "diffuse": [1.0, 1.0, 1.0], "specular": [1.0, 1.0, 1.0]}
  ],
  "materials": {
"red": {"ambient": [0.1, 0.0, 0.0], "diffuse": [0.7, 0.0, 0.0],
        "specular": [1.0, 1.0, 1.0], "shininess": 100.0, "reflection": 0.5}
  },
  "spheres": [{"center": [-0.2, 0.0, -1.0], "radius": 0.7, "material": "red"}],
  "triangles": [
{"vertices": [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], "material": "red"}
  ],
  "meshes": [
{"path": "models/torus.obj", "material": "red", "scale": 1.0,
 "rotate": [0.0, 0.0, 0.0], "translate": [0.0, 0.0, 0.0]}
  ]
}"#;

#[test]
fn the_contract_example_has_every_value() {
    let dir = TempDir::new("example");
    let obj = copy_torus(&dir, "models");
    let scene = load_ok(&dir.write("example.toml", EXAMPLE_TOML));

    assert_eq!(
        scene.camera,
        Camera {
            position: DVec3::new(0.0, 0.0, 1.0),
            look_at: DVec3::ZERO,
            up: DVec3::Y,
            vfov_degrees: 58.7155,
        }
    );
    assert_eq!(
        scene.render,
        RenderSettings {
            width: 1920,
            height: 1080,
            min_intensity: 0.05,
            max_depth: 10,
            background: DVec3::ZERO,
            shadow_mode: ShadowMode::Ambient,
            samples: 1,
            integrator: kdray_core::scene::Integrator::Whitted,
            seed: 0,
            tone_map: kdray_core::scene::ToneMap::Aces,
            exposure: 0.0,
            denoise: false,
        }
    );
    assert_eq!(
        scene.lights,
        vec![Light {
            position: DVec3::splat(5.0),
            ambient: DVec3::ONE,
            diffuse: DVec3::ONE,
            specular: DVec3::ONE,
            kind: LightKind::Point,
            reference_distance: None,
        }]
    );
    assert_eq!(
        scene.materials,
        vec![Material {
            name: "red".into(),
            ambient: DVec3::new(0.1, 0.0, 0.0),
            diffuse: DVec3::new(0.7, 0.0, 0.0),
            specular: DVec3::ONE,
            shininess: 100.0,
            reflection: 0.5,
            transmission: 0.0,
            ior: 1.5,
            texture: None,
            physical: kdray_core::scene::Physical::LAMBERTIAN,
            maps: kdray_core::scene::MaterialMaps::NONE,
            alpha: kdray_core::scene::Alpha::OPAQUE,
        }]
    );
    assert_eq!(
        scene.spheres,
        vec![Sphere {
            center: DVec3::new(-0.2, 0.0, -1.0),
            radius: 0.7,
            material: 0,
        }]
    );
    assert_eq!(
        scene.triangles[0],
        Triangle::flat([DVec3::ZERO, DVec3::X, DVec3::Y], 0)
    );
    // The mesh, untransformed, all red.
    let raw = load_obj(&obj, false).unwrap();
    assert_eq!(scene.triangles.len(), 1 + raw.triangles.len());
    for (t, r) in scene.triangles[1..].iter().zip(&raw.triangles) {
        assert_eq!(Some(t.vertices), raw.vertices(r));
        assert_eq!(t.material, 0);
    }
    assert_eq!(scene.object_count(), 2 + raw.triangles.len());
}

#[test]
fn the_contract_example_in_json_is_the_same_scene() {
    let dir = TempDir::new("example-json");
    copy_torus(&dir, "models");
    let toml = load_ok(&dir.write("example.toml", EXAMPLE_TOML));
    let json = load_ok(&dir.write("example.json", EXAMPLE_JSON));
    assert_eq!(toml, json);
}

#[test]
fn a_scene_with_every_kind_of_entry_is_the_same_in_toml_and_json() {
    let dir = TempDir::new("same");
    copy_torus(&dir, "models");
    dir.write("models/tri.obj", ONE_TRIANGLE_OBJ);
    let doc = two_triangles()
        .set("camera.up", "[0, 1, 0.5]")
        .set("camera.vfov", "45")
        .set("render.width", "320")
        .set("render.height", "240")
        .set("render.min_intensity", "0.01")
        .set("render.max_depth", "5")
        .set("render.background", "[0.2, 0.3, 0.4]")
        .set("render.shadow_mode", "\"seed\"")
        .set("render.samples", "4")
        .set("lights[0].ambient", "[0.1, 0.1, 0.1]")
        .set("lights[1].position", "[-3, 2, 1]")
        .set("lights[1].specular", "[0.5, 0.5, 0.5]")
        .set("materials.red.specular", "[1, 1, 1]")
        .set("materials.red.shininess", "64")
        .set("materials.red.reflection", "0.25")
        .set("spheres[1].center", "[1, 1, -2]")
        .set("spheres[1].radius", "0.3")
        .set("spheres[1].material", "\"blue\"")
        .set("meshes[0].path", "\"models/torus.obj\"")
        .set("meshes[0].scale", "[0.5, 1, 2]")
        .set("meshes[0].rotate", "[10, 20, 30]")
        .set("meshes[0].translate", "[0, -1, -4]")
        .set("meshes[1].path", "\"models/tri.obj\"")
        .set("meshes[1].material", "\"red\"")
        .set("meshes[1].scale", "2");
    let toml = load_ok(&dir.write("scene.toml", &doc.toml().text));
    let json = load_ok(&dir.write("scene.json", &doc.json().text));
    assert_eq!(toml, json);
    assert_eq!(toml.lights.len(), 2);
    assert_eq!(toml.spheres.len(), 2);
    assert_eq!(toml.triangles.len(), 2 + 48 * 24 * 2 + 1);
    assert_eq!(toml.materials.len(), 4);
}

/// The first fenced block of `lang` after `heading` in docs/scene-format.md.
fn docs_block(doc: &str, heading: &str, lang: &str) -> String {
    let after = &doc[doc
        .find(heading)
        .unwrap_or_else(|| panic!("no {heading:?} in the docs"))..];
    let fence = format!("```{lang}\n");
    let start = after
        .find(&fence)
        .unwrap_or_else(|| panic!("no {lang} block after {heading:?}"))
        + fence.len();
    let len = after[start..].find("```").unwrap();
    after[start..start + len].to_string()
}

#[test]
fn the_complete_example_in_the_docs_parses_the_same_in_toml_and_json() {
    let path = common::repo_path("docs/scene-format.md");
    let doc = std::fs::read_to_string(&path).unwrap();
    let dir = TempDir::new("docs");
    copy_torus(&dir, "models");
    let toml = load_ok(&dir.write(
        "example.toml",
        &docs_block(&doc, "## Complete example", "toml"),
    ));
    let json = load_ok(&dir.write(
        "example.json",
        &docs_block(&doc, "## Complete example", "json"),
    ));
    assert_eq!(toml, json);
    assert!(!toml.spheres.is_empty() && toml.triangles.len() > 1);
    // The error line quoted in the docs is what the code prints.
    let bad = docs_block(&doc, "## Errors", "toml");
    let shown = parse_err(&bad, SceneFormat::Toml).to_string();
    assert!(
        doc.contains(&shown.replace(TOML_FILE, "scene.toml")),
        "the docs should quote: {shown}"
    );
}
