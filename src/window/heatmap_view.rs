//! *pure*: the window's cost heatmap. The accumulation pass adds each
//! pixel's walk cost (nodes visited, leaves visited, objects tested, over
//! its rays) to a cost buffer beside its colour; this turns the costs read
//! back, divided by each pixel's sample count, into texels that the present
//! pass shows as they are: the colour map of `output::heatmap`, the work per
//! sample (nodes visited plus objects tested) scaled to the image's largest.

use crate::output::heatmap::colour;

/// The texels of the heatmap of `costs` (three words per pixel, as
/// `gpu::bindings::PIXEL_COSTS`) over `accumulation` (per pixel: colour
/// sums and the sample count in `[3]`), and the scale's top: the largest
/// work per sample, rounded up, at least 1. A pixel without samples stays
/// empty (count 0), as in the accumulation buffer, so the present pass
/// treats it alike. Each texel is a colour level / 255 with count 1: the
/// present pass's quantisation gives back exactly the colour map's levels.
pub fn heatmap_texels(costs: &[u32], accumulation: &[[f32; 4]]) -> (Vec<[f32; 4]>, u32) {
    let work: Vec<Option<f64>> = accumulation
        .iter()
        .zip(costs.chunks_exact(crate::gpu::bindings::COST_WORDS))
        .map(|(a, c)| (a[3] > 0.0).then(|| (c[0] as f64 + c[2] as f64) / a[3] as f64))
        .collect();
    let max = work
        .iter()
        .flatten()
        .fold(0.0f64, |m, &w| m.max(w))
        .ceil()
        .max(1.0);
    let texels = work
        .iter()
        .map(|w| match w {
            Some(w) => {
                let [r, g, b] = colour(w / max);
                [r as f32 / 255.0, g as f32 / 255.0, b as f32 / 255.0, 1.0]
            }
            None => [0.0; 4],
        })
        .collect();
    (texels, max as u32)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// What the present pass does to a texel: floor(255 * sum / count + 0.5).
    fn shown(t: [f32; 4]) -> [u8; 3] {
        std::array::from_fn(|k| (255.0 * (t[k] / t[3]).clamp(0.0, 1.0) + 0.5).floor() as u8)
    }

    #[test]
    fn texels_show_work_per_sample_in_the_colour_map() {
        // Pixel 0: 2 samples, 10 nodes + 30 objects = 20 per sample (the
        // largest); pixel 1: 1 sample, 5 + 5 = 10 per sample; pixel 2: no
        // sample yet; pixel 3: 4 samples, no work. Leaves do not count.
        let costs = [10, 4, 30, 5, 2, 5, 7, 7, 7, 0, 9, 0];
        let acc = [
            [0.5, 0.5, 0.5, 2.0],
            [0.1, 0.2, 0.3, 1.0],
            [0.0; 4],
            [1.0, 1.0, 1.0, 4.0],
        ];
        let (texels, max) = heatmap_texels(&costs, &acc);
        assert_eq!(max, 20);
        assert_eq!(shown(texels[0]), colour(1.0));
        assert_eq!(shown(texels[1]), colour(0.5));
        assert_eq!(texels[2], [0.0; 4], "no sample: left empty");
        assert_eq!(shown(texels[3]), colour(0.0));
        // Every level of the map comes back exactly through the present pass.
        for i in 0..=1000 {
            let c = colour(i as f64 / 1000.0);
            let t = [
                c[0] as f32 / 255.0,
                c[1] as f32 / 255.0,
                c[2] as f32 / 255.0,
                1.0,
            ];
            assert_eq!(shown(t), c);
        }
    }

    #[test]
    fn the_scale_rounds_up_and_is_at_least_one() {
        let (_, max) = heatmap_texels(&[1, 0, 2, 0, 0, 0], &[[0.0, 0.0, 0.0, 2.0], [0.0; 4]]);
        assert_eq!(max, 2, "1.5 per sample rounds up");
        let (_, max) = heatmap_texels(&[0, 0, 0], &[[0.0, 0.0, 0.0, 1.0]]);
        assert_eq!(max, 1);
        let (texels, max) = heatmap_texels(&[], &[]);
        assert_eq!((texels.len(), max), (0, 1));
    }
}
