//! Mesh files that give no mesh (no faces, binary read as OBJ, unknown
//! extension, truncated or corrupt glTF, buffers outside readable files,
//! points and lines) are refused with an error naming the file.

use super::*;

/// Loads a scene whose mesh is `name` (already in `dir`), material
/// overridden, and returns its error and the `(from ...)` note a file
/// error without a line ends with.
fn error_of(dir: &TempDir, name: &str) -> (SceneError, String) {
    let (scene, line) = scene_with_mesh(
        dir,
        &[("path", &format!("\"{name}\"")), ("material", "\"red\"")],
    );
    let note = format!(" (from meshes[0].path in {}:{line})", scene.display());
    (load_err(&scene), note)
}

#[track_caller]
fn assert_file_error(dir: &TempDir, name: &str, message: &str) {
    let (e, note) = error_of(dir, name);
    let want = format!("{}: {message}{note}", dir.join(name).display());
    assert_eq!(e.to_string(), want);
    assert_eq!((e.line, e.key.as_deref()), (None, None));
}

#[test]
fn an_obj_without_faces_is_an_error() {
    let dir = TempDir::new("nofaces");
    dir.write("empty.obj", "");
    dir.write("points.obj", "# only vertices\nv 0 0 0\nv 1 0 0\nv 0 1 0\n");
    let no_faces = "no faces: the file has no `f` statement, so the mesh would draw nothing";
    assert_file_error(&dir, "empty.obj", no_faces);
    assert_file_error(&dir, "points.obj", no_faces);
    dir.write("flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\nf 1 1 2\n");
    assert_file_error(
        &dir,
        "flat.obj",
        "all 2 faces have zero area, so the mesh would draw nothing",
    );
}

#[test]
fn a_binary_file_read_as_obj_names_the_line_of_the_first_bad_byte() {
    let dir = TempDir::new("binobj");
    // Bytes 0..=255: a newline at 10, the first invalid UTF-8 byte at 128.
    let bytes: Vec<u8> = (0..=255).collect();
    std::fs::write(dir.join("binary.obj"), &bytes).unwrap();
    let (e, _) = error_of(&dir, "binary.obj");
    assert_eq!(
        e.to_string(),
        format!(
            "{}:2: not a text OBJ file: invalid UTF-8 at byte 128 (a binary file? kdray reads binary glTF as .glb)",
            dir.join("binary.obj").display()
        )
    );
    // The glTF binary itself, misnamed .obj: the same error, not an empty mesh.
    std::fs::copy(test_models_dir().join("tetra.glb"), dir.join("tetra.obj")).unwrap();
    let (e, _) = error_of(&dir, "tetra.obj");
    assert!(e.message.starts_with("not a text OBJ file"), "{e}");
}

#[test]
fn unknown_extensions_are_errors() {
    let dir = TempDir::new("ext");
    dir.write("model.stl", "solid x\nendsolid x\n");
    dir.write("model", ONE_TRIANGLE_OBJ);
    assert_file_error(
        &dir,
        "model.stl",
        "unknown mesh file extension \".stl\"; kdray reads .obj, .gltf and .glb",
    );
    assert_file_error(
        &dir,
        "model",
        "no mesh file extension; kdray reads .obj, .gltf and .glb",
    );
    // Extensions are case-insensitive.
    dir.write("UPPER.OBJ", ONE_TRIANGLE_OBJ);
    let (scene, _) = scene_with_mesh(&dir, &[("path", "\"UPPER.OBJ\""), ("material", "\"red\"")]);
    assert_eq!(load_ok(&scene).triangles.len(), 2);
}

#[test]
fn truncated_and_corrupt_gltf_files_are_errors() {
    let dir = TempDir::new("badgltf");
    let glb = std::fs::read(test_models_dir().join("tetra.glb")).unwrap();
    std::fs::write(dir.join("cut.glb"), &glb[..500]).unwrap();
    assert_file_error(
        &dir,
        "cut.glb",
        &format!(
            "truncated GLB: its header declares {} bytes, the file has 500",
            glb.len()
        ),
    );
    std::fs::write(dir.join("header.glb"), &glb[..10]).unwrap();
    assert_file_error(
        &dir,
        "header.glb",
        "truncated GLB: 10 bytes, less than its 12-byte header",
    );
    let mut lying = glb.clone();
    lying[8..12].copy_from_slice(&4u32.to_le_bytes());
    std::fs::write(dir.join("lying.glb"), &lying).unwrap();
    assert_file_error(
        &dir,
        "lying.glb",
        "corrupt GLB: its header declares 4 bytes, less than the 12-byte header",
    );
    // Not JSON, and JSON that is not glTF: the crate's reason follows.
    dir.write("text.gltf", "{ not json");
    dir.write("empty.glb", "");
    dir.write(
        "other.gltf",
        "{\"asset\": {\"version\": \"2.0\"}, \"nodes\": [{\"mesh\": 3}]}",
    );
    for name in ["text.gltf", "empty.glb", "other.gltf"] {
        let (e, note) = error_of(&dir, name);
        assert_eq!(e.file, dir.join(name));
        assert!(e.message.starts_with("not a valid glTF 2.0 file: "), "{e}");
        assert!(e.message.ends_with(&note), "{e}");
        assert!(
            std::error::Error::source(&e).is_some(),
            "{e} keeps the crate's error"
        );
    }
    let (e, _) = error_of(&dir, "other.gltf");
    assert!(
        e.message.contains("nodes[0].mesh"),
        "names the JSON path: {e}"
    );
    // Valid glTF with no scene, or a scene with no mesh: nothing to draw.
    dir.write("noscene.gltf", "{\"asset\": {\"version\": \"2.0\"}}");
    assert_file_error(
        &dir,
        "noscene.gltf",
        "no scene: the file defines no scene to place its meshes, so it would draw nothing",
    );
    dir.write(
        "nomesh.gltf",
        "{\"asset\": {\"version\": \"2.0\"}, \"scenes\": [{\"nodes\": [0]}], \"nodes\": [{}]}",
    );
    assert_file_error(
        &dir,
        "nomesh.gltf",
        "no triangles: the scene's nodes place no mesh with triangles, so it would draw nothing",
    );
}

