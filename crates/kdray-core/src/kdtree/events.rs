//! Sweep events of the SAH build (Wald & Havran 2006): on each axis, where
//! an object's clipped box starts, ends, or lies flat. One event is one u64,
//! `position key (32 bits) | kind (2) | object id (30)`, so that sorting
//! events by (position, kind, id) is an integer sort and a list of them is
//! compact (8 bytes an event).
//!
//! A node's [`EventLists`]: its objects' events, sorted, per axis. The
//! children's lists are the parent's, split in linear time, plus the
//! re-clipped boxes of the objects that straddle the plane, whose few new
//! events are sorted and merged in. The only full sort is at the root.

use crate::geometry::Aabb;

use super::binned::ClippedBox;
use super::clip::{sides, Shapes};

/// Event kinds, in the order they sort at one position.
pub const END: u64 = 0;
pub const PLANAR: u64 = 1;
pub const START: u64 = 2;

/// Object ids must fit the 30 bits an event has for them (a billion objects:
/// far beyond what a scene can hold in memory).
pub const MAX_OBJECTS: usize = 1 << 30;
const ID_MASK: u64 = (1 << 30) - 1;

/// A u32 ordered as `f32::total_cmp` orders the floats: negative floats with
/// all bits flipped, the others with the sign bit set.
pub fn key(x: f32) -> u32 {
    let bits = x.to_bits();
    if bits >> 31 == 1 {
        !bits
    } else {
        bits | 1 << 31
    }
}

/// The float whose [`key`] is `k`.
pub fn value(k: u32) -> f32 {
    f32::from_bits(if k >> 31 == 1 { k & !(1 << 31) } else { !k })
}

/// An event. `-0.0` is stored as `0.0`, so that equal positions have equal
/// keys.
pub fn pack(position: f32, kind: u64, id: u32) -> u64 {
    debug_assert!((id as u64) <= ID_MASK);
    ((key(position + 0.0) as u64) << 32) | (kind << 30) | id as u64
}

pub fn position_key(event: u64) -> u32 {
    (event >> 32) as u32
}

pub fn kind(event: u64) -> u64 {
    (event >> 30) & 3
}

pub fn id(event: u64) -> u32 {
    (event & ID_MASK) as u32
}

/// Appends the events of object `id` with clipped box `b` to the three
/// axes' lists: a flat side gives one planar event, any other a start and
/// an end.
pub fn push_box(lists: &mut [Vec<u64>; 3], id: u32, b: &Aabb) {
    for_each_event(id, b, |a, event| lists[a].push(event));
}

/// Calls `f(axis, event)` for each event of object `id` with clipped box
/// `b`, as [`push_box`] files them.
pub fn for_each_event(id: u32, b: &Aabb, mut f: impl FnMut(usize, u64)) {
    for a in 0..3 {
        if b.min[a] == b.max[a] {
            f(a, pack(b.min[a], PLANAR, id));
        } else {
            f(a, pack(b.min[a], START, id));
            f(a, pack(b.max[a], END, id));
        }
    }
}

/// Merges two sorted lists into one.
pub fn merge(a: Vec<u64>, b: Vec<u64>) -> Vec<u64> {
    if b.is_empty() {
        return a;
    }
    if a.is_empty() {
        return b;
    }
    let mut out = Vec::with_capacity(a.len() + b.len());
    let (mut i, mut j) = (0, 0);
    while i < a.len() && j < b.len() {
        if a[i] <= b[j] {
            out.push(a[i]);
            i += 1;
        } else {
            out.push(b[j]);
            j += 1;
        }
    }
    out.extend_from_slice(&a[i..]);
    out.extend_from_slice(&b[j..]);
    out
}

/// Where each object of a node goes, by id, while its lists are split.
const BELOW: u8 = 1;
const ABOVE: u8 = 2;
const BOTH: u8 = 3;

/// One node's objects: the events of their clipped boxes, sorted, per axis.
#[derive(Debug)]
pub struct EventLists {
    pub(super) axes: [Vec<u64>; 3],
    pub(super) count: usize,
}

