//! `[shapes.NAME]` and `[[instances]]`: a scene written with instances
//! flattens to the very scene written with placed meshes, and every bad
//! shape or instance is a one-line error at its key, in TOML and JSON.

use super::*;
use kdray_core::prepare::{Accel, PreparedScene};

/// The head of a scene: camera, a light, materials red and blue.
const HEAD: &str = "[camera]\nposition = [0, 0, 10]\nlook_at = [0, 0, 0]\n\
    [[lights]]\nposition = [0, 10, 0]\n\
    [materials.blue]\ndiffuse = [0, 0, 0.7]\n[materials.red]\ndiffuse = [0.7, 0, 0]\n";

/// Three placements of the torus: mirrored and non-uniformly scaled with
/// its file's materials, turned with `red`, and moved with its own again.
const PLACEMENTS: [(&str, Option<&str>); 3] = [
    (
        "scale = [1, -2, 0.5]\nrotate = [10, 20, 30]\ntranslate = [1, 2, 3]",
        None,
    ),
    ("scale = 0.5\nrotate = [0, 90, 0]", Some("red")),
    ("translate = [-3, 0, 1]", None),
];

fn material_line(material: Option<&str>) -> String {
    material.map_or(String::new(), |m| format!("material = \"{m}\"\n"))
}

#[test]
fn instances_flatten_to_the_triangles_of_the_same_meshes_placed() {
    let dir = TempDir::new("instances-flatten");
    copy_torus(&dir, "models");
    for smooth in ["", "smooth = true\n", "smooth = false\n"] {
        let mut placed = HEAD.to_string();
        let mut instanced = format!("{HEAD}[shapes.torus]\npath = \"models/torus.obj\"\n{smooth}");
        for (transform, material) in PLACEMENTS {
            let material = material_line(material);
            placed.push_str(&format!(
                "[[meshes]]\npath = \"models/torus.obj\"\n{smooth}{transform}\n{material}"
            ));
            instanced.push_str(&format!(
                "[[instances]]\nshape = \"torus\"\n{transform}\n{material}"
            ));
        }
        let placed = load_ok(&dir.write("placed.toml", &placed));
        let instanced = load_ok(&dir.write("instanced.toml", &instanced));

        assert!(instanced.triangles.is_empty(), "instances stay unflattened");
        assert_eq!(instanced.instances.len(), 3);
        assert_eq!(instanced.shapes.len(), 1);
        assert_eq!(
            instanced.instanced_triangle_count(),
            placed.triangles.len(),
            "the torus has no collapsed triangle"
        );
        // The torus's file materials once for the shape, as for the first
        // mesh entry; the third entry's copies are the difference.
        let mut expected = placed.clone();
        let torus_materials = 2;
        assert_eq!(expected.materials.len(), 2 + 2 * torus_materials);
        expected.materials.truncate(2 + torus_materials);
        let third = &mut expected.triangles[2 * placed.triangles.len() / 3..];
        for t in third {
            t.material -= torus_materials as u32;
        }
        let flattened = instanced.clone().flattened();
        assert_eq!(flattened, expected, "smooth: {smooth:?}");
        // The renderers' preparation flattens the same way.
        let prepared = PreparedScene::new(instanced, Accel::Brute);
        assert_eq!(prepared.scene, expected);
    }
}

#[test]
fn an_instance_by_matrix_equals_one_by_scale_rotate_and_translate() {
    let text = |transform: &str| {
        format!(
            "{HEAD}[shapes.tri]\ntriangles = [[[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 0, 1], [1, 0, 1], [0, 2, 1]]]\nmaterial = \"red\"\n\
             [[instances]]\nshape = \"tri\"\nmaterial = \"blue\"\n{transform}\n"
        )
    };
    let by_parts = parse_ok(
        &text("scale = [2, -1, 3]\nrotate = [0, 0, 90]\ntranslate = [5, 6, 7]"),
        SceneFormat::Toml,
    )
    .flattened();
    // Scale, then 90 degrees about z (x -> y, y -> -x), then move.
    let by_matrix = parse_ok(
        &text("matrix = [[0, 1, 0, 5], [2, 0, 0, 6], [0, 0, 3, 7], [0, 0, 0, 1]]"),
        SceneFormat::Toml,
    )
    .flattened();
    assert_eq!(by_parts.triangles.len(), 2);
    assert_eq!(by_matrix.triangles.len(), 2);
    for (a, b) in by_parts.triangles.iter().zip(&by_matrix.triangles) {
        assert_eq!(
            a.material, 0,
            "the instance's material overrides the shape's"
        );
        assert_eq!(a.material, b.material);
        for (p, q) in a.vertices.iter().zip(b.vertices) {
            assert_close(*p, q);
        }
    }
    assert_close(
        by_matrix.triangles[0].vertices[1],
        DVec3::new(5.0, 8.0, 7.0),
    );
    // Inline triangles are flat, as `[[triangles]]`.
    assert!(by_matrix.triangle_normals.is_empty());
}

