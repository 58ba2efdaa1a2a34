//! The surface area heuristic with perfect splits in O(N log N) (Wald &
//! Havran 2006): each node holds, per axis, the sorted events of its
//! objects' clipped boxes. The best plane is one sweep over the three lists;
//! the children's lists are the parent's, split in linear time, plus the
//! re-clipped boxes of the objects that straddle the plane, whose few new
//! events are sorted and merged in. The only full sort is at the root.
//!
//! Classification is [`super::clip::sides`]: against a plane at `p`, an
//! object goes below when its clipped `min <= p + ε`, above when
//! `max >= p - ε`. The sweep counts objects without ε (a cost estimate).

use crate::geometry::Aabb;

use super::build::{BuildParams, Decision, Strategy};
use super::clip::{sides, Shapes};
use super::events::{self, END, PLANAR, START};

/// One node's objects: the events of their clipped boxes, sorted, per axis.
#[derive(Debug)]
pub struct EventLists {
    axes: [Vec<u64>; 3],
    count: usize,
}

/// Sorts the root's three lists, one thread per list when `threads > 1`.
fn sort_lists(lists: &mut [Vec<u64>; 3], threads: usize) {
    if threads < 2 || lists[0].len() < 1 << 16 {
        lists.iter_mut().for_each(|l| l.sort_unstable());
        return;
    }
    let [x, y, z] = lists;
    std::thread::scope(|scope| {
        let z_sort = scope.spawn(|| z.sort_unstable());
        if threads > 2 {
            let y_sort = scope.spawn(|| y.sort_unstable());
            x.sort_unstable();
            join(y_sort);
        } else {
            x.sort_unstable();
            y.sort_unstable();
        }
        join(z_sort);
    });
}

fn join(handle: std::thread::ScopedJoinHandle<'_, ()>) {
    if let Err(payload) = handle.join() {
        std::panic::resume_unwind(payload);
    }
}

impl EventLists {
    /// The root's lists: every object by its box (the root cell is the union
    /// of the boxes, so there is nothing to clip).
    pub fn root(shapes: &Shapes<'_>, threads: usize) -> Self {
        let n = shapes.len();
        assert!(n <= events::MAX_OBJECTS, "{n} objects: at most 2^30");
        let mut axes = [(); 3].map(|_| Vec::with_capacity(2 * n));
        for id in 0..n as u32 {
            events::push_box(&mut axes, id, &shapes.bounds(id));
        }
        sort_lists(&mut axes, threads);
        EventLists { axes, count: n }
    }

    /// The object ids, ascending.
    fn ids(&self) -> Vec<u32> {
        let mut ids: Vec<u32> = self.axes[0]
            .iter()
            .filter(|&&e| events::kind(e) != END)
            .map(|&e| events::id(e))
            .collect();
        ids.sort_unstable();
        ids
    }
}

/// The best plane found by the sweep.
#[derive(Debug, Clone, Copy)]
struct Split {
    axis: usize,
    position: f32,
    cost: f32,
    below: usize,
    above: usize,
}

/// Where each object of the node goes; indexed by object id.
const BELOW: u8 = 1;
const ABOVE: u8 = 2;
const BOTH: u8 = 3;

pub struct Sah<'a> {
    pub shapes: Shapes<'a>,
    pub params: BuildParams,
}

