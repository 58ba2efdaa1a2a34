//! The kernel's per-frame uniform ([`FrameParams`]) built from a camera
//! frame, the render settings and the uploaded scene. The tile fields are
//! filled in per dispatch by the renderer, `sample_index` per pass by the
//! window. [`FrameParams::uniform_buffer`] makes the buffer it is written
//! to.

use super::{GpuContext, SceneBuffers};
use crate::geometry::Aabb;
use crate::gpu::FrameParams;
use crate::kdtree::Traversal;
use crate::layout::{EnvironmentWords, SceneArrays};
use crate::layout::{
    ACCEL_BRUTE, ACCEL_KDTREE, SHADOW_AMBIENT, SHADOW_SEED, TRAVERSAL_RESTART, TRAVERSAL_ROPES,
    TRAVERSAL_SHORT_STACK,
};
use crate::layout::{INTEGRATOR_PATH, INTEGRATOR_WHITTED};
use crate::prepare::{Accel, PreparedScene};
use crate::scene::{CameraBasis, Integrator, RenderSettings, ShadowMode};

impl FrameParams {
    /// A uniform buffer for one `FrameParams`, written before each dispatch
    /// (the renderer's and the window's; `label` names it).
    pub fn uniform_buffer(ctx: &GpuContext, label: &str) -> crate::Result<wgpu::Buffer> {
        ctx.checked("creating the frame parameters", |device| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: std::mem::size_of::<FrameParams>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        })
    }

    /// What `trace_rays` reads: the scene's counts and box, and the accel
    /// (no camera, image or tile).
    pub fn for_queries(scene: &SceneBuffers, accel: Accel) -> FrameParams {
        FrameParams {
            scene_min: scene.bounds.min.to_array(),
            sphere_count: scene.sphere_count,
            scene_max: scene.bounds.max.to_array(),
            object_count: scene.object_count,
            light_count: scene.light_count,
            emitter_count: scene.emitter_count,
            accel: accel_value(accel),
            node_count: scene.node_count,
            ..bytemuck::Zeroable::zeroed()
        }
    }

    /// The whole image as one tile, sample 0.
    pub fn new(
        camera: &CameraBasis,
        render: &RenderSettings,
        scene: &SceneBuffers,
        accel: Accel,
    ) -> FrameParams {
        let counts = SceneCounts {
            bounds: scene.bounds,
            sphere_count: scene.sphere_count,
            object_count: scene.object_count,
            light_count: scene.light_count,
            emitter_count: scene.emitter_count,
            node_count: scene.node_count,
            environment: scene.environment,
        };
        Self::with_counts(camera, render, &counts, accel)
    }

    /// [`FrameParams::new`] for `prepared`'s own camera and settings,
    /// searching with the accel it was prepared for, over `buffers`
    /// uploaded from it ([`super::GpuScene::frame_params`] for a scene
    /// uploaded whole; this for buffers uploaded another way).
    pub fn for_prepared(prepared: &PreparedScene, buffers: &SceneBuffers) -> FrameParams {
        let scene = &prepared.scene;
        Self::new(
            &scene.camera.basis(),
            &scene.render,
            buffers,
            prepared.accel,
        )
    }

    /// [`FrameParams::new`] for arrays not uploaded (the web export writes
    /// them into its bundle): the same counts, read from the host copies.
    pub fn for_arrays(
        camera: &CameraBasis,
        render: &RenderSettings,
        arrays: &SceneArrays,
        accel: Accel,
    ) -> FrameParams {
        let counts = SceneCounts {
            bounds: arrays.bounds,
            sphere_count: arrays.spheres.len() as u32,
            object_count: arrays.objects.len() as u32,
            light_count: arrays.point_light_count(),
            emitter_count: arrays.emitter_count,
            node_count: arrays.nodes.len() as u32,
            environment: arrays.environment,
        };
        Self::with_counts(camera, render, &counts, accel)
    }

    fn with_counts(
        camera: &CameraBasis,
        render: &RenderSettings,
        scene: &SceneCounts,
        accel: Accel,
    ) -> FrameParams {
        let f = |v: glam::DVec3| v.as_vec3().to_array();
        FrameParams {
            camera_position: f(camera.position),
            tan_half_vfov: camera.tan_half_vfov as f32,
            camera_forward: f(camera.forward),
            aspect: (render.width as f64 / render.height as f64) as f32,
            camera_right: f(camera.right),
            min_intensity: render.min_intensity as f32,
            camera_up: f(camera.up),
            max_depth: render.max_depth,
            background: f(render.background),
            shadow_mode: match render.shadow_mode {
                ShadowMode::Ambient => SHADOW_AMBIENT,
                ShadowMode::Seed => SHADOW_SEED,
            },
            scene_min: scene.bounds.min.to_array(),
            sphere_count: scene.sphere_count,
            scene_max: scene.bounds.max.to_array(),
            object_count: scene.object_count,
            width: render.width,
            height: render.height,
            samples_per_axis: render.samples_per_axis(),
            light_count: scene.light_count,
            tile_origin: [0, 0],
            tile_size: [render.width, render.height],
            accel: accel_value(accel),
            node_count: scene.node_count,
            sample_index: 0,
            traversal: traversal_value(Traversal::default()),
            integrator: match render.integrator {
                Integrator::Whitted => INTEGRATOR_WHITTED,
                Integrator::Path => INTEGRATOR_PATH,
            },
            seed: render.seed,
            emitter_count: scene.emitter_count,
            sample_count: 0,
            samples: render.samples,
            env_offset: scene.environment.offset,
            env_width: scene.environment.width,
            env_height: scene.environment.height,
            env_intensity: scene.environment.intensity,
            env_rotation_cos: scene.environment.rotation_cos,
            env_rotation_sin: scene.environment.rotation_sin,
            _pad0: 0,
        }
    }

    /// The same parameters with the k-d walk `traversal` (the default walk
    /// unless set).
    pub fn with_traversal(self, traversal: Traversal) -> FrameParams {
        FrameParams {
            traversal: traversal_value(traversal),
            ..self
        }
    }
}

/// What the kernel's parameters say of the scene's arrays.
struct SceneCounts {
    bounds: Aabb,
    sphere_count: u32,
    object_count: u32,
    light_count: u32,
    emitter_count: u32,
    node_count: u32,
    environment: EnvironmentWords,
}

/// `FrameParams::traversal` for `traversal`.
pub(super) fn traversal_value(traversal: Traversal) -> u32 {
    match traversal {
        Traversal::Restart => TRAVERSAL_RESTART,
        Traversal::Ropes => TRAVERSAL_ROPES,
        Traversal::ShortStack => TRAVERSAL_SHORT_STACK,
    }
}

/// `FrameParams::accel` for `accel`.
pub(super) fn accel_value(accel: Accel) -> u32 {
    match accel {
        Accel::Kdtree => ACCEL_KDTREE,
        Accel::Brute => ACCEL_BRUTE,
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn every_accel_is_found_by_its_name() {
        kdray_core::choice::assert_names_round_trip::<super::Accel>();
    }
}
