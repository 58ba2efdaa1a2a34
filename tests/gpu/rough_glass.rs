//! Rough (frosted) glass and thin walls in the path tracer
//! (shaders/bsdf_rough_dielectric.wgsl, `transmission_roughness` and
//! `thin_walled`): a glass ball in front of a wall whose left half glows
//! red and right half blue, seen through the ball. The lobes themselves are
//! checked against their CPU counterparts in bsdf_lobes.rs.

use crate::common;

use common::*;
use kdray::gpu::{Accel, GpuScene, PreparedScene, Renderer, TilePlan};
use kdray::scene::Scene;

const SIDE: u32 = 24;

/// The ball of `keys` (glass of index 1.5) before the two-coloured wall.
fn ball(keys: &str, samples: u32, seed: u32) -> Scene {
    scene_from_toml(&format!(
        r#"
        [camera]
        position = [0, 0, 4]
        look_at = [0, 0, 0]
        vfov = 32
        [render]
        width = {SIDE}
        height = {SIDE}
        integrator = "path"
        samples = {samples}
        seed = {seed}
        max_depth = 8
        [materials.glass]
        diffuse = [0, 0, 0]
        transmission = 1
        ior = 1.5
        {keys}
        [materials.red]
        diffuse = [0, 0, 0]
        emission = [1.0, 0.1, 0.1]
        [materials.blue]
        diffuse = [0, 0, 0]
        emission = [0.1, 0.1, 1.0]
        [[spheres]]
        center = [0, 0, 0]
        radius = 1
        material = "glass"
        [[triangles]]
        vertices = [[-8, -8, -3], [0, -8, -3], [0, 8, -3]]
        material = "red"
        [[triangles]]
        vertices = [[-8, -8, -3], [0, 8, -3], [-8, 8, -3]]
        material = "red"
        [[triangles]]
        vertices = [[0, -8, -3], [8, -8, -3], [8, 8, -3]]
        material = "blue"
        [[triangles]]
        vertices = [[0, -8, -3], [8, 8, -3], [0, 8, -3]]
        material = "blue"
        "#
    ))
}

/// The frame's mean radiance per pixel (r, g, b, row-major).
fn radiance(scene: &Scene) -> Vec<f32> {
    let ctx = gpu();
    let prepared = PreparedScene::new(scene.clone(), Accel::Kdtree);
    let uploaded = GpuScene::upload(ctx, prepared).unwrap_or_else(|e| panic!("{e}"));
    let renderer = Renderer::new(ctx)
        .unwrap_or_else(|e| panic!("{e}"))
        .with_settings(&scene.render)
        .with_radiance();
    let plan = TilePlan::new(
        SIDE,
        SIDE,
        TilePlan::DEFAULT_MAX_TILE_PIXELS,
        kdray::gpu::max_binding_bytes(&ctx.device.limits()),
    );
    let mut out = Vec::new();
    let summary = renderer
        .render_bands_with_cost(
            ctx,
            uploaded.buffers(),
            uploaded.frame_params(),
            plan,
            false,
            &mut |band| {
                out.extend_from_slice(band.radiance.expect("path frames carry radiance"));
                Ok(())
            },
        )
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(summary.rays.nonfinite, 0, "no sample is NaN or infinite");
    out
}

/// The pixels well inside the ball's disc (its radius is about 11 pixels).
fn inside_ball() -> impl Iterator<Item = usize> {
    let c = SIDE as i32 / 2;
    (0..SIDE as i32 * SIDE as i32)
        .filter(move |i| {
            let (x, y) = (i % SIDE as i32 - c, i / SIDE as i32 - c);
            x * x + y * y <= 25
        })
        .map(|i| i as usize)
}

/// The mean over the ball's pixels of |a - b| in every channel.
fn mean_difference(a: &[f32], b: &[f32]) -> f64 {
    let pixels: Vec<usize> = inside_ball().collect();
    let sum: f64 = pixels
        .iter()
        .flat_map(|&p| (0..3).map(move |c| 3 * p + c))
        .map(|i| (a[i] as f64 - b[i] as f64).abs())
        .sum();
    sum / (3 * pixels.len()) as f64
}

/// Frosted glass blurs what it shows: its image of the wall differs from
/// the smooth ball's by far more than two renders of the smooth ball with
/// different seeds differ (the noise).
#[test]
fn a_rough_glass_ball_blurs_what_the_smooth_one_shows() {
    let smooth = radiance(&ball("", 64, 1));
    let noise = mean_difference(&smooth, &radiance(&ball("", 64, 2)));
    let rough = radiance(&ball("transmission_roughness = 0.5", 64, 1));
    let blur = mean_difference(&smooth, &rough);
    assert!(
        blur > 5.0 * noise,
        "rough vs smooth {blur}, the noise {noise}"
    );
}

/// As its roughness tends to 0, frosted glass converges to the smooth
/// ball: over the ball's pixels the two images' mean differs by no more
/// than the noise (four standard errors of the per-pixel differences) and
/// the light single-scattering microfacets lose (under 0.5%).
#[test]
fn a_frosted_ball_of_roughness_near_0_converges_to_the_smooth_one() {
    let smooth = radiance(&ball("", 256, 3));
    let frosted = radiance(&ball("transmission_roughness = 0.02", 256, 4));
    let pixels: Vec<usize> = inside_ball().collect();
    for c in 0..3 {
        let d: Vec<f64> = pixels
            .iter()
            .map(|&p| frosted[3 * p + c] as f64 - smooth[3 * p + c] as f64)
            .collect();
        let n = d.len() as f64;
        let mean = d.iter().sum::<f64>() / n;
        let var = d.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / (n - 1.0);
        let level = pixels
            .iter()
            .map(|&p| smooth[3 * p + c] as f64)
            .sum::<f64>()
            / n;
        assert!(
            mean.abs() <= 4.0 * (var / n).sqrt() + 0.005 * level,
            "channel {c}: mean difference {mean}, standard error {}, level {level}",
            (var / n).sqrt()
        );
    }
}

/// A solid ball is a lens: it shows the wall upside down and mirrored, so
/// left of its centre it shows the blue half. A thin-walled one lets the
/// light through unbent: left of its centre, the red half.
#[test]
fn a_thin_walled_ball_shows_the_wall_unbent_and_a_solid_one_inverted() {
    let left = ((SIDE / 2) * SIDE + SIDE / 2 - 4) as usize;
    for (keys, red_side) in [
        ("", false),
        ("thin_walled = true", true),
        ("thin_walled = true\ntransmission_roughness = 0.1", true),
    ] {
        let image = radiance(&ball(keys, 16, 1));
        let (r, b) = (image[3 * left], image[3 * left + 2]);
        assert_eq!(r > 2.0 * b, red_side, "{keys:?}: red {r}, blue {b}");
        assert_eq!(b > 2.0 * r, !red_side, "{keys:?}: red {r}, blue {b}");
    }
}
