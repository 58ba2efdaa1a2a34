//! Scene format v1 (docs/scene-format.md), checked rule by rule through the
//! public API: `kdray_core::scene::parse_scene` and `kdray_core::scene::load_scene`.
//!
//! Every error test checks the file, the exact line and the exact key of the
//! error, that it prints on one line as `file:line: key: message`, and that
//! the message says what is wrong; rules that do not depend on the format are
//! checked in TOML and in JSON. Most documents are built once with [`Doc`]
//! and rendered both ways, one key per line, so that the expected line of
//! each key is known exactly.
//!
//! One module per part of the format; this file holds the helpers they share.

#[path = "../common/mod.rs"]
mod common;
mod doc;

mod animation;
mod authored_gltf;
mod bad_mesh_files;
mod camera;
mod examples;
mod files_and_syntax;
mod gltf_alpha;
mod gltf_cameras;
mod gltf_emission;
mod gltf_instances;
mod gltf_lights;
mod gltf_meshes;
mod gltf_optimised;
mod instances;
mod light_kinds;
mod mesh_normals;
mod mesh_placement;
mod meshes;
mod numbers;
mod obj_reader;
mod objects;
mod render;
mod schema;
use common::textured;
mod rough_transmission;
mod textures;
mod volume;

use common::TempDir;
use doc::*;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

use glam::DVec3;
use kdray_core::scene::obj::load_obj;
use kdray_core::scene::{
    load_scene, parse_scene, Camera, Light, LightKind, Material, RenderSettings, Scene, SceneError,
    SceneFormat, ShadowMode, Sphere, Triangle,
};

// ============================================================== temp files

/// Copies the shipped torus.obj and torus.mtl into `folder` of `dir`; returns the OBJ's path.
fn copy_torus(dir: &TempDir, folder: &str) -> PathBuf {
    for name in ["torus.obj", "torus.mtl"] {
        let text = std::fs::read_to_string(models_dir().join(name)).unwrap();
        dir.write(&format!("{folder}/{name}"), &text);
    }
    dir.join(&format!("{folder}/torus.obj"))
}

fn models_dir() -> PathBuf {
    common::repo_path("scenes/models")
}

/// A one-triangle OBJ: (0,0,0), (1,0,0), (0,1,0).
const ONE_TRIANGLE_OBJ: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

// ============================================================== parsing and errors

/// The (never read) paths that in-memory documents are parsed as.
const TOML_FILE: &str = "scenes/test.toml";
const JSON_FILE: &str = "scenes/test.json";

fn file_of(format: SceneFormat) -> &'static Path {
    Path::new(match format {
        SceneFormat::Toml => TOML_FILE,
        SceneFormat::Json => JSON_FILE,
    })
}

#[track_caller]
fn parse_ok(text: &str, format: SceneFormat) -> Scene {
    parse_scene(text, file_of(format), format)
        .unwrap_or_else(|e| panic!("expected {format:?} to parse, got: {e}\n---\n{text}"))
}

#[track_caller]
fn parse_err(text: &str, format: SceneFormat) -> SceneError {
    match parse_scene(text, file_of(format), format) {
        Ok(_) => panic!("expected {format:?} to be rejected\n---\n{text}"),
        Err(e) => e,
    }
}

#[track_caller]
fn load_ok(path: &Path) -> Scene {
    load_scene(path).unwrap_or_else(|e| panic!("expected {} to load, got: {e}", path.display()))
}

#[track_caller]
fn load_err(path: &Path) -> SceneError {
    match load_scene(path) {
        Ok(_) => panic!("expected {} to be rejected", path.display()),
        Err(e) => e,
    }
}

/// Checks all the contract promises about an error: the file, the exact line
/// and key, a Display of one line that reads `file:line: key: message`, and
/// a message that mentions each of `words` (case-insensitive).
#[track_caller]
fn assert_error(
    e: &SceneError,
    file: &Path,
    line: Option<usize>,
    key: Option<&str>,
    words: &[&str],
) {
    let shown = e.to_string();
    assert_eq!(e.file, file, "file of `{shown}`");
    assert_eq!(e.line, line, "line of `{shown}`");
    assert_eq!(e.key.as_deref(), key, "key of `{shown}`");
    assert!(
        !shown.contains(['\n', '\r']),
        "the error is not one line: {shown:?}"
    );
    let mut expected = file.display().to_string();
    if let Some(line) = line {
        expected.push_str(&format!(":{line}"));
    }
    if let Some(key) = key {
        expected.push_str(&format!(": {key}"));
    }
    expected.push_str(&format!(": {}", e.message));
    assert_eq!(shown, expected, "Display is not `file:line: key: message`");
    assert!(
        e.message.trim().len() >= 8,
        "the message says too little: `{shown}`"
    );
    let message = e.message.to_lowercase();
    for word in words {
        assert!(
            message.contains(&word.to_lowercase()),
            "the message of `{shown}` should mention {word:?}"
        );
    }
}

#[track_caller]
fn assert_close(got: DVec3, want: DVec3) {
    assert!(
        (got - want).abs().max_element() < 1e-12,
        "got {got}, want {want}"
    );
}

// ============================================================== mesh files

/// The folder of the small glTF models (written by tests/models/make_models.py).
fn test_models_dir() -> PathBuf {
    common::repo_path("tests/models")
}

/// Copies `name` from tests/models into `dir`; returns its path there.
fn copy_model(dir: &TempDir, name: &str) -> PathBuf {
    let to = dir.join(name);
    std::fs::copy(test_models_dir().join(name), &to).unwrap();
    to
}

/// Writes `scene.toml` in `dir`: the base scene plus one `[[meshes]]` entry
/// with the given keys (values as TOML text). Returns the path and the line
/// of `meshes[0].path`.
fn scene_with_mesh(dir: &TempDir, keys: &[(&str, &str)]) -> (PathBuf, usize) {
    let mut doc = base();
    for (key, value) in keys {
        doc = doc.set(&format!("meshes[0].{key}"), value);
    }
    let text = doc.toml();
    let line = text.line("meshes[0].path");
    (dir.write("scene.toml", &text.text), line)
}
