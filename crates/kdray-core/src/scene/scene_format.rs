//! The two languages a scene file is written in, TOML and JSON, and which
//! one a file's name says it is.

use std::path::Path;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SceneFormat {
    Toml,
    Json,
}

impl SceneFormat {
    /// `.json` files are JSON; everything else is read as TOML.
    pub fn from_path(path: &Path) -> Self {
        match path.extension().and_then(|e| e.to_str()) {
            Some(ext) if ext.eq_ignore_ascii_case("json") => SceneFormat::Json,
            _ => SceneFormat::Toml,
        }
    }
}
