//! kdray: a ray tracer whose k-d tree is built on the CPU and walked by a
//! WGSL compute shader through wgpu.
//!
//! Data flows one way: [`scene`] (parse, validate, OBJ) -> [`kdtree`] (SAH
//! build, flat GPU layout, CPU mirror of the traversal) -> [`gpu`] (adapter,
//! buffers, pipeline, dispatch, readback) -> [`output`] (PNG).

pub mod geometry;
pub mod kdtree;
pub mod layout;
pub mod scene;
