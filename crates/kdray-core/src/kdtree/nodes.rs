//! The tree's own records: [`KdNode`] as the build writes it and the CPU
//! walks read it, and a leaf's box and ropes ([`LeafRopes`]), which the
//! kernel reads as they are. The `layout` module re-exports both and packs
//! `KdNode` into the kernel's `GpuKdNode`.

use bytemuck::{Pod, Zeroable};

/// A k-d tree node, 16 bytes, as the build writes it and the CPU walks read
/// it (the kernel reads it packed, as `layout`'s `GpuKdNode`). Nodes are
/// stored depth first: an inner node's left ("below the plane") child is
/// the next node.
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
