//! Surface-area-heuristic k-d tree construction over object bounding boxes.
//!
//! Classification against a plane at `p` on axis `a` (bounds clipped to the
//! node): an object goes below (left) when `min <= p` and above (right) when
//! `max > p`, or when it is flat and lies in the plane (`min == max == p`).
//! So an object straddling the plane is referenced by both children; one
//! touching the plane from either side is in the left child, which is the
//! side the traversal takes for rays lying in the plane; and one lying in
//! the plane is in both, for rays that cross two planes at once at its edge
//! and so never enter the cell below. This is what makes the tree exact
//! where the seed's is not.

use crate::geometry::Aabb;
use crate::layout::KdNode;

/// Knobs of the build. Costs are in units of one traversal step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BuildParams {
    pub max_depth: u32,
    pub traversal_cost: f32,
    pub intersection_cost: f32,
    /// Cost factor (< 1) that rewards cutting off empty space.
    pub empty_bonus: f32,
}

impl BuildParams {
    /// Depth limit 8 + 1.3 log2 N (Havran's rule of thumb); intersection
    /// cost 20 and empty bonus 0.8 as in Wald & Havran 2006, but traversal
    /// 40 rather than their 15: kd-restart re-descends for every leaf, so
    /// steps cost more than in a stack walk. Measured on lavapipe (see
    /// docs/benchmarks.md): 11-18% faster at 1,000 to 1,000,000 spheres, and
    /// less than half the tree memory at a million.
    pub fn for_object_count(n: usize) -> Self {
        let max_depth = (8.0 + 1.3 * (n.max(1) as f64).log2()).round() as u32;
        BuildParams {
            max_depth: max_depth.min(64),
            traversal_cost: 40.0,
            intersection_cost: 20.0,
            empty_bonus: 0.8,
        }
    }
}

/// The flattened tree: nodes depth first, and the leaves' object id lists.
#[derive(Debug, Clone, PartialEq)]
pub struct KdTree {
    pub nodes: Vec<KdNode>,
    pub leaf_objects: Vec<u32>,
    /// Union of all object bounds: the root node's box.
    pub bounds: Aabb,
    pub max_depth: u32,
}

struct Builder<'a> {
    object_bounds: &'a [Aabb],
    params: BuildParams,
    nodes: Vec<KdNode>,
    leaf_objects: Vec<u32>,
    deepest: u32,
}

/// Subtrees over fewer objects than this are built on the calling thread.
const PARALLEL_MIN_OBJECTS: usize = 4096;

/// Builds the tree over objects `0..object_bounds.len()`, using as many
/// threads as the machine has.
pub fn build(object_bounds: &[Aabb], params: BuildParams) -> KdTree {
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    build_with_threads(object_bounds, params, threads)
}

/// [`build`] with at most `threads` threads. The tree does not depend on
/// the number: subtrees built apart are appended in the order a single
/// thread builds them.
pub fn build_with_threads(object_bounds: &[Aabb], params: BuildParams, threads: usize) -> KdTree {
    let bounds = object_bounds.iter().copied().fold(Aabb::EMPTY, Aabb::union);
    let mut builder = Builder::new(object_bounds, params);
    let ids: Vec<u32> = (0..object_bounds.len() as u32).collect();
    if ids.is_empty() {
        builder.leaf(&ids, 0);
        return KdTree {
            nodes: builder.nodes,
            leaf_objects: builder.leaf_objects,
            bounds: Aabb {
                min: glam::Vec3::ZERO,
                max: glam::Vec3::ZERO,
            },
            max_depth: 0,
        };
    }
    builder.node(ids, bounds, 0, threads.max(1));
    KdTree {
        nodes: builder.nodes,
        leaf_objects: builder.leaf_objects,
        bounds,
        max_depth: builder.deepest,
    }
}

/// Sorts like `sort_unstable_by(f32::total_cmp)`, through u32 keys of the
/// same order (integer sorts are about twice as fast as a comparator's).
fn sort_total(values: &mut [f32]) {
    // Negative floats: all bits flipped; the rest: the sign bit set.
    fn key(x: f32) -> u32 {
        let bits = x.to_bits();
        if bits >> 31 == 1 {
            !bits
        } else {
            bits | 1 << 31
        }
    }
    fn value(k: u32) -> f32 {
        f32::from_bits(if k >> 31 == 1 { k & !(1 << 31) } else { !k })
    }
    let mut keys: Vec<u32> = values.iter().map(|&x| key(x)).collect();
    keys.sort_unstable();
    for (v, k) in values.iter_mut().zip(keys) {
        *v = value(k);
    }
}

struct Split {
    axis: usize,
    position: f32,
    cost: f32,
}

impl<'a> Builder<'a> {
    fn new(object_bounds: &'a [Aabb], params: BuildParams) -> Self {
        Builder {
            object_bounds,
            params,
            nodes: Vec::new(),
            leaf_objects: Vec::new(),
            deepest: 0,
        }
    }

    fn leaf(&mut self, ids: &[u32], depth: u32) {
        self.deepest = self.deepest.max(depth);
        self.nodes.push(KdNode {
            kind: KdNode::LEAF,
            split: 0.0,
            index: self.leaf_objects.len() as u32,
            count: ids.len() as u32,
        });
        self.leaf_objects.extend_from_slice(ids);
    }

    fn clipped(&self, id: u32, cell: &Aabb) -> Aabb {
        let b = self.object_bounds[id as usize];
        Aabb {
            min: b.min.max(cell.min),
            max: b.max.min(cell.max),
        }
    }