#[test]
fn shapes_and_instances_read_alike_from_toml_and_json() {
    let doc = base()
        .set(
            "shapes.tri.triangles",
            "[[[0, 0, 0], [1, 0, 0], [0, 1, 0]]]",
        )
        .set("shapes.tri.material", "\"red\"")
        .set("instances[0].shape", "\"tri\"")
        .set("instances[0].translate", "[0, 0, -3]")
        .set("instances[1].shape", "\"tri\"")
        .set(
            "instances[1].matrix",
            "[[-1, 0, 0, 1], [0, 1, 0, 0], [0, 0, 1, -3], [0, 0, 0, 1]]",
        )
        .set("instances[1].material", "\"blue\"");
    let scene = assert_accepted(&doc);
    assert_eq!(scene.instances.len(), 2);
    assert_eq!(scene.instances[1].material, Some(0));
    assert!(scene.instances[1].transform.matrix3.determinant() < 0.0);
    let bounds = scene.instance_bounds(1).unwrap();
    assert_close(bounds[0], DVec3::new(0.0, 0.0, -3.0));
    assert_close(bounds[1], DVec3::new(1.0, 1.0, -3.0));
}

/// `base()` with a one-triangle shape `tri` and one instance of it.
fn with_instance() -> Doc {
    base()
        .set(
            "shapes.tri.triangles",
            "[[[0, 0, 0], [1, 0, 0], [0, 1, 0]]]",
        )
        .set("shapes.tri.material", "\"red\"")
        .set("instances[0].shape", "\"tri\"")
}

#[test]
fn an_instance_of_an_unknown_shape_is_an_error() {
    let doc = with_instance().set("instances[0].shape", "\"tree\"");
    assert_rejected(
        &doc,
        "instances[0].shape",
        &["unknown shape", "\"tree\"", "tri"],
    );
}

#[test]
fn a_singular_or_non_affine_matrix_is_an_error() {
    let singular = with_instance().set(
        "instances[0].matrix",
        "[[1, 0, 0, 0], [2, 0, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]",
    );
    assert_rejected(&singular, "instances[0].matrix", &["singular"]);
    let projective = with_instance().set(
        "instances[0].matrix",
        "[[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 1, 1]]",
    );
    assert_rejected(
        &projective,
        "instances[0].matrix[3]",
        &["[0, 0, 0, 1]", "affine"],
    );
    let short = with_instance().set(
        "instances[0].matrix",
        "[[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0]]",
    );
    assert_rejected(&short, "instances[0].matrix", &["length 4"]);
    let both = with_instance()
        .set(
            "instances[0].matrix",
            "[[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]",
        )
        .set("instances[0].translate", "[1, 0, 0]");
    assert_rejected(&both, "instances[0].matrix", &["not both"]);
    let far = with_instance().set(
        "instances[0].matrix",
        "[[1e300, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]",
    );
    assert_rejected(&far, "instances[0].matrix", &["1e15"]);
    let flat = with_instance().set("instances[0].scale", "[1, 0, 1]");
    assert_rejected(&flat, "instances[0].scale", &["non-zero"]);
}

#[test]
fn a_non_finite_matrix_entry_is_an_error_at_its_index() {
    let text = with_instance()
        .set(
            "instances[0].matrix",
            "[[1, 0, 0, 0], [0, nan, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]",
        )
        .toml();
    assert_rejected_text(&text, "instances[0].matrix[1][1]", &["finite"]);
}

#[test]
fn a_bad_shape_is_an_error_at_its_key() {
    let no_material = with_instance().remove("shapes.tri.material");
    // A missing key's error points at its table.
    for text in no_material.both() {
        let e = text.parse_err();
        let (key, words) = (
            Some("shapes.tri.material"),
            ["inline triangles need a material"],
        );
        assert_error(&e, text.file(), Some(text.line("shapes.tri")), key, &words);
    }
    let both = with_instance().set("shapes.tri.path", "\"models/none.obj\"");
    assert_rejected(&both, "shapes.tri.triangles", &["not both"]);
    let flat = with_instance().set(
        "shapes.tri.triangles",
        "[[[0, 0, 0], [1, 0, 0], [2, 0, 0]]]",
    );
    assert_rejected(&flat, "shapes.tri.triangles[0]", &["zero area"]);
    let unknown = with_instance().set("shapes.tri.material", "\"green\"");
    assert_rejected(
        &unknown,
        "shapes.tri.material",
        &["unknown material", "\"green\""],
    );
    let override_unknown = with_instance().set("instances[0].material", "\"green\"");
    assert_rejected(
        &override_unknown,
        "instances[0].material",
        &["unknown material", "\"green\""],
    );
}

