//! The scene on the device: a [`PreparedScene`] (which records the search
//! it was prepared for) with its uploaded buffers, and the kernel's
//! parameters for frames of it. `render` and the window trace a `GpuScene`.

use std::time::Instant;

use super::{Accel, GpuContext, PreparedScene, SceneBuffers};
use crate::error::Result;
use crate::geometry::Aabb;
use crate::gpu::FrameParams;
use crate::kdtree::BuildStrategy;
use crate::scene::{Camera, Light, RenderSettings, Scene};

/// An upload that failed, and the prepared scene it was given.
pub struct UploadFailed {
    pub error: crate::Error,
    /// Boxed: a prepared scene is large, and this travels in a Result.
    pub prepared: Box<PreparedScene>,
}

/// A prepared scene and its buffers on one device.
pub struct GpuScene {
    prepared: PreparedScene,
    buffers: SceneBuffers,
    /// Wall time of the upload, in milliseconds.
    upload_ms: f64,
}

impl GpuScene {
    /// Uploads `prepared`'s arrays (refused with one line if a buffer
    /// exceeds the adapter's binding limit or the device runs out of
    /// memory).
    pub fn upload(ctx: &GpuContext, prepared: PreparedScene) -> Result<Self> {
        Self::try_upload(ctx, prepared).map_err(|failed| failed.error)
    }

    /// [`GpuScene::upload`], handing the prepared scene back when the upload
    /// fails (a benchmark goes on with the next build of the same scene).
    pub fn try_upload(
        ctx: &GpuContext,
        prepared: PreparedScene,
    ) -> std::result::Result<Self, UploadFailed> {
        let started = Instant::now();
        match SceneBuffers::upload(ctx, &prepared.arrays) {
            Ok(buffers) => Ok(GpuScene {
                prepared,
                buffers,
                upload_ms: started.elapsed().as_secs_f64() * 1e3,
            }),
            Err(error) => Err(UploadFailed {
                error,
                prepared: Box::new(prepared),
            }),
        }
    }

    /// The prepared scene back, its buffers freed.
    pub fn into_prepared(self) -> PreparedScene {
        self.prepared
    }

    /// The scene with its tree and arrays, as prepared on the CPU.
    pub fn prepared(&self) -> &PreparedScene {
        &self.prepared
    }

    /// The scene as loaded.
    pub fn scene(&self) -> &Scene {
        &self.prepared.scene
    }

    /// The buffers the kernel binds.
    pub fn buffers(&self) -> &SceneBuffers {
        &self.buffers
    }

    /// The search it was prepared for.
    pub fn accel(&self) -> Accel {
        self.prepared.accel
    }

    /// How its k-d tree was built.
    pub fn strategy(&self) -> BuildStrategy {
        self.prepared.strategy
    }

    /// Wall time of the upload, in milliseconds.
    pub fn upload_ms(&self) -> f64 {
        self.upload_ms
    }

    /// The root cell of its tree: the objects' box, widened by the build's
    /// tolerance.
    pub fn bounds(&self) -> Aabb {
        self.prepared.tree.bounds
    }

    /// Puts `lights` (one per the scene's light, as an animation's
    /// [`Frame`](crate::scene::Frame) gives them) in the lights buffer, for
    /// the frames traced after it, each with its chance of being picked
    /// (rebuilt with them); the tree and the other buffers stay.
    pub fn write_lights(&self, ctx: &GpuContext, lights: &[Light]) {
        let lights = self.prepared.arrays.frame_lights(lights);
        self.buffers.write_lights(&ctx.queue, &lights);
    }

    /// The kernel's parameters for the scene's own camera and settings, with
    /// the search it was prepared for: the whole image as one tile, sample 0.
    pub fn frame_params(&self) -> FrameParams {
        self.view_params(
            &self.prepared.scene.camera,
            &self.prepared.scene.render,
            self.accel(),
        )
    }

    /// The kernel's parameters for a frame seen from `camera` with `render`'s
    /// settings, searching with `accel` (brute force needs no tree; a k-d
    /// walk over a scene prepared for brute force walks its single leaf).
    pub fn view_params(
        &self,
        camera: &Camera,
        render: &RenderSettings,
        accel: Accel,
    ) -> FrameParams {
        FrameParams::new(&camera.basis(), render, &self.buffers, accel)
    }
}
