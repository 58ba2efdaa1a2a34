//! Clipping an object to a k-d cell: the box of the part of the object
//! near the cell, so that a long triangle is referenced only by the cells
//! its clipped part reaches ("perfect splits", Wald & Havran 2006).
//!
//! An object belongs to a cell when it comes within the scene's tolerance
//! `ε` of the closed cell: the build files it in every such leaf, both
//! children when it merely touches a plane or passes within ε of it. ε is
//! [`TOLERANCE`] times the largest coordinate magnitude of the scene, 32 f32
//! ulps there: a ray/object test rounds in proportion to the coordinates it
//! works with, so it can report a hit a few ulps off an object (on the far
//! side of a plane the object only touches, at a vertex where three split
//! planes meet). Without ε such a hit is found by brute force and missed by
//! the tree. Ray origins farther out than about 16 times the scene's
//! magnitude round by more than ε (see docs/design.md).
//!
//! Triangles are clipped as polygons (Sutherland-Hodgman, in f64) against
//! the planes of the widened cell that cut their box; the polygon's box is
//! rounded outwards to f32, so it never loses a point of the exact answer.
//! Spheres and plain boxes clip by their box.

use glam::DVec3;

use crate::geometry::{Aabb, Primitives, TriangleF32};

/// The objects a tree is built over: plain boxes (each object is its box) or
/// a scene's spheres and triangles.
#[derive(Debug, Clone, Copy)]
pub enum Shapes<'a> {
    Boxes(&'a [Aabb]),
    Primitives {
        prims: &'a Primitives,
        /// ε: how near a cell an object must come to belong to it.
        tolerance: f32,
        /// The union of the objects' boxes, which ε is made from (kept, not
        /// made again for the root's cell).
        union: Aabb,
    },
}

/// ε relative to the scene's coordinate magnitude: 2^-18, 32 f32 ulps.
pub const TOLERANCE: f32 = 1.0 / (1u32 << 18) as f32;

impl<'a> Shapes<'a> {
    pub fn primitives(prims: &'a Primitives) -> Self {
        let union = prims.scene_bounds();
        let magnitude = if prims.is_empty() {
            0.0
        } else {
            union.magnitude()
        };
        Shapes::Primitives {
            prims,
            tolerance: magnitude * TOLERANCE,
            union,
        }
    }

    /// The union of all objects' boxes ([`crate::geometry::union_in_pieces`]
    /// for plain boxes, on the current pool's threads with `parallel`).
    pub fn union(&self, parallel: bool) -> Aabb {
        match self {
            Shapes::Boxes(b) => {
                crate::geometry::union_in_pieces(b.len(), |id| b[id as usize], parallel)
            }
            Shapes::Primitives { union, .. } => *union,
        }
    }

    /// ε, in scene units: plain boxes are exact (0), the scene's objects
    /// get [`TOLERANCE`] of its magnitude.
    pub fn tolerance(&self) -> f32 {
        match self {
            Shapes::Boxes(_) => 0.0,
            Shapes::Primitives { tolerance, .. } => *tolerance,
        }
    }

    pub fn len(&self) -> usize {
        match self {
            Shapes::Boxes(b) => b.len(),
            Shapes::Primitives { prims, .. } => prims.len(),
        }
    }

    pub fn bounds(&self, id: u32) -> Aabb {
        match self {
            Shapes::Boxes(b) => b[id as usize],
            Shapes::Primitives { prims, .. } => prims.bounds(id),
        }
    }

    /// Box of the part of object `id` within ε of the closed `cell`, or
    /// `None` when the object does not come that near. Never smaller than
    /// the exact answer (see the module comment).
    pub fn clip(&self, id: u32, cell: &Aabb) -> Option<Aabb> {
        self.clip_within(id, &self.reach(cell))
    }

    /// Where an object must come to belong to `cell`: the cell widened by
    /// ε ([`Shapes::clip_within`] takes it, so that a partition widens
    /// each child's cell once).
    pub fn reach(&self, cell: &Aabb) -> Aabb {
        widen(cell, self.tolerance())
    }

    /// Box of the part of object `id` in `reach`, a cell widened by
    /// [`Shapes::reach`], or `None` when it does not meet it.
    pub fn clip_within(&self, id: u32, reach: &Aabb) -> Option<Aabb> {
        match self {
            Shapes::Primitives { prims, .. } if id as usize >= prims.spheres.len() => {
                let t = &prims.triangles[id as usize - prims.spheres.len()];
                clip_triangle(t, reach)
            }
            _ => intersect(&self.bounds(id), reach),
        }
    }

