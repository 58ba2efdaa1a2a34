//! The surface area heuristic with perfect splits in O(N log N) (Wald &
//! Havran 2006): each node holds, per axis, the sorted events of its
//! objects' clipped boxes ([`super::events::EventLists`], which also splits
//! them between the children). The best plane is one sweep over the three
//! lists; big nodes are split by binning first ([`super::binned`]), small
//! ones from their boxes ([`super::few`]).
//!
//! Classification is [`super::clip::sides`]: against a plane at `p`, an
//! object goes below when its clipped `min <= p + ε`, above when
//! `max >= p - ε`. The sweep counts objects at a candidate's exact position
//! as touching it (both sides) and ignores ε otherwise (a cost estimate).

use crate::geometry::Aabb;

use super::binned::{self, ClippedBox};
use super::build_params::BuildParams;
use super::clip::{clear_above, clear_below, Shapes};
use super::events::{self, EventLists, END, PLANAR};
use super::few::{self, FEW};
use super::split::{gap_may_beat, inverse_area, AxisCost, Split};
use super::strategy::{Decision, Strategy};

/// Nodes of this many objects or more have their three lists partitioned
/// in parallel when the build has threads: the root of the 1.1 M-triangle
/// bunny took 81 ms to partition on one thread, while the other waited.
const PARALLEL_PARTITION_OBJECTS: usize = 1 << 16;

/// The SAH build's strategy over a scene's shapes.
pub struct Sah<'a> {
    shapes: Shapes<'a>,
    params: BuildParams,
    /// How far a gap plane keeps from the positions it lies between: ε of
    /// the scene's magnitude (`clip::TOLERANCE`) even for exact boxes,
    /// whose classification has none. A hit test rounds a few ulps of
    /// the coordinates beyond its object, so a plane nearer than that could
    /// put a reported hit in a cell that does not hold its object (a
    /// proptest found one with planes one ulp from the faces).
    gap: f32,
    /// Nodes of more objects are binned ([`BuildParams::binned_above`]).
    binned_above: usize,
}

impl<'a> Sah<'a> {
    /// The strategy for `shapes`, whose union is `root`.
    pub fn new(shapes: Shapes<'a>, params: BuildParams, root: &Aabb) -> Self {
        let magnitude = root.magnitude();
        let gap = shapes.tolerance().max(magnitude * super::clip::TOLERANCE);
        Sah {
            shapes,
            params,
            gap: if gap.is_finite() { gap } else { 0.0 },
            binned_above: params.binned_above(shapes.len()),
        }
    }
}

