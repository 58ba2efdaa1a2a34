//! The GPU-free half of kdray's denoiser: Open Image Denoise 1.4.3's RT
//! filter (its U-Net and trained weights, Apache-2.0) for HDR images, with
//! or without albedo and normal.
//!
//! - [`tza`]: reading OIDN's weights archives; [`weights`]: a network's
//!   weights checked against the U-Net;
//! - [`network`]: the U-Net as a list of steps over tensor slots;
//!   [`layers`]: the CPU reference of each layer kind; [`cpu_net`]: the
//!   whole network and denoise on the CPU (tests only: slow);
//! - [`transfer`]: autoexposure and the PU transfer function; [`pack`]: the
//!   input and output conventions per pixel and per tile; [`tiling`]: the
//!   tiles of a large image.
//!
//! The kdray crate runs the same steps in WGSL (`src/denoise/`).

pub mod cpu_net;
pub mod layers;
pub mod network;
pub mod pack;
pub mod tiling;
pub mod transfer;
pub mod tza;
pub mod weights;

pub use cpu_net::denoise_cpu;
pub use pack::DenoiseImages;
pub use tiling::{Tile, TilePlan};
pub use weights::{ConvWeights, Weights, WeightsError};
