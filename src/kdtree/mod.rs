//! The k-d tree: built on the CPU ([`build`]: the surface area heuristic
//! with perfect splits, or the seed's median split), flattened into the GPU
//! layout ([`crate::layout::KdNode`] + a leaf-object list), and walked by a
//! CPU mirror of the shader's stackless traversal ([`traverse`]) that the
//! tests check against brute force.

mod build;
mod clip;
mod events;
mod median;
mod sah;
pub mod traverse;

pub use build::{
    build, build_primitives, build_with_threads, BuildParams, BuildStrategy, KdTree,
};

use crate::geometry::Primitives;

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
