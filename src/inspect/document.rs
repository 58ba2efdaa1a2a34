//! The document `kdray inspect` prints (docs/inspect.md describes it): the
//! pixel and how it was traced, and each of its rays with the walk that
//! searched it, its hit, its counted work and (a shadow ray) its light.

use serde::Serialize;

use kdray_core::reference::LightId;

/// The format's version: raised when a key changes meaning or goes.
pub const INSPECT_VERSION: u32 = 1;

/// The document `kdray inspect` prints.
#[derive(Debug, Clone, Serialize)]
pub struct Inspection {
    pub version: u32,
    pub scene: String,
    /// Column, row; (0, 0) is the top-left pixel.
    pub pixel: [u32; 2],
    pub frame: u32,
    pub width: u32,
    pub height: u32,
    /// Samples per pixel; the rays are those of sample 0 (the top-left
    /// cell of the k x k grid).
    pub samples: u32,
    /// `whitted` or `path`.
    pub integrator: &'static str,
    /// `kdtree` or `brute` (no walk: every object tested).
    pub accel: &'static str,
    pub traversal: &'static str,
    pub build: &'static str,
    /// `kernel` or `cpu`.
    pub walk_source: &'static str,
    pub rays: Vec<InspectedRay>,
    /// The sample's colour (Whitted, before clamping) or radiance (path)
    /// as the kernel computed it; the kernel source only.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sample: Option<[f32; 3]>,
}

/// One traced ray.
#[derive(Debug, Clone, Serialize)]
pub struct InspectedRay {
    /// `primary`, `shadow`, `reflected`, `refracted` or (path) `bounce`.
    pub kind: &'static str,
    /// `nearest` (the closest hit) or `any` (a shadow ray's: any hit before
    /// the light ends the search).
    pub query: &'static str,
    pub origin: [f32; 3],
    /// Unit.
    pub direction: [f32; 3],
    /// How far the query looks (`null`: unbounded).
    pub t_limit: Option<f32>,
    /// The part of the ray the walk searches: inside the scene's box, past
    /// the origin, up to `t_limit` (`null`: none, the walk never starts;
    /// always with brute force, which clips nothing).
    pub t_interval: Option<[f32; 2]>,
    pub walk: Vec<Step>,
    pub hit: Option<InspectedHit>,
    pub counts: Counts,
    /// A shadow ray's light: what it aims at, and with what probability.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub light: Option<InspectedLight>,
}

/// The light a shadow ray aims at, in the scene's terms, and the chance
/// the integrator gave it: in the path tracer's next-event estimation the
/// probability of picking it from the hit (by power; an emitter through the
/// light tree) and the density of the ray's
/// direction; in the Whitted integrator every light gets its shadow ray
/// (probability 1).
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct InspectedLight {
    /// `light` (an entry of the scene's `[[lights]]`), `emitter` (an object
    /// whose material emits) or `sky` (the sky image).
    pub source: &'static str,
    /// A scene light: its index in `[[lights]]`, in file order.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub index: Option<u32>,
    /// A scene light: `point`, `spot` or `directional`; an emitter:
    /// `sphere` or `triangle`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub kind: Option<&'static str>,
    /// An emitter: its object id, numbered as hits are.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub object: Option<u32>,
    /// An emissive triangle: its index among the scene's triangles.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub triangle: Option<u32>,
    /// The probability the light was picked with (Whitted: 1).
    pub pick: f32,
    /// The solid-angle density of the ray's direction, the pick included
    /// (the path tracer, for an emitter or the sky); `null` for a point,
    /// spot or directional light (a delta) and in the Whitted integrator.
    pub pdf: Option<f32>,
}

impl InspectedLight {
    /// The light, as the CPU reference names it.
    pub fn id(&self) -> LightId {
        match (self.source, self.index, self.object) {
            ("light", Some(i), _) => LightId::Scene(i),
            ("emitter", _, Some(o)) => LightId::Emitter(o),
            _ => LightId::Sky,
        }
    }
}

/// One step of a walk: an inner node, a leaf, or how the walk moved on.
#[derive(Debug, Clone, Serialize)]
#[serde(untagged)]
pub enum Step {
    Node {
        node: usize,
        depth: u32,
        axis: &'static str,
        split: f32,
        /// The segment still to search in this node.
        t: [f32; 2],
        /// The child the walk goes on in.
        near: usize,
        /// Where the segment crosses the plane into the other child, when
        /// it does (`far`).
        #[serde(skip_serializing_if = "Option::is_none")]
        t_split: Option<f32>,
        #[serde(skip_serializing_if = "Option::is_none")]
        far: Option<usize>,
    },
    Leaf {
        leaf: usize,
        depth: u32,
        objects: Vec<u32>,
        /// Where the ray is inside the leaf.
        t: [f32; 2],
        tested: Vec<Tested>,
        /// The rope walk's leaf the ray spends no time in: not tested.
        #[serde(skip_serializing_if = "std::ops::Not::not")]
        skipped: bool,
    },
    Push {
        push: Resume,
    },
    Pop {
        pop: Resume,
    },
    Restart {
        restart: Restart,
    },
    Rope {
        rope: Rope,
    },
}

/// A short-stack entry: the far child and the segment's end there.
#[derive(Debug, Clone, Serialize)]
pub struct Resume {
    pub node: usize,
    pub t_max: f32,
}

/// A descent starting over from `node` at `t_min`.
#[derive(Debug, Clone, Serialize)]
pub struct Restart {
    pub node: usize,
    pub t_min: f32,
}

/// The rope walk leaving a leaf through `face` at `t_min` for `node`.
#[derive(Debug, Clone, Serialize)]
pub struct Rope {
    /// `x-`, `x+`, `y-`, `y+`, `z-` or `z+`.
    pub face: &'static str,
    pub node: usize,
    pub t_min: f32,
}

/// One object test in a leaf.
#[derive(Debug, Clone, Serialize)]
pub struct Tested {
    pub object: u32,
    pub hit: bool,
    /// Where the ray meets the object (any t > 0, within the query's limit
    /// or not).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub t: Option<f32>,
}

/// What the query returned.
#[derive(Debug, Clone, Serialize)]
pub struct InspectedHit {
    pub object: u32,
    /// `sphere` or `triangle`.
    pub kind: &'static str,
    pub t: f32,
    pub point: [f32; 3],
    /// Unit geometric normal, facing the ray.
    pub normal: [f32; 3],
}

/// The walk's work, counted as the kernel counts it (`WalkCost`), and its
/// restarts.
#[derive(Debug, Clone, Copy, Serialize, PartialEq, Eq)]
pub struct Counts {
    pub nodes: u32,
    pub leaves: u32,
    pub tests: u32,
    pub restarts: u32,
}
