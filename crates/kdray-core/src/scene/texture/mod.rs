//! Base-colour textures: an image decoded once on the host into RGBA8
//! texels with its mip chain (mip_chain.rs), the filters and wrap modes its
//! material asks for, and the exact sampling rule the kernel
//! (shaders/texture.wgsl) and the CPU reference share; the level of detail
//! at a hit comes from ray cones (ray_cone.rs).
//!
//! This file is the module's face: `image_texture` holds [`Texture`], its
//! filters and wrap modes, and the sampling rule; `mip_chain` builds its
//! levels; `ray_cone` the level of detail at a hit.

mod image_texture;
mod mip_chain;
mod ray_cone;

pub use image_texture::{
    wrap_index, LevelView, MinFilter, MipMode, Texture, TextureFilter, TextureWrap,
    TEXEL_COORDINATE_LIMIT,
};
pub use mip_chain::{mip_chain, MipLevel};
pub use ray_cone::{pixel_spread_angle, texture_lod};
