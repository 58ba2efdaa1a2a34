//! `[[meshes]]` entries with OBJ files: the transform (scale, then rotate
//! in degrees about x, y, z, then translate), paths relative to the scene
//! file, materials from MTL files or the scene's override (the default grey,
//! with a warning, where the file names none it defines), and OBJ and MTL
//! errors named by their file and line.

use super::*;
use kdray_core::scene::mesh::MeshMaterial;
use kdray_core::scene::{load_scene_with, Warning};

/// Writes `scene.toml` in `dir` (the base scene plus `[[meshes]]` with the
/// given keys, in the given order) and returns its path.
fn mesh_scene(dir: &TempDir, mesh_keys: &[(&str, &str)]) -> PathBuf {
    let mut doc = base();
    for (key, value) in mesh_keys {
        doc = doc.set(&format!("meshes[0].{key}"), value);
    }
    dir.write("scene.toml", &doc.toml().text)
}

/// The one triangle of models/tri.obj after the mesh transform.
#[track_caller]
fn transformed(mesh_keys: &[(&str, &str)]) -> [DVec3; 3] {
    let dir = TempDir::new("xform");
    dir.write("models/tri.obj", ONE_TRIANGLE_OBJ);
    let mut keys = vec![("path", "\"models/tri.obj\""), ("material", "\"red\"")];
    keys.extend_from_slice(mesh_keys);
    let scene = load_ok(&mesh_scene(&dir, &keys));
    // triangles[0] is the scene's own [[triangles]] entry; meshes come after.
    assert_eq!(scene.triangles.len(), 2);
    scene.triangles[1].vertices
}

#[track_caller]
fn assert_vertices(got: [DVec3; 3], want: [[f64; 3]; 3]) {
    for (g, w) in got.into_iter().zip(want) {
        assert_close(g, DVec3::from_array(w));
    }
}

#[test]
fn no_transform_is_the_identity() {
    assert_vertices(transformed(&[]), [[0., 0., 0.], [1., 0., 0.], [0., 1., 0.]]);
    let explicit = [
        ("scale", "1"),
        ("rotate", "[0, 0, 0]"),
        ("translate", "[0, 0, 0]"),
    ];
    assert_vertices(
        transformed(&explicit),
        [[0., 0., 0.], [1., 0., 0.], [0., 1., 0.]],
    );
}

#[test]
fn rotations_are_degrees_about_the_world_axes() {
    // z by 90: x -> y, y -> -x.
    assert_vertices(
        transformed(&[("rotate", "[0, 0, 90]")]),
        [[0., 0., 0.], [0., 1., 0.], [-1., 0., 0.]],
    );
    // x by 90: y -> z.
    assert_vertices(
        transformed(&[("rotate", "[90, 0, 0]")]),
        [[0., 0., 0.], [1., 0., 0.], [0., 0., 1.]],
    );
    // y by 90: x -> -z.
    assert_vertices(
        transformed(&[("rotate", "[0, 90, 0]")]),
        [[0., 0., 0.], [0., 0., -1.], [0., 1., 0.]],
    );
}

#[test]
fn rotations_apply_x_then_y_then_z() {
    // Rz * Ry * Rx: x (1,0,0) -> Rx (1,0,0) -> Ry (0,0,-1) -> Rz (0,0,-1);
    //               y (0,1,0) -> Rx (0,0,1) -> Ry (1,0,0)  -> Rz (0,1,0).
    // (z first would send x to (0,0,1).)
    assert_vertices(
        transformed(&[("rotate", "[90, 90, 90]")]),
        [[0., 0., 0.], [0., 0., -1.], [0., 1., 0.]],
    );
    // Rz * Rx alone: y -> z under Rx, and z stays under Rz.
    assert_vertices(
        transformed(&[("rotate", "[90, 0, 90]")]),
        [[0., 0., 0.], [0., 1., 0.], [0., 0., 1.]],
    );
}

