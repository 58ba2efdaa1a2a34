//! Property tests: the CPU mirror of the shader's stackless k-d traversal
//! agrees with brute force on random scenes and rays, including the cases
//! the seed's tree gets wrong (straddling objects, nearer hits in the far
//! child) and the numerically awkward ones (axis-parallel rays, rays on and
//! in split planes, coincident, tiny and huge objects).

use std::path::Path;

#[path = "support/strategies.rs"]
mod strategies;

use glam::Vec3;
use kdray::geometry::{Primitives, Ray, SphereF32, T_INFINITY};
use kdray::kdtree::traverse::{any_hit, any_hit_brute, closest_hit, closest_hit_brute};
use kdray::kdtree::KdTree;
use proptest::prelude::*;
use strategies::{direction, ray_for, scene, traversal_cost, tree_for, vec3};

fn check_closest(tree: &KdTree, prims: &Primitives, ray: &Ray) -> Result<(), TestCaseError> {
    let kd = closest_hit(tree, prims, ray, T_INFINITY);
    let brute = closest_hit_brute(prims, ray, T_INFINITY);
    match (kd, brute) {
        (None, None) => {}
        (Some(k), Some(b)) => {
            let tol = 1e-4 * b.t.max(1.0);
            prop_assert!(
                (k.t - b.t).abs() <= tol,
                "t differs: kd {:?} brute {:?} ray {:?}",
                k,
                b,
                ray
            );
            // A different object is fine only for a tie (coincident objects).
        }
        (k, b) => prop_assert!(false, "kd {:?} brute {:?} ray {:?}", k, b, ray),
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 512, .. ProptestConfig::default() })]

    #[test]
    fn closest_hit_matches_brute_force(
        prims in scene(),
        cost in traversal_cost(),
        rays in prop::collection::vec((vec3(14.0), direction(), prop::option::of(any::<usize>())), 1..40),
    ) {
        let tree = tree_for(&prims, cost);
        for (origin, dir, on_plane) in rays {
            let ray = ray_for(&tree, origin, dir, on_plane);
            check_closest(&tree, &prims, &ray)?;
        }
    }

    #[test]
    fn any_hit_matches_brute_force_on_segments(
        prims in scene(),
        cost in traversal_cost(),
        rays in prop::collection::vec((vec3(14.0), direction(), prop::option::of(any::<usize>()), 0.01f32..30.0), 1..40),
    ) {
        let tree = tree_for(&prims, cost);
        for (origin, dir, on_plane, length) in rays {
            let ray = ray_for(&tree, origin, dir, on_plane);
            // Segments ending exactly at a hit are ties; step back from them.
            let brute_t = closest_hit_brute(&prims, &ray, T_INFINITY).map(|h| h.t);
            if brute_t.is_some_and(|t| (t - length).abs() <= 1e-4 * length.max(1.0)) {
                continue;
            }
            prop_assert_eq!(any_hit(&tree, &prims, &ray, length), any_hit_brute(&prims, &ray, length), "ray {:?} length {}", ray, length);
        }
    }

    /// Rays aimed at a random object's centre from outside: most of them hit,
    /// so the comparison is not dominated by misses.
    #[test]
    fn aimed_rays_match_brute_force(prims in scene(),
        cost in traversal_cost(), picks in prop::collection::vec((any::<usize>(), vec3(14.0)), 1..30)) {
        let tree = tree_for(&prims, cost);
        for (pick, origin) in picks {
            let b = prims.bounds((pick % prims.len()) as u32);
            let target = (b.min + b.max) * 0.5;
            let Some(dir) = (target - origin).try_normalize() else { continue };
            check_closest(&tree, &prims, &Ray { origin, dir })?;
        }
    }

    /// The flat layout the kernel relies on for bounds and termination
    /// (shaders/traverse.wgsl; naga's forced loop bounds are off, see
    /// `gpu::shaders::trace_module`): the root at 0; an interior node's
    /// children after it (below at i + 1, above past the whole below
    /// subtree), so a descent only moves forward; every node reached once;
    /// leaf ranges inside `leaf_objects`, naming real objects.
    #[test]
    fn flat_layout_is_what_the_kernel_assumes(prims in scene(), cost in traversal_cost()) {
        let tree = tree_for(&prims, cost);
        let n = tree.nodes.len();
        prop_assert!(n >= 1);
        let mut reached = vec![0u32; n];
        let mut pending = vec![0usize];
        while let Some(i) = pending.pop() {
            reached[i] += 1;
            let node = tree.nodes[i];
            if node.is_leaf() {
                let end = node.index as usize + node.count as usize;
                prop_assert!(end <= tree.leaf_objects.len(), "leaf {} ends at {}", i, end);
                for &id in &tree.leaf_objects[node.index as usize..end] {
                    prop_assert!((id as usize) < prims.len(), "leaf {} names object {}", i, id);
                }
            } else {
                prop_assert!(node.kind < 3, "node {} has kind {}", i, node.kind);
                prop_assert!(node.split.is_finite(), "node {} splits at {}", i, node.split);
                let above = node.index as usize;
                prop_assert!(i + 1 < above && above < n, "node {}: children {} and {} of {}", i, i + 1, above, n);
                pending.push(i + 1);
                pending.push(above);
            }
        }
        prop_assert!(reached.iter().all(|&r| r == 1), "every node reached exactly once: {:?}", reached);
    }

    /// Every object is referenced by the leaf containing any point of its box.
    #[test]
    fn every_point_of_an_object_is_in_its_leaf(prims in scene(),
        cost in traversal_cost(), fractions in prop::collection::vec((0.0f32..=1.0, 0.0f32..=1.0, 0.0f32..=1.0, any::<usize>()), 1..50)) {
        let tree = tree_for(&prims, cost);
        for (fx, fy, fz, pick) in fractions {
            let id = (pick % prims.len()) as u32;
            let b = prims.bounds(id);
            let p = b.min + (b.max - b.min) * Vec3::new(fx, fy, fz);
            let mut node = 0usize;
            while !tree.nodes[node].is_leaf() {
                let n = tree.nodes[node];
                node = if p[n.kind as usize] <= n.split { node + 1 } else { n.index as usize };
            }
            let leaf = tree.nodes[node];
            let ids = &tree.leaf_objects[leaf.index as usize..(leaf.index + leaf.count) as usize];
            prop_assert!(ids.contains(&id), "object {} missing from the leaf holding {:?}", id, p);
        }
    }
}

