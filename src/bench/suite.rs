//! `kdray bench --suite`: the four scenes on which every build and walk is
//! measured, with the sizes chosen so the whole matrix (3 builds x 3 walks,
//! and brute force) runs in about 10-15 minutes in release on the
//! project's 2-core machine under lavapipe:
//!
//! | scene | objects | image | max_depth |
//! |---|--:|---|--:|
//! | random spheres | [`SUITE_SPHERES`] | 640x480 | 1 |
//! | random triangles | [`SUITE_TRIANGLES`] | 640x480 | 1 |
//! | the bunny (`scenes/peers/bunny.toml`), or a generated mesh | 69,666 (+ 4) | 1920x1080 | 1 |
//! | the seed scene (`scenes/seed.toml`) | 4 | 960x540 | its own (64) |
//!
//! max_depth 1 is primary + shadow rays, the work the peers trace
//! (scripts/peers), so rays/s compare with Embree's on the triangle scenes;
//! the seed scene keeps its reflections, as the study rendered it. The two
//! scene files are compiled in, so the suite runs from any folder; the
//! bunny's mesh is read from [`BUNNY_OBJ`] (Debian's glmark2-data) and,
//! where it is missing, a generated mesh of about as many triangles takes
//! its place in the same set-up ([`generated_mesh_scene`]; the summary says
//! which ran).

use std::path::{Path, PathBuf};

use glam::DVec3;

use super::bench_case::{BenchCase, CaseSource};
use super::random_scene::{RandomSceneSpec, SceneKind};
use crate::error::{Error, Result};
use crate::scene::{Scene, SceneFormat, Triangle};

/// Random spheres of the suite: the 10,000 spheres at which the k-d tree
/// and brute force are compared.
pub const SUITE_SPHERES: usize = 10_000;
/// Random triangles of the suite.
pub const SUITE_TRIANGLES: usize = 100_000;
/// Where Debian's glmark2-data puts the Stanford bunny.
pub const BUNNY_OBJ: &str = "/usr/share/glmark2/models/bunny.obj";
/// The scene of the peer comparison (docs/peers.md).
pub const BUNNY_SCENE: &str = "scenes/peers/bunny.toml";
const BUNNY_TOML: &str = include_str!("../../scenes/peers/bunny.toml");
/// The seed study's reference scene.
pub const SEED_SCENE: &str = "scenes/seed.toml";
const SEED_TOML: &str = include_str!("../../scenes/seed.toml");
/// Label of the bunny's stand-in.
pub const GENERATED_MESH: &str = "generated-mesh";

/// The suite's cases, in the order they run. `bunny_obj` is where the
/// bunny's mesh should be ([`BUNNY_OBJ`]; tests point it elsewhere).
pub fn suite_cases(seed: u64, bunny_obj: &Path) -> Vec<BenchCase> {
    let random = |kind, count| {
        CaseSource::Random(RandomSceneSpec {
            kind,
            count,
            seed,
            width: 640,
            height: 480,
        })
    };
    let mesh = if bunny_obj.is_file() {
        CaseSource::Text {
            label: "bunny.toml".into(),
            path: PathBuf::from(BUNNY_SCENE),
            text: BUNNY_TOML,
        }
    } else {
        CaseSource::GeneratedMesh
    };
    vec![
        BenchCase {
            source: random(SceneKind::Spheres, SUITE_SPHERES),
            width: None,
            height: None,
            max_depth: Some(1),
        },
        BenchCase {
            source: random(SceneKind::Triangles, SUITE_TRIANGLES),
            width: None,
            height: None,
            max_depth: Some(1),
        },
        BenchCase {
            source: mesh,
            width: Some(1920),
            height: Some(1080),
            max_depth: Some(1),
        },
        BenchCase {
            source: CaseSource::Text {
                label: "seed.toml".into(),
                path: PathBuf::from(SEED_SCENE),
                text: SEED_TOML,
            },
            width: Some(960),
            height: Some(540),
            max_depth: None,
        },
    ]
}

/// A scene file compiled into the binary, parsed as if read from `path`.
pub fn parse_text(path: &Path, text: &str) -> Result<Scene> {
    Ok(crate::scene::parse_scene(text, path, SceneFormat::Toml)?)
}

/// Rows and columns of the generated mesh's latitude-longitude grid:
/// 2 x 194 x 178 = 69,064 triangles (two per cell, one per cell in the
/// rows that touch a pole), about the bunny's 69,666.
const MESH_ROWS: usize = 180;
const MESH_COLUMNS: usize = 194;

