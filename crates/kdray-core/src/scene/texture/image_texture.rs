//! A texture: its image as RGBA8 texels with the mip chain, the filters and
//! wrap modes its material asks for, and the exact sampling rule the kernel
//! (shaders/texture.wgsl) and the CPU reference share.
//!
//! Texture coordinates in a [`Scene`](crate::scene::Scene) follow the image: u runs
//! right from the left edge of the image, v runs down from its top row
//! (glTF's convention; the OBJ reader turns OBJ's v, which runs up from the
//! bottom row, into 1 - v). Texel (i, j) of a level has its centre at
//! ((i + 0.5) / width, (j + 0.5) / height) of that level. A texel multiplies
//! a material's diffuse and ambient colours as stored in the file (byte /
//! 255, no gamma curve); its alpha is read only where the material's
//! alpha mode asks ([`crate::scene::Alpha`], [`Texture::sample_alpha`]).
//!
//! Sampling at level of detail lambda ([`Texture::sample_lod`]): lambda <= 0
//! reads the base level with the magnification filter; above 0 the
//! minification filter reads, by its mip mode, the base level only
//! ([`MipMode::None`]), level ceil(lambda - 0.5) ([`MipMode::Nearest`]), or
//! levels floor(lambda) and the next, blended by the fraction
//! ([`MipMode::Linear`], trilinear with bilinear levels); lambda is first
//! clamped to the last level.

use glam::{Vec2, Vec3};

use super::mip_chain::{mip_chain, MipLevel};

/// How a texture is read between texel centres.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TextureFilter {
    /// The texel the point lies in (glTF NEAREST).
    Nearest,
    /// The four nearest texel centres, weighted by distance (glTF LINEAR,
    /// OBJ's `map_Kd`).
    Bilinear,
}

/// How a minified texture (lambda > 0) picks among its levels.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MipMode {
    /// The base level only (glTF minFilter NEAREST or LINEAR).
    None,
    /// The nearest level (glTF *_MIPMAP_NEAREST).
    Nearest,
    /// The two nearest levels, blended (glTF *_MIPMAP_LINEAR).
    Linear,
}

/// The minification filter: how each level is read, and which levels.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MinFilter {
    pub filter: TextureFilter,
    pub mip: MipMode,
}

impl MinFilter {
    /// LINEAR_MIPMAP_LINEAR: bilinear levels blended (glTF's minFilter
    /// unset, and OBJ's `map_Kd`).
    pub const TRILINEAR: MinFilter = MinFilter {
        filter: TextureFilter::Bilinear,
        mip: MipMode::Linear,
    };
}

/// What a texel index outside the image reads, per axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TextureWrap {
    Repeat,
    ClampToEdge,
    MirroredRepeat,
}

/// Texel coordinates are clamped into ±2^24 before they become integers:
/// f32 holds every integer up to there, and the wrap stays exact.
pub const TEXEL_COORDINATE_LIMIT: f32 = 16_777_216.0;

/// A decoded image with its mip chain and its sampler.
#[derive(Debug, Clone, PartialEq)]
pub struct Texture {
    /// The file (or glTF image) it came from, for messages.
    pub name: String,
    /// The base level's size.
    pub width: u32,
    pub height: u32,
    /// The base level, row by row from the image's top row; each texel r |
    /// g << 8 | b << 16 | a << 24 (WGSL's `unpack4x8unorm` order).
    pub texels: Vec<u32>,
    /// The magnification filter (lambda <= 0).
    pub filter: TextureFilter,
    /// The minification filter (lambda > 0).
    pub min_filter: MinFilter,
    /// Along u, then along v.
    pub wrap: [TextureWrap; 2],
    /// The levels below the base, halving down to 1 x 1 ([`mip_chain`]).
    pub mip_levels: Vec<MipLevel>,
}

/// One level of a texture, borrowed: its size and texels.
#[derive(Debug, Clone, Copy)]
pub struct LevelView<'a> {
    pub width: u32,
    pub height: u32,
    pub texels: &'a [u32],
}

impl Texture {
    /// A texture of base level `texels` (`width` x `height`, both above 0),
    /// its mip chain built here.
    pub fn new(
        name: &str,
        (width, height): (u32, u32),
        texels: Vec<u32>,
        filter: TextureFilter,
        min_filter: MinFilter,
        wrap: [TextureWrap; 2],
    ) -> Texture {
        assert_eq!(texels.len(), width as usize * height as usize);
        let mip_levels = mip_chain(width, height, &texels);
        Texture {
            name: name.to_string(),
            width,
            height,
            texels,
            filter,
            min_filter,
            wrap,
            mip_levels,
        }
    }

