//! `[render]`: the image size, the integrator and its settings, and what a
//! hit sees when no light reaches it.

use glam::DVec3;

use super::integrator::{Integrator, ToneMap};

/// What happens at a hit from which no light is visible.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ShadowMode {
    /// The hit still gets its ambient term and the path goes on.
    Ambient,
    /// The path ends and adds nothing (the seed's Algorithm 1).
    Seed,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RenderSettings {
    pub width: u32,
    pub height: u32,
    /// The seed's ind_ref: a path stops once its weight falls below this.
    pub min_intensity: f64,
    /// Most hits evaluated along one path, primary hit included (1..=64).
    pub max_depth: u32,
    pub background: DVec3,
    pub shadow_mode: ShadowMode,
    /// Samples per pixel: a perfect square k * k for the Whitted
    /// integrator (a k x k grid), any count >= 1 for the path tracer
    /// (uniformly random positions in the pixel).
    pub samples: u32,
    pub integrator: Integrator,
    /// The path tracer's random numbers: the same seed, the same image.
    pub seed: u32,
    /// How a path-traced PNG maps radiance to 8-bit sRGB, after scaling it
    /// by 2^`exposure`.
    pub tone_map: ToneMap,
    /// Stops, finite.
    pub exposure: f64,
    /// Whether `kdray render` denoises the path-traced image (with its
    /// albedo and normal) before writing it; path tracer only.
    pub denoise: bool,
}

impl RenderSettings {
    /// k for samples = k * k.
    pub fn samples_per_axis(&self) -> u32 {
        (self.samples as f64).sqrt().round() as u32
    }
}
