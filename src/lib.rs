//! kdray: a ray tracer whose k-d tree is built on the CPU and walked by a
//! WGSL compute shader through wgpu.
//!
//! The GPU-free layers ([`scene`], [`geometry`], [`kdtree`], [`layout`]) are
//! the `kdray-core` crate, re-exported here under the same paths.
//!
//! Data flows one way: [`scene`] (parse, validate, OBJ and glTF, animation)
//! -> [`kdtree`] (build, flat GPU layout, the CPU walks) -> [`gpu`] (the
//! prepared and uploaded scene, the contract, pipelines, dispatch, readback)
//! -> [`output`] (PNG). On top: [`render`] strings them together for one
//! frame; [`inspect`] shows the rays of one pixel and their walks; [`window`] traces interactively; [`web`] exports a prepared scene
//! as a site that traces it in a browser; [`farm`] hands frames or bands to
//! a Slurm cluster; [`bench`](mod@bench) measures. docs/design.md's Architecture is the
//! map.

pub use kdray_core::{choice, geometry, kdtree, layout, prepare, scene};

pub mod bench;
pub mod denoise;
pub mod error;
pub mod farm;
pub mod gpu;
pub mod inspect;
pub mod output;
pub mod render;
pub mod web;
pub mod window;

pub use error::{Error, Result};
