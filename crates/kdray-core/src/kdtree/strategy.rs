//! The contract between the build's frame ([`build`](mod@super::build)) and the
//! strategies that decide each node ([`super::sah`], [`super::median`]).

use crate::geometry::Aabb;

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
