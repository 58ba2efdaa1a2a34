//! The `textures` storage buffer's layout: texture headers, mip level
//! tables, texture coordinate records and texels in one array of u32
//! words, as shaders/texture.wgsl reads them.

use super::objects::GpuTriangleNormals;

/// The `textures` buffer, one array of u32 words (shaders/texture.wgsl):
/// a prefix of [`TextureWords::PREFIX_WORDS`] words (the first word of the
/// records, a record's length in words, where in a record its colours, its
/// tangents and its second channel of texture coordinates begin, 0 where
/// the scene has none); then per texture a
/// header of [`TextureWords::HEADER_WORDS`] words (the first word of its
/// level table, its level count, magnification filter, minification
/// filter, mip mode, wrap along u, wrap along v); then each texture's level
/// table, [`TextureWords::LEVEL_WORDS`] words per level from the base down
/// to 1 x 1 (first texel word, width, height); then the records, one per
/// triangle that has one: u, v of its three corners (f32 bits); where the
/// scene has vertex colours, each corner's RGBA as two words of 16-bit
/// unorm pairs (WGSL's pack2x16unorm: r g, then b a); where it has
/// tangents, each corner's unit tangent octahedral-encoded (as vertex
/// normals are) and one word of flags ([`TextureWords::TANGENT_PRESENT`],
/// and bit k set where corner k's bitangent sign is negative); where some
/// material reads a second channel of texture coordinates, those of its
/// three corners (f32 bits, zero where it has none); then the
/// texels, per texture its levels in order, RGBA8 a word, row by row from
/// the level's top row. Built by [`TextureWords::pack`].
pub struct TextureWords;

/// What the records of [`TextureWords::pack`] hold, one entry per record:
/// the texture coordinates, and beside them, where not empty (then as long
/// as `uvs`), the vertex colours, the tangents (a zero w is none) and the
/// second channel of coordinates.
#[derive(Debug, Default)]
pub struct Records {
    pub uvs: Vec<[glam::Vec2; 3]>,
    pub colours: Vec<[glam::Vec4; 3]>,
    pub tangents: Vec<[glam::Vec4; 3]>,
    pub second_uvs: Vec<[glam::Vec2; 3]>,
}

impl TextureWords {
    pub const PREFIX_WORDS: u32 = 5;
    pub const HEADER_WORDS: u32 = 7;
    pub const LEVEL_WORDS: u32 = 3;
    /// A record's texture coordinates; the colours' and tangents' words
    /// follow where the scene has them.
    pub const UV_WORDS: u32 = 6;
    pub const COLOUR_WORDS: u32 = 6;
    pub const TANGENT_WORDS: u32 = 4;
    /// In a record's tangent flags: the triangle has tangents.
    pub const TANGENT_PRESENT: u32 = 1 << 4;
    pub const FILTER_NEAREST: u32 = 0;
    pub const FILTER_BILINEAR: u32 = 1;
    pub const MIP_NONE: u32 = 0;
    pub const MIP_NEAREST: u32 = 1;
    pub const MIP_LINEAR: u32 = 2;
    pub const WRAP_REPEAT: u32 = 0;
    pub const WRAP_CLAMP: u32 = 1;
    pub const WRAP_MIRROR: u32 = 2;

