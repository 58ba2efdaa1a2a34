//! The binned surface area heuristic, for the nodes of the SAH build that
//! hold many objects (Wald 2007 for BVHs; Shevtsov, Soupikov and Kapustin
//! 2007 and Zhou et al. 2008 for k-d trees): the objects' clipped boxes are
//! counted into [`BINS`] equal bins per axis and the heuristic is evaluated
//! at the bins' boundaries only. That is O(n) per node with no sorted event
//! lists to keep, where the exact sweep ([`super::sah`]) splits and merges
//! six events per object at every level. Near the top of the tree, where
//! nodes are big, 32 candidates per axis find planes about as good as every
//! event does; below `BuildParams::exact_below` objects the exact sweep
//! takes over (docs/design.md has the measurements).
//!
//! Partition is the exact build's: [`super::clip::sides`] with ε, and the
//! objects straddling the plane clipped again to each child's cell.

use glam::Vec3A;

use crate::geometry::Aabb;

use super::build_params::BuildParams;
use super::clip::{clear_above, clear_below, sides, Shapes};
use super::split::{inverse_area, AxisCost, Split};

/// Bins per axis.
pub const BINS: usize = 32;

/// An object of a node and the box of its part in the node's cell.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClippedBox {
    pub id: u32,
    pub bounds: Aabb,
}

/// The cheapest plane strictly inside the cell over all three axes (ties:
/// the first found, x before y before z, lower before higher), or `None`
/// for a flat cell. The bins span the objects' extent in the cell, not the
/// cell, and the two planes just outside that extent (`gap` away, like the
/// exact sweep's gap planes) are candidates too: they cut off the empty
/// space around the objects, which bins over the whole cell blur (measured
/// on the bunny: 28% more nodes visited a ray without them). Each boundary
/// is moved to the nearest object face on the side its cost favours (per
/// bin, the lowest start and highest end are kept): the tree costs within
/// 1% of the exact sweep's by the heuristic, where plain boundaries cost
/// up to 17% more (docs/design.md). Counts are estimates: an object goes
/// below a boundary when its box starts in a lower bin, above when it ends
/// in the boundary's bin or a higher one. With `parallel` (the caller is a
/// worker of the build's pool) a big node's boxes are counted in halves on
/// two threads (`in_halves`); the plane is the same either way.
#[allow(clippy::neg_cmp_op_on_partial_ord)] // NaN counts as not positive
pub fn best_split(
    boxes: &[ClippedBox],
    cell: &Aabb,
    params: &BuildParams,
    gap: f32,
    parallel: bool,
) -> Option<Split> {
    let n = boxes.len();
    let inv_area = inverse_area(cell)?;
    let extent = in_halves(boxes, parallel, extent_of, Aabb::union);
    let lo = [0, 1, 2].map(|a| extent.min[a].max(cell.min[a]));
    let hi = [0, 1, 2].map(|a| extent.max[a].min(cell.max[a]));
    let width = [0, 1, 2].map(|a| hi[a] - lo[a]);
    let binnable = [0, 1, 2].map(|a| width[a] > 0.0 && width[a].is_finite());
    let scale = [0, 1, 2].map(|a| {
        if binnable[a] {
            BINS as f32 / width[a]
        } else {
            0.0
        }
    });
    let (lo3, scale3) = (Vec3A::from_array(lo), Vec3A::from_array(scale));
    let Bins {
        starts,
        ends,
        first_start,
        last_end,
    } = in_halves(
        boxes,
        parallel,
        |b| Bins::count(b, lo3, scale3),
        Bins::merge,
    );
    let mut best: Option<Split> = None;
    for a in 0..3 {
        let cost = AxisCost::new(params, cell, a, inv_area);
        let mut consider = |x, below, above| cost.keep_cheaper(&mut best, x, below, above);
        let (lo, hi, width) = (lo[a], hi[a], width[a]);
        consider(clear_below(lo, gap), 0, n);
        if !binnable[a] {
            consider(clear_above(hi, gap), n, 0);
            continue;
        }
        let (starts, ends) = (&starts[a], &ends[a]);
        // The lowest start in bin i or above.
        let mut start_above = first_start[a];
        for i in (0..BINS - 1).rev() {
            start_above[i] = start_above[i].min(start_above[i + 1]);
        }
        let (mut below, mut above) = (0, n);
        let mut end_below = f32::NEG_INFINITY;
        for i in 1..BINS {
            below += starts[i - 1] as usize;
            above -= ends[i - 1] as usize;
            end_below = end_below.max(last_end[a][i - 1]);
            let x = lo + width * (i as f32 / BINS as f32);
            if !(lo < x && x < hi) {
                continue;
            }
            // The boundary moved down to just above every object ending
            // below it, or up to just below every object starting above
            // it: the empty space between them is cut away, which the
            // boundary alone blurs (the torus's tree cost 17% more without).
            // With these counts (at most the true ones) the cost is linear
            // in the position, so only the end its slope favours can win.
            let snapped = if below >= above {
                clear_above(end_below, gap)
            } else {
                clear_below(start_above[i], gap)
            };
            if snapped.is_finite() && (snapped < x) == (below >= above) {
                consider(snapped, below, above);
            } else {
                consider(x, below, above);
            }
        }
        consider(clear_above(hi, gap), n, 0);
    }
    best
}

