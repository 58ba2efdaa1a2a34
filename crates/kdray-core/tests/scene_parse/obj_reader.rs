//! The OBJ and MTL reader on its own (`kdray_core::scene::obj`): statements,
//! index forms, materials, and every error with its file, line and
//! statement.

use std::path::{Path, PathBuf};

use glam::DVec3;
use kdray_core::scene::mesh::{Mesh, MeshMaterial, MeshTriangle, NO_INDEX};
use kdray_core::scene::obj::{load_obj, parse_obj};
use kdray_core::scene::SceneError;
use std::sync::atomic::{AtomicUsize, Ordering};

fn p() -> &'static Path {
    Path::new("mesh.obj")
}

fn parse(text: &str) -> Mesh {
    parse_obj(text, p(), false).unwrap_or_else(|e| panic!("parse failed: {e}"))
}

fn parse_err(text: &str, with_materials: bool) -> SceneError {
    match parse_obj(text, p(), with_materials) {
        Ok(mesh) => panic!("expected an error, got {mesh:?}"),
        Err(e) => e,
    }
}

fn assert_err(e: &SceneError, file: &Path, line: usize, key: &str) {
    assert_eq!(e.file, file, "{e}");
    assert_eq!(e.line, Some(line), "{e}");
    assert_eq!(e.key.as_deref(), Some(key), "{e}");
    assert!(!e.message.is_empty());
    assert!(!e.to_string().contains('\n'));
}

/// `mesh` has exactly one warning, at `file`:`line`, containing `words`.
#[track_caller]
fn assert_warning(mesh: &Mesh, file: &Path, line: usize, words: &[&str]) {
    assert_eq!(mesh.warnings.len(), 1, "{:?}", mesh.warnings);
    let w = &mesh.warnings[0];
    assert_eq!((w.file.as_path(), w.line), (file, Some(line)), "{w}");
    for word in words {
        assert!(w.message.contains(word), "{w} lacks {word:?}");
    }
}

