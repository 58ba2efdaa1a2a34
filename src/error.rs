//! The crate's error type and the CLI's exit codes: 2 for bad input (scene
//! or arguments), 1 for everything else (GPU, I/O).

use crate::scene::SceneError;

#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A scene, OBJ or MTL file at fault: `file:line: key: message`.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// A command-line value out of range.
    #[error("{0}")]
    Usage(String),
    /// No adapter, a failed device request, a validation error, device loss.
    #[error("{0}")]
    Gpu(String),
    /// Writing the output failed.
    #[error("{0}")]
    Output(String),
}

impl Error {
    pub fn exit_code(&self) -> i32 {
        match self {
            Error::Scene(_) | Error::Usage(_) => 2,
            Error::Gpu(_) | Error::Output(_) => 1,
        }
    }
}

pub type Result<T, E = Error> = std::result::Result<T, E>;
