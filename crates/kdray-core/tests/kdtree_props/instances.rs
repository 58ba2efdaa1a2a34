//! The two-level structure over instances (`kdray_core::two_level`): every
//! walk through the top tree and each shape's tree finds what brute force
//! finds over all instances' triangles carried into the world, on random
//! instance sets (mirrored, non-uniformly scaled, overlapping, coincident
//! and nested instances); and its memory grows with the unique triangles
//! plus the instances, where the flattened structure's grows with their
//! product.

use super::*;
use common::strategies::{direction, size, vec3};
use glam::{DAffine3, DMat3, DQuat, DVec3, Vec3};
use kdray_core::geometry::TriangleF32;
use kdray_core::kdtree::traverse::closest_hit_brute;
use kdray_core::two_level::{flattened_bytes, shape_ray, InstanceHit, ShapeTree, TwoLevel};

/// A shape: 1 to 24 triangles about its origin, of the walks' sizes
/// (tiny to huge), some axis-aligned.
fn shape() -> impl Strategy<Value = Vec<TriangleF32>> {
    let triangle = prop_oneof![
        3 => (vec3(1.5), size(), vec3(1.0), vec3(1.0))
            .prop_map(|(c, s, a, b)| TriangleF32 { v: [c, c + a * s, c + b * s] }),
        1 => (vec3(1.5), size(), 0usize..3).prop_map(|(c, s, axis)| {
            let (u, v) = (Vec3::AXES[(axis + 1) % 3], Vec3::AXES[(axis + 2) % 3]);
            TriangleF32 { v: [c, c + u * s, c + v * s] }
        }),
    ];
    prop::collection::vec(triangle, 1..24)
}

/// A transform: turned about a random axis, scaled per axis by 0.2 to 3,
/// each axis mirrored or not, and moved within the scene.
fn transform() -> impl Strategy<Value = DAffine3> {
    (
        vec3(1.0),
        -3.2f64..3.2,
        (0.2f64..3.0, 0.2f64..3.0, 0.2f64..3.0),
        (any::<bool>(), any::<bool>(), any::<bool>()),
        vec3(20.0),
    )
        .prop_map(|(axis, angle, (x, y, z), (mx, my, mz), t)| {
            let axis = axis.as_dvec3().try_normalize().unwrap_or(DVec3::Z);
            let sign = |m: bool| if m { -1.0 } else { 1.0 };
            let scale = DVec3::new(x * sign(mx), y * sign(my), z * sign(mz));
            DAffine3 {
                matrix3: DMat3::from_quat(DQuat::from_axis_angle(axis, angle))
                    * DMat3::from_diagonal(scale),
                translation: t.as_dvec3(),
            }
        })
}

/// Shapes and instances of them: random transforms, then for some of them
/// a coincident copy and a nested one (the same shape, scaled about its
/// instance's origin by 0.5 or 2: one box inside the other).
fn instance_set() -> impl Strategy<Value = (Vec<Vec<TriangleF32>>, Vec<(u32, DAffine3)>)> {
    prop::collection::vec(shape(), 1..4).prop_flat_map(|shapes| {
        let n = shapes.len() as u32;
        let instances = prop::collection::vec((0..n, transform()), 1..60);
        let copies = prop::collection::vec((any::<prop::sample::Index>(), any::<bool>()), 0..4);
        (Just(shapes), instances, copies).prop_map(|(shapes, mut instances, copies)| {
            for (pick, nested) in copies {
                let (shape, t) = instances[pick.index(instances.len())];
                let t = match nested {
                    false => t,
                    true => {
                        // Scaled by 2 about its box's centre: the copy's
                        // box holds the original's.
                        let mut b = kdray_core::geometry::Aabb::EMPTY;
                        for tri in &shapes[shape as usize] {
                            b = b.union(tri.bounds());
                        }
                        let c = ((b.min + b.max) * 0.5).as_dvec3();
                        t * DAffine3::from_translation(c)
                            * DAffine3::from_scale(DVec3::splat(2.0))
                            * DAffine3::from_translation(-c)
                    }
                };
                instances.push((shape, t));
            }
            (shapes, instances)
        })
    })
}

