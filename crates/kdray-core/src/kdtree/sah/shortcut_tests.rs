//! The shortcuts of the SAH sweep (`super`) against the full sweep: the
//! stack path for few objects and the leaf bound must decide as the event
//! lists do.

use super::*;
use crate::kdtree::build_params::BuildParams;
use glam::Vec3;
use proptest::prelude::{prop, prop_assert, prop_assert_eq, proptest};
use proptest::strategy::Strategy as _;

/// Boxes on a coarse grid, so that faces coincide and objects touch,
/// some flat on an axis.
fn boxes(max: usize) -> impl proptest::strategy::Strategy<Value = Vec<Aabb>> {
    let corner = || {
        (0i32..8, 0i32..8, 0i32..8).prop_map(|(x, y, z)| Vec3::new(x as f32, y as f32, z as f32))
    };
    let size = || {
        (0i32..4, 0i32..4, 0i32..4).prop_map(|(x, y, z)| Vec3::new(x as f32, y as f32, z as f32))
    };
    prop::collection::vec((corner(), size()), 1..=max).prop_map(|v| {
        v.into_iter()
            .map(|(min, s)| Aabb { min, max: min + s })
            .collect()
    })
}

/// Boxes of any finite coordinates around the origin, three in four
/// flat on one axis, some starting on x where the one before ends.
fn float_boxes(max: usize) -> impl proptest::strategy::Strategy<Value = Vec<Aabb>> {
    let corner = || (-4.0f32..4.0, -4.0f32..4.0, -4.0f32..4.0).prop_map(Vec3::from);
    let size = || {
        (0.0f32..2.0, 0.0f32..2.0, 0.0f32..2.0, 0usize..4).prop_map(|(x, y, z, flat)| {
            let mut s = Vec3::new(x, y, z);
            if flat < 3 {
                s[flat] = 0.0;
            }
            s
        })
    };
    prop::collection::vec((corner(), size(), proptest::bool::ANY), 1..=max).prop_map(|v| {
        let mut out: Vec<Aabb> = Vec::with_capacity(v.len());
        for (min, s, touch) in v {
            let mut b = Aabb { min, max: min + s };
            if let (true, Some(last)) = (touch, out.last()) {
                (b.min.x, b.max.x) = (last.max.x, last.max.x + s.x);
            }
            out.push(b);
        }
        out
    })
}

/// [`float_boxes`] scaled by 2^-60 to 2^60 and moved by up to 2^20 of
/// their size: cells whose coordinates round coarsely against their
/// width, and costs of any magnitude.
fn far_float_boxes(max: usize) -> impl proptest::strategy::Strategy<Value = Vec<Aabb>> {
    (float_boxes(max), -60i32..60, -1.0e6f32..1.0e6).prop_map(|(all, exp, shift)| {
        let scale = 2f32.powi(exp);
        all.into_iter()
            .map(|b| Aabb {
                min: (b.min + shift) * scale,
                max: (b.max + shift) * scale,
            })
            .collect()
    })
}

/// A node of up to `max` boxes of every kind above, the margin of its
/// cell around them, and the build's costs.
fn nodes(max: usize) -> impl proptest::strategy::Strategy<Value = (Vec<Aabb>, f32, BuildParams)> {
    (
        proptest::prop_oneof![boxes(max), float_boxes(max), far_float_boxes(max)],
        0.0f32..2.0,
        prop::sample::select(vec![1.0f32, 10.0, 40.0]),
        prop::sample::select(vec![0.8f32, 0.95, 1.0]),
    )
        .prop_map(|(all, margin, traversal_cost, empty_bonus)| {
            let params = BuildParams {
                empty_bonus,
                ..params(traversal_cost)
            };
            (all, margin, params)
        })
}

/// The cell of a node of [`nodes`] and the build over its boxes.
fn node(all: &[Aabb], margin: f32, params: BuildParams) -> (Aabb, Sah<'_>) {
    let cell = cell_around(all, margin);
    (cell, Sah::new(Shapes::Boxes(all), params, &cell))
}

/// Each box as the clipped box of the object of its index.
fn as_clipped(all: &[Aabb]) -> Vec<ClippedBox> {
    all.iter()
        .enumerate()
        .map(|(id, &bounds)| ClippedBox {
            id: id as u32,
            bounds,
        })
        .collect()
}

/// A split with its position and cost as bits, to compare exactly.
fn exact_plane(s: Split) -> (usize, u32, u32, usize, usize) {
    (
        s.axis,
        s.position.to_bits(),
        s.cost.to_bits(),
        s.below,
        s.above,
    )
}

/// The cell: the boxes' union, grown by `margin` on every side.
fn cell_around(all: &[Aabb], margin: f32) -> Aabb {
    let u = all.iter().copied().fold(Aabb::EMPTY, Aabb::union);
    Aabb {
        min: u.min - margin,
        max: u.max + margin,
    }
}

