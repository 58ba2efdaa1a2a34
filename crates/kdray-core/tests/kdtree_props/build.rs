//! The build's family of cases: scenes made to stress the clipping of the
//! SAH build with perfect splits (triangles clipped to the cells as
//! polygons), the binned one and the median build: long thin triangles, fans
//! sharing a vertex, triangles lying in and snapped to candidate planes,
//! coincident copies. Every point of a triangle (vertices, edges, points
//! exactly on split planes) lies in a leaf that references it.

use glam::{DVec3, Vec3};
use kdray_core::geometry::{Aabb, Primitives, Ray, SphereF32, TriangleF32, T_INFINITY};
use kdray_core::kdtree::traverse::{closest_hit, closest_hit_brute};
use kdray_core::kdtree::{build_primitives, BuildParams, BuildStrategy, KdTree};
use proptest::prelude::*;

use super::common::strategies::{direction, traversal_cost, unit, vec3};
use super::{check_any, check_closest, check_flat_layout, Walks};

/// Coordinates on a half-unit grid: many objects then share planes, and
/// edges and faces lie in the planes the build cuts at.
fn snapped(range: i32) -> impl Strategy<Value = Vec3> {
    (-range..=range, -range..=range, -range..=range)
        .prop_map(|(x, y, z)| Vec3::new(x as f32, y as f32, z as f32) * 0.5)
}

#[derive(Debug, Clone)]
enum Object {
    Sphere(SphereF32),
    Triangles(Vec<TriangleF32>),
}

fn triangle(v: [Vec3; 3]) -> Object {
    Object::Triangles(vec![TriangleF32 { v }])
}

fn object() -> impl Strategy<Value = Object> {
    prop_oneof![
        // Long thin triangles: 3 to 25 units long, 1e-4 to 0.3 wide.
        (
            vec3(10.0),
            unit(),
            3.0f32..25.0,
            0.0f32..1.0,
            unit(),
            prop_oneof![1e-4f32..1e-2, 1e-2f32..0.3]
        )
            .prop_map(|(a, d, len, along, side, width)| {
                let b = a + d * len;
                triangle([a, b, a + d * (len * along) + side * width])
            }),
        // Long thin triangles lying in an axis plane.
        (
            snapped(16),
            0usize..3,
            -12.0f32..12.0,
            -12.0f32..12.0,
            -1.0f32..1.0,
            -1.0f32..1.0,
            1e-3f32..0.5
        )
            .prop_map(|(a, axis, du, dv, au, av, width)| {
                let (u, v) = (Vec3::AXES[(axis + 1) % 3], Vec3::AXES[(axis + 2) % 3]);
                let b = a + u * du + v * dv;
                triangle([
                    a,
                    b,
                    a + u * (du * 0.5 + au * width) + v * (dv * 0.5 + av * width),
                ])
            }),
        // A fan: thin triangles sharing one vertex, as a fanned polygon.
        (vec3(10.0), unit(), 0.5f32..8.0, 3usize..24).prop_map(|(centre, axis, radius, n)| {
            let (u, w) = axis.any_orthonormal_pair();
            let rim: Vec<Vec3> = (0..n)
                .map(|i| {
                    let a = std::f32::consts::TAU * i as f32 / n as f32;
                    centre + radius * (a.cos() * u + a.sin() * w)
                })
                .collect();
            Object::Triangles(
                (1..n - 1)
                    .map(|i| TriangleF32 {
                        v: [rim[0], rim[i], rim[i + 1]],
                    })
                    .collect(),
            )
        }),
        // Triangles with snapped vertices: vertices and edges on shared planes.
        (snapped(16), snapped(4), snapped(4)).prop_map(|(a, b, c)| triangle([a, a + b, a + c])),
        // Small random triangles.
        (vec3(10.0), 0.01f32..2.0, unit(), unit()).prop_map(|(c, s, a, b)| triangle([
            c,
            c + a * s,
            c + b * s
        ])),
        (
            vec3(10.0),
            prop_oneof![0.05f32..1.0, 1e-4f32..1e-2, 3.0f32..20.0]
        )
            .prop_map(|(center, radius)| Object::Sphere(SphereF32 { center, radius })),
    ]
}

