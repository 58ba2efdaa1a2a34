//! The session's inspection mode (X): a click inspects the image pixel
//! under it, the pixel is inspected again when the scene, walk or depth
//! changes, and the overlay draws its rays from the camera shown
//! ([`inspection`](super::inspection) holds what an inspection does).

use glam::DVec2;

use super::click::image_pixel;
use super::inspection::{inspect_pixel, InspectAt, InspectMode, InspectSettings, Outcome};
use super::projection::{near_plane, ViewProjection};
use super::session::Session;
use crate::gpu::WalkRecorder;

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
            .map_or_else(|| WalkRecorder::new(self.ctx), Ok);
        let recorder = match made {
            Ok(recorder) => recorder,
            Err(e) => {
                eprintln!("kdray: inspecting failed: {e}");
                self.inspect.outcome = Outcome::Failed(e.to_string());
                return;
            }
        };
        let outcome = inspect_pixel(self.ctx, &recorder, &self.scene, &at, &how);
        self.recorder = Some(recorder);
        let outcome = outcome.and_then(|(totals, vertices)| {
            self.viewer.overlay_mut().set_lines(self.ctx, &vertices)?;
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
