//! The shape of a built tree: its node, leaf and reference counts.

use super::build::KdTree;

/// Shape of a built tree, as reported by `--stats`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TreeStats {
    pub nodes: usize,
    pub leaves: usize,
    pub max_depth: u32,
    /// Mean number of object references per leaf (empty leaves included).
    pub refs_per_leaf: f64,
}

impl KdTree {
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