/// Every instance's triangles carried into the world (in f64, then
/// rounded to f32, as flattening does), in instance order; and where each
/// instance's start.
fn world_triangles(
    shapes: &[Vec<TriangleF32>],
    instances: &[(u32, DAffine3)],
) -> (Primitives, Vec<usize>) {
    let mut prims = Primitives::default();
    let mut starts = Vec::new();
    for (shape, t) in instances {
        starts.push(prims.triangles.len());
        for tri in &shapes[*shape as usize] {
            prims.triangles.push(TriangleF32 {
                v: tri.v.map(|v| t.transform_point3(v.as_dvec3()).as_vec3()),
            });
        }
    }
    (prims, starts)
}

/// Whether `ray` at `t` meets world triangle `tri` within a hair of one of
/// its edges, or runs nearly in its plane: where the world test and the
/// shape-space test, rounding differently, may disagree.
fn grazes(tri: &TriangleF32, ray: &Ray, t: f32) -> bool {
    let [a, b, c] = tri.v.map(|v| v.as_dvec3());
    let p = ray.origin.as_dvec3() + ray.dir.as_dvec3() * t as f64;
    let n = (b - a).cross(c - a);
    let nn = n.length_squared();
    let bary = [
        (c - b).cross(p - b).dot(n) / nn,
        (a - c).cross(p - c).dot(n) / nn,
        (b - a).cross(p - a).dot(n) / nn,
    ];
    let in_plane = n.normalize().dot(ray.dir.as_dvec3().normalize()).abs() < 1e-3;
    in_plane || bary.iter().any(|x| x.abs() < 1e-3)
}

/// Brute force in each shape's space: every instance's triangles tested
/// with the ray carried there, the arithmetic the two-level walk's leaves
/// do. The nearest hit.
fn brute_in_shapes(two: &TwoLevel, ray: &Ray, t_limit: f32) -> Option<InstanceHit> {
    let mut best: Option<InstanceHit> = None;
    for (i, inst) in two.instances.iter().enumerate() {
        let shape = &two.shapes[inst.shape as usize];
        let local = shape_ray(&inst.to_shape, ray);
        if let Some(h) = closest_hit_brute(&shape.prims, &local, t_limit) {
            if best.is_none_or(|b| h.t < b.t) {
                best = Some(InstanceHit {
                    instance: i as u32,
                    triangle: h.object,
                    t: h.t,
                });
            }
        }
    }
    best
}

fn build(shapes: &[Vec<TriangleF32>], instances: &[(u32, DAffine3)]) -> TwoLevel {
    let trees = shapes.iter().cloned().map(ShapeTree::build).collect();
    TwoLevel::build(trees, instances)
}

proptest! {
    #![proptest_config(common::proptest_config(96))]

    #[test]
    fn two_level_walks_find_what_brute_force_finds_over_all_instances(
        (shapes, instances) in instance_set(),
        rays in prop::collection::vec((vec3(25.0), direction()), 1..12),
    ) {
        let two = build(&shapes, &instances);
        prop_assert_eq!(two.instances.len(), instances.len(), "every transform is invertible");
        let (world, starts) = world_triangles(&shapes, &instances);
        let world_index = |h: &InstanceHit| starts[h.instance as usize] + h.triangle as usize;
        for (origin, dir) in rays {
            let ray = Ray { origin, dir };
            let exact = brute_in_shapes(&two, &ray, T_INFINITY);
            let in_world = closest_hit_brute(&world, &ray, T_INFINITY);
            for walk in Traversal::ALL {
                let hit = two.closest_hit(walk, &ray, T_INFINITY);
                // Against brute force in the shapes' spaces: the same
                // triangle tests, so the same hit or miss.
                match (hit, exact) {
                    (None, None) => {}
                    (Some(h), Some(b)) => prop_assert!(
                        (h.t - b.t).abs() <= 1e-4 * b.t.max(1.0),
                        "{}: two-level {:?}, brute force {:?}, ray {:?}", walk, h, b, ray
                    ),
                    (h, b) => prop_assert!(false, "{}: two-level {:?}, brute force {:?}, ray {:?}", walk, h, b, ray),
                }
                // Against brute force over the world's triangles: the same
                // nearest distance, unless the nearer of the two grazes an
                // edge that the two roundings see on opposite sides.
                let same = match (hit, in_world) {
                    (None, None) => true,
                    (Some(h), Some(w)) => (h.t - w.t).abs() <= 1e-4 * w.t.max(1.0),
                    _ => false,
                };
                if !same {
                    let nearer = match (hit, in_world) {
                        (Some(h), Some(w)) if h.t < w.t => (world_index(&h), h.t),
                        (Some(h), None) => (world_index(&h), h.t),
                        (_, Some(w)) => (w.object as usize, w.t),
                        (None, None) => unreachable!(),
                    };
                    prop_assert!(
                        grazes(&world.triangles[nearer.0], &ray, nearer.1),
                        "{}: two-level {:?}, world brute force {:?}, ray {:?}", walk, hit, in_world, ray
                    );
                }
                // Any hit: short of the nearest hit, nothing; past it,
                // something.
                if let Some(b) = exact {
                    prop_assert!(two.any_hit(walk, &ray, b.t * 1.001 + 1e-6), "{}: any-hit missed {:?}", walk, b);
                    if b.t > 1e-3 {
                        let short = b.t * 0.999;
                        let brute_any = brute_in_shapes(&two, &ray, short).is_some_and(|h| h.t < short);
                        prop_assert_eq!(two.any_hit(walk, &ray, short), brute_any, "{}: any-hit short of {:?}", walk, b);
                    }
                } else {
                    prop_assert!(!two.any_hit(walk, &ray, T_INFINITY), "{}: any-hit found what brute force did not", walk);
                }
            }
        }
    }
}

