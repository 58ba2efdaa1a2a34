//! `kdray generate`'s library half: one of the bench's random scenes,
//! checked and written as a scene file whose header says how to make it
//! again ([`write_random_scene`]).

use std::path::Path;

use super::options::{check_count, check_side};
use super::random_scene::{random_scene, scene_file_text, RandomSceneSpec};
use crate::error::{Error, Result};
use crate::scene::{Scene, SceneFormat};

/// From this many objects a TOML scene loads slowly and JSON is the better
/// format (a million spheres: about ten times the time and three times the
/// memory from TOML; docs/benchmarks.md, "OBJ load").
pub const BIG_TOML_OBJECTS: usize = 100_000;

/// Generates the scene of `spec` and writes it to `output` (.json for
/// JSON, anything else TOML), atomically; returns the scene. A count or
/// image side out of range is a usage error naming its flag.
pub fn write_random_scene(spec: &RandomSceneSpec, output: &Path) -> Result<Scene> {
    check_count("--count", spec.count)?;
    check_side("--width", Some(spec.width))?;
    check_side("--height", Some(spec.height))?;
    let scene = random_scene(spec);
    let header = format!(
        "A random scene of kdray's benchmark, written by:\n  kdray generate --kind {} --count {} --seed {} --width {} --height {}\n\
         {} objects (centres uniform in [-2, 2]^3, sizes ~ 1/cbrt(N)); one light; a quarter are half mirrors.",
        spec.kind.name(),
        spec.count,
        spec.seed,
        spec.width,
        spec.height,
        spec.count
    );
    let text =
        scene_file_text(&scene, SceneFormat::from_path(output), &header).map_err(Error::Output)?;
    crate::output::write_file_atomic(output, text.as_bytes())?;
    Ok(scene)
}

/// Whether a scene of `count` objects written to `output` would be a TOML
/// file big enough to load slowly ([`BIG_TOML_OBJECTS`]).
pub fn is_big_toml(output: &Path, count: usize) -> bool {
    SceneFormat::from_path(output) == SceneFormat::Toml && count >= BIG_TOML_OBJECTS
}
