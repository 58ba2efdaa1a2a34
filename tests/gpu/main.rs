//! The GPU tier (docs/testing.md, "Tiers"): every test that needs a GPU
//! adapter (lavapipe in CI, SwiftShader's Vulkan for `swiftshader`) or runs
//! the kdray binary, and no tool beyond Mesa and the packages
//! scripts/test.sh installs for it. One test binary, so it is linked once:
//! run it with `scripts/test.sh gpu` or `cargo test -p kdray --test gpu`.
//!
//! To add tests: write `tests/gpu/NAME.rs` starting with
//! `use crate::common;` (and `use common::*;` for the helpers), and add
//! `mod NAME;` below. Tests that need Chromium, Slurm, Xvfb or a memory
//! limit belong in tests/external/ instead.

#[path = "../common/mod.rs"]
mod common;

mod alpha_mask;
mod bench;
mod bench_matrix;
mod bsdf_lobes;
mod cli;
mod cli_animation;
mod cli_bad_input;
mod cli_heatmap;
mod denoise;
mod denoise_cli;
mod denoise_render;
mod double_sided;
mod examples;
mod glass;
mod gltf_camera;
mod gltf_lights;
mod golden;
mod gpu_faults;
mod gpu_ray_queries;
mod gpu_render;
mod inspect;
mod inspect_cli;
mod inspect_kernel;
mod instances;
mod light_kinds;
mod light_sampling;
mod material_maps;
mod open_model;
mod optimised_gltf;
mod path_tracing;
mod pathological;
mod pipeline_cache;
mod quad_pairs;
mod rough_glass;
mod smooth_shading;
mod split_bindings;
mod swiftshader;
mod textured_models;
mod textures;
mod triangle_edges;
mod triangle_meshes;
mod vertex_attributes;
mod web_export;
mod whitted_emission;
