//! The k-d node as the kernel reads it ([`GpuKdNode`], unpacked by
//! `unpack_kd_node` in shaders/chunks.wgsl): the tree's [`KdNode`] packed.

use bytemuck::{Pod, Zeroable};

use crate::kdtree::KdNode;

/// A k-d tree node as the kernel reads it, 8 bytes: the same node as a
/// [`KdNode`] in half the space (the layout of Wald's thesis, 2004). The
/// kind sits in the low 2 bits of `tag_and_index`, and above it an inner
/// node's above-child index or a leaf's object count; `split_or_first` is
/// an inner node's plane (its f32 bits) or a leaf's first entry in the
/// leaf-object list. A descent step loads two words instead of four:
/// measured on lavapipe, 11% off the bunny's frame and 12% off the gears'
/// (docs/benchmarks.md). Unpacked by `unpack_kd_node` in
/// shaders/chunks.wgsl, which [`GpuKdNode::unpack`] mirrors.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct GpuKdNode {
    pub tag_and_index: u32,
    pub split_or_first: u32,
}

impl GpuKdNode {
    /// The largest child index or leaf count the 30 bits above the kind
    /// hold: a tree of more nodes, or with more leaf references, cannot be
    /// packed (`SceneArrays::check_fits` refuses it).
    pub const MAX_INDEX: u32 = (1 << 30) - 1;

    /// `n` packed; its index (inner) or count (leaf) must be at most
    /// [`GpuKdNode::MAX_INDEX`], and a leaf's `split` and an inner node's
    /// `count` must be 0 (as the build writes them) for `unpack` to give
    /// `n` back.
    pub fn pack(n: &KdNode) -> Self {
        let (above, low) = if n.is_leaf() {
            (n.count, n.index)
        } else {
            (n.index, n.split.to_bits())
        };
        GpuKdNode {
            tag_and_index: n.kind | (above << 2),
            split_or_first: low,
        }
    }

    /// The node `pack` was given, as the kernel's `unpack_kd_node` reads it.
    pub fn unpack(&self) -> KdNode {
        let kind = self.tag_and_index & 3;
        let above = self.tag_and_index >> 2;
        if kind == KdNode::LEAF {
            KdNode {
                kind,
                split: 0.0,
                index: self.split_or_first,
                count: above,
            }
        } else {
            KdNode {
                kind,
                split: f32::from_bits(self.split_or_first),
                index: above,
                count: 0,
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    proptest::proptest! {
        /// Packing keeps every field the kernel reads: an inner node's
        /// axis, plane bits (negative zero, subnormals, infinities) and
        /// child index up to the 30-bit limit; a leaf's first entry (any
        /// u32) and count up to the limit.
        #[test]
        fn packed_nodes_unpack_to_the_same_node(
            axis in 0u32..3,
            split_bits in proptest::prelude::any::<u32>(),
            index in 0..=GpuKdNode::MAX_INDEX,
            first in proptest::prelude::any::<u32>(),
        ) {
            let split = f32::from_bits(split_bits);
            let inner = KdNode { kind: axis, split, index, count: 0 };
            let back = GpuKdNode::pack(&inner).unpack();
            proptest::prop_assert_eq!((back.kind, back.split.to_bits(), back.index, back.count),
                (axis, split_bits, index, 0));
            let leaf = KdNode { kind: KdNode::LEAF, split: 0.0, index: first, count: index };
            proptest::prop_assert_eq!(GpuKdNode::pack(&leaf).unpack(), leaf);
        }
    }

    #[test]
    fn the_packing_limits_are_30_bits() {
        let top = KdNode {
            kind: 2,
            split: -1.5,
            index: GpuKdNode::MAX_INDEX,
            count: 0,
        };
        assert_eq!(GpuKdNode::pack(&top).tag_and_index, u32::MAX - 1);
        let leaf = KdNode {
            kind: KdNode::LEAF,
            split: 0.0,
            index: u32::MAX,
            count: GpuKdNode::MAX_INDEX,
        };
        assert_eq!(GpuKdNode::pack(&leaf).tag_and_index, u32::MAX);
    }
}