    /// Decodes a PNG or JPEG image; the error says why it could not be.
    pub fn decode(
        name: &str,
        bytes: &[u8],
        filter: TextureFilter,
        min_filter: MinFilter,
        wrap: [TextureWrap; 2],
    ) -> Result<Texture, String> {
        let image = image::load_from_memory(bytes).map_err(|e| e.to_string())?;
        // Consumed, not copied: an RGBA8 image is held once, not twice,
        // while its texels are made.
        let rgba = image.into_rgba8();
        let (width, height) = rgba.dimensions();
        if width == 0 || height == 0 {
            return Err("the image has no pixels".to_string());
        }
        let texels = rgba.pixels().map(|p| u32::from_le_bytes(p.0)).collect();
        Ok(Texture::new(
            name,
            (width, height),
            texels,
            filter,
            min_filter,
            wrap,
        ))
    }

    /// Its levels: 1 + the mip chain's.
    pub fn level_count(&self) -> u32 {
        1 + self.mip_levels.len() as u32
    }

    /// Level `k` (0 the base; `k` below [`Self::level_count`]).
    pub fn level(&self, k: u32) -> LevelView<'_> {
        match k.checked_sub(1) {
            None => LevelView {
                width: self.width,
                height: self.height,
                texels: &self.texels,
            },
            Some(below) => {
                let l = &self.mip_levels[below as usize];
                LevelView {
                    width: l.width,
                    height: l.height,
                    texels: &l.texels,
                }
            }
        }
    }

    /// The base level's mean colour, its texels decoded from sRGB as the
    /// kernel decodes colour textures (texture.wgsl, `srgb_to_linear`).
    pub fn mean_linear_colour(&self) -> [f64; 3] {
        let decode = |byte: u8| {
            let c = byte as f64 / 255.0;
            if c <= 0.04045 {
                c / 12.92
            } else {
                ((c + 0.055) / 1.055).powf(2.4)
            }
        };
        let mut sum = [0.0f64; 3];
        for t in &self.texels {
            let [r, g, b, _] = t.to_le_bytes();
            for (s, byte) in sum.iter_mut().zip([r, g, b]) {
                *s += decode(byte);
            }
        }
        let n = self.texels.len().max(1) as f64;
        sum.map(|s| s / n)
    }

    /// The colour of texel (x, y) of the base level, wrapped into the
    /// image, in [0, 1].
    pub fn texel(&self, x: i32, y: i32) -> Vec3 {
        self.level_texel(self.level(0), x, y)
    }

    /// The colour of texel (x, y) of `level`, wrapped into it, in [0, 1].
    fn level_texel(&self, level: LevelView, x: i32, y: i32) -> Vec3 {
        let x = wrap_index(x, level.width as i32, self.wrap[0]);
        let y = wrap_index(y, level.height as i32, self.wrap[1]);
        let t = level.texels[(y as usize) * level.width as usize + x as usize];
        let [r, g, b, _] = t.to_le_bytes();
        Vec3::new(r as f32, g as f32, b as f32) / 255.0
    }

    /// The colour at texture coordinate `uv` magnified (lambda <= 0): the
    /// base level read by the magnification filter.
    pub fn sample(&self, uv: Vec2) -> Vec3 {
        self.sample_level(0, self.filter, uv)
    }

    /// The colour at texture coordinate `uv` (the module's convention) at
    /// level of detail `lambda` ([`texture_lod`](super::ray_cone::texture_lod)): the rule `sample_texture`
    /// in shaders/texture.wgsl computes, in the same f32 steps.
    pub fn sample_lod(&self, uv: Vec2, lambda: f32) -> Vec3 {
        if lambda <= 0.0 {
            return self.sample(uv);
        }
        let filter = self.min_filter.filter;
        let lod = lambda.min((self.level_count() - 1) as f32);
        match self.min_filter.mip {
            MipMode::None => self.sample_level(0, filter, uv),
            MipMode::Nearest => self.sample_level((lod - 0.5).ceil() as u32, filter, uv),
            MipMode::Linear => {
                let l0 = lod.floor();
                let f = lod - l0;
                let a = self.sample_level(l0 as u32, filter, uv);
                if f == 0.0 {
                    return a;
                }
                mix(a, self.sample_level(l0 as u32 + 1, filter, uv), f)
            }
        }
    }

    /// Level `k` at `uv` by `filter`: point or bilinear, texel centres at
    /// (i + 0.5) / the level's size.
    fn sample_level(&self, k: u32, filter: TextureFilter, uv: Vec2) -> Vec3 {
        let level = self.level(k);
        let size = Vec2::new(level.width as f32, level.height as f32);
        let limit = TEXEL_COORDINATE_LIMIT;
        match filter {
            TextureFilter::Nearest => {
                let p = (uv * size)
                    .floor()
                    .clamp(Vec2::splat(-limit), Vec2::splat(limit));
                self.level_texel(level, p.x as i32, p.y as i32)
            }
            TextureFilter::Bilinear => {
                let p = (uv * size - 0.5).clamp(Vec2::splat(-limit), Vec2::splat(limit));
                let p0 = p.floor();
                let t = p - p0;
                let (x, y) = (p0.x as i32, p0.y as i32);
                let at = |x, y| self.level_texel(level, x, y);
                let top = mix(at(x, y), at(x + 1, y), t.x);
                let bottom = mix(at(x, y + 1), at(x + 1, y + 1), t.x);
                mix(top, bottom, t.y)
            }
        }
    }

    /// The alpha at texture coordinate `uv` on the base level, read by the
    /// magnification filter: the walks' alpha test (crate::geometry::alpha_test), the
    /// rule `sample_alpha` in shaders/alpha.wgsl computes, in the same f32
    /// steps. The base level whatever the distance: a walk has no ray cone.
    pub fn sample_alpha(&self, uv: Vec2) -> f32 {
        let level = self.level(0);
        let size = Vec2::new(level.width as f32, level.height as f32);
        let limit = TEXEL_COORDINATE_LIMIT;
        let at = |x: i32, y: i32| {
            let x = wrap_index(x, level.width as i32, self.wrap[0]);
            let y = wrap_index(y, level.height as i32, self.wrap[1]);
            let t = level.texels[(y as usize) * level.width as usize + x as usize];
            (t >> 24) as f32 / 255.0
        };
        match self.filter {
            TextureFilter::Nearest => {
                let p = (uv * size)
                    .floor()
                    .clamp(Vec2::splat(-limit), Vec2::splat(limit));
                at(p.x as i32, p.y as i32)
            }
            TextureFilter::Bilinear => {
                let p = (uv * size - 0.5).clamp(Vec2::splat(-limit), Vec2::splat(limit));
                let p0 = p.floor();
                let t = p - p0;
                let (x, y) = (p0.x as i32, p0.y as i32);
                let lerp = |a: f32, b: f32, t: f32| a * (1.0 - t) + b * t;
                let top = lerp(at(x, y), at(x + 1, y), t.x);
                let bottom = lerp(at(x, y + 1), at(x + 1, y + 1), t.x);
                lerp(top, bottom, t.y)
            }
        }
    }

    /// Bytes of its texels on the GPU, every level.
    pub fn texel_bytes(&self) -> u64 {
        let below: usize = self.mip_levels.iter().map(|l| l.texels.len()).sum();
        (self.texels.len() + below) as u64 * 4
    }
}

