//! The scene as the window traces it: a [`PreparedScene`] (made on a worker
//! thread for reloads), uploaded, and turned into the kernel's parameters
//! for each pass.

use std::path::Path;

use super::camera_controller::Bounds;
use super::refinement::Pass;
use crate::error::Result;
use crate::gpu::{Accel, GpuContext, PreparedScene, SceneBuffers};
use crate::kdtree::BuildStrategy;
use crate::layout::FrameParams;
use crate::scene::{Camera, RenderSettings, Scene};

/// Loads `path` and prepares it with the k-d tree built by `strategy`: the
/// window switches between the tree and brute force per frame (brute force
/// only changes a flag the kernel reads), so the tree is always built.
/// `seen` is told of every file read (the files to watch for hot reload).
pub fn load(
    path: &Path,
    strategy: BuildStrategy,
    seen: &mut dyn FnMut(&Path),
) -> Result<PreparedScene> {
    let scene = crate::scene::load_scene_observed(path, seen)?;
    Ok(PreparedScene::built_by(scene, Accel::Kdtree, strategy))
}

/// A prepared scene on the device.
pub struct GpuScene {
    prepared: PreparedScene,
    pub buffers: SceneBuffers,
}

impl GpuScene {
    pub fn upload(ctx: &GpuContext, prepared: PreparedScene) -> Result<Self> {
        let buffers = prepared.upload(ctx)?;
        Ok(GpuScene { prepared, buffers })
    }

    /// How its k-d tree was built.
    pub fn strategy(&self) -> BuildStrategy {
        self.prepared.strategy
    }

    /// The scene as loaded.
    pub fn scene(&self) -> &Scene {
        &self.prepared.scene
    }

    /// The scene's box, for the camera controls.
    pub fn bounds(&self) -> Bounds {
        let b = self.prepared.tree.bounds;
        Bounds {
            min: b.min.as_dvec3(),
            max: b.max.as_dvec3(),
        }
    }

    /// The kernel's parameters for `pass` seen from `camera` in a `w` x `h`
    /// window.
    pub fn pass_params(
        &self,
        camera: Camera,
        max_depth: u32,
        accel: Accel,
        pass: &Pass,
        (w, h): (u32, u32),
    ) -> FrameParams {
        let (iw, ih) = pass.image;
        let render = RenderSettings {
            width: iw,
            height: ih,
            max_depth,
            ..self.prepared.scene.render
        };
        let mut p = FrameParams::new(&camera.basis(), &render, &self.buffers, accel);
        p.aspect = (w as f64 / h as f64) as f32;
        p.samples_per_axis = pass.samples_per_axis;
        p.sample_index = pass.sample_index;
        p.tile_origin = [0, pass.first_row];
        p.tile_size = [iw, pass.rows];
        p
    }
}