#[test]
fn scale_is_a_number_or_per_axis_and_comes_first() {
    assert_vertices(
        transformed(&[("scale", "[2, 1, 1]")]),
        [[0., 0., 0.], [2., 0., 0.], [0., 1., 0.]],
    );
    assert_vertices(
        transformed(&[("scale", "3")]),
        [[0., 0., 0.], [3., 0., 0.], [0., 3., 0.]],
    );
    assert_vertices(
        transformed(&[("scale", "0.5")]),
        [[0., 0., 0.], [0.5, 0., 0.], [0., 0.5, 0.]],
    );
    // Negative scales mirror; only 0 is refused.
    assert_vertices(
        transformed(&[("scale", "[-1, 1, 1]")]),
        [[0., 0., 0.], [-1., 0., 0.], [0., 1., 0.]],
    );
    // Scale before rotation: x is stretched, then turned onto y.
    assert_vertices(
        transformed(&[("scale", "[2, 1, 1]"), ("rotate", "[0, 0, 90]")]),
        [[0., 0., 0.], [0., 2., 0.], [-1., 0., 0.]],
    );
}

#[test]
fn translate_comes_last() {
    assert_vertices(
        transformed(&[("translate", "[1, 2, 3]")]),
        [[1., 2., 3.], [2., 2., 3.], [1., 3., 3.]],
    );
    // v' = Rz * Ry * Rx * (scale * v) + translate, keys in any order.
    assert_vertices(
        transformed(&[
            ("translate", "[1, 2, 3]"),
            ("rotate", "[0, 0, 90]"),
            ("scale", "2"),
        ]),
        [[1., 2., 3.], [1., 4., 3.], [-1., 2., 3.]],
    );
}

#[test]
fn a_zero_scale_is_an_error() {
    for bad in ["0", "[1, 0, 1]", "[0, 0, 0]", "-0.0"] {
        assert_rejected(
            &with_mesh().set("meshes[0].scale", bad),
            "meshes[0].scale",
            &["non-zero"],
        );
    }
}

#[test]
fn extreme_transforms() {
    let dir = TempDir::new("extreme");
    dir.write("tri.obj", ONE_TRIANGLE_OBJ);
    let mesh = |scale: &str| {
        base()
            .set("meshes[0].path", "\"tri.obj\"")
            .set("meshes[0].material", "\"red\"")
            .set("meshes[0].scale", scale)
            .toml()
    };
    // A triangle flattened below what f64 can hold is skipped, like any
    // zero-area face of an OBJ file.
    let scene = load_ok(&dir.write("flat.toml", &mesh("[1e-200, 1e-200, 1]").text));
    assert_eq!(scene.triangles.len(), 1);
    // A vertex sent past the largest f64 is an error on the scale.
    dir.write("tri.obj", "v 0 0 0\nv 1e300 0 0\nv 0 1 0\nf 1 2 3\n");
    let text = mesh("1e300");
    let path = dir.write("huge.toml", &text.text);
    let line = Some(text.line("meshes[0].scale"));
    let e = load_err(&path);
    assert_error(&e, &path, line, Some("meshes[0].scale"), &["non-finite"]);
}

#[test]
fn mesh_paths_are_relative_to_the_scene_file() {
    let dir = TempDir::new("relative");
    dir.write("sub/models/tri.obj", ONE_TRIANGLE_OBJ);
    dir.write("shared/tri.obj", ONE_TRIANGLE_OBJ);
    let doc = base()
        .set("meshes[0].path", "\"models/tri.obj\"")
        .set("meshes[0].material", "\"red\"")
        .set("meshes[1].path", "\"../shared/tri.obj\"")
        .set("meshes[1].material", "\"blue\"");
    for (name, text) in [
        ("sub/scene.toml", doc.toml()),
        ("sub/scene.json", doc.json()),
    ] {
        let scene = load_ok(&dir.write(name, &text.text));
        assert_eq!(scene.triangles.len(), 3);
    }
    // An absolute path is used as it is.
    let abs = dir.join("shared/tri.obj");
    let doc = base()
        .set("meshes[0].path", &format!("{:?}", abs.to_str().unwrap()))
        .set("meshes[0].material", "\"red\"");
    let scene = load_ok(&dir.write("elsewhere/scene.toml", &doc.toml().text));
    assert_eq!(scene.triangles.len(), 2);
}

