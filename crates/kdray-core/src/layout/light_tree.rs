//! The light tree: how next-event estimation picks one of the emitters
//! (emissive spheres and triangles) from a shading point p, in proportion
//! to an estimate of the light each group of emitters can send to p (the
//! importance-sampled light BVH of Conty Estevez and Kulla, "Importance
//! Sampling of Many Lights with Adaptive Tree Splitting", 2018, as pbrt-v4's
//! `BVHLightSampler` has it).
//!
//! Each node bounds a group of emitters ([`LightBounds`]): its box, its
//! power phi (`light_picks`' watts), the cone of its surface normals (axis,
//! cos theta_o), how far past a normal it emits (cos theta_e: pi / 2 for
//! a diffuse emitter) and whether some of it emits on both sides. Its
//! importance at p ([`importance`]) is phi cos theta' / d^2, d the distance
//! from p to the box's centre (never below the radius of the sphere around
//! the box) and theta' the smallest angle between a direction the group
//! may emit in and the direction to p that the bounds allow; 0 where no
//! point of the group emits toward p. On a surface it is multiplied by the
//! largest cosine, with the surface's normal, of a direction from p into
//! the sphere around the box: 0 where the group lies wholly behind it.
//!
//! The kernel walks down from the root, choosing at each inner node one of
//! its two children with probability proportional to its importance at p
//! and multiplying those probabilities; the probability of an emitter, for
//! multiple importance sampling, is the product of the same shares up the
//! parent links from its leaf. The tree is built here, on the host: every
//! split by the paper's orientation-aware surface area heuristic (12
//! buckets on each axis), one emitter per leaf; an emitter of no power is
//! left out (never picked). Its nodes ([`GpuLightNode`]) lie in the lights
//! buffer after the emitters' entries (the kernel binds no buffer more: it
//! already uses more storage buffers than WebGPU's default limit of 8 per
//! stage, which the page raises to the adapter's), each in one
//! [`GpuLight`]-sized record (`GpuLightNode::to_light`; WGSL's
//! `light_node` reads it back).

use bytemuck::{Pod, Zeroable};
use glam::{DVec3, Vec3};

use super::light::GpuLight;

/// `GpuLightNode::child` of a leaf: this bit, or'ed with the emitter's
/// index among the emitters' entries.
pub const LIGHT_TREE_LEAF: u32 = 1 << 31;
/// `GpuLightNode::parent` of the root.
pub const LIGHT_TREE_ROOT: u32 = u32::MAX;
/// An emitter's leaf when the tree leaves it out (no power).
pub const NO_LEAF: u32 = u32::MAX;

/// One node of the light tree as the kernel reads it (shaders/emitters.wgsl,
/// `LightNode`). Indices count from the tree's first node.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct GpuLightNode {
    /// The box around the node's emitters.
    pub lo: [f32; 3],
    /// An inner node: its first child (the second follows it); a leaf:
    /// [`LIGHT_TREE_LEAF`] | the emitter's index among the emitters.
    pub child: u32,
    pub hi: [f32; 3],
    /// Its parent, or [`LIGHT_TREE_ROOT`].
    pub parent: u32,
    /// The axis of the cone around its emitters' normals (unit).
    pub axis: [f32; 3],
    /// The cosine of that cone's half-angle.
    pub cos_theta_o: f32,
    /// The node's power: its emitters' together.
    pub phi: f32,
    /// The cosine of the angle past a normal that it emits to.
    pub cos_theta_e: f32,
    /// 1 where some emitter of the node emits on both sides.
    pub two_sided: u32,
    pub _pad: u32,
}

impl GpuLightNode {
    /// The node in a lights-buffer record: `lo` in `position`, `child` in
    /// `kind`, `hi` in `ambient`, `parent` in `object`, `axis` in
    /// `diffuse`, `cos_theta_o` in `cos_outer`, and (phi, cos_theta_e, the
    /// bits of `two_sided`) in `specular`.
    pub fn to_light(&self) -> GpuLight {
        GpuLight {
            position: self.lo,
            kind: self.child,
            ambient: self.hi,
            object: self.parent,
            diffuse: self.axis,
            cos_outer: self.cos_theta_o,
            specular: [self.phi, self.cos_theta_e, f32::from_bits(self.two_sided)],
            ..Zeroable::zeroed()
        }
    }

