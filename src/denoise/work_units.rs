//! A tile's run as a list of units of work, in order: packing the tile,
//! the network's dispatches ([`super::dispatches::network_dispatches`]),
//! each convolution optionally cut into bands of rows so that no unit
//! exceeds a cost, and unpacking. `render --denoise` and the farm run a
//! tile's units in one submission, uncut; the window runs a few at a time
//! between frames, cut. A band computes the same invocations, each pixel
//! as the whole dispatch does, so the output does not depend on the cut.
//!
//! A unit's cost is in multiply-adds (a resampling, packing or unpacking:
//! one per value written), the measure the window's budget learns a rate
//! for.

use super::dispatches::{DenoiseKernel, StepDispatch};
use super::kernels::{CONV_OUTPUTS, WORKGROUP};

/// What a unit runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UnitKind {
    /// The tile's source pixels uploaded and packed into the input tensor.
    Pack,
    /// Rows `first_row ..` (`rows` of them, a multiple of the workgroup
    /// unless they reach the last row) of the network's dispatch `index`.
    Dispatch {
        index: usize,
        first_row: u32,
        rows: u32,
    },
    /// The output rectangle unpacked and read back.
    Unpack,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct WorkUnit {
    pub kind: UnitKind,
    /// Multiply-adds (or values written).
    pub cost: u64,
}

/// Multiply-adds of one row of a convolution `d` on a tile
/// `tile_width` wide: 3x3 taps of every input channel for each of the
/// dispatch's sixteen outputs.
fn conv_row_cost(d: &StepDispatch, tile_width: usize, tile_height: usize) -> u64 {
    let (width, _) = d.size(tile_width, tile_height);
    width as u64 * u64::from(d.src_channels + d.skip_channels) * 9 * CONV_OUTPUTS as u64
}

/// The units of a `tile_width` x `tile_height` tile's run of `dispatches`
/// for a network reading `input_channels`: each convolution cut into
/// bands of whole workgroup rows of at most `max_cost` (a single
/// workgroup row if even that exceeds it), or left whole with `None`.
pub fn tile_units(
    dispatches: &[StepDispatch],
    input_channels: usize,
    tile_width: usize,
    tile_height: usize,
    max_cost: Option<u64>,
) -> Vec<WorkUnit> {
    let pixels = (tile_width * tile_height) as u64;
    let mut units = vec![WorkUnit {
        kind: UnitKind::Pack,
        cost: pixels * input_channels as u64,
    }];
    for (index, d) in dispatches.iter().enumerate() {
        let (width, height) = d.size(tile_width, tile_height);
        if d.kernel != DenoiseKernel::Conv {
            units.push(WorkUnit {
                kind: UnitKind::Dispatch {
                    index,
                    first_row: 0,
                    rows: height,
                },
                cost: width as u64 * height as u64 * u64::from(d.out_channels),
            });
            continue;
        }
        let row_cost = conv_row_cost(d, tile_width, tile_height);
        let band = match max_cost {
            None => height.max(1),
            Some(max) => {
                let workgroup_rows = max / (row_cost * u64::from(WORKGROUP)).max(1);
                (workgroup_rows.clamp(1, u64::from(u32::MAX / WORKGROUP)) as u32) * WORKGROUP
            }
        };
        let mut first_row = 0;
        loop {
            let rows = band.min(height - first_row);
            units.push(WorkUnit {
                kind: UnitKind::Dispatch {
                    index,
                    first_row,
                    rows,
                },
                cost: row_cost * u64::from(rows),
            });
            first_row += rows;
            if first_row >= height {
                break;
            }
        }
    }
    units.push(WorkUnit {
        kind: UnitKind::Unpack,
        cost: pixels * 3,
    });
    units
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::denoise::gpu_weights::LayerBlocks;
    use crate::denoise::network_dispatches;
    use kdray_core::denoise::network::{conv_input_channels, CONV_LAYERS};

    fn table(input_channels: usize) -> Vec<StepDispatch> {
        let layers: Vec<LayerBlocks> = CONV_LAYERS
            .iter()
            .zip(conv_input_channels(input_channels))
            .map(|(l, ic)| LayerBlocks {
                out_channels: l.out_channels as u32,
                in_channels: ic as u32,
                group_offsets: (0..l.out_channels.div_ceil(8)).map(|g| g as u64).collect(),
            })
            .collect();
        network_dispatches(&layers, input_channels)
    }

    /// The rows of each dispatch in turn, as (dispatch, first row, rows).
    fn bands(units: &[WorkUnit]) -> Vec<(usize, u32, u32)> {
        units
            .iter()
            .filter_map(|u| match u.kind {
                UnitKind::Dispatch {
                    index,
                    first_row,
                    rows,
                } => Some((index, first_row, rows)),
                _ => None,
            })
            .collect()
    }

    #[test]
    fn uncut_units_are_the_dispatches_between_packing_and_unpacking() {
        let dispatches = table(9);
        let units = tile_units(&dispatches, 9, 480, 368, None);
        assert_eq!(units.len(), dispatches.len() + 2);
        assert_eq!(units[0].kind, UnitKind::Pack);
        assert_eq!(units.last().unwrap().kind, UnitKind::Unpack);
        for (i, (index, first_row, rows)) in bands(&units).into_iter().enumerate() {
            assert_eq!((index, first_row), (i, 0));
            assert_eq!(rows, dispatches[i].size(480, 368).1);
        }
    }

    /// Cut, every dispatch's rows are covered once, in order, by bands of
    /// whole workgroup rows within the cost (a workgroup row at least),
    /// and the total cost is the uncut run's.
    #[test]
    fn cut_units_cover_every_row_once_within_the_cost() {
        let dispatches = table(9);
        let (w, h) = (480, 368);
        let whole: u64 = tile_units(&dispatches, 9, w, h, None)
            .iter()
            .map(|u| u.cost)
            .sum();
        for max in [1u64, 1 << 20, 1 << 24, 1 << 28] {
            let units = tile_units(&dispatches, 9, w, h, Some(max));
            assert_eq!(units.iter().map(|u| u.cost).sum::<u64>(), whole, "{max}");
            let mut next = vec![0u32; dispatches.len()];
            let mut last_index = 0;
            for u in &units {
                let UnitKind::Dispatch {
                    index,
                    first_row,
                    rows,
                } = u.kind
                else {
                    continue;
                };
                assert!(index >= last_index, "in order");
                last_index = index;
                assert_eq!(first_row, next[index], "contiguous");
                next[index] += rows;
                let height = dispatches[index].size(w, h).1;
                let one_row = conv_row_cost(&dispatches[index], w, h) * u64::from(WORKGROUP);
                if dispatches[index].kernel == DenoiseKernel::Conv {
                    assert!(
                        rows % WORKGROUP == 0 || next[index] == height,
                        "whole workgroup rows"
                    );
                    assert!(u.cost <= max.max(one_row), "{u:?} over {max}");
                }
            }
            for (i, d) in dispatches.iter().enumerate() {
                assert_eq!(next[i], d.size(w, h).1, "every row of dispatch {i}");
            }
        }
        // The full-resolution layers of a window-sized tile need many bands.
        let cut = tile_units(&dispatches, 9, w, h, Some(1 << 24));
        assert!(cut.len() > 4 * dispatches.len(), "{}", cut.len());
    }
}
