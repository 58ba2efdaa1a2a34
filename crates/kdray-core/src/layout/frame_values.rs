//! The values of `FrameParams`' switches (integrator, search, walk, shadow
//! mode), and the kernel's fixed limits for glass.

/// `FrameParams::integrator` values.
pub const INTEGRATOR_WHITTED: u32 = 0;
pub const INTEGRATOR_PATH: u32 = 1;

/// `FrameParams::accel` values.
pub const ACCEL_KDTREE: u32 = 0;
pub const ACCEL_BRUTE: u32 = 1;
/// `FrameParams::traversal` values (`kdtree::Traversal`).
pub const TRAVERSAL_RESTART: u32 = 0;
pub const TRAVERSAL_ROPES: u32 = 1;
pub const TRAVERSAL_SHORT_STACK: u32 = 2;
/// The glass path's stack: at most this many rays wait while a sample
/// follows another (shaders/glass.wgsl; docs/scene-format.md says how).
pub const GLASS_STACK_DEPTH: u32 = 4;
/// A shadow ray through glass passes at most this many transmissive
/// surfaces; one that would pass more counts as blocked.
pub const SHADOW_CROSSINGS: u32 = 8;
/// `FrameParams::shadow_mode` values.
pub const SHADOW_AMBIENT: u32 = 0;
pub const SHADOW_SEED: u32 = 1;