    /// The node a lights-buffer record holds ([`Self::to_light`]'s inverse).
    pub fn from_light(l: &GpuLight) -> GpuLightNode {
        GpuLightNode {
            lo: l.position,
            child: l.kind,
            hi: l.ambient,
            parent: l.object,
            axis: l.diffuse,
            cos_theta_o: l.cos_outer,
            phi: l.specular[0],
            cos_theta_e: l.specular[1],
            two_sided: l.specular[2].to_bits(),
            _pad: 0,
        }
    }

    pub fn is_leaf(&self) -> bool {
        self.child & LIGHT_TREE_LEAF != 0
    }
}

/// What the tree knows of an emitter or a group of them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LightBounds {
    pub lo: Vec3,
    pub hi: Vec3,
    pub phi: f64,
    /// Unit.
    pub axis: DVec3,
    pub cos_theta_o: f64,
    pub cos_theta_e: f64,
    pub two_sided: bool,
}

impl LightBounds {
    /// An emissive sphere: it emits outward in every direction.
    pub fn sphere(center: Vec3, radius: f32, phi: f64) -> LightBounds {
        LightBounds {
            lo: center - Vec3::splat(radius),
            hi: center + Vec3::splat(radius),
            phi,
            axis: DVec3::Z,
            cos_theta_o: -1.0,
            cos_theta_e: 0.0,
            two_sided: false,
        }
    }

    /// An emissive triangle: it emits around its front, the side
    /// (v1 - v0) x (v2 - v0) points to, or on both sides.
    pub fn triangle(v: [Vec3; 3], phi: f64, two_sided: bool) -> LightBounds {
        let [a, b, c] = v.map(|p| p.as_dvec3());
        let axis = (b - a).cross(c - a).normalize_or(DVec3::Z);
        LightBounds {
            lo: v[0].min(v[1]).min(v[2]),
            hi: v[0].max(v[1]).max(v[2]),
            phi,
            axis,
            cos_theta_o: 1.0,
            cos_theta_e: 0.0,
            two_sided,
        }
    }

    /// The bounds of both groups.
    pub fn union(&self, other: &LightBounds) -> LightBounds {
        let (axis, cos_theta_o) = cone_union(
            (self.axis, self.cos_theta_o),
            (other.axis, other.cos_theta_o),
        );
        LightBounds {
            lo: self.lo.min(other.lo),
            hi: self.hi.max(other.hi),
            phi: self.phi + other.phi,
            axis,
            cos_theta_o,
            cos_theta_e: self.cos_theta_e.min(other.cos_theta_e),
            two_sided: self.two_sided || other.two_sided,
        }
    }

    fn centroid(&self) -> DVec3 {
        0.5 * (self.lo.as_dvec3() + self.hi.as_dvec3())
    }

    /// The paper's cost of a group split off along `dim` of a node whose
    /// box has extent `extent`: phi times the solid-angle measure of its
    /// cone (M_omega), the surface area of its box, and the node's
    /// longest extent over its extent along `dim` (thin splits cost more).
    fn cost(&self, extent: DVec3, dim: usize) -> f64 {
        use std::f64::consts::PI;
        let theta_o = self.cos_theta_o.clamp(-1.0, 1.0).acos();
        let theta_e = self.cos_theta_e.clamp(-1.0, 1.0).acos();
        let theta_w = (theta_o + theta_e).min(PI);
        let sin_o = (1.0 - self.cos_theta_o * self.cos_theta_o).max(0.0).sqrt();
        let m_omega = 2.0 * PI * (1.0 - self.cos_theta_o)
            + PI / 2.0
                * (2.0 * theta_w * sin_o - (theta_o - 2.0 * theta_w).cos() - 2.0 * theta_o * sin_o
                    + self.cos_theta_o);
        let e = (self.hi - self.lo).as_dvec3().max(DVec3::ZERO);
        let area = 2.0 * (e.x * e.y + e.y * e.z + e.z * e.x);
        let kr = extent.max_element() / extent[dim].max(f64::MIN_POSITIVE);
        self.phi * m_omega * kr * area
    }
}