impl Sah<'_> {
    /// The cheapest plane strictly inside the cell over all three axes.
    /// The candidates on an axis are each event position x, where the
    /// objects that start, end or lie at x touch the plane and so go to
    /// both children ([`sides`]), and in each gap between neighbouring
    /// positions the two planes nearest its ends that touch nothing
    /// ([`clear_above`], [`clear_below`]), where the same objects go to one
    /// side only. In a mesh every vertex plane touches the triangles around
    /// the vertex; without the gap planes each split copied them into both
    /// children (2.3x the references of a one-side rule on the subdivided
    /// bunny, docs/design.md). Ties go to the first found (x before y
    /// before z, lower before higher), which keeps the tree the same on any
    /// thread count. Gaps that cannot beat the best so far are passed over
    /// ([`gap_may_beat`]), which a test holds to the full sweep's plane.
    fn best_split(&self, axes: [&[u64]; 3], n: usize, cell: &Aabb) -> Option<Split> {
        self.sweep(axes, n, cell, true)
    }

    /// [`Sah::best_split`], with or without passing over the gaps that
    /// cannot beat the best.
    #[allow(clippy::neg_cmp_op_on_partial_ord)] // NaN counts as not positive
    fn sweep(&self, axes: [&[u64]; 3], n: usize, cell: &Aabb, skip_gaps: bool) -> Option<Split> {
        let inv_area = inverse_area(cell)?;
        let gap = self.gap;
        let mut best: Option<Split> = None;
        for (a, list) in axes.into_iter().enumerate() {
            let (lo, hi) = (cell.min[a], cell.max[a]);
            if !(hi > lo) {
                continue;
            }
            let cost = AxisCost::new(&self.params, cell, a, inv_area);
            let consider = |best: &mut Option<Split>, x, below, above| {
                cost.keep_cheaper(best, x, below, above)
            };
            // Over the positions before the current one: objects whose
            // start, end or planar event lies there.
            let (mut starts, mut ends, mut planars) = (0usize, 0usize, 0usize);
            let mut previous: Option<f32> = None;
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
                // The gap before x: below, the objects with min before it;
                // above, those with max after it.
                let (gap_below, gap_above) = (starts + planars, n - ends - planars);
                match previous {
                    None => consider(&mut best, clear_below(x, gap), gap_below, gap_above),
                    // The cost is linear in the gap, so at least its
                    // value at one end: a gap that cannot beat the best
                    // is passed over without placing its planes.
                    Some(xp)
                        if skip_gaps
                            && !gap_may_beat(&best, &cost, xp, x, gap_below, gap_above) => {}
                    Some(xp) => {
                        let (gap_low, gap_high) = (clear_above(xp, gap), clear_below(x, gap));
                        // With the counts fixed, the cost is linear in the
                        // position, rising when more objects are below: only
                        // one end of the gap can be cheapest (both on a tie).
                        if gap_low <= gap_high {
                            if gap_below >= gap_above {
                                consider(&mut best, gap_low, gap_below, gap_above);
                            }
                            if gap_below <= gap_above {
                                consider(&mut best, gap_high, gap_below, gap_above);
                            }
                        }
                    }
                }
                // At x: min <= x below, max >= x above.
                consider(&mut best, x, starts + s + planars + pl, n - ends - planars);
                starts += s;
                ends += e;
                planars += pl;
                previous = Some(x);
            }
            if let Some(xp) = previous {
                consider(
                    &mut best,
                    clear_above(xp, gap),
                    starts + planars,
                    n - ends - planars,
                );
            }
        }
        best
    }
}

/// A node's objects: their clipped boxes while the node is split by
/// binning ([`binned`]), their sorted events once the exact sweep takes over.
#[derive(Debug)]
pub enum SahObjects {
    Boxes(Vec<ClippedBox>),
    Events(EventLists),
}

