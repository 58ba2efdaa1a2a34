//! The surface area heuristic's cost model, shared by its three searches
//! for a plane (the sweep of [`super::sah`], the bins of [`super::binned`],
//! the small nodes of [`super::few`]): the cost of a plane on one axis of a
//! cell, the best plane found, and the bound that skips a gap between
//! candidates.

use crate::geometry::Aabb;

use super::build_params::BuildParams;

/// The best plane found, and the heuristic's counts for it.
#[derive(Debug, Clone, Copy)]
pub(super) struct Split {
    pub axis: usize,
    pub position: f32,
    pub cost: f32,
    pub below: usize,
    pub above: usize,
}

/// One over the cell's surface area, by which every plane's cost divides
/// its children's areas; `None` for a flat or NaN cell, which no plane
/// splits.
pub(super) fn inverse_area(cell: &Aabb) -> Option<f32> {
    let area = cell.surface_area();
    (area > 0.0).then(|| 1.0 / area)
}

/// The surface area heuristic's cost of a plane on one axis of a cell, as
/// a function of its position: a child's area is linear in it.
pub(super) struct AxisCost {
    axis: usize,
    lo: f32,
    hi: f32,
    /// A child's share of the cell's area is `flat + per_unit * width`.
    flat: f32,
    per_unit: f32,
    traversal: f32,
    intersection: f32,
    empty_bonus: f32,
}

impl AxisCost {
    pub fn new(params: &BuildParams, cell: &Aabb, axis: usize, inv_area: f32) -> Self {
        let e = (cell.max - cell.min).max(glam::Vec3::ZERO);
        let (d1, d2) = (e[(axis + 1) % 3], e[(axis + 2) % 3]);
        AxisCost {
            axis,
            lo: cell.min[axis],
            hi: cell.max[axis],
            flat: 2.0 * d1 * d2 * inv_area,
            per_unit: 2.0 * (d1 + d2) * inv_area,
            traversal: params.traversal_cost,
            intersection: params.intersection_cost,
            empty_bonus: params.empty_bonus,
        }
    }

    /// The cost of a plane at `x` with `below` and `above` objects in the
    /// children.
    pub fn at(&self, x: f32, below: usize, above: usize) -> f32 {
        // Through u32 (counts are below 2^30, `events::MAX_OBJECTS`): one
        // instruction each, where a usize takes several.
        self.at_counts(x, below as u32 as f32, above as u32 as f32)
    }

    /// [`AxisCost::at`] with the counts as floats (whole numbers), the
    /// form a loop over many positions vectorises.
    #[inline(always)]
    pub fn at_counts(&self, x: f32, below: f32, above: f32) -> f32 {
        let p_below = self.flat + self.per_unit * (x - self.lo);
        let p_above = self.flat + self.per_unit * (self.hi - x);
        let bonus = if below == 0.0 || above == 0.0 {
            self.empty_bonus
        } else {
            1.0
        };
        self.traversal + bonus * self.intersection * (p_below * below + p_above * above)
    }

    /// Whether a plane at `x` lies strictly inside the cell (NaN does not).
    #[inline(always)]
    pub fn inside(&self, x: f32) -> bool {
        self.lo < x && x < self.hi
    }

    pub fn axis(&self) -> usize {
        self.axis
    }

    /// Makes a plane at `x` the `best` when it lies strictly inside the
    /// cell and costs less (the first found wins a tie).
    pub fn keep_cheaper(&self, best: &mut Option<Split>, x: f32, below: usize, above: usize) {
        if !self.inside(x) {
            return;
        }
        let cost = self.at(x, below, above);
        if best.is_none_or(|b| cost < b.cost) {
            *best = Some(Split {
                axis: self.axis,
                position: x,
                cost,
                below,
                above,
            });
        }
    }
}

/// Whether a plane in the gap between positions `low` and `high`, with
/// `below` and `above` objects in the children, may cost no more than the
/// `best`: the cost is linear in the position, so at least its value at one
/// end, less a margin for the rounding of the two sums.
pub(super) fn gap_may_beat(
    best: &Option<Split>,
    cost: &AxisCost,
    low: f32,
    high: f32,
    below: usize,
    above: usize,
) -> bool {
    let Some(best) = best else {
        return true;
    };
    let (at_low, at_high) = (cost.at(low, below, above), cost.at(high, below, above));
    let bound = if at_low < at_high { at_low } else { at_high };
    bound * (1.0 - GAP_ROUNDING_MARGIN) <= best.cost
}

/// How far the rounding of a cost at a gap's end may take it above the
/// exact line's (a few ulps of the sums): see [`gap_may_beat`].
pub(super) const GAP_ROUNDING_MARGIN: f32 = 1e-4;