/// Nodes of this many objects or more are binned in two halves, on two
/// threads when the build has them, and the halves merged: the 1.1 M
/// bunny's root took 33 ms on one thread while the other waited.
const HALVES_OBJECTS: usize = 1 << 16;

/// `f` of all `boxes`: for a node of [`HALVES_OBJECTS`] or more, `merge`
/// of `f` of each half (on two threads with `parallel`, the same halves
/// either way, so the result does not depend on the threads).
fn in_halves<T: Send>(
    boxes: &[ClippedBox],
    parallel: bool,
    f: impl Fn(&[ClippedBox]) -> T + Sync,
    merge: impl FnOnce(T, T) -> T,
) -> T {
    if boxes.len() < HALVES_OBJECTS {
        return f(boxes);
    }
    let (lower, upper) = boxes.split_at(boxes.len() / 2);
    let (a, b) = if parallel {
        rayon::join(|| f(lower), || f(upper))
    } else {
        (f(lower), f(upper))
    };
    merge(a, b)
}

/// The union of the boxes' bounds.
fn extent_of(boxes: &[ClippedBox]) -> Aabb {
    boxes.iter().fold(Aabb::EMPTY, |e, b| e.union(b.bounds))
}

/// A node's boxes counted into the bins of each axis.
struct Bins {
    /// Boxes whose min falls in each bin.
    starts: [[u32; BINS]; 3],
    /// Boxes whose max falls in each bin.
    ends: [[u32; BINS]; 3],
    /// Per bin, the lowest min in it.
    first_start: [[f32; BINS]; 3],
    /// Per bin, the highest max in it.
    last_end: [[f32; BINS]; 3],
}

impl Bins {
    /// The boxes counted into bins starting at `lo`, `scale` bins a unit.
    /// One pass fills the six histograms: their increments are independent
    /// (per axis, one after another, neighbouring boxes of a mesh often
    /// fall in one bin and wait on each other's count; two sets of
    /// histograms for alternate boxes were no faster). The clamp in
    /// `bins_of` puts boxes reaching ε past the cell in the end bins.
    fn count(boxes: &[ClippedBox], lo: Vec3A, scale: Vec3A) -> Bins {
        let mut bins = Bins {
            starts: [[0; BINS]; 3],
            ends: [[0; BINS]; 3],
            first_start: [[f32::INFINITY; BINS]; 3],
            last_end: [[f32::NEG_INFINITY; BINS]; 3],
        };
        for b in boxes {
            let start_bins = bins_of(b.bounds.min, lo, scale);
            let end_bins = bins_of(b.bounds.max, lo, scale);
            for a in 0..3 {
                let (min, max) = (b.bounds.min[a], b.bounds.max[a]);
                let (s, e) = (start_bins[a], end_bins[a]);
                bins.starts[a][s] += 1;
                bins.ends[a][e] += 1;
                // Plain compares (a NaN bound keeps what is there) rather
                // than f32::min and max, whose NaN handling doubles the work.
                let (first, last) = (bins.first_start[a][s], bins.last_end[a][e]);
                bins.first_start[a][s] = if min < first { min } else { first };
                bins.last_end[a][e] = if max > last { max } else { last };
            }
        }
        bins
    }

    /// The bins of the lower boxes and then the upper ones: on a tie the
    /// lower's bound stays, as one pass over all of them keeps the first.
    fn merge(mut self, upper: Bins) -> Bins {
        for a in 0..3 {
            for i in 0..BINS {
                self.starts[a][i] += upper.starts[a][i];
                self.ends[a][i] += upper.ends[a][i];
                let (first, last) = (upper.first_start[a][i], upper.last_end[a][i]);
                if first < self.first_start[a][i] {
                    self.first_start[a][i] = first;
                }
                if last > self.last_end[a][i] {
                    self.last_end[a][i] = last;
                }
            }
        }
        self
    }
}

