//! Property tests of the GPU kernel's walks, ray by ray, through its debug
//! entry point `trace_rays` (src/gpu/ray_query.rs): on the same random
//! scenes, trees and rays as the CPU mirror's tests (tests/common/
//! strategies.rs), the kernel's k-d walk finds what the kernel's brute-force
//! loop finds. Both run the same intersection code on the same device, so
//! this isolates the walk; the image tests compare the kernel with the CPU.
//! The work each walk does (nodes and leaves visited, objects tested) is
//! held against the CPU mirror's count, ray by ray.

use crate::common;

use std::sync::OnceLock;

use common::strategies::{direction, ray_for, scene, traversal_cost, tree_for, vec3};
use kdray::geometry::{Primitives, Ray, T_INFINITY};
use kdray::gpu::{Accel, GpuScene, PreparedScene, RayQueries, RayQuery};
use kdray::kdtree::traverse::{self, Hit, WalkCost};
use kdray::kdtree::{KdTree, Ropes, Traversal, WalkQuery, WalkScene};
use kdray::scene::{Scene, Sphere, Triangle};
use proptest::prelude::*;

fn queries() -> &'static RayQueries {
    static QUERIES: OnceLock<RayQueries> = OnceLock::new();
    QUERIES.get_or_init(|| RayQueries::new(common::gpu()).unwrap_or_else(|e| panic!("{e}")))
}

/// A scene holding exactly `prims` (f32 -> f64 -> f32 is exact).
fn scene_of(prims: &Primitives) -> Scene {
    let mut scene = common::scene_from_toml(
        "[camera]\nposition = [0, 0, 30]\nlook_at = [0, 0, 0]\n\
         [[lights]]\nposition = [0, 20, 0]\n[materials.m]\ndiffuse = [1, 1, 1]\n",
    );
    scene.spheres = prims
        .spheres
        .iter()
        .map(|s| Sphere {
            center: s.center.as_dvec3(),
            radius: s.radius as f64,
            material: 0,
        })
        .collect();
    scene.triangles = prims
        .triangles
        .iter()
        .map(|t| Triangle::flat(t.v.map(|v| v.as_dvec3()), 0))
        .collect();
    scene
}

/// The kernel's answers to `rays` over `tree`: brute force's, and each k-d
/// walk's (`Traversal::ALL` order).
fn trace_both(
    prims: &Primitives,
    tree: &KdTree,
    rays: &[RayQuery],
) -> (Vec<Option<Hit>>, Vec<Vec<Option<Hit>>>) {
    let prepared = PreparedScene::with_tree(scene_of(prims), tree.clone());
    assert_eq!(
        prepared.tree.nodes, tree.nodes,
        "the GPU walks the tree built here"
    );
    let ctx = common::gpu();
    let uploaded = GpuScene::upload(ctx, prepared).unwrap_or_else(|e| panic!("{e}"));
    let (buffers, prepared) = (uploaded.buffers(), uploaded.prepared());
    let trace = |accel, walk| {
        queries()
            .trace_counted(ctx, buffers, &prepared.arrays.scene_ids, accel, walk, rays)
            .unwrap_or_else(|e| panic!("{e}"))
            .into_iter()
            .map(|(hit, _)| hit)
            .collect()
    };
    let brute = trace(Accel::Brute, Traversal::Restart);
    let walks = Traversal::ALL
        .iter()
        .map(|&walk| trace(Accel::Kdtree, walk))
        .collect();
    (brute, walks)
}

/// Nearest hits agree: both miss, or both hit at the same t (a different
/// object only at a tie, i.e. coincident objects).
fn check_nearest(
    kd: &[Option<Hit>],
    brute: &[Option<Hit>],
    rays: &[RayQuery],
) -> Result<(), TestCaseError> {
    for ((k, b), q) in kd.iter().zip(brute).zip(rays) {
        match (k, b) {
            (None, None) => {}
            (Some(k), Some(b)) => prop_assert!(
                (k.t - b.t).abs() <= 1e-4 * b.t.max(1.0),
                "t differs: kd {:?} brute {:?} ray {:?}",
                k,
                b,
                q.ray
            ),
            (k, b) => prop_assert!(false, "kd {:?} brute {:?} ray {:?}", k, b, q.ray),
        }
    }
    Ok(())
}

fn nearest(ray: Ray) -> RayQuery {
    RayQuery {
        ray,
        t_limit: T_INFINITY,
        any_hit: false,
    }
}

