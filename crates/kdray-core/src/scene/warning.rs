//! Warnings: what a file asks for that kdray does not do, or leaves out and
//! kdray fills in (an OBJ face with no material, a glTF texture, an
//! extension). Unlike a [`SceneError`](super::SceneError) the file still
//! loads. The readers return their warnings (on [`Mesh`](super::mesh::Mesh))
//! instead of printing them, so a caller chooses where they go: the CLI
//! prints each as one line on stderr, tests look at them.

use std::fmt;
use std::path::{Path, PathBuf};

/// One thing a file asked for that kdray ignores or fills in, printed on one
/// line as `file:line: warning: message`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Warning {
    /// The file that asks (the mesh, MTL or glTF file).
    pub file: PathBuf,
    /// 1-based line number, where the cause has one (OBJ and MTL files).
    pub line: Option<usize>,
    /// What was asked and what kdray does instead, in one line.
    pub message: String,
}

impl Warning {
    pub fn new(file: &Path, line: Option<usize>, message: impl Into<String>) -> Self {
        Warning {
            file: file.to_path_buf(),
            line,
            message: message.into(),
        }
    }
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.file.display())?;
        if let Some(line) = self.line {
            write!(f, ":{line}")?;
        }
        write!(f, ": warning: {}", self.message)
    }
}

/// Where the top-level loaders ([`load_scene`](super::load_scene) and
/// friends) send warnings when the caller does not collect them: stderr,
/// one line each, so that what a file asks for is never ignored in silence.
pub fn print_warning(warning: Warning) {
    eprintln!("{warning}");
}
