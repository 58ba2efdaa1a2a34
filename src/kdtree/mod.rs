//! The k-d tree: built on the CPU with the surface area heuristic
//! ([`build`]), flattened into the GPU layout ([`crate::layout::KdNode`] +
//! a leaf-object list), and walked by CPU mirrors of the shader's stackless
//! walks ([`Traversal`]: [`traverse`], [`traverse_ropes`] over [`Ropes`],
//! [`traverse_short_stack`]) that the tests check against brute force.

mod build;
pub mod ropes;
pub mod traversal;
pub mod traverse;
pub mod traverse_ropes;
pub mod traverse_short_stack;

pub use build::{build, build_with_threads, BuildParams, KdTree};
pub use ropes::Ropes;
pub use traversal::Traversal;

use crate::geometry::{Aabb, Primitives};
use crate::layout::KdNode;

impl KdTree {
    /// Builds the tree over all objects of `prims` with the default parameters.
    pub fn for_primitives(prims: &Primitives) -> KdTree {
        let bounds: Vec<_> = (0..prims.len() as u32).map(|id| prims.bounds(id)).collect();
        build(&bounds, BuildParams::for_object_count(bounds.len()))
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
