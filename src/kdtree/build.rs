//! k-d tree construction: the frame both build strategies share (the
//! recursion, the flat node list, subtrees on threads), the parameters, and
//! the tree itself. The strategies decide each node: [`super::sah`] (the
//! surface area heuristic with perfect splits, the default) and
//! [`super::median`] (the seed study's median split, for comparison).
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
use crate::layout::KdNode;

use super::clip::Shapes;
use super::median::Median;
use super::sah::Sah;

/// How the build chooses its planes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum BuildStrategy {
    /// Surface area heuristic over the clipped objects' bounds, every event
    /// a candidate (Wald & Havran 2006): the default. In scenes of more
    /// than [`BuildParams::bin_past_objects`] objects (2^19) its big nodes
    /// are binned as [`BuildStrategy::Binned`] bins them
    /// ([`BINNED_PAST_OBJECTS`] says why).
    #[default]
    Sah,
    /// The same heuristic evaluated at 32 bin boundaries per axis, snapped
    /// to the nearest object faces, in nodes of many objects, exact below
    /// (after Shevtsov et al. 2007): a tree as good by the heuristic (within
    /// 1-3%) and as fast to trace, built 1.3-1.5x faster (docs/benchmarks.md).
    Binned,
    /// The seed study's Algorithm 2: the median of the objects' centres on
    /// axis `depth mod 3`, down to one object per leaf, with straddling
    /// objects in both children (the study put them on one side only).
    Median,
}

impl BuildStrategy {
    pub const ALL: [BuildStrategy; 3] = [
        BuildStrategy::Sah,
        BuildStrategy::Binned,
        BuildStrategy::Median,
    ];

    /// The next strategy of [`BuildStrategy::ALL`], round (the window's K).
    pub fn next(self) -> BuildStrategy {
        let i = BuildStrategy::ALL
            .iter()
            .position(|&b| b == self)
            .unwrap_or(0);
        BuildStrategy::ALL[(i + 1) % BuildStrategy::ALL.len()]
    }

    pub fn name(self) -> &'static str {
        match self {
            BuildStrategy::Sah => "sah",
            BuildStrategy::Binned => "binned",
            BuildStrategy::Median => "median",
        }
    }
}

impl std::fmt::Display for BuildStrategy {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl crate::choice::Choice for BuildStrategy {
    const ALL: &'static [Self] = &BuildStrategy::ALL;

    fn name(self) -> &'static str {
        BuildStrategy::name(self)
    }

    fn help(self) -> &'static str {
        match self {
            BuildStrategy::Sah => "surface area heuristic with perfect splits, every event a candidate (Wald & Havran 2006); binned in big nodes past 2^19 objects",
            BuildStrategy::Binned => "the same, binned in big nodes with snapped boundaries: a faster build of a tree as good",
            BuildStrategy::Median => "the seed's median split, straddlers in both children",
        }
    }
}

/// Knobs of the build. Costs are in units of one traversal step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BuildParams {
    pub max_depth: u32,
    pub traversal_cost: f32,
    pub intersection_cost: f32,
    /// Cost factor (< 1) that rewards cutting off empty space.
    pub empty_bonus: f32,
    /// The binned build ([`BuildStrategy::Binned`]) bins nodes of more
    /// objects than this and sweeps every event of the others.
    pub exact_below: usize,
    /// The default build ([`BuildStrategy::Sah`]) bins as the binned build
    /// does in scenes of more objects than this ([`BINNED_PAST_OBJECTS`]),
    /// and sweeps every event of every node in the others.
    pub bin_past_objects: usize,
    pub strategy: BuildStrategy,
}

/// The cost of testing a sphere, in the build's units (a traversal step
/// costs 40): Wald & Havran's 20 (see [`BuildParams::for_object_count`]).
pub const SPHERE_TEST_COST: f32 = 20.0;