/// The bins of a box's three mins, or maxes, at once, for bins starting at
/// `lo` and `scale` bins a unit: `((x - lo) * scale) as usize` clamped to
/// the last bin, as the saturating cast does it (below 0 and NaN to bin
/// 0), with the float clamped first in four lanes. The line of the three
/// casts was 4.7% of the profile of the 1.1 M bunny's binned build; the
/// lanes took 1.7% off its CPU time, and converting through i32 2.5% more
/// (three rounds alternating).
#[inline(always)]
fn bins_of(x: glam::Vec3, lo: Vec3A, scale: Vec3A) -> [usize; 3] {
    let last = Vec3A::splat((BINS - 1) as f32);
    // SSE's max gives its second operand for a NaN: 0, as the cast does.
    // Through i32, exact in [0, 31], where a cast to usize saturates in
    // more instructions.
    let f = ((Vec3A::from(x) - lo) * scale).max(Vec3A::ZERO).min(last);
    [
        f.x as i32 as usize,
        f.y as i32 as usize,
        f.z as i32 as usize,
    ]
}

/// The children's boxes for the plane of `split`: an object wholly on one
/// side keeps its box; one on both sides (within `eps`) is clipped again to
/// each child's cell and left out of a child it turns out not to reach.
/// Order is kept, so the tree does not depend on threads. The split's
/// counts size the children (estimates: a few more objects may come within
/// ε of the plane).
pub fn partition(
    boxes: Vec<ClippedBox>,
    split: &Split,
    cell: &Aabb,
    shapes: &Shapes<'_>,
) -> (Vec<ClippedBox>, Vec<ClippedBox>) {
    let router = Router::new(split, cell, shapes);
    if boxes.len() <= IN_PLACE {
        partition_in_place(boxes, split, &router)
    } else {
        partition_fresh(boxes, split, &router)
    }
}

/// Nodes of at most this many objects ([`super::few::FEW`] and some more)
/// give their vector to the lower child: one allocation fewer per split,
/// where most splits are (the bunny's binned build, one thread: 1.5% less
/// CPU). A bigger node's child would keep the parent's capacity.
const IN_PLACE: usize = 64;

/// Where a node's boxes go against its split plane: a box wholly on one
/// side keeps its box; one on both (within ε), or a NaN box, is clipped
/// again to each child's reach and left out of a child it turns out not to
/// reach.
struct Router<'a, 's> {
    axis: usize,
    position: f32,
    eps: f32,
    below_reach: Aabb,
    above_reach: Aabb,
    shapes: &'a Shapes<'s>,
}

impl<'a, 's> Router<'a, 's> {
    fn new(split: &Split, cell: &Aabb, shapes: &'a Shapes<'s>) -> Self {
        let mut below_cell = *cell;
        below_cell.max[split.axis] = split.position;
        let mut above_cell = *cell;
        above_cell.min[split.axis] = split.position;
        Router {
            axis: split.axis,
            position: split.position,
            eps: shapes.tolerance(),
            below_reach: shapes.reach(&below_cell),
            above_reach: shapes.reach(&above_cell),
            shapes,
        }
    }

    /// Box `b`'s part in the lower and in the upper child.
    #[inline(always)]
    fn route(&self, b: ClippedBox) -> (Option<ClippedBox>, Option<ClippedBox>) {
        let (min, max) = (b.bounds.min[self.axis], b.bounds.max[self.axis]);
        match sides(min, max, self.position, self.eps) {
            (true, false) => (Some(b), None),
            (false, true) => (None, Some(b)),
            _ => {
                let (below, above) =
                    self.shapes
                        .clip_across(b.id, self.axis, &self.below_reach, &self.above_reach);
                let boxed = |bounds| ClippedBox { id: b.id, bounds };
                (below.map(boxed), above.map(boxed))
            }
        }
    }
}

/// Room for a child of about `count` boxes out of `n`.
fn room(count: usize, n: usize) -> usize {
    (count + count / 16 + 4).min(n)
}

/// [`partition`] into two new vectors.
fn partition_fresh(boxes: Vec<ClippedBox>, split: &Split, router: &Router) -> Children {
    let mut below = crate::huge_pages::with_capacity(room(split.below, boxes.len()));
    let mut above = crate::huge_pages::with_capacity(room(split.above, boxes.len()));
    for b in boxes {
        let (lower, upper) = router.route(b);
        below.extend(lower);
        above.extend(upper);
    }
    (below, above)
}

