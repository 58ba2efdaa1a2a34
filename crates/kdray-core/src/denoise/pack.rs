//! The images a denoise reads, and how a tile of them becomes the network's
//! input tensor and its output becomes pixels again, as OIDN 1.4.3's input
//! and output reorders do for HDR colour (the `hdr` mode):
//!
//! - colour: times the input scale, NaN to 0, clamped to [0, f32::MAX],
//!   then normalised PU ([`super::transfer`]);
//! - albedo: NaN to 0, clamped to [0, 1] (no scale, no transfer function);
//! - normal: NaN to 0, clamped to [-1, 1], then mapped to [0, 1];
//! - pixels outside the image: 0 in every channel;
//! - output: NaN to 0, clamped to [0, f32::MAX], inverse PU, then divided
//!   by the input scale (times 0 if the scale is 0).
//!
//! The GPU's kernels (shaders/denoise/pack.wgsl) do the same per pixel.

use super::layers::Tensor;
use super::tiling::Tile;
use super::transfer::{pu_forward, pu_inverse, sanitize_hdr};

/// The images of one denoise: three floats a pixel, row-major, top row
/// first. The network is chosen by which are present: colour alone, or
/// colour with albedo and normal (a normal needs an albedo).
#[derive(Clone, Copy, Debug)]
pub struct DenoiseImages<'a> {
    pub width: usize,
    pub height: usize,
    pub color: &'a [f32],
    pub albedo: Option<&'a [f32]>,
    pub normal: Option<&'a [f32]>,
}

impl DenoiseImages<'_> {
    /// 3, 6 or 9: colour, then albedo, then normal.
    pub fn input_channels(&self) -> usize {
        3 + 3 * usize::from(self.albedo.is_some()) + 3 * usize::from(self.normal.is_some())
    }

    /// Whether every image holds `width * height * 3` floats and a normal
    /// comes with an albedo.
    pub fn check(&self) -> Result<(), String> {
        let n = self.width * self.height * 3;
        for (name, image) in [
            ("colour", Some(self.color)),
            ("albedo", self.albedo),
            ("normal", self.normal),
        ] {
            if let Some(image) = image {
                if image.len() != n {
                    return Err(format!(
                        "the {name} image holds {} floats, expected {n} ({} x {} x 3)",
                        image.len(),
                        self.width,
                        self.height
                    ));
                }
            }
        }
        if self.normal.is_some() && self.albedo.is_none() {
            return Err("a normal image needs an albedo image".into());
        }
        Ok(())
    }
}

/// One colour value as the network reads it.
pub fn pack_color(v: f32, input_scale: f32) -> f32 {
    pu_forward(sanitize_hdr(v * input_scale))
}

/// One albedo value as the network reads it.
pub fn pack_albedo(v: f32) -> f32 {
    if v.is_nan() {
        0.0
    } else {
        v.clamp(0.0, 1.0)
    }
}

/// One normal component as the network reads it.
pub fn pack_normal(v: f32) -> f32 {
    let v = if v.is_nan() { 0.0 } else { v.clamp(-1.0, 1.0) };
    v * 0.5 + 0.5
}

/// One output value of the network as HDR colour.
pub fn unpack_color(v: f32, input_scale: f32) -> f32 {
    let output_scale = if input_scale != 0.0 {
        1.0 / input_scale
    } else {
        0.0
    };
    pu_inverse(sanitize_hdr(v)) * output_scale
}

/// The network's input tensor for `tile` (`tile_height` x `tile_width`).
pub fn pack_tile(
    images: &DenoiseImages<'_>,
    input_scale: f32,
    tile: &Tile,
    tile_height: usize,
    tile_width: usize,
) -> Tensor {
    let mut t = Tensor::zeros(images.input_channels(), tile_height, tile_width);
    let plane = tile_height * tile_width;
    for y in 0..tile.src_height {
        for x in 0..tile.src_width {
            let src = ((tile.src_y + y) * images.width + tile.src_x + x) * 3;
            let dst = (tile.offset_y + y) * tile_width + tile.offset_x + x;
            for c in 0..3 {
                t.data[c * plane + dst] = pack_color(images.color[src + c], input_scale);
                if let Some(albedo) = images.albedo {
                    t.data[(3 + c) * plane + dst] = pack_albedo(albedo[src + c]);
                }
                if let Some(normal) = images.normal {
                    t.data[(6 + c) * plane + dst] = pack_normal(normal[src + c]);
                }
            }
        }
    }
    t
}