    /// [`Shapes::clip_within`] into both children of a split on `axis`,
    /// whose reaches `below` and `above` differ only on that axis.
    pub fn clip_across(
        &self,
        id: u32,
        axis: usize,
        below: &Aabb,
        above: &Aabb,
    ) -> (Option<Aabb>, Option<Aabb>) {
        match self {
            Shapes::Primitives { prims, .. } if id as usize >= prims.spheres.len() => {
                let t = &prims.triangles[id as usize - prims.spheres.len()];
                clip_triangle_across(t, axis, below, above)
            }
            _ => {
                let b = self.bounds(id);
                (intersect(&b, below), intersect(&b, above))
            }
        }
    }
}

/// `cell` grown by `eps` on every side, rounded outwards.
pub fn widen(cell: &Aabb, eps: f32) -> Aabb {
    if eps == 0.0 {
        return *cell;
    }
    let down = |x: f32| f32_down(x as f64 - eps as f64);
    let up = |x: f32| f32_up(x as f64 + eps as f64);
    Aabb {
        min: cell.min.to_array().map(down).into(),
        max: cell.max.to_array().map(up).into(),
    }
}

/// Whether an object whose clipped box spans `[min, max]` on the plane's
/// axis goes below a plane at `p` and above it: below when it comes within
/// `eps` of the lower side (`min <= p + eps`), above when within `eps` of
/// the upper side (`max >= p - eps`). Touching goes both ways.
pub fn sides(min: f32, max: f32, p: f32, eps: f32) -> (bool, bool) {
    (
        min as f64 <= p as f64 + eps as f64,
        max as f64 >= p as f64 - eps as f64,
    )
}

/// The nearest plane position above `x` that an object ending at `x` does
/// not touch (more than `eps` away, by [`sides`]'s arithmetic).
pub fn clear_above(x: f32, eps: f32) -> f32 {
    let p = f32_up(x as f64 + 2.0 * eps as f64);
    if p > x {
        p
    } else {
        p.next_up()
    }
}

/// The nearest plane position below `x` that an object starting at `x`
/// does not touch.
pub fn clear_below(x: f32, eps: f32) -> f32 {
    let p = f32_down(x as f64 - 2.0 * eps as f64);
    if p < x {
        p
    } else {
        p.next_down()
    }
}

/// The intersection of two closed boxes, or `None` when they do not meet.
pub fn intersect(a: &Aabb, b: &Aabb) -> Option<Aabb> {
    let out = Aabb {
        min: a.min.max(b.min),
        max: a.max.min(b.max),
    };
    out.min.cmple(out.max).all().then_some(out)
}

/// A triangle clipped by up to six planes has at most nine vertices.
const MAX_VERTICES: usize = 9;

/// A convex polygon of at most [`MAX_VERTICES`] vertices, in f64.
struct Polygon {
    vertices: [DVec3; MAX_VERTICES],
    len: usize,
}

impl Polygon {
    fn triangle(t: &TriangleF32) -> Self {
        let mut vertices = [DVec3::ZERO; MAX_VERTICES];
        for (v, w) in vertices.iter_mut().zip(t.v) {
            *v = w.as_dvec3();
        }
        Polygon { vertices, len: 3 }
    }

    fn empty() -> Self {
        Polygon {
            vertices: [DVec3::ZERO; MAX_VERTICES],
            len: 0,
        }
    }

    /// Writes into `out` the part with `x[axis] <= c` (`keep_below`) or
    /// `x[axis] >= c`. New vertices lie exactly on the plane; the others
    /// are kept as they are.
    fn clip_into(&self, axis: usize, c: f64, keep_below: bool, out: &mut Polygon) {
        let inside = |v: &DVec3| {
            if keep_below {
                v[axis] <= c
            } else {
                v[axis] >= c
            }
        };
        out.len = 0;
        let n = self.len;
        let Some(&last) = self.vertices[..n].last() else {
            return;
        };
        let mut push = |v: DVec3| {
            // A convex polygon gains at most one vertex per plane; the guard
            // only matters for a polygon that rounding made slightly concave.
            if out.len < MAX_VERTICES {
                out.vertices[out.len] = v;
                out.len += 1;
            }
        };
        // Each edge (prev, cur), the last vertex to the first first; the
        // previous vertex is carried along (an index `% n` was a division
        // per vertex).
        let mut prev = last;
        let mut prev_in = inside(&prev);
        for &cur in &self.vertices[..n] {
            let cur_in = inside(&cur);
            if prev_in != cur_in {
                // One endpoint on each side, so the denominator is non-zero
                // and t lies in [0, 1] (rounding is monotonic).
                let t = (c - prev[axis]) / (cur[axis] - prev[axis]);
                let mut v = prev + (cur - prev) * t;
                v[axis] = c;
                push(v);
            }
            if cur_in {
                push(cur);
            }
            (prev, prev_in) = (cur, cur_in);
        }
    }

