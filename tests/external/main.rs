//! The external tier (docs/testing.md, "Tiers"): tests that drive a tool
//! beyond the GPU driver: headless Chromium (`web`), node on the page's
//! scripts (`web_tiles`), a Slurm cluster
//! (`farm`, `farm_path`), an X server (`window`, `window_inspect`, under Xvfb: `x_window`) and lavapipe with its
//! allocations made to fail (`gpu_memory`, through a preloaded library built
//! with cc), the docs' generated tables against the python3 scripts that
//! print them (`doc_tables`), and `kdray denoise` against native Open Image
//! Denoise through python3's `oidn` wheel (`denoise_oidn`). A missing tool fails the test that needs it, naming the tool
//! and how to install it (`scripts/test.sh external` installs them all).
//! Run it with `scripts/test.sh external` or `cargo test -p kdray --test external`.
//!
//! To add tests: write `tests/external/NAME.rs` starting with
//! `use crate::common;` and add `mod NAME;` below.

#[path = "../common/mod.rs"]
mod common;

mod denoise_oidn;
mod doc_tables;
mod farm;
mod farm_path;
mod gpu_memory;
mod tools;
mod web;
mod web_inspect;
mod web_tiles;
mod window;
mod window_inspect;
mod x_window;
