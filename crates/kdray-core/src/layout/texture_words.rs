//! The `textures` storage buffer's layout: texture headers, mip level
//! tables, texture coordinate records and texels in one array of u32
//! words, as shaders/texture.wgsl reads them.

/// The `textures` buffer, one array of u32 words (shaders/texture.wgsl):
/// word 0 the first word of the texture coordinate records; then per
/// texture a header of [`TextureWords::HEADER_WORDS`] words (the first word
/// of its level table, its level count, magnification filter, minification
/// filter, mip mode, wrap along u, wrap along v); then each texture's level
/// table, [`TextureWords::LEVEL_WORDS`] words per level from the base down
/// to 1 x 1 (first texel word, width, height); then the records, six words
/// per textured triangle (u, v of its three corners, f32 bits); then the
/// texels, per texture its levels in order, RGBA8 a word, row by row from
/// the level's top row. Built by [`TextureWords::pack`].
pub struct TextureWords;

impl TextureWords {
    pub const HEADER_WORDS: u32 = 7;
    pub const LEVEL_WORDS: u32 = 3;
    pub const RECORD_WORDS: u32 = 6;
    pub const FILTER_NEAREST: u32 = 0;
    pub const FILTER_BILINEAR: u32 = 1;
    pub const MIP_NONE: u32 = 0;
    pub const MIP_NEAREST: u32 = 1;
    pub const MIP_LINEAR: u32 = 2;
    pub const WRAP_REPEAT: u32 = 0;
    pub const WRAP_CLAMP: u32 = 1;
    pub const WRAP_MIRROR: u32 = 2;

    /// The buffer for `textures` and the texture coordinate records `uvs`
    /// (in the order the triangles' `uvs` index them); empty without
    /// textures.
    pub fn pack(textures: &[crate::scene::Texture], uvs: &[[glam::Vec2; 3]]) -> Vec<u32> {
        use crate::scene::{MipMode, TextureFilter, TextureWrap};
        if textures.is_empty() {
            return Vec::new();
        }
        let level_tables = 1 + textures.len() as u32 * Self::HEADER_WORDS;
        let levels: u32 = textures.iter().map(|t| t.level_count()).sum();
        let records = level_tables + levels * Self::LEVEL_WORDS;
        let mut words = vec![records];
        let filter = |f: TextureFilter| match f {
            TextureFilter::Nearest => Self::FILTER_NEAREST,
            TextureFilter::Bilinear => Self::FILTER_BILINEAR,
        };
        let wrap = |w: TextureWrap| match w {
            TextureWrap::Repeat => Self::WRAP_REPEAT,
            TextureWrap::ClampToEdge => Self::WRAP_CLAMP,
            TextureWrap::MirroredRepeat => Self::WRAP_MIRROR,
        };
        let mut table = level_tables;
        for t in textures {
            let mip = match t.min_filter.mip {
                MipMode::None => Self::MIP_NONE,
                MipMode::Nearest => Self::MIP_NEAREST,
                MipMode::Linear => Self::MIP_LINEAR,
            };
            words.extend([
                table,
                t.level_count(),
                filter(t.filter),
                filter(t.min_filter.filter),
                mip,
                wrap(t.wrap[0]),
                wrap(t.wrap[1]),
            ]);
            table += t.level_count() * Self::LEVEL_WORDS;
        }
        let mut texel_start = records + uvs.len() as u32 * Self::RECORD_WORDS;
        for t in textures {
            for k in 0..t.level_count() {
                let level = t.level(k);
                words.extend([texel_start, level.width, level.height]);
                texel_start = texel_start.wrapping_add(level.texels.len() as u32);
            }
        }
        for corners in uvs {
            for uv in corners {
                words.extend([uv.x.to_bits(), uv.y.to_bits()]);
            }
        }
        for t in textures {
            for k in 0..t.level_count() {
                words.extend_from_slice(t.level(k).texels);
            }
        }
        words
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{MinFilter, MipMode, Texture, TextureFilter, TextureWrap};

    #[test]
    fn headers_level_tables_records_and_every_level_s_texels_lie_where_the_words_say() {
        let grey = |v: u8| u32::from_le_bytes([v, v, v, 255]);
        let a = Texture::new(
            "a",
            (4, 2),
            [0, 10, 20, 30, 40, 50, 60, 70].map(grey).to_vec(),
            TextureFilter::Nearest,
            MinFilter::TRILINEAR,
            [TextureWrap::Repeat, TextureWrap::ClampToEdge],
        );
        let b = Texture::new(
            "b",
            (1, 1),
            vec![grey(9)],
            TextureFilter::Bilinear,
            MinFilter {
                filter: TextureFilter::Nearest,
                mip: MipMode::Nearest,
            },
            [TextureWrap::MirroredRepeat; 2],
        );
        let uv = [glam::Vec2::new(0.5, 0.25); 3];
        let words = TextureWords::pack(&[a, b], &[uv]);
        // Word 0, two headers, 3 + 1 levels of 3 words: records at 27.
        assert_eq!(words[0], 27);
        assert_eq!(&words[1..8], &[15, 3, 0, 1, 2, 0, 1]);
        assert_eq!(&words[8..15], &[24, 1, 1, 0, 1, 2, 2]);
        // Texels after the one record (6 words): from 33.
        assert_eq!(&words[15..27], &[33, 4, 2, 41, 2, 1, 43, 1, 1, 44, 1, 1]);
        assert_eq!(words[27], 0.5f32.to_bits());
        assert_eq!(words[28], 0.25f32.to_bits());
        assert_eq!(&words[41..45], &[grey(25), grey(45), grey(35), grey(9)]);
        assert_eq!(words.len(), 45);
    }
}
