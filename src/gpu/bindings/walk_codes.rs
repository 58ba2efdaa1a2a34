//! The inspect kernel's log layout: the header, each record's tag, the
//! kinds of ray and the sky's light kind. The kernel reads them as
//! generated constants (`INSPECT_*`, `RAY_*`); gpu/walk_log.rs decodes the
//! log by them.

use crate::layout::{LIGHT_DIRECTIONAL, LIGHT_EMITTER, LIGHT_POINT, LIGHT_SPOT};

/// The header word holding how many words the kernel meant to write.
pub const WORDS_USED: u32 = 0;
/// The word the kernel's other lanes, and writes past the log's end,
/// go to; never read.
pub const SINK: u32 = 1;
/// Words before the first record.
pub const HEADER_WORDS: u32 = 2;
/// kind, any-hit (0 or 1), origin (3), direction (3), t_limit, then the
/// light a shadow ray aims at: its entry in the lights buffer (NO_OBJECT:
/// not a shadow ray; a scene light's entry is its index in `[[lights]]`),
/// its kind (`GpuLight::kind`, or [`LIGHT_SKY`]), the scene id of an
/// emitter's object (else NO_OBJECT), the probability it was picked with
/// (Whitted: 1) and the solid-angle density of the ray's direction, the
/// pick included (0: a delta light, and in Whitted).
pub const RAY: u32 = 1;
/// t_min, t_far: the segment the walk searches.
pub const SEGMENT: u32 = 2;
/// node, t_min, t_max, near, far, t_split, crosses (0 or 1).
pub const NODE: u32 = 3;
/// node, t_min, t_max.
pub const LEAF: u32 = 4;
/// node: a leaf the rope walk skips.
pub const SKIPPED: u32 = 5;
/// scene id, met (0 or 1), t.
pub const TESTED: u32 = 6;
/// node, t_max.
pub const PUSH: u32 = 7;
/// node, t_max.
pub const POP: u32 = 8;
/// node, t_min.
pub const RESTART: u32 = 9;
/// face, node, t_min.
pub const ROPE: u32 = 10;
/// scene id (NO_OBJECT: a miss), t, point (3), normal (3), nodes,
/// leaves, tests.
pub const HIT: u32 = 11;
/// The sample's colour (3), unclamped: the last record.
pub const SAMPLE: u32 = 12;

// A RAY record's kind.
pub const RAY_PRIMARY: u32 = 0;
pub const RAY_SHADOW: u32 = 1;
pub const RAY_REFLECTED: u32 = 2;
pub const RAY_REFRACTED: u32 = 3;
pub const RAY_BOUNCE: u32 = 4;

/// A shadow ray's light kind for the sky image, besides `GpuLight::kind`'s.
pub const LIGHT_SKY: u32 = 4;
const _: () = assert!(
    LIGHT_SKY != LIGHT_POINT
        && LIGHT_SKY != LIGHT_SPOT
        && LIGHT_SKY != LIGHT_DIRECTIONAL
        && LIGHT_SKY != LIGHT_EMITTER
);