impl Sah<'_> {
    /// The root's objects: boxes when the scene is big enough to bin (made
    /// on the build's threads with `parallel`), else sorted events
    /// (`threads` sort the three lists).
    pub fn root(&self, threads: usize, parallel: bool) -> SahObjects {
        if self.shapes.len() > self.binned_above {
            let root_box = |id| ClippedBox {
                id,
                bounds: self.shapes.bounds(id),
            };
            let ids = 0..self.shapes.len() as u32;
            let mut boxes = crate::huge_pages::with_capacity(ids.len());
            if parallel {
                use rayon::prelude::*;
                boxes.par_extend(ids.into_par_iter().map(root_box));
            } else {
                boxes.extend(ids.map(root_box));
            }
            SahObjects::Boxes(boxes)
        } else {
            SahObjects::Events(EventLists::root(&self.shapes, threads))
        }
    }

    /// Whether every plane costs at least as much as testing the node's
    /// `n` objects, so that the node is a leaf without a sweep. A plane's
    /// cost is at least `T + bonus I flat n`: each object goes to one child
    /// or both, and a child's share of the cell's area is at least `flat`,
    /// the share of the cell's cross-section ([`AxisCost`]). With a
    /// sphere's cost (T = 2 I), nodes of two objects never split; about half
    /// of all nodes are leaves, and their sweeps found nothing. (A triangle
    /// test costs up to 80, twice T (`triangle_test_cost`), so in small
    /// meshes nodes of two triangles may split.)
    fn no_plane_can_pay(&self, n: usize, cell: &Aabb) -> bool {
        let e = (cell.max - cell.min).max(glam::Vec3::ZERO);
        let smallest_cross_section = (e.y * e.z).min(e.z * e.x).min(e.x * e.y);
        let flat = 2.0 * smallest_cross_section / cell.surface_area();
        let p = &self.params;
        let bound =
            p.traversal_cost + p.empty_bonus.min(1.0) * p.intersection_cost * flat * n as f32;
        // The margin covers the sweep's f32 rounding of the same terms.
        bound * (1.0 - 1e-5) >= p.intersection_cost * n as f32
    }

    /// The exact sweep's decision (Wald & Havran 2006); with `parallel`, a
    /// big node's three lists are partitioned on the build's threads.
    fn split_events(
        &self,
        lists: EventLists,
        cell: &Aabb,
        parallel: bool,
        side: &mut Vec<u8>,
    ) -> Decision<SahObjects> {
        let n = lists.count;
        let leaf_cost = self.params.intersection_cost * n as f32;
        let axes = [0, 1, 2].map(|a| lists.axes[a].as_slice());
        match self.best_split(axes, n, cell) {
            Some(s) if s.cost < leaf_cost && !(s.below == n && s.above == n) => {
                let parallel = parallel && n >= PARALLEL_PARTITION_OBJECTS;
                let (below, above) =
                    lists.partition(&self.shapes, (s.axis, s.position), cell, parallel, side);
                if below.count == n && above.count == n {
                    // Everything came within ε of the plane: no progress.
                    return Decision::Leaf(SahObjects::Events(below));
                }
                Decision::Split {
                    axis: s.axis,
                    position: s.position,
                    below: SahObjects::Events(below),
                    above: SahObjects::Events(above),
                }
            }
            _ => Decision::Leaf(SahObjects::Events(lists)),
        }
    }

    /// The exact decision for a node of at most [`FEW`] objects: the plane
    /// [`Sah::split_events`] would choose ([`few::cheapest_paying_split`]
    /// for up to [`few::MAX_OBJECTS`] finite boxes, else
    /// [`Sah::sorted_few_split`]), and the boxes partitioned as the binned
    /// build partitions them (the same children).
    fn split_few(&self, boxes: Vec<ClippedBox>, cell: &Aabb) -> Decision<SahObjects> {
        debug_assert!(boxes.len() <= FEW);
        let searchable = boxes.len() <= few::MAX_OBJECTS
            && boxes
                .iter()
                .all(|b| b.bounds.min.is_finite() && b.bounds.max.is_finite());
        let best = if searchable {
            few::cheapest_paying_split(&boxes, cell, &self.params, self.gap)
        } else {
            self.sorted_few_split(&boxes, cell)
        };
        self.split_boxes_at(boxes, best, cell, |boxes| {
            Decision::Leaf(SahObjects::Boxes(boxes))
        })
    }

    /// The best plane for at most [`FEW`] boxes by the sorted sweep: the
    /// events of their boxes sorted on the stack and swept as
    /// [`Sah::split_events`] sweeps its lists (the same events in the same
    /// order, so the same plane).
    fn sorted_few_split(&self, boxes: &[ClippedBox], cell: &Aabb) -> Option<Split> {
        let mut events = [[0u64; 2 * FEW]; 3];
        let mut lens = [0usize; 3];
        for b in boxes {
            events::for_each_event(b.id, &b.bounds, |a, e| {
                events[a][lens[a]] = e;
                lens[a] += 1;
            });
        }
        for (list, &len) in events.iter_mut().zip(&lens) {
            list[..len].sort_unstable();
        }
        let sorted = [0, 1, 2].map(|a| &events[a][..lens[a]]);
        self.best_split(sorted, boxes.len(), cell)
    }

    /// The full sweep's plane for `boxes`: every gap costed, none passed
    /// over (the reference the tests hold the shortcuts to).
    #[cfg(test)]
    fn full_sweep(&self, boxes: &[ClippedBox], cell: &Aabb) -> Option<Split> {
        let lists = EventLists::from_boxes(boxes);
        let axes = [0, 1, 2].map(|a| lists.axes[a].as_slice());
        self.sweep(axes, boxes.len(), cell, false)
    }

    /// Splits `boxes` at `split` when it pays (it costs less than a leaf
    /// and does not put every object in both children), else leaves them
    /// to `otherwise`. A leaf, too, when clipping put every object in both.
    fn split_boxes_at(
        &self,
        boxes: Vec<ClippedBox>,
        split: Option<Split>,
        cell: &Aabb,
        otherwise: impl FnOnce(Vec<ClippedBox>) -> Decision<SahObjects>,
    ) -> Decision<SahObjects> {
        let n = boxes.len();
        let leaf_cost = self.params.intersection_cost * n as f32;
        match split {
            Some(s) if s.cost < leaf_cost && !(s.below == n && s.above == n) => {
                let (below, above) = binned::partition(boxes, &s, cell, &self.shapes);
                if below.len() == n && above.len() == n {
                    return Decision::Leaf(SahObjects::Boxes(below));
                }
                Decision::Split {
                    axis: s.axis,
                    position: s.position,
                    below: SahObjects::Boxes(below),
                    above: SahObjects::Boxes(above),
                }
            }
            _ => otherwise(boxes),
        }
    }

    /// The exact decision over a node's boxes.
    fn split_exact(
        &self,
        boxes: Vec<ClippedBox>,
        cell: &Aabb,
        side: &mut Vec<u8>,
    ) -> Decision<SahObjects> {
        if boxes.len() <= FEW {
            self.split_few(boxes, cell)
        } else {
            self.split_events(EventLists::from_boxes(&boxes), cell, false, side)
        }
    }

    /// The binned decision; when binning finds no plane worth taking, the
    /// exact sweep looks at every event before the node becomes a leaf.
    fn split_boxes(
        &self,
        boxes: Vec<ClippedBox>,
        cell: &Aabb,
        parallel: bool,
        side: &mut Vec<u8>,
    ) -> Decision<SahObjects> {
        let best = binned::best_split(&boxes, cell, &self.params, self.gap, parallel);
        self.split_boxes_at(boxes, best, cell, |boxes| {
            self.split_exact(boxes, cell, side)
        })
    }
}

