//! Bad input through the `kdray` binary: out-of-range flags, broken scene
//! files and undrawable mesh files exit 2 with one line naming the file, line
//! and key, and leave an existing output as it was (no temporary file left).

use std::path::Path;

use crate::cli::{kdray, render_args, scene_path};
use crate::common;

use common::TempDir;

#[test]
fn out_of_range_size_and_bad_accel_are_usage_errors() {
    let dir = TempDir::new("usage");
    let seed = scene_path("seed.toml");
    for width in ["0", "16385"] {
        let run = kdray(
            &dir.path,
            &[
                "render", &seed, "-o", "out.png", "--width", width, "--height", "36",
            ],
        );
        assert_eq!(run.code, 2, "--width {width}: {run:#?}");
        let line = run.one_error_line();
        assert!(line.contains("--width"), "{line}");
        assert!(line.contains(width), "{line}");
    }
    let run = kdray(
        &dir.path,
        &render_args(&seed, &["-o", "out.png", "--accel", "nonsense"]),
    );
    assert_eq!(run.code, 2, "{run:#?}");
    assert!(!run.panicked(), "{run:#?}");
    assert!(!dir.join("out.png").exists());
}

/// A small valid scene; the cases below each break one part of it.
const BASE_SCENE: &str = r#"[camera]
position = [0.0, 0.0, 3.0]
look_at  = [0.0, 0.0, 0.0]

[[lights]]
position = [2.0, 2.0, 2.0]

[materials.red]
diffuse = [0.8, 0.1, 0.1]

[[spheres]]
center   = [0.0, 0.0, 0.0]
radius   = 1.0
material = "red"
"#;

const BASE_JSON: &str = r#"{
  "camera": { "position": [0.0, 0.0, 3.0], "look_at": [0.0, 0.0, 0.0] },
  "lights": [ { "position": [2.0, 2.0, 2.0] } ],
  "materials": { "red": { "diffuse": [0.8, 0.1, 0.1] } },
  "spheres": [
    {
      "center": [0.0, 0.0, 0.0],
      "radius": 1.0,
      "material": "red"
    }
  ]
}
"#;

/// `BASE_SCENE` with `from` replaced by `to` (which must occur).
fn base_with(from: &str, to: &str) -> String {
    assert!(BASE_SCENE.contains(from), "{from:?} not in the base scene");
    BASE_SCENE.replacen(from, to, 1)
}

/// 1-based line of the first line of `text` containing `needle`.
fn line_of(text: &str, needle: &str) -> usize {
    text.lines()
        .position(|l| l.contains(needle))
        .unwrap_or_else(|| panic!("{needle:?} not in {text}"))
        + 1
}

struct BadScene {
    name: &'static str,
    /// None: the file does not exist.
    text: Option<String>,
    /// The line of the fault, found by this text in the scene.
    line_of: Option<&'static str>,
    /// Further text the error line must contain (keys, file names).
    mentions: &'static [&'static str],
    /// The error is about another file (an OBJ) and names the scene's line
    /// in a trailing note, `(from KEY in SCENE:LINE)`, not as `SCENE:LINE:`.
    line_in_note: bool,
}