/// Degenerate triangles (zero area) are left out: they cannot be hit, and
/// scenes refuse them.
fn has_area(t: &TriangleF32) -> bool {
    (t.v[1] - t.v[0]).cross(t.v[2] - t.v[0]).length_squared() > 0.0
}

fn scene() -> impl Strategy<Value = Primitives> {
    (prop::collection::vec(object(), 1..40), 0usize..4).prop_map(|(objects, copies)| {
        let mut prims = Primitives::default();
        for o in objects {
            match o {
                Object::Sphere(s) => prims.spheres.push(s),
                Object::Triangles(ts) => prims.triangles.extend(ts.into_iter().filter(has_area)),
            }
        }
        // Coincident objects: repeat the first few exactly.
        let repeated: Vec<_> = prims.triangles.iter().take(copies).copied().collect();
        prims.triangles.extend(repeated);
        if prims.is_empty() {
            prims.spheres.push(SphereF32 {
                center: Vec3::ZERO,
                radius: 1.0,
            });
        }
        prims
    })
}

/// Build parameters: any strategy; traversal costs 1 (deep trees, many
/// planes), 15 and 40 (the default's). The binned build bins every node of
/// three objects or more, so that these small scenes exercise it.
pub(super) fn params(prims: &Primitives, strategy: BuildStrategy, cost: f32) -> BuildParams {
    BuildParams {
        traversal_cost: cost,
        strategy,
        exact_below: 2,
        ..BuildParams::for_primitives(prims)
    }
}

fn strategy() -> impl Strategy<Value = BuildStrategy> {
    prop::sample::select(BuildStrategy::ALL.to_vec())
}

fn tree_for(prims: &Primitives, strategy: BuildStrategy, cost: f32) -> KdTree {
    build_primitives(prims, params(prims, strategy, cost), 1)
}

/// The leaf a point descends to: below a plane when `p <= split`, as the
/// traversal sends a ray lying in the plane.
fn leaf_ids(tree: &KdTree, p: Vec3) -> &[u32] {
    let mut node = 0usize;
    while !tree.nodes[node].is_leaf() {
        let n = tree.nodes[node];
        node = if p[n.kind as usize] <= n.split {
            node + 1
        } else {
            n.index as usize
        };
    }
    let leaf = tree.nodes[node];
    &tree.leaf_objects[leaf.index as usize..(leaf.index + leaf.count) as usize]
}

fn f64v(v: Vec3) -> DVec3 {
    v.as_dvec3()
}

/// Rounds a point of the triangle computed in f64 to the nearest f32, after
/// clamping it to the triangle's box (which the exact point lies in; the f64
/// computation can leave it by a hair, 5e-17 off a plane the triangle
/// touches, say, which f32 can represent).
fn to_f32(t: &TriangleF32, p: DVec3) -> Vec3 {
    let b = t.bounds();
    p.clamp(f64v(b.min), f64v(b.max)).as_vec3()
}

/// A point of the triangle, from barycentric weights in f64, rounded to the
/// nearest f32 (so it is what an f32 computation of that point gives at best).
fn on_triangle(t: &TriangleF32, a: f64, b: f64) -> Vec3 {
    let (a, b) = if a + b > 1.0 {
        (1.0 - a, 1.0 - b)
    } else {
        (a, b)
    };
    let [p, q, r] = t.v.map(f64v);
    to_f32(t, p + (q - p) * a + (r - p) * b)
}