/// A node's object ids, ascending.
fn ids(objects: SahObjects) -> Vec<u32> {
    let mut out = Vec::new();
    Sah::leaf_ids(objects, &mut out);
    out
}

/// A decision as the plane and each child's ids, ascending.
fn summary(d: Decision<SahObjects>) -> (Option<(usize, u32)>, Vec<u32>, Vec<u32>) {
    match d {
        Decision::Leaf(o) => (None, ids(o), vec![]),
        Decision::Split {
            axis,
            position,
            below,
            above,
        } => (Some((axis, position.to_bits())), ids(below), ids(above)),
    }
}

fn params(traversal_cost: f32) -> BuildParams {
    BuildParams {
        traversal_cost,
        ..BuildParams::for_object_count(FEW)
    }
}

proptest! {
    /// `split_few` takes the plane and children the event lists give.
    #[test]
    fn few_objects_split_as_the_event_lists_do(
        all in boxes(FEW), margin in 0.0f32..2.0, traversal_cost in prop::sample::select(vec![1.0f32, 10.0, 40.0])
    ) {
        let cell = cell_around(&all, margin);
        let sah = Sah::new(Shapes::Boxes(&all), params(traversal_cost), &cell);
        let clipped = as_clipped(&all);
        let few = summary(sah.split_few(clipped.clone(), &cell));
        let lists = sah.split_events(EventLists::from_boxes(&clipped), &cell, false, &mut Vec::new());
        prop_assert_eq!(few, summary(lists));
    }

    /// The sweep that passes over gaps which cannot beat the best finds
    /// the full sweep's plane, for nodes of up to 200 boxes (so sorted
    /// lists of hundreds of events) of every kind the tests make.
    #[test]
    fn passing_over_gaps_keeps_the_sweeps_plane((all, margin, params) in nodes(200)) {
        let (cell, sah) = node(&all, margin, params);
        let clipped = as_clipped(&all);
        let lists = EventLists::from_boxes(&clipped);
        let axes = [0, 1, 2].map(|a| lists.axes[a].as_slice());
        prop_assert_eq!(
            sah.best_split(axes, all.len(), &cell).map(exact_plane),
            sah.full_sweep(&clipped, &cell).map(exact_plane)
        );
    }

    /// The search without sorting ([`few`]) finds the full sweep's
    /// plane whenever that plane costs less than a leaf, at every node
    /// size up to [`FEW`]: on grid boxes (ties, touching faces, flat
    /// boxes, zeros of both signs) and on boxes of any coordinates, near
    /// the origin or scaled and moved far from it.
    #[test]
    fn the_search_without_sorting_finds_the_sweeps_plane((all, margin, params) in nodes(FEW)) {
        let (cell, sah) = node(&all, margin, params);
        let clipped = as_clipped(&all);
        let leaf_cost = params.intersection_cost * all.len() as f32;
        let sorted = sah
            .full_sweep(&clipped, &cell)
            .filter(|s| s.cost < leaf_cost)
            .map(exact_plane);
        let unsorted = few::cheapest_paying_split(&clipped, &cell, &params, sah.gap).map(exact_plane);
        prop_assert_eq!(unsorted, sorted);
    }

    /// When the bound says no plane can pay, the sweep finds none that
    /// does.
    #[test]
    fn the_leaf_bound_never_hides_a_paying_plane(
        all in boxes(6), margin in 0.0f32..2.0, traversal_cost in prop::sample::select(vec![1.0f32, 10.0, 40.0])
    ) {
        let cell = cell_around(&all, margin);
        let sah = Sah::new(Shapes::Boxes(&all), params(traversal_cost), &cell);
        let n = all.len();
        if sah.no_plane_can_pay(n, &cell) {
            let lists = EventLists::root(&Shapes::Boxes(&all), 1);
            let axes = [0, 1, 2].map(|a| lists.axes[a].as_slice());
            let best = sah.best_split(axes, n, &cell);
            let leaf_cost = sah.params.intersection_cost * n as f32;
            prop_assert!(best.is_none_or(|s| s.cost >= leaf_cost), "{best:?} against {leaf_cost}");
        }
    }

    /// Boxes read back from a node's event lists are the boxes.
    #[test]
    fn event_lists_give_their_boxes_back(all in boxes(FEW)) {
        let clipped = as_clipped(&all);
        prop_assert_eq!(EventLists::from_boxes(&clipped).into_boxes(), clipped);
    }
}

/// The bound is not vacuous: two objects in a cube never pay for a
/// plane at the default costs (T = 2 I), twenty do.
#[test]
fn the_leaf_bound_decides_small_nodes() {
    let cube = Aabb {
        min: Vec3::ZERO,
        max: Vec3::ONE,
    };
    let all = [cube; 20];
    let sah = Sah::new(Shapes::Boxes(&all), params(40.0), &cube);
    assert!(sah.no_plane_can_pay(2, &cube));
    assert!(!sah.no_plane_can_pay(20, &cube));
}
