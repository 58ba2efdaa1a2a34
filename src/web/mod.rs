//! `kdray web SCENE -o DIR`: the scene prepared on the CPU (k-d tree and
//! arrays, as `render` prepares it) and written as a static site that traces
//! it in a browser with WebGPU, running the same WGSL kernel.
//!
//! - [`bundle`]: the versioned binary bundle of the prepared scene.
//! - [`contract`]: the host-shader contract as JSON, for the page's script.
//! - [`denoise`]: the denoiser's weights, kernels and dispatch table for
//!   the page.
//! - [`site`]: the site's files (the page from web/, the kernel, the bundle
//!   and the contract), each written atomically into a folder that is new,
//!   empty or already a kdray site.

pub mod bundle;
pub mod contract;
pub mod denoise;
pub mod site;

pub use site::{export_site, SITE_MARKER};
