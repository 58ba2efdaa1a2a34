//! kdray: a ray tracer whose k-d tree is built on the CPU and walked by a
//! WGSL compute shader through wgpu.
//!
//! Data flows one way: [`scene`] (parse, validate, OBJ) -> [`kdtree`] (SAH
//! build, flat GPU layout, CPU mirror of the traversal) -> [`gpu`] (adapter,
//! buffers, pipeline, tiled dispatch, readback) -> [`output`] (PNG).
//! [`render`] strings them together for one frame; [`web`] exports a
//! prepared scene as a site that traces it in a browser.

pub mod bench;
pub mod choice;
pub mod error;
pub mod farm;
pub mod fuzz_support;
pub mod geometry;
pub mod gpu;
mod huge_pages;
pub mod kdtree;
pub mod layout;
pub mod output;
pub mod reference;
pub mod render;
pub mod scene;
pub mod web;
pub mod window;

pub use error::{Error, Result};
