//! The schema: unknown keys, missing keys, values of the wrong type, and
//! arrays of the wrong length, in TOML and JSON.

use super::*;

#[test]
fn unknown_keys_are_errors_naming_the_key() {
    let cases: &[(&str, &str)] = &[
        ("foo", "1"),
        ("camera.fov", "60"),
        ("render.gamma", "2.2"),
        ("lights[0].colour", "[1, 1, 1]"),
        ("materials.red.shine", "3"),
        ("materials.blue.Diffuse", "[1, 1, 1]"),
        ("spheres[1].color", "[1, 0, 0]"),
        ("triangles[0].normal", "[0, 0, 1]"),
        ("meshes[0].rotation", "[0, 0, 90]"),
    ];
    for &(key, value) in cases {
        let doc = with_mesh()
            .set("spheres[1].center", "[1, 0, -1]")
            .set("spheres[1].radius", "0.25")
            .set("spheres[1].material", "\"blue\"")
            .set(key, value);
        let name = key.rsplit('.').next().unwrap();
        assert_rejected(
            &doc,
            key,
            &["unknown field", &format!("`{name}`"), "expected"],
        );
    }
}

#[test]
fn wrong_types_are_errors_naming_the_key() {
    // (key set, value, key reported, words)
    let cases: &[(&str, &str, &str, &[&str])] = &[
        (
            "spheres[1].radius",
            "\"big\"",
            "spheres[1].radius",
            &["invalid type", "string"],
        ),
        (
            "spheres[1].center",
            "1",
            "spheres[1].center",
            &["invalid type"],
        ),
        (
            "spheres[1].material",
            "3",
            "spheres[1].material",
            &["invalid type"],
        ),
        (
            "camera.position",
            "[0, 0]",
            "camera.position",
            &["invalid length 2", "3"],
        ),
        (
            "camera.position",
            "[0, 0, 1, 1]",
            "camera.position",
            &["invalid length"],
        ),
        (
            "camera.position",
            "[0, \"a\", 1]",
            "camera.position[1]",
            &["invalid type"],
        ),
        ("camera.up", "\"y\"", "camera.up", &["invalid type"]),
        ("camera.vfov", "[60]", "camera.vfov", &["invalid type"]),
        ("render.width", "1.5", "render.width", &["invalid type"]),
        ("render.width", "\"800\"", "render.width", &["invalid type"]),
        ("render.height", "-1", "render.height", &["invalid value"]),
        (
            "render.max_depth",
            "2.5",
            "render.max_depth",
            &["invalid type"],
        ),
        ("render.samples", "-4", "render.samples", &["invalid value"]),
        (
            "render.background",
            "0",
            "render.background",
            &["invalid type"],
        ),
        (
            "render.shadow_mode",
            "\"hard\"",
            "render.shadow_mode",
            &["unknown variant", "ambient", "seed"],
        ),
        (
            "render.shadow_mode",
            "\"Seed\"",
            "render.shadow_mode",
            &["unknown variant"],
        ),
        (
            "render.shadow_mode",
            "1",
            "render.shadow_mode",
            &["invalid type"],
        ),
        (
            "lights[0].ambient",
            "1",
            "lights[0].ambient",
            &["invalid type"],
        ),
        (
            "materials.red.diffuse",
            "0.5",
            "materials.red.diffuse",
            &["invalid type"],
        ),
        (
            "materials.red.shininess",
            "\"shiny\"",
            "materials.red.shininess",
            &["invalid type"],
        ),
        (
            "triangles[0].vertices",
            "[[0, 0, 0], [1, 0, 0]]",
            "triangles[0].vertices",
            &["invalid length"],
        ),
        (
            "triangles[0].vertices",
            "[0, 0, 0]",
            "triangles[0].vertices[0]",
            &["invalid type"],
        ),
        ("meshes[0].path", "7", "meshes[0].path", &["invalid type"]),
        (
            "meshes[0].scale",
            "\"big\"",
            "meshes[0].scale",
            &["a number or an array of 3 numbers"],
        ),
        (
            "meshes[0].scale",
            "[1, 2]",
            "meshes[0].scale",
            &["invalid length"],
        ),
        (
            "meshes[0].scale",
            "[1, 2, 3, 4]",
            "meshes[0].scale",
            &["invalid length"],
        ),
        (
            "meshes[0].rotate",
            "90",
            "meshes[0].rotate",
            &["invalid type"],
        ),
        ("lights", "3", "lights", &["invalid type"]),
        (
            "materials",
            "[]",
            "materials",
            &["invalid type", "materials"],
        ),
        (
            "render",
            "5",
            "render",
            &["invalid type", "a [render] table"],
        ),
        (
            "camera",
            "[0, 0, 1]",
            "camera",
            &["invalid type", "a [camera] table"],
        ),
        // A table is never an array of its fields in order.
        (
            "camera",
            "[[0, 0, 1], [0, 0, 0]]",
            "camera",
            &["invalid type", "a [camera] table"],
        ),
        (
            "spheres",
            "[[[0, 0, 0], 1, \"red\"]]",
            "spheres[0]",
            &["invalid type", "a [[spheres]] table"],
        ),
        (
            "lights",
            "[1]",
            "lights[0]",
            &["invalid type", "a [[lights]] table"],
        ),
        (
            "spheres",
            "[[0, 0, 0]]",
            "spheres[0]",
            &["invalid type", "a [[spheres]] table"],
        ),
        (
            "triangles",
            "[\"a\"]",
            "triangles[0]",
            &["invalid type", "a [[triangles]] table"],
        ),
        (
            "meshes",
            "[2]",
            "meshes[0]",
            &["invalid type", "a [[meshes]] table"],
        ),
        (
            "materials.red",
            "1",
            "materials.red",
            &["invalid type", "a material table"],
        ),
    ];
    for &(set, value, key, words) in cases {
        let doc = with_mesh()
            .set("spheres[1].center", "[1, 0, -1]")
            .set("spheres[1].radius", "0.25")
            .set("spheres[1].material", "\"blue\"")
            .set(set, value);
        assert_rejected(&doc, key, words);
    }
}

