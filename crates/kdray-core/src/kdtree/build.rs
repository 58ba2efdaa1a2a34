//! k-d tree construction: the frame both build strategies share (the
//! recursion, the flat node list, subtrees on threads) and the tree itself;
//! its parameters are in [`super::build_params`]. The strategies
//! ([`super::strategy`]) decide each node: [`super::sah`] (the surface area
//! heuristic with perfect splits, the default) and [`super::median`] (the
//! seed study's median split, for comparison).
//!
//! Classification against a plane at `p` on axis `a`, by the object's box
//! clipped to the node's cell (`super::clip`): an object goes below (left)
//! when it comes within ε of the lower side and above (right) when within ε
//! of the upper side ([`super::clip::sides`]). So an object straddling the
//! plane, touching it, or lying in it is referenced by both children: a ray
//! that meets it there (crossing two or three planes at once at a cell's
//! edge or corner, or passing a few ulps beyond a vertex by rounding) finds
//! it from either side. This is what makes the tree exact where the seed's
//! is not.

use crate::geometry::{Aabb, Primitives};

use super::build_params::{BuildParams, BuildStrategy};
use super::clip::Shapes;
use super::median::Median;
use super::nodes::KdNode;
use super::sah::Sah;
use super::strategy::{Decision, Strategy};

/// The flattened tree: nodes depth first, and the leaves' object id lists.
#[derive(Debug, Clone, PartialEq)]
pub struct KdTree {
    pub nodes: Vec<KdNode>,
    pub leaf_objects: Vec<u32>,
    /// The root node's box: the union of all object bounds, widened by the
    /// build's tolerance ε (see `clip`).
    pub bounds: Aabb,
    pub max_depth: u32,
}

/// Builds the tree over boxes `0..object_bounds.len()` (each object is its
/// box), using as many threads as the machine has.
pub fn build(object_bounds: &[Aabb], params: BuildParams) -> KdTree {
    build_with_threads(object_bounds, params, available_threads())
}

/// [`build`] with at most `threads` threads. The tree does not depend on
/// the number: subtrees built apart are appended in the order a single
/// thread builds them.
pub fn build_with_threads(object_bounds: &[Aabb], params: BuildParams, threads: usize) -> KdTree {
    build_shapes(Shapes::Boxes(object_bounds), params, threads)
}

/// Builds the tree over a scene's spheres (clipped by their boxes) and
/// triangles (clipped as polygons) with at most `threads` threads; the tree
/// does not depend on the number.
pub fn build_primitives(prims: &Primitives, params: BuildParams, threads: usize) -> KdTree {
    build_shapes(Shapes::primitives(prims), params, threads)
}

impl KdTree {
    /// Builds the tree over all objects of `prims` with the default parameters.
    pub fn for_primitives(prims: &Primitives) -> KdTree {
        Self::build_for(prims, BuildParams::for_primitives(prims))
    }

    /// Builds the tree over all objects of `prims` (triangles clipped to the
    /// cells as polygons, spheres by their boxes) on every core.
    pub fn build_for(prims: &Primitives, params: BuildParams) -> KdTree {
        build_primitives(prims, params, available_threads())
    }

    /// One leaf holding objects `0..object_count`, in `bounds`: a valid tree
    /// that any walk searches like brute force (what a brute-force render
    /// uploads, since the kernel needs some tree bound).
    pub fn single_leaf(object_count: u32, bounds: Aabb) -> KdTree {
        KdTree {
            nodes: vec![KdNode {
                kind: KdNode::LEAF,
                split: 0.0,
                index: 0,
                count: object_count,
            }],
            leaf_objects: (0..object_count).collect(),
            bounds,
            max_depth: 0,
        }
    }

    /// Calls `f(node, cell)` for every node with the cell it covers,
    /// parents before children (the root's cell is `bounds`).
    pub fn visit_cells(&self, mut f: impl FnMut(&KdNode, &Aabb)) {
        let mut pending = vec![(0usize, self.bounds)];
        while let Some((i, cell)) = pending.pop() {
            let Some(node) = self.nodes.get(i) else {
                continue;
            };
            f(node, &cell);
            if !node.is_leaf() {
                let axis = node.kind as usize;
                let (mut below, mut above) = (cell, cell);
                below.max[axis] = node.split;
                above.min[axis] = node.split;
                pending.push((node.index as usize, above));
                pending.push((i + 1, below));
            }
        }
    }
}

fn available_threads() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

fn build_shapes(shapes: Shapes<'_>, params: BuildParams, threads: usize) -> KdTree {
    build_forking(shapes, params, threads, PARALLEL_MIN_OBJECTS).0
}

