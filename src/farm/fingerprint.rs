//! What a farm's images are made from: the scene file and every file it
//! loads (meshes, MTL, glTF buffers), each with its size and a 64-bit
//! FNV-1a hash of its bytes, recorded in the plan so that a re-run or a
//! task notices a changed input and names it.

use std::hash::Hasher;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::scene::Scene;

/// One input file as it was when the farm was planned.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct InputFile {
    /// Absolute.
    pub path: PathBuf,
    pub bytes: u64,
    /// FNV-1a, 64 bits, as 16 hex digits.
    pub fnv1a64: String,
}

/// Loads the scene at `path` (absolute) and fingerprints the files it read,
/// in the order it read them (the scene file first).
pub fn load_and_fingerprint(path: &Path) -> Result<(Scene, Vec<InputFile>)> {
    let mut read = Vec::new();
    let scene = crate::scene::load_scene_observed(path, &mut |p| read.push(p.to_path_buf()))?;
    let mut inputs: Vec<InputFile> = Vec::with_capacity(read.len());
    for p in read {
        let path = std::path::absolute(&p).unwrap_or(p);
        if inputs.iter().any(|i| i.path == path) {
            continue;
        }
        inputs.push(fingerprint_file(&path)?);
    }
    Ok((scene, inputs))
}

/// Size and hash of one file.
pub fn fingerprint_file(path: &Path) -> Result<InputFile> {
    let bytes = std::fs::read(path).map_err(|source| Error::File {
        path: path.to_path_buf(),
        what: "cannot read",
        source,
    })?;
    Ok(InputFile {
        path: path.to_path_buf(),
        bytes: bytes.len() as u64,
        fnv1a64: format!("{:016x}", fnv1a64(&bytes)),
    })
}

/// The 64-bit FNV-1a hash of `bytes`, by the `fnv` crate: stable across
/// builds and platforms, and about 1 GB/s, ample to notice an edited file
/// (it is not a defence against someone forging one).
pub fn fnv1a64(bytes: &[u8]) -> u64 {
    let mut hasher = fnv::FnvHasher::default();
    hasher.write(bytes);
    hasher.finish()
}

/// The first difference between two lists of inputs, in words, or `None`.
pub fn difference(was: &[InputFile], now: &[InputFile]) -> Option<String> {
    for old in was {
        match now.iter().find(|n| n.path == old.path) {
            None => {
                return Some(format!(
                    "{} is no longer loaded by the scene",
                    old.path.display()
                ))
            }
            Some(new) if new != old => {
                return Some(format!("{} changed", old.path.display()));
            }
            Some(_) => {}
        }
    }
    now.iter()
        .find(|n| !was.iter().any(|o| o.path == n.path))
        .map(|n| format!("the scene now also loads {}", n.path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fnv1a64_matches_the_published_test_vectors() {
        assert_eq!(fnv1a64(b""), 0xcbf29ce484222325);
        assert_eq!(fnv1a64(b"a"), 0xaf63dc4c8601ec8c);
        assert_eq!(fnv1a64(b"foobar"), 0x85944171f73967e8);
    }

    fn input(path: &str, hash: &str) -> InputFile {
        InputFile {
            path: path.into(),
            bytes: 1,
            fnv1a64: hash.into(),
        }
    }

    #[test]
    fn differences_name_the_file() {
        let was = [input("/s.toml", "1"), input("/m.obj", "2")];
        assert_eq!(difference(&was, &was), None);
        let edited = [input("/s.toml", "1"), input("/m.obj", "3")];
        assert_eq!(difference(&was, &edited).unwrap(), "/m.obj changed");
        let fewer = [input("/s.toml", "1")];
        assert!(difference(&was, &fewer)
            .unwrap()
            .contains("/m.obj is no longer"));
        assert!(difference(&fewer, &was)
            .unwrap()
            .contains("also loads /m.obj"));
    }
}