/// Sorts the root's three lists, one thread per list when `threads > 1`.
/// (With two threads one of them sorts two lists. Splitting the third list
/// between them and merging its halves was no faster: 2.45 - 2.47 s against
/// 2.43 s for the 1.1 M bunny's exact build, the copies costing what the
/// balance saved.)
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
        assert!(n <= MAX_OBJECTS, "{n} objects: at most 2^30");
        let mut axes = [(); 3].map(|_| Vec::with_capacity(2 * n));
        for id in 0..n as u32 {
            push_box(&mut axes, id, &shapes.bounds(id));
        }
        sort_lists(&mut axes, threads);
        EventLists { axes, count: n }
    }

    /// The lists of a node's clipped boxes, sorted here.
    pub(super) fn from_boxes(boxes: &[ClippedBox]) -> Self {
        let mut axes = [(); 3].map(|_| Vec::with_capacity(2 * boxes.len()));
        for b in boxes {
            push_box(&mut axes, b.id, &b.bounds);
        }
        axes.iter_mut().for_each(|l| l.sort_unstable());
        EventLists {
            axes,
            count: boxes.len(),
        }
    }

    /// The objects' clipped boxes, by ascending id, read back from the
    /// events (a `-0.0` bound comes back as `0.0`, which classifies alike).
    pub(super) fn into_boxes(self) -> Vec<ClippedBox> {
        let ids = self.ids();
        let mut boxes: Vec<ClippedBox> = ids
            .iter()
            .map(|&id| ClippedBox {
                id,
                bounds: Aabb::EMPTY,
            })
            .collect();
        for (a, list) in self.axes.iter().enumerate() {
            for &e in list {
                let Ok(slot) = ids.binary_search(&id(e)) else {
                    continue; // an END without its START: none are made
                };
                let x = value(position_key(e));
                let b = &mut boxes[slot].bounds;
                match kind(e) {
                    START => b.min[a] = x,
                    END => b.max[a] = x,
                    _ => (b.min[a], b.max[a]) = (x, x),
                }
            }
        }
        boxes
    }

    /// The object ids, ascending.
    pub(super) fn ids(&self) -> Vec<u32> {
        let mut ids: Vec<u32> = self.unsorted_ids().collect();
        ids.sort_unstable();
        ids
    }

    /// The object ids, in the order of the x axis's events.
    pub(super) fn unsorted_ids(&self) -> impl Iterator<Item = u32> + '_ {
        self.axes[0]
            .iter()
            .filter(|&&e| kind(e) != END)
            .map(|&e| id(e))
    }

    /// Splits the lists at the plane `position` on `axis`: objects wholly
    /// on one side keep their events; those on both sides are clipped again
    /// to each child's cell (and dropped from a child they turn out not to
    /// reach). `side` is scratch space, one entry per object; with
    /// `parallel`, the three lists are split on the build's threads.
    pub(super) fn partition(
        self,
        shapes: &Shapes<'_>,
        (axis, position): (usize, f32),
        cell: &Aabb,
        parallel: bool,
        side: &mut Vec<u8>,
    ) -> (EventLists, EventLists) {
        if side.len() < shapes.len() {
            side.resize(shapes.len(), 0);
        }
        let on_axis = &self.axes[axis];
        set_sides(on_axis, position, shapes.tolerance(), side);
        let (only_below, only_above, straddling) = count_sides(on_axis, side);
        let (new_below, new_above) = clip_straddlers(shapes, &straddling, (axis, position), cell);
        // Each axis's list splits apart from the others: its events of
        // objects on one side, merged with the straddlers' new events.
        let side: &[u8] = side;
        let split = |list, new_below, new_above| {
            split_list(side, (only_below, only_above), list, new_below, new_above)
        };
        let [lx, ly, lz] = self.axes;
        let [bx, by, bz] = new_below.axes;
        let [ax, ay, az] = new_above.axes;
        let ((x, y), z) = if parallel {
            rayon::join(
                || rayon::join(|| split(lx, bx, ax), || split(ly, by, ay)),
                || split(lz, bz, az),
            )
        } else {
            ((split(lx, bx, ax), split(ly, by, ay)), split(lz, bz, az))
        };
        (
            EventLists {
                axes: [x.0, y.0, z.0],
                count: only_below + new_below.count,
            },
            EventLists {
                axes: [x.1, y.1, z.1],
                count: only_above + new_above.count,
            },
        )
    }
}

/// Sets each object's side of the plane at `p` (tolerance `eps`) in one
/// pass over the axis's sorted events `on_axis`: an object's start (or
/// planar) event comes before its end event.
#[inline]
fn set_sides(on_axis: &[u64], p: f32, eps: f32, side: &mut [u8]) {
    for &e in on_axis {
        let x = value(position_key(e));
        let id = id(e) as usize;
        match kind(e) {
            START => {
                let (below, _) = sides(x, f32::INFINITY, p, eps);
                side[id] = if below { BOTH } else { ABOVE };
            }
            END => {
                let (_, above) = sides(f32::NEG_INFINITY, x, p, eps);
                if !above {
                    side[id] &= BELOW;
                }
            }
            _ => {
                side[id] = match sides(x, x, p, eps) {
                    (true, true) => BOTH,
                    (true, false) => BELOW,
                    _ => ABOVE,
                };
            }
        }
    }
}

/// The objects only below, only above, and the ids of those on both
/// sides, in the order of the axis's events `on_axis`.
#[inline]
fn count_sides(on_axis: &[u64], side: &[u8]) -> (usize, usize, Vec<u32>) {
    let (mut only_below, mut only_above) = (0, 0);
    let mut straddling: Vec<u32> = Vec::new();
    for &e in on_axis {
        if kind(e) == END {
            continue;
        }
        match side[id(e) as usize] {
            BELOW => only_below += 1,
            ABOVE => only_above += 1,
            _ => straddling.push(id(e)),
        }
    }
    (only_below, only_above, straddling)
}

