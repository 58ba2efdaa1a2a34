//! Denoised images: the path tracer's radiance, albedo and normal of a
//! whole image denoised by the GPU denoiser ([`Denoiser`]) and written as
//! `kdray render --denoise` and the farm write them (scene-format.md, "Denoised
//! output"): a PNG tone-mapped as the scene says, or an EXR of the denoised
//! radiance beside the denoiser's three inputs.

use std::path::{Path, PathBuf};

use crate::denoise::Denoiser;
use crate::error::Result;
use crate::output::exr::{is_exr_path, write_exr_atomic};
use crate::scene::RenderSettings;
use kdray_core::denoise::DenoiseImages;

/// The files written beside a denoised `X.exr`: the noisy radiance, the
/// albedo and the normal, as `X.noisy.exr`, `X.albedo.exr` and
/// `X.normal.exr` (the names `kdray render --denoise -o X.exr` uses).
pub fn denoise_input_paths(exr: &Path) -> [PathBuf; 3] {
    ["noisy.exr", "albedo.exr", "normal.exr"].map(|e| exr.with_extension(e))
}

/// A whole image's denoiser inputs: linear radiance, mean albedo and mean
/// normal, three floats a pixel each, rows top to bottom.
#[derive(Debug, Clone, PartialEq)]
pub struct NoisyImage {
    pub width: u32,
    pub height: u32,
    pub color: Vec<f32>,
    pub albedo: Vec<f32>,
    pub normal: Vec<f32>,
}

impl NoisyImage {
    /// The image denoised by `denoiser` (OIDN's `rt_hdr_alb_nrm` network,
    /// autoexposure, as `render --denoise`).
    pub fn denoise(&self, denoiser: &Denoiser<'_>) -> Result<Vec<f32>> {
        let images = DenoiseImages {
            width: self.width as usize,
            height: self.height as usize,
            color: &self.color,
            albedo: Some(&self.albedo),
            normal: Some(&self.normal),
        };
        denoiser.denoise(&images, None)
    }

    /// Writes `denoised` (this image denoised, [`NoisyImage::denoise`])
    /// atomically to `path`: a PNG tone-mapped with `render`'s `tone_map`
    /// and `exposure`, or an EXR of the denoised radiance, written after
    /// this image's three files beside it ([`denoise_input_paths`]).
    pub fn write(&self, denoised: &[f32], path: &Path, render: &RenderSettings) -> Result<()> {
        let (w, h) = (self.width, self.height);
        if !is_exr_path(path) {
            let scale = render.exposure.exp2() as f32;
            let rgb: Vec<u8> = denoised
                .iter()
                .map(|&v| render.tone_map.to_srgb8(v, scale))
                .collect();
            return crate::output::write_png_atomic(path, w, h, &rgb);
        }
        let [noisy, albedo, normal] = denoise_input_paths(path);
        write_exr_atomic(&noisy, w, h, &self.color)?;
        write_exr_atomic(&albedo, w, h, &self.albedo)?;
        write_exr_atomic(&normal, w, h, &self.normal)?;
        write_exr_atomic(path, w, h, denoised)
    }
}
