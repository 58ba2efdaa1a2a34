//! Base-colour textures: an image decoded once on the host into RGBA8
//! texels, with the filter and wrap modes its material asks for, and the
//! exact sampling rule the kernel (shaders/texture.wgsl) and the CPU
//! reference share.
//!
//! Texture coordinates in a [`Scene`](super::Scene) follow the image: u runs
//! right from the left edge of the image, v runs down from its top row
//! (glTF's convention; the OBJ reader turns OBJ's v, which runs up from the
//! bottom row, into 1 - v). Texel (i, j) has its centre at
//! ((i + 0.5) / width, (j + 0.5) / height). A texel multiplies a material's
//! diffuse and ambient colours as stored in the file (byte / 255, no gamma
//! curve); alpha is ignored. There are no mip levels: a texture far away is
//! sampled at its base level, point or bilinear (it may alias).

use glam::{Vec2, Vec3};

/// How a texture is read between texel centres.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TextureFilter {
    /// The texel the point lies in (glTF NEAREST).
    Nearest,
    /// The four nearest texel centres, weighted by distance (glTF LINEAR,
    /// OBJ's `map_Kd`).
    Bilinear,
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

/// A decoded image with its sampler.
#[derive(Debug, Clone, PartialEq)]
pub struct Texture {
    /// The file (or glTF image) it came from, for messages.
    pub name: String,
    pub width: u32,
    pub height: u32,
    /// Row by row from the image's top row; each texel r | g << 8 | b << 16
    /// | a << 24 (WGSL's `unpack4x8unorm` order).
    pub texels: Vec<u32>,
    pub filter: TextureFilter,
    /// Along u, then along v.
    pub wrap: [TextureWrap; 2],
}

impl Texture {
    /// Decodes a PNG or JPEG image; the error says why it could not be.
    pub fn decode(
        name: &str,
        bytes: &[u8],
        filter: TextureFilter,
        wrap: [TextureWrap; 2],
    ) -> Result<Texture, String> {
        let image = image::load_from_memory(bytes).map_err(|e| e.to_string())?;
        let rgba = image.to_rgba8();
        let (width, height) = rgba.dimensions();
        if width == 0 || height == 0 {
            return Err("the image has no pixels".to_string());
        }
        let texels = rgba.pixels().map(|p| u32::from_le_bytes(p.0)).collect();
        Ok(Texture {
            name: name.to_string(),
            width,
            height,
            texels,
            filter,
            wrap,
        })
    }

    /// The colour of texel (x, y), wrapped into the image, in [0, 1].
    pub fn texel(&self, x: i32, y: i32) -> Vec3 {
        let x = wrap_index(x, self.width as i32, self.wrap[0]);
        let y = wrap_index(y, self.height as i32, self.wrap[1]);
        let t = self.texels[(y as usize) * self.width as usize + x as usize];
        let [r, g, b, _] = t.to_le_bytes();
        Vec3::new(r as f32, g as f32, b as f32) / 255.0
    }

    /// The colour at texture coordinate `uv` (the module's convention): the
    /// rule `sample_texture` in shaders/texture.wgsl computes, in the same
    /// f32 steps.
    pub fn sample(&self, uv: Vec2) -> Vec3 {
        let size = Vec2::new(self.width as f32, self.height as f32);
        let limit = TEXEL_COORDINATE_LIMIT;
        match self.filter {
            TextureFilter::Nearest => {
                let p = (uv * size)
                    .floor()
                    .clamp(Vec2::splat(-limit), Vec2::splat(limit));
                self.texel(p.x as i32, p.y as i32)
            }
            TextureFilter::Bilinear => {
                let p = (uv * size - 0.5).clamp(Vec2::splat(-limit), Vec2::splat(limit));
                let p0 = p.floor();
                let t = p - p0;
                let (x, y) = (p0.x as i32, p0.y as i32);
                let top = mix(self.texel(x, y), self.texel(x + 1, y), t.x);
                let bottom = mix(self.texel(x, y + 1), self.texel(x + 1, y + 1), t.x);
                mix(top, bottom, t.y)
            }
        }
    }

    /// Bytes of its texels on the GPU.
    pub fn texel_bytes(&self) -> u64 {
        self.texels.len() as u64 * 4
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
        Texture {
            name: "t".into(),
            width: 2,
            height: 1,
            texels: vec![
                u32::from_le_bytes([255, 0, 0, 255]),
                u32::from_le_bytes([0, 0, 255, 255]),
            ],
            filter,
            wrap: [wrap; 2],
        }
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
}