proptest! {
    // The old walk's mistake showed in one fresh run of 512 cases in three
    // and in two of 2,048 cases in three (a few seconds); the cases it found
    // are kept in kdtree_props.proptest-regressions and replayed first.
    #![proptest_config(ProptestConfig { cases: 2048, .. ProptestConfig::default() })]

    /// Rays that graze a split plane: starting just off it and nearly
    /// parallel to it, they stay within a hair of the plane for a long
    /// stretch of t, so hits on its two sides are easily taken in the wrong
    /// order (an early walk accepted a hit just across the plane, beyond its
    /// leaf, before visiting the leaf with a nearer one).
    #[test]
    fn grazing_rays_match_brute_force(
        prims in scene(),
        cost in traversal_cost(),
        rays in prop::collection::vec(
            (vec3(14.0), any::<usize>(), -1e-2f32..1e-2, 1e-6f32..1e-2, any::<bool>(), -1.0f32..1.0, -1.0f32..1.0),
            1..40,
        ),
    ) {
        let tree = tree_for(&prims, cost);
        let inner: Vec<_> = tree.nodes.iter().filter(|n| !n.is_leaf()).collect();
        if inner.is_empty() {
            return Ok(()); // one leaf: no split plane to graze
        }
        for (mut origin, pick, offset, slope, down, x, y) in rays {
            let n = inner[pick % inner.len()];
            let a = n.kind as usize;
            origin[a] = n.split + offset;
            let mut dir = Vec3::ZERO;
            dir[(a + 1) % 3] = x;
            dir[(a + 2) % 3] = y;
            let Some(flat) = dir.try_normalize() else { continue };
            let mut dir = flat;
            dir[a] = if down { -slope } else { slope };
            check_closest(&tree, &prims, &Ray { origin, dir: dir.normalize() })?;
        }
    }
}

