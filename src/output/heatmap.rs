//! A picture of the cost: per pixel, the work the kernel did (k-d nodes
//! visited plus objects tested, summed over every ray of the pixel:
//! primary, shadow and reflection, all samples), in false colour, with a
//! colour bar and its scale printed under the image.
//!
//! The scale is linear from 0 to `max` work units; pixels above it show the
//! top colour, and the bar says so (`>= max`). A fixed `max` makes heatmaps
//! of different runs comparable; without one the image's own maximum is used.

use std::path::Path;

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::font::{register as register_font, FAMILY};
use crate::error::{Error, Result};

/// Rows under the image that hold the bar and its labels.
pub const BAR_ROWS: u32 = 40;

/// Control points of the colour map (close to matplotlib's "inferno":
/// perceptually ordered, dark for no work, bright for the most).
pub const STOPS: [(f64, [f64; 3]); 5] = [
    (0.0, [0.0, 0.0, 4.0]),
    (0.25, [87.0, 16.0, 110.0]),
    (0.5, [188.0, 55.0, 84.0]),
    (0.75, [249.0, 142.0, 9.0]),
    (1.0, [252.0, 255.0, 164.0]),
];

/// The colour of `x` in [0, 1] (clamped), by linear interpolation between
/// the control points.
pub fn colour(x: f64) -> [u8; 3] {
    let x = if x.is_nan() { 0.0 } else { x.clamp(0.0, 1.0) };
    let i = STOPS
        .iter()
        .rposition(|(at, _)| *at <= x)
        .unwrap_or(0)
        .min(STOPS.len() - 2);
    let (x0, c0) = STOPS[i];
    let (x1, c1) = STOPS[i + 1];
    let f = (x - x0) / (x1 - x0);
    std::array::from_fn(|k| (c0[k] + f * (c1[k] - c0[k])).round() as u8)
}

/// The scale a heatmap uses: `requested`, or the largest cost (at least 1).
pub fn scale_max(costs: &[u32], requested: Option<u32>) -> u32 {
    requested
        .unwrap_or_else(|| costs.iter().copied().max().unwrap_or(0))
        .max(1)
}

/// The heatmap of `costs` (row-major, `width` x `height`) as 8-bit RGB of
/// `width` x (`height` + [`BAR_ROWS`]): the image, then the bar and labels.
pub fn heatmap_rgb(costs: &[u32], width: u32, height: u32, max: u32) -> Result<Vec<u8>> {
    assert_eq!(
        costs.len(),
        width as usize * height as usize,
        "one cost per pixel"
    );
    let total_height = height + BAR_ROWS;
    let mut rgb = vec![255u8; width as usize * total_height as usize * 3];
    for (pixel, &c) in rgb.chunks_exact_mut(3).zip(costs) {
        pixel.copy_from_slice(&colour(c as f64 / max as f64));
    }
    draw_bar(&mut rgb, width, height, max)?;
    Ok(rgb)
}

/// The bar under the image: the colour map from 0 to `max`, with labels.
fn draw_bar(rgb: &mut [u8], width: u32, height: u32, max: u32) -> Result<()> {
    register_font()?;
    let total_height = height + BAR_ROWS;
    let root = BitMapBackend::with_buffer(rgb, (width, total_height)).into_drawing_area();
    let margin = 6i32.min(width as i32 / 8);
    let (x0, x1) = (margin, width as i32 - margin);
    let (y0, y1) = (height as i32 + 4, height as i32 + 14);
    let drawing_error =
        |e: &dyn std::fmt::Debug| Error::Output(format!("drawing the heatmap's scale: {e:?}"));
    for x in x0..x1.max(x0 + 1) {
        let [r, g, b] = colour((x - x0) as f64 / (x1 - x0 - 1).max(1) as f64);
        root.draw(&PathElement::new(vec![(x, y0), (x, y1)], RGBColor(r, g, b)))
            .map_err(|e| drawing_error(&e))?;
    }
    let style = (FAMILY, 12).into_font().color(&BLACK);
    let labels = [
        (x0, "0".to_string(), HPos::Left),
        ((x0 + x1) / 2, format!("{}", max / 2), HPos::Center),
        (x1, format!(">= {max}"), HPos::Right),
    ];
    for (x, text, h) in labels {
        let style = style.pos(Pos::new(h, VPos::Top));
        root.draw(&Text::new(text, (x, y1 + 2), style))
            .map_err(|e| drawing_error(&e))?;
    }
    let caption = "work per pixel: k-d nodes visited + objects tested, all rays";
    let style = style.pos(Pos::new(HPos::Center, VPos::Top));
    root.draw(&Text::new(caption, ((x0 + x1) / 2, y1 + 14), style))
        .map_err(|e| drawing_error(&e))?;
    root.present().map_err(|e| drawing_error(&e))?;
    Ok(())
}