/// Points where the triangle meets the plane `x[axis] = c`, exactly on the
/// plane: where its edges cross it, and points between two such crossings.
fn on_plane(t: &TriangleF32, axis: usize, c: f32, fractions: &[f64]) -> Vec<Vec3> {
    let v = t.v.map(f64v);
    let c64 = c as f64;
    let mut crossings = Vec::new();
    for i in 0..3 {
        let (p, q) = (v[i], v[(i + 1) % 3]);
        if (p[axis] - c64) * (q[axis] - c64) <= 0.0 && p[axis] != q[axis] {
            let s = (c64 - p[axis]) / (q[axis] - p[axis]);
            let mut x = p + (q - p) * s;
            x[axis] = c64;
            crossings.push(x);
        } else if p[axis] == c64 {
            crossings.push(p);
        }
    }
    let mut points = Vec::new();
    for (i, &x) in crossings.iter().enumerate() {
        for &y in &crossings[i + 1..] {
            for &f in fractions {
                let mut z = x + (y - x) * f;
                z[axis] = c64;
                points.push(to_f32(t, z));
            }
        }
        points.push(to_f32(t, x));
    }
    points
}

fn inner_planes(tree: &KdTree) -> Vec<(usize, f32)> {
    tree.nodes
        .iter()
        .filter(|n| !n.is_leaf())
        .map(|n| (n.kind as usize, n.split))
        .collect()
}

/// What a ray is made from: an origin, a direction, and how to tie it to the
/// scene (see `ray_for`).
type RaySeed = (Vec3, Vec3, u8, usize, f64, f64);

fn ray_seed() -> impl Strategy<Value = RaySeed> {
    (
        vec3(16.0),
        direction(),
        0u8..5,
        any::<usize>(),
        0.0f64..=1.0,
        0.0f64..=1.0,
    )
}

/// Turns a seed into a ray: 0 as drawn; 1 starting on a split plane; 2 lying
/// in a split plane (starting on it, parallel to it); 3 aimed at a point of a
/// triangle (a vertex, an edge or inside); 4 aimed at a triangle's vertex.
fn ray_for(tree: &KdTree, prims: &Primitives, seed: RaySeed) -> Option<Ray> {
    let (mut origin, mut dir, how, pick, a, b) = seed;
    let planes = inner_planes(tree);
    match how {
        1 | 2 if !planes.is_empty() => {
            let (axis, c) = planes[pick % planes.len()];
            origin[axis] = c;
            if how == 2 {
                dir[axis] = 0.0;
                dir = dir.try_normalize()?;
            }
        }
        3 | 4 if !prims.triangles.is_empty() => {
            let t = &prims.triangles[pick % prims.triangles.len()];
            let target = if how == 4 {
                t.v[pick / prims.triangles.len() % 3]
            } else {
                // Snap a third of the weights to an edge.
                let b = if a < 0.33 { 0.0 } else { b };
                on_triangle(t, a, b)
            };
            dir = (target - origin).try_normalize()?;
        }
        _ => {}
    }
    Some(Ray { origin, dir })
}

