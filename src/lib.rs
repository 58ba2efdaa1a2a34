//! kdray: a ray tracer whose k-d tree is built on the CPU and walked by a
//! WGSL compute shader through wgpu.
//!
//! Data flows one way: [`scene`] (parse, validate, OBJ and glTF, animation)
//! -> [`kdtree`] (build, flat GPU layout, the CPU walks) -> [`gpu`] (the
//! prepared and uploaded scene, the contract, pipelines, dispatch, readback)
//! -> [`output`] (PNG). On top: [`render`] strings them together for one
//! frame; [`window`] traces interactively; [`web`] exports a prepared scene
//! as a site that traces it in a browser; [`farm`] hands frames or bands to
//! a Slurm cluster; [`bench`](mod@bench) measures. docs/design.md's Architecture is the
//! map.

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