/// Writes the heatmap of `costs` to `path` (atomically); returns the scale's
/// maximum.
pub fn write_heatmap(
    path: &Path,
    costs: &[u32],
    width: u32,
    height: u32,
    max: Option<u32>,
) -> Result<u32> {
    let max = scale_max(costs, max);
    let rgb = heatmap_rgb(costs, width, height, max)?;
    super::write_png_atomic(path, width, height + BAR_ROWS, &rgb)?;
    Ok(max)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_colour_map_runs_from_dark_to_bright_through_its_stops() {
        assert_eq!(colour(0.0), [0, 0, 4]);
        assert_eq!(colour(0.5), [188, 55, 84]);
        assert_eq!(colour(1.0), [252, 255, 164]);
        // Halfway between the first two stops.
        assert_eq!(colour(0.125), [44, 8, 57]);
        // Out of range and NaN clamp.
        assert_eq!(colour(7.0), colour(1.0));
        assert_eq!(colour(-1.0), colour(0.0));
        assert_eq!(colour(f64::NAN), colour(0.0));
        // Brightness (sum of channels) never falls as the cost rises.
        let sums: Vec<u32> = (0..=100)
            .map(|i| colour(i as f64 / 100.0).iter().map(|&c| c as u32).sum())
            .collect();
        assert!(sums.windows(2).all(|w| w[0] <= w[1]), "{sums:?}");
    }

    #[test]
    fn the_scale_is_the_requested_one_or_the_largest_cost() {
        assert_eq!(scale_max(&[3, 9, 4], None), 9);
        assert_eq!(scale_max(&[3, 9, 4], Some(5)), 5);
        assert_eq!(scale_max(&[0, 0], None), 1);
        assert_eq!(scale_max(&[], None), 1);
    }

    /// Pixels take the colour of their cost over the scale; costs above it
    /// clamp; the bar under the image is drawn (not left white).
    #[test]
    fn pixels_show_their_cost_and_the_bar_sits_below() {
        let (w, h) = (64u32, 2u32);
        let costs: Vec<u32> = (0..w * h).map(|i| i % 64).collect();
        let rgb = heatmap_rgb(&costs, w, h, 32).unwrap();
        assert_eq!(rgb.len(), (w * (h + BAR_ROWS) * 3) as usize);
        let at = |x: u32, y: u32| {
            let i = ((y * w + x) * 3) as usize;
            [rgb[i], rgb[i + 1], rgb[i + 2]]
        };
        assert_eq!(at(0, 0), colour(0.0));
        assert_eq!(at(16, 0), colour(0.5));
        assert_eq!(at(32, 1), colour(1.0));
        assert_eq!(at(63, 1), colour(1.0), "above the scale clamps");
        // The bar: dark at its left end, bright at its right end.
        let bar_row = h + 8;
        assert_eq!(at(6, bar_row), colour(0.0));
        assert!(at(w - 7, bar_row).iter().map(|&c| c as u32).sum::<u32>() > 600);
        // Labels: some dark text pixels in the rows under the bar.
        let text_rows = (h + 16..h + BAR_ROWS).flat_map(|y| (0..w).map(move |x| (x, y)));
        assert!(
            text_rows
                .filter(|&(x, y)| at(x, y).iter().all(|&c| c < 128))
                .count()
                > 10
        );
    }
}
