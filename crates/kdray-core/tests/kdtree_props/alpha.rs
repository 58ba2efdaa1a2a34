//! The walks on scenes with alpha-masked triangles (common::masked): a hit
//! in a hole is no hit for any walk or brute force, so every walk still
//! gives brute force's nearest and any hit, and the masked scene's hits
//! are the plain scene's where they fall on solid texels.

use kdray_core::geometry::{Primitives, Ray, T_INFINITY};
use kdray_core::kdtree::traverse::closest_hit_brute;
use proptest::prelude::*;

use super::common::masked::{checker_alphas, masked_scene};
use super::common::strategies::{self, direction, ray_for, scene, traversal_cost, vec3};
use super::{check_any, check_closest, Walks};

/// `prims` with every second triangle masked by the checker, as walked.
fn masked(prims: &Primitives, uv_scale: f64) -> Primitives {
    let masked =
        Primitives::from_scene(&masked_scene(prims, &checker_alphas(), uv_scale, "whitted"));
    assert!(prims.triangles.len() < 2 || masked.alpha.is_some());
    masked
}

proptest! {
    #![proptest_config(crate::common::proptest_config(256))]

    #[test]
    fn masked_closest_and_any_hits_match_brute_force(
        prims in scene(),
        cost in traversal_cost(),
        uv_scale in 0.5f64..6.0,
        rays in prop::collection::vec((vec3(14.0), direction(), prop::option::of(any::<usize>()), 0.01f32..30.0), 1..40),
    ) {
        let prims = masked(&prims, uv_scale);
        let walks = Walks::new(strategies::tree_for(&prims, cost));
        for (origin, dir, on_plane, length) in rays {
            let ray = ray_for(&walks.tree, origin, dir, on_plane);
            check_closest(&walks, &prims, &ray)?;
            let brute_t = closest_hit_brute(&prims, &ray, T_INFINITY).map(|h| h.t);
            if brute_t.is_some_and(|t| (t - length).abs() <= 1e-4 * length.max(1.0)) {
                continue;
            }
            check_any(&walks, &prims, &ray, length)?;
        }
    }
}

/// Rays straight down onto a masked triangle over an opaque one: through
/// a hole they reach the floor, on a solid texel (128 of 255 included)
/// they stop on the mask, through 127 they pass, for every walk.
#[test]
fn rays_pass_through_holes_and_stop_on_solid_texels() {
    use glam::Vec3;
    use kdray_core::geometry::TriangleF32;
    let tri = |z: f32, size: f32| TriangleF32 {
        v: [
            Vec3::new(0.0, 0.0, z),
            Vec3::new(size, 0.0, z),
            Vec3::new(0.0, size, z),
        ],
    };
    // Triangle 0 the floor (opaque), triangle 1 the mask: texture
    // coordinates (0, 0), (1, 0), (0, 1) over a 4-unit side: one texel a unit.
    let plain = Primitives {
        triangles: vec![tri(-1.0, 8.0), tri(1.0, 4.0)],
        ..Default::default()
    };
    let prims = masked(&plain, 1.0);
    let walks = Walks::new(strategies::tree_for(&prims, 1.0));
    let alphas = checker_alphas();
    let mut holes = 0;
    for (x, y) in [(0, 0), (1, 0), (2, 0), (0, 1), (1, 1), (0, 2)] {
        let origin = Vec3::new(x as f32 + 0.5, y as f32 + 0.25, 5.0);
        let ray = Ray {
            origin,
            dir: Vec3::NEG_Z,
        };
        let solid = alphas[(y * 4 + x) as usize] >= 128;
        let expected = if solid { 1 } else { 0 };
        for walk in kdray_core::kdtree::Traversal::ALL {
            let hit = walks
                .closest_hit(walk, &prims, &ray, T_INFINITY)
                .map(|h| h.object);
            assert_eq!(hit, Some(expected), "{walk}: texel ({x}, {y})");
            assert!(
                walks.any_hit(walk, &prims, &ray, 5.5) == solid,
                "{walk}: texel ({x}, {y})"
            );
        }
        holes += usize::from(!solid);
    }
    assert_eq!(holes, 2, "texel (1, 0) at 127 and the checker's (0, 1)");
}