    fn bounds(&self) -> (DVec3, DVec3) {
        let vs = &self.vertices[..self.len];
        let min = vs.iter().copied().fold(DVec3::INFINITY, DVec3::min);
        let max = vs.iter().copied().fold(DVec3::NEG_INFINITY, DVec3::max);
        (min, max)
    }
}

/// Largest f32 not above `x`.
fn f32_down(x: f64) -> f32 {
    let f = x as f32;
    if f as f64 > x {
        f.next_down()
    } else {
        f
    }
}

/// Smallest f32 not below `x`.
fn f32_up(x: f64) -> f32 {
    let f = x as f32;
    if (f as f64) < x {
        f.next_up()
    } else {
        f
    }
}

/// Box of the part of triangle `t` inside the closed box `reach`, rounded
/// outwards, or `None` when they do not meet.
pub fn clip_triangle(t: &TriangleF32, reach: &Aabb) -> Option<Aabb> {
    let bounds = t.bounds();
    let exact = intersect(&bounds, reach)?;
    if exact == bounds {
        return Some(bounds); // inside: nothing to clip
    }
    let mut clip = Clip::new(t);
    for a in 0..3 {
        clip.by_faces_on(a, reach, &bounds);
    }
    clip.bounds(t, reach, &exact)
}

/// [`clip_triangle`] into the two children of a split on `axis`, whose
/// reaches `below` and `above` differ only on that axis: the planes of the
/// other two axes clip the triangle once for both (a straddler's two clips
/// were 14% of the binned build). The planes apply in another order than
/// [`clip_triangle`]'s, so a bound may differ in the last bit of its f64
/// polygon, which the guard and the outward rounding absorb.
pub fn clip_triangle_across(
    t: &TriangleF32,
    axis: usize,
    below: &Aabb,
    above: &Aabb,
) -> (Option<Aabb>, Option<Aabb>) {
    let bounds = t.bounds();
    let (exact_below, exact_above) = (intersect(&bounds, below), intersect(&bounds, above));
    let inside = |exact: Option<Aabb>| exact.is_none_or(|e| e == bounds);
    if inside(exact_below) && inside(exact_above) {
        return (exact_below, exact_above);
    }
    let mut shared = Clip::new(t);
    for a in (0..3).filter(|&a| a != axis) {
        shared.by_faces_on(a, below, &bounds);
    }
    let shared = shared.polygon();
    let child = |reach: &Aabb, exact: Option<Aabb>| {
        let exact = exact?;
        if exact == bounds {
            return Some(bounds);
        }
        // The child's planes read the shared polygon in place (a copy of
        // it for each child cost 1.5% of the build).
        let (mut first, mut second) = (Polygon::empty(), Polygon::empty());
        let mut polygon = shared;
        if reach.min[axis] > bounds.min[axis] {
            polygon.clip_into(axis, reach.min[axis] as f64, false, &mut first);
            polygon = &first;
        }
        if reach.max[axis] < bounds.max[axis] {
            polygon.clip_into(axis, reach.max[axis] as f64, true, &mut second);
            polygon = &second;
        }
        polygon_bounds(polygon, t, reach, &exact)
    };
    (child(below, exact_below), child(above, exact_above))
}

/// A triangle being clipped: each plane clips one polygon into the other,
/// and they swap (into polygons kept here rather than a new one of 224
/// bytes to zero and move for each plane: the 1.1 M bunny's binned build
/// took 3% less CPU).
struct Clip {
    polygons: [Polygon; 2],
    current: usize,
}

impl Clip {
    fn new(t: &TriangleF32) -> Self {
        Clip {
            polygons: [Polygon::triangle(t), Polygon::empty()],
            current: 0,
        }
    }

