//! The `textures` storage buffer's layout: texture headers, texture
//! coordinate records and texels in one array of u32 words, as
//! shaders/texture.wgsl reads them.

/// The `textures` buffer, one array of u32 words (shaders/texture.wgsl):
/// word 0 the first word of the texture coordinate records; then per
/// texture a header of [`TextureWords::HEADER_WORDS`] words (first texel
/// word, width, height, filter, wrap along u, wrap along v); then the
/// records, six words per textured triangle (u, v of its three corners,
/// f32 bits); then the texels, RGBA8 a word, row by row from the image's
/// top row. Built by [`TextureWords::pack`].
pub struct TextureWords;

impl TextureWords {
    pub const HEADER_WORDS: u32 = 6;
    pub const RECORD_WORDS: u32 = 6;
    pub const FILTER_NEAREST: u32 = 0;
    pub const FILTER_BILINEAR: u32 = 1;
    pub const WRAP_REPEAT: u32 = 0;
    pub const WRAP_CLAMP: u32 = 1;
    pub const WRAP_MIRROR: u32 = 2;

    /// The buffer for `textures` and the texture coordinate records `uvs`
    /// (in the order the triangles' `uvs` index them); empty without
    /// textures.
    pub fn pack(textures: &[crate::scene::Texture], uvs: &[[glam::Vec2; 3]]) -> Vec<u32> {
        use crate::scene::{TextureFilter, TextureWrap};
        if textures.is_empty() {
            return Vec::new();
        }
        let records = 1 + textures.len() as u32 * Self::HEADER_WORDS;
        let mut texel_start = records + uvs.len() as u32 * Self::RECORD_WORDS;
        let mut words = vec![records];
        for t in textures {
            let wrap = |w: TextureWrap| match w {
                TextureWrap::Repeat => Self::WRAP_REPEAT,
                TextureWrap::ClampToEdge => Self::WRAP_CLAMP,
                TextureWrap::MirroredRepeat => Self::WRAP_MIRROR,
            };
            let filter = match t.filter {
                TextureFilter::Nearest => Self::FILTER_NEAREST,
                TextureFilter::Bilinear => Self::FILTER_BILINEAR,
            };
            words.extend([
                texel_start,
                t.width,
                t.height,
                filter,
                wrap(t.wrap[0]),
                wrap(t.wrap[1]),
            ]);
            texel_start = texel_start.wrapping_add(t.texels.len() as u32);
        }
        for corners in uvs {
            for uv in corners {
                words.extend([uv.x.to_bits(), uv.y.to_bits()]);
            }
        }
        for t in textures {
            words.extend_from_slice(&t.texels);
        }
        words
    }
}
