//! Pathological but valid scenes (tests/scenes/): each renders, shows
//! something, and the k-d tree gives the brute-force image.

use crate::common;

use common::*;
use kdray::gpu::Accel;

fn load(name: &str) -> kdray::scene::Scene {
    let path = repo_path(&format!("tests/scenes/{name}.toml"));
    kdray::scene::load_scene(&path).unwrap_or_else(|e| panic!("{e}"))
}

/// Renders tests/scenes/NAME.toml with the k-d tree and brute force.
fn check(name: &str, min_covered: f64) -> kdray::gpu::RenderedImage {
    check_scene(name, &load(name), min_covered)
}

/// Renders `scene` with the k-d tree and brute force: no pixel may have hit
/// llvmpipe's loop limit, the images must agree, and at least `min_covered`
/// of the pixels must differ from the corner's (background).
fn check_scene(
    name: &str,
    scene: &kdray::scene::Scene,
    min_covered: f64,
) -> kdray::gpu::RenderedImage {
    let kd = render(scene, Accel::Kdtree);
    let brute = render(scene, Accel::Brute);
    for (accel, image) in [("kdtree", &kd), ("brute", &brute)] {
        assert_eq!(
            image.rays.loop_limited, 0,
            "{name} ({accel}): some pixels ran into llvmpipe's loop limit"
        );
    }
    let d = compare(&kd.rgb, &brute.rgb, kd.width, kd.height, 0);
    assert_eq!(
        d.pixels_over, 0,
        "{name}: k-d tree and brute force differ: {d:?}"
    );
    let background = pixel(&kd, 0, 0);
    let covered = kd.rgb.chunks_exact(3).filter(|p| *p != background).count();
    assert!(
        covered as f64 >= min_covered * (kd.width * kd.height) as f64,
        "{name}: only {covered} pixels show an object"
    );
    kd
}

#[test]
fn all_objects_at_one_point() {
    check("one_point", 0.1);
}

#[test]
fn objects_far_from_the_origin() {
    check("far_from_origin", 0.3);
}

#[test]
fn very_thin_triangles() {
    check("thin_triangles", 0.002);
}

/// Opaque copies: every ray that reaches the cluster tests all 10,001
/// objects of its leaf, four times or so per path, which stays under
/// llvmpipe's 65,535 loop iterations per pixel (see the next test).
#[test]
fn ten_thousand_copies_of_one_sphere() {
    let mut scene = load("ten_thousand_copies");
    for m in &mut scene.materials {
        m.reflection = 0.0;
    }
    check_scene("ten_thousand_copies (opaque)", &scene, 0.3);
}

/// With reflective copies a path tests the 10,001-object leaf eight times:
/// about 80,000 loop iterations. On llvmpipe, which silently ends a pixel's
/// loops at 65,535, the renderer must count those pixels and warn; on other
/// adapters nothing is limited.
#[test]
fn llvmpipe_loop_limit_is_detected_and_reported() {
    let scene = load("ten_thousand_copies");
    let (_, stats) = kdray::render::render_scene(
        gpu(),
        &scene,
        Accel::Kdtree,
        kdray::gpu::TilePlan::DEFAULT_MAX_TILE_PIXELS,
    )
    .unwrap();
    if gpu().has_loop_limit() {
        assert!(
            stats.loop_limited_pixels > 0,
            "llvmpipe's loop limit went unnoticed"
        );
        let warning = stats.loop_limit_warning().expect("a warning");
        assert!(
            warning.contains("65,535") && warning.lines().count() == 1,
            "{warning}"
        );
    } else {
        assert_eq!(stats.loop_limited_pixels, 0);
    }
}

#[test]
fn camera_inside_a_sphere_sees_its_far_side() {
    let image = check("camera_inside_sphere", 0.0);
    // Every primary ray hits the enclosing sphere: no background anywhere.
    let background = quantize([0.1, 0.1, 0.2]);
    assert!(
        image.rgb.chunks_exact(3).all(|p| p != background),
        "a ray escaped the sphere"
    );
}

#[test]
fn light_inside_an_object() {
    check("light_inside_object", 0.3);
}

#[test]
fn rays_exactly_along_split_planes() {
    check("rays_on_split_planes", 0.1);
}

/// Every build's tree gives brute force's image on the split-plane scene,
/// with every walk. Its boxes meet at edges the rays pass through exactly,
/// so two faces are hit at one t; the GPU stores objects in each tree's
/// leaf order, and the binned and median trees rendered pixel (39, 27)
/// brighter while ties went to the lower GPU id rather than the lower
/// scene id.
#[test]
fn every_build_breaks_ties_as_brute_force_does() {
    use kdray::gpu::{GpuScene, PreparedScene};
    use kdray::kdtree::{BuildStrategy, Traversal};
    let scene = load("rays_on_split_planes");
    let brute = render(&scene, Accel::Brute);
    for strategy in BuildStrategy::ALL {
        let prepared = PreparedScene::built_by(scene.clone(), Accel::Kdtree, strategy);
        let uploaded = GpuScene::upload(gpu(), prepared).unwrap_or_else(|e| panic!("{e}"));
        for traversal in Traversal::ALL {
            let mut rgb = Vec::new();
            kdray::render::render_streaming(
                gpu(),
                &uploaded,
                None,
                kdray::render::StreamOptions::new(traversal),
                &mut |band| {
                    rgb.extend_from_slice(band.rgb);
                    Ok(())
                },
            )
            .unwrap_or_else(|e| panic!("{e}"));
            let d = compare(&rgb, &brute.rgb, brute.width, brute.height, 0);
            assert_eq!(d.pixels_over, 0, "{strategy} / {traversal:?}: {d:?}");
        }
    }
}