/// The cost of testing a triangle in a scene of `objects` objects: 80 (four
/// sphere tests) up to [`SMALL_SCENE_OBJECTS`], 40 up to
/// [`LARGE_SCENE_OBJECTS`], 10 ([`LARGE_SCENE_TRIANGLE_COST`]) beyond. A
/// triangle test loads nine floats where a sphere's loads four, and the
/// frame of a mesh is faster the more the heuristic trades its triangle
/// tests for node steps; but the tree grows with it (about 11, 6, 2 and 0.7
/// nodes a triangle on the bunny), and with it the build and the GPU arrays.
/// Measured on lavapipe (docs/design.md "Costs"): at 80 against 40 the
/// bunny, the torus and `scenes/bunny.toml` render 7 - 8% faster and the
/// gears 2.5%; at 40 against 20, 6 - 18% on meshes up to 1.1 M triangles.
/// Past the tiers the build costs more than one 1080p frame gains: at
/// 278,664 triangles 80 builds in 1.61 s instead of 1.13 for a 7% faster
/// frame; past 2^19 the cost is a trade of the frame for the build, no
/// longer a test's price: at 1.1 M triangles 10 builds in 0.95 s instead of
/// 1.49 (binned) with 37% smaller GPU arrays, for a frame 7% slower (3.75
/// against 3.52 s at 1080p), and build + upload + frame is 8% shorter; at
/// 557,332 triangles 2% shorter.
pub fn triangle_test_cost(objects: usize) -> f32 {
    if objects <= SMALL_SCENE_OBJECTS {
        80.0
    } else if objects <= LARGE_SCENE_OBJECTS {
        40.0
    } else {
        LARGE_SCENE_TRIANGLE_COST
    }
}

/// A triangle's cost past [`LARGE_SCENE_OBJECTS`] ([`triangle_test_cost`]).
/// Not what a test costs (about twice a sphere's) but the build's price:
/// leaves of about 7 triangles instead of 3, a third of the nodes, for a
/// frame 6 - 7% slower (docs/design.md "A fourth tier").
pub const LARGE_SCENE_TRIANGLE_COST: f32 = 10.0;

/// Scenes of at most this many objects test a triangle at 80
/// ([`triangle_test_cost`]).
pub const SMALL_SCENE_OBJECTS: usize = 1 << 17;

/// Scenes of more than this many objects test a triangle at
/// [`LARGE_SCENE_TRIANGLE_COST`] ([`triangle_test_cost`]).
pub const LARGE_SCENE_OBJECTS: usize = 1 << 19;

/// The factor (< 1) on the cost of a split that leaves one child empty:
/// 0.95, where Wald & Havran 2006 took 0.8. Measured on lavapipe (docs/
/// design.md "Costs"): the gears' frame 11% faster (502 - 505
/// against 562 - 599 ms), the 1.1 M bunny built 4% faster with 13% fewer
/// nodes, the bunny, the torus and random spheres within 1%, a random
/// triangle soup 3% slower. With the weaker bonus the gears' tree spends
/// its splits on separating the thin triangles rather than on cutting off
/// empty space: 24,913 nodes instead of 14,371, and 7.2 triangles tested a
/// ray instead of 9.2.
pub const EMPTY_BONUS: f32 = 0.95;

impl BuildParams {
    /// Depth limit 8 + 1.3 log2 N (Havran's rule of thumb); intersection
    /// cost 20 ([`SPHERE_TEST_COST`]) as in Wald & Havran 2006, but
    /// traversal 40 rather than their 15: kd-restart re-descends for every
    /// leaf, so steps cost more than in a stack walk.
    /// Measured on lavapipe (see docs/benchmarks.md): 11-18% faster at
    /// 1,000 to 1,000,000 spheres, and less than half the tree memory at a
    /// million. With the rope walk and 8-byte nodes, a million spheres are
    /// still fastest at 40 (20 is 5% slower there, 1-5% faster at 1,000 and
    /// 10,000). Empty bonus 0.95 ([`EMPTY_BONUS`]) rather than their 0.8.
    pub fn for_object_count(n: usize) -> Self {
        let max_depth = (8.0 + 1.3 * (n.max(1) as f64).log2()).round() as u32;
        BuildParams {
            max_depth: max_depth.min(64),
            traversal_cost: 40.0,
            intersection_cost: SPHERE_TEST_COST,
            empty_bonus: EMPTY_BONUS,
            exact_below: BINNED_EXACT_BELOW,
            bin_past_objects: BINNED_PAST_OBJECTS,
            strategy: BuildStrategy::Sah,
        }
    }