/// [`build_shapes`], forking nodes whose children both hold `fork_min`
/// objects or more; also says how many subtrees other threads built.
fn build_forking(
    shapes: Shapes<'_>,
    params: BuildParams,
    threads: usize,
    fork_min: usize,
) -> (KdTree, usize) {
    let threads = threads.max(1);
    let n = shapes.len();
    if n == 0 {
        let median = Median { shapes, params };
        let mut builder = Builder::new(&median, fork_min);
        builder.leaf(Vec::new(), 0);
        let tree = KdTree {
            nodes: builder.nodes,
            leaf_objects: builder.leaf_objects,
            bounds: Aabb {
                min: glam::Vec3::ZERO,
                max: glam::Vec3::ZERO,
            },
            max_depth: 0,
        };
        return (tree, 0);
    }
    // The build runs on a pool of `threads` threads (this one for 1, or
    // when the pool cannot start), the root's bounds and objects too.
    let pool = (threads > 1)
        .then(|| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .thread_name(|i| format!("kdray-kdtree-{i}"))
                .build()
                .ok()
        })
        .flatten();
    let run = |parallel: bool| {
        // The root cell reaches ε past the objects, like every cell: a ray
        // meeting an object at its box's corner may, by rounding, miss the
        // exact box (a proptest's ray aimed at a lone triangle's vertex did).
        let bounds = super::clip::widen(&shapes.union(parallel), shapes.tolerance());
        let built = match params.strategy {
            BuildStrategy::Sah | BuildStrategy::Binned => {
                let sah = Sah::new(shapes, params, &bounds);
                let root = sah.root(threads, parallel);
                build_from(&sah, root, bounds, parallel, fork_min)
            }
            BuildStrategy::Median => {
                let median = Median { shapes, params };
                let root = median.root();
                build_from(&median, root, bounds, parallel, fork_min)
            }
        };
        (built, bounds)
    };
    let (((nodes, leaf_objects, deepest), taken), bounds) = match pool {
        Some(pool) => pool.install(|| run(true)),
        None => run(false),
    };
    let tree = KdTree {
        nodes,
        leaf_objects,
        bounds,
        max_depth: deepest,
    };
    (tree, taken)
}

/// Builds the tree from the root's objects, forking nodes whose children
/// both hold `fork_min` objects or more when `parallel` (the caller is a
/// worker of the build's pool): the nodes, the leaf lists and the depth of
/// the deepest leaf, and how many subtrees were built by a thread other
/// than their parent's.
fn build_from<S: Strategy>(
    strategy: &S,
    root: S::Objects,
    bounds: Aabb,
    parallel: bool,
    fork_min: usize,
) -> ((Vec<KdNode>, Vec<u32>, u32), usize) {
    let mut builder = Builder::new(strategy, fork_min);
    builder.node(root, bounds, 0, parallel);
    (
        (builder.nodes, builder.leaf_objects, builder.deepest),
        builder.taken,
    )
}

struct Builder<'s, S: Strategy> {
    strategy: &'s S,
    scratch: S::Scratch,
    nodes: Vec<KdNode>,
    leaf_objects: Vec<u32>,
    deepest: u32,
    /// Both children of a node this big or bigger are forked as tasks.
    fork_min: usize,
    /// How many subtrees other threads built and this one appended.
    taken: usize,
}

/// A node forks its children as parallel tasks only when both hold at least
/// this many objects; smaller subtrees are built on the thread that has
/// them. The value is the one the old static split used, not tuned: at the
/// 1.1M-triangle bunny's rate (4.4 s of one thread, about 4 us an object)
/// such a subtree is some 16 ms of work, and only three subtrees changed
/// threads in that build.
const PARALLEL_MIN_OBJECTS: usize = 4096;

impl<'s, S: Strategy> Builder<'s, S> {
    fn new(strategy: &'s S, fork_min: usize) -> Self {
        Builder {
            strategy,
            scratch: strategy.scratch(),
            nodes: Vec::new(),
            leaf_objects: Vec::new(),
            deepest: 0,
            fork_min,
            taken: 0,
        }
    }

    fn leaf(&mut self, objects: S::Objects, depth: u32) {
        self.deepest = self.deepest.max(depth);
        let first = self.leaf_objects.len();
        S::leaf_ids(objects, &mut self.leaf_objects);
        self.nodes.push(KdNode {
            kind: KdNode::LEAF,
            split: 0.0,
            index: first as u32,
            count: (self.leaf_objects.len() - first) as u32,
        });
    }