/// WGSL's `mix`: a * (1 - t) + b * t.
fn mix(a: Vec3, b: Vec3, t: f32) -> Vec3 {
    a * (1.0 - t) + b * t
}

/// Texel index `i` of an axis with `n` texels, wrapped into 0..n.
pub fn wrap_index(i: i32, n: i32, wrap: TextureWrap) -> i32 {
    match wrap {
        TextureWrap::Repeat => i.rem_euclid(n),
        TextureWrap::ClampToEdge => i.clamp(0, n - 1),
        TextureWrap::MirroredRepeat => {
            let m = i.rem_euclid(2 * n);
            if m >= n {
                2 * n - 1 - m
            } else {
                m
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn two_by_one(filter: TextureFilter, wrap: TextureWrap) -> Texture {
        Texture::new(
            "t",
            (2, 1),
            vec![
                u32::from_le_bytes([255, 0, 0, 255]),
                u32::from_le_bytes([0, 0, 255, 255]),
            ],
            filter,
            MinFilter::TRILINEAR,
            [wrap; 2],
        )
    }

    /// sRGB 188 decodes to about 0.5 linear: the mean of a red and a blue
    /// texel is half of each, and mid-grey is not 188 / 255.
    #[test]
    fn the_mean_colour_is_the_mean_of_the_decoded_texels() {
        let mean = two_by_one(TextureFilter::Nearest, TextureWrap::Repeat).mean_linear_colour();
        assert_eq!(mean, [0.5, 0.0, 0.5]);
        let grey = Texture::new(
            "grey",
            (1, 1),
            vec![u32::from_le_bytes([188, 188, 188, 255])],
            TextureFilter::Nearest,
            MinFilter::TRILINEAR,
            [TextureWrap::Repeat; 2],
        );
        let m = grey.mean_linear_colour();
        assert!((m[0] - 0.5029).abs() < 1e-3, "{m:?}");
    }

    #[test]
    fn wrap_modes_fold_indices_into_the_image() {
        let r: Vec<i32> = (-3..6)
            .map(|i| wrap_index(i, 3, TextureWrap::Repeat))
            .collect();
        assert_eq!(r, [0, 1, 2, 0, 1, 2, 0, 1, 2]);
        let c: Vec<i32> = (-3..6)
            .map(|i| wrap_index(i, 3, TextureWrap::ClampToEdge))
            .collect();
        assert_eq!(c, [0, 0, 0, 0, 1, 2, 2, 2, 2]);
        let m: Vec<i32> = (-3..6)
            .map(|i| wrap_index(i, 3, TextureWrap::MirroredRepeat))
            .collect();
        assert_eq!(m, [2, 1, 0, 0, 1, 2, 2, 1, 0]);
    }

    #[test]
    fn nearest_reads_the_texel_a_point_lies_in_and_bilinear_blends_centres() {
        let red = Vec3::new(1.0, 0.0, 0.0);
        let blue = Vec3::new(0.0, 0.0, 1.0);
        let n = two_by_one(TextureFilter::Nearest, TextureWrap::Repeat);
        assert_eq!(n.sample(Vec2::new(0.49, 0.5)), red);
        assert_eq!(n.sample(Vec2::new(0.51, 0.5)), blue);
        assert_eq!(n.sample(Vec2::new(1.25, 0.5)), red);
        let b = two_by_one(TextureFilter::Bilinear, TextureWrap::ClampToEdge);
        // Texel centres at u = 0.25 and 0.75; halfway between them, half each.
        assert_eq!(b.sample(Vec2::new(0.25, 0.5)), red);
        assert_eq!(b.sample(Vec2::new(0.5, 0.5)), (red + blue) * 0.5);
        // Clamped past the last centre.
        assert_eq!(b.sample(Vec2::new(0.95, 0.5)), blue);
        let r = two_by_one(TextureFilter::Bilinear, TextureWrap::Repeat);
        // Repeat: u = 0 lies halfway between the last texel and the first.
        assert_eq!(r.sample(Vec2::new(0.0, 0.5)), (red + blue) * 0.5);
    }

    /// A 2 x 2 texture, black and white along the top row and white and
    /// black along the bottom: its 1 x 1 level is mid grey (128).
    fn checker(mag: TextureFilter, min_filter: MinFilter) -> Texture {
        let (b, w) = (
            u32::from_le_bytes([0, 0, 0, 255]),
            u32::from_le_bytes([255, 255, 255, 255]),
        );
        Texture::new(
            "c",
            (2, 2),
            vec![b, w, w, b],
            mag,
            min_filter,
            [TextureWrap::Repeat; 2],
        )
    }

    #[test]
    fn minification_picks_levels_by_lambda_and_its_mip_mode() {
        let grey = Vec3::splat(128.0 / 255.0);
        let black = Vec3::ZERO;
        let uv = Vec2::new(0.25, 0.25); // the black texel's centre
        let min = |filter, mip| MinFilter { filter, mip };
        let close = |a: Vec3, b: Vec3| (a - b).abs().max_element() < 1e-6;
        let nearest = TextureFilter::Nearest;
        let t = checker(nearest, MinFilter::TRILINEAR);
        assert_eq!(t.level_count(), 2);
        assert_eq!(t.texel_bytes(), (4 + 1) * 4);
        // lambda <= 0: the magnification filter (nearest) at the base.
        assert_eq!(t.sample_lod(uv, 0.0), black);
        assert_eq!(t.sample_lod(uv, -3.0), black);
        // Trilinear: bilinear at the texel centre is black; a quarter of
        // the way to level 1 is a quarter grey; past the last level, level 1.
        assert!(close(t.sample_lod(uv, 0.25), grey * 0.25));
        assert!(close(t.sample_lod(uv, 1.0), grey));
        assert!(close(t.sample_lod(uv, 9.0), grey));
        // Nearest level: level 0 up to lambda 0.5, level 1 above.
        let n = checker(nearest, min(nearest, MipMode::Nearest));
        assert_eq!(n.sample_lod(uv, 0.5), black);
        assert!(close(n.sample_lod(uv, 0.51), grey));
        // No mip levels: the minification filter at the base level (here
        // bilinear, halfway between the texel centres: their mean).
        let none = checker(nearest, min(TextureFilter::Bilinear, MipMode::None));
        assert_eq!(none.sample_lod(uv, 5.0), black);
        let between = Vec2::new(0.5, 0.25);
        assert_eq!(none.sample_lod(between, 5.0), Vec3::splat(0.5));
        assert_eq!(none.sample_lod(between, 0.0), Vec3::ONE);
    }
}