    /// Nodes of more objects than this are split by binning, the others by
    /// the exact sweep, in a scene of `objects` objects: `exact_below` for
    /// the binned build at every size and for the default one past
    /// `bin_past_objects`; never otherwise.
    pub fn binned_above(&self, objects: usize) -> usize {
        match self.strategy {
            BuildStrategy::Binned => self.exact_below,
            BuildStrategy::Sah if objects > self.bin_past_objects => self.exact_below,
            BuildStrategy::Sah | BuildStrategy::Median => usize::MAX,
        }
    }

    /// The defaults for a scene's objects: the intersection cost is the
    /// mean of its objects' test costs ([`SPHERE_TEST_COST`],
    /// [`triangle_test_cost`]), since the heuristic counts objects, not
    /// their kinds.
    pub fn for_primitives(prims: &Primitives) -> Self {
        let n = prims.len();
        let mut params = Self::for_object_count(n);
        if n > 0 {
            let spheres = prims.spheres.len() as f64;
            let triangles = prims.triangles.len() as f64;
            let total =
                spheres * SPHERE_TEST_COST as f64 + triangles * triangle_test_cost(n) as f64;
            params.intersection_cost = (total / n as f64) as f32;
        }
        params
    }
}

/// With [`BuildStrategy::Binned`], nodes of more objects than this are
/// split by binning (see [`BuildParams::exact_below`]). Measured on the
/// bunny subdivided to 1.1 M triangles, one thread, CPU time under load 3
/// (two runs each): 8 built in 4.8-4.9 s but with
/// 8% more references, 32 in 5.0-5.4 s, 128 and 512 in 6.1-7.4 s, the
/// exact sweep everywhere in 7.3-7.8 s; 32 is the compromise. With snapped
/// bins, 12 and 6 gave
/// 2% and 4% more nodes and built no faster than 32. With leaves of about
/// 7 triangles (`LARGE_SCENE_TRIANGLE_COST`) and the search without sorting
/// up to 16 objects, 16 builds the 1.1 M bunny in 1.69 s of one thread
/// against 1.77 s at 32 (three rounds each), with 1% more
/// references, the same heuristic cost (200.5), the same image, nodes
/// visited (12.87 a ray against 12.86) and objects tested (8.51) and a
/// frame within the noise; on smaller scenes 0.2 - 1% more references
/// and a cost within 0.1%.
pub const BINNED_EXACT_BELOW: usize = 16;

/// The default build ([`BuildStrategy::Sah`]) bins the big nodes of scenes
/// of more objects than this ([`BuildParams::bin_past_objects`]): the size
/// past which a triangle's cost is the build's price, not a test's
/// ([`LARGE_SCENE_OBJECTS`]). Measured past it (two threads,
/// docs/benchmarks.md): the exact sweep built the 1.1 M bunny in 3.2 s
/// against 1.5 s binned and two 278 k bunnies in 1.64 s against 0.72 s,
/// for trees within 1% by the heuristic; the 1.1 M bunny's image was the
/// same, byte for byte, and its frame the same. Up to it every tree stays
/// the exact sweep's.
pub const BINNED_PAST_OBJECTS: usize = LARGE_SCENE_OBJECTS;

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

