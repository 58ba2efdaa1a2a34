//! What the window draws over the image for an inspected pixel
//! ([`crate::inspect::Inspection`]): world-space line segments for its rays
//! (origin to hit), the cells of the k-d tree their walks visited (wireframe
//! boxes) and the split planes they crossed (the plane's rectangle inside
//! its node's cell), each coloured by what it is; and the counts the title
//! shows. Pure: the GPU side is `overlay.rs`.

use std::collections::BTreeMap;

use bytemuck::{Pod, Zeroable};
use glam::Vec3;

use crate::geometry::Aabb;
use crate::inspect::{InspectedRay, Inspection, Step};
use crate::layout::KdNode;

/// What a line shows; each has its own colour ([`LineKind::colour`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum LineKind {
    /// A leaf cell some walk visited (and tested objects in, or skipped).
    Leaf,
    /// The cell of the leaf where a ray's hit was found.
    HitLeaf,
    /// A split plane some walk crossed, inside its node's cell.
    SplitPlane,
    Primary,
    Shadow,
    Reflected,
    Refracted,
    /// A path tracer's sampled next ray.
    Bounce,
}

impl LineKind {
    /// Linear RGB in 0..=1, written to the window's (non-sRGB) target as is.
    pub fn colour(self) -> [f32; 3] {
        match self {
            LineKind::Leaf => [0.25, 0.45, 1.0],
            LineKind::HitLeaf => [1.0, 0.15, 0.15],
            LineKind::SplitPlane => [0.2, 0.85, 0.3],
            LineKind::Primary => [1.0, 1.0, 1.0],
            LineKind::Shadow => [1.0, 0.85, 0.1],
            LineKind::Reflected => [1.0, 0.25, 1.0],
            LineKind::Refracted => [0.1, 0.9, 1.0],
            LineKind::Bounce => [1.0, 0.55, 0.1],
        }
    }

    /// The kind of a ray's line, by the inspection's `kind` name.
    fn of_ray(kind: &str) -> LineKind {
        match kind {
            "shadow" => LineKind::Shadow,
            "reflected" => LineKind::Reflected,
            "refracted" => LineKind::Refracted,
            "bounce" => LineKind::Bounce,
            _ => LineKind::Primary,
        }
    }
}

/// One segment, in scene units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Line {
    pub a: Vec3,
    pub b: Vec3,
    pub kind: LineKind,
}

/// A vertex of the line shader (shaders/overlay.wgsl's `VertexIn`).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct LineVertex {
    pub position: [f32; 3],
    pub colour: [f32; 3],
}

/// Each node's cell, by descending the splits from the root's (`root`,
/// the kernel's `scene_min`/`scene_max`): an inner node's lower child (at
/// i + 1) keeps the part below its split, its upper child (at `index`) the
/// part above. None for a node no descent reaches; a malformed tree (a
/// child out of range, or reached twice) gives None or its first cell,
/// never a panic.
pub fn node_cells(nodes: &[KdNode], root: Aabb) -> Vec<Option<Aabb>> {
    let mut cells = vec![None; nodes.len()];
    let mut stack = vec![(0usize, root)];
    while let Some((i, cell)) = stack.pop() {
        let Some(slot) = cells.get_mut(i) else {
            continue;
        };
        if slot.is_some() {
            continue;
        }
        *slot = Some(cell);
        let n = nodes[i];
        if n.kind > 2 {
            continue; // a leaf
        }
        let axis = n.kind as usize;
        // Inside the cell, so that a bad split makes no inverted box.
        let split = n.split.max(cell.min[axis]).min(cell.max[axis]);
        let (mut lower, mut upper) = (cell, cell);
        lower.max[axis] = split;
        upper.min[axis] = split;
        stack.push((n.index as usize, upper));
        stack.push((i + 1, lower));
    }
    cells
}

/// The leaf (node index) where `ray`'s hit was found: the last leaf of its
/// walk that tested the hit object and hit it. None without a hit or a walk
/// (brute force).
pub fn hit_leaf(ray: &InspectedRay) -> Option<usize> {
    let hit = ray.hit.as_ref()?;
    ray.walk.iter().rev().find_map(|step| match step {
        Step::Leaf { leaf, tested, .. }
            if tested.iter().any(|t| t.hit && t.object == hit.object) =>
        {
            Some(*leaf)
        }
        _ => None,
    })
}

