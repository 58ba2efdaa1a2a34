//! The exact heuristic for nodes of a few objects, without sorting. Most
//! of a big mesh's nodes are small: 1.23 M of the 2.3 M nodes of the
//! 1.1 M-triangle bunny's tree held 3 to 12 objects when its leaves held
//! about 3 (and 46% of them became leaves). Every face of every box is a
//! candidate position, and each box is compared against all candidates of
//! an axis at once, in lanes the compiler vectorises. The counts are the ones the
//! sorted sweep ([`super::sah`]) keeps, so the plane is the sweep's, bit
//! for bit (a proptest holds them equal, and the digest of the bunny's
//! tree did not change). The costs are bounded in lanes too, and only the
//! candidates that may beat the best so far (at first, the leaf's cost)
//! are costed exactly, so a node that stays a leaf costs no more than its
//! counts.

use crate::geometry::Aabb;

use super::binned::ClippedBox;
use super::build_params::BuildParams;
use super::clip::{clear_above, clear_below};
use super::split::{inverse_area, AxisCost, Split, GAP_ROUNDING_MARGIN};

/// Nodes of at most this many objects are searched here, bigger ones by the
/// sorted sweep: this search is O(n^2) where the sort is O(n log n).
/// Measured on the 1.1 M-triangle bunny, binned build on one thread, CPU
/// time (three rounds): 3.90-3.94 s
/// with the sorted sweep for every node, 3.58-3.62 s with this search up
/// to 10, 12 or 14 objects, 3.93 s up to 16 and 4.04 s up to 20 (and once
/// the counts were integers, up to 16 took the time of up to 12). With
/// leaves of about 7 triangles (`LARGE_SCENE_TRIANGLE_COST`,
/// three rounds): up to 16 1.76 - 1.78 s, 24 1.77 - 1.78 s, 32 1.81 s, 12 1.79 -
/// 1.81 s.
pub(super) const MAX_OBJECTS: usize = 16;

/// Nodes of at most this many objects are split by
/// [`Sah::split_few`](super::sah::Sah::split_few), from their clipped boxes
/// with the events sorted on the stack, rather than by keeping sorted event
/// lists (whose split, merge and allocations cost more than sorting a few
/// events afresh). Both find the same plane.
pub(super) const FEW: usize = 32;

/// Candidates are compared in groups of this many (two SSE registers).
const LANES: usize = 8;

/// One group of candidate positions `y` of one axis, and what the sweep
/// knows at each: how many boxes start at or before it, end at or after
/// it, and end after it, and the next position above it.
struct Group {
    y: [f32; LANES],
    starts_at_or_before: [f32; LANES],
    ends_at_or_after: [f32; LANES],
    ends_after: [f32; LANES],
    /// The lowest min or max above `y`; infinite above the highest.
    next: [f32; LANES],
}

impl Group {
    /// The counts at positions `y` (NaN past the last candidate, so that
    /// every cost and comparison of theirs fails) over the boxes spanning
    /// `[mins[j], maxs[j]]`. The accumulators stay in registers while the
    /// boxes stream past.
    #[inline(always)]
    fn count(y: [f32; LANES], mins: &[f32], maxs: &[f32]) -> Group {
        // Integer counts: a compare's mask is subtracted, where a float
        // count would mask a 1.0 and add it.
        let mut starts_at_or_before = [0i32; LANES];
        let mut ends_at_or_after = [0i32; LANES];
        let mut ends_after = [0i32; LANES];
        let mut next = [f32::INFINITY; LANES];
        for (&min, &max) in mins.iter().zip(maxs) {
            for l in 0..LANES {
                let y = y[l];
                starts_at_or_before[l] += (min <= y) as i32;
                ends_at_or_after[l] += (max >= y) as i32;
                ends_after[l] += (max > y) as i32;
                let above_min = if min > y { min } else { f32::INFINITY };
                let above_max = if max > y { max } else { f32::INFINITY };
                let n = next[l];
                let n = if above_min < n { above_min } else { n };
                next[l] = if above_max < n { above_max } else { n };
            }
        }
        Group {
            y,
            starts_at_or_before: starts_at_or_before.map(|c| c as f32),
            ends_at_or_after: ends_at_or_after.map(|c| c as f32),
            ends_after: ends_after.map(|c| c as f32),
            next,
        }
    }

