//! How OIDN 1.4.3 maps HDR colour into the network's range and back: the
//! input scale (autoexposure unless given), then the PU transfer function
//! (a fit of the perceptually uniform PU2 curve of Aydin et al. 2008,
//! normalised at 100 cd/m^2), scaled so that the largest half float,
//! 65504, maps to 1. The GPU's packing kernel repeats these formulas in
//! WGSL (shaders/denoise/pack.wgsl); a test holds the two together.

/// The PU fit's constants, digit for digit as OIDN's color.ispc states them
/// (each becomes the nearest f32, as there).
#[allow(clippy::excessive_precision)]
mod pu_constants {
    pub const PU_A: f32 = 1.41283765e03;
    pub const PU_B: f32 = 1.64593172e00;
    pub const PU_C: f32 = 4.31384981e-01;
    pub const PU_D: f32 = -2.94139609e-03;
    pub const PU_E: f32 = 1.92653254e-01;
    pub const PU_F: f32 = 6.26026094e-03;
    pub const PU_G: f32 = 9.98620152e-01;
    pub const PU_Y0: f32 = 1.57945760e-06;
    pub const PU_Y1: f32 = 3.22087631e-02;
    pub const PU_X0: f32 = 2.23151711e-03;
    pub const PU_X1: f32 = 3.70974749e-01;
}
pub use pu_constants::*;

/// The largest HDR value the normalisation maps to 1 (the largest half float).
pub const HDR_Y_MAX: f32 = 65504.0;

/// PU of one value, unnormalised (`y` >= 0).
pub fn pu_forward_raw(y: f32) -> f32 {
    if y <= PU_Y0 {
        PU_A * y
    } else if y <= PU_Y1 {
        PU_B * y.powf(PU_C) + PU_D
    } else {
        PU_E * (y + PU_F).ln() + PU_G
    }
}

/// The inverse of [`pu_forward_raw`].
pub fn pu_inverse_raw(x: f32) -> f32 {
    if x <= PU_X0 {
        x / PU_A
    } else if x <= PU_X1 {
        ((x - PU_D) / PU_B).powf(1.0 / PU_C)
    } else {
        ((x - PU_G) / PU_E).exp() - PU_F
    }
}

/// 1 / PU(65504): what PU's output is multiplied by.
pub fn pu_norm_scale() -> f32 {
    1.0 / pu_forward_raw(HDR_Y_MAX)
}

/// Normalised PU: `y` in [0, 65504] to [0, 1].
pub fn pu_forward(y: f32) -> f32 {
    pu_forward_raw(y) * pu_norm_scale()
}

/// The inverse of [`pu_forward`].
pub fn pu_inverse(x: f32) -> f32 {
    pu_inverse_raw(x * pu_forward_raw(HDR_Y_MAX))
}

/// Rec. 709 luminance, OIDN's weights.
pub fn luminance(rgb: [f32; 3]) -> f32 {
    0.212_671 * rgb[0] + 0.715_160 * rgb[1] + 0.072_169 * rgb[2]
}

/// NaN to zero, then clamped to [0, the largest f32]: how OIDN sanitises
/// HDR colour.
pub fn sanitize_hdr(v: f32) -> f32 {
    if v.is_nan() {
        0.0
    } else {
        v.clamp(0.0, f32::MAX)
    }
}

