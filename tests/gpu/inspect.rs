//! `kdray inspect`'s rays and walks (src/inspect/) against brute force
//! and the kernel: on random pixels of a few scenes, with every walk, each
//! inspected ray's hit is brute force's and the kernel's for the same ray
//! (the ray query entry point, `RayQueries::trace_counted`), and the work
//! the inspected walk counts is the kernel walk's: what shows that the
//! walk printed, the CPU mirror's, is the one the GPU makes. The walks'
//! steps are consistent with their hits: every object hit lies in a leaf
//! the walk tested, and leaves are tested front to back.

use crate::common;

use kdray::geometry::{Primitives, Ray, T_INFINITY};
use kdray::gpu::{Accel, GpuScene, PreparedScene, RayQueries, RayQuery};
use kdray::inspect::{build_tree, inspect_scene, InspectedRay, Step};
use kdray::kdtree::traverse::{brute_counted, Hit};
use kdray::kdtree::{BuildStrategy, Traversal};
use kdray::scene::{load_scene, Scene};

/// Scene files (relative to the repository), drawn at this size.
const SCENES: [&str; 6] = [
    "scenes/seed.toml",
    "scenes/mirrors.toml",
    "scenes/torus.toml",
    "scenes/glass.toml",
    "tests/scenes/rays_on_split_planes.toml",
    "tests/scenes/thin_triangles.toml",
];
const WIDTH: u32 = 64;
const HEIGHT: u32 = 48;
/// Random pixels per scene, besides the centre.
const PIXELS: usize = 10;

fn small_scene(path: &str) -> Scene {
    let full = format!("{}/{path}", env!("CARGO_MANIFEST_DIR"));
    let mut scene = load_scene(full.as_ref()).unwrap_or_else(|e| panic!("{e}"));
    (scene.render.width, scene.render.height) = (WIDTH, HEIGHT);
    scene
}

/// `count` pixels of a `width` x `height` image: the centre, then a fixed
/// pseudo-random sequence.
pub(crate) fn pixels(salt: u64, width: u32, height: u32, count: usize) -> Vec<(u32, u32)> {
    let mut state = 0x9e37_79b9_7f4a_7c15u64 ^ salt;
    let mut next = |n: u32| {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        ((state >> 33) % n as u64) as u32
    };
    let mut out = vec![(width / 2, height / 2)];
    out.extend((1..count).map(|_| (next(width), next(height))));
    out
}

fn ray_of(r: &InspectedRay) -> Ray {
    Ray {
        origin: r.origin.into(),
        dir: r.direction.into(),
    }
}

fn query_of(r: &InspectedRay) -> RayQuery {
    RayQuery {
        ray: ray_of(r),
        t_limit: r.t_limit.unwrap_or(T_INFINITY),
        any_hit: r.query == "any",
    }
}

/// Same object, t equal within f32 rounding (the kernel may fuse a
/// multiply-add the CPU rounds twice).
fn same_hit(a: Option<Hit>, b: Option<Hit>) -> bool {
    match (a, b) {
        (None, None) => true,
        (Some(a), Some(b)) => a.object == b.object && (a.t - b.t).abs() <= 1e-5 * a.t.max(1.0),
        _ => false,
    }
}

fn inspected_hit(r: &InspectedRay) -> Option<Hit> {
    r.hit.as_ref().map(|h| Hit {
        object: h.object,
        t: h.t,
    })
}

/// Every object hit is among the objects of a leaf the walk tested, and
/// the tested leaves follow each other front to back (each starts where
/// the one before ends) from the start of the searched segment.
fn check_walk_steps(what: &str, r: &InspectedRay) {
    let mut expected_start = r.t_interval.map(|t| t[0]);
    let mut tested_objects = Vec::new();
    for step in &r.walk {
        if let Step::Leaf {
            t, tested, skipped, ..
        } = step
        {
            if *skipped {
                continue;
            }
            assert_eq!(Some(t[0]), expected_start, "{what}: leaves out of order");
            expected_start = Some(t[1]);
            tested_objects.extend(tested.iter().map(|x| x.object));
        }
    }
    if let Some(hit) = &r.hit {
        assert!(
            tested_objects.contains(&hit.object),
            "{what}: object {} hit outside the leaves tested",
            hit.object
        );
    }
}

