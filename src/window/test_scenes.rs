//! The unit tests' scenes: a scene of the repository, loaded at a given
//! image size with one sample per pixel.

use crate::scene::Scene;

/// `name` (relative to the repository's root) at `width` x `height`, one
/// sample per pixel.
pub(super) fn scene(name: &str, width: u32, height: u32) -> Scene {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(name);
    let mut scene = crate::scene::load_scene(&path).unwrap();
    (scene.render.width, scene.render.height) = (width, height);
    scene.render.samples = 1;
    scene
}
