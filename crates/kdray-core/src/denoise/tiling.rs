//! Cutting an image into tiles the network runs on one at a time, as OIDN
//! 1.4.3 does (unet.cpp): every tile is the same `tile_height` x
//! `tile_width` (multiples of 16), tiles overlap by [`TILE_OVERLAP`] (96)
//! pixels on each inner side so that each output pixel sees its whole
//! receptive field, and a tile smaller than the tile size (the last ones,
//! or the whole of a small image) is zero-padded, its pixels placed at an
//! offset that is a multiple of 16 so that the poolings see the same grid.
//!
//! The tile size starts at the whole image rounded up to 16 and, while the
//! network's largest tensor for it exceeds `max_tensor_bytes` (kdray: the
//! device's largest storage binding, 128 MiB on lavapipe), the longer side
//! is split into one more tile, never below three overlaps (288 pixels).

use super::network::{tensor_floats, ALIGNMENT, TILE_OVERLAP};

/// The tiles of an image: their common size and each one's rectangles.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TilePlan {
    pub tile_height: usize,
    pub tile_width: usize,
    pub tiles: Vec<Tile>,
}

/// One tile: which image pixels it reads, where they go in the tile's
/// tensor, and which of them it writes back.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Tile {
    /// The image rectangle read (including overlap): origin and size.
    pub src_y: usize,
    pub src_x: usize,
    pub src_height: usize,
    pub src_width: usize,
    /// Where that rectangle starts in the tile's tensor (the rest is zero).
    pub offset_y: usize,
    pub offset_x: usize,
    /// The image rectangle written (without overlap); its pixel (y, x) is
    /// the tensor's (y - src_y + offset_y, x - src_x + offset_x).
    pub out_y: usize,
    pub out_x: usize,
    pub out_height: usize,
    pub out_width: usize,
}

fn round_up(n: usize, to: usize) -> usize {
    n.div_ceil(to) * to
}

/// One side's tile size and tile count, split `splits` times (OIDN's
/// formula), for a side of `n` pixels.
fn side(n: usize, count: usize) -> usize {
    let min_tile = 3 * TILE_OVERLAP;
    if count == 1 {
        return round_up(n, ALIGNMENT);
    }
    (round_up(
        n.saturating_sub(2 * TILE_OVERLAP).div_ceil(count),
        ALIGNMENT,
    ) + 2 * TILE_OVERLAP)
        .max(min_tile)
}

/// The tile origins, sizes and overlaps along one side of `n` pixels cut
/// into tiles of `tile` pixels: (source start, source size, offset in the
/// tile, output start, output size).
fn spans(n: usize, tile: usize) -> Vec<(usize, usize, usize, usize, usize)> {
    let o = TILE_OVERLAP;
    let count = if n > tile {
        (n - 2 * o).div_ceil(tile - 2 * o)
    } else {
        1
    };
    (0..count)
        .map(|i| {
            let start = if i == 0 { 0 } else { i * (tile - 2 * o) };
            let begin = if i > 0 { o } else { 0 };
            let end = if i + 1 < count { o } else { 0 };
            let size = (n - start).min(tile);
            let offset = tile - round_up(size, ALIGNMENT);
            (start, size, offset, start + begin, size - begin - end)
        })
        .collect()
}

impl TilePlan {
    /// The tiles of a `width` x `height` image for a network reading
    /// `input_channels`, each tensor at most `max_tensor_bytes` where the
    /// minimum tile size allows (see [`TilePlan::largest_tensor_bytes`]).
    pub fn new(width: usize, height: usize, input_channels: usize, max_tensor_bytes: u64) -> Self {
        let min_tile = 3 * TILE_OVERLAP;
        let (mut count_h, mut count_w) = (1, 1);
        let (mut tile_h, mut tile_w) = (side(height, 1), side(width, 1));
        let bytes = |h: usize, w: usize| tensor_floats(input_channels, h, w).0 as u64 * 4;
        while bytes(tile_h, tile_w) > max_tensor_bytes {
            if tile_h > min_tile && tile_h > tile_w {
                count_h += 1;
                tile_h = side(height, count_h);
            } else if tile_w > min_tile {
                count_w += 1;
                tile_w = side(width, count_w);
            } else {
                break;
            }
        }
        let mut tiles = Vec::new();
        for (src_y, src_height, offset_y, out_y, out_height) in spans(height, tile_h) {
            for (src_x, src_width, offset_x, out_x, out_width) in spans(width, tile_w) {
                tiles.push(Tile {
                    src_y,
                    src_x,
                    src_height,
                    src_width,
                    offset_y,
                    offset_x,
                    out_y,
                    out_x,
                    out_height,
                    out_width,
                });
            }
        }
        TilePlan {
            tile_height: tile_h,
            tile_width: tile_w,
            tiles,
        }
    }