/// How far along `ray` its line goes: to its hit; missing, to the end of
/// its query (a shadow ray's light), else where it leaves the scene's box,
/// else `far`.
pub fn ray_length(ray: &InspectedRay, far: f32) -> f32 {
    let t = match (&ray.hit, ray.t_limit, ray.t_interval) {
        (Some(hit), _, _) => hit.t,
        (None, Some(limit), _) => limit,
        (None, None, Some([_, t1])) => t1,
        (None, None, None) => far,
    };
    if t.is_finite() && t >= 0.0 {
        t
    } else {
        far
    }
}

/// How long a ray that misses everything is drawn, in scene units: twice
/// the diagonal of the scene's box `bounds` (1 for an empty or unbounded
/// box).
pub fn miss_length(bounds: &Aabb) -> f32 {
    let d = (bounds.max - bounds.min).length();
    if d.is_finite() && d > 0.0 {
        2.0 * d
    } else {
        1.0
    }
}

/// The 12 edges of `cell`.
pub fn box_edges(cell: &Aabb) -> [(Vec3, Vec3); 12] {
    let corner = |i: usize| {
        Vec3::new(
            if i & 1 == 0 { cell.min.x } else { cell.max.x },
            if i & 2 == 0 { cell.min.y } else { cell.max.y },
            if i & 4 == 0 { cell.min.z } else { cell.max.z },
        )
    };
    // Corners that differ in one bit share an edge.
    let mut edges = [(Vec3::ZERO, Vec3::ZERO); 12];
    let mut n = 0;
    for i in 0..8 {
        for bit in [1, 2, 4] {
            if i & bit == 0 {
                edges[n] = (corner(i), corner(i | bit));
                n += 1;
            }
        }
    }
    edges
}

/// The 4 edges of the rectangle where the plane `axis` = `split` cuts
/// `cell`.
pub fn plane_edges(cell: &Aabb, axis: usize, split: f32) -> [(Vec3, Vec3); 4] {
    let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
    let point = |a: f32, b: f32| {
        let mut p = Vec3::ZERO;
        p[axis] = split;
        p[u] = a;
        p[v] = b;
        p
    };
    let (u0, u1, v0, v1) = (cell.min[u], cell.max[u], cell.min[v], cell.max[v]);
    let corners = [point(u0, v0), point(u1, v0), point(u1, v1), point(u0, v1)];
    [
        (corners[0], corners[1]),
        (corners[1], corners[2]),
        (corners[2], corners[3]),
        (corners[3], corners[0]),
    ]
}

/// The lines of `inspection`: the cells its walks visited (each once; a
/// hit leaf of any ray in [`LineKind::HitLeaf`]), the split planes they
/// crossed (each once), then each ray from its origin over
/// [`ray_length`]. `cells` are [`node_cells`] of the tree walked (empty
/// for brute force); `far` is the length of a ray that misses everything.
pub fn overlay_lines(inspection: &Inspection, cells: &[Option<Aabb>], far: f32) -> Vec<Line> {
    // Node -> what to draw of it; the larger kind wins (a hit leaf over a
    // visited one).
    let mut drawn: BTreeMap<usize, (LineKind, Option<(usize, f32)>)> = BTreeMap::new();
    let mut mark = |node: usize, kind: LineKind, plane: Option<(usize, f32)>| {
        let entry = drawn.entry(node).or_insert((kind, plane));
        if kind > entry.0 {
            *entry = (kind, plane);
        }
    };
    for ray in &inspection.rays {
        let hit = hit_leaf(ray);
        for step in &ray.walk {
            match step {
                Step::Leaf { leaf, .. } if Some(*leaf) == hit => {
                    mark(*leaf, LineKind::HitLeaf, None)
                }
                Step::Leaf { leaf, .. } => mark(*leaf, LineKind::Leaf, None),
                Step::Node {
                    node,
                    axis,
                    split,
                    t_split: Some(_),
                    ..
                } => {
                    let a = ["x", "y", "z"].iter().position(|n| n == axis).unwrap_or(0);
                    mark(*node, LineKind::SplitPlane, Some((a, *split)));
                }
                _ => {}
            }
        }
    }
    let mut lines = Vec::new();
    for (node, (kind, plane)) in drawn {
        let Some(Some(cell)) = cells.get(node) else {
            continue;
        };
        let edges: Vec<(Vec3, Vec3)> = match plane {
            Some((axis, split)) => plane_edges(cell, axis, split).to_vec(),
            None => box_edges(cell).to_vec(),
        };
        lines.extend(edges.into_iter().map(|(a, b)| Line { a, b, kind }));
    }
    for ray in &inspection.rays {
        let origin = Vec3::from(ray.origin);
        let end = origin + Vec3::from(ray.direction) * ray_length(ray, far);
        lines.push(Line {
            a: origin,
            b: end,
            kind: LineKind::of_ray(ray.kind),
        });
    }
    lines
}