    /// The buffer for `textures` and the records `r`, in the order the
    /// triangles' `uvs` index them; empty without textures and colours.
    pub fn pack(textures: &[crate::scene::Texture], r: &Records) -> Vec<u32> {
        let Records {
            uvs,
            colours,
            tangents,
            second_uvs,
        } = r;
        use crate::scene::{MipMode, TextureFilter, TextureWrap};
        if textures.is_empty() && colours.is_empty() {
            return Vec::new();
        }
        let level_tables = Self::PREFIX_WORDS + textures.len() as u32 * Self::HEADER_WORDS;
        let levels: u32 = textures.iter().map(|t| t.level_count()).sum();
        let records = level_tables + levels * Self::LEVEL_WORDS;
        let mut record_words = Self::UV_WORDS;
        let mut part = |present: bool, words: u32| {
            let at = if present { record_words } else { 0 };
            record_words += if present { words } else { 0 };
            at
        };
        let colour_at = part(!colours.is_empty(), Self::COLOUR_WORDS);
        let tangent_at = part(!tangents.is_empty(), Self::TANGENT_WORDS);
        let second_at = part(!second_uvs.is_empty(), Self::UV_WORDS);
        let mut words = vec![records, record_words, colour_at, tangent_at, second_at];
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
        let mut texel_start = records + uvs.len() as u32 * record_words;
        for t in textures {
            for k in 0..t.level_count() {
                let level = t.level(k);
                words.extend([texel_start, level.width, level.height]);
                texel_start = texel_start.wrapping_add(level.texels.len() as u32);
            }
        }
        for (i, corners) in uvs.iter().enumerate() {
            for uv in corners {
                words.extend([uv.x.to_bits(), uv.y.to_bits()]);
            }
            if let Some(c) = colours.get(i) {
                for rgba in c {
                    words.extend([pack_unorm16(rgba.x, rgba.y), pack_unorm16(rgba.z, rgba.w)]);
                }
            }
            if let Some(t) = tangents.get(i) {
                words.extend(Self::tangent_words(t));
            }
            if let Some(second) = second_uvs.get(i) {
                for uv in second {
                    words.extend([uv.x.to_bits(), uv.y.to_bits()]);
                }
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

impl TextureWords {
    /// A record's tangent words: three octahedral directions and the flags.
    fn tangent_words(t: &[glam::Vec4; 3]) -> [u32; 4] {
        if t.iter()
            .any(|t| t.w == 0.0 || t.truncate().length_squared() == 0.0)
        {
            return [0; 4];
        }
        let mut flags = Self::TANGENT_PRESENT;
        for (k, c) in t.iter().enumerate() {
            if c.w < 0.0 {
                flags |= 1 << k;
            }
        }
        let oct = |c: glam::Vec4| {
            let GpuTriangleNormals { n0, .. } =
                GpuTriangleNormals::pack([c.truncate().as_dvec3().normalize(); 3]);
            n0
        };
        [oct(t[0]), oct(t[1]), oct(t[2]), flags]
    }
}

/// Two values in [0, 1] as WGSL's pack2x16unorm packs them (`a` low).
fn pack_unorm16(a: f32, b: f32) -> u32 {
    let q = |x: f32| (x.clamp(0.0, 1.0) * 65535.0).round() as u32;
    q(a) | (q(b) << 16)
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
        let records = Records {
            uvs: vec![uv],
            ..Records::default()
        };
        let words = TextureWords::pack(&[a, b], &records);
        // The prefix, two headers, 3 + 1 levels of 3 words: records at 31,
        // 6 words each, no colours, tangents or second coordinates.
        assert_eq!(&words[0..5], &[31, 6, 0, 0, 0]);
        assert_eq!(&words[5..12], &[19, 3, 0, 1, 2, 0, 1]);
        assert_eq!(&words[12..19], &[28, 1, 1, 0, 1, 2, 2]);
        // Texels after the one record: from 37.
        assert_eq!(&words[19..31], &[37, 4, 2, 45, 2, 1, 47, 1, 1, 48, 1, 1]);
        assert_eq!(words[31], 0.5f32.to_bits());
        assert_eq!(words[32], 0.25f32.to_bits());
        assert_eq!(&words[45..49], &[grey(25), grey(45), grey(35), grey(9)]);
        assert_eq!(words.len(), 49);
    }

    #[test]
    fn colours_and_tangents_follow_each_record_s_coordinates() {
        let uv = [glam::Vec2::ZERO; 3];
        let colour = [glam::Vec4::new(1.0, 0.0, 0.5, 1.0); 3];
        let up = glam::Vec4::new(0.0, 0.0, 1.0, -1.0);
        let tangents = [[up, up, up.truncate().extend(1.0)], [glam::Vec4::ZERO; 3]];
        let second = [glam::Vec2::new(0.75, 0.5); 3];
        let records = Records {
            uvs: vec![uv, uv],
            colours: vec![colour; 2],
            tangents: tangents.to_vec(),
            second_uvs: vec![second; 2],
        };
        let words = TextureWords::pack(&[], &records);
        // Records at 5, 22 words each: colours at 6, tangents at 12, the
        // second coordinates at 16.
        assert_eq!(&words[0..5], &[5, 22, 6, 12, 16]);
        assert_eq!(words.len(), 5 + 2 * 22);
        assert_eq!(words[5 + 6], 65535);
        assert_eq!(words[5 + 7], 32768 | (65535 << 16));
        let oct_up = GpuTriangleNormals::pack([glam::DVec3::Z; 3]).n0;
        assert_eq!(
            &words[5 + 12..5 + 16],
            &[
                oct_up,
                oct_up,
                oct_up,
                TextureWords::TANGENT_PRESENT | 0b011
            ]
        );
        assert_eq!(words[5 + 16], 0.75f32.to_bits());
        assert_eq!(words[5 + 17], 0.5f32.to_bits());
        // The second triangle has no tangents.
        assert_eq!(&words[27 + 12..27 + 16], &[0; 4]);
        // Without textures and colours there is no buffer.
        let bare = Records {
            uvs: vec![uv],
            ..Records::default()
        };
        assert!(TextureWords::pack(&[], &bare).is_empty());
    }
}