    /// Clips by the faces of `reach` on axis `a` that cut `bounds`.
    fn by_faces_on(&mut self, a: usize, reach: &Aabb, bounds: &Aabb) {
        if reach.min[a] > bounds.min[a] {
            self.plane(a, reach.min[a] as f64, false);
        }
        if reach.max[a] < bounds.max[a] {
            self.plane(a, reach.max[a] as f64, true);
        }
    }

    fn plane(&mut self, axis: usize, c: f64, keep_below: bool) {
        let [first, second] = &mut self.polygons;
        let (from, to) = if self.current == 0 {
            (first, second)
        } else {
            (second, first)
        };
        from.clip_into(axis, c, keep_below, to);
        self.current = 1 - self.current;
    }

    fn polygon(&self) -> &Polygon {
        &self.polygons[self.current]
    }

    /// The clipped polygon's box ([`polygon_bounds`]).
    fn bounds(&self, t: &TriangleF32, reach: &Aabb, exact: &Aabb) -> Option<Aabb> {
        polygon_bounds(self.polygon(), t, reach, exact)
    }
}

/// The box of `polygon`, clipped from triangle `t` to `reach`, rounded
/// outwards and within `exact` (the triangle's box within `reach`), or
/// `None` when nothing is left.
fn polygon_bounds(polygon: &Polygon, t: &TriangleF32, reach: &Aabb, exact: &Aabb) -> Option<Aabb> {
    if polygon.len == 0 {
        return None;
    }
    // f64 rounding of the clip is some 1e-16 of the coordinates; a guard of
    // 2^-40 of them keeps the box conservative before it is rounded to f32.
    let (min, max) = polygon.bounds();
    let guard = t.magnitude().max(reach.magnitude()) as f64 * (1.0 / (1u64 << 40) as f64);
    let widened = Aabb {
        min: (min - guard).to_array().map(f32_down).into(),
        max: (max + guard).to_array().map(f32_up).into(),
    };
    // Sides the clip did not cut stay exactly the triangle's own.
    intersect(&widened, exact)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    proptest::proptest! {
        /// A gap plane is touched by nothing at `x`: an object ending there
        /// goes below only, one starting there above only; and it lies
        /// within a few ε (or one ulp for ε = 0) of `x`.
        #[test]
        fn gap_planes_touch_nothing_at_x(x in -1e6f32..1e6, scale in 0u32..3) {
            let eps = [0.0, 1e-6, x.abs() * TOLERANCE][scale as usize];
            let above = clear_above(x, eps);
            proptest::prop_assert_eq!(sides(x, x, above, eps), (true, false));
            proptest::prop_assert!(above as f64 - x as f64 <= 3.0 * eps as f64 + (x.abs() * f32::EPSILON) as f64 + 1e-38);
            let below = clear_below(x, eps);
            proptest::prop_assert_eq!(sides(x, x, below, eps), (false, true));
            proptest::prop_assert!(x as f64 - below as f64 <= 3.0 * eps as f64 + (x.abs() * f32::EPSILON) as f64 + 1e-38);
        }
    }

    proptest::proptest! {
        /// Clipping into both children at once gives each child the box
        /// that clipping into it alone gives, to within one ulp a face or
        /// the f64 clip's rounding guard (the planes apply in another
        /// order): for triangles with vertices on a coarse grid (on the
        /// planes, on the cell's faces, across both) or anywhere.
        #[test]
        fn clipping_across_a_split_is_clipping_each_child(
            grid in proptest::bool::ANY,
            raw in proptest::collection::vec(-4.0f32..4.0, 9),
            axis in 0usize..3,
            position in -2.0f32..2.0,
            eps in proptest::sample::select(vec![0.0f32, 1e-3]),
        ) {
            let c = |x: f32| if grid { (x * 2.0).round() * 0.5 } else { x };
            let v = |i: usize| Vec3::new(c(raw[i]), c(raw[i + 1]), c(raw[i + 2]));
            let t = TriangleF32 { v: [v(0), v(3), v(6)] };
            let position = c(position);
            let cell = cube(-2.5, 2.0);
            let (mut below_cell, mut above_cell) = (cell, cell);
            below_cell.max[axis] = position;
            above_cell.min[axis] = position;
            let (below, above) = (widen(&below_cell, eps), widen(&above_cell, eps));
            let across = clip_triangle_across(&t, axis, &below, &above);
            for (got, reach, sibling) in [(across.0, below, across.1), (across.1, above, across.0)] {
                let alone = clip_triangle(&t, &reach);
                match (got, alone) {
                    // A triangle that meets this child at one point of the
                    // split plane only (no area, no segment: its edge
                    // crosses the plane exactly on a face of the cell):
                    // the fused clip may leave the child without it, since
                    // the sibling, which shares the plane, holds the point.
                    (None, Some(a)) if (0..3).all(|i| a.max[i] - a.min[i] <= 1e-6)
                        && (a.min[axis] - position).abs() <= 1e-6 =>
                    {
                        let s = sibling.expect("the sibling holds the contact point");
                        proptest::prop_assert!(
                            (0..3).all(|i| s.min[i] <= a.max[i] + 1e-6 && a.min[i] <= s.max[i] + 1e-6),
                            "{s:?} does not hold the contact {a:?}"
                        );
                    }
                    (Some(g), Some(a)) => {
                        for i in 0..3 {
                            for (x, y) in [(g.min[i], a.min[i]), (g.max[i], a.max[i])] {
                                // The guard of `polygon_bounds` at these
                                // magnitudes (at most 4).
                                let guard = 4.0 * (1.0 / (1u64 << 40) as f32);
                                proptest::prop_assert!(
                                    x == y || x.next_up() == y || x.next_down() == y || (x - y).abs() <= guard,
                                    "{g:?} against {a:?}"
                                );
                            }
                        }
                    }
                    (g, a) => proptest::prop_assert_eq!(g, a),
                }
            }
        }
    }

    fn cube(min: f32, max: f32) -> Aabb {
        Aabb {
            min: Vec3::splat(min),
            max: Vec3::splat(max),
        }
    }

    /// Each bound is the exact value or at most a few ulps (of the
    /// triangle's magnitude) outside it, never inside.
    fn assert_close_outside(got: Aabb, exact: Aabb, magnitude: f32) {
        let slack = magnitude * 2f32.powi(-18);
        for a in 0..3 {
            assert!(
                got.min[a] <= exact.min[a] && exact.min[a] - got.min[a] <= slack,
                "min {a}: got {:?}, exact {:?}",
                got,
                exact
            );
            assert!(
                got.max[a] >= exact.max[a] && got.max[a] - exact.max[a] <= slack,
                "max {a}: got {:?}, exact {:?}",
                got,
                exact
            );
        }
    }

    #[test]
    fn a_triangle_inside_the_cell_keeps_its_box() {
        let t = TriangleF32 {
            v: [Vec3::ZERO, Vec3::X, Vec3::Y],
        };
        assert_eq!(clip_triangle(&t, &cube(-1.0, 2.0)), Some(t.bounds()));
    }

    /// The right triangle (0,0,0), (4,0,0), (0,4,0) in the plane z = 0.
    fn right_triangle() -> TriangleF32 {
        TriangleF32 {
            v: [
                Vec3::ZERO,
                Vec3::new(4.0, 0.0, 0.0),
                Vec3::new(0.0, 4.0, 0.0),
            ],
        }
    }

    /// The right triangle (0,0,0), (4,0,0), (0,4,0) clipped by the unit cube
    /// [1,2]^3 shifted to z in [-1, 1]: its hypotenuse x + y = 4 passes the
    /// cell's far corner, so the part inside is the square [1,2] x [1,2]
    /// (x + y <= 4 holds everywhere in it, with equality only at (2,2)).
    #[test]
    fn a_triangle_clipped_by_a_box_gives_the_exact_polygon_box() {
        let t = right_triangle();
        let cell = Aabb {
            min: Vec3::new(1.0, 1.0, -1.0),
            max: Vec3::new(2.0, 2.0, 1.0),
        };
        let got = clip_triangle(&t, &cell).unwrap();
        let exact = Aabb {
            min: Vec3::new(1.0, 1.0, 0.0),
            max: Vec3::new(2.0, 2.0, 0.0),
        };
        // Here every side lies on the cell or in the triangle's own plane,
        // both exact, so the result is exact too.
        assert_eq!(got, exact);
    }

    /// A cell crossed by the hypotenuse: the polygon is the part of
    /// [2,3] x [0.5,3] below x + y = 4, whose box is [2,3] x [0.5,2].
    #[test]
    fn the_hypotenuse_cuts_the_cell() {
        let t = right_triangle();
        let cell = Aabb {
            min: Vec3::new(2.0, 0.5, -1.0),
            max: Vec3::new(3.0, 3.0, 1.0),
        };
        let got = clip_triangle(&t, &cell).unwrap();
        let exact = Aabb {
            min: Vec3::new(2.0, 0.5, 0.0),
            max: Vec3::new(3.0, 2.0, 0.0),
        };
        assert_close_outside(got, exact, 4.0);
    }

    /// A long thin triangle along the diagonal of a 10-unit cube misses the
    /// cells its box covers off the diagonal.
    #[test]
    fn a_diagonal_sliver_misses_the_cells_off_its_diagonal() {
        let t = TriangleF32 {
            v: [
                Vec3::ZERO,
                Vec3::new(10.0, 10.0, 10.0),
                Vec3::new(10.0, 10.0, 9.9),
            ],
        };
        let off = Aabb {
            min: Vec3::new(6.0, 0.0, 0.0),
            max: Vec3::new(10.0, 4.0, 10.0),
        };
        assert_eq!(clip_triangle(&t, &off), None);
        let on = Aabb {
            min: Vec3::new(4.0, 4.0, 0.0),
            max: Vec3::new(6.0, 6.0, 10.0),
        };
        let got = clip_triangle(&t, &on).unwrap();
        // The sliver is x = y = s, z in [0.99 s, s]; for s in [4, 6] that is
        // z from 3.96 (on the edge to (10,10,9.9)) to 6.
        let exact = Aabb {
            min: Vec3::new(4.0, 4.0, 3.96),
            max: Vec3::splat(6.0),
        };
        assert_close_outside(got, exact, 10.0);
    }

    /// A triangle touching the cell at one vertex, or along one edge lying
    /// in a face, is kept (the cell is closed), with a flat box there.
    #[test]
    fn touching_the_closed_cell_counts() {
        let t = TriangleF32 {
            v: [
                Vec3::ONE,
                Vec3::new(3.0, 1.0, 2.0),
                Vec3::new(2.0, 3.0, 3.0),
            ],
        };
        let got = clip_triangle(&t, &cube(0.0, 1.0)).unwrap();
        assert_close_outside(got, cube(1.0, 1.0), 3.0);
        let edge = TriangleF32 {
            v: [
                Vec3::new(1.0, 0.2, 0.2),
                Vec3::new(1.0, 0.8, 0.8),
                Vec3::new(3.0, 0.5, 0.1),
            ],
        };
        let got = clip_triangle(&edge, &cube(0.0, 1.0)).unwrap();
        assert_eq!(got.max.x, 1.0);
        assert_close_outside(
            got,
            Aabb {
                min: Vec3::new(1.0, 0.2, 0.2),
                max: Vec3::new(1.0, 0.8, 0.8),
            },
            3.0,
        );
    }

    /// A triangle lying in a face plane of the cell, bigger than the face:
    /// clipped to the face rectangle, flat and exact on its own axis.
    #[test]
    fn a_triangle_in_a_face_plane_is_clipped_to_the_face() {
        let t = TriangleF32 {
            v: [
                Vec3::new(-5.0, -5.0, 1.0),
                Vec3::new(15.0, -5.0, 1.0),
                Vec3::new(-5.0, 15.0, 1.0),
            ],
        };
        let got = clip_triangle(&t, &cube(0.0, 1.0)).unwrap();
        assert_eq!(
            got,
            Aabb {
                min: Vec3::new(0.0, 0.0, 1.0),
                max: Vec3::new(1.0, 1.0, 1.0),
            }
        );
    }

    #[test]
    fn a_far_triangle_is_dropped_and_boxes_clip_by_intersection() {
        let t = TriangleF32 {
            v: [Vec3::splat(5.0), Vec3::splat(6.0), Vec3::new(5.0, 6.0, 5.0)],
        };
        assert_eq!(clip_triangle(&t, &cube(0.0, 1.0)), None);
        let boxes = [cube(0.5, 3.0)];
        let shapes = Shapes::Boxes(&boxes);
        assert_eq!(shapes.clip(0, &cube(0.0, 1.0)), Some(cube(0.5, 1.0)));
        assert_eq!(shapes.clip(0, &cube(3.5, 4.0)), None);
    }

    #[test]
    fn outward_rounding() {
        let x = 0.1f64;
        assert!(f32_down(x) as f64 <= x && f32_up(x) as f64 >= x);
        assert_eq!(f32_up(x), f32_down(x).next_up());
        assert_eq!(f32_down(0.5), 0.5);
        assert_eq!(f32_up(0.5), 0.5);
    }
}