/// The cone around both cones (axis, cos of half-angle): the smaller one
/// where one holds the other, else the cone that just holds both (the
/// whole sphere past pi).
fn cone_union(a: (DVec3, f64), b: (DVec3, f64)) -> (DVec3, f64) {
    use std::f64::consts::PI;
    let theta_a = a.1.clamp(-1.0, 1.0).acos();
    let theta_b = b.1.clamp(-1.0, 1.0).acos();
    let theta_d = a.0.dot(b.0).clamp(-1.0, 1.0).acos();
    if (theta_d + theta_b).min(PI) <= theta_a {
        return a;
    }
    if (theta_d + theta_a).min(PI) <= theta_b {
        return b;
    }
    let theta_o = (theta_a + theta_d + theta_b) / 2.0;
    let whole = (a.0, -1.0);
    if theta_o >= PI {
        return whole;
    }
    // Rotate a's axis toward b's by theta_o - theta_a.
    let w = a.0.cross(b.0);
    if w.length_squared() == 0.0 {
        return whole;
    }
    let rotation = glam::DQuat::from_axis_angle(w.normalize(), theta_o - theta_a);
    ((rotation * a.0).normalize(), theta_o.cos())
}

/// The node's importance at p on a surface of unit normal n (zero: none):
/// phi cos theta' / d^2 (module header), times, with a normal, the cosine
/// of the smallest angle between n and a direction from p into the sphere
/// around the box (theta_i', as theta' clamped at 0); 0 where its emitters
/// send nothing toward p, or where all of them lie behind the surface (the
/// path tracer lights a surface from the side its normal faces only). The
/// kernel's `light_importance` computes the same in f32.
pub fn importance(node: &GpuLightNode, p: DVec3, n: DVec3) -> f64 {
    let phi = node.phi as f64;
    if phi <= 0.0 {
        return 0.0;
    }
    let lo = Vec3::from(node.lo).as_dvec3();
    let hi = Vec3::from(node.hi).as_dvec3();
    let centre = 0.5 * (lo + hi);
    let radius2 = 0.25 * (hi - lo).length_squared();
    let to_p = p - centre;
    let dist2 = to_p.length_squared();
    let d2 = dist2.max(radius2);
    let axis = Vec3::from(node.axis).as_dvec3();
    let mut cos_w = if dist2 > 0.0 {
        axis.dot(to_p) / dist2.sqrt()
    } else {
        1.0
    };
    if node.two_sided != 0 {
        cos_w = cos_w.abs();
    }
    let sin_w = (1.0 - cos_w * cos_w).max(0.0).sqrt();
    // The half-angle of the sphere around the box, seen from p (all
    // directions from inside it).
    let cos_b = if dist2 > radius2 {
        (1.0 - radius2 / dist2).max(0.0).sqrt()
    } else {
        -1.0
    };
    let sin_b = (1.0 - cos_b * cos_b).max(0.0).sqrt();
    let cos_o = node.cos_theta_o as f64;
    let sin_o = (1.0 - cos_o * cos_o).max(0.0).sqrt();
    // theta_x = max(theta_w - theta_o, 0), theta' = max(theta_x - theta_b, 0).
    let (cos_x, sin_x) = if cos_w < cos_o {
        (cos_w * cos_o + sin_w * sin_o, sin_w * cos_o - cos_w * sin_o)
    } else {
        (1.0, 0.0)
    };
    let cos_p = if cos_x < cos_b {
        cos_x * cos_b + sin_x * sin_b
    } else {
        1.0
    };
    if cos_p <= node.cos_theta_e as f64 {
        return 0.0;
    }
    let mut cos_pi = 1.0;
    if n != DVec3::ZERO {
        // theta_i' = max(theta_i - theta_b, 0), theta_i the angle between
        // n and the direction from p to the box's centre.
        let cos_i = if dist2 > 0.0 {
            -n.dot(to_p) / dist2.sqrt()
        } else {
            1.0
        };
        let sin_i = (1.0 - cos_i * cos_i).max(0.0).sqrt();
        if cos_i < cos_b {
            cos_pi = cos_i * cos_b + sin_i * sin_b;
        }
        if cos_pi <= 0.0 {
            return 0.0;
        }
    }
    phi * cos_p * cos_pi / d2
}