    /// Builds the subtree over `objects` in `cell`, appending its nodes depth
    /// first (below child, then above child). With `parallel` (the caller is
    /// a worker of the build's thread pool) the children of big nodes are
    /// forked: the below child is built here and the above child is left to
    /// any idle thread (work stealing, so threads stay busy whatever the
    /// shape of the tree: with the old static split, two threads ran the
    /// 1.1M-triangle bunny's build at 1.6x one thread's speed, now at 1.95x,
    /// docs/design.md).
    /// The above child is built into a builder of its own only when another
    /// thread took it, and appended after the below child either way, so
    /// the tree is the same on any number of threads.
    fn node(&mut self, objects: S::Objects, cell: Aabb, depth: u32, parallel: bool) {
        let (axis, position, below, above) =
            match self
                .strategy
                .split(objects, &cell, depth, parallel, &mut self.scratch)
            {
                Decision::Leaf(objects) => {
                    self.leaf(objects, depth);
                    return;
                }
                Decision::Split {
                    axis,
                    position,
                    below,
                    above,
                } => (axis, position, below, above),
            };
        let mut below_cell = cell;
        below_cell.max[axis] = position;
        let mut above_cell = cell;
        above_cell.min[axis] = position;

        let this = self.nodes.len();
        self.nodes.push(KdNode {
            kind: axis as u32,
            split: position,
            index: 0,
            count: 0,
        });
        let fork = parallel && S::count(&below).min(S::count(&above)) >= self.fork_min;
        if !fork {
            self.node(below, below_cell, depth + 1, parallel);
            self.nodes[this].index = self.nodes.len() as u32;
            self.node(above, above_cell, depth + 1, parallel);
            return;
        }
        let (strategy, fork_min) = (self.strategy, self.fork_min);
        let (_, taken) = rayon::join_context(
            |_| self.node(below, below_cell, depth + 1, true),
            move |task| {
                if task.migrated() {
                    let mut other = Builder::new(strategy, fork_min);
                    other.node(above, above_cell, depth + 1, true);
                    Ok(other)
                } else {
                    // Not taken: this thread builds it, in place, below.
                    Err(above)
                }
            },
        );
        match taken {
            Ok(other) => self.append_above_child(this, other),
            Err(above) => {
                self.nodes[this].index = self.nodes.len() as u32;
                self.node(above, above_cell, depth + 1, true);
            }
        }
    }

