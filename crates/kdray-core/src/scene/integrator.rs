//! How a frame's light is computed and how its radiance becomes a PNG's
//! pixels: `[render] integrator`, `tone_map` and `exposure`.

use crate::choice::Choice;

/// The light transport a frame is rendered with.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Integrator {
    /// The seed's: point lights, hard shadows, Blinn-Phong, perfect mirrors
    /// and glass, a bounded recursion (Whitted 1980).
    #[default]
    Whitted,
    /// Unbiased Monte Carlo path tracing: next-event estimation and BSDF
    /// sampling combined by multiple importance sampling, Russian roulette.
    Path,
}

impl Choice for Integrator {
    const ALL: &'static [Self] = &[Self::Whitted, Self::Path];

    fn name(self) -> &'static str {
        match self {
            Self::Whitted => "whitted",
            Self::Path => "path",
        }
    }

    fn help(self) -> &'static str {
        match self {
            Self::Whitted => "the seed's Whitted ray tracing with Blinn-Phong shading",
            Self::Path => "physically based path tracing (converges to the exact image)",
        }
    }
}

/// How linear radiance becomes an 8-bit PNG pixel of a path-traced frame
/// (Whitted PNGs are written as the seed's colours, clamped, unchanged).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum ToneMap {
    /// Narkowicz's fit of the ACES filmic curve, then the sRGB transfer
    /// function: highlights roll off instead of clipping.
    #[default]
    Aces,
    /// Clamped to [0, 1], then the sRGB transfer function.
    Clamp,
}

impl Choice for ToneMap {
    const ALL: &'static [Self] = &[Self::Aces, Self::Clamp];

    fn name(self) -> &'static str {
        match self {
            Self::Aces => "aces",
            Self::Clamp => "clamp",
        }
    }

    fn help(self) -> &'static str {
        match self {
            Self::Aces => "ACES filmic curve (Narkowicz's fit), then sRGB",
            Self::Clamp => "clamped to [0, 1], then sRGB",
        }
    }
}

impl ToneMap {
    /// The 8-bit sRGB value of linear radiance `x` scaled by `scale`
    /// (2^exposure). Non-finite radiance never reaches here (the kernel
    /// drops such samples); a NaN would map to 0.
    pub fn to_srgb8(self, x: f32, scale: f32) -> u8 {
        let v = x * scale;
        let mapped = match self {
            Self::Aces => {
                let v = v.max(0.0);
                (v * (2.51 * v + 0.03)) / (v * (2.43 * v + 0.59) + 0.14)
            }
            Self::Clamp => v,
        };
        let c = mapped.clamp(0.0, 1.0);
        let encoded = if c <= 0.003_130_8 {
            12.92 * c
        } else {
            1.055 * c.powf(1.0 / 2.4) - 0.055
        };
        (encoded * 255.0 + 0.5).floor().clamp(0.0, 255.0) as u8
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn integrators_and_tone_maps_are_found_by_their_names() {
        crate::choice::assert_names_round_trip::<Integrator>();
        crate::choice::assert_names_round_trip::<ToneMap>();
    }

    /// The sRGB curve's known points: 0 -> 0, 1 -> 255, 0.5 -> 188
    /// (0.7354 x 255), 0.0031308 -> 12.92 x 0.0031308 x 255 = 10.3.
    #[test]
    fn clamp_follows_the_srgb_transfer_function() {
        let t = ToneMap::Clamp;
        assert_eq!(t.to_srgb8(0.0, 1.0), 0);
        assert_eq!(t.to_srgb8(1.0, 1.0), 255);
        assert_eq!(t.to_srgb8(7.0, 1.0), 255);
        assert_eq!(t.to_srgb8(0.5, 1.0), 188);
        assert_eq!(t.to_srgb8(0.0031308, 1.0), 10);
        assert_eq!(t.to_srgb8(0.25, 2.0), 188);
        assert_eq!(t.to_srgb8(f32::NAN, 1.0), 0);
    }

    /// ACES rolls highlights off: monotonic, 0 at 0, below 1 at 1, close to
    /// white only far above 1.
    #[test]
    fn aces_is_monotonic_and_rolls_highlights_off() {
        let t = ToneMap::Aces;
        assert_eq!(t.to_srgb8(0.0, 1.0), 0);
        let mut last = 0;
        for i in 0..200 {
            let v = t.to_srgb8(i as f32 * 0.05, 1.0);
            assert!(v >= last);
            last = v;
        }
        assert!(t.to_srgb8(1.0, 1.0) < 240);
        assert!(t.to_srgb8(16.0, 1.0) >= 254);
    }
}
