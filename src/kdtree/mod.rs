//! The k-d tree: built on the CPU ([`build`]: the surface area heuristic
//! with perfect splits, or the seed's median split), flattened into the GPU
//! layout ([`crate::layout::KdNode`] + a leaf-object list), and walked by CPU
//! mirrors of the shader's stackless walks ([`Traversal`]: [`traverse`],
//! [`traverse_ropes`] over [`Ropes`], [`traverse_short_stack`]) that the
//! tests check against brute force.

mod binned;
mod build;
mod clip;
mod events;
mod median;
pub mod ropes;
mod sah;
pub mod traversal;
pub mod traverse;
pub mod traverse_ropes;
pub mod traverse_short_stack;

pub use build::{build, build_primitives, build_with_threads, BuildParams, BuildStrategy, KdTree};
pub use ropes::Ropes;
pub use traversal::Traversal;

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
