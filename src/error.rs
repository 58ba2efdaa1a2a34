//! The crate's error type and the CLI's exit codes: 2 for bad input (scene
//! or arguments), 1 for everything else (GPU, I/O).

use std::path::PathBuf;

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
    /// Reading or writing a file failed: `path: what: cause`.
    #[error("{}: {what}: {source}", path.display())]
    File {
        path: PathBuf,
        what: &'static str,
        #[source]
        source: std::io::Error,
    },
    /// Encoding a streamed PNG failed.
    #[error("{}: {what}: {source}", path.display())]
    Png {
        path: PathBuf,
        what: &'static str,
        #[source]
        source: png::EncodingError,
    },
    /// Encoding or decoding an image through the `image` crate failed.
    #[error("{}: {source}", path.display())]
    Image {
        path: PathBuf,
        #[source]
        source: image::ImageError,
    },
    /// Serialising a report or figures as JSON failed.
    #[error("writing JSON: {0}")]
    Json(#[from] serde_json::Error),
    /// Any other failure to produce the output.
    #[error("{0}")]
    Output(String),
}

impl Error {
    pub fn exit_code(&self) -> i32 {
        match self {
            Error::Scene(_) | Error::Usage(_) => 2,
            Error::Gpu(_)
            | Error::File { .. }
            | Error::Png { .. }
            | Error::Image { .. }
            | Error::Json(_)
            | Error::Output(_) => 1,
        }
    }
}

pub type Result<T, E = Error> = std::result::Result<T, E>;