proptest! {
    #![proptest_config(crate::common::proptest_config(512))]

    /// Every point of every triangle (its vertices, points on its edges and
    /// inside, and points where it meets a split plane, exactly on the
    /// plane) descends to a leaf that references the triangle; every point of
    /// a sphere's box, to one that references the sphere.
    #[test]
    fn every_point_of_a_triangle_is_in_a_leaf_that_references_it(
        prims in scene(),
        strategy in strategy(),
        cost in traversal_cost(),
        samples in prop::collection::vec((0.0f64..=1.0, 0.0f64..=1.0, any::<usize>()), 8),
    ) {
        let tree = tree_for(&prims, strategy, cost);
        let planes = inner_planes(&tree);
        let s = prims.spheres.len();
        for (i, t) in prims.triangles.iter().enumerate() {
            let id = (s + i) as u32;
            let mut points = t.v.to_vec();
            for &(a, b, pick) in &samples {
                points.push(on_triangle(t, a, b));
                points.push(on_triangle(t, a, 0.0)); // on an edge
                points.push(on_triangle(t, 0.0, b));
                points.push(on_triangle(t, a, 1.0 - a));
                if !planes.is_empty() {
                    let (axis, c) = planes[pick % planes.len()];
                    points.extend(on_plane(t, axis, c, &[a, b]));
                }
            }
            // Every plane the triangle crosses, once.
            for &(axis, c) in planes.iter().take(64) {
                points.extend(on_plane(t, axis, c, &[0.5]));
            }
            for p in points {
                prop_assert!(leaf_ids(&tree, p).contains(&id), "triangle {} {:?} missing from the leaf holding {:?}", id, t, p);
            }
        }
        for (id, sphere) in prims.spheres.iter().enumerate() {
            let b = sphere.bounds();
            for &(x, y, pick) in &samples {
                let z = (pick % 1001) as f32 / 1000.0;
                let p = b.min + (b.max - b.min) * Vec3::new(x as f32, y as f32, z);
                prop_assert!(leaf_ids(&tree, p).contains(&(id as u32)), "sphere {} missing from the leaf holding {:?}", id, p);
            }
        }
    }

    #[test]
    fn closest_hit_matches_brute_force(
        prims in scene(),
        strategy in strategy(),
        cost in traversal_cost(),
        rays in prop::collection::vec(ray_seed(), 1..40),
    ) {
        let walks = Walks::new(tree_for(&prims, strategy, cost));
        for seed in rays {
            if let Some(ray) = ray_for(&walks.tree, &prims, seed) {
                check_closest(&walks, &prims, &ray)?;
            }
        }
    }

    #[test]
    fn any_hit_matches_brute_force_on_segments(
        prims in scene(),
        strategy in strategy(),
        cost in traversal_cost(),
        rays in prop::collection::vec((ray_seed(), 0.01f32..40.0), 1..40),
    ) {
        let walks = Walks::new(tree_for(&prims, strategy, cost));
        for (seed, length) in rays {
            let Some(ray) = ray_for(&walks.tree, &prims, seed) else { continue };
            // Segments ending exactly at a hit are ties; step back from them.
            let brute_t = closest_hit_brute(&prims, &ray, T_INFINITY).map(|h| h.t);
            if brute_t.is_some_and(|t| (t - length).abs() <= 1e-4 * length.max(1.0)) {
                continue;
            }
            check_any(&walks, &prims, &ray, length)?;
        }
    }

    /// The layout the kernel relies on (`check_flat_layout`), for every
    /// strategy over primitives.
    #[test]
    fn flat_layout_is_what_the_kernel_assumes(prims in scene(), strategy in strategy(), cost in traversal_cost()) {
        check_flat_layout(&tree_for(&prims, strategy, cost), prims.len())?;
    }
}

/// Cells of the leaves that reference object `id`.
fn cells_referencing(tree: &KdTree, id: u32) -> Vec<Aabb> {
    let mut out = Vec::new();
    tree.visit_cells(|node, cell| {
        if node.is_leaf()
            && tree.leaf_objects[node.index as usize..(node.index + node.count) as usize]
                .contains(&id)
        {
            out.push(*cell);
        }
    });
    out
}

/// Distance from the segment `a`-`b` to the box, by sampling the segment
/// finely (enough for the margin the test allows).
fn segment_box_distance(a: Vec3, b: Vec3, cell: &Aabb) -> f32 {
    (0..=10_000)
        .map(|i| {
            let p = a.lerp(b, i as f32 / 10_000.0);
            (cell.min - p).max(p - cell.max).max(Vec3::ZERO).length()
        })
        .fold(f32::INFINITY, f32::min)
}

