//! The k-d tree: built on the CPU ([`build`]: the surface area heuristic
//! with perfect splits, or the seed's median split), flattened into the GPU
//! layout ([`crate::layout::KdNode`] + a leaf-object list), and walked by CPU
//! mirrors of the shader's stackless walks ([`Traversal`]: [`traverse`], the
//! restart walk, plain or with a short stack; [`traverse_ropes`] over
//! [`Ropes`]), built from the steps they share ([`walk_step`]), that the
//! tests check against brute force.

mod binned;
mod build;
mod build_params;
mod clip;
mod events;
mod few;
mod median;
pub mod ropes;
mod sah;
mod split;
mod strategy;
pub mod traversal;
pub mod traverse;
pub mod traverse_ropes;
pub mod walk_observer;
pub mod walk_step;

pub use build::{build, build_primitives, build_with_threads, KdTree};
pub use build_params::{
    triangle_test_cost, BuildParams, BuildStrategy, BINNED_PAST_OBJECTS, EMPTY_BONUS,
    LARGE_SCENE_OBJECTS, LARGE_SCENE_TRIANGLE_COST, SMALL_SCENE_OBJECTS, SPHERE_TEST_COST,
};
pub use ropes::Ropes;
pub use traversal::Traversal;
pub use walk_observer::{WalkEvent, WalkObserver};
pub use walk_step::{WalkQuery, WalkScene};

use crate::geometry::{Aabb, Primitives};
use crate::layout::KdNode;

impl KdTree {
    /// Builds the tree over all objects of `prims` with the default parameters.
    pub fn for_primitives(prims: &Primitives) -> KdTree {
        Self::build_for(prims, BuildParams::for_primitives(prims))
    }

    /// Builds the tree over all objects of `prims` (triangles clipped to the
    /// cells as polygons, spheres by their boxes) on every core.
    pub fn build_for(prims: &Primitives, params: BuildParams) -> KdTree {
        build_primitives(prims, params, build::available_threads())
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

    pub fn stats(&self) -> TreeStats {
        let leaves = self.nodes.iter().filter(|n| n.is_leaf()).count();
        TreeStats {
            nodes: self.nodes.len(),
            leaves,
            max_depth: self.max_depth,
            refs_per_leaf: self.leaf_objects.len() as f64 / leaves.max(1) as f64,
        }
    }
}

/// Shape of a built tree, as reported by `--stats`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TreeStats {
    pub nodes: usize,
    pub leaves: usize,
    pub max_depth: u32,
    /// Mean number of object references per leaf (empty leaves included).
    pub refs_per_leaf: f64,
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

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
}
