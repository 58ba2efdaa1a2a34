//! The examples of the library, run as tests: `render_to_image` renders
//! scenes/seed.toml and is compared with its golden image as
//! tests/gpu/golden.rs compares it; `trace_on_cpu`'s hits and shadows are
//! checked against brute force and against values worked out by hand;
//! `inspect_picture` draws an inspected pixel's lines over a side view.

use crate::common;

#[allow(dead_code)]
#[path = "../../examples/render_to_image.rs"]
mod render_to_image;

#[allow(dead_code)]
#[path = "../../examples/trace_on_cpu.rs"]
mod trace_on_cpu;

#[allow(dead_code)]
#[path = "../../examples/inspect_picture.rs"]
mod inspect_picture;

use common::*;
use glam::Vec3;
use kdray::geometry::Ray;
use kdray::kdtree::KdTree;
use kdray::output::{read_png_rgb, write_png_atomic};

/// The budgets of tests/gpu/golden.rs: mean FLIP error, and pixels more than 2
/// levels off per mille of the image.
const MAX_MEAN_FLIP: f32 = 0.01;
const MAX_PIXELS_OVER_PER_MILLE: usize = 1;

#[test]
fn render_to_image_matches_the_seed_golden_image() {
    // The goldens are the shipped scenes 160 pixels wide (`small_scene`).
    let image = render_to_image::render(gpu(), &repo_path("scenes/seed.toml"), Some(160))
        .unwrap_or_else(|e| panic!("{e}"));
    let golden_path = repo_path("tests/golden/seed.png");
    let (w, h, golden) = read_png_rgb(&golden_path)
        .unwrap_or_else(|e| panic!("no golden image {}: {e}", golden_path.display()));
    assert_eq!(
        (w, h),
        image.dimensions(),
        "the golden's size and the example's image size differ"
    );
    let rgb = image.as_raw();
    let d = compare(&golden, rgb, w, h, 2);
    let budget = (w * h) as usize * MAX_PIXELS_OVER_PER_MILLE / 1000;
    if d.mean_flip > MAX_MEAN_FLIP || d.pixels_over > budget {
        let dir = failure_dir();
        write_png_atomic(&dir.join("example-seed-actual.png"), w, h, rgb).unwrap();
        write_png_atomic(
            &dir.join("example-seed-diff.png"),
            w,
            h,
            &difference_image(&golden, rgb),
        )
        .unwrap();
        panic!(
            "render_to_image's seed differs from its golden: {d:?} (budget: FLIP {MAX_MEAN_FLIP}, {budget} pixels); see {}",
            dir.display()
        );
    }
}

#[test]
fn render_to_image_reports_a_missing_scene_file() {
    let missing = repo_path("scenes/no-such-scene.toml");
    let error = render_to_image::render(gpu(), &missing, Some(16))
        .expect_err("a missing scene file renders nothing");
    assert!(
        error.to_string().contains("no-such-scene.toml"),
        "the error names the file: {error}"
    );
}

#[test]
fn trace_on_cpu_agrees_with_brute_force() {
    let prims = trace_on_cpu::example_primitives();
    let tree = KdTree::for_primitives(&prims);
    assert!(
        tree.stats().leaves > 1,
        "the example's tree should split its scene, so that the walk is exercised"
    );
    // The example's grid, and a finer one that also meets the small spheres'
    // silhouettes.
    for (columns, rows) in [(64, 24), (301, 203)] {
        let rays = trace_on_cpu::camera_rays(columns, rows);
        let walked = trace_on_cpu::trace(&prims, Some(&tree), &rays);
        let brute = trace_on_cpu::trace(&prims, None, &rays);
        for (i, (w, b)) in walked.iter().zip(&brute).enumerate() {
            assert_eq!(w, b, "{columns}x{rows} grid, ray {i}: {:?}", rays[i]);
        }
        let hits = walked.iter().filter(|p| p.hit.is_some()).count();
        let shadowed = walked.iter().filter(|p| p.in_shadow).count();
        assert!(
            hits > rays.len() / 3 && hits < rays.len(),
            "{hits} of {} rays hit: the grid sees both the scene and the sky",
            rays.len()
        );
        assert!(shadowed > 0, "the big sphere casts a shadow on the floor");
    }
}