#[test]
fn inspected_walks_hit_what_brute_force_and_the_kernel_hit_at_the_kernels_cost() {
    let ctx = common::gpu();
    let queries = RayQueries::new(ctx).unwrap_or_else(|e| panic!("{e}"));
    let (mut compared, mut rays_seen) = (0usize, 0usize);
    for (salt, path) in SCENES.iter().enumerate() {
        let scene = small_scene(path);
        let prims = Primitives::from_scene(&scene);
        let prepared = PreparedScene::built_by(scene.clone(), Accel::Kdtree, BuildStrategy::Sah);
        assert!(
            prepared.tree == build_tree(&scene, BuildStrategy::Sah),
            "{path}: inspect builds the tree render uploads"
        );
        let tree = prepared.tree.clone();
        let uploaded = GpuScene::upload(ctx, prepared).unwrap_or_else(|e| panic!("{e}"));
        let ids = &uploaded.prepared().arrays.scene_ids;
        for traversal in Traversal::ALL {
            let mut rays = Vec::new();
            for (x, y) in pixels(salt as u64, WIDTH, HEIGHT, PIXELS + 1) {
                let inspection = inspect_scene(&scene, Some(tree.clone()), traversal, (x, y))
                    .unwrap_or_else(|e| panic!("{e}"));
                let primary = &inspection.rays[0];
                assert_eq!(primary.kind, "primary");
                let what = format!("{path} {traversal} pixel {x},{y}");
                let (brute, _) = brute_counted(&prims, &ray_of(primary), T_INFINITY, false);
                assert_eq!(
                    inspected_hit(primary).map(|h| (h.object, h.t.to_bits())),
                    brute.map(|h| (h.object, h.t.to_bits())),
                    "{what}: the primary ray's hit is brute force's"
                );
                for r in &inspection.rays {
                    check_walk_steps(&what, r);
                    rays.push((what.clone(), r.clone()));
                }
            }
            let asked: Vec<RayQuery> = rays.iter().map(|(_, r)| query_of(r)).collect();
            let gpu = queries
                .trace_counted(
                    ctx,
                    uploaded.buffers(),
                    ids,
                    Accel::Kdtree,
                    traversal,
                    &asked,
                )
                .unwrap_or_else(|e| panic!("{e}"));
            for ((what, r), (hit, cost)) in rays.iter().zip(gpu) {
                let cpu = inspected_hit(r);
                rays_seen += 1;
                if r.query == "any" {
                    // Any hit: which object ends the search is the walk's
                    // order, so only whether one does is compared here.
                    assert_eq!(hit.is_some(), cpu.is_some(), "{what}: {} ray", r.kind);
                } else {
                    assert!(
                        same_hit(hit, cpu),
                        "{what}: {} ray: GPU {hit:?}, inspected {cpu:?}",
                        r.kind
                    );
                }
                // A t an ulp apart may end a walk a leaf sooner or later;
                // costs are compared where the hits agree bit for bit (on
                // lavapipe 537 of the 585 rays; the others differ by an ulp).
                let bits = |h: Option<Hit>| h.map(|h| (h.object, h.t.to_bits()));
                if bits(hit) != bits(cpu) {
                    continue;
                }
                compared += 1;
                let counted = (r.counts.nodes, r.counts.leaves, r.counts.tests);
                let kernel = (cost.nodes_visited, cost.leaves_visited, cost.objects_tested);
                assert_eq!(counted, kernel, "{what}: {} ray's walk", r.kind);
            }
        }
    }
    assert!(
        compared * 10 >= rays_seen * 9,
        "costs compared on {compared} of {rays_seen} rays only"
    );
}
