//! The scenes a bench measures: each [`BenchCase`] (defined in
//! [`bench_case`](super::bench_case)) loaded from where it comes from (a
//! random scene, a scene file, the suite's compiled-in files or its
//! generated mesh) at the image size and depth it is measured at, and the
//! list of them a configuration asks for ([`cases`]).

use std::path::Path;

use super::bench_case::{BenchCase, CaseSource};
use super::options::{BenchConfig, BenchMode};
use super::random_scene::{self, random_scene, RandomSceneSpec, SceneKind};
use super::suite;
use crate::error::Result;
use crate::scene::Scene;

impl BenchCase {
    /// What the progress line says while the scene is made.
    pub fn describe(&self) -> String {
        match &self.source {
            CaseSource::Random(spec) => format!("generating {} {}", spec.count, spec.kind.name()),
            CaseSource::File(p) | CaseSource::Text { path: p, .. } => {
                format!("loading {}", p.display())
            }
            CaseSource::GeneratedMesh => "generating a mesh in the bunny's place".into(),
        }
    }

    /// The scene's label and the scene, with the overrides applied.
    pub fn load(&self) -> Result<(String, Scene)> {
        let (label, mut scene) = match &self.source {
            CaseSource::Random(spec) => (spec.kind.name().to_string(), random_scene(spec)),
            CaseSource::File(path) => (
                path.file_name().map_or_else(
                    || path.display().to_string(),
                    |f| f.to_string_lossy().into_owned(),
                ),
                crate::scene::load_scene(path)?,
            ),
            CaseSource::Text { label, path, text } => {
                (label.clone(), suite::parse_text(path, text)?)
            }
            CaseSource::GeneratedMesh => (
                suite::GENERATED_MESH.to_string(),
                suite::generated_mesh_scene()?,
            ),
        };
        scene.render.width = self.width.unwrap_or(scene.render.width);
        scene.render.height = self.height.unwrap_or(scene.render.height);
        if let Some(d) = self.max_depth {
            scene.render.max_depth = d;
        }
        Ok((label, scene))
    }
}

/// The cases `config` asks for.
pub fn cases(config: &BenchConfig) -> Vec<BenchCase> {
    match config.mode {
        BenchMode::Suite => suite::suite_cases(config.seed, Path::new(suite::BUNNY_OBJ)),
        BenchMode::Scenes => config
            .scenes
            .iter()
            .map(|p| BenchCase {
                source: CaseSource::File(p.clone()),
                width: config.width,
                height: config.height,
                max_depth: config.max_depth,
            })
            .collect(),
        BenchMode::Random => {
            let kind = config.kind.unwrap_or(SceneKind::Spheres);
            config
                .sizes
                .iter()
                .map(|&n| BenchCase {
                    source: CaseSource::Random(RandomSceneSpec {
                        kind,
                        count: n,
                        seed: config.seed,
                        width: config.width.unwrap_or(random_scene::DEFAULT_WIDTH),
                        height: config.height.unwrap_or(random_scene::DEFAULT_HEIGHT),
                    }),
                    width: None,
                    height: None,
                    max_depth: config.max_depth,
                })
                .collect()
        }
    }
}

/// `label-n`, in the characters a file name may safely hold.
pub fn scene_slug(label: &str, n: usize) -> String {
    let clean: String = label
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() {
                c.to_ascii_lowercase()
            } else {
                '-'
            }
        })
        .collect();
    format!("{clean}-{n}")
}