/// A light tree: its nodes (the root first) and each emitter's leaf.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct LightTree {
    pub nodes: Vec<GpuLightNode>,
    /// By emitter (the order of [`LightTree::build`]'s input): its leaf, or
    /// [`NO_LEAF`].
    pub leaf_of: Vec<u32>,
}

impl LightTree {
    /// The tree over `emitters`, each with a key that orders them
    /// independently of the input's order (the scene's object id), so
    /// that the same emitters in another order give the same tree. An
    /// emitter whose power is not a positive number is left out.
    pub fn build(emitters: &[(u32, LightBounds)]) -> LightTree {
        let mut leaf_of = vec![NO_LEAF; emitters.len()];
        let mut order: Vec<usize> = (0..emitters.len())
            .filter(|&i| emitters[i].1.phi > 0.0 && emitters[i].1.phi.is_finite())
            .collect();
        order.sort_by_key(|&i| emitters[i].0);
        if order.is_empty() {
            return LightTree {
                nodes: Vec::new(),
                leaf_of,
            };
        }
        let bounds = |i: usize| &emitters[i].1;
        let mut nodes = vec![GpuLightNode {
            parent: LIGHT_TREE_ROOT,
            ..Zeroable::zeroed()
        }];
        let mut work = vec![(0usize, 0..order.len())];
        while let Some((node, range)) = work.pop() {
            let slice = &mut order[range.clone()];
            let b = slice[1..]
                .iter()
                .fold(*bounds(slice[0]), |b, &i| b.union(bounds(i)));
            let parent = nodes[node].parent;
            if slice.len() == 1 {
                nodes[node] = node_of(&b, LIGHT_TREE_LEAF | slice[0] as u32, parent);
                leaf_of[slice[0]] = node as u32;
                continue;
            }
            let mid = split(slice, &b, |i| bounds(i));
            let child = nodes.len();
            nodes[node] = node_of(&b, child as u32, parent);
            let placeholder = GpuLightNode {
                parent: node as u32,
                ..Zeroable::zeroed()
            };
            nodes.extend([placeholder; 2]);
            work.push((child, range.start..range.start + mid));
            work.push((child + 1, range.start + mid..range.end));
        }
        LightTree { nodes, leaf_of }
    }

    /// The probability that the walk from the root, at p on a surface of
    /// normal n (zero: none), ends at emitter `emitter`'s leaf (0 for one
    /// the tree leaves out).
    pub fn pmf(&self, p: DVec3, n: DVec3, emitter: usize) -> f64 {
        let Some(&leaf) = self.leaf_of.get(emitter).filter(|&&l| l != NO_LEAF) else {
            return 0.0;
        };
        let mut node = leaf as usize;
        let mut probability = 1.0;
        while self.nodes[node].parent != LIGHT_TREE_ROOT {
            let parent = self.nodes[node].parent as usize;
            let first = self.nodes[parent].child as usize;
            let a = importance(&self.nodes[first], p, n);
            let b = importance(&self.nodes[first + 1], p, n);
            if a + b <= 0.0 {
                return 0.0;
            }
            probability *= if node == first { a } else { b } / (a + b);
            node = parent;
        }
        probability
    }

    /// The walk from the root at p on a surface of normal n (zero: none)
    /// with the random number u in [0, 1): the emitter it ends at and its
    /// probability (None where nothing is lit from p).
    pub fn sample(&self, p: DVec3, n: DVec3, mut u: f64) -> Option<(usize, f64)> {
        let mut node = self.nodes.first()?;
        let mut probability = 1.0;
        while !node.is_leaf() {
            let first = node.child as usize;
            let a = importance(&self.nodes[first], p, n);
            let b = importance(&self.nodes[first + 1], p, n);
            if a + b <= 0.0 {
                return None;
            }
            let share = a / (a + b);
            if u < share {
                u /= share;
                probability *= share;
                node = &self.nodes[first];
            } else {
                u = ((u - share) / (1.0 - share)).min(1.0 - f64::EPSILON);
                probability *= b / (a + b);
                node = &self.nodes[first + 1];
            }
        }
        Some(((node.child & !LIGHT_TREE_LEAF) as usize, probability))
    }

