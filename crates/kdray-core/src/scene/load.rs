//! Scene files in: read a TOML or JSON scene file, deserialise it into the
//! file schema ([`schema`](super::schema)) and validate it into a
//! [`Scene`](super::Scene) ([`validate`](super::validate)), loading its
//! meshes on the way. Every error names the file, the line (via the
//! lazily made [`SourceMap`](super::source_map::SourceMap)) and the key. A
//! path to a model file (`.obj`, `.gltf`, `.glb`) instead of a scene file
//! is opened as a scene of its own ([`model_scene`](super::model_scene)).
//! Warnings go to the caller's sink (the `_with` functions) or, from the
//! plain ones, to stderr.

use std::cell::{OnceCell, RefCell};
use std::path::Path;

use super::document_errors::{json_error, toml_error};
use super::error::SceneError;
use super::mesh_file::MeshFormat;
use super::scene_format::SceneFormat;
use super::schema::{RawScene, TableOf};
use super::source_map::LazySourceMap;
use super::validate::Validator;
use super::validated_scene::Scene;
use super::warning::{print_warning, Warning};

/// Reads and validates a scene file; mesh paths are relative to its folder.
/// A model file (`.obj`, `.gltf`, `.glb`) becomes the scene of
/// [`model_scene`](super::model_scene). Warnings are printed on stderr.
pub fn load_scene(path: &Path) -> Result<Scene, SceneError> {
    load_scene_with(path, &mut |_| {}, &mut print_warning)
}

/// [`load_scene`], calling `on_read` with every file it reads (the scene
/// file first, then each mesh and its MTL or buffer files), just before
/// reading it, and also for a file that then fails: the list of files a
/// reload must watch, the file that broke included.
pub fn load_scene_observed(
    path: &Path,
    on_read: &mut dyn FnMut(&Path),
) -> Result<Scene, SceneError> {
    load_scene_with(path, on_read, &mut print_warning)
}

/// [`load_scene_observed`], handing each [`Warning`] to `warn` instead of
/// printing it.
pub fn load_scene_with(
    path: &Path,
    on_read: &mut dyn FnMut(&Path),
    warn: &mut dyn FnMut(Warning),
) -> Result<Scene, SceneError> {
    if MeshFormat::of_path(path).is_some() {
        return super::model_scene::model_scene_with(path, on_read, warn);
    }
    on_read(path);
    let bytes = super::input_file::read_input_file(path).map_err(|e| {
        SceneError::new(path, None, None, format!("cannot read scene file: {e}")).with_source(e)
    })?;
    let text = String::from_utf8(bytes).map_err(|e| {
        SceneError::new(
            path,
            None,
            None,
            format!("cannot read scene file: not UTF-8 text ({e})"),
        )
        .with_source(e)
    })?;
    parse_observed(&text, path, SceneFormat::from_path(path), on_read, warn)
}

/// Parses scene text; `path` names the file in errors and anchors mesh paths.
/// Warnings are printed on stderr.
pub fn parse_scene(text: &str, path: &Path, format: SceneFormat) -> Result<Scene, SceneError> {
    parse_scene_with(text, path, format, &mut print_warning)
}

/// [`parse_scene`], handing each [`Warning`] to `warn` instead of printing it.
pub fn parse_scene_with(
    text: &str,
    path: &Path,
    format: SceneFormat,
    warn: &mut dyn FnMut(Warning),
) -> Result<Scene, SceneError> {
    parse_observed(text, path, format, &mut |_| {}, warn)
}

fn parse_observed(
    text: &str,
    path: &Path,
    format: SceneFormat,
    on_read: &mut dyn FnMut(&Path),
    warn: &mut dyn FnMut(Warning),
) -> Result<Scene, SceneError> {
    let map = LazySourceMap {
        text,
        format,
        map: OnceCell::new(),
    };
    let raw = match format {
        SceneFormat::Toml => toml::from_str::<TableOf<RawScene>>(text)
            .map_err(|e| toml_error(e, text, map.get(), path))?,
        SceneFormat::Json => serde_json::from_str::<TableOf<RawScene>>(text)
            .map_err(|e| json_error(e, text, map.get(), path))?,
    };
    Validator {
        file: path,
        map,
        on_read: RefCell::new(on_read),
        warn: RefCell::new(warn),
    }
    .scene(raw.0)
}