/// The bunny's scene (camera, light, floor, mirror) with a generated mesh in
/// the bunny's place: a closed, bumpy sphere of radius about 0.9 standing on
/// the floor, triangulated on a latitude-longitude grid (fan triangles at
/// the poles), so that it has the bunny's size, position and triangle count
/// and, like a scanned mesh, small triangles of uneven shapes.
pub fn generated_mesh_scene() -> Result<Scene> {
    // The bunny's file without its [[meshes]] table (which needs the OBJ).
    let start = BUNNY_TOML
        .find("[[meshes]]")
        .ok_or_else(|| Error::Output(format!("{BUNNY_SCENE}: no [[meshes]] table")))?;
    let end = BUNNY_TOML[start..]
        .find("\n\n")
        .map_or(BUNNY_TOML.len(), |e| start + e);
    let text = format!("{}{}", &BUNNY_TOML[..start], &BUNNY_TOML[end..]);
    let mut scene = parse_text(Path::new(BUNNY_SCENE), &text)?;
    let material = scene
        .materials
        .iter()
        .position(|m| m.name == "bunny")
        .ok_or_else(|| Error::Output(format!("{BUNNY_SCENE}: no material \"bunny\"")))?
        as u32;
    let centre = DVec3::new(0.0, 0.95, 0.0);
    let point = |row: usize, column: usize| {
        let theta = std::f64::consts::PI * row as f64 / (MESH_ROWS - 1) as f64;
        let phi = std::f64::consts::TAU * column as f64 / MESH_COLUMNS as f64;
        let bumps = 1.0
            + 0.08 * (5.0 * theta).sin() * (7.0 * phi).cos()
            + 0.03 * (17.0 * theta + 3.0 * phi).sin();
        let r = 0.85 * bumps;
        centre
            + r * DVec3::new(
                theta.sin() * phi.cos(),
                theta.cos(),
                theta.sin() * phi.sin(),
            )
    };
    let mut triangles = Vec::with_capacity(2 * MESH_COLUMNS * (MESH_ROWS - 1));
    for row in 0..MESH_ROWS - 1 {
        for c in 0..MESH_COLUMNS {
            let c1 = (c + 1) % MESH_COLUMNS;
            let (a, b) = (point(row, c), point(row, c1));
            let (d, e) = (point(row + 1, c), point(row + 1, c1));
            if row == 0 {
                // The north pole: every column's top points coincide.
                triangles.push(Triangle::flat([a, e, d], material));
            } else if row == MESH_ROWS - 2 {
                triangles.push(Triangle::flat([a, b, d], material));
            } else {
                triangles.push(Triangle::flat([a, b, e], material));
                triangles.push(Triangle::flat([a, e, d], material));
            }
        }
    }
    scene.triangles.splice(0..0, triangles);
    Ok(scene)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_suite_has_four_scenes_and_says_which_mesh() {
        let missing = Path::new("/no/such/bunny.obj");
        let cases = suite_cases(7, missing);
        assert_eq!(cases.len(), 4);
        assert!(matches!(cases[2].source, CaseSource::GeneratedMesh));
        assert_eq!((cases[2].width, cases[2].height), (Some(1920), Some(1080)));
        assert_eq!(cases[2].max_depth, Some(1));
        match &cases[0].source {
            CaseSource::Random(spec) => {
                assert_eq!(
                    (spec.kind, spec.count, spec.seed),
                    (SceneKind::Spheres, SUITE_SPHERES, 7)
                )
            }
            _ => panic!("random spheres first"),
        }
        // An existing file stands for the bunny's mesh: the bunny is chosen.
        let here = Path::new(env!("CARGO_MANIFEST_DIR")).join("Cargo.toml");
        let cases = suite_cases(7, &here);
        assert!(
            matches!(&cases[2].source, CaseSource::Text { label, .. } if label == "bunny.toml")
        );
        let seed = match &cases[3].source {
            CaseSource::Text { path, text, .. } => parse_text(path, text).unwrap(),
            _ => panic!("the seed scene last"),
        };
        assert_eq!(seed.spheres.len(), 4);
    }

    #[test]
    fn without_the_bunny_the_suite_loads_the_generated_mesh_at_the_bunnys_settings() {
        let cases = suite_cases(7, Path::new("/no/such/bunny.obj"));
        let (label, scene) = cases[2].load().unwrap();
        assert_eq!(label, GENERATED_MESH);
        let r = &scene.render;
        assert_eq!((r.width, r.height, r.max_depth), (1920, 1080, 1));
        assert!(scene.spheres.is_empty() && scene.triangles.len() > 60_000);
    }

    #[test]
    fn the_generated_mesh_stands_where_the_bunny_does() {
        let scene = generated_mesh_scene().unwrap();
        let bunny = scene
            .materials
            .iter()
            .position(|m| m.name == "bunny")
            .unwrap() as u32;
        let mesh_count = scene
            .triangles
            .iter()
            .filter(|t| t.material == bunny)
            .count();
        assert_eq!(mesh_count, 2 * MESH_COLUMNS * (MESH_ROWS - 2));
        assert!((60_000..80_000).contains(&mesh_count));
        // Floor and mirror: the bunny file's four triangles.
        assert_eq!(scene.triangles.len(), mesh_count + 4);
        for t in scene.triangles.iter().filter(|t| t.material == bunny) {
            let [a, b, c] = t.vertices;
            assert!((b - a).cross(c - a).length() > 1e-9, "degenerate {t:?}");
            for v in t.vertices {
                assert!(
                    v.y > 0.0 && v.y < 2.0 && v.x.abs() < 1.1 && v.z.abs() < 1.1,
                    "{v}"
                );
            }
        }
    }
}