#[test]
fn a_material_override_applies_to_every_face_and_skips_the_mtl() {
    let dir = TempDir::new("override");
    copy_torus(&dir, "models");
    let scene_path = mesh_scene(
        &dir,
        &[("path", "\"models/torus.obj\""), ("material", "\"red\"")],
    );
    let scene = load_ok(&scene_path);
    let names: Vec<_> = scene.materials.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(names, ["blue", "red"], "no MTL materials are added");
    let red = scene
        .materials
        .iter()
        .position(|m| m.name == "red")
        .unwrap() as u32;
    let mesh = &scene.triangles[1..];
    assert_eq!(mesh.len(), 48 * 24 * 2);
    assert!(mesh.iter().all(|t| t.material == red));

    // With an override the MTL file is never read: a missing one is fine.
    dir.write(
        "models/nomtl.obj",
        &format!("mtllib missing.mtl\nusemtl nothing\n{ONE_TRIANGLE_OBJ}"),
    );
    let scene_path = mesh_scene(
        &dir,
        &[("path", "\"models/nomtl.obj\""), ("material", "\"blue\"")],
    );
    assert_eq!(load_ok(&scene_path).triangles.len(), 2);
}

#[test]
fn without_an_override_faces_use_their_mtl_materials() {
    let dir = TempDir::new("mtl");
    let obj = copy_torus(&dir, "models");
    let scene = load_ok(&mesh_scene(&dir, &[("path", "\"models/torus.obj\"")]));

    let find = |name: &str| scene.materials.iter().position(|m| m.name == name);
    let gold = find("torus.obj:gold").expect("MTL materials are named file.obj:name");
    let teal = find("torus.obj:teal").unwrap();
    assert_eq!(scene.materials.len(), 4);
    assert_eq!(
        scene.materials[gold],
        Material {
            name: "torus.obj:gold".into(),
            ambient: DVec3::new(0.10, 0.08, 0.02),
            diffuse: DVec3::new(0.75, 0.58, 0.16),
            specular: DVec3::new(0.60, 0.55, 0.40),
            shininess: 128.0,
            reflection: 0.0,
            transmission: 0.0,
            ior: 1.5,
            texture: None,
            physical: kdray_core::scene::Physical::LAMBERTIAN,
            maps: kdray_core::scene::MaterialMaps::NONE,
            alpha: kdray_core::scene::Alpha::OPAQUE,
        }
    );
    assert_eq!(
        scene.materials[teal],
        Material {
            name: "torus.obj:teal".into(),
            ambient: DVec3::new(0.02, 0.08, 0.08),
            diffuse: DVec3::new(0.08, 0.50, 0.50),
            specular: DVec3::new(0.30, 0.30, 0.30),
            shininess: 64.0,
            reflection: 0.0,
            transmission: 0.0,
            ior: 1.5,
            texture: None,
            physical: kdray_core::scene::Physical::LAMBERTIAN,
            maps: kdray_core::scene::MaterialMaps::NONE,
            alpha: kdray_core::scene::Alpha::OPAQUE,
        }
    );
    // Face for face, the same triangles and materials as the OBJ loader gives.
    let raw = load_obj(&obj, true).unwrap();
    let mesh = &scene.triangles[1..];
    assert_eq!(mesh.len(), raw.triangles.len());
    for (t, r) in mesh.iter().zip(&raw.triangles) {
        assert_eq!(Some(t.vertices), raw.vertices(r));
        let want = format!("torus.obj:{}", raw.materials[r.material().unwrap()].name);
        assert_eq!(scene.materials[t.material as usize].name, want);
    }
    let gold_faces = mesh.iter().filter(|t| t.material == gold as u32).count();
    assert_eq!(gold_faces * 2, mesh.len(), "rings alternate gold and teal");
}

#[test]
fn a_missing_mtl_colour_is_black_and_reflection_is_zero() {
    let dir = TempDir::new("black");
    dir.write("m.mtl", "newmtl only_kd\nKd 0.2 0.4 0.6\n");
    dir.write(
        "m.obj",
        &format!("mtllib m.mtl\nusemtl only_kd\n{ONE_TRIANGLE_OBJ}"),
    );
    let scene = load_ok(&mesh_scene(&dir, &[("path", "\"m.obj\"")]));
    let m = scene
        .materials
        .iter()
        .find(|m| m.name == "m.obj:only_kd")
        .unwrap();
    assert_eq!(m.ambient, DVec3::ZERO);
    assert_eq!(m.diffuse, DVec3::new(0.2, 0.4, 0.6));
    assert_eq!(m.specular, DVec3::ZERO);
    assert_eq!(m.shininess, 0.0);
    assert_eq!(m.reflection, 0.0);
}