/// A sliver along the diagonal of a grid of small spheres: with clipping it
/// is referenced only by leaves it passes through, not by every leaf of its
/// bounding box (the whole scene). The box build referenced it everywhere.
#[test]
fn a_diagonal_sliver_is_referenced_only_where_it_passes() {
    let mut prims = Primitives::default();
    for i in 0..8 {
        for j in 0..8 {
            for k in 0..8 {
                prims.spheres.push(SphereF32 {
                    center: Vec3::new(i as f32, j as f32, k as f32) * 1.25 + 0.6,
                    radius: 0.2,
                });
            }
        }
    }
    let (a, b) = (Vec3::ZERO, Vec3::splat(10.0));
    prims.triangles.push(TriangleF32 {
        v: [a, b, b - Vec3::new(0.0, 0.0, 0.01)],
    });
    let id = prims.spheres.len() as u32;
    for strategy in BuildStrategy::ALL {
        let tree = tree_for(&prims, strategy, 15.0);
        let cells = cells_referencing(&tree, id);
        let leaves = tree.nodes.iter().filter(|n| n.is_leaf()).count();
        assert!(leaves > 100, "{strategy}: a deep tree ({leaves} leaves)");
        assert!(!cells.is_empty());
        for cell in &cells {
            let d = segment_box_distance(a, b, cell);
            assert!(
                d < 0.02,
                "{strategy}: the sliver is {d} away from a cell referencing it: {cell:?}"
            );
        }
    }
}

/// The median build is the seed's: the root splits x between the two middle
/// centres, the next level y, and separated objects end in leaves of one.
#[test]
fn the_median_build_halves_by_centres_down_to_single_objects() {
    let mut prims = Primitives::default();
    for i in 0..4 {
        for j in 0..4 {
            for k in 0..4 {
                prims.spheres.push(SphereF32 {
                    center: Vec3::new(i as f32, j as f32, k as f32) * 2.0,
                    radius: 0.5,
                });
            }
        }
    }
    let tree = tree_for(&prims, BuildStrategy::Median, 40.0);
    let root = tree.nodes[0];
    assert_eq!((root.kind, root.split), (0, 3.0), "root plane");
    let below = tree.nodes[1];
    assert_eq!((below.kind, below.split), (1, 3.0), "second level plane");
    let leaves: Vec<_> = tree.nodes.iter().filter(|n| n.is_leaf()).collect();
    assert_eq!(leaves.len(), 64);
    assert!(leaves.iter().all(|l| l.count == 1));
    assert_eq!(tree.max_depth, 6);
}

/// Rays through the gear scene against brute force, both builds:
/// long thin fan triangles meeting at 16 shared vertices.
#[test]
fn gear_scene_rays_match_brute_force() {
    use kdray_core::random_scene::{random_scene, RandomSceneSpec, SceneKind};
    let scene = random_scene(&RandomSceneSpec::new(SceneKind::Gears, 4_578));
    let prims = Primitives::from_scene(&scene);
    let mut rng = kdray_core::random_scene::SplitMix64::new(9);
    for strategy in BuildStrategy::ALL {
        let tree = KdTree::build_for(&prims, params(&prims, strategy, 40.0));
        for i in 0..3000 {
            let origin = Vec3::new(
                rng.range(-4.0, 4.0) as f32,
                rng.range(-4.0, 4.0) as f32,
                rng.range(-4.0, 8.5) as f32,
            );
            // Aimed at a vertex (every third ray) or a point of a triangle.
            let t = &prims.triangles[rng.below(prims.triangles.len() as u64) as usize];
            let target = if i % 3 == 0 {
                t.v[rng.below(3) as usize]
            } else {
                on_triangle(t, rng.next_f64(), rng.next_f64())
            };
            let Some(dir) = (target - origin).try_normalize() else {
                continue;
            };
            let ray = Ray { origin, dir };
            let kd = closest_hit(&tree, &prims, &ray, T_INFINITY).map(|h| h.t);
            let brute = closest_hit_brute(&prims, &ray, T_INFINITY).map(|h| h.t);
            // Triangles sharing the vertex aimed at may give a hair
            // different t for the same point: a tie.
            let tie = |k: f32, b: f32| (k - b).abs() <= 1e-4 * b.max(1.0);
            assert!(
                kd.is_none() && brute.is_none() || kd.zip(brute).is_some_and(|(k, b)| tie(k, b)),
                "{strategy}: kd {kd:?} brute {brute:?} ray {ray:?}"
            );
        }
    }
}
