//! The GPU data layout: `#[repr(C)]` Pod types that mirror the structs of
//! shaders/types.wgsl byte for byte, and [`SceneArrays`], a scene and its
//! tree flattened into them. kdray's `gpu::layout_check` checks every size
//! and field offset against naga's layout of the WGSL declarations.
//!
//! This file is the module's face: the types live in `tree_nodes` (the
//! kernel's packed k-d node; the tree's own nodes and ropes, re-exported
//! here, are `crate::kdtree`'s), `objects` (spheres, triangles, packed normals),
//! `material`, `light` and `frame_values` (the values of `FrameParams`'
//! switches); `light_picks` gives each light its chance of being picked by
//! power; `scene_arrays` flattens a scene into them, and
//! `texture_words` lays out the textures buffer.
//!
//! WGSL's `vec3<f32>` is 16-byte aligned, so each `[f32; 3]` is followed by a
//! 4-byte field (a scalar that belongs with it, or explicit padding).

mod frame_values;
mod light;
pub mod light_picks;
pub mod light_tree;
mod material;
mod objects;
mod scene_arrays;
mod texture_words;
mod tree_nodes;

pub use crate::kdtree::{KdNode, LeafRopes};
pub use frame_values::{
    ACCEL_BRUTE, ACCEL_KDTREE, GLASS_STACK_DEPTH, INTEGRATOR_PATH, INTEGRATOR_WHITTED,
    SHADOW_AMBIENT, SHADOW_CROSSINGS, SHADOW_SEED, TRAVERSAL_RESTART, TRAVERSAL_ROPES,
    TRAVERSAL_SHORT_STACK,
};
pub use light::{GpuLight, LIGHT_DIRECTIONAL, LIGHT_EMITTER, LIGHT_POINT, LIGHT_SPOT};
pub use material::{
    GpuMaterial, ALPHA_BLEND, ALPHA_MASK, ALPHA_OPAQUE, MODEL_LAMBERTIAN, MODEL_METAL_ROUGH,
    UV_SLOT_BASE, UV_SLOT_EMISSIVE, UV_SLOT_METAL_ROUGH, UV_SLOT_NORMAL, UV_SLOT_OCCLUSION,
};
pub use objects::{GpuSphere, GpuTriangle, GpuTriangleNormals};
pub use scene_arrays::{EnvironmentWords, SceneArrays};
pub use texture_words::{Records, TextureWords};
pub use tree_nodes::GpuKdNode;
