//! Inspection mode (X): a click inspects the image pixel under the cursor
//! ([`crate::inspect::inspect_frame_on_gpu`]: the rays of its first sample,
//! Whitted or path traced as the window shows it, and their k-d walks, as
//! the kernel logs them) with the window's scene, frame, camera, walk,
//! build and search, and the overlay draws its rays and cells from then on,
//! from whatever viewpoint the camera moves to. Changing the walk, the
//! search, the build, the integrator (or reloading) or max_depth inspects
//! the same pixel again as it was seen when clicked.
//!
//! The window's session (session.rs) holds an [`InspectMode`] and
//! inspects with [`inspect_pixel`].
//!
//! The kernel's rays use the window's aspect ratio and the inspected ones
//! the image's, which differ only when the device limits the image below
//! the window's size (`Refinement::image_size`). The lights are those of
//! the frame shown when it is inspected.

use super::inspect_lines::{
    line_vertices, miss_length, node_cells, overlay_lines, totals, LineVertex, Totals,
};
use super::title::InspectTitle;
use crate::error::Result;
use crate::gpu::{Accel, GpuContext, GpuScene, WalkRecorder};
use crate::inspect::inspect_frame_on_gpu;
use crate::kdtree::Traversal;
use crate::scene::{Camera, Integrator, Light};

/// Where a click inspected: the pixel and how the window saw it then.
#[derive(Debug, Clone)]
pub struct InspectAt {
    pub pixel: (u32, u32),
    pub camera: Camera,
    /// The image's size, in pixels.
    pub image: (u32, u32),
    /// The animation frame shown (its lights light the pixel).
    pub frame: u32,
}

/// What the inspected rays are traced with, besides the scene.
pub struct InspectSettings<'a> {
    pub accel: Accel,
    pub traversal: Traversal,
    pub max_depth: u32,
    pub integrator: Integrator,
    /// Samples per pixel (sample 0's place in the pixel depends on it).
    pub samples: u32,
    pub lights: &'a [Light],
}

/// What the last click gave.
#[derive(Debug, Clone, PartialEq)]
pub enum Outcome {
    Waiting,
    Outside,
    Failed(String),
    Shown(Totals),
}

/// Inspection mode's state.
#[derive(Debug, Clone)]
pub struct InspectMode {
    pub on: bool,
    /// The pixel last inspected, for inspecting it again.
    pub at: Option<InspectAt>,
    pub outcome: Outcome,
}

impl Default for InspectMode {
    fn default() -> Self {
        InspectMode {
            on: false,
            at: None,
            outcome: Outcome::Waiting,
        }
    }
}

impl InspectMode {
    /// What the title says of it (nothing while off); `path`: the window
    /// traces the path integrator.
    pub fn title(&self, path: bool) -> Option<InspectTitle<'_>> {
        if !self.on {
            return None;
        }
        Some(match (&self.outcome, &self.at) {
            (Outcome::Shown(totals), Some(at)) => InspectTitle::Shown {
                pixel: at.pixel,
                totals: *totals,
                path,
            },
            (Outcome::Outside, _) => InspectTitle::Outside,
            (Outcome::Failed(why), _) => InspectTitle::Failed(why),
            _ => InspectTitle::Waiting,
        })
    }
}

/// Inspects `at` in `scene` with `how`: the work summed over its rays, and
/// the overlay's line vertices.
pub fn inspect_pixel(
    ctx: &GpuContext,
    recorder: &WalkRecorder,
    scene: &GpuScene,
    at: &InspectAt,
    how: &InspectSettings,
) -> Result<(Totals, Vec<LineVertex>)> {
    let mut seen = scene.scene().clone();
    seen.camera = at.camera;
    seen.lights = how.lights.to_vec();
    (seen.render.width, seen.render.height) = at.image;
    seen.render.samples = how.samples.max(1);
    seen.render.max_depth = how.max_depth;
    seen.render.integrator = how.integrator;
    // The tree the kernel walks (a single leaf for a scene prepared for
    // brute force); brute force walks none.
    let tree = match how.accel {
        Accel::Kdtree => Some(scene.prepared().tree.clone()),
        Accel::Brute => None,
    };
    let cells = tree
        .as_ref()
        .map(|t| node_cells(&t.nodes, t.bounds))
        .unwrap_or_default();
    let params = scene.view_params(&seen.camera, &seen.render, how.accel);
    let inspection =
        inspect_frame_on_gpu(ctx, recorder, scene, &seen, params, how.traversal, at.pixel)?;
    let lines = overlay_lines(&inspection, &cells, miss_length(&scene.bounds()));
    Ok((totals(&inspection), line_vertices(&lines)))
}
