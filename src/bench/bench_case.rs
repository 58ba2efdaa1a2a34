//! One scene a bench measures ([`BenchCase`]) and where it comes from
//! ([`CaseSource`]): the data that the configuration's list
//! ([`cases`](mod@super::cases)) and the suite ([`suite`](super::suite)) both
//! make; loading a case is in [`cases`](mod@super::cases).

use std::path::PathBuf;

use super::random_scene::RandomSceneSpec;

/// Where a measured scene comes from.
#[derive(Debug, Clone)]
pub enum CaseSource {
    Random(RandomSceneSpec),
    File(PathBuf),
    /// A scene file compiled into the binary (the suite's), read as if
    /// from `path`.
    Text {
        label: String,
        path: PathBuf,
        text: &'static str,
    },
    /// The suite's stand-in for the bunny ([`suite::generated_mesh_scene`](super::suite::generated_mesh_scene)).
    GeneratedMesh,
}

/// One scene to measure, with the image size and depth it is measured at
/// (None: the scene's own).
#[derive(Debug, Clone)]
pub struct BenchCase {
    pub source: CaseSource,
    pub width: Option<u32>,
    pub height: Option<u32>,
    pub max_depth: Option<u32>,
}
