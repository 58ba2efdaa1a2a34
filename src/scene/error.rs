//! The one error type of scene loading: a file, a line, a key and a message,
//! printed on one line as `file:line: key: message`.

use std::fmt;
use std::path::{Path, PathBuf};

/// Bad input in a scene, OBJ or MTL file. The CLI maps it to exit code 2.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneError {
    /// The file at fault (the scene file, or an OBJ/MTL file it refers to).
    pub file: PathBuf,
    /// 1-based line number, where the fault has one.
    pub line: Option<usize>,
    /// The key at fault as a path into the document, e.g. `spheres[2].radius`.
    pub key: Option<String>,
    /// What is wrong, in one line.
    pub message: String,
}

impl SceneError {
    pub fn new(
        file: &Path,
        line: Option<usize>,
        key: Option<String>,
        message: impl Into<String>,
    ) -> Self {
        // Keep the promise of one line even if a message from a library has several.
        let message = message
            .into()
            .lines()
            .map(str::trim)
            .filter(|l| !l.is_empty())
            .collect::<Vec<_>>()
            .join(" ");
        SceneError {
            file: file.to_path_buf(),
            line,
            key,
            message,
        }
    }
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.file.display())?;
        if let Some(line) = self.line {
            write!(f, ":{line}")?;
        }
        if let Some(key) = &self.key {
            write!(f, ": {key}")?;
        }
        write!(f, ": {}", self.message)
    }
}

impl std::error::Error for SceneError {}
