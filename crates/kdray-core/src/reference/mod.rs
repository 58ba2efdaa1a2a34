//! A CPU reference of shaders/trace.wgsl + shade.wgsl + glass.wgsl +
//! texture.wgsl: the same path loop (with glass: refraction, Fresnel, the
//! stack of pending rays, shadow rays through glass; with textures: the
//! texture at the hit, its mip level chosen by the ray cone of the path's
//! length from the eye, multiplying diffuse and ambient), shading and f32 arithmetic over the CPU
//! mirror of the traversal, so GPU images can be checked pixel by pixel and
//! a single path can be inspected: [`ReferenceTracer::trace_recorded`](crate::reference::ReferenceTracer::trace_recorded)
//! returns every ray a sample traces with its walk, step by step (what
//! `kdray inspect` prints). Slow (one thread); for tests, debugging and
//! inspection only.
//!
//! This file is the module's face: `tracer` holds the tracer, its searches
//! and the camera's rays; `rays` the rays and Whitted steps it records;
//! `surface` the surface at a hit (normals, refraction, the material with
//! its textures read), `whitted` the Whitted path loop and its shading,
//! `light_choice` the light a shadow ray aims at and the path tracer's
//! chance of picking each light, from the lights' power.

mod light_choice;
mod rays;
mod surface;
mod tracer;
mod whitted;

pub use crate::geometry::barycentrics;
pub use light_choice::{AimedLight, LightChoice, LightId};
pub use rays::{RayKind, TracedRay, WhittedRay, WhittedStep};
pub use surface::{
    reflection_dir, refract_fresnel, refraction_at, smooth_surface, Refraction, Surface,
};
pub use tracer::ReferenceTracer;