    /// Lower bounds of the three kinds of candidate at each position: the
    /// plane at `y` itself (exact; infinite outside the cell); a gap plane
    /// between `y` and the next position (the cost is linear in between,
    /// so at least its value at one end); a gap plane below `y` when it is
    /// the `lowest` position.
    #[inline(always)]
    fn bounds(&self, cost: &AxisCost, n: f32, lowest: f32) -> [[f32; LANES]; 3] {
        let mut at = [f32::INFINITY; LANES];
        let mut gap_after = [f32::INFINITY; LANES];
        let mut gap_before = [f32::INFINITY; LANES];
        for l in 0..LANES {
            let y = self.y[l];
            let below = self.starts_at_or_before[l];
            let here = cost.at_counts(y, below, self.ends_at_or_after[l]);
            at[l] = if cost.inside(y) { here } else { f32::INFINITY };
            let above = self.ends_after[l];
            let next = self.next[l];
            let far = if next < f32::INFINITY { next } else { y };
            let (near, far) = (
                cost.at_counts(y, below, above),
                cost.at_counts(far, below, above),
            );
            gap_after[l] = if near < far { near } else { far };
            let before = cost.at_counts(y, 0.0, n);
            gap_before[l] = if y == lowest { before } else { f32::INFINITY };
        }
        [at, gap_after, gap_before]
    }
}

/// The plane the sorted sweep chooses ([`super::sah`]) when it costs less
/// than a leaf of `boxes`, else `None`. The boxes' bounds must be finite.
/// Ties go as in the sweep: the lowest axis, then the lowest position.
#[allow(clippy::neg_cmp_op_on_partial_ord)] // NaN counts as not positive
pub(super) fn cheapest_paying_split(
    boxes: &[ClippedBox],
    cell: &Aabb,
    params: &BuildParams,
    gap: f32,
) -> Option<Split> {
    let n = boxes.len();
    debug_assert!(n <= FEW);
    let inv_area = inverse_area(cell)?;
    let mut best = Best {
        split: None,
        cost: params.intersection_cost * n as f32,
    };
    let may_beat = |bound: f32, best: &Best| bound * (1.0 - GAP_ROUNDING_MARGIN) <= best.cost;
    for a in 0..3 {
        if !(cell.max[a] > cell.min[a]) {
            continue;
        }
        let cost = AxisCost::new(params, cell, a, inv_area);
        // The candidates: every min, then every max (-0.0 as 0.0, as the
        // sweep's events store it), then NaN to fill the last group.
        let mut positions = [f32::NAN; 2 * FEW + LANES];
        let (mut mins, mut maxs) = ([0.0; FEW], [0.0; FEW]);
        let mut lowest = f32::INFINITY;
        for (j, b) in boxes.iter().enumerate() {
            (mins[j], maxs[j]) = (b.bounds.min[a] + 0.0, b.bounds.max[a] + 0.0);
            (positions[j], positions[n + j]) = (mins[j], maxs[j]);
            lowest = lowest.min(mins[j]);
        }
        let (mins, maxs) = (&mins[..n], &maxs[..n]);
        for first in (0..2 * n).step_by(LANES) {
            let mut y = [0.0; LANES];
            y.copy_from_slice(&positions[first..first + LANES]);
            let group = Group::count(y, mins, maxs);
            let [at, gap_after, gap_before] = group.bounds(&cost, n as f32, lowest);
            for l in 0..LANES.min(2 * n - first) {
                let y = group.y[l];
                // Counts become integers only for the candidates costed.
                let below = || group.starts_at_or_before[l] as usize;
                if at[l] <= best.cost {
                    let above = group.ends_at_or_after[l] as usize;
                    best.offer(&cost, y, below(), above);
                }
                if may_beat(gap_after[l], &best) {
                    // The gap between y and the next position, as the sweep
                    // takes it: only the end the cost's slope favours.
                    let (below, above) = (below(), group.ends_after[l] as usize);
                    let low = clear_above(y, gap);
                    let next = group.next[l];
                    if next == f32::INFINITY {
                        best.offer(&cost, low, below, above);
                    } else {
                        let high = clear_below(next, gap);
                        if low <= high {
                            if below >= above {
                                best.offer(&cost, low, below, above);
                            }
                            if below <= above {
                                best.offer(&cost, high, below, above);
                            }
                        }
                    }
                }
                if may_beat(gap_before[l], &best) {
                    best.offer(&cost, clear_below(y, gap), 0, n);
                }
            }
        }
    }
    best.split
}

/// The cheapest plane offered so far, or the cost to beat.
struct Best {
    split: Option<Split>,
    cost: f32,
}

impl Best {
    /// Keeps a plane at `x` strictly inside the cell when it costs less, or
    /// as much at a lower position on the same axis.
    fn offer(&mut self, cost: &AxisCost, x: f32, below: usize, above: usize) {
        if !cost.inside(x) {
            return;
        }
        let c = cost.at(x, below, above);
        let wins = c < self.cost
            || (c == self.cost
                && self
                    .split
                    .is_some_and(|s| s.axis == cost.axis() && x < s.position));
        if wins {
            self.cost = c;
            self.split = Some(Split {
                axis: cost.axis(),
                position: x,
                cost: c,
                below,
                above,
            });
        }
    }
}
