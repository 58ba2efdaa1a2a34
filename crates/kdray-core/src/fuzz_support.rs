//! What the fuzz targets (`fuzz/`) and their replay (`crates/kdray-core/tests/fuzz_regressions.rs`)
//! run on one input. Anything may fail, nothing may panic. Kept out of
//! `scene/`: the scene check goes on to build a k-d tree and trace a ray,
//! which the scene layer knows nothing of.

use std::path::Path;

use crate::scene::{self, SceneFormat};

/// Where files named by fuzz inputs are looked for: a folder that does not exist.
const NOWHERE: &str = "/nonexistent-kdray-fuzz";

/// Parse and validate scene text; if it validates, build its k-d tree and
/// trace a ray through it from the camera of the first, middle and last
/// frames (the animation's keys and orbit, and each camera's basis).
pub fn scene(text: &str, format: SceneFormat) {
    let path = Path::new(NOWHERE).join("scene");
    if let Ok(scene) = scene::parse_scene(text, &path, format) {
        let prims = crate::geometry::Primitives::from_scene(&scene);
        let tree = crate::kdtree::KdTree::for_primitives(&prims);
        let cameras = scene.camera_path();
        let last = scene.frame_count() - 1;
        for frame in [0, last / 2, last] {
            let camera = cameras.camera_at(frame);
            let basis = camera.basis();
            let ray = crate::geometry::Ray {
                origin: camera.position.as_vec3(),
                dir: basis.forward.as_vec3(),
            };
            let _ = crate::kdtree::traverse::closest_hit(
                &tree,
                &prims,
                &ray,
                crate::geometry::T_INFINITY,
            );
        }
    }
}

/// Any bytes as an OBJ file (lossily decoded), with and without materials.
pub fn obj(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    let path = Path::new(NOWHERE).join("mesh.obj");
    let _ = scene::obj::parse_obj(&text, &path, false);
    let _ = scene::obj::parse_obj(&text, &path, true);
}

/// Any bytes as an MTL material library (lossily decoded); its `map_Kd`
/// images are looked for in a folder that does not exist (an absolute path
/// is read as written).
pub fn mtl(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    let path = Path::new(NOWHERE).join("materials.mtl");
    let _ = scene::obj::parse_mtl_library(&text, &path);
}

/// Any bytes as a glTF or GLB file, with and without materials; external
/// buffers are never found.
pub fn gltf(data: &[u8]) {
    let path = Path::new(NOWHERE).join("mesh.gltf");
    for with_materials in [false, true] {
        let _ = scene::gltf::parse_gltf(data, &path, with_materials, &mut |_| {
            Err(std::io::Error::from(std::io::ErrorKind::NotFound))
        });
    }
}