/// tetra_external.gltf in `dir` with its buffer URI replaced by `uri`.
fn with_buffer_uri(dir: &TempDir, name: &str, uri: &str) {
    let text = std::fs::read_to_string(test_models_dir().join("tetra_external.gltf")).unwrap();
    let mut json: serde_json::Value = serde_json::from_str(&text).unwrap();
    json["buffers"][0]["uri"] = serde_json::Value::String(uri.to_string());
    dir.write(name, &json.to_string());
}

#[test]
fn buffer_uris_outside_readable_files_are_errors() {
    let dir = TempDir::new("uris");
    with_buffer_uri(&dir, "missing.gltf", "nowhere.bin");
    let (e, note) = error_of(&dir, "missing.gltf");
    let prefix = format!(
        "buffer 0: cannot read {} (URI \"nowhere.bin\"): ",
        dir.join("nowhere.bin").display()
    );
    assert!(
        e.message.starts_with(&prefix) && e.message.ends_with(&note),
        "{e}"
    );
    with_buffer_uri(&dir, "device.gltf", "/dev/zero");
    assert_file_error(
        &dir,
        "device.gltf",
        "buffer 0: cannot read /dev/zero (URI \"/dev/zero\"): not a regular file",
    );
    with_buffer_uri(&dir, "url.gltf", "https://example.com/tetra.bin");
    assert_file_error(
        &dir,
        "url.gltf",
        "buffer 0: URI \"https://example.com/tetra.bin\": a \"https:\" URI; kdray reads buffers only from files named by a relative path, or from data: URIs",
    );
    with_buffer_uri(&dir, "folder.gltf", ".");
    let (e, _) = error_of(&dir, "folder.gltf");
    assert!(e.message.contains("not a regular file"), "{e}");
    // A buffer file shorter than its byteLength.
    with_buffer_uri(&dir, "short.gltf", "short.bin");
    let bin = std::fs::read(test_models_dir().join("tetra.bin")).unwrap();
    std::fs::write(dir.join("short.bin"), &bin[..100]).unwrap();
    assert_file_error(
        &dir,
        "short.gltf",
        "buffer 0 is truncated: byteLength 120 but 100 bytes present",
    );
    // A bad data URI.
    with_buffer_uri(
        &dir,
        "data.gltf",
        "data:application/octet-stream;base64,AA#A",
    );
    let (e, _) = error_of(&dir, "data.gltf");
    assert!(
        e.message.contains("invalid base64 character at offset 2"),
        "{e}"
    );
}

#[test]
fn points_and_lines_are_errors() {
    let dir = TempDir::new("lines");
    copy_model(&dir, "lines.gltf");
    assert_file_error(
        &dir,
        "lines.gltf",
        "mesh 0 primitive 0: mode Lines is not a surface; kdray draws TRIANGLES, TRIANGLE_STRIP and TRIANGLE_FAN only",
    );
}

#[test]
fn a_latin1_obj_loads_with_its_names_matched_byte_for_byte() {
    let dir = TempDir::new("latin1");
    // Older exporters write names and comments in Latin-1: "æ" is 0xe6.
    let mut obj = b"# Terr\xe6n export\nmtllib land.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\n".to_vec();
    obj.extend_from_slice(b"usemtl Terraind\xe6k\nf 1 2 3\n");
    std::fs::write(dir.join("land.obj"), &obj).unwrap();
    std::fs::write(dir.join("land.mtl"), b"newmtl Terraind\xe6k\nKd 1 0 0\n").unwrap();
    let mesh = kdray_core::scene::obj::load_obj(&dir.join("land.obj"), true).unwrap();
    assert_eq!(mesh.triangles.len(), 1);
    assert_eq!(mesh.materials[0].name, "Terraind\u{e6}k");
    assert_eq!(mesh.materials[0].diffuse, DVec3::new(1.0, 0.0, 0.0));
    // One warning: the file was not UTF-8, named at its first such byte.
    assert_eq!(mesh.warnings.len(), 1, "{:?}", mesh.warnings);
    let w = mesh.warnings[0].to_string();
    assert!(w.contains("land.obj:1:") && w.contains("Latin-1"), "{w}");
}

#[test]
fn a_utf16_obj_is_refused_as_utf16() {
    let dir = TempDir::new("utf16");
    let mut bytes = vec![0xff, 0xfe];
    for unit in "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n".encode_utf16() {
        bytes.extend_from_slice(&unit.to_le_bytes());
    }
    std::fs::write(dir.join("wide.obj"), &bytes).unwrap();
    let (e, _) = error_of(&dir, "wide.obj");
    assert!(e.message.contains("UTF-16"), "{e}");
}