fn d(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

/// The vertices of triangle `i` of `mesh`.
fn vertices(mesh: &Mesh, i: usize) -> [DVec3; 3] {
    mesh.vertices(&mesh.triangles[i]).unwrap()
}

/// A fresh folder under the temp dir, unique per process and call.
fn temp_dir(tag: &str) -> PathBuf {
    static COUNTER: AtomicUsize = AtomicUsize::new(0);
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    let dir = std::env::temp_dir().join(format!("kdray-obj-test-{}-{tag}-{n}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

const SQUARE: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";

#[test]
fn single_triangle() {
    let mesh = parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    assert_eq!(
        mesh.triangles,
        vec![MeshTriangle {
            corners: [0, 1, 2],
            normals: [NO_INDEX; 3],
            uvs: [NO_INDEX; 3],
            material: NO_INDEX
        }]
    );
    assert_eq!(
        mesh.positions,
        [d(0., 0., 0.), d(1., 0., 0.), d(0., 1., 0.)]
    );
    assert!(mesh.normals.is_empty());
    assert!(mesh.materials.is_empty());
}

#[test]
fn w_coordinate_is_ignored() {
    let mesh = parse("v 0 0 0 1\nv 1 0 0 0.5\nv 0 1 0 2\nf 1 2 3\n");
    assert_eq!(
        vertices(&mesh, 0),
        [d(0., 0., 0.), d(1., 0., 0.), d(0., 1., 0.)]
    );
}

#[test]
fn quad_is_fan_triangulated() {
    let mesh = parse(&format!("{SQUARE}f 1 2 3 4\n"));
    let [a, b, c, e] = [d(0., 0., 0.), d(1., 0., 0.), d(1., 1., 0.), d(0., 1., 0.)];
    assert_eq!(mesh.triangles.len(), 2);
    assert_eq!(vertices(&mesh, 0), [a, b, c]);
    assert_eq!(vertices(&mesh, 1), [a, c, e]);
}

#[test]
fn pentagon_gives_three_triangles() {
    let text = "v 0 0 0\nv 2 0 0\nv 3 1 0\nv 1 2 0\nv -1 1 0\nf 1 2 3 4 5\n";
    let mesh = parse(text);
    let v = [
        d(0., 0., 0.),
        d(2., 0., 0.),
        d(3., 1., 0.),
        d(1., 2., 0.),
        d(-1., 1., 0.),
    ];
    let got: Vec<_> = (0..mesh.triangles.len())
        .map(|i| vertices(&mesh, i))
        .collect();
    assert_eq!(
        got,
        vec![[v[0], v[1], v[2]], [v[0], v[2], v[3]], [v[0], v[3], v[4]]]
    );
}

#[test]
fn all_vertex_token_forms() {
    let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\n\
                f 1 2 3\nf 1/1 2/2 3/3\nf 1//1 2//1 3//1\nf 1/1/1 2/2/1 3/3/1\n";
    let mesh = parse(text);
    assert_eq!(mesh.triangles.len(), 4);
    for i in 0..4 {
        assert_eq!(
            vertices(&mesh, i),
            [d(0., 0., 0.), d(1., 0., 0.), d(0., 1., 0.)]
        );
    }
    // Only the `v//vn` and `v/vt/vn` forms name normals.
    let normals: Vec<_> = mesh.triangles.iter().map(|t| t.normals).collect();
    assert_eq!(normals, [[NO_INDEX; 3], [NO_INDEX; 3], [0; 3], [0; 3]]);
}

#[test]
fn negative_indices_are_relative_to_vertices_so_far() {
    // -1 is the last vertex defined before the face, not in the file.
    let text =
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nv 5 5 5\nv 6 5 5\nvn 0 0 1\nf -5//1 -1//1 -2//1\n";
    let mesh = parse(text);
    assert_eq!(
        vertices(&mesh, 0),
        [d(0., 0., 0.), d(1., 0., 0.), d(0., 1., 0.)]
    );
    assert_eq!(
        vertices(&mesh, 1),
        [d(0., 0., 0.), d(6., 5., 5.), d(5., 5., 5.)]
    );
    assert_eq!(mesh.triangles[1].corners, [0, 4, 3]);
    assert_eq!(mesh.triangles[1].normals, [0; 3]);
}

#[test]
fn zero_area_faces_are_skipped() {
    // Repeated vertex, collinear vertices; then a quad whose first fan
    // triangle is degenerate but whose second is not.
    let text = "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\n\
                f 1 1 4\nf 1 2 3\nf 1 2 3 4\n";
    let mesh = parse(text);
    assert_eq!(mesh.triangles.len(), 1);
    assert_eq!(
        vertices(&mesh, 0),
        [d(0., 0., 0.), d(2., 0., 0.), d(0., 1., 0.)]
    );
    // Tiny but non-zero area is kept...
    let mesh = parse("v 0 0 0\nv 1e-10 0 0\nv 0 1e-10 0\nf 1 2 3\n");
    assert_eq!(mesh.triangles.len(), 1);
    // ...unless the cross product's length underflows to 0 in f64 (its
    // normal could not be computed either).
    let mesh = parse("v 0 0 0\nv 1e-100 0 0\nv 0 1e-100 0\nf 1 2 3\n");
    assert_eq!(mesh.triangles.len(), 0);
}

#[test]
fn ignored_statements_comments_crlf_and_whitespace() {
    let text =
        "# a comment\r\n\r\n  \t \r\nmtllib nowhere.mtl\r\no thing\r\ng group\r\ns 1\r\ns off\r\n\
                vt 0.5 0.5\r\nvn 0 0 1\r\nvp 0.1 0.2\r\nusemtl nothing\r\n\
                v   0\t0   0   # trailing comment\r\nv 1 0 0#glued\r\nv 0 1 0\r\n\
                l 1 2\r\np 1\r\ncstype bspline\r\nfoo bar baz\r\n\
                f  1   2\t3  # the face\r\n#f 1 2\r\n";
    let mesh = parse(text);
    assert_eq!(mesh.triangles.len(), 1);
    assert_eq!(
        vertices(&mesh, 0),
        [d(0., 0., 0.), d(1., 0., 0.), d(0., 1., 0.)]
    );
}

#[test]
fn byte_order_mark_is_skipped() {
    let mesh = parse("\u{feff}v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    assert_eq!(mesh.triangles.len(), 1);
}

#[test]
fn material_names_may_contain_spaces() {
    let dir = temp_dir("spaces");
    let obj = dir.join("m.obj");
    std::fs::write(
        &obj,
        "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl  my gold  # c\nf 1 2 3\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("m.mtl"),
        "\u{feff}newmtl my gold\t\r\n  Kd 1 1 0\r\n",
    )
    .unwrap();
    let mesh = load_obj(&obj, true).unwrap();
    assert_eq!(mesh.materials[0].name, "my gold");
    assert_eq!(mesh.materials[0].diffuse, d(1., 1., 0.));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn empty_input_is_an_empty_mesh() {
    assert_eq!(parse(""), Mesh::default());
    assert_eq!(parse("# nothing\n\n"), Mesh::default());
}

#[test]
fn a_missing_mtl_is_ignored_without_materials_and_warned_about_with_them() {
    let dir = temp_dir("nomtl");
    let obj = dir.join("m.obj");
    std::fs::write(
        &obj,
        "mtllib missing.mtl\nusemtl gold\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    )
    .unwrap();
    let mesh = load_obj(&obj, false).unwrap();
    assert_eq!(mesh.triangles.len(), 1);
    assert_eq!(mesh.triangles[0].material(), None);
    assert!(mesh.materials.is_empty());
    assert!(mesh.warnings.is_empty(), "{:?}", mesh.warnings);
    // With materials the missing file is one warning at the mtllib line,
    // and the face gets the default grey.
    let mesh = load_obj(&obj, true).unwrap();
    assert_warning(&mesh, &obj, 1, &["missing.mtl", "default grey"]);
    assert_eq!(mesh.materials, [MeshMaterial::default_grey()]);
    assert_eq!(mesh.triangles[0].material(), Some(0));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn mtllib_is_relative_to_the_obj_folder() {
    let dir = temp_dir("mtl");
    std::fs::create_dir_all(dir.join("sub/mat")).unwrap();
    let obj = dir.join("sub/m.obj");
    std::fs::write(
        &obj,
        "mtllib mat/a.mtl  mat/b.mtl\r\n\
         v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n\
         usemtl teal\nf 1 2 3\nusemtl gold\nf 1 2 3 4\nusemtl teal\nf 2 4 3\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("sub/mat/a.mtl"),
        "# materials\nnewmtl gold\nKa 0.1 0.08 0.02\nKd 0.75 0.6 0.15\nKs 0.6 0.55 0.4\nNs 128\n\
         illum 2\nd 1\nTr 0\nNi 1.5\nKe 0 0 0\nmap_Kd gold.png\n\nnewmtl unused\nKd 1\n",
    )
    .unwrap();
    std::fs::write(dir.join("sub/mat/b.mtl"), "newmtl teal\r\nKd 0.5\r\n").unwrap();

    let mesh = load_obj(&obj, true).unwrap();
    let names: Vec<_> = mesh.materials.iter().map(|m| m.name.as_str()).collect();
    // Deduplicated; only used ones, in order of first use.
    assert_eq!(names, ["teal", "gold"]);
    assert_eq!(
        mesh.materials[0],
        MeshMaterial {
            name: "teal".into(),
            ambient: DVec3::ZERO,
            diffuse: DVec3::splat(0.5),
            specular: DVec3::ZERO,
            shininess: 0.0,
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
        mesh.materials[1],
        MeshMaterial {
            name: "gold".into(),
            ambient: d(0.1, 0.08, 0.02),
            diffuse: d(0.75, 0.6, 0.15),
            specular: d(0.6, 0.55, 0.4),
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
    let used: Vec<_> = mesh.triangles.iter().map(|t| t.material()).collect();
    assert_eq!(used, [Some(0), Some(1), Some(1), Some(0)]);

    // Without materials, the same file gives the same triangles and no materials.
    let plain = load_obj(&obj, false).unwrap();
    assert!(plain.materials.is_empty());
    assert!(plain.triangles.iter().all(|t| t.material().is_none()));
    assert_eq!(plain.triangles.len(), 4);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn mtl_errors_name_the_mtl_file_and_line() {
    let dir = temp_dir("mtlerr");
    let obj = dir.join("m.obj");
    let mtl = dir.join("m.mtl");
    std::fs::write(
        &obj,
        "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\n",
    )
    .unwrap();
    let cases: &[(&str, usize, &str)] = &[
        ("Kd 1 1 1\nnewmtl a\n", 1, "Kd"),
        ("# c\nNs 10\nnewmtl a\n", 2, "Ns"),
        ("newmtl a\nKd 1 x 1\n", 2, "Kd"),
        ("newmtl a\nKa 1 1\n", 2, "Ka"),
        ("newmtl a\nKs 1 1 1 1\n", 2, "Ks"),
        ("newmtl a\nKs\n", 2, "Ks"),
        ("newmtl a\n\nKd nan 0 0\n", 3, "Kd"),
        ("newmtl a\nKd inf 0 0\n", 2, "Kd"),
        ("newmtl a\nNs\n", 2, "Ns"),
        ("newmtl a\nNs 1 2\n", 2, "Ns"),
        ("newmtl a\nNs abc\n", 2, "Ns"),
        ("newmtl a\nNs -1\n", 2, "Ns"),
        ("newmtl\n", 1, "newmtl"),
    ];
    for &(text, line, key) in cases {
        std::fs::write(&mtl, text).unwrap();
        let e = load_obj(&obj, true).unwrap_err();
        assert_err(&e, &mtl, line, key);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn faces_without_a_defined_material_get_the_default_grey_and_statements_without_names_are_errors() {
    let dir = temp_dir("usemtl");
    let obj = dir.join("m.obj");
    std::fs::write(dir.join("m.mtl"), "newmtl a\nKd 1 0 0\n").unwrap();
    let tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    let grey = MeshMaterial::default_grey();

    // A face before any usemtl: warned at the face, once for all such faces.
    std::fs::write(&obj, format!("mtllib m.mtl\n{tri}f 1 2 3\nf 1 2 3\n")).unwrap();
    let mesh = load_obj(&obj, true).unwrap();
    assert_warning(&mesh, &obj, 5, &["no usemtl"]);
    assert_eq!(mesh.materials, std::slice::from_ref(&grey));

    // An unknown material: warned at the usemtl line, naming it; the
    // known one keeps its colour.
    std::fs::write(
        &obj,
        format!("mtllib m.mtl\n{tri}usemtl a\nf 1 2 3\nusemtl nope\nf 1 2 3\nf 1 2 3\n"),
    )
    .unwrap();
    let mesh = load_obj(&obj, true).unwrap();
    assert_warning(&mesh, &obj, 7, &["'nope'", "m.mtl"]);
    assert_eq!(mesh.materials.len(), 2);
    assert_eq!(mesh.materials[0].diffuse, d(1., 0., 0.));
    assert_eq!(mesh.materials[1], grey);
    let used: Vec<_> = mesh.triangles.iter().map(|t| t.material()).collect();
    assert_eq!(used, [Some(0), Some(1), Some(1)]);

    // No mtllib at all.
    std::fs::write(&obj, format!("{tri}usemtl a\nf 1 2 3\n")).unwrap();
    let mesh = load_obj(&obj, true).unwrap();
    assert_warning(&mesh, &obj, 4, &["'a'", "no mtllib"]);

    // An mtllib with no file name.
    std::fs::write(&obj, format!("mtllib\n{tri}")).unwrap();
    assert_err(&load_obj(&obj, true).unwrap_err(), &obj, 1, "mtllib");

    // A usemtl with no name.
    std::fs::write(&obj, format!("mtllib m.mtl\n{tri}usemtl   # none\n")).unwrap();
    assert_err(&load_obj(&obj, true).unwrap_err(), &obj, 5, "usemtl");

    // Without materials none of these matter.
    std::fs::write(&obj, format!("{tri}usemtl zzz\nf 1 2 3\nmtllib\nusemtl\n")).unwrap();
    assert_eq!(load_obj(&obj, false).unwrap().triangles.len(), 1);

    // mtllib after usemtl still resolves (the check happens at the face).
    std::fs::write(&obj, format!("usemtl a\nmtllib m.mtl\n{tri}f 1 2 3\n")).unwrap();
    let mesh = load_obj(&obj, true).unwrap();
    assert_eq!(mesh.materials.len(), 1);
    assert_eq!(mesh.materials[0].diffuse, d(1., 0., 0.));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn unreadable_obj_file() {
    let missing = std::env::temp_dir().join(format!(
        "kdray-obj-test-{}-does-not-exist.obj",
        std::process::id()
    ));
    let e = load_obj(&missing, false).unwrap_err();
    assert_eq!(e.file, missing);
    assert_eq!(e.line, None);
    // The OS's text varies by platform; just make sure there is some.
    assert!(e.message.starts_with("cannot read OBJ file: "), "{e}");
    assert!(e.message.len() > "cannot read OBJ file: ".len(), "{e}");
}

#[test]
fn vertex_errors() {
    let cases: &[(&str, usize)] = &[
        ("v 1 2\n", 1),
        ("v\n", 1),
        ("# c\nv 1 2 x\n", 2),
        ("v 0 0 0\nv 1 NaN 0\n", 2),
        ("v 1 2 inf\n", 1),
        ("v -infinity 2 3\n", 1),
        ("v 1e400 0 0\n", 1),
        ("v 1 2 3 w\n", 1),
        ("v 1,0 2 3\n", 1),
    ];
    for &(text, line) in cases {
        assert_err(&parse_err(text, false), p(), line, "v");
    }
}

#[test]
fn face_errors() {
    let cases: &[(&str, usize)] = &[
        ("f 1 2 3\n", 1),                 // no vertices yet
        ("v 0 0 0\nv 1 0 0\nf 1 2\n", 3), // too few vertices
        ("v 0 0 0\nf\n", 2),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", 4),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", 4),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n", 4),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n", 4),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3.0\n", 4),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 //3\n", 4),
        (
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999999999999999999\n",
            4,
        ),
        (
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -99999999999999999999999999\n",
            4,
        ),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9223372036854775807\n", 4),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -9223372036854775808\n", 4),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -0\n", 4),
    ];
    for &(text, line) in cases {
        assert_err(&parse_err(text, false), p(), line, "f");
    }
    // A face referring to a vertex defined after it is out of range.
    assert_err(
        &parse_err("v 0 0 0\nv 1 0 0\nf 1 2 3\nv 0 1 0\n", false),
        p(),
        3,
        "f",
    );
}

#[test]
fn display_is_file_line_key_message() {
    let e = parse_err("v 0 0 0\n\nv 1 2\n", false);
    assert!(e.to_string().starts_with("mesh.obj:3: v: "), "{e}");
}

#[test]
fn never_panics_on_odd_input() {
    let inputs = [
        "f",
        "f /",
        "f //",
        "f ///",
        "f 1/",
        "v",
        "v \u{0}",
        "usemtl",
        "mtllib",
        "f -",
        "f +",
        "v 1 2 3\nf -1 -1 -1",
        "\u{feff}v 1 2 3",
        "f 1 1 1 1 1 1 1 1 1",
        "\r\r\n\r",
        "#\n#\\\n",
        "v 0 0 0\nf 1 1 1\nf 1//",
    ];
    for text in inputs {
        for with_materials in [false, true] {
            let _ = parse_obj(text, p(), with_materials);
        }
    }
    // Every prefix of a small valid file.
    let full = "mtllib x.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1/1/1 2//2 -1\n";
    for end in 0..=full.len() {
        let _ = parse_obj(&full[..end], p(), false);
        let _ = parse_obj(&full[..end], p(), true);
    }
}

#[test]
fn large_mesh_parses() {
    // A 200 x 200 grid of quads = 80,000 triangles.
    let n = 200usize;
    let mut text = String::new();
    for j in 0..=n {
        for i in 0..=n {
            text.push_str(&format!("v {i} {j} 0\n"));
        }
    }
    for j in 0..n {
        for i in 0..n {
            let a = j * (n + 1) + i + 1;
            text.push_str(&format!("f {} {} {} {}\n", a, a + 1, a + n + 2, a + n + 1));
        }
    }
    let mesh = parse(&text);
    assert_eq!(mesh.triangles.len(), 2 * n * n);
}

#[test]
fn shipped_torus_model() {
    let obj = crate::common::repo_path("scenes/models/torus.obj");
    let mesh = load_obj(&obj, true).unwrap();
    assert_eq!(mesh.triangles.len(), 48 * 24 * 2);
    let mut names: Vec<_> = mesh.materials.iter().map(|m| m.name.as_str()).collect();
    names.sort();
    assert_eq!(names, ["gold", "teal"]);
    for t in &mesh.triangles {
        assert!(t.material().is_some());
        let vertices = mesh.vertices(t).unwrap();
        for v in vertices {
            // Inside the torus's bounding box, on its surface.
            let ring = (v.x * v.x + v.z * v.z).sqrt() - 1.0;
            let tube = (ring * ring + v.y * v.y).sqrt();
            assert!((tube - 0.35).abs() < 1e-5, "{v}");
        }
        // Outward winding: the normal points away from the tube's centre line.
        let [a, b, c] = vertices;
        let n = (b - a).cross(c - a);
        let centroid = (a + b + c) / 3.0;
        let on_ring = DVec3::new(centroid.x, 0.0, centroid.z).normalize();
        assert!(n.dot(centroid - on_ring) > 0.0);
    }
    assert!(std::fs::metadata(&obj).unwrap().len() < 200 * 1024);
}

#[test]
fn mtl_texture_statements_other_than_map_kd_are_ignored_with_one_warning_per_file() {
    let (mesh, obj, mtl) = a_triangle_of_material_a(
        "other-maps",
        "newmtl a\nKd 0.5 0.25 1\nmap_Ka wood.png\nmap_Bump -bm 1 n.png\nbump n.png\n",
    );
    assert_warning(
        &mesh,
        &mtl,
        3,
        &["map_Ka", "2 more", "no textures but map_Kd"],
    );
    assert_flat_kd_and_no_warnings_without_materials(&mesh, &obj);
}

#[test]
fn a_missing_map_kd_image_is_a_warning_naming_it_and_the_flat_kd() {
    let (mesh, obj, mtl) = a_triangle_of_material_a(
        "maps",
        "newmtl a\nKd 0.5 0.25 1\nmap_Kd wood.png\nmap_Bump -bm 1 n.png\nbump n.png\n",
    );
    assert_eq!(mesh.warnings.len(), 2, "{:?}", mesh.warnings);
    let missing = &mesh.warnings[0];
    assert_eq!(
        (missing.file.as_path(), missing.line),
        (mtl.as_path(), Some(3))
    );
    for word in ["cannot read texture", "wood.png", "flat Kd"] {
        assert!(missing.message.contains(word), "{missing} lacks {word:?}");
    }
    let others = &mesh.warnings[1];
    assert_eq!(others.line, Some(4), "{others}");
    assert!(others.message.contains("map_Bump (and 1 more"), "{others}");
    assert_flat_kd_and_no_warnings_without_materials(&mesh, &obj);
}

/// A fresh folder holding `m.mtl` with `mtl_text` and `m.obj`, one triangle
/// of material `a` from it: the mesh read with materials, and the OBJ and
/// MTL files' paths.
fn a_triangle_of_material_a(tag: &str, mtl_text: &str) -> (Mesh, PathBuf, PathBuf) {
    let dir = temp_dir(tag);
    let (obj, mtl) = (dir.join("m.obj"), dir.join("m.mtl"));
    std::fs::write(&mtl, mtl_text).unwrap();
    let obj_text = "mtllib m.mtl\nusemtl a\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    std::fs::write(&obj, obj_text).unwrap();
    (load_obj(&obj, true).unwrap(), obj, mtl)
}

/// Material `a` of `mesh` keeps its flat Kd (0.5 0.25 1) and no texture;
/// read without materials, `obj` has no warning (its MTL file is not read).
fn assert_flat_kd_and_no_warnings_without_materials(mesh: &Mesh, obj: &Path) {
    assert_eq!(mesh.materials[0].diffuse, d(0.5, 0.25, 1.0));
    assert!(mesh.materials[0].texture.is_none());
    assert!(load_obj(obj, false).unwrap().warnings.is_empty());
}