#[test]
fn missing_required_keys_name_their_table() {
    let cases: &[(&str, &str, &str)] = &[
        ("camera.position", "camera", "`position`"),
        ("camera.look_at", "camera", "`look_at`"),
        ("lights[0].position", "lights[0]", "`position`"),
        ("materials.red.diffuse", "materials.red", "`diffuse`"),
        ("spheres[1].radius", "spheres[1]", "`radius`"),
        ("spheres[1].center", "spheres[1]", "`center`"),
        ("spheres[1].material", "spheres[1]", "`material`"),
        ("triangles[0].vertices", "triangles[0]", "`vertices`"),
        ("triangles[0].material", "triangles[0]", "`material`"),
        ("meshes[0].path", "meshes[0]", "`path`"),
    ];
    for &(removed, table, word) in cases {
        let doc = with_mesh()
            .set("materials.red.ambient", "[0, 0, 0]")
            .set("spheres[1].center", "[1, 0, -1]")
            .set("spheres[1].radius", "0.25")
            .set("spheres[1].material", "\"blue\"")
            .remove(removed);
        for text in doc.both() {
            let e = text.parse_err();
            // A material's colour (`diffuse` or `base_color`) and a light's
            // position (a directional light has none) are checked after
            // reading, at the table's key; the rest by the reader, which
            // names a JSON object where it ends.
            let line = match removed {
                "materials.red.diffuse" | "lights[0].position" => text.line(table),
                _ => text.table_line(table),
            };
            assert_error(
                &e,
                text.file(),
                Some(line),
                Some(table),
                &["missing field", word],
            );
        }
    }
}

#[test]
fn a_json_document_must_be_an_object() {
    for text in ["[]", "3", "null", "\"scene\""] {
        let e = parse_err(text, SceneFormat::Json);
        assert_error(
            &e,
            Path::new(JSON_FILE),
            None,
            None,
            &["invalid type", "expected a scene"],
        );
    }
}

#[test]
fn a_missing_camera_is_an_error_about_the_whole_file() {
    for text in base().remove("camera").both() {
        let e = text.parse_err();
        assert_error(&e, text.file(), None, None, &["missing field", "`camera`"]);
    }
    for format in [SceneFormat::Toml, SceneFormat::Json] {
        let text = if format == SceneFormat::Json {
            "{}"
        } else {
            ""
        };
        let e = parse_err(text, format);
        assert_error(
            &e,
            file_of(format),
            None,
            None,
            &["missing field", "`camera`"],
        );
    }
}

#[test]
fn at_least_one_light_is_required() {
    // No lights key at all: no line to name.
    for text in base().remove("lights").both() {
        let e = text.parse_err();
        assert_error(&e, text.file(), None, Some("lights"), &["at least one"]);
    }
    // An empty list: its line.
    assert_rejected(&base().set("lights", "[]"), "lights", &["at least one"]);
}

#[test]
fn every_optional_key_may_be_left_out() {
    let doc = Doc::default()
        .set("camera.position", "[0, 0, 1]")
        .set("camera.look_at", "[0, 0, 0]")
        .set("lights[0].position", "[5, 5, 5]");
    let scene = assert_accepted(&doc);
    assert!(scene.materials.is_empty());
    assert!(scene.spheres.is_empty());
    assert!(scene.triangles.is_empty());
    assert_eq!(scene.object_count(), 0);
}