#[test]
fn trace_on_cpu_finds_the_hits_worked_out_by_hand() {
    let prims = trace_on_cpu::example_primitives();
    let tree = KdTree::for_primitives(&prims);
    let from_origin = |dir: Vec3| Ray {
        origin: Vec3::ZERO,
        dir: dir.normalize(),
    };
    let rays = [
        // Straight ahead: the unit sphere at z = -4, front face at t = 3
        // (exact in f32: every step of the test is an integer).
        from_origin(Vec3::NEG_Z),
        // The floor beside the sphere, (0.9, -1, -4), at t = sqrt(17.81) (the
        // ray passes 1.28 from the sphere's centre): the way to the light
        // passes 0.74 from it, so the sphere shades this point.
        from_origin(Vec3::new(0.9, -1.0, -4.0)),
        // The floor at (3, -1, -2), at t = sqrt(14), in the light (its way to
        // the light passes 2.58 from the sphere's centre).
        from_origin(Vec3::new(3.0, -1.0, -2.0)),
        // Up into the sky: nothing.
        from_origin(Vec3::Y),
    ];
    let probes = trace_on_cpu::trace(&prims, Some(&tree), &rays);

    let sphere = probes[0].hit.expect("the ray ahead hits the big sphere");
    assert_eq!((sphere.object, sphere.t), (0, 3.0));
    // At (0, 0, -3) the normal is +z and the light (0, 5, -4) lies behind
    // the tangent plane (to the light: (0, 5, -1)): the sphere shades itself.
    assert!(
        probes[0].in_shadow,
        "the sphere's front point faces away from the light above"
    );

    let floor_objects = prims.spheres.len() as u32..prims.len() as u32;
    for (probe, t, in_shadow) in [
        (&probes[1], 17.81f32.sqrt(), true),
        (&probes[2], 14f32.sqrt(), false),
    ] {
        let hit = probe.hit.expect("the ray down hits the floor");
        assert!(
            floor_objects.contains(&hit.object),
            "{hit:?} is not the floor"
        );
        assert!((hit.t - t).abs() <= 1e-5 * t, "{hit:?}: want t = {t}");
        assert_eq!(probe.in_shadow, in_shadow, "{hit:?}");
    }

    assert_eq!(probes[3].hit, None, "the ray up meets nothing");
    assert!(!probes[3].in_shadow);
}

/// The README's inspect picture: over the side view, the lines change
/// pixels (a k-d walk of ten leaves draws hundreds), every changed pixel
/// takes a line's colour, and the rest of the image is the plain render.
#[test]
fn inspect_picture_draws_the_pixels_rays_and_cells_over_the_side_view() {
    use kdray::window::inspect_lines::LineKind;
    let picture = inspect_picture::picture(
        gpu(),
        &repo_path("scenes/random_spheres.toml"),
        (320, 180),
        40.0,
        1.0,
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(picture.inspection.rays[0].kind, "primary");
    assert!(picture.inspection.rays[0].hit.is_some());
    let colours: Vec<[u8; 3]> = [
        LineKind::Leaf,
        LineKind::HitLeaf,
        LineKind::SplitPlane,
        LineKind::Primary,
        LineKind::Shadow,
        LineKind::Reflected,
        LineKind::Refracted,
        LineKind::Bounce,
    ]
    .iter()
    .map(|k| k.colour().map(|c| (255.0 * c).round() as u8))
    .collect();
    let mut changed = 0;
    for (plain, drawn) in picture.plain.chunks(3).zip(picture.with_lines.chunks(3)) {
        if plain != drawn {
            changed += 1;
            assert!(
                colours.iter().any(|c| c[..] == *drawn),
                "pixel {drawn:?} is no line's colour"
            );
        }
    }
    assert!(changed > 300, "the lines changed only {changed} pixels");
}