#[test]
fn obj_statements_and_index_forms() {
    let dir = TempDir::new("forms");
    // A quad written with every vertex form and negative indices,
    // plus a zero-area face (skipped silently inside an OBJ).
    dir.write(
        "m.obj",
        "# comment\no thing\ng group\ns off\n\
         v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\n\
         f 1 2/1 3//1 4/1/1\n\
         f -4 -3 -2 -1\n\
         f 1 2 2\n\
         f 1 2 1\n",
    );
    let scene = load_ok(&mesh_scene(
        &dir,
        &[("path", "\"m.obj\""), ("material", "\"red\"")],
    ));
    let mesh = &scene.triangles[1..];
    assert_eq!(
        mesh.len(),
        4,
        "two quads fan-triangulated; zero-area faces dropped"
    );
    let (a, b, c, d) = (DVec3::ZERO, DVec3::X, DVec3::new(1., 1., 0.), DVec3::Y);
    assert_eq!(mesh[0].vertices, [a, b, c]);
    assert_eq!(mesh[1].vertices, [a, c, d]);
    assert_eq!(mesh[2].vertices, [a, b, c]);
    assert_eq!(mesh[3].vertices, [a, c, d]);
}

#[test]
fn an_obj_that_cannot_be_read_names_the_obj_and_the_mesh_entry() {
    let dir = TempDir::new("noobj");
    let doc = base().set("meshes[0].path", "\"models/nope.obj\"");
    for (name, text) in [("scene.toml", doc.toml()), ("scene.json", doc.json())] {
        let scene_path = dir.write(name, &text.text);
        let e = load_err(&scene_path);
        let line = text.line("meshes[0].path");
        let at = format!("{}:{line}", scene_path.display());
        assert_error(
            &e,
            &dir.join("models/nope.obj"),
            None,
            None,
            &["cannot read OBJ file", "meshes[0].path", &at],
        );
    }
    // The same for a folder where the file should be.
    std::fs::create_dir_all(dir.join("models/folder.obj")).unwrap();
    let scene_path = mesh_scene(&dir, &[("path", "\"models/folder.obj\"")]);
    let e = load_err(&scene_path);
    assert_error(
        &e,
        &dir.join("models/folder.obj"),
        None,
        None,
        &["cannot read OBJ file"],
    );
}