impl Strategy for Sah<'_> {
    type Objects = SahObjects;
    /// Which side each object goes to, indexed by id (one per thread).
    type Scratch = Vec<u8>;

    fn scratch(&self) -> Vec<u8> {
        Vec::new()
    }

    fn count(objects: &SahObjects) -> usize {
        match objects {
            SahObjects::Boxes(boxes) => boxes.len(),
            SahObjects::Events(lists) => lists.count,
        }
    }

    fn leaf_ids(objects: SahObjects, out: &mut Vec<u32>) {
        let first = out.len();
        match objects {
            SahObjects::Boxes(boxes) => out.extend(boxes.iter().map(|b| b.id)),
            SahObjects::Events(lists) => out.extend(lists.unsorted_ids()),
        }
        out[first..].sort_unstable();
    }

    /// A leaf when the node holds at most one object, at the depth limit,
    /// when no plane is cheaper than testing every object, or when the best
    /// plane would not separate anything. Nodes of more than
    /// `binned_above` objects are split by binning, the others by the exact
    /// sweep.
    fn split(
        &self,
        objects: SahObjects,
        cell: &Aabb,
        depth: u32,
        parallel: bool,
        side: &mut Vec<u8>,
    ) -> Decision<SahObjects> {
        let n = Self::count(&objects);
        if n <= 1 || depth >= self.params.max_depth || self.no_plane_can_pay(n, cell) {
            return Decision::Leaf(objects);
        }
        match objects {
            SahObjects::Boxes(boxes) if n > self.binned_above => {
                self.split_boxes(boxes, cell, parallel, side)
            }
            SahObjects::Boxes(boxes) => self.split_exact(boxes, cell, side),
            SahObjects::Events(lists) if n <= FEW => self.split_few(lists.into_boxes(), cell),
            SahObjects::Events(lists) => self.split_events(lists, cell, parallel, side),
        }
    }
}

#[cfg(test)]
mod shortcut_tests;
