//! Ropes (Popov, Günther, Seidel, Slusallek 2007): for every leaf, its box
//! and, for each of its six faces, the node on the other side, built in one
//! pass over a finished tree. The rope walk (`traverse_ropes`) leaves a leaf
//! through a face and descends from that face's node to the next leaf
//! instead of from the root.
//!
//! Ropes are pushed down as far as the face allows (the paper's rope
//! optimisation): below a node splitting on the face's own axis the face
//! lies on the near child's outer side; below one splitting across it, the
//! face lies in one child when it is strictly on that child's side of the
//! plane. A face that touches or crosses the plane stops the push: a ray
//! leaving through the face's edge on that plane is on the plane, and only
//! the walk's descent, with the ray's own `t` values, can say which side it
//! goes on next.

use super::build::KdTree;
use super::nodes::{KdNode, LeafRopes};

/// The rope data of a tree, in the layout the shader reads.
#[derive(Debug, Clone, PartialEq)]
pub struct Ropes {
    /// One record per leaf, leaves in node order.
    pub leaves: Vec<LeafRopes>,
    /// For each node, the index of its record in `leaves` (leaves only;
    /// 0 for inner nodes).
    pub leaf_of_node: Vec<u32>,
}

impl Ropes {
    /// Builds the ropes of `tree`: a depth-first pass that hands each child
    /// its parent's box and ropes, with the split plane as one face and the
    /// sibling as that face's rope, pushing every rope down at every node
    /// (so each push starts where the parent's ended). O(nodes x depth) at
    /// worst.
    pub fn build(tree: &KdTree) -> Ropes {
        let nodes = &tree.nodes;
        let b = tree.bounds;
        let root_faces = [b.min.x, b.max.x, b.min.y, b.max.y, b.min.z, b.max.z];
        let mut leaves = Vec::new();
        let mut leaf_of_node = vec![0u32; nodes.len()];
        let mut pending = vec![(0usize, root_faces, [LeafRopes::NONE; 6])];
        while let Some((i, faces, mut ropes)) = pending.pop() {
            for (face, rope) in ropes.iter_mut().enumerate() {
                *rope = push_down(nodes, *rope, face, &faces);
            }
            let node = nodes[i];
            if node.is_leaf() {
                leaf_of_node[i] = leaves.len() as u32;
                leaves.push(LeafRopes {
                    faces: boundary_at_infinity(faces, &ropes),
                    ropes,
                });
                continue;
            }
            let a = node.kind as usize;
            let (below, above) = (i + 1, node.index as usize);
            let (mut below_faces, mut below_ropes) = (faces, ropes);
            below_faces[2 * a + 1] = node.split;
            below_ropes[2 * a + 1] = above as u32;
            let (mut above_faces, mut above_ropes) = (faces, ropes);
            above_faces[2 * a] = node.split;
            above_ropes[2 * a] = below as u32;
            // Below first, so that the records come in node order.
            pending.push((above, above_faces, above_ropes));
            pending.push((below, below_faces, below_ropes));
        }
        Ropes {
            leaves,
            leaf_of_node,
        }
    }

    /// The record of leaf node `node`.
    pub fn leaf(&self, node: usize) -> &LeafRopes {
        &self.leaves[self.leaf_of_node[node] as usize]
    }
}

/// `faces` with each face that has no rope (the scene's boundary) moved to
/// infinity, outwards: the walk then meets only faces it can leave through.
fn boundary_at_infinity(mut faces: [f32; 6], ropes: &[u32; 6]) -> [f32; 6] {
    for (face, (plane, &rope)) in faces.iter_mut().zip(ropes).enumerate() {
        if rope == LeafRopes::NONE {
            *plane = if face % 2 == 1 {
                f32::INFINITY
            } else {
                f32::NEG_INFINITY
            };
        }
    }
    faces
}

