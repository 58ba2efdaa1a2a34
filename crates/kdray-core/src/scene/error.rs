//! The one error type of scene loading: a file, a line, a key and a message,
//! printed on one line as `file:line: key: message`.

use std::fmt;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Bad input in a scene, mesh (OBJ, glTF), MTL or buffer file. The CLI maps
/// it to exit code 2.
#[derive(Debug, Clone)]
pub struct SceneError {
    /// The file at fault (the scene file, or a mesh/MTL/buffer file it refers to).
    pub file: PathBuf,
    /// 1-based line number, where the fault has one.
    pub line: Option<usize>,
    /// The key at fault as a path into the document, e.g. `spheres[2].radius`.
    pub key: Option<String>,
    /// What is wrong, in one line (a library error's text included).
    pub message: String,
    /// The library error behind it (I/O, TOML, JSON, glTF), if any; its text
    /// is already part of `message`.
    source: Option<Arc<dyn std::error::Error + Send + Sync + 'static>>,
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
            source: None,
        }
    }

    /// The same error with another message; the source is kept.
    pub(crate) fn reworded(self, message: impl Into<String>) -> Self {
        SceneError {
            source: self.source,
            ..SceneError::new(&self.file, self.line, self.key, message)
        }
    }

    /// The same error, keeping `source` as its cause.
    pub fn with_source(mut self, source: impl std::error::Error + Send + Sync + 'static) -> Self {
        self.source = Some(Arc::new(source));
        self
    }
}

/// Equal when file, line, key and message are: the source is already in the
/// message, and library errors are not comparable.
impl PartialEq for SceneError {
    fn eq(&self, other: &Self) -> bool {
        (&self.file, self.line, &self.key, &self.message)
            == (&other.file, other.line, &other.key, &other.message)
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

impl std::error::Error for SceneError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        self.source
            .as_deref()
            .map(|e| e as &(dyn std::error::Error + 'static))
    }
}
