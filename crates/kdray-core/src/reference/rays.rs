//! What the tracer records: the rays a sample traces ([`TracedRay`], each
//! with its [`RayKind`] and walk, a shadow ray with its light) and the Whitted loop's glass rays and
//! steps ([`WhittedRay`], [`WhittedStep`]).

use crate::geometry::Ray;
use crate::kdtree::traverse::{Hit, WalkCost};
use crate::kdtree::WalkEvent;

use super::light_choice::AimedLight;

/// Why a ray is traced.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RayKind {
    /// From the camera.
    Primary,
    /// Towards a light (with glass: each part between two glass surfaces).
    Shadow,
    /// The mirror ray of a hit.
    Reflected,
    /// Through a glass surface.
    Refracted,
    /// A path tracer's next ray, sampled from the surface's scattering
    /// (the GPU's inspect kernel records these; this tracer follows the
    /// Whitted integrator only).
    Bounce,
}

/// One ray a sample traced, in order, recorded by
/// [`ReferenceTracer::trace_recorded`](crate::reference::ReferenceTracer::trace_recorded).
#[derive(Debug, Clone, PartialEq)]
pub struct TracedRay {
    pub kind: RayKind,
    pub ray: Ray,
    /// How far the query looked (`T_INFINITY`: no limit).
    pub t_limit: f32,
    /// An any-hit query (a shadow ray without glass) rather than nearest hit.
    pub any: bool,
    pub hit: Option<Hit>,
    /// The walk's counted work, as the kernel counts it.
    pub cost: WalkCost,
    /// The walk's steps (none for brute force).
    pub walk: Vec<WalkEvent>,
    /// A shadow ray's light (every part of one through glass names it).
    pub light: Option<AimedLight>,
}

/// A ray a sample follows on the glass path: mirror of `WhittedRay` in
/// shaders/glass.wgsl.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WhittedRay {
    pub ray: Ray,
    pub kind: RayKind,
    /// Its share of the sample's colour.
    pub weight: f32,
    /// Hits on its path before this ray.
    pub hits: u32,
    /// The path's length from the eye to its origin (the texture's ray cone).
    pub path_length: f32,
    /// Whether it runs inside glass.
    pub inside: bool,
}

/// One ray the glass path traced, in order, and what it hit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WhittedStep {
    pub ray: WhittedRay,
    pub hit: Option<Hit>,
}