/// OIDN's autoexposure of an HDR image (`rgb`: three floats a pixel,
/// row-major): the image is cut into blocks of about 16 x 16 pixels
/// (`(n + 8) / 16` blocks along each side, edges by integer division), the
/// mean luminance of each block found, and the log2 of those above 1e-8
/// averaged; the scale brings that geometric mean to 0.18. 1 when no block
/// is bright enough (or the image has under 8 pixels along a side).
pub fn autoexposure(width: usize, height: usize, rgb: &[f32]) -> f32 {
    const KEY: f32 = 0.18;
    const EPS: f32 = 1e-8;
    const K: usize = 16;
    let (hk, wk) = ((height + K / 2) / K, (width + K / 2) / K);
    let mut sum = 0.0f64;
    let mut count = 0usize;
    for i in 0..hk {
        let (y0, y1) = (i * height / hk, (i + 1) * height / hk);
        for j in 0..wk {
            let (x0, x1) = (j * width / wk, (j + 1) * width / wk);
            let mut l = 0.0f64;
            for y in y0..y1 {
                for x in x0..x1 {
                    let p = &rgb[(y * width + x) * 3..][..3];
                    let c = [sanitize_hdr(p[0]), sanitize_hdr(p[1]), sanitize_hdr(p[2])];
                    l += f64::from(luminance(c));
                }
            }
            let l = (l / ((y1 - y0) * (x1 - x0)) as f64) as f32;
            if l > EPS {
                sum += f64::from(l.log2());
                count += 1;
            }
        }
    }
    if count > 0 {
        KEY / ((sum / count as f64) as f32).exp2()
    } else {
        1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// PU and its inverse undo each other across the whole HDR range,
    /// through all three pieces of the fit.
    #[test]
    fn pu_round_trips() {
        let mut y = 1e-8f32;
        while y < HDR_Y_MAX {
            let back = pu_inverse(pu_forward(y));
            assert!(
                (back - y).abs() <= 2e-4 * y + 1e-9,
                "{y} -> {} -> {back}",
                pu_forward(y)
            );
            y *= 1.37;
        }
        assert!((pu_forward(HDR_Y_MAX) - 1.0).abs() < 1e-6);
        assert_eq!(pu_forward(0.0), 0.0);
    }

    /// The fit's pieces meet: continuous and increasing at the joins.
    #[test]
    fn pu_is_continuous_and_increasing() {
        for join in [PU_Y0, PU_Y1] {
            let (below, above) = (pu_forward_raw(join), pu_forward_raw(join * 1.0001));
            assert!(above > below && above - below < 1e-3, "{join}");
        }
        assert!((pu_forward_raw(PU_Y0) - PU_X0).abs() < 1e-5);
        assert!((pu_forward_raw(PU_Y1) - PU_X1).abs() < 1e-5);
    }

    /// A uniform grey of luminance L gets the scale 0.18 / L; black, 1.
    #[test]
    fn autoexposure_of_a_uniform_image_brings_it_to_the_key() {
        let (w, h) = (40, 24);
        let grey = vec![2.5f32; w * h * 3];
        let scale = autoexposure(w, h, &grey);
        let l = luminance([2.5; 3]);
        assert!((scale - 0.18 / l).abs() < 1e-5 * scale, "{scale}");
        assert_eq!(autoexposure(w, h, &vec![0.0; w * h * 3]), 1.0);
        assert_eq!(autoexposure(5, 5, &[1.0; 75]), 1.0);
    }

    /// Half the blocks at luminance a and half at b: the geometric mean.
    /// NaN and negative values count as zero.
    #[test]
    fn autoexposure_is_the_geometric_mean_of_block_luminances() {
        let (w, h) = (64, 32);
        let mut rgb = vec![0.0f32; w * h * 3];
        for y in 0..h {
            for x in 0..w {
                let v = if x < 32 { 4.0 } else { 0.25 };
                rgb[(y * w + x) * 3..][..3].copy_from_slice(&[v, v, v]);
            }
        }
        let (la, lb) = (luminance([4.0; 3]), luminance([0.25; 3]));
        let expected = 0.18 / (la * lb).sqrt();
        assert!((autoexposure(w, h, &rgb) - expected).abs() < 1e-5 * expected);
        rgb[0] = f32::NAN;
        rgb[4] = -1e9;
        let with_bad = autoexposure(w, h, &rgb);
        assert!(with_bad.is_finite() && with_bad > expected);
    }
}
