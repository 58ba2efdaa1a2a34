//! Rays, boxes and the two primitives, in f32 exactly as the shader computes
//! them (shaders/intersect.wgsl mirrors every function here line by line), so
//! CPU tests exercise the same arithmetic the GPU runs.
//!
//! This file is the module's face: `ray` holds the ray and the spawn
//! offset; `aabb` the boxes; `sphere` and `triangle` the two primitives and
//! their ray tests; `alpha_test` the holes alpha-tested triangles have;
//! `primitives` the scene's objects and the one object test every walk runs.

mod aabb;
pub mod alpha_test;
mod primitives;
mod ray;
mod sphere;
mod triangle;

pub use aabb::{union_in_pieces, Aabb};
pub use primitives::Primitives;
pub use ray::{spawn_offset, Ray, PARALLEL_EPSILON, T_INFINITY};
pub use sphere::SphereF32;
pub use triangle::{barycentrics, RayShear, TriangleF32, HIT_BOX_MARGIN, IN_PLANE_MARGIN};
