//! How an image is cut into dispatches, each small enough for the
//! adapter's storage bindings and for a real GPU's watchdog.

/// How the image is cut into dispatches: bands of whole rows, each band one
/// or more tiles of at most `tile_width` x `max_rows` pixels. Band heights
/// adapt so that one dispatch takes about `target_dispatch_ms` (real GPUs
/// reset dispatches that run for seconds); buffers never exceed the
/// adapter's storage binding size. `rows` (all by default) limits the
/// render to rows `rows.0..rows.1` of the image, whose pixels are those of
/// the whole image's render (a farm task's band).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TilePlan {
    pub tile_width: u32,
    pub max_rows: u32,
    pub target_dispatch_ms: f64,
    pub rows: (u32, u32),
}

impl TilePlan {
    /// Default bound on one dispatch's pixels (about one megapixel).
    pub const DEFAULT_MAX_TILE_PIXELS: u64 = 1 << 20;
    /// Default time one dispatch should take.
    pub const DEFAULT_TARGET_DISPATCH_MS: f64 = 250.0;
    /// Pixels in the first band, which measures the adapter's speed.
    const FIRST_BAND_PIXELS: u64 = 1 << 16;

    pub fn new(width: u32, height: u32, max_tile_pixels: u64, max_binding_bytes: u64) -> Self {
        // The output buffer holds the ray counters, then 4 bytes per pixel
        // (16 with radiance); the cost buffer (when asked for) 12 bytes per pixel.
        let max_pixels = max_tile_pixels
            .min(max_binding_bytes.saturating_sub(64) / PixelOutput::Radiance.bytes())
            .max(1);
        let tile_width = width.min(max_pixels as u32).max(1);
        let max_rows = (max_pixels / tile_width as u64).clamp(1, height.max(1) as u64) as u32;
        TilePlan {
            tile_width,
            max_rows,
            target_dispatch_ms: Self::DEFAULT_TARGET_DISPATCH_MS,
            rows: (0, u32::MAX),
        }
    }

    /// This plan for rows `first..end` of the image only.
    pub fn with_rows(self, first: u32, end: u32) -> Self {
        TilePlan {
            rows: (first, end),
            ..self
        }
    }

    /// Rows of the first band: small, to measure before committing to more.
    pub(super) fn first_band_rows(&self, width: u32) -> u32 {
        ((Self::FIRST_BAND_PIXELS / width.max(1) as u64) as u32).clamp(1, self.max_rows)
    }

    /// Rows of the next band, given how long the last one took per row.
    #[allow(clippy::neg_cmp_op_on_partial_ord)] // NaN counts as not positive
    pub(super) fn next_band_rows(&self, ms_per_row: f64) -> u32 {
        if !(ms_per_row > 0.0) {
            return self.max_rows;
        }
        ((self.target_dispatch_ms / ms_per_row) as u64).clamp(1, self.max_rows as u64) as u32
    }

    /// This plan with tiles small enough for `bytes_per_pixel` of output
    /// in one binding of `max_binding_bytes` (the feature output's 48; the
    /// plan fits 16).
    pub(super) fn fitting(self, bytes_per_pixel: u64, max_binding_bytes: u64) -> Self {
        let max_pixels = (max_binding_bytes.saturating_sub(64) / bytes_per_pixel).max(1);
        let tile_width = self.tile_width.min(max_pixels as u32).max(1);
        let max_rows = self
            .max_rows
            .min((max_pixels / tile_width as u64).max(1) as u32);
        TilePlan {
            tile_width,
            max_rows,
            ..self
        }
    }
}

/// What `render_tile` writes per pixel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum PixelOutput {
    /// One packed RGBA8.
    Rgb8,
    /// Four words: the radiance sums (`RADIANCE_OUTPUT`).
    Radiance,
    /// Twelve words: the radiance, albedo and normal sums
    /// (`FEATURE_OUTPUT`).
    Features,
}

impl PixelOutput {
    /// Bytes per pixel.
    pub(super) fn bytes(self) -> u64 {
        match self {
            PixelOutput::Rgb8 => 4,
            PixelOutput::Radiance => 16,
            PixelOutput::Features => 48,
        }
    }

    /// Words per pixel.
    pub(super) fn words(self) -> usize {
        self.bytes() as usize / 4
    }

    /// Whether the pixels are radiance sums (either float output).
    pub(super) fn radiance(self) -> bool {
        self != PixelOutput::Rgb8
    }
}
