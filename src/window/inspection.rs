//! Inspection mode (X): a click inspects the image pixel under the cursor
//! ([`crate::inspect::inspect_frame_on_gpu`]: the rays of its first sample,
//! Whitted or path traced as the window shows it, and their k-d walks, as
//! the kernel logs them) with the window's scene, frame, camera, walk,
//! build and search, and the overlay draws its rays and cells from then on,
//! from whatever viewpoint the camera moves to. Changing the walk, the
//! search, the build, the integrator (or reloading) or max_depth inspects
//! the same pixel again as it was seen when clicked.
//!
//! The kernel's rays use the window's aspect ratio and the inspected ones
//! the image's, which differ only when the device limits the image below
//! the window's size (`Refinement::image_size`). The lights are those of
//! the frame shown when it is inspected.

use glam::DVec2;

use super::click::image_pixel;
use super::inspect_lines::{
    line_vertices, miss_length, node_cells, overlay_lines, totals, LineVertex, Totals,
};
use super::projection::{near_plane, ViewProjection};
use super::session::Session;
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

impl Session {
    /// X: inspection mode on or off (off forgets the pixel and its lines).
    pub(super) fn toggle_inspect(&mut self) {
        self.inspect.on = !self.inspect.on;
        if !self.inspect.on {
            self.inspect = InspectMode::default();
            self.viewer.overlay_mut().clear();
        }
    }

    /// A click at window position `at` in inspection mode: inspects the
    /// image pixel there, as the window shows it now.
    pub(super) fn inspect_click(&mut self, at: DVec2) {
        if !self.inspect.on {
            return;
        }
        let window = self.surface.size();
        let image = self.refinement.image_size(window);
        let Some(pixel) = image_pixel(at, window, image) else {
            self.inspect.outcome = Outcome::Outside;
            return;
        };
        self.inspect.at = Some(InspectAt {
            pixel,
            camera: self.controller.camera(),
            image,
            frame: self.playback.frame(),
        });
        self.reinspect();
    }

    /// Inspects the last clicked pixel again with the window's current
    /// walk, search, scene and max_depth; reports a failure in the title
    /// (and on stderr), keeping the window going.
    pub(super) fn reinspect(&mut self) {
        let Some(at) = self.inspect.at.clone() else {
            return;
        };
        let lights = self.path.lights_at(at.frame);
        let how = InspectSettings {
            accel: self.accel,
            traversal: self.traversal,
            max_depth: self.max_depth,
            integrator: self.integrator,
            samples: self.refinement.samples(),
            lights: &lights,
        };
        let made = self
            .recorder
            .take()
            .map_or_else(|| WalkRecorder::new(&self.ctx), Ok);
        let recorder = match made {
            Ok(recorder) => recorder,
            Err(e) => {
                eprintln!("kdray: inspecting failed: {e}");
                self.inspect.outcome = Outcome::Failed(e.to_string());
                return;
            }
        };
        let outcome = inspect_pixel(&self.ctx, &recorder, &self.scene, &at, &how);
        self.recorder = Some(recorder);
        let outcome = outcome.and_then(|(totals, vertices)| {
            self.viewer.overlay_mut().set_lines(&self.ctx, &vertices)?;
            Ok(totals)
        });
        self.inspect.outcome = match outcome {
            Ok(totals) => {
                let (x, y) = at.pixel;
                eprintln!(
                    "kdray: inspected pixel {x},{y}: {} rays, {} nodes, {} leaves, {} tests, {} restarts",
                    totals.rays, totals.nodes, totals.leaves, totals.tests, totals.restarts
                );
                Outcome::Shown(totals)
            }
            Err(e) => {
                eprintln!("kdray: inspecting failed: {e}");
                self.viewer.overlay_mut().clear();
                Outcome::Failed(e.to_string())
            }
        };
    }

    /// The overlay's projection for the camera shown now, in the window's
    /// aspect ratio (as the kernel's frames use it).
    pub(super) fn overlay_view(&self) -> ViewProjection {
        let (w, h) = self.surface.size();
        let camera = self.controller.camera();
        ViewProjection::new(
            &camera,
            w.max(1) as f64 / h.max(1) as f64,
            near_plane(&camera),
        )
    }
}