/// Two vertices per line, for a LineList draw.
pub fn line_vertices(lines: &[Line]) -> Vec<LineVertex> {
    lines
        .iter()
        .flat_map(|l| {
            let colour = l.kind.colour();
            [l.a, l.b].map(|p| LineVertex {
                position: p.to_array(),
                colour,
            })
        })
        .collect()
}

/// The pixel's work summed over its rays, for the title.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Totals {
    pub rays: u32,
    pub nodes: u32,
    pub leaves: u32,
    pub tests: u32,
    pub restarts: u32,
}

pub fn totals(inspection: &Inspection) -> Totals {
    inspection.rays.iter().fold(
        Totals {
            rays: inspection.rays.len() as u32,
            ..Totals::default()
        },
        |t, r| Totals {
            nodes: t.nodes + r.counts.nodes,
            leaves: t.leaves + r.counts.leaves,
            tests: t.tests + r.counts.tests,
            restarts: t.restarts + r.counts.restarts,
            ..t
        },
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::inspect::{build_tree, inspect_scene};
    use crate::kdtree::{BuildStrategy, KdTree, Traversal};
    use crate::window::test_scenes::scene;

    fn inside(p: Vec3, cell: &Aabb, slack: f32) -> bool {
        p.cmpge(cell.min - slack).all() && p.cmple(cell.max + slack).all()
    }

    fn volume(cell: &Aabb) -> f64 {
        (cell.max - cell.min).as_dvec3().element_product()
    }

    /// Every inner node's two children split its cell at its plane: they
    /// share the plane as a face, their union is the parent's cell and
    /// their volumes add up to its volume; every node of a built tree has a
    /// cell.
    #[test]
    fn child_cells_partition_their_parent_at_the_split() {
        for (name, strategy) in [
            ("scenes/mirrors.toml", BuildStrategy::Sah),
            ("scenes/torus.toml", BuildStrategy::Median),
            ("scenes/cornell_box.toml", BuildStrategy::Sah),
        ] {
            let tree = build_tree(&scene(name, 8, 8), strategy);
            assert!(tree.nodes.len() > 3, "{name}: a tree of one leaf");
            let cells = node_cells(&tree.nodes, tree.bounds);
            assert_eq!(cells[0], Some(tree.bounds));
            for (i, n) in tree.nodes.iter().enumerate() {
                let parent = cells[i].unwrap_or_else(|| panic!("{name}: node {i} has no cell"));
                if n.is_leaf() {
                    continue;
                }
                let a = n.kind as usize;
                let lower = cells[i + 1].unwrap();
                let upper = cells[n.index as usize].unwrap();
                assert_eq!(lower.max[a], n.split, "{name}: node {i}");
                assert_eq!(upper.min[a], n.split, "{name}: node {i}");
                assert_eq!(lower.min, parent.min, "{name}: node {i}");
                assert_eq!(upper.max, parent.max, "{name}: node {i}");
                for other in (0..3).filter(|&o| o != a) {
                    assert_eq!(lower.max[other], parent.max[other]);
                    assert_eq!(upper.min[other], parent.min[other]);
                }
                let sum = volume(&lower) + volume(&upper);
                assert!((sum - volume(&parent)).abs() <= 1e-6 * volume(&parent).max(1e-12));
            }
        }
    }

    /// A tree whose child indices point back up or out of range gives
    /// cells for what it reaches and no panic.
    #[test]
    fn a_malformed_tree_gives_cells_without_panicking() {
        let root = Aabb {
            min: Vec3::ZERO,
            max: Vec3::ONE,
        };
        let inner = |index| KdNode {
            kind: 0,
            split: 7.0, // outside the cell
            index,
            count: 0,
        };
        let nodes = [inner(0), inner(99)];
        let cells = node_cells(&nodes, root);
        assert_eq!(cells[0], Some(root));
        let child = cells[1].unwrap();
        assert!(child.min.cmple(child.max).all(), "{child:?}");
        assert!(node_cells(&[], root).is_empty());
    }

    /// Every ray's hit point lies in the cell of its hit leaf, on scenes
    /// with reflections and glass, for each walk.
    #[test]
    fn a_hit_point_lies_inside_its_hit_leafs_cell() {
        let mut checked = 0;
        for (name, pixels) in [
            ("scenes/mirrors.toml", [(32, 18), (10, 30), (50, 5)]),
            ("scenes/glass.toml", [(32, 18), (20, 20), (40, 12)]),
            ("scenes/cornell_box.toml", [(32, 18), (5, 30), (60, 3)]),
        ] {
            let scene = scene(name, 64, 36);
            let tree = build_tree(&scene, BuildStrategy::Sah);
            let cells = node_cells(&tree.nodes, tree.bounds);
            let slack = 1e-4 * (tree.bounds.max - tree.bounds.min).length();
            for traversal in [Traversal::Restart, Traversal::Ropes, Traversal::ShortStack] {
                for pixel in pixels {
                    let inspection =
                        inspect_scene(&scene, Some(tree.clone()), traversal, pixel).unwrap();
                    for ray in &inspection.rays {
                        let Some(hit) = &ray.hit else { continue };
                        let leaf = hit_leaf(ray).unwrap_or_else(|| {
                            panic!("{name} {pixel:?} {traversal:?}: a hit without a hit leaf")
                        });
                        let cell = cells[leaf].unwrap();
                        assert!(
                            inside(Vec3::from(hit.point), &cell, slack),
                            "{name} {pixel:?} {traversal:?}: {:?} outside leaf {leaf}'s {cell:?}",
                            hit.point
                        );
                        checked += 1;
                    }
                }
            }
        }
        assert!(checked > 30, "only {checked} hits");
    }

    /// The lines of an inspected pixel: each ray once, from its origin to
    /// its hit point (or the end of its search), in its kind's colour; 12
    /// edges for each distinct leaf visited, one of them red per hit; 4 for
    /// each plane crossed, lying in that plane inside its node's cell.
    #[test]
    fn lines_show_each_ray_and_the_cells_and_planes_of_its_walk() {
        let scene = scene("scenes/mirrors.toml", 64, 36);
        let tree = build_tree(&scene, BuildStrategy::Sah);
        let cells = node_cells(&tree.nodes, tree.bounds);
        let inspection =
            inspect_scene(&scene, Some(tree.clone()), Traversal::Ropes, (32, 18)).unwrap();
        assert!(inspection.rays.len() >= 3);
        let lines = overlay_lines(&inspection, &cells, 100.0);
        let ray_lines: Vec<&Line> = lines
            .iter()
            .filter(|l| l.kind >= LineKind::Primary)
            .collect();
        assert_eq!(ray_lines.len(), inspection.rays.len());
        for (line, ray) in ray_lines.iter().zip(&inspection.rays) {
            assert_eq!(line.a, Vec3::from(ray.origin));
            assert_eq!(line.kind, LineKind::of_ray(ray.kind));
            let end = match (&ray.hit, ray.t_limit) {
                (Some(hit), _) => Vec3::from(hit.point),
                (None, Some(limit)) => Vec3::from(ray.origin) + Vec3::from(ray.direction) * limit,
                (None, None) => {
                    let t1 = ray.t_interval.map_or(100.0, |t| t[1]);
                    Vec3::from(ray.origin) + Vec3::from(ray.direction) * t1
                }
            };
            assert!((line.b - end).length() < 1e-4, "{ray:?}: {line:?}");
        }
        let mut leaves = std::collections::BTreeSet::new();
        let mut planes = std::collections::BTreeSet::new();
        for ray in &inspection.rays {
            for step in &ray.walk {
                match step {
                    Step::Leaf { leaf, .. } => {
                        leaves.insert(*leaf);
                    }
                    Step::Node {
                        node,
                        t_split: Some(_),
                        ..
                    } => {
                        planes.insert(*node);
                    }
                    _ => {}
                }
            }
        }
        let count = |kind| lines.iter().filter(|l| l.kind == kind).count();
        let hits = inspection
            .rays
            .iter()
            .filter_map(hit_leaf)
            .collect::<std::collections::BTreeSet<_>>();
        assert!(!hits.is_empty() && !planes.is_empty());
        assert_eq!(count(LineKind::HitLeaf), 12 * hits.len());
        assert_eq!(count(LineKind::Leaf), 12 * (leaves.len() - hits.len()));
        assert_eq!(count(LineKind::SplitPlane), 4 * planes.len());
        for line in lines.iter().filter(|l| l.kind == LineKind::SplitPlane) {
            let on_a_crossed_plane = planes.iter().any(|&n| {
                let node = tree.nodes[n];
                let a = node.kind as usize;
                let cell = cells[n].unwrap();
                line.a[a] == node.split
                    && line.b[a] == node.split
                    && inside(line.a, &cell, 0.0)
                    && inside(line.b, &cell, 0.0)
            });
            assert!(on_a_crossed_plane, "{line:?}");
        }
        assert_eq!(line_vertices(&lines).len(), 2 * lines.len());
        let t = totals(&inspection);
        assert_eq!(t.rays as usize, inspection.rays.len());
        assert_eq!(
            t.nodes,
            inspection.rays.iter().map(|r| r.counts.nodes).sum::<u32>()
        );
        assert!(t.leaves >= leaves.len() as u32 && t.tests > 0);
    }

    /// Brute force has no walk: the rays only, a missing ray as far as the
    /// given length.
    #[test]
    fn brute_force_draws_rays_without_cells() {
        let scene = scene("scenes/seed.toml", 32, 32);
        let inspection = inspect_scene(&scene, None, Traversal::Ropes, (0, 0)).unwrap();
        let lines = overlay_lines(&inspection, &[], 50.0);
        assert_eq!(lines.len(), inspection.rays.len());
        assert!(lines.iter().all(|l| l.kind >= LineKind::Primary));
        let primary = &inspection.rays[0];
        if primary.hit.is_none() {
            assert!((lines[0].b - lines[0].a).length() > 49.9);
        }
        // A single-leaf tree: one box.
        let single = KdTree::single_leaf(3, tree_box());
        let cells = node_cells(&single.nodes, single.bounds);
        assert_eq!(cells, vec![Some(tree_box())]);
    }

    fn tree_box() -> Aabb {
        Aabb {
            min: Vec3::splat(-1.0),
            max: Vec3::splat(2.0),
        }
    }

    #[test]
    fn box_and_plane_edges_trace_the_cell() {
        assert_eq!(miss_length(&tree_box()), 2.0 * 27f32.sqrt());
        assert_eq!(miss_length(&Aabb::EMPTY), 1.0);
        let cell = tree_box();
        let edges = box_edges(&cell);
        for (a, b) in edges {
            // Each edge runs along one axis, the cell's full length.
            let d = (b - a).abs();
            assert_eq!(d.cmpeq(Vec3::ZERO).bitmask().count_ones(), 2, "{a} {b}");
            assert_eq!(d.max_element(), 3.0);
        }
        let plane = plane_edges(&cell, 1, 0.5);
        for (a, b) in plane {
            assert_eq!((a.y, b.y), (0.5, 0.5));
            assert!(inside(a, &cell, 0.0) && inside(b, &cell, 0.0));
        }
        let perimeter: f32 = plane.iter().map(|(a, b)| (b - a).length()).sum();
        assert_eq!(perimeter, 12.0);
    }
}