    /// Appends a subtree built apart as the above child of node `this`,
    /// shifting its node and leaf-list indices past what is here.
    fn append_above_child(&mut self, this: usize, above: Builder<'_, S>) {
        let node_base = self.nodes.len() as u32;
        let leaf_base = self.leaf_objects.len() as u32;
        self.nodes[this].index = node_base;
        self.nodes.extend(above.nodes.into_iter().map(|mut node| {
            node.index += if node.is_leaf() { leaf_base } else { node_base };
            node
        }));
        self.leaf_objects.extend(above.leaf_objects);
        self.deepest = self.deepest.max(above.deepest);
        self.taken += 1 + above.taken;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    /// Boxes of a few sizes scattered by a fixed generator (an LCG), some
    /// long enough to straddle many planes.
    fn scattered_boxes(n: usize) -> Vec<Aabb> {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = move || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 40) as f32 / (1u64 << 24) as f32
        };
        (0..n)
            .map(|i| {
                let min = Vec3::new(next(), next(), next()) * 100.0;
                let size = if i % 7 == 0 { 20.0 } else { 1.0 };
                let extent = Vec3::new(next(), next(), next()) * size;
                Aabb {
                    min,
                    max: min + extent,
                }
            })
            .collect()
    }

    /// A scene big enough for the root's bounds to be joined from pieces
    /// and its boxes binned in halves, on the threads or on one: the same
    /// bounds, bit for bit, and the same tree.
    #[test]
    fn a_big_root_is_split_alike_on_any_thread_count() {
        let mut boxes = scattered_boxes(70_000);
        // A zero of each sign on the lowest faces, where a join in another
        // order could keep the other one.
        boxes[5].min.x = -0.0;
        boxes[40_000].min.x = 0.0;
        let params = BuildParams {
            strategy: BuildStrategy::Binned,
            ..BuildParams::for_object_count(boxes.len())
        };
        let bits = |b: Aabb| [b.min.to_array(), b.max.to_array()].map(|v| v.map(f32::to_bits));
        let serial_bounds = Shapes::Boxes(&boxes).union(false);
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .expect("a pool");
        let parallel_bounds = pool.install(|| Shapes::Boxes(&boxes).union(true));
        assert_eq!(bits(serial_bounds), bits(parallel_bounds));
        let (serial, _) = build_forking(Shapes::Boxes(&boxes), params, 1, PARALLEL_MIN_OBJECTS);
        let (parallel, _) = build_forking(Shapes::Boxes(&boxes), params, 2, PARALLEL_MIN_OBJECTS);
        assert!(serial == parallel, "two threads built another tree");
        assert_eq!(bits(serial.bounds), bits(parallel.bounds));
    }

    /// With every node forked (children of 2 objects or more), idle threads
    /// take subtrees from all over the tree and from each other, and the
    /// tree they append is the one a single thread builds, for every
    /// strategy. The test also checks that subtrees were taken, so that the
    /// appending path ran. Whether an idle thread takes one depends on the
    /// scheduler: in a release build beside the other tests on two cores
    /// a whole round sometimes ran on one thread, so rounds
    /// repeat, each checked, until some subtree was taken (at most 50).
    #[test]
    fn subtrees_taken_by_other_threads_give_the_same_tree() {
        let boxes = scattered_boxes(3_000);
        for strategy in BuildStrategy::ALL {
            let params = BuildParams {
                strategy,
                ..BuildParams::for_object_count(boxes.len())
            };
            let (serial, none) = build_forking(Shapes::Boxes(&boxes), params, 1, 2);
            assert_eq!(none, 0, "{strategy}: one thread takes nothing");
            assert!(serial.nodes.len() > 1000, "{strategy}: a deep tree");
            let mut taken = 0;
            for _round in 0..50 {
                for threads in [2, 3, 8] {
                    let (tree, t) = build_forking(Shapes::Boxes(&boxes), params, threads, 2);
                    assert!(
                        tree == serial,
                        "{strategy}: {threads} threads built another tree"
                    );
                    taken += t;
                }
                if taken > 0 {
                    break;
                }
            }
            assert!(
                taken > 0,
                "{strategy}: no subtree was taken by another thread"
            );
        }
    }

    /// The same rule, through a build: with the scene's size lowered under
    /// the threshold, the default build makes the binned build's tree; at
    /// the threshold, the exact sweep's, which here is another tree.
    #[test]
    fn past_its_scene_size_the_default_build_is_the_binned_one() {
        let boxes = scattered_boxes(2_000);
        let params = |strategy, bin_past_objects| BuildParams {
            strategy,
            bin_past_objects,
            ..BuildParams::for_object_count(boxes.len())
        };
        let tree = |p| build_with_threads(&boxes, p, 1);
        let binned = tree(params(BuildStrategy::Binned, usize::MAX));
        let exact = tree(params(BuildStrategy::Sah, usize::MAX));
        assert!(binned != exact, "the scene must tell the two builds apart");
        let n = boxes.len();
        assert!(tree(params(BuildStrategy::Sah, n - 1)) == binned);
        assert!(tree(params(BuildStrategy::Sah, n)) == exact);
    }

    /// One split of the cube [0, 2]^3 at x = 0.5: the walk visits parents
    /// first, below first, each with its cell.
    #[test]
    fn the_cells_are_visited_parents_first_with_their_boxes() {
        let tree = KdTree {
            nodes: vec![
                KdNode {
                    kind: 0,
                    split: 0.5,
                    index: 2,
                    count: 0,
                },
                KdNode {
                    kind: KdNode::LEAF,
                    split: 0.0,
                    index: 0,
                    count: 1,
                },
                KdNode {
                    kind: KdNode::LEAF,
                    split: 0.0,
                    index: 1,
                    count: 3,
                },
            ],
            leaf_objects: vec![0, 1, 2, 3],
            bounds: Aabb {
                min: Vec3::ZERO,
                max: Vec3::splat(2.0),
            },
            max_depth: 1,
        };
        let mut cells = Vec::new();
        tree.visit_cells(|n, c| cells.push((n.count, c.max.x, c.min.x)));
        assert_eq!(cells, [(0, 2.0, 0.0), (1, 0.5, 0.0), (3, 2.0, 0.5)]);
    }

    /// Two boxes apart on x: the plane goes in the gap between them, where
    /// it touches neither, so each is referenced once. A plane at either
    /// box's face touches that box and files it in both children (the sweep
    /// used to choose one, counting the box on one side only).
    #[test]
    fn a_gap_between_objects_is_split_without_copying_them() {
        let boxes = [
            Aabb {
                min: Vec3::ZERO,
                max: Vec3::ONE,
            },
            Aabb {
                min: Vec3::new(2.0, 0.0, 0.0),
                max: Vec3::new(3.0, 1.0, 1.0),
            },
        ];
        // A cheap step, so that two objects are worth a split.
        let params = BuildParams {
            traversal_cost: 1.0,
            ..BuildParams::for_object_count(2)
        };
        let tree = build_with_threads(&boxes, params, 1);
        let root = tree.nodes[0];
        assert!(!root.is_leaf(), "no split: {:?}", tree.nodes);
        assert_eq!(root.kind, 0, "split on x");
        assert!(1.0 < root.split && root.split < 2.0, "{}", root.split);
        assert_eq!(tree.leaf_objects.len(), 2, "{:?}", tree);
    }
}