    /// Gives each leaf the power `phi(emitter)` and each inner node the sum
    /// of its children's, keeping the boxes and cones: the same walk with
    /// other weights (tests compare pick rules with it).
    pub fn reweight(nodes: &mut [GpuLightNode], phi: impl Fn(usize) -> f32) {
        // Children come after their parent: the reverse order sees them first.
        for i in (0..nodes.len()).rev() {
            let n = nodes[i];
            nodes[i].phi = match n.is_leaf() {
                true => phi((n.child & !LIGHT_TREE_LEAF) as usize),
                false => nodes[n.child as usize].phi + nodes[n.child as usize + 1].phi,
            };
        }
    }
}

fn node_of(b: &LightBounds, child: u32, parent: u32) -> GpuLightNode {
    GpuLightNode {
        lo: b.lo.to_array(),
        child,
        hi: b.hi.to_array(),
        parent,
        axis: b.axis.as_vec3().to_array(),
        cos_theta_o: b.cos_theta_o as f32,
        phi: b.phi as f32,
        cos_theta_e: b.cos_theta_e as f32,
        two_sided: u32::from(b.two_sided),
        _pad: 0,
    }
}

/// Buckets per axis of the split's search.
const BUCKETS: usize = 12;

/// Splits `slice` (at least two emitters, bounded by `b` together) in two,
/// the cheaper split of the paper's cost over 12 buckets of the centroids
/// on each axis; where the centroids coincide, in halves by key order.
/// Returns the first part's length (1 ..= len - 1).
fn split<'a>(
    slice: &mut [usize],
    b: &LightBounds,
    bounds: impl Fn(usize) -> &'a LightBounds,
) -> usize {
    let (mut cmin, mut cmax) = (DVec3::splat(f64::MAX), DVec3::splat(f64::MIN));
    for &i in slice.iter() {
        let c = bounds(i).centroid();
        (cmin, cmax) = (cmin.min(c), cmax.max(c));
    }
    let extent = (b.hi - b.lo).as_dvec3();
    let bucket = |i: usize, dim: usize| {
        let t = (bounds(i).centroid()[dim] - cmin[dim]) / (cmax[dim] - cmin[dim]);
        ((t * BUCKETS as f64) as usize).min(BUCKETS - 1)
    };
    let mut best: Option<(f64, usize, usize)> = None; // cost, dim, first bucket on the right
    for dim in 0..3 {
        if cmax[dim] <= cmin[dim] {
            continue;
        }
        let mut groups: [Option<LightBounds>; BUCKETS] = [None; BUCKETS];
        for &i in slice.iter() {
            let g = &mut groups[bucket(i, dim)];
            *g = Some(g.map_or(*bounds(i), |g| g.union(bounds(i))));
        }
        let fold = |gs: &[Option<LightBounds>]| {
            gs.iter()
                .flatten()
                .fold(None, |acc: Option<LightBounds>, g| {
                    Some(acc.map_or(*g, |a| a.union(g)))
                })
        };
        for s in 1..BUCKETS {
            let (Some(l), Some(r)) = (fold(&groups[..s]), fold(&groups[s..])) else {
                continue;
            };
            let cost = l.cost(extent, dim) + r.cost(extent, dim);
            if best.is_none_or(|(c, _, _)| cost < c) {
                best = Some((cost, dim, s));
            }
        }
    }
    if let Some((_, dim, s)) = best {
        let (left, right): (Vec<usize>, Vec<usize>) =
            slice.iter().partition(|&&i| bucket(i, dim) < s);
        if !left.is_empty() && !right.is_empty() {
            let mid = left.len();
            slice[..mid].copy_from_slice(&left);
            slice[mid..].copy_from_slice(&right);
            return mid;
        }
    }
    slice.len() / 2
}

#[cfg(test)]
#[path = "light_tree_tests.rs"]
mod tests;
