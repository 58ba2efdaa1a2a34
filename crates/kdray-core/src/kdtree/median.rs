//! The seed study's median split (its Algorithm 2), made exact: the plane on
//! axis `depth mod 3` halves the node's objects by their centres, and the
//! recursion goes down to one object per leaf. The study sent each object to
//! one side by its centre; here objects are classified by their clipped
//! boxes like in the SAH build (`build.rs`), so straddling objects go to
//! both children and the tree finds what brute force finds. It exists so
//! that the bench can set the study's own tree beside the SAH's.
//!
//! The plane lies halfway between the two middle centres (for two objects,
//! between them, rather than through one of them, which would make it
//! straddle). When that plane is not strictly inside the cell or would
//! leave a child every object, the next axes are tried; when none works
//! (coincident objects, or mesh triangles that all reach across the plane)
//! the node is a leaf, as at the depth limit. Requiring both children to
//! shrink is what "down to one object" becomes once straddlers go to both
//! sides: with a weaker rule (only "not all objects in both children") a
//! mesh's neighbours, which share vertices, were copied down to the depth
//! limit, and the bunny's tree had 41 M nodes, too big to upload.

use crate::geometry::Aabb;

use super::build_params::BuildParams;
use super::clip::{sides, Shapes};
use super::strategy::{Decision, Strategy};

pub struct Median<'a> {
    pub shapes: Shapes<'a>,
    pub params: BuildParams,
}

/// A node's objects: ids with their boxes clipped to the node's cell.
type Clipped = Vec<(u32, Aabb)>;

impl Median<'_> {
    /// Every object with its box (the root cell holds them all).
    pub fn root(&self) -> Clipped {
        (0..self.shapes.len() as u32)
            .map(|id| (id, self.shapes.bounds(id)))
            .collect()
    }

    /// The plane between the two middle centres on axis `a`.
    fn median_plane(objects: &Clipped, a: usize, centres: &mut Vec<f32>) -> f32 {
        centres.clear();
        centres.extend(objects.iter().map(|(_, b)| 0.5 * b.min[a] + 0.5 * b.max[a]));
        let m = centres.len() / 2;
        let (lower, upper, _) = centres.select_nth_unstable_by(m, f32::total_cmp);
        let below = lower.iter().copied().fold(f32::NEG_INFINITY, f32::max);
        0.5 * below + 0.5 * *upper
    }

    fn partition(&self, objects: Clipped, a: usize, p: f32, cell: &Aabb) -> (Clipped, Clipped) {
        let mut below_cell = *cell;
        below_cell.max[a] = p;
        let mut above_cell = *cell;
        above_cell.min[a] = p;
        let (mut below, mut above) = (Vec::new(), Vec::new());
        let eps = self.shapes.tolerance();
        for (id, b) in objects {
            let (goes_below, goes_above) = sides(b.min[a], b.max[a], p, eps);
            if goes_below && goes_above {
                below.extend(self.shapes.clip(id, &below_cell).map(|c| (id, c)));
                above.extend(self.shapes.clip(id, &above_cell).map(|c| (id, c)));
            } else if goes_below {
                below.push((id, b));
            } else {
                above.push((id, b));
            }
        }
        (below, above)
    }
}

impl Strategy for Median<'_> {
    type Objects = Clipped;
    /// The centres being selected from.
    type Scratch = Vec<f32>;

    fn scratch(&self) -> Vec<f32> {
        Vec::new()
    }

    fn count(objects: &Clipped) -> usize {
        objects.len()
    }

    fn leaf_ids(objects: Clipped, out: &mut Vec<u32>) {
        let first = out.len();
        out.extend(objects.into_iter().map(|(id, _)| id));
        out[first..].sort_unstable();
    }

    fn split(
        &self,
        objects: Clipped,
        cell: &Aabb,
        depth: u32,
        _parallel: bool,
        centres: &mut Vec<f32>,
    ) -> Decision<Clipped> {
        let n = objects.len();
        if n <= 1 || depth >= self.params.max_depth {
            return Decision::Leaf(objects);
        }
        for k in 0..3 {
            let a = (depth as usize + k) % 3;
            let p = Self::median_plane(&objects, a, centres);
            if !(cell.min[a] < p && p < cell.max[a]) {
                continue;
            }
            let below = objects.iter().filter(|(_, b)| b.min[a] <= p).count();
            let above = objects
                .iter()
                .filter(|(_, b)| b.max[a] > p || b.min[a] == p)
                .count();
            if below == n || above == n {
                continue;
            }
            let (below, above) = self.partition(objects, a, p, cell);
            if below.len() == n || above.len() == n {
                // Objects within ε of the plane: no progress on one side.
                return Decision::Leaf(if below.len() == n { below } else { above });
            }
            return Decision::Split {
                axis: a,
                position: p,
                below,
                above,
            };
        }
        Decision::Leaf(objects)
    }
}
