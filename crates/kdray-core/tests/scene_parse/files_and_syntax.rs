//! Scene files and their syntax: a missing file or a folder, TOML and JSON
//! syntax errors with their line, NaN and infinity in JSON, duplicate keys,
//! the format picked by extension, and the file every error names.

use super::*;

#[test]
fn missing_scene_file() {
    let dir = TempDir::new("missing");
    for name in ["nope.toml", "nope.json"] {
        let path = dir.join(name);
        let e = load_err(&path);
        assert_error(&e, &path, None, None, &["cannot read scene file"]);
    }
}

#[test]
fn a_folder_is_not_a_scene_file() {
    let dir = TempDir::new("folder");
    let e = load_err(&dir.path);
    assert_error(&e, &dir.path, None, None, &["cannot read scene file"]);
}

#[test]
fn malformed_toml_names_the_line() {
    let cases: &[(&str, usize, &str)] = &[
        ("[camera\nposition = [0, 0, 1]\n", 1, "expected"),
        (
            "[camera]\nposition = [0, 0, 1]\nlook_at = [0, 0,\n",
            3,
            "array",
        ),
        (
            "[camera]\nposition = [0, 0, 1]\n\nlook_at = \n",
            4,
            "expected",
        ),
        ("# a comment\n[camera]\nposition = [0 0 1]\n", 3, "expected"),
        ("[camera]\nposition = \"open\n", 2, "string"),
        ("[camera]\n= [0, 0, 1]\n", 2, "key"),
    ];
    for &(text, line, word) in cases {
        let e = parse_err(text, SceneFormat::Toml);
        assert_error(&e, Path::new(TOML_FILE), Some(line), None, &[word]);
    }
}

#[test]
fn malformed_json_names_the_line() {
    // A syntax error names the key it stopped at when there is one.
    let cases: &[(&str, usize, Option<&str>, &str)] = &[
        ("{\n  \"camera\": {\n", 3, None, "eof"),
        ("", 1, None, "eof"),
        (
            "{\n  \"render\": {}\n  \"lights\": []\n}",
            3,
            Some("lights"),
            "expected `,` or `}`",
        ),
        ("{\n  \"render\": {},\n}\n", 3, None, "trailing comma"),
        ("{\n  'camera': {}\n}", 2, None, "key"),
        ("{\n  \"camera\" {}\n}", 2, None, "expected"),
    ];
    for &(text, line, key, word) in cases {
        let e = parse_err(text, SceneFormat::Json);
        assert_error(&e, Path::new(JSON_FILE), Some(line), key, &[word]);
    }
    // Something after the document.
    let text = base().json().text + "\n{}\n";
    let e = parse_err(&text, SceneFormat::Json);
    let line = text.lines().count();
    assert_error(
        &e,
        Path::new(JSON_FILE),
        Some(line),
        None,
        &["trailing characters"],
    );
}

#[test]
fn json_has_no_nan_or_infinity_literals() {
    for literal in ["NaN", "Infinity", "-Infinity"] {
        let text = base().set("spheres[0].radius", literal).json();
        let e = text.parse_err();
        let line = text.line("spheres[0].radius");
        let words = ["not a json number", "finite"];
        assert_error(
            &e,
            text.file(),
            Some(line),
            Some("spheres[0].radius"),
            &words,
        );
    }
}

#[test]
fn duplicate_keys_are_errors() {
    // TOML: a syntax error at the second occurrence, naming the key.
    let text = "[camera]\nposition = [0, 0, 1]\nposition = [0, 0, 2]\n";
    let e = parse_err(text, SceneFormat::Toml);
    assert_error(
        &e,
        Path::new(TOML_FILE),
        Some(3),
        None,
        &["duplicate", "position"],
    );

    let text = base().toml().text + "\n[materials.red]\ndiffuse = [1, 1, 1]\n";
    let line = text.lines().count() - 1;
    let e = parse_err(&text, SceneFormat::Toml);
    assert_error(
        &e,
        Path::new(TOML_FILE),
        Some(line),
        None,
        &["duplicate", "red"],
    );

    // JSON: a repeated field, or a repeated material name (which
    // serde_json alone would let the last one win).
    let text =
        "{\n  \"camera\": {\n    \"position\": [0, 0, 1],\n    \"position\": [0, 0, 2]\n  }\n}";
    let e = parse_err(text, SceneFormat::Json);
    assert_error(
        &e,
        Path::new(JSON_FILE),
        Some(4),
        Some("camera.position"),
        &["duplicate"],
    );

    let text = "{\n  \"camera\": {\"position\": [0, 0, 1], \"look_at\": [0, 0, 0]},\n  \
                \"lights\": [{\"position\": [1, 1, 1]}],\n  \"materials\": {\n    \
                \"red\": {\"diffuse\": [1, 0, 0]},\n    \"red\": {\"diffuse\": [0, 1, 0]}\n  }\n}";
    let e = parse_err(text, SceneFormat::Json);
    assert_error(
        &e,
        Path::new(JSON_FILE),
        Some(6),
        Some("materials.red"),
        &["red", "twice"],
    );
}

#[test]
fn the_extension_picks_the_format() {
    let dir = TempDir::new("ext");
    let json = base().json().text;
    let toml = base().toml().text;
    let expected = assert_accepted(&base());
    // `.json` in any case is JSON; anything else is TOML.
    assert_eq!(load_ok(&dir.write("a.json", &json)), expected);
    assert_eq!(load_ok(&dir.write("b.JSON", &json)), expected);
    assert_eq!(load_ok(&dir.write("c.toml", &toml)), expected);
    assert_eq!(load_ok(&dir.write("d.scene", &toml)), expected);
    assert_eq!(load_ok(&dir.write("noextension", &toml)), expected);
    // JSON in a .toml file is read as TOML, and fails as TOML.
    let path = dir.write("e.toml", &json);
    let e = load_err(&path);
    assert_eq!(e.file, path);
    assert_eq!(e.line, Some(1), "{e}");
    assert_eq!(e.key, None, "{e}");
}

#[test]
fn errors_from_load_scene_name_the_real_file() {
    let dir = TempDir::new("real");
    let doc = two_spheres().set("spheres[1].radius", "-1");
    for (name, text) in [("s.toml", doc.toml()), ("s.json", doc.json())] {
        let path = dir.write(name, &text.text);
        let e = load_err(&path);
        let line = text.line("spheres[1].radius");
        assert_error(&e, &path, Some(line), Some("spheres[1].radius"), &["> 0"]);
        assert!(e
            .to_string()
            .starts_with(&format!("{}:{line}: spheres[1].radius: ", path.display())));
    }
}