/// Each walk's hits and costs on the GPU and on the CPU mirror, ray by ray:
/// equal costs (and brute force's, whose loop runs over the GPU's object
/// order). Hits are compared elsewhere; here they only show where the two
/// sides rounded differently, which would explain a cost difference.
fn check_costs(prims: &Primitives, tree: &KdTree, rays: &[RayQuery]) -> Result<(), TestCaseError> {
    let prepared = PreparedScene::with_tree(scene_of(prims), tree.clone());
    let ctx = common::gpu();
    let uploaded = GpuScene::upload(ctx, prepared).unwrap_or_else(|e| panic!("{e}"));
    let (buffers, prepared) = (uploaded.buffers(), uploaded.prepared());
    let ids = &prepared.arrays.scene_ids;
    let tree = &prepared.tree;
    let ropes = Ropes::build(tree);
    let gpu = |accel, walk| {
        queries()
            .trace_counted(ctx, buffers, ids, accel, walk, rays)
            .unwrap_or_else(|e| panic!("{e}"))
    };
    for walk in Traversal::ALL {
        for ((hit, cost), q) in gpu(Accel::Kdtree, walk).into_iter().zip(rays) {
            let (cpu_hit, cpu_cost) = walk.walk_counted(
                walk_scene(tree, &ropes, prims),
                query(&q.ray, q.t_limit, q.any_hit),
            );
            // The kernel may round a hit's t an ulp off the CPU's (fused
            // multiply-adds in the watertight test); the walk's "is the hit
            // before this leaf's exit" then may decide otherwise, and the
            // costs differ legitimately. Compare where both hits agree.
            let bits = |h: Option<Hit>| h.map(|h| (h.object, h.t.to_bits()));
            if bits(hit) != bits(cpu_hit) {
                continue;
            }
            prop_assert_eq!(
                cost,
                cpu_cost,
                "{}: GPU cost {:?} (hit {:?}), CPU {:?} (hit {:?}), query {:?}",
                walk,
                cost,
                hit,
                cpu_cost,
                cpu_hit,
                q
            );
            prop_assert!(cost.leaves_visited <= cost.nodes_visited, "{:?}", cost);
        }
    }
    for ((hit, cost), q) in gpu(Accel::Brute, Traversal::default())
        .into_iter()
        .zip(rays)
    {
        // The kernel's loop, in its object order (GPU id g is scene id ids[g]).
        let mut expected = WalkCost::default();
        for &id in ids {
            expected.objects_tested += 1;
            if q.any_hit && prims.intersect(id, &q.ray).is_some_and(|t| t < q.t_limit) {
                break;
            }
        }
        prop_assert_eq!(cost, expected, "brute force: hit {:?}, query {:?}", hit, q);
        if !q.any_hit {
            prop_assert_eq!(
                traverse::brute_counted(prims, &q.ray, q.t_limit, false).1,
                expected
            );
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(crate::common::proptest_config(96))]

    /// The kernel's walk costs equal the CPU mirror's, ray by ray, for every
    /// walk and brute force, nearest and any-hit queries.
    #[test]
    fn gpu_walk_costs_equal_the_cpu_mirrors(
        prims in scene(),
        cost in traversal_cost(),
        rays in prop::collection::vec(
            (vec3(14.0), direction(), prop::option::of(any::<usize>()), prop::option::of(0.01f32..30.0)),
            1..64,
        ),
    ) {
        let tree = tree_for(&prims, cost);
        let rays: Vec<RayQuery> = rays
            .into_iter()
            .map(|(origin, dir, on_plane, segment)| RayQuery {
                ray: ray_for(&tree, origin, dir, on_plane),
                t_limit: segment.unwrap_or(T_INFINITY),
                any_hit: segment.is_some(),
            })
            .collect();
        check_costs(&prims, &tree, &rays)?;
    }

    /// The CPU mirror's counts are consistent: a leaf is a node, each
    /// descent ends in a leaf, a one-leaf tree tests every object once per
    /// ray that enters the scene's box (as brute force does), and a walk
    /// tests no more objects than the leaves it visited hold.
    #[test]
    fn walk_costs_are_consistent(
        prims in scene(),
        cost in traversal_cost(),
        rays in prop::collection::vec((vec3(14.0), direction(), prop::option::of(any::<usize>())), 1..64),
    ) {
        let tree = tree_for(&prims, cost);
        let ropes = Ropes::build(&tree);
        let one_leaf = KdTree::single_leaf(prims.len() as u32, prims.scene_bounds());
        let one_leaf_ropes = Ropes::build(&one_leaf);
        let max_leaf = tree.nodes.iter().filter(|n| n.is_leaf()).map(|n| n.count).max().unwrap_or(0);
        for (origin, dir, on_plane) in rays {
            let ray = ray_for(&tree, origin, dir, on_plane);
            let enters = one_leaf.bounds.ray_interval(&ray).is_some_and(|(_, t_exit)| t_exit >= 0.0);
            let brute = traverse::brute_counted(&prims, &ray, T_INFINITY, false).1;
            prop_assert_eq!(brute, WalkCost { objects_tested: prims.len() as u32, ..WalkCost::default() });
            for walk in Traversal::ALL {
                let (_, c) = walk.walk_counted(walk_scene(&tree, &ropes, &prims), query(&ray, T_INFINITY, false));
                prop_assert!(c.leaves_visited <= c.nodes_visited, "{}: {:?}", walk, c);
                prop_assert!(c.objects_tested <= c.leaves_visited * max_leaf, "{}: {:?}", walk, c);
                prop_assert_eq!(c.nodes_visited == 0, c.leaves_visited == 0, "{}: {:?}", walk, c);
                let (_, c) = walk.walk_counted(walk_scene(&one_leaf, &one_leaf_ropes, &prims), query(&ray, T_INFINITY, false));
                let expected = match enters {
                    true => WalkCost { nodes_visited: 1, leaves_visited: 1, objects_tested: prims.len() as u32 },
                    false => WalkCost::default(),
                };
                prop_assert_eq!(c, expected, "{}: one leaf, ray {:?}", walk, ray);
            }
        }
    }

    #[test]
    fn gpu_nearest_hits_match_brute_force(
        prims in scene(),
        cost in traversal_cost(),
        rays in prop::collection::vec((vec3(14.0), direction(), prop::option::of(any::<usize>())), 1..64),
    ) {
        let tree = tree_for(&prims, cost);
        let rays: Vec<RayQuery> = rays
            .into_iter()
            .map(|(origin, dir, on_plane)| nearest(ray_for(&tree, origin, dir, on_plane)))
            .collect();
        let (brute, walks) = trace_both(&prims, &tree, &rays);
        for kd in &walks {
            check_nearest(kd, &brute, &rays)?;
        }
    }

    /// Rays aimed at objects from outside: mostly hits.
    #[test]
    fn gpu_aimed_rays_match_brute_force(
        prims in scene(),
        cost in traversal_cost(),
        picks in prop::collection::vec((any::<usize>(), vec3(14.0)), 1..64),
    ) {
        let tree = tree_for(&prims, cost);
        let rays: Vec<RayQuery> = picks
            .into_iter()
            .filter_map(|(pick, origin)| {
                let b = prims.bounds((pick % prims.len()) as u32);
                let dir = ((b.min + b.max) * 0.5 - origin).try_normalize()?;
                Some(nearest(Ray { origin, dir }))
            })
            .collect();
        let (brute, walks) = trace_both(&prims, &tree, &rays);
        for kd in &walks {
            check_nearest(kd, &brute, &rays)?;
        }
    }

    /// Shadow-ray queries on segments: blocked or not, as brute force says
    /// (segments ending within rounding of a hit are ties and skipped).
    #[test]
    fn gpu_any_hits_match_brute_force_on_segments(
        prims in scene(),
        cost in traversal_cost(),
        rays in prop::collection::vec((vec3(14.0), direction(), prop::option::of(any::<usize>()), 0.01f32..30.0), 1..64),
    ) {
        let tree = tree_for(&prims, cost);
        let segments: Vec<(Ray, f32)> = rays
            .into_iter()
            .map(|(origin, dir, on_plane, length)| (ray_for(&tree, origin, dir, on_plane), length))
            .collect();
        // Where brute force first hits each ray, to skip segments ending there.
        let whole: Vec<RayQuery> = segments.iter().map(|&(ray, _)| nearest(ray)).collect();
        let (first, _) = trace_both(&prims, &tree, &whole);
        let shadow: Vec<RayQuery> = segments
            .iter()
            .zip(&first)
            .filter(|((_, length), hit)| {
                !hit.is_some_and(|h| (h.t - length).abs() <= 1e-4 * length.max(1.0))
            })
            .map(|(&(ray, t_limit), _)| RayQuery { ray, t_limit, any_hit: true })
            .collect();
        let (brute, walks) = trace_both(&prims, &tree, &shadow);
        for (kd, walk) in walks.iter().zip(Traversal::ALL) {
            for ((k, b), q) in kd.iter().zip(&brute).zip(&shadow) {
                prop_assert_eq!(k.is_some(), b.is_some(), "{}: kd {:?} brute {:?} query {:?}", walk, k, b, q);
                if let Some(hit) = k {
                    prop_assert!(hit.t < q.t_limit, "{}: any hit {:?} beyond {}", walk, hit, q.t_limit);
                }
            }
        }
    }
}

/// One triangle traced by the kernel, each ray expected to hit it or not:
/// the kernel's brute-force loop and the CPU's agree with the expectation
/// and with each other's t, and every walk gives brute force's answer.
fn check_one_triangle(tri: kdray::geometry::TriangleF32, rays: &[(RayQuery, bool)]) {
    let prims = Primitives {
        spheres: Vec::new(),
        triangles: vec![tri],
        alpha: None,
    };
    let tree = KdTree::for_primitives(&prims);
    let queries: Vec<RayQuery> = rays.iter().map(|&(q, _)| q).collect();
    let (brute, walks) = trace_both(&prims, &tree, &queries);
    for ((q, hits), b) in rays.iter().zip(&brute) {
        let cpu = traverse::closest_hit_brute(&prims, &q.ray, T_INFINITY);
        assert_eq!(cpu.is_some(), *hits, "CPU: {cpu:?} for {:?}", q.ray);
        assert_eq!(b.is_some(), *hits, "kernel: {b:?} for {:?}", q.ray);
        if let (Some(b), Some(c)) = (b, cpu) {
            assert!((b.t - c.t).abs() <= 1e-4 * c.t, "kernel {b:?}, CPU {c:?}");
        }
    }
    for (kd, walk) in walks.iter().zip(Traversal::ALL) {
        assert_eq!(kd, &brute, "{walk}");
    }
}

/// The kernel's triangle test, like the CPU's (`TriangleF32::runs_in_plane`),
/// misses a triangle seen edge-on: a CI run's ray lying in a grid triangle's
/// plane, beyond its box, was hit there by the CPU test, and rays in the
/// plane through the triangle's inside. The same rays tilted out of the plane
/// by 1e-2 rad hit it, on the kernel as on the CPU.
#[test]
fn gpu_rays_in_a_triangles_plane_miss_it() {
    use glam::Vec3;
    let tri = kdray::geometry::TriangleF32 {
        v: [
            Vec3::new(-7.75, 4.25, 7.5),
            Vec3::new(-2.25, 7.75, 5.5),
            Vec3::new(1.25, 5.5, -0.25),
        ],
    };
    let n = tri.normal();
    let (u, w) = n.any_orthonormal_pair();
    let centroid = (tri.v[0] + tri.v[1] + tri.v[2]) / 3.0;
    let mut rays = vec![(
        nearest(Ray {
            origin: Vec3::new(7.5000725, 16.0, 3.9999275),
            dir: Vec3::new(0.0, -1.0, -1.0).normalize(),
        }),
        false,
    )];
    for k in 0..8 {
        let angle = k as f32 * std::f32::consts::TAU / 8.0;
        let along = u * angle.cos() + w * angle.sin();
        let in_plane = Ray {
            origin: centroid - along * 5.0,
            dir: along,
        };
        let dir = (along + n * 1e-2).normalize();
        let tilted = Ray {
            origin: centroid - dir * 5.0,
            dir,
        };
        rays.push((nearest(in_plane), false));
        rays.push((nearest(tilted), true));
    }
    check_one_triangle(tri, &rays);
}

/// The kernel, like the CPU (`TriangleF32::holds_hit_at`), turns away a
/// hit the rounding made beside a triangle: a CI run's triangle 1.5e-4
/// across, 18 units out, 5e-4 rad off edge-on, was "hit" 19 units beside
/// itself. A ray along its normal through its centroid, from as far, hits it.
#[test]
fn gpu_hits_beside_a_far_small_triangle_are_turned_away() {
    use glam::Vec3;
    let tri = kdray::geometry::TriangleF32 {
        v: [
            Vec3::new(0.09544055, 6.176846, 3.757659),
            Vec3::new(0.09544055, 6.176853, 3.7576532),
            Vec3::new(0.09558137, 6.176692, 3.7577822),
        ],
    };
    let centroid = (tri.v[0] + tri.v[1] + tri.v[2]) / 3.0;
    let beside = Ray {
        origin: Vec3::new(-8.836889, -6.568033, 13.11186),
        dir: Vec3::new(0.7282444, -0.5278434, 0.4370827),
    };
    let head_on = Ray {
        origin: centroid + tri.normal() * 18.0,
        dir: -tri.normal(),
    };
    check_one_triangle(tri, &[(nearest(beside), false), (nearest(head_on), true)]);
}

/// An empty scene costs nothing: no walk reads a node or tests an object.
#[test]
fn an_empty_scene_costs_nothing() {
    let prims = Primitives::default();
    let tree = KdTree::for_primitives(&prims);
    let ropes = Ropes::build(&tree);
    let ray = Ray {
        origin: glam::Vec3::new(0.0, 0.0, 5.0),
        dir: glam::Vec3::new(0.0, 0.0, -1.0),
    };
    for walk in Traversal::ALL {
        for any in [false, true] {
            let (hit, cost) = walk.walk_counted(
                walk_scene(&tree, &ropes, &prims),
                query(&ray, T_INFINITY, any),
            );
            assert_eq!((hit, cost), (None, WalkCost::default()), "{walk}");
        }
    }
    assert_eq!(
        traverse::brute_counted(&prims, &ray, T_INFINITY, false),
        (None, WalkCost::default())
    );
}

/// Each pixel's costs as `render_tile` writes them (`render_bands_with_cost`),
/// in dispatches of at most `max_tile_pixels`, and the summary's totals.
fn pixel_costs(
    scene: &Scene,
    traversal: Traversal,
    max_tile_pixels: u64,
) -> (Vec<WalkCost>, kdray::gpu::CostTotals) {
    let ctx = common::gpu();
    let uploaded = GpuScene::upload(ctx, PreparedScene::new(scene.clone(), Accel::Kdtree))
        .unwrap_or_else(|e| panic!("{e}"));
    let renderer = kdray::gpu::Renderer::new(ctx).unwrap_or_else(|e| panic!("{e}"));
    let params = uploaded.frame_params().with_traversal(traversal);
    let (w, h) = (scene.render.width, scene.render.height);
    let plan = kdray::gpu::TilePlan::new(
        w,
        h,
        max_tile_pixels,
        kdray::gpu::max_binding_bytes(&ctx.device.limits()),
    );
    let mut costs = Vec::new();
    let summary = renderer
        .render_bands_with_cost(ctx, uploaded.buffers(), params, plan, true, &mut |band| {
            costs.extend_from_slice(band.costs.expect("asked for costs"));
            Ok(())
        })
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(costs.len(), (w * h) as usize);
    (costs, summary.cost.expect("asked for costs"))
}

/// The per-pixel costs land on their pixels whatever the tiling (odd,
/// partial tiles give the same costs, pixel for pixel), their sums are the
/// summary's totals, and a pixel whose ray misses the scene's box costs
/// nothing while one on an object does work.
#[test]
fn per_pixel_costs_do_not_depend_on_tiling_and_sum_to_the_totals() {
    let mut scene = common::small_scene(&common::repo_path("scenes/mixed.toml"));
    scene.render.max_depth = 1; // primary rays and their shadow rays only
    for walk in Traversal::ALL {
        let (whole, totals) = pixel_costs(&scene, walk, u64::MAX);
        let (tiled, tiled_totals) = pixel_costs(&scene, walk, 37 * 3);
        assert_eq!(whole, tiled, "{walk}");
        assert_eq!(totals, tiled_totals, "{walk}");
        let mut sum = kdray::gpu::CostTotals::default();
        whole.iter().for_each(|c| sum.add(c));
        assert_eq!(sum, totals, "{walk}");
        assert!(whole.iter().all(|c| c.leaves_visited <= c.nodes_visited));
        assert!(
            whole.iter().any(|c| *c == WalkCost::default()),
            "{walk}: no free pixel"
        );
        assert!(
            whole.iter().any(|c| c.objects_tested > 0),
            "{walk}: no work"
        );
    }
}

/// What the CPU walks search: `tree`, its `ropes` and `prims`.
fn walk_scene<'a>(tree: &'a KdTree, ropes: &'a Ropes, prims: &'a Primitives) -> WalkScene<'a> {
    WalkScene { tree, ropes, prims }
}

/// A CPU walk's query.
fn query(ray: &Ray, t_limit: f32, any: bool) -> WalkQuery<'_> {
    WalkQuery { ray, t_limit, any }
}