/// Writes the output pixels of `tile` from the network's output `t` into
/// `out` (three floats a pixel, `width` pixels a row).
pub fn unpack_tile(t: &Tensor, input_scale: f32, tile: &Tile, width: usize, out: &mut [f32]) {
    let plane = t.height * t.width;
    for y in tile.out_y..tile.out_y + tile.out_height {
        for x in tile.out_x..tile.out_x + tile.out_width {
            let ty = y - tile.src_y + tile.offset_y;
            let tx = x - tile.src_x + tile.offset_x;
            for c in 0..3 {
                out[(y * width + x) * 3 + c] =
                    unpack_color(t.data[c * plane + ty * t.width + tx], input_scale);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::denoise::tiling::TilePlan;

    #[test]
    fn packing_follows_oidns_conventions() {
        assert_eq!(pack_normal(-1.0), 0.0);
        assert_eq!(pack_normal(1.0), 1.0);
        assert_eq!(pack_normal(0.0), 0.5);
        assert_eq!(pack_normal(-7.0), 0.0);
        assert_eq!(pack_normal(f32::NAN), 0.5);
        assert_eq!(pack_albedo(1.5), 1.0);
        assert_eq!(pack_albedo(-0.5), 0.0);
        assert_eq!(pack_albedo(f32::NAN), 0.0);
        assert_eq!(pack_color(f32::NAN, 2.0), 0.0);
        assert_eq!(pack_color(-3.0, 2.0), 0.0);
        assert!(pack_color(f32::INFINITY, 1.0).is_finite());
        assert_eq!(unpack_color(f32::NAN, 1.0), 0.0);
        assert_eq!(unpack_color(0.4, 0.0), 0.0);
    }

    /// Packing then unpacking colour gives it back (within PU's round
    /// trip), whatever the input scale.
    #[test]
    fn colour_round_trips_through_the_scale_and_pu() {
        for scale in [0.01f32, 1.0, 37.0] {
            for v in [0.0f32, 1e-4, 0.18, 1.0, 20.0, 900.0] {
                let back = unpack_color(pack_color(v, scale), scale);
                assert!((back - v).abs() <= 3e-4 * v + 1e-7, "{v} x {scale}: {back}");
            }
        }
    }

    /// A padded tile holds the image's pixels at its offset and zeros
    /// elsewhere, and unpacking an identity tensor writes every pixel back.
    #[test]
    fn a_tile_packs_and_unpacks_its_pixels() {
        let (w, h) = (20, 11);
        let color: Vec<f32> = (0..w * h * 3).map(|i| (i % 17) as f32 * 0.3).collect();
        let albedo = vec![0.5f32; w * h * 3];
        let normal = vec![-1.0f32; w * h * 3];
        let images = DenoiseImages {
            width: w,
            height: h,
            color: &color,
            albedo: Some(&albedo),
            normal: Some(&normal),
        };
        images.check().unwrap();
        let plan = TilePlan::new(w, h, 9, u64::MAX);
        let tile = plan.tiles[0];
        let t = pack_tile(&images, 1.0, &tile, plan.tile_height, plan.tile_width);
        assert_eq!((t.channels, t.height, t.width), (9, 16, 32));
        assert_eq!(t.at(0, 3, 4), pack_color(color[(3 * w + 4) * 3], 1.0));
        assert_eq!(t.at(4, 10, 19), 0.5);
        assert_eq!(t.at(7, 0, 0), 0.0);
        assert_eq!(t.at(0, 11, 3), 0.0, "below the image");
        assert_eq!(t.at(5, 2, 20), 0.0, "right of the image");
        let mut out = vec![-1.0f32; w * h * 3];
        unpack_tile(&t, 1.0, &tile, w, &mut out);
        for (o, c) in out.iter().zip(&color) {
            assert!((o - c).abs() <= 3e-4 * c + 1e-7);
        }
    }

    #[test]
    fn mismatched_images_are_refused() {
        let color = vec![0.0f32; 12];
        let short = vec![0.0f32; 9];
        let images = DenoiseImages {
            width: 2,
            height: 2,
            color: &color,
            albedo: Some(&short),
            normal: None,
        };
        assert!(images.check().unwrap_err().contains("albedo image holds 9"));
        let no_albedo = DenoiseImages {
            albedo: None,
            normal: Some(&color),
            ..images
        };
        assert!(no_albedo.check().unwrap_err().contains("needs an albedo"));
    }
}