impl Sah<'_> {
    /// The cheapest plane strictly inside the cell over all three axes,
    /// among the positions of the events; ties go to the first found (x
    /// before y before z, lower before higher), which keeps the tree the
    /// same on any thread count.
    #[allow(clippy::neg_cmp_op_on_partial_ord)] // NaN counts as not positive
    fn best_split(&self, lists: &EventLists, cell: &Aabb) -> Option<Split> {
        let n = lists.count;
        let area = cell.surface_area();
        if !(area > 0.0) {
            return None;
        }
        let inv_area = 1.0 / area;
        let p = &self.params;
        let mut best: Option<Split> = None;
        for (a, list) in lists.axes.iter().enumerate() {
            let (lo, hi) = (cell.min[a], cell.max[a]);
            if !(hi > lo) {
                continue;
            }
            // Objects whose start, end or planar event lies before the
            // current position.
            let (mut starts, mut ends, mut planars) = (0usize, 0usize, 0usize);
            let mut i = 0;
            while i < list.len() {
                let k = events::position_key(list[i]);
                let (mut s, mut e, mut pl) = (0, 0, 0);
                while i < list.len() && events::position_key(list[i]) == k {
                    match events::kind(list[i]) {
                        END => e += 1,
                        PLANAR => pl += 1,
                        _ => s += 1,
                    }
                    i += 1;
                }
                let x = events::value(k);
                // min <= x, and max > x or flat at x.
                let below = starts + s + planars + pl;
                let above = n - ends - e - planars;
                starts += s;
                ends += e;
                planars += pl;
                if !(lo < x && x < hi) {
                    continue;
                }
                let mut below_cell = *cell;
                below_cell.max[a] = x;
                let mut above_cell = *cell;
                above_cell.min[a] = x;
                let p_below = below_cell.surface_area() * inv_area;
                let p_above = above_cell.surface_area() * inv_area;
                let bonus = if below == 0 || above == 0 {
                    p.empty_bonus
                } else {
                    1.0
                };
                let cost = p.traversal_cost
                    + bonus
                        * p.intersection_cost
                        * (p_below * below as f32 + p_above * above as f32);
                if best.is_none_or(|b| cost < b.cost) {
                    best = Some(Split {
                        axis: a,
                        position: x,
                        cost,
                        below,
                        above,
                    });
                }
            }
        }
        best
    }

    /// Splits the node's lists at `split`: objects wholly on one side keep
    /// their events; those on both sides are clipped again to each child's
    /// cell (and dropped from a child they turn out not to reach).
    fn partition(
        &self,
        lists: EventLists,
        split: &Split,
        cell: &Aabb,
        side: &mut Vec<u8>,
    ) -> (EventLists, EventLists) {
        let (a, p, eps) = (split.axis, split.position, self.shapes.tolerance());
        if side.len() < self.shapes.len() {
            side.resize(self.shapes.len(), 0);
        }
        let on_axis = &lists.axes[a];
        for &e in on_axis {
            if events::kind(e) != END {
                side[events::id(e) as usize] = BOTH;
            }
        }
        // An end event is the object's max, a start its min, a planar both.
        for &e in on_axis {
            let x = events::value(events::position_key(e));
            let id = events::id(e) as usize;
            let (below, above) = match events::kind(e) {
                END => sides(f32::NEG_INFINITY, x, p, eps),
                START => sides(x, f32::INFINITY, p, eps),
                _ => sides(x, x, p, eps),
            };
            if !above {
                side[id] = BELOW;
            } else if !below {
                side[id] = ABOVE;
            }
        }
        let straddling: Vec<u32> = on_axis
            .iter()
            .filter(|&&e| events::kind(e) != END && side[events::id(e) as usize] == BOTH)
            .map(|&e| events::id(e))
            .collect();

        let mut below_cell = *cell;
        below_cell.max[a] = split.position;
        let mut above_cell = *cell;
        above_cell.min[a] = split.position;
        let mut new_below: [Vec<u64>; 3] = Default::default();
        let mut new_above: [Vec<u64>; 3] = Default::default();
        let (mut n_below, mut n_above) = (0, 0);
        for &id in &straddling {
            if let Some(b) = self.shapes.clip(id, &below_cell) {
                events::push_box(&mut new_below, id, &b);
                n_below += 1;
            }
            if let Some(b) = self.shapes.clip(id, &above_cell) {
                events::push_box(&mut new_above, id, &b);
                n_above += 1;
            }
        }
        let only_below = on_axis
            .iter()
            .filter(|&&e| events::kind(e) != END && side[events::id(e) as usize] == BELOW)
            .count();
        let only_above = on_axis
            .iter()
            .filter(|&&e| events::kind(e) != END && side[events::id(e) as usize] == ABOVE)
            .count();
        let [lx, ly, lz] = lists.axes;
        let mut below_axes: [Vec<u64>; 3] = Default::default();
        let mut above_axes: [Vec<u64>; 3] = Default::default();
        for (axis, list) in [lx, ly, lz].into_iter().enumerate() {
            let mut below = Vec::with_capacity(2 * only_below + new_below[axis].len());
            let mut above = Vec::with_capacity(2 * only_above + new_above[axis].len());
            for &e in &list {
                match side[events::id(e) as usize] {
                    BELOW => below.push(e),
                    ABOVE => above.push(e),
                    _ => {}
                }
            }
            drop(list);
            let mut nb = std::mem::take(&mut new_below[axis]);
            let mut na = std::mem::take(&mut new_above[axis]);
            nb.sort_unstable();
            na.sort_unstable();
            below_axes[axis] = events::merge(below, nb);
            above_axes[axis] = events::merge(above, na);
        }
        (
            EventLists {
                axes: below_axes,
                count: only_below + n_below,
            },
            EventLists {
                axes: above_axes,
                count: only_above + n_above,
            },
        )
    }
}

impl Strategy for Sah<'_> {
    type Objects = EventLists;
    /// Which side each object goes to, indexed by id (one per thread).
    type Scratch = Vec<u8>;

    fn scratch(&self) -> Vec<u8> {
        Vec::new()
    }

    fn count(objects: &EventLists) -> usize {
        objects.count
    }

    fn leaf_ids(objects: EventLists) -> Vec<u32> {
        objects.ids()
    }

    /// A leaf when the node holds at most one object, at the depth limit,
    /// when no plane is cheaper than testing every object, or when the best
    /// plane would not separate anything.
    fn split(
        &self,
        lists: EventLists,
        cell: &Aabb,
        depth: u32,
        side: &mut Vec<u8>,
    ) -> Decision<EventLists> {
        let n = lists.count;
        if n <= 1 || depth >= self.params.max_depth {
            return Decision::Leaf(lists);
        }
        let leaf_cost = self.params.intersection_cost * n as f32;
        match self.best_split(&lists, cell) {
            Some(s) if s.cost < leaf_cost && !(s.below == n && s.above == n) => {
                let (below, above) = self.partition(lists, &s, cell, side);
                if below.count == n && above.count == n {
                    // Everything came within ε of the plane: no progress.
                    return Decision::Leaf(below);
                }
                Decision::Split {
                    axis: s.axis,
                    position: s.position,
                    below,
                    above,
                }
            }
            _ => Decision::Leaf(lists),
        }
    }
}
