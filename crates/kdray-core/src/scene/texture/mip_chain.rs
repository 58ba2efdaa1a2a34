//! A texture's mip chain: each level half the size of the one before it,
//! rounded down and at least 1 texel, every texel the rounded mean of a box
//! of the level before it, built once on the host from the stored RGBA8
//! bytes (no gamma curve, as every kdray colour).
//!
//! The box of texel i along an axis of n texels (the level before has n,
//! this one m = max(1, n / 2) rounded down): texels 2i and 2i + 1 when n is
//! even; when n is odd and above 1, the last texel (i = m - 1) also takes
//! texel n - 1 = 2i + 2, so no texel is dropped (3 -> 1 averages all three,
//! 5 -> 2 averages {0, 1} and {2, 3, 4}); when n is 1, texel 0 alone. A
//! level texel is the box along x times the box along y, each of the four
//! bytes (r, g, b, a) the sum over the box plus half the box's texel count,
//! divided by that count (integer division: the mean rounded half up). The
//! chain ends at the 1 x 1 level: a w x h texture has
//! floor(log2(max(w, h))) + 1 levels.

/// One level of a texture below its base: the texels as [`super::Texture`]
/// stores them (row by row from the top row, RGBA8 a word).
#[derive(Debug, Clone, PartialEq)]
pub struct MipLevel {
    pub width: u32,
    pub height: u32,
    pub texels: Vec<u32>,
}

/// The levels below a `width` x `height` base level `texels`, halving down
/// to 1 x 1 (empty for a 1 x 1 texture).
pub fn mip_chain(width: u32, height: u32, texels: &[u32]) -> Vec<MipLevel> {
    let mut levels: Vec<MipLevel> = Vec::new();
    let (mut w, mut h) = (width, height);
    while w > 1 || h > 1 {
        let above = levels.last().map_or(texels, |l| l.texels.as_slice());
        let next = half_level(w, h, above);
        (w, h) = (next.width, next.height);
        levels.push(next);
    }
    levels
}

/// The texel range of box `i` along an axis of `n` texels halved to `m`.
fn box_range(i: u32, n: u32, m: u32) -> std::ops::Range<u32> {
    if n == 1 {
        return 0..1;
    }
    let end = if n % 2 == 1 && i == m - 1 {
        n
    } else {
        2 * i + 2
    };
    2 * i..end
}

/// The level below a `w` x `h` level (module doc).
fn half_level(w: u32, h: u32, texels: &[u32]) -> MipLevel {
    let (width, height) = ((w / 2).max(1), (h / 2).max(1));
    let mut out = Vec::with_capacity(width as usize * height as usize);
    for j in 0..height {
        let rows = box_range(j, h, height);
        for i in 0..width {
            let columns = box_range(i, w, width);
            let mut sum = [0u32; 4];
            let mut count = 0u32;
            for y in rows.clone() {
                for x in columns.clone() {
                    let bytes = texels[(y * w + x) as usize].to_le_bytes();
                    for (s, b) in sum.iter_mut().zip(bytes) {
                        *s += u32::from(b);
                    }
                    count += 1;
                }
            }
            out.push(u32::from_le_bytes(
                sum.map(|s| ((s + count / 2) / count) as u8),
            ));
        }
    }
    MipLevel {
        width,
        height,
        texels: out,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grey(v: u8) -> u32 {
        u32::from_le_bytes([v, v, v, 255])
    }

    #[test]
    fn a_4x2_texture_halves_to_2x1_then_1x1_by_2x2_boxes() {
        // Row 0: 0 10 20 30; row 1: 40 50 60 70 (grey, opaque).
        let base: Vec<u32> = [0, 10, 20, 30, 40, 50, 60, 70].map(grey).to_vec();
        let chain = mip_chain(4, 2, &base);
        assert_eq!(chain.len(), 2);
        assert_eq!((chain[0].width, chain[0].height), (2, 1));
        // (0 + 10 + 40 + 50) / 4 = 25; (20 + 30 + 60 + 70) / 4 = 45.
        assert_eq!(chain[0].texels, vec![grey(25), grey(45)]);
        assert_eq!((chain[1].width, chain[1].height), (1, 1));
        // A 2 x 1 level: the box is 2 x 1; (25 + 45) / 2 = 35.
        assert_eq!(chain[1].texels, vec![grey(35)]);
    }

    #[test]
    fn a_3x3_texture_averages_all_nine_texels_into_its_1x1_level() {
        // 0, 1, ..., 8 in red, 100 in green, alpha 255 - 10 k.
        let base: Vec<u32> = (0..9u8)
            .map(|k| u32::from_le_bytes([k, 100, 7 * k, 255 - 10 * k]))
            .collect();
        let chain = mip_chain(3, 3, &base);
        assert_eq!(chain.len(), 1);
        assert_eq!((chain[0].width, chain[0].height), (1, 1));
        // red: 36 / 9 = 4; blue: 252 / 9 = 28; alpha: (2295 - 360) / 9 = 215.
        assert_eq!(chain[0].texels, vec![u32::from_le_bytes([4, 100, 28, 215])]);
    }

    #[test]
    fn an_odd_axis_folds_its_last_texel_into_the_last_box_and_means_round_half_up() {
        // 5 x 1: boxes {0, 1} and {2, 3, 4}; then 2 x 1 -> 1 x 1.
        let base: Vec<u32> = [0, 1, 10, 11, 13].map(grey).to_vec();
        let chain = mip_chain(5, 1, &base);
        // (0 + 1 + 1) / 2 = 1 (0.5 rounds up); (34 + 1) / 3 = 11 (11.33).
        assert_eq!(chain[0].texels, vec![grey(1), grey(11)]);
        assert_eq!(chain[1].texels, vec![grey(6)]);
        assert_eq!(chain.len(), 2);
        // A 1 x 1 texture has no level below it.
        assert!(mip_chain(1, 1, &[grey(9)]).is_empty());
        // 1 x 4: the x box is texel 0 alone.
        let tall = mip_chain(1, 4, &[grey(0), grey(2), grey(4), grey(8)]);
        assert_eq!(tall[0].texels, vec![grey(1), grey(6)]);
        assert_eq!(tall[1].texels, vec![grey(4)]);
    }
}