    /// The bytes of the network's largest tensor for this plan's tiles.
    pub fn largest_tensor_bytes(&self, input_channels: usize) -> u64 {
        tensor_floats(input_channels, self.tile_height, self.tile_width).0 as u64 * 4
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const LAVAPIPE_BINDING: u64 = 128 << 20;

    /// Every output pixel is written by exactly one tile, from a tile pixel
    /// with at least the overlap of real image (or the image's edge) on
    /// every side, and each tile's source fits its tensor at a 16-aligned
    /// offset.
    fn check_cover(plan: &TilePlan, width: usize, height: usize) {
        let mut written = vec![0u8; width * height];
        for t in &plan.tiles {
            assert_eq!(t.offset_y % ALIGNMENT, 0);
            assert_eq!(t.offset_x % ALIGNMENT, 0);
            assert_eq!(t.src_y % ALIGNMENT, 0, "the pooling grid is the image's");
            assert!(t.offset_y + t.src_height <= plan.tile_height);
            assert!(t.offset_x + t.src_width <= plan.tile_width);
            assert!(t.src_y + t.src_height <= height && t.src_x + t.src_width <= width);
            for y in t.out_y..t.out_y + t.out_height {
                assert!(y - t.src_y >= TILE_OVERLAP || t.src_y == 0);
                assert!(
                    t.src_y + t.src_height - y > TILE_OVERLAP || t.src_y + t.src_height == height
                );
                for x in t.out_x..t.out_x + t.out_width {
                    assert!(x - t.src_x >= TILE_OVERLAP || t.src_x == 0);
                    assert!(
                        t.src_x + t.src_width - x > TILE_OVERLAP || t.src_x + t.src_width == width
                    );
                    written[y * width + x] += 1;
                }
            }
        }
        assert!(written.iter().all(|&n| n == 1), "{width}x{height}");
    }

    #[test]
    fn a_small_image_is_one_padded_tile() {
        let plan = TilePlan::new(640, 360, 9, LAVAPIPE_BINDING);
        assert_eq!((plan.tile_width, plan.tile_height), (640, 368));
        assert_eq!(plan.tiles.len(), 1);
        assert_eq!(plan.tiles[0].offset_y, 0);
        check_cover(&plan, 640, 360);
    }

    /// 4K fits lavapipe's 128 MiB binding in tiles, and every pixel is
    /// covered once.
    #[test]
    fn four_k_is_cut_into_tiles_within_the_binding() {
        for channels in [3, 9] {
            let plan = TilePlan::new(3840, 2160, channels, LAVAPIPE_BINDING);
            assert!(plan.tiles.len() > 1);
            assert!(plan.largest_tensor_bytes(channels) <= LAVAPIPE_BINDING);
            check_cover(&plan, 3840, 2160);
        }
    }

    /// Small budgets force many tiles (and the minimum tile), odd sizes
    /// leave a small last tile padded at the top and left.
    #[test]
    fn many_tiles_cover_odd_images_once() {
        for (w, h, budget) in [
            (1000, 700, 20 << 20),
            (333, 1201, 1 << 20),
            (17, 5, 1),
            (600, 290, 30 << 20),
        ] {
            let plan = TilePlan::new(w, h, 3, budget);
            check_cover(&plan, w, h);
            let smallest =
                plan.tile_height <= 3 * TILE_OVERLAP && plan.tile_width <= 3 * TILE_OVERLAP;
            assert!(
                plan.largest_tensor_bytes(3) <= budget || smallest,
                "{w}x{h}"
            );
        }
        let plan = TilePlan::new(1000, 700, 3, 20 << 20);
        assert!(plan.tiles.len() >= 4);
        assert!(plan.tiles.iter().any(|t| t.offset_x > 0 || t.offset_y > 0));
    }
}