#[test]
fn a_bad_obj_line_names_the_obj_line_and_statement() {
    let dir = TempDir::new("badobj");
    let cases: &[(&str, usize, &str)] = &[
        ("v 0 0 0\nv 1 2\n", 2, "v"),
        ("v 0 0 0\nv 1 0 nan\n", 2, "v"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 4\n", 5, "f"),
        ("v 0 0 0\nf 0 1 1\n", 2, "f"),
    ];
    for &(text, line, key) in cases {
        let obj = dir.write("m.obj", text);
        let scene_path = mesh_scene(&dir, &[("path", "\"m.obj\""), ("material", "\"red\"")]);
        let e = load_err(&scene_path);
        assert_error(&e, &obj, Some(line), Some(key), &[]);
    }
}

/// A scene loaded with its warnings collected instead of printed.
fn load_with_warnings(path: &Path) -> (Scene, Vec<Warning>) {
    let mut warnings = Vec::new();
    let scene = load_scene_with(path, &mut |_| {}, &mut |w| warnings.push(w))
        .unwrap_or_else(|e| panic!("expected {} to load, got: {e}", path.display()));
    (scene, warnings)
}

#[test]
fn a_face_without_a_material_gets_the_default_grey_and_one_warning_naming_file_and_line() {
    let dir = TempDir::new("nomat");
    dir.write("m.mtl", "newmtl a\nKd 1 0 0\n");
    // (OBJ text, line of the warning, words in it)
    let cases: &[(&str, usize, &[&str])] = &[
        // No usemtl before the face: at the face.
        (
            "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
            5,
            &["no material", "default grey"],
        ),
        // No mtllib/usemtl at all.
        (
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
            4,
            &["no material", "default grey"],
        ),
        // A usemtl naming a material the MTL does not define: at the usemtl.
        (
            "mtllib m.mtl\nusemtl b\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
            2,
            &["'b'", "not defined", "default grey"],
        ),
        // An MTL file that is not there: at the mtllib, and only there.
        (
            "mtllib gone.mtl\nusemtl a\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
            1,
            &["cannot read mtl file", "gone.mtl", "default grey"],
        ),
    ];
    for &(text, line, words) in cases {
        let obj = dir.write("m.obj", text);
        let scene_path = mesh_scene(&dir, &[("path", "\"m.obj\"")]);
        let (scene, warnings) = load_with_warnings(&scene_path);
        assert_eq!(warnings.len(), 1, "{text:?}: {warnings:?}");
        let w = &warnings[0];
        assert_eq!(
            (w.file.as_path(), w.line),
            (obj.as_path(), Some(line)),
            "{w}"
        );
        let shown = w.to_string();
        assert!(
            shown.starts_with(&format!("{}:{line}: warning: ", obj.display())),
            "{shown}"
        );
        assert!(!shown.contains('\n'), "{shown}");
        for word in words {
            assert!(
                shown.to_lowercase().contains(word),
                "{shown:?} lacks {word:?}"
            );
        }
        // The mesh's triangle (the last; the base scene has one) is grey.
        let grey = MeshMaterial::default_grey();
        let mesh_triangles = &scene.triangles[scene.triangles.len() - 1..];
        for t in mesh_triangles {
            let m = &scene.materials[t.material as usize];
            assert_eq!(
                (m.ambient, m.diffuse),
                (grey.ambient, grey.diffuse),
                "{m:?}"
            );
            assert!(m.name.ends_with(&grey.name), "{m:?}");
        }
        // With a `material` override the same OBJ is fine, with no warning.
        let scene_path = mesh_scene(&dir, &[("path", "\"m.obj\""), ("material", "\"red\"")]);
        let (scene, warnings) = load_with_warnings(&scene_path);
        assert_eq!(scene.triangles.len(), 2);
        assert!(warnings.is_empty(), "{warnings:?}");
    }
}

#[test]
fn negative_mtl_colours_are_errors() {
    let dir = TempDir::new("negmtl");
    dir.write("m.mtl", "newmtl dark\nKd 0.5 0.5 0.5\nKs 0.1 -0.2 0.1\n");
    dir.write(
        "m.obj",
        &format!("mtllib m.mtl\nusemtl dark\n{ONE_TRIANGLE_OBJ}"),
    );
    let doc = base().set("meshes[0].path", "\"m.obj\"");
    let text = doc.toml();
    let scene_path = dir.write("scene.toml", &text.text);
    let e = load_err(&scene_path);
    let line = Some(text.line("meshes[0].path"));
    let words = ["\"dark\"", "Ks", ">= 0"];
    assert_error(&e, &scene_path, line, Some("meshes[0].path"), &words);
    // Unused by the override, the MTL does not matter.
    let doc = doc.set("meshes[0].material", "\"red\"");
    assert_eq!(
        load_ok(&dir.write("scene.toml", &doc.toml().text))
            .triangles
            .len(),
        2
    );
}

#[test]
fn mtl_errors_name_the_mtl_file() {
    let dir = TempDir::new("badmtl");
    let mtl = dir.write("m.mtl", "newmtl a\nKd 1 0\n");
    dir.write(
        "m.obj",
        &format!("mtllib m.mtl\nusemtl a\n{ONE_TRIANGLE_OBJ}"),
    );
    let e = load_err(&mesh_scene(&dir, &[("path", "\"m.obj\"")]));
    assert_error(&e, &mtl, Some(2), Some("Kd"), &["expected 3 numbers"]);
}

#[test]
fn the_same_obj_twice_gives_two_copies() {
    let dir = TempDir::new("twice");
    copy_torus(&dir, "models");
    let doc = base()
        .set("meshes[0].path", "\"models/torus.obj\"")
        .set("meshes[1].path", "\"models/torus.obj\"")
        .set("meshes[1].translate", "[3, 0, 0]");
    let scene = load_ok(&dir.write("scene.toml", &doc.toml().text));
    let n = 48 * 24 * 2;
    assert_eq!(scene.triangles.len(), 1 + 2 * n);
    for (a, b) in scene.triangles[1..=n].iter().zip(&scene.triangles[n + 1..]) {
        for (va, vb) in a.vertices.iter().zip(b.vertices) {
            assert_close(vb, *va + DVec3::new(3.0, 0.0, 0.0));
        }
    }
}