/// The smallest node below `rope` whose cell still holds the whole `face`
/// of the box `faces` (see the module comment for where it stops).
fn push_down(nodes: &[KdNode], rope: u32, face: usize, faces: &[f32; 6]) -> u32 {
    let axis = face / 2;
    let high_side = face % 2 == 1;
    let mut rope = rope;
    while rope != LeafRopes::NONE && !nodes[rope as usize].is_leaf() {
        let n = nodes[rope as usize];
        let (below, above) = (rope + 1, n.index);
        let b = n.kind as usize;
        rope = if b == axis {
            // The rope's cell starts at the face. A plane beyond the face
            // leaves the face on the near child; a plane on the face is
            // crossed at the same t as the face, which the descent counts
            // as crossed, so the face belongs to the far child.
            let at = faces[face];
            match high_side {
                true if n.split > at => below,
                true => above,
                false if n.split < at => above,
                false => below,
            }
        } else if faces[2 * b + 1] < n.split {
            below
        } else if faces[2 * b] > n.split {
            above
        } else {
            break; // the face touches or crosses the plane
        };
    }
    rope
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Aabb, Primitives, SphereF32};
    use glam::Vec3;

    fn tree_of_spheres(centres: &[Vec3]) -> KdTree {
        let prims = Primitives {
            spheres: centres
                .iter()
                .map(|&center| SphereF32 {
                    center,
                    radius: 0.3,
                })
                .collect(),
            ..Default::default()
        };
        let bounds: Vec<_> = (0..prims.len() as u32).map(|id| prims.bounds(id)).collect();
        let params = crate::kdtree::BuildParams {
            traversal_cost: 1.0,
            ..crate::kdtree::BuildParams::for_object_count(bounds.len())
        };
        crate::kdtree::build(&bounds, params)
    }

    /// A record's box, its faces at infinity cut to the scene's `bounds`.
    fn box_of(r: &LeafRopes, bounds: &Aabb) -> Aabb {
        let f = r.faces;
        Aabb {
            min: Vec3::new(f[0], f[2], f[4]).max(bounds.min),
            max: Vec3::new(f[1], f[3], f[5]).min(bounds.max),
        }
    }

    /// The cells of all nodes, by a walk independent of `Ropes::build`.
    fn cells(tree: &KdTree) -> Vec<Aabb> {
        let mut cells = vec![tree.bounds; tree.nodes.len()];
        for i in 0..tree.nodes.len() {
            let n = tree.nodes[i];
            if !n.is_leaf() {
                let a = n.kind as usize;
                let mut below = cells[i];
                below.max[a] = n.split;
                let mut above = cells[i];
                above.min[a] = n.split;
                cells[i + 1] = below;
                cells[n.index as usize] = above;
            }
        }
        cells
    }

    /// Every leaf gets its cell as its box; a face on the scene's boundary
    /// has no rope and lies at infinity; every other face's rope is a node
    /// whose cell holds the whole face and lies on the face's outer side.
    #[test]
    fn ropes_point_across_their_faces() {
        let mut centres = Vec::new();
        for i in 0..6 {
            for j in 0..5 {
                centres.push(Vec3::new(
                    i as f32 * 1.1,
                    j as f32 * 0.7 + (i % 2) as f32 * 0.3,
                    (i * j % 3) as f32,
                ));
            }
        }
        let tree = tree_of_spheres(&centres);
        let ropes = Ropes::build(&tree);
        let cells = cells(&tree);
        let leaves: Vec<_> = (0..tree.nodes.len())
            .filter(|&i| tree.nodes[i].is_leaf())
            .collect();
        assert!(leaves.len() > 10, "{} leaves", leaves.len());
        assert_eq!(ropes.leaves.len(), leaves.len());
        let mut ropes_to_leaves = 0;
        for &i in &leaves {
            let r = ropes.leaf(i);
            let cell = cells[i];
            assert_eq!(box_of(r, &tree.bounds), cell, "leaf {i}");
            for face in 0..6 {
                let (a, high) = (face / 2, face % 2 == 1);
                let on_boundary = match high {
                    true => cell.max[a] == tree.bounds.max[a],
                    false => cell.min[a] == tree.bounds.min[a],
                };
                if on_boundary {
                    assert_eq!(r.ropes[face], LeafRopes::NONE, "leaf {i} face {face}");
                    let outwards = if high {
                        f32::INFINITY
                    } else {
                        f32::NEG_INFINITY
                    };
                    assert_eq!(r.faces[face], outwards, "leaf {i} face {face}");
                    continue;
                }
                assert_eq!(r.faces[face], if high { cell.max[a] } else { cell.min[a] });
                let target = r.ropes[face] as usize;
                let t = cells[target];
                // Across: the target's cell starts at the face's plane.
                match high {
                    true => assert_eq!(t.min[a], cell.max[a], "leaf {i} face {face}"),
                    false => assert_eq!(t.max[a], cell.min[a], "leaf {i} face {face}"),
                }
                // The whole face lies in the target's cell.
                for b in (0..3).filter(|&b| b != a) {
                    assert!(
                        t.min[b] <= cell.min[b] && cell.max[b] <= t.max[b],
                        "leaf {i} face {face}: {t:?} {cell:?}"
                    );
                }
                // Pushed down: a node on the face's axis always has a child
                // holding the face; one across it only if the face is
                // strictly on one side of its plane.
                let n = tree.nodes[target];
                if n.is_leaf() {
                    ropes_to_leaves += 1;
                } else {
                    let b = n.kind as usize;
                    assert_ne!(b, a, "leaf {i} face {face}: rope not pushed down");
                    assert!(
                        cell.min[b] <= n.split && n.split <= cell.max[b],
                        "leaf {i} face {face}: rope not pushed down"
                    );
                }
            }
        }
        assert!(
            ropes_to_leaves > leaves.len(),
            "{ropes_to_leaves} ropes end at a leaf"
        );
    }
}