    /// Builds the subtree over `ids` in `cell`, appending its nodes depth
    /// first (below child, then above child) with up to `threads` threads.
    fn node(&mut self, ids: Vec<u32>, cell: Aabb, depth: u32, threads: usize) {
        let n = ids.len();
        let leaf_cost = self.params.intersection_cost * n as f32;
        let split = if n <= 1 || depth >= self.params.max_depth {
            None
        } else {
            self.best_split(&ids, &cell)
        };
        let Some(split) = split.filter(|s| s.cost < leaf_cost) else {
            self.leaf(&ids, depth);
            return;
        };
        let (a, p) = (split.axis, split.position);
        let mut left = Vec::new();
        let mut right = Vec::new();
        for &id in &ids {
            let b = self.clipped(id, &cell);
            if b.min[a] <= p {
                left.push(id);
            }
            // A flat object lying in the plane goes both ways: a ray can meet
            // it from either side at a point where it crosses two planes at
            // once, and so spends no time in the cell below.
            if b.max[a] > p || b.min[a] == p {
                right.push(id);
            }
        }
        if left.len() == n && right.len() == n {
            self.leaf(&ids, depth); // no progress possible
            return;
        }
        drop(ids);
        let mut left_cell = cell;
        left_cell.max[a] = p;
        let mut right_cell = cell;
        right_cell.min[a] = p;

        let this = self.nodes.len();
        self.nodes.push(KdNode {
            kind: a as u32,
            split: p,
            index: 0,
            count: 0,
        });
        if threads < 2 || n < PARALLEL_MIN_OBJECTS {
            self.node(left, left_cell, depth + 1, 1);
            self.nodes[this].index = self.nodes.len() as u32;
            self.node(right, right_cell, depth + 1, 1);
            return;
        }
        // The above child on another thread, into a builder of its own.
        let right_threads = threads / 2;
        let mut above = Builder::new(self.object_bounds, self.params);
        let mut job = Some((right, right_cell));
        let worker_panic = std::thread::scope(|scope| {
            let worker = std::thread::Builder::new()
                .name("kdray-kdtree".into())
                .spawn_scoped(scope, || {
                    if let Some((ids, cell)) = job.take() {
                        above.node(ids, cell, depth + 1, right_threads);
                    }
                });
            self.node(left, left_cell, depth + 1, threads - right_threads);
            worker.ok().and_then(|w| w.join().err())
        });
        if let Some(payload) = worker_panic {
            std::panic::resume_unwind(payload);
        }
        if let Some((ids, cell)) = job.take() {
            // The thread could not start: build it here.
            above.node(ids, cell, depth + 1, 1);
        }
        self.append_above_child(this, above);
    }

    /// Appends a subtree built apart as the above child of node `this`,
    /// shifting its node and leaf-list indices past what is here.
    fn append_above_child(&mut self, this: usize, above: Builder<'_>) {
        let node_base = self.nodes.len() as u32;
        let leaf_base = self.leaf_objects.len() as u32;
        self.nodes[this].index = node_base;
        self.nodes.extend(above.nodes.into_iter().map(|mut node| {
            node.index += if node.is_leaf() { leaf_base } else { node_base };
            node
        }));
        self.leaf_objects.extend(above.leaf_objects);
        self.deepest = self.deepest.max(above.deepest);
    }

    /// The cheapest plane over all axes, among the objects' clipped bound
    /// planes strictly inside the cell.
    #[allow(clippy::neg_cmp_op_on_partial_ord)] // NaN counts as not positive
    fn best_split(&self, ids: &[u32], cell: &Aabb) -> Option<Split> {
        let n = ids.len();
        let area = cell.surface_area();
        if !(area > 0.0) {
            return None;
        }
        let inv_area = 1.0 / area;
        let mut best: Option<Split> = None;
        let mut mins = Vec::with_capacity(n);
        let mut maxs = Vec::with_capacity(n);
        for a in 0..3 {
            let (lo, hi) = (cell.min[a], cell.max[a]);
            if !(hi > lo) {
                continue;
            }
            mins.clear();
            maxs.clear();
            for &id in ids {
                let b = self.clipped(id, cell);
                mins.push(b.min[a]);
                maxs.push(b.max[a]);
            }
            sort_total(&mut mins);
            sort_total(&mut maxs);
            // Sweep candidate planes in increasing order; i = #(min <= p), j = #(max <= p).
            let (mut i, mut j) = (0, 0);
            loop {
                let next = match (mins.get(i), maxs.get(j)) {
                    (Some(&x), Some(&y)) => x.min(y),
                    (Some(&x), None) => x,
                    (None, Some(&y)) => y,
                    (None, None) => break,
                };
                while i < n && mins[i] <= next {
                    i += 1;
                }
                while j < n && maxs[j] <= next {
                    j += 1;
                }
                if next <= lo || next >= hi {
                    continue;
                }
                let (n_left, n_right) = (i, n - j);
                let mut left_cell = *cell;
                left_cell.max[a] = next;
                let mut right_cell = *cell;
                right_cell.min[a] = next;
                let p_left = left_cell.surface_area() * inv_area;
                let p_right = right_cell.surface_area() * inv_area;
                let bonus = if n_left == 0 || n_right == 0 {
                    self.params.empty_bonus
                } else {
                    1.0
                };
                let cost = self.params.traversal_cost
                    + bonus
                        * self.params.intersection_cost
                        * (p_left * n_left as f32 + p_right * n_right as f32);
                if best.as_ref().is_none_or(|b| cost < b.cost) {
                    best = Some(Split {
                        axis: a,
                        position: next,
                        cost,
                    });
                }
            }
        }
        best
    }
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
        fn sort_total_sorts_like_total_cmp(mut values in prop::collection::vec(any_float(), 0..200)) {
            let mut expected = values.clone();
            expected.sort_unstable_by(f32::total_cmp);
            sort_total(&mut values);
            let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            prop_assert_eq!(bits(&values), bits(&expected));
        }
    }
}