#[test]
fn bad_scenes_exit_2_with_one_line_and_leave_output_alone() {
    let dir = TempDir::new("bad-scenes");
    let cases = [
        BadScene {
            name: "missing.toml",
            text: None,
            line_of: None,
            mentions: &[],
            line_in_note: false,
        },
        BadScene {
            name: "malformed.toml",
            text: Some(base_with("radius   = 1.0", "radius   = = 1.0")),
            line_of: Some("radius"),
            mentions: &[],
            line_in_note: false,
        },
        BadScene {
            name: "unknown_key.toml",
            text: Some(base_with("radius   = 1.0", "radius   = 1.0\ncolour   = 3")),
            line_of: Some("colour"),
            mentions: &["spheres[0].colour"],
            line_in_note: false,
        },
        BadScene {
            name: "negative_radius.toml",
            text: Some(base_with("radius   = 1.0", "radius   = -1.0")),
            line_of: Some("radius"),
            mentions: &["spheres[0].radius"],
            line_in_note: false,
        },
        BadScene {
            name: "unknown_material.toml",
            text: Some(base_with("material = \"red\"", "material = \"blue\"")),
            line_of: Some("\"blue\""),
            mentions: &["spheres[0].material", "blue"],
            line_in_note: false,
        },
        BadScene {
            name: "nan.toml",
            text: Some(base_with("radius   = 1.0", "radius   = nan")),
            line_of: Some("nan"),
            mentions: &["spheres[0].radius"],
            line_in_note: false,
        },
        BadScene {
            name: "samples.toml",
            text: Some(format!("{BASE_SCENE}\n[render]\nsamples = 3\n")),
            line_of: Some("samples"),
            mentions: &["render.samples"],
            line_in_note: false,
        },
        BadScene {
            name: "missing_obj.toml",
            text: Some(format!(
                "{BASE_SCENE}\n[[meshes]]\npath = \"no-such-mesh.obj\"\nmaterial = \"red\"\n"
            )),
            line_of: Some("no-such-mesh.obj"),
            mentions: &["no-such-mesh.obj", "meshes[0].path"],
            line_in_note: true,
        },
        BadScene {
            name: "unknown_shape.toml",
            text: Some(format!(
                "{BASE_SCENE}\n[shapes.tri]\ntriangles = [[[0, 0, 0], [1, 0, 0], [0, 1, 0]]]\nmaterial = \"red\"\n[[instances]]\nshape = \"tree\"\n"
            )),
            line_of: Some("\"tree\""),
            mentions: &["instances[0].shape", "tree"],
            line_in_note: false,
        },
        BadScene {
            name: "singular_instance.toml",
            text: Some(format!(
                "{BASE_SCENE}\n[shapes.tri]\ntriangles = [[[0, 0, 0], [1, 0, 0], [0, 1, 0]]]\nmaterial = \"red\"\n[[instances]]\nshape = \"tri\"\nmatrix = [[1, 0, 0, 0], [1, 0, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]\n"
            )),
            line_of: Some("matrix"),
            mentions: &["instances[0].matrix", "singular"],
            line_in_note: false,
        },
        BadScene {
            name: "wrong_type.json",
            text: Some(BASE_JSON.replacen("\"radius\": 1.0", "\"radius\": \"big\"", 1)),
            line_of: Some("\"big\""),
            mentions: &["spheres[0].radius"],
            line_in_note: false,
        },
    ];

    let out = dir.join("out.png");
    let original = b"not a PNG, and must stay as it is".to_vec();
    std::fs::write(&out, &original).unwrap();
    for case in cases {
        let scene = match &case.text {
            Some(text) => dir.write(case.name, text),
            None => dir.join(case.name),
        };
        let scene = scene.to_str().unwrap();
        let run = kdray(&dir.path, &render_args(scene, &["-o", "out.png"]));
        assert_eq!(run.code, 2, "{}: {run:#?}", case.name);
        let line = run.one_error_line();
        assert!(
            line.contains(scene),
            "{}: no scene path in {line}",
            case.name
        );
        if let (Some(text), Some(needle)) = (&case.text, case.line_of) {
            let n = line_of(text, needle);
            let want = if case.line_in_note {
                format!("{scene}:{n})")
            } else {
                format!("{scene}:{n}:")
            };
            assert!(line.contains(&want), "{}: want {want} in {line}", case.name);
        }
        for m in case.mentions {
            assert!(line.contains(m), "{}: want {m} in {line}", case.name);
        }
        assert_eq!(std::fs::read(&out).unwrap(), original, "{}", case.name);
        assert!(
            dir.temp_files().is_empty(),
            "{}: {:?}",
            case.name,
            dir.temp_files()
        );
    }
}

/// Mesh files that cannot be drawn (binary data, no faces, a cut or corrupt
/// glTF, an unknown extension, a buffer outside the folder) are errors that
/// name the mesh file, never an empty mesh and a picture without the model.
#[test]
fn bad_mesh_files_exit_2_with_one_line_and_write_nothing() {
    let dir = TempDir::new("bad-meshes");
    let models = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/models");
    let glb = std::fs::read(models.join("tetra.glb")).unwrap();
    let external = std::fs::read_to_string(models.join("tetra_external.gltf")).unwrap();
    let binary: Vec<u8> = (0..=255).collect();
    let files: [(&str, Vec<u8>, &str); 8] = [
        ("binary.glb", binary.clone(), "not a valid glTF 2.0 file"),
        ("binary.obj", binary, "not a text OBJ file"),
        ("empty.obj", Vec::new(), "no faces"),
        (
            "points.obj",
            b"v 0 0 0\nv 1 0 0\nv 0 1 0\n".to_vec(),
            "no faces",
        ),
        ("cut.glb", glb[..600].to_vec(), "truncated GLB"),
        (
            "corrupt.gltf",
            b"{\"asset\": ".to_vec(),
            "not a valid glTF 2.0 file",
        ),
        (
            "model.ply",
            b"ply\n".to_vec(),
            "unknown mesh file extension",
        ),
        (
            "outside.gltf",
            external
                .replace("tetra.bin", "../../no/such/tetra.bin")
                .into_bytes(),
            "buffer 0: cannot read",
        ),
    ];
    for (name, bytes, words) in files {
        std::fs::write(dir.join(name), &bytes).unwrap();
        let scene = dir.write(
            "scene.toml",
            &format!("{BASE_SCENE}\n[[meshes]]\npath = \"{name}\"\nmaterial = \"red\"\n"),
        );
        let run = kdray(
            &dir.path,
            &render_args(scene.to_str().unwrap(), &["-o", "out.png"]),
        );
        assert_eq!(run.code, 2, "{name}: {run:#?}");
        let line = run.one_error_line();
        let file = dir.join(name);
        assert!(
            line.contains(&file.display().to_string()) && line.contains(words),
            "{name}: want {} and {words:?} in {line}",
            file.display()
        );
        assert!(
            !dir.join("out.png").exists(),
            "{name}: an image was written"
        );
        assert!(
            dir.temp_files().is_empty(),
            "{name}: {:?}",
            dir.temp_files()
        );
    }
}