/// A grid of `count` triangles in the unit square, as a shape.
fn grid_shape(count: usize) -> Vec<TriangleF32> {
    (0..count)
        .map(|i| {
            let (x, y) = ((i % 50) as f32 * 0.02, (i / 50) as f32 * 0.02);
            TriangleF32 {
                v: [
                    Vec3::new(x, y, 0.0),
                    Vec3::new(x + 0.02, y, 0.0),
                    Vec3::new(x, y + 0.02, 0.0),
                ],
            }
        })
        .collect()
}

/// `count` instances of shape 0 on a line, turned and scaled in turn.
fn row_of_instances(count: usize) -> Vec<(u32, DAffine3)> {
    (0..count)
        .map(|i| {
            let turn = DQuat::from_rotation_y(i as f64 * 0.7);
            let scale = DVec3::new(
                1.0 + (i % 3) as f64,
                1.0,
                if i % 2 == 0 { 1.0 } else { -1.0 },
            );
            (
                0,
                DAffine3::from_scale_rotation_translation(
                    scale,
                    turn,
                    DVec3::new(i as f64 * 1.5, 0.0, 0.0),
                ),
            )
        })
        .collect()
}

/// The flattened structure's bytes: every instance's world triangles and
/// one tree over them.
fn flattened(shapes: &[Vec<TriangleF32>], instances: &[(u32, DAffine3)]) -> usize {
    let (prims, _) = world_triangles(shapes, instances);
    let tree = KdTree::for_primitives(&prims);
    let ropes = Ropes::build(&tree);
    flattened_bytes(&prims, &tree, &ropes)
}

#[test]
fn two_level_memory_grows_with_unique_triangles_plus_instances() {
    let bytes = |triangles: usize, instances: usize| {
        let shapes = vec![grid_shape(triangles)];
        let placed = row_of_instances(instances);
        (build(&shapes, &placed).bytes(), flattened(&shapes, &placed))
    };
    let (few, few_flat) = bytes(100, 8);
    let (few_more_instances, few_more_instances_flat) = bytes(100, 32);
    let (many, many_flat) = bytes(400, 8);
    let (many_more_instances, many_more_instances_flat) = bytes(400, 32);
    // An instance costs its record and its share of the top tree, the same
    // few hundred bytes whatever its shape's size.
    for (a, b) in [(few, few_more_instances), (many, many_more_instances)] {
        let per_instance = (b - a) as f64 / 24.0;
        assert!(per_instance < 400.0, "{per_instance} bytes per instance");
    }
    // A unique triangle costs the same however many instances there are.
    let per_triangle = |a: usize, b: usize| (b - a) as f64 / 300.0;
    let (with_few, with_more) = (
        per_triangle(few, many),
        per_triangle(few_more_instances, many_more_instances),
    );
    assert!(
        (with_more - with_few).abs() <= 0.05 * with_few,
        "{with_few} and {with_more} bytes per unique triangle"
    );
    // Flattened, an instance costs its shape's triangles: four times as
    // much for a shape four times as large.
    let flat_per_instance = |a: usize, b: usize| (b - a) as f64 / 24.0;
    let (small, large) = (
        flat_per_instance(few_flat, few_more_instances_flat),
        flat_per_instance(many_flat, many_more_instances_flat),
    );
    assert!(
        large > 3.0 * small,
        "{small} and {large} bytes per flattened instance"
    );
    assert!(many_more_instances * 8 < many_more_instances_flat);
}
