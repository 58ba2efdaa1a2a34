//! The scene as the window traces it: prepared on the CPU (its tree and GPU
//! arrays; on a worker thread for reloads), uploaded, and turned into the
//! shader's parameters for each pass. All of the window's scene preparation
//! is in this file, so it can be replaced in one place.

use std::path::Path;

use super::camera_controller::Bounds;
use super::refinement::Pass;
use crate::error::Result;
use crate::geometry::Primitives;
use crate::gpu::{frame_params, Accel, GpuContext, SceneArrays, SceneBuffers};
use crate::kdtree::KdTree;
use crate::layout::FrameParams;
use crate::scene::{Camera, Scene};

/// A scene ready for the device: its tree (over all objects; brute force
/// only changes a flag the shader reads) and its GPU arrays. All CPU work,
/// so reloads make it on a worker thread.
pub struct PreparedScene {
    pub scene: Scene,
    tree: KdTree,
    arrays: SceneArrays,
}

impl PreparedScene {
    pub fn load(path: &Path) -> Result<Self> {
        let scene = crate::scene::load_scene(path)?;
        let prims = Primitives::from_scene(&scene);
        let tree = KdTree {
            bounds: prims.scene_bounds(),
            ..KdTree::for_primitives(&prims)
        };
        let arrays = SceneArrays::new(&scene, &prims, &tree);
        Ok(PreparedScene {
            scene,
            tree,
            arrays,
        })
    }
}

/// A prepared scene on the device.
pub struct GpuScene {
    /// Its camera and render size are overwritten for each pass.
    scene: Scene,
    tree: KdTree,
    pub buffers: SceneBuffers,
}

impl GpuScene {
    pub fn upload(ctx: &GpuContext, prepared: PreparedScene) -> Result<Self> {
        let PreparedScene {
            scene,
            tree,
            arrays,
        } = prepared;
        let buffers = SceneBuffers::upload(ctx, &arrays)?;
        Ok(GpuScene {
            scene,
            tree,
            buffers,
        })
    }

    /// The scene as loaded, but for the camera and render size (those of
    /// the last pass).
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// The scene's box, for the camera controls.
    pub fn bounds(&self) -> Bounds {
        Bounds {
            min: self.tree.bounds.min.as_dvec3(),
            max: self.tree.bounds.max.as_dvec3(),
        }
    }

    /// The shader's parameters for `pass` seen from `camera` in a `w` x `h`
    /// window.
    pub fn pass_params(
        &mut self,
        camera: Camera,
        max_depth: u32,
        accel: Accel,
        pass: &Pass,
        (w, h): (u32, u32),
    ) -> FrameParams {
        let (iw, ih) = pass.image;
        self.scene.camera = camera;
        self.scene.render.width = iw;
        self.scene.render.height = ih;
        self.scene.render.max_depth = max_depth;
        let mut p = frame_params(&self.scene, &self.tree, &self.buffers, accel);
        p.aspect = (w as f64 / h as f64) as f32;
        p.samples_per_axis = pass.samples_per_axis;
        p.sample_index = pass.sample_index;
        p.tile_origin = [0, pass.first_row];
        p.tile_size = [iw, pass.rows];
        p
    }
}