/// [`partition`], writing the lower child over `boxes`: each box gives
/// that child at most one box, so the write never passes the read.
fn partition_in_place(mut boxes: Vec<ClippedBox>, split: &Split, router: &Router) -> Children {
    let mut above = Vec::with_capacity(room(split.above, boxes.len()));
    let mut kept = 0;
    for i in 0..boxes.len() {
        let (lower, upper) = router.route(boxes[i]);
        above.extend(upper);
        if let Some(lower) = lower {
            boxes[kept] = lower;
            kept += 1;
        }
    }
    boxes.truncate(kept);
    (boxes, above)
}

/// The boxes of a split's lower and upper child.
type Children = (Vec<ClippedBox>, Vec<ClippedBox>);

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    fn unit_box(id: u32, x: f32) -> ClippedBox {
        ClippedBox {
            id,
            bounds: Aabb {
                min: Vec3::new(x, 0.0, 0.0),
                max: Vec3::new(x + 1.0, 1.0, 1.0),
            },
        }
    }

    /// The binned plane of eight boxes, on one thread.
    fn split_of_eight(boxes: &[ClippedBox], cell: &Aabb, gap: f32) -> Split {
        best_split(boxes, cell, &BuildParams::for_object_count(8), gap, false).expect("a split")
    }

    /// Two clusters of unit boxes on x, [0, 4] and [12, 16], in the cell
    /// [0, 16]: the best boundary lies in the empty stretch between them
    /// and counts each cluster on its side only.
    #[test]
    fn the_best_boundary_separates_two_clusters() {
        let boxes: Vec<_> = (0..4)
            .map(|i| unit_box(i, i as f32))
            .chain((4..8).map(|i| unit_box(i, 8.0 + i as f32)))
            .collect();
        let cell = Aabb {
            min: Vec3::ZERO,
            max: Vec3::new(16.0, 1.0, 1.0),
        };
        let s = split_of_eight(&boxes, &cell, 1e-5);
        assert_eq!(s.axis, 0);
        assert!((4.0..=12.0).contains(&s.position), "{}", s.position);
        assert_eq!((s.below, s.above), (4, 4));
    }

    /// A gap between clusters that does not end at a bin boundary: the
    /// plane snaps to just past the bigger cluster's faces, cutting away all
    /// the empty space, not to the first boundary inside the gap.
    #[test]
    fn the_plane_snaps_to_the_edge_of_the_empty_space() {
        let thin = |id, x0: f32, x1: f32| ClippedBox {
            id,
            bounds: Aabb {
                min: Vec3::new(x0, 0.0, 0.0),
                max: Vec3::new(x1, 1.0, 1.0),
            },
        };
        // Bins of width 1 over [0, 32]; the gap is (5.3, 26.7).
        let boxes: Vec<_> = (0..6)
            .map(|i| thin(i, 0.0, 5.3))
            .chain([thin(6, 26.7, 32.0), thin(7, 26.7, 32.0)])
            .collect();
        let cell = Aabb {
            min: Vec3::ZERO,
            max: Vec3::new(32.0, 1.0, 1.0),
        };
        let s = split_of_eight(&boxes, &cell, 1e-4);
        assert_eq!((s.axis, s.below, s.above), (0, 6, 2));
        assert!(5.3 < s.position && s.position < 5.301, "{}", s.position);
    }

    /// Bins as bits, to compare floats exactly (-0.0 apart from 0.0).
    fn bits(b: &Bins) -> Vec<u32> {
        let counts = b.starts.iter().chain(&b.ends).flatten().copied();
        let bounds = b.first_start.iter().chain(&b.last_end).flatten();
        counts.chain(bounds.map(|x| x.to_bits())).collect()
    }

    /// A node big enough to be binned in halves: the halves' bins merged
    /// are one pass's, bit for bit, for boxes on a coarse grid (ties in
    /// every bin, -0.0 beside 0.0, flat boxes); and the plane is the same
    /// with the halves on one thread and on two. A merge that let the upper
    /// half win a tie, or dropped a count, fails it.
    #[test]
    fn binning_in_halves_is_one_pass() {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = move |m: u64| {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 33) % m
        };
        let zero = |x: f32, negative: bool| if negative && x == 0.0 { -0.0 } else { x };
        let boxes: Vec<ClippedBox> = (0..HALVES_OBJECTS as u32 + 4_097)
            .map(|id| {
                let min = [0, 1, 2].map(|_| zero(next(40) as f32 * 0.25, next(2) == 0));
                let size = [0, 1, 2].map(|_| next(5) as f32 * 0.5);
                ClippedBox {
                    id,
                    bounds: Aabb {
                        min: Vec3::from(min),
                        max: Vec3::from(min) + Vec3::from(size),
                    },
                }
            })
            .collect();
        let (lo, scale) = (Vec3A::splat(-0.5), Vec3A::splat(2.5));
        let (lower, upper) = boxes.split_at(boxes.len() / 2);
        let merged = Bins::count(lower, lo, scale).merge(Bins::count(upper, lo, scale));
        assert_eq!(bits(&merged), bits(&Bins::count(&boxes, lo, scale)));

        let cell = Aabb {
            min: Vec3::splat(-1.0),
            max: Vec3::splat(13.0),
        };
        let params = BuildParams::for_object_count(boxes.len());
        let serial = best_split(&boxes, &cell, &params, 1e-4, false).expect("a split");
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .expect("a pool");
        let parallel = pool
            .install(|| best_split(&boxes, &cell, &params, 1e-4, true))
            .expect("a split");
        assert_eq!(
            (
                serial.axis,
                serial.position.to_bits(),
                serial.cost.to_bits()
            ),
            (
                parallel.axis,
                parallel.position.to_bits(),
                parallel.cost.to_bits()
            )
        );
        assert_eq!(
            (serial.below, serial.above),
            (parallel.below, parallel.above)
        );
    }

    proptest::proptest! {
        /// Binning three coordinates at once puts each in the bin the
        /// saturating cast of one gives, for any floats: NaN, infinities,
        /// below the first bin and past the last.
        #[test]
        fn bins_in_lanes_are_the_casts_bins(
            x in proptest::array::uniform3(proptest::prop_oneof![
                proptest::num::f32::ANY, -2.0f32..40.0, proptest::sample::select(vec![f32::NAN, f32::INFINITY, f32::NEG_INFINITY, -0.0])
            ]),
            lo in -8.0f32..8.0,
            scale in proptest::sample::select(vec![0.0f32, 1e-30, 0.37, 1.0, 8.0, 1e30]),
        ) {
            let got = bins_of(Vec3::from(x), Vec3A::splat(lo), Vec3A::splat(scale));
            let want = x.map(|x| (((x - lo) * scale) as usize).min(BINS - 1));
            proptest::prop_assert_eq!(got, want);
        }

        /// The lower child written over the parent's vector is the one
        /// built afresh, and so is the upper child, for boxes on a coarse
        /// grid (faces on the plane, flat boxes) and any plane.
        #[test]
        fn partition_in_place_matches_fresh_vectors(
            raw in proptest::collection::vec((0i32..8, 0i32..8, 0i32..4, 0i32..4), 1..80),
            axis in 0usize..2,
            position in 0i32..16,
        ) {
            let all: Vec<Aabb> = raw
                .iter()
                .map(|&(x, y, w, h)| Aabb {
                    min: Vec3::new(x as f32, y as f32, 0.0),
                    max: Vec3::new((x + w) as f32, (y + h) as f32, 1.0),
                })
                .collect();
            let shapes = Shapes::Boxes(&all);
            let boxes: Vec<ClippedBox> = all
                .iter()
                .enumerate()
                .map(|(id, &bounds)| ClippedBox { id: id as u32, bounds })
                .collect();
            let cell = Aabb { min: Vec3::ZERO, max: Vec3::new(12.0, 12.0, 1.0) };
            let split = Split { axis, position: position as f32 * 0.75, cost: 0.0, below: 1, above: 1 };
            let router = Router::new(&split, &cell, &shapes);
            let fresh = partition_fresh(boxes.clone(), &split, &router);
            let in_place = partition_in_place(boxes, &split, &router);
            proptest::prop_assert_eq!(in_place, fresh);
        }
    }

    /// A box across the plane is clipped into both children; boxes on one
    /// side keep their boxes.
    #[test]
    fn straddlers_are_clipped_into_both_children() {
        let boxes = vec![unit_box(0, 0.0), unit_box(1, 1.5), unit_box(2, 3.0)];
        let all: Vec<Aabb> = boxes.iter().map(|b| b.bounds).collect();
        let shapes = Shapes::Boxes(&all);
        let cell = Aabb {
            min: Vec3::ZERO,
            max: Vec3::new(4.0, 1.0, 1.0),
        };
        let split = Split {
            axis: 0,
            position: 2.0,
            cost: 0.0,
            below: 2,
            above: 2,
        };
        let (below, above) = partition(boxes.clone(), &split, &cell, &shapes);
        assert_eq!(below.iter().map(|b| b.id).collect::<Vec<_>>(), [0, 1]);
        assert_eq!(above.iter().map(|b| b.id).collect::<Vec<_>>(), [1, 2]);
        assert_eq!(below[0], boxes[0]);
        assert_eq!(below[1].bounds.max.x, 2.0);
        assert_eq!(above[0].bounds.min.x, 2.0);
        assert_eq!(above[1], boxes[2]);
    }
}