pub(super) fn available_threads() -> usize {
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

/// What a strategy decides at one node.
pub(super) enum Decision<O> {
    Leaf(O),
    /// Split at `position` on `axis`, with the objects of each child.
    Split {
        axis: usize,
        position: f32,
        below: O,
        above: O,
    },
}

/// A way of choosing planes. `split` must depend only on its arguments, so
/// that the tree is the same whichever thread builds a subtree.
pub(super) trait Strategy: Sync {
    /// A node's objects, in whatever form the strategy keeps them.
    type Objects: Send;
    /// Working memory a builder reuses from node to node (a subtree that
    /// another thread takes gets a builder, and so a scratch, of its own).
    type Scratch: Send;
    fn scratch(&self) -> Self::Scratch;
    fn count(objects: &Self::Objects) -> usize;
    /// Appends the ids of a leaf's objects to `out`, ascending (into the
    /// tree's list itself: a vector of its own for each of the 1.1 M-triangle
    /// bunny's 1.16 M leaves cost 1% of its build).
    fn leaf_ids(objects: Self::Objects, out: &mut Vec<u32>);
    /// With `parallel` the caller is a worker of the build's thread pool,
    /// and the split may share its own work out on it (the decision must
    /// not depend on it).
    fn split(
        &self,
        objects: Self::Objects,
        cell: &Aabb,
        depth: u32,
        parallel: bool,
        scratch: &mut Self::Scratch,
    ) -> Decision<Self::Objects>;
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

    /// A scene's intersection cost is the mean of its objects' test costs.
    #[test]
    fn intersection_cost_follows_the_scene_kinds() {
        use crate::geometry::{SphereF32, TriangleF32};
        let sphere = SphereF32 {
            center: Vec3::ZERO,
            radius: 1.0,
        };
        let triangle = TriangleF32 {
            v: [Vec3::ZERO, Vec3::X, Vec3::Y],
        };
        let scene = |s: usize, t: usize| Primitives {
            spheres: vec![sphere; s],
            triangles: vec![triangle; t],
        };
        let cost = |s, t| BuildParams::for_primitives(&scene(s, t)).intersection_cost;
        assert_eq!(cost(0, 0), SPHERE_TEST_COST);
        assert_eq!(cost(5, 0), SPHERE_TEST_COST);
        assert_eq!(cost(0, 5), 80.0);
        assert_eq!(cost(1, 3), (SPHERE_TEST_COST + 3.0 * 80.0) / 4.0);
        let params = BuildParams::for_primitives(&scene(1, 3));
        assert_eq!(params.traversal_cost, 40.0);
        // The tiers, at their edges.
        assert_eq!(cost(0, SMALL_SCENE_OBJECTS), 80.0);
        assert_eq!(cost(0, SMALL_SCENE_OBJECTS + 1), 40.0);
        assert_eq!(cost(0, LARGE_SCENE_OBJECTS), 40.0);
        assert_eq!(cost(0, LARGE_SCENE_OBJECTS + 1), LARGE_SCENE_TRIANGLE_COST);
    }

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

    /// The default build sweeps every event up to `bin_past_objects`
    /// objects and bins beyond, at the binned build's `exact_below`; the
    /// binned build bins at every size, the median build never.
    #[test]
    fn the_default_build_bins_only_past_its_scene_size() {
        let params = |strategy| BuildParams {
            strategy,
            ..BuildParams::for_object_count(10)
        };
        let sah = params(BuildStrategy::Sah);
        assert_eq!(sah.bin_past_objects, BINNED_PAST_OBJECTS);
        assert_eq!(BINNED_PAST_OBJECTS, LARGE_SCENE_OBJECTS);
        assert_eq!(sah.binned_above(BINNED_PAST_OBJECTS), usize::MAX);
        assert_eq!(
            sah.binned_above(BINNED_PAST_OBJECTS + 1),
            BINNED_EXACT_BELOW
        );
        for n in [0, 17, BINNED_PAST_OBJECTS + 1] {
            assert_eq!(
                params(BuildStrategy::Binned).binned_above(n),
                BINNED_EXACT_BELOW
            );
            assert_eq!(params(BuildStrategy::Median).binned_above(n), usize::MAX);
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
}