/// One child's share of the straddling objects: the events of their boxes
/// clipped to its cell, unsorted, per axis, and how many reach it.
#[derive(Default)]
struct Reclipped {
    axes: [Vec<u64>; 3],
    count: usize,
}

/// The `straddling` objects clipped again to the cells below and above
/// the plane `position` on `axis` through `cell`.
fn clip_straddlers(
    shapes: &Shapes<'_>,
    straddling: &[u32],
    (axis, position): (usize, f32),
    cell: &Aabb,
) -> (Reclipped, Reclipped) {
    let mut below_cell = *cell;
    below_cell.max[axis] = position;
    let mut above_cell = *cell;
    above_cell.min[axis] = position;
    let (mut new_below, mut new_above) = (Reclipped::default(), Reclipped::default());
    let below_reach = shapes.reach(&below_cell);
    let above_reach = shapes.reach(&above_cell);
    for &id in straddling {
        let (below, above) = shapes.clip_across(id, axis, &below_reach, &above_reach);
        if let Some(b) = below {
            push_box(&mut new_below.axes, id, &b);
            new_below.count += 1;
        }
        if let Some(b) = above {
            push_box(&mut new_above.axes, id, &b);
            new_above.count += 1;
        }
    }
    (new_below, new_above)
}

/// One axis's sorted `list` split by `side`: (below, above), each with the
/// straddlers' `new_below` or `new_above` events sorted and merged in.
/// `only` counts the objects only below and only above (for the room).
#[inline]
fn split_list(
    side: &[u8],
    (only_below, only_above): (usize, usize),
    list: Vec<u64>,
    mut new_below: Vec<u64>,
    mut new_above: Vec<u64>,
) -> (Vec<u64>, Vec<u64>) {
    let mut below = Vec::with_capacity(2 * only_below + new_below.len());
    let mut above = Vec::with_capacity(2 * only_above + new_above.len());
    for &e in &list {
        match side[id(e) as usize] {
            BELOW => below.push(e),
            ABOVE => above.push(e),
            _ => {}
        }
    }
    drop(list);
    new_below.sort_unstable();
    new_above.sort_unstable();
    (merge(below, new_below), merge(above, new_above))
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// Finite floats and the awkward ones: both zeros, subnormals,
    /// infinities and NaNs of either sign.
    fn any_float() -> impl Strategy<Value = f32> {
        prop_oneof![
            any::<f32>(),
            prop::sample::select(vec![
                0.0,
                -0.0,
                f32::MIN_POSITIVE / 2.0,
                -f32::MIN_POSITIVE / 2.0,
                f32::INFINITY,
                f32::NEG_INFINITY,
                f32::NAN,
                -f32::NAN,
                f32::MAX,
                f32::MIN,
            ]),
        ]
    }

    proptest! {
        #[test]
        fn keys_sort_like_total_cmp(mut values in prop::collection::vec(any_float(), 0..200)) {
            let mut expected = values.clone();
            expected.sort_unstable_by(f32::total_cmp);
            values.sort_unstable_by_key(|&x| key(x));
            let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            prop_assert_eq!(bits(&values), bits(&expected));
            for x in values {
                prop_assert_eq!(value(key(x)).to_bits(), x.to_bits());
            }
        }

        #[test]
        fn events_sort_by_position_then_kind_then_id(
            raw in prop::collection::vec((-1e3f32..1e3, 0u64..3, 0u32..1 << 30), 0..100)
        ) {
            let mut events: Vec<u64> = raw.iter().map(|&(p, k, id)| pack(p, k, id)).collect();
            events.sort_unstable();
            let mut expected = raw.clone();
            expected.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
            let got: Vec<_> = events.iter().map(|&e| (value(position_key(e)), kind(e), id(e))).collect();
            prop_assert_eq!(got, expected);
        }

        #[test]
        fn merge_is_a_sorted_union(mut a in prop::collection::vec(any::<u64>(), 0..50), mut b in prop::collection::vec(any::<u64>(), 0..50)) {
            a.sort_unstable();
            b.sort_unstable();
            let mut expected = [a.clone(), b.clone()].concat();
            expected.sort_unstable();
            prop_assert_eq!(merge(a, b), expected);
        }
    }

    #[test]
    fn negative_zero_is_zero() {
        assert_eq!(pack(-0.0, START, 7), pack(0.0, START, 7));
        assert!(pack(-1e-30, END, 0) < pack(0.0, END, 0));
    }

    /// The root's lists come out sorted on one, two and three threads.
    #[test]
    fn root_lists_sort_alike_on_any_thread_count() {
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = move || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            state >> 48 // 16 bits: many repeats
        };
        let lists: [Vec<u64>; 3] =
            [70_001, 70_000, 65_537].map(|n| (0..n).map(|_| next()).collect());
        let mut expected = lists.clone();
        expected.iter_mut().for_each(|l| l.sort_unstable());
        for threads in [1, 2, 3] {
            let mut got = lists.clone();
            sort_lists(&mut got, threads);
            assert!(got == expected, "{threads} threads");
        }
    }
}
