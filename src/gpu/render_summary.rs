//! What a render measured besides its pixels: the rays the kernel traced,
//! by kind, the walk's work when it was counted, and where the GPU time
//! came from.

use super::kernel_io::RayCounters;
use crate::kdtree::traverse::WalkCost;

/// The walk's work over the whole image (every ray of every pixel), summed
/// from the per-pixel costs.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize)]
pub struct CostTotals {
    pub nodes_visited: u64,
    pub leaves_visited: u64,
    pub objects_tested: u64,
}

impl CostTotals {
    pub fn add(&mut self, c: &WalkCost) {
        self.nodes_visited += c.nodes_visited as u64;
        self.leaves_visited += c.leaves_visited as u64;
        self.objects_tested += c.objects_tested as u64;
    }
}

/// Rays the shader traced, by kind, summed over tiles.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize)]
pub struct RayTotals {
    /// One per sample: width * height * samples.
    pub primary: u64,
    /// One per light tested from a hit (L.N > 0), shadow mode permitting.
    pub shadow: u64,
    /// Mirror continuations after the primary hit.
    pub reflection: u64,
    /// Invocations whose loops came near llvmpipe's limit of 65,535
    /// iterations per invocation (see `GpuContext::has_loop_limit`).
    pub loop_limited: u64,
    /// Path samples dropped because their radiance was not finite.
    pub nonfinite: u64,
}

/// Where `gpu_ms` comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum GpuTimeSource {
    /// GPU timestamp queries around each tile's compute pass.
    Timestamp,
    /// Wall time from submit to readback (adapters without timestamps).
    Wall,
}

impl GpuTimeSource {
    pub fn name(self) -> &'static str {
        match self {
            GpuTimeSource::Timestamp => "timestamp",
            GpuTimeSource::Wall => "wall",
        }
    }
}

/// What a render measured besides its pixels.
#[derive(Debug, Clone, Copy)]
pub struct RenderSummary {
    /// Sum over tiles of GPU time (timestamp queries) or of submit-to-done wall time.
    pub gpu_ms: f64,
    pub gpu_time_source: GpuTimeSource,
    pub rays: RayTotals,
    /// The walk's work, when the render was asked for per-pixel costs.
    pub cost: Option<CostTotals>,
}

impl RayTotals {
    pub(super) fn add(&mut self, c: &RayCounters) {
        self.primary += c.primary as u64;
        self.shadow += c.shadow as u64;
        self.reflection += c.reflection as u64;
        self.loop_limited += c.loop_limited as u64;
        self.nonfinite += c.nonfinite as u64;
    }

    /// Primary, shadow and reflection rays together.
    pub fn total(&self) -> u64 {
        self.primary + self.shadow + self.reflection
    }
}
