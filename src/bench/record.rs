//! One run of the bench, as `bench.json` and `bench.csv` record it: a
//! (scene, acceleration[, build, walk]) measurement, or why there is none
//! ([`RunStatus`]).

use serde::{Deserialize, Serialize};

use super::named;
use crate::choice::Choice;
use crate::gpu::Accel;
use crate::kdtree::{BuildStrategy, Traversal};
use crate::scene::Scene;

/// How a run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum RunStatus {
    Ok,
    /// Over the brute-force budget: not run.
    Skipped,
    Failed,
}

impl RunStatus {
    pub fn name(self) -> &'static str {
        match self {
            RunStatus::Ok => "ok",
            RunStatus::Skipped => "skipped",
            RunStatus::Failed => "failed",
        }
    }
}

/// One (scene, acceleration[, build, walk]) measurement, or the record of
/// why there is none.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct RunRecord {
    /// `spheres`, `triangles`, `mixed`, `gears`, the scene file's name, or
    /// `generated-mesh` (the suite's stand-in for the bunny).
    pub scene: String,
    /// Objects (spheres + triangles).
    pub n: usize,
    pub spheres: usize,
    pub triangles: usize,
    pub accel: Accel,
    /// The k-d tree's build (kdtree runs).
    #[serde(default, with = "named::option")]
    pub build: Option<BuildStrategy>,
    /// The k-d walk (kdtree runs).
    #[serde(default)]
    pub traversal: Option<Traversal>,
    /// The scene as measured, written for peers (relative to the output
    /// folder; with `write_scenes`).
    #[serde(default)]
    pub scene_file: Option<String>,
    pub status: RunStatus,
    /// Why it was skipped or failed.
    pub note: Option<String>,
    pub width: u32,
    pub height: u32,
    pub samples: u32,
    pub max_depth: u32,
    /// Generating (random) or loading (file) the scene.
    pub scene_ms: f64,
    /// Building the k-d tree (kdtree runs only).
    pub build_ms: Option<f64>,
    pub kd_nodes: Option<usize>,
    pub kd_leaves: Option<usize>,
    pub kd_max_depth: Option<u32>,
    pub kd_refs_per_leaf: Option<f64>,
    /// Flattening into GPU arrays and creating the storage buffers.
    pub upload_ms: Option<f64>,
    pub gpu_scene_bytes: Option<u64>,
    /// Median GPU time of the timed frames.
    pub gpu_ms: Option<f64>,
    pub gpu_ms_min: Option<f64>,
    pub gpu_ms_max: Option<f64>,
    /// Every timed frame's GPU time, in order.
    pub gpu_ms_samples: Vec<f64>,
    pub gpu_time_source: Option<crate::gpu::GpuTimeSource>,
    /// Median host wall time of one `Renderer::render` call (dispatch + readback + packing).
    pub frame_wall_ms: Option<f64>,
    pub primary_rays: Option<u64>,
    pub shadow_rays: Option<u64>,
    pub reflection_rays: Option<u64>,
    pub total_rays: Option<u64>,
    /// All rays per second of median GPU time, in millions.
    pub mrays_per_s: Option<f64>,
    /// Primary rays per second of median GPU time, in millions.
    pub primary_mrays_per_s: Option<f64>,
    /// Peak resident host memory during this run, MiB (VmHWM; Linux only).
    pub peak_host_mib: Option<f64>,
    /// The walk's work per ray (all rays of the warm-up frame, as
    /// `render --stats` counts them).
    #[serde(default)]
    pub nodes_visited_per_ray: Option<f64>,
    #[serde(default)]
    pub leaves_visited_per_ray: Option<f64>,
    #[serde(default)]
    pub objects_tested_per_ray: Option<f64>,
    /// Brute runs: the most pixels by which any k-d cell's image of this
    /// scene differs from brute force's.
    pub pixels_differing_from_kdtree: Option<u64>,
    /// Kdtree runs: pixels whose colour differs from brute force's image.
    #[serde(default)]
    pub pixels_differing_from_brute: Option<u64>,
    /// Pixels whose loops reached llvmpipe's 65,535-iteration limit (and may
    /// be wrong); counted on llvmpipe only, null elsewhere.
    pub loop_limited_pixels: Option<u64>,
}

impl RunRecord {
    /// A run of `accel` on scene `s` (labelled `scene`, made in
    /// `scene_ms`) with nothing measured yet.
    pub fn empty(scene: &str, s: &Scene, accel: Accel, scene_ms: f64) -> Self {
        RunRecord {
            scene: scene.to_string(),
            n: s.object_count(),
            spheres: s.spheres.len(),
            triangles: s.triangles.len(),
            accel,
            build: None,
            traversal: None,
            scene_file: None,
            status: RunStatus::Ok,
            note: None,
            width: s.render.width,
            height: s.render.height,
            samples: s.render.samples,
            max_depth: s.render.max_depth,
            scene_ms,
            build_ms: None,
            kd_nodes: None,
            kd_leaves: None,
            kd_max_depth: None,
            kd_refs_per_leaf: None,
            upload_ms: None,
            gpu_scene_bytes: None,
            gpu_ms: None,
            gpu_ms_min: None,
            gpu_ms_max: None,
            gpu_ms_samples: Vec::new(),
            gpu_time_source: None,
            frame_wall_ms: None,
            primary_rays: None,
            shadow_rays: None,
            reflection_rays: None,
            total_rays: None,
            mrays_per_s: None,
            primary_mrays_per_s: None,
            peak_host_mib: None,
            nodes_visited_per_ray: None,
            leaves_visited_per_ray: None,
            objects_tested_per_ray: None,
            pixels_differing_from_kdtree: None,
            pixels_differing_from_brute: None,
            loop_limited_pixels: None,
        }
    }

    /// `kdtree sah/ropes`, `brute`: the run's acceleration and cell.
    pub fn cell_name(&self) -> String {
        match (self.build, self.traversal) {
            (Some(b), Some(t)) => format!("{} {}/{}", self.accel.name(), b.name(), t.name()),
            _ => self.accel.name().to_string(),
        }
    }

    pub fn is_ok(&self) -> bool {
        self.status == RunStatus::Ok
    }
}