/// A big sphere straddling every plane among small ones: each ray's answer
/// equals brute force (the seed's tree puts such a sphere on one side only).
#[test]
fn straddling_sphere_scene_matches_brute_force() {
    let mut prims = Primitives::default();
    prims.spheres.push(SphereF32 {
        center: Vec3::new(-5.0, 0.0, 0.0),
        radius: 0.5,
    });
    prims.spheres.push(SphereF32 {
        center: Vec3::new(-4.0, 0.0, 0.0),
        radius: 0.2,
    });
    prims.spheres.push(SphereF32 {
        center: Vec3::new(5.0, 0.0, 0.0),
        radius: 0.5,
    });
    prims.spheres.push(SphereF32 {
        center: Vec3::new(0.5, 0.0, 0.0),
        radius: 4.0,
    });
    // Cheap traversal steps, so that even four spheres get split planes.
    let bounds: Vec<_> = (0..prims.len() as u32).map(|id| prims.bounds(id)).collect();
    let params = kdray::kdtree::BuildParams {
        traversal_cost: 1.0,
        ..kdray::kdtree::BuildParams::for_object_count(bounds.len())
    };
    let tree = kdray::kdtree::build(&bounds, params);
    assert!(tree.nodes.len() > 1, "the scene must be split");
    let ray = Ray {
        origin: Vec3::new(-10.0, 0.0, 0.0),
        dir: Vec3::X,
    };
    let hit = closest_hit(&tree, &prims, &ray, T_INFINITY).expect("hit");
    assert_eq!(hit.object, 0);
    let ray = Ray {
        origin: Vec3::new(-3.0, 0.0, 0.0),
        dir: Vec3::X,
    };
    let hit = closest_hit(&tree, &prims, &ray, T_INFINITY).expect("hit");
    assert_eq!(hit, closest_hit_brute(&prims, &ray, T_INFINITY).unwrap());
}

/// The tree does not depend on how many threads build it (subtrees built
/// apart are appended in single-thread order), on scenes big enough for the
/// parallel path.
#[test]
fn threads_do_not_change_the_tree() {
    use kdray::bench::{random_scene, RandomSceneSpec, SceneKind};
    for (kind, count) in [(SceneKind::Spheres, 20_000), (SceneKind::Mixed, 9_000)] {
        let scene = random_scene(&RandomSceneSpec {
            kind,
            count,
            seed: 7,
            width: 8,
            height: 8,
        });
        let prims = Primitives::from_scene(&scene);
        let bounds: Vec<_> = (0..prims.len() as u32).map(|id| prims.bounds(id)).collect();
        let params = kdray::kdtree::BuildParams::for_object_count(bounds.len());
        let serial = kdray::kdtree::build_with_threads(&bounds, params, 1);
        assert!(serial.nodes.len() > 1000, "{kind:?}: a deep tree");
        for threads in [2, 3, 8] {
            let parallel = kdray::kdtree::build_with_threads(&bounds, params, threads);
            assert!(
                parallel == serial,
                "{kind:?}: {threads} threads built another tree"
            );
        }
    }
}

/// A shadow ray of `tests/scenes/rays_on_split_planes.toml` (pixel 39, 27)
/// that passes exactly through the edge where two faces of a box meet, the
/// face in the plane y = 1 and the face in x = -1, both split planes. It
/// goes from the cell x < -1, y > 1 straight into x > -1, y < 1, spending no
/// time in the cells beside the corner, where both faces used to be filed
/// (an object touching a plane went below only); brute force counts the hit
/// on the edge, so the walk must find it too. Flat objects lying in a split
/// plane now go to both sides.
#[test]
fn a_ray_through_the_corner_of_two_split_planes_finds_the_faces_there() {
    let scene = kdray::scene::load_scene(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/scenes/rays_on_split_planes.toml"),
    )
    .unwrap();
    let prims = Primitives::from_scene(&scene);
    let tree = KdTree::for_primitives(&prims);
    let ray = Ray {
        origin: Vec3::new(-1.076953, 1.076953, -1.999799),
        dir: Vec3::new(0.10646964, -0.10646964, 0.98859924),
    };
    let length = 10.115119;
    assert!(
        any_hit_brute(&prims, &ray, length),
        "brute force sees the edge"
    );
    assert!(
        any_hit(&tree, &prims, &ray, length),
        "the walk missed the edge"
    );
    let kd = closest_hit(&tree, &prims, &ray, T_INFINITY).expect("hit");
    let brute = closest_hit_brute(&prims, &ray, T_INFINITY).unwrap();
    assert_eq!(kd.t, brute.t);
}

#[test]
fn ten_thousand_copies_of_one_sphere() {
    let prims = Primitives {
        spheres: vec![
            SphereF32 {
                center: Vec3::new(1.0, 2.0, 3.0),
                radius: 0.5
            };
            10_000
        ],
        ..Default::default()
    };
    let tree = KdTree::for_primitives(&prims);
    let ray = Ray {
        origin: Vec3::new(1.0, 2.0, -10.0),
        dir: Vec3::Z,
    };
    let hit = closest_hit(&tree, &prims, &ray, T_INFINITY).expect("hit");
    assert!((hit.t - 12.5).abs() < 1e-4);
    assert!(any_hit(&tree, &prims, &ray, 13.0));
    assert!(!any_hit(&tree, &prims, &ray, 12.0));
}
