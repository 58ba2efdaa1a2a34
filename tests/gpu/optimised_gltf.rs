//! The web's optimised glTF files render as their original does: Khronos'
//! BoxTextured and the variants glTF Transform made of it
//! (tests/models/optimised/: quantized, meshopt- and Draco-compressed
//! geometry, a WebP texture), each rendered small on the GPU and compared
//! with the original's image. And an OBJ of another project written in
//! Latin-1 (assimp-testmodels' regr01.obj) loads, its names matched.

use std::path::Path;

use crate::common;

use common::gpu;
use kdray::gpu::{Accel, TilePlan};
use kdray::scene::{Scene, Warning};

/// The model opened alone (its default camera and light), rendered at
/// 96 x 96: the RGB bytes and the warnings.
fn render(path: &Path) -> (Vec<u8>, Vec<Warning>) {
    let mut warnings = Vec::new();
    let mut scene: Scene =
        kdray::scene::load_scene_with(path, &mut |_| {}, &mut |w| warnings.push(w))
            .unwrap_or_else(|e| panic!("{e}"));
    scene.render.width = 96;
    scene.render.height = 96;
    let rgb = kdray::render::render_scene(
        gpu(),
        &scene,
        Accel::Kdtree,
        TilePlan::DEFAULT_MAX_TILE_PIXELS,
    )
    .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
    .0
    .rgb;
    (rgb, warnings)
}

/// Mean absolute difference per channel, in levels of 255.
fn mean_difference(a: &[u8], b: &[u8]) -> f64 {
    assert_eq!(a.len(), b.len());
    let total: u64 = a
        .iter()
        .zip(b)
        .map(|(x, y)| u64::from(x.abs_diff(*y)))
        .sum();
    total as f64 / a.len() as f64
}

#[test]
fn quantized_meshopt_draco_and_webp_boxes_render_as_the_original() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/models/optimised");
    let (original, _) = render(&dir.join("box.glb"));
    // The original is not blank: the box and its texture show.
    assert!(
        original.chunks(3).any(|p| p != &original[0..3]),
        "a blank image"
    );
    for name in [
        "box_quantized.glb",
        "box_meshopt.glb",
        "box_draco.glb",
        "box_webp.glb",
    ] {
        let (rgb, warnings) = render(&dir.join(name));
        assert!(warnings.is_empty(), "{name}: {warnings:?}");
        // Measured on lavapipe: 0 for quantize and meshopt (the box's
        // corners quantize exactly), 0.04 for Draco, 0.12 for lossy WebP.
        let d = mean_difference(&original, &rgb);
        assert!(d < 0.5, "{name}: mean difference {d} levels");
    }
}

/// regr01.obj names a material `Terraind\xe6k` (Latin-1 "æ") in its OBJ
/// and MTL files: it loads, with one warning saying it was read as Latin-1,
/// and that material is found (no "undefined material" warning).
#[test]
fn a_latin1_obj_of_another_project_loads_with_its_materials() {
    let path = Path::new("/usr/share/assimp/models/OBJ/regr01.obj");
    assert!(
        path.exists(),
        "{} is missing: this test needs Debian's assimp-testmodels (scripts/test.sh installs it)",
        path.display()
    );
    let mut warnings = Vec::new();
    let scene = kdray::scene::load_scene_with(path, &mut |_| {}, &mut |w| warnings.push(w))
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(!scene.triangles.is_empty());
    let latin1: Vec<&Warning> = warnings
        .iter()
        .filter(|w| w.message.contains("Latin-1"))
        .collect();
    assert_eq!(latin1.len(), 1, "{warnings:?}");
    assert!(
        scene
            .materials
            .iter()
            .any(|m| m.name.contains("Terraind\u{e6}k")),
        "{:?}",
        scene.materials.iter().map(|m| &m.name).collect::<Vec<_>>()
    );
    assert!(
        !warnings.iter().any(|w| w.message.contains("Terraind")),
        "{warnings:?}"
    );
}
