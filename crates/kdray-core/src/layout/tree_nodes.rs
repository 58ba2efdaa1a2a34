//! The k-d tree's records: [`KdNode`] as the build writes it, [`GpuKdNode`]
//! as the kernel reads it (shaders/chunks.wgsl, `unpack_kd_node`), and a
//! leaf's box and ropes ([`LeafRopes`]).

use bytemuck::{Pod, Zeroable};

/// A k-d tree node, 16 bytes, as the build writes it and the CPU walks read
/// it (the kernel reads [`GpuKdNode`]). Nodes are stored depth first: an
/// inner node's left ("below the plane") child is the next node.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct KdNode {
    /// 0, 1, 2: inner node splitting on x, y, z; [`KdNode::LEAF`]: leaf.
    pub kind: u32,
    /// Inner: the plane's coordinate on axis `kind`. Leaf: unused (0).
    pub split: f32,
    /// Inner: index of the right ("above the plane") child.
    /// Leaf: index of its first object id in the leaf-object list.
    pub index: u32,
    /// Leaf: number of object ids. Inner: 0.
    pub count: u32,
}

impl KdNode {
    pub const LEAF: u32 = 3;

    pub fn is_leaf(&self) -> bool {
        self.kind == Self::LEAF
    }
}

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

/// A leaf's box and its six ropes (Popov et al. 2007), 48 bytes: the rope
/// walk's per-leaf data (`kdtree::ropes`). Face `2 * axis` is the box's
/// low side on that axis, `2 * axis + 1` its high side; a ray leaves through
/// face `2 * axis + (dir[axis] > 0)`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct LeafRopes {
    /// The plane coordinate of each face (min x, max x, min y, max y, min z,
    /// max z); on the scene's boundary -inf for a low face and +inf for a
    /// high one, so that a ray never meets it (the rope walk then needs no
    /// rope to see that it has none).
    pub faces: [f32; 6],
    /// The node beyond each face: the smallest one whose cell holds the
    /// whole face strictly inside its planes; [`LeafRopes::NONE`] on the
    /// scene's boundary.
    pub ropes: [u32; 6],
}

impl LeafRopes {
    pub const NONE: u32 = u32::MAX;
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