#[test]
fn a_missing_shape_file_names_the_shape_and_its_line() {
    let dir = TempDir::new("instances-missing");
    let text = format!(
        "{HEAD}[shapes.tree]\npath = \"models/tree.obj\"\n[[instances]]\nshape = \"tree\"\n"
    );
    let path = dir.write("scene.toml", &text);
    let e = load_err(&path);
    assert_eq!(e.file, dir.join("models/tree.obj"));
    let shown = e.to_string();
    assert!(
        shown.contains(&format!("from shapes.tree.path in {}:11", path.display())),
        "{shown}"
    );
}

#[test]
fn the_two_level_structure_of_a_scene_hits_what_its_flattened_triangles_do() {
    use kdray_core::geometry::{Primitives, Ray, T_INFINITY};
    use kdray_core::kdtree::traverse::closest_hit_brute;
    use kdray_core::kdtree::Traversal;
    use kdray_core::two_level::TwoLevel;

    let dir = TempDir::new("instances-two-level");
    copy_torus(&dir, "models");
    let mut text = format!("{HEAD}[shapes.torus]\npath = \"models/torus.obj\"\n");
    for (transform, material) in PLACEMENTS {
        let material = material_line(material);
        text.push_str(&format!(
            "[[instances]]\nshape = \"torus\"\n{transform}\n{material}"
        ));
    }
    let scene = load_ok(&dir.write("scene.toml", &text));
    let two = TwoLevel::from_scene(&scene);
    let flat = Primitives::from_scene(&scene.clone().flattened());
    let mut hits = 0;
    for i in 0..400 {
        let (u, v) = ((i % 20) as f32 / 19.0 - 0.5, (i / 20) as f32 / 19.0 - 0.5);
        let ray = Ray {
            origin: glam::Vec3::new(0.3, 0.2, 12.0),
            dir: glam::Vec3::new(u * 1.1, v * 0.9, -1.0).normalize(),
        };
        let want = closest_hit_brute(&flat, &ray, T_INFINITY);
        for walk in Traversal::ALL {
            let got = two.closest_hit(walk, &ray, T_INFINITY);
            match (got, want) {
                (None, None) => {}
                (Some(g), Some(w)) => assert!((g.t - w.t).abs() <= 1e-4 * w.t, "{g:?} {w:?}"),
                (g, w) => panic!("{walk}: two-level {g:?}, flattened {w:?}, ray {ray:?}"),
            }
        }
        hits += usize::from(want.is_some());
    }
    assert!(hits >= 20, "only {hits} of 400 rays hit the tori");
}

#[test]
fn instances_placing_more_triangles_than_the_tree_takes_are_an_error() {
    let dir = TempDir::new("instances-too-many");
    // 65,536 triangles: a 256 x 128 grid of quads.
    let mut obj = String::new();
    for j in 0..=128 {
        for i in 0..=256 {
            obj.push_str(&format!("v {i} {j} 0\n"));
        }
    }
    for j in 0..128 {
        for i in 0..256 {
            let v = |i: usize, j: usize| j * 257 + i + 1;
            obj.push_str(&format!(
                "f {} {} {}\n",
                v(i, j),
                v(i + 1, j),
                v(i + 1, j + 1)
            ));
            obj.push_str(&format!(
                "f {} {} {}\n",
                v(i, j),
                v(i + 1, j + 1),
                v(i, j + 1)
            ));
        }
    }
    dir.write("grid.obj", &obj);
    let copies = kdray_core::scene::MAX_FLATTENED_OBJECTS / 65_536;
    let mut text = format!("{HEAD}[shapes.grid]\npath = \"grid.obj\"\nmaterial = \"red\"\n");
    // Exactly the limit fits; one more instance does not.
    text.push_str(&"[[instances]]\nshape = \"grid\"\n".repeat(copies));
    let fits = dir.write("fits.toml", &text);
    assert_eq!(load_ok(&fits).instanced_triangle_count(), 1 << 30);
    text.push_str("[[instances]]\nshape = \"grid\"\n");
    let path = dir.write("scene.toml", &text);
    let e = load_err(&path);
    assert_error(
        &e,
        &path,
        Some(13),
        Some("instances"),
        &["1073807360 triangles", "flattens"],
    );
}
