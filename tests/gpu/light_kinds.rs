//! Spot and directional lights (`[[lights]]` `kind`) on the GPU: a spot
//! lights a plane inside its cone by the documented falloff and nothing
//! outside it; a directional light casts parallel shadows, also of objects
//! far away; in the path tracer both give the radiance the documented
//! units predict.

use crate::common;

use common::*;
use glam::DVec3;
use kdray::gpu::Accel;
use kdray::scene::spot_factor;
use kdray_core::reference::ReferenceTracer;

const SIZE: u32 = 64;
/// The camera looks straight down from this height at the origin, +x to
/// the right and +z down the image.
const EYE_HEIGHT: f64 = 10.0;
const VFOV: f64 = 40.0;

/// A white plane at y = 0, seen from above, under `lights` (TOML), with
/// `extra` objects.
fn plane_scene(lights: &str, extra: &str, render: &str) -> String {
    format!(
        r#"
[camera]
position = [0, {EYE_HEIGHT}, 0]
look_at = [0, 0, 0]
up = [0, 0, -1]
vfov = {VFOV}

[render]
width = {SIZE}
height = {SIZE}
{render}

[materials.white]
diffuse = [1, 1, 1]

[[triangles]]
vertices = [[-50, 0, -50], [50, 0, 50], [50, 0, -50]]
material = "white"

[[triangles]]
vertices = [[-50, 0, -50], [-50, 0, 50], [50, 0, 50]]
material = "white"
{lights}
{extra}
"#
    )
}

/// The point of the plane at the centre of pixel (row, column).
fn plane_point(row: u32, column: u32) -> DVec3 {
    let half = EYE_HEIGHT * (VFOV / 2.0).to_radians().tan();
    let at = |i: u32| ((f64::from(i) + 0.5) / f64::from(SIZE) * 2.0 - 1.0) * half;
    DVec3::new(at(column), 0.0, at(row))
}

#[test]
fn a_spot_light_lights_the_plane_inside_its_cone_by_its_falloff_and_nothing_outside() {
    let (height, inner, outer) = (2.0, 20.0f64, 30.0f64);
    let scene = scene_from_toml(&plane_scene(
        &format!(
            r#"
[[lights]]
kind = "spot"
position = [0, {height}, 0]
direction = [0, -1, 0]
inner_cone = {inner}
outer_cone = {outer}
ambient = [0, 0, 0]
specular = [0, 0, 0]
"#
        ),
        "",
        "",
    ));
    let image = render(&scene, Accel::Kdtree);
    let (cos_inner, cos_outer) = (inner.to_radians().cos(), outer.to_radians().cos());
    let (mut full, mut dark, mut between) = (0, 0, 0);
    for row in 0..SIZE {
        for column in 0..SIZE {
            let p = plane_point(row, column);
            let to_light = (DVec3::new(0.0, height, 0.0) - p).normalize();
            let cos_angle = to_light.y; // off the axis, straight down
            let expected = spot_factor(cos_angle, cos_inner, cos_outer) * to_light.y;
            let want = quantize([expected; 3])[0];
            let got = pixel(&image, row, column);
            assert!(
                got.iter().all(|&c| c.abs_diff(want) <= 1),
                "pixel ({row}, {column}) at {p}: {got:?}, want {want}"
            );
            match cos_angle {
                c if c >= cos_inner => full += 1,
                c if c <= cos_outer => dark += 1,
                _ => between += 1,
            }
        }
    }
    // The image holds all three parts of the cone: the test sees each.
    assert!(
        full > 100 && between > 100 && dark > 1000,
        "{full} {between} {dark}"
    );
    // The CPU reference agrees.
    let reference = ReferenceTracer::new(&scene, true);
    for (row, column) in [(32, 32), (32, 40), (32, 44), (20, 20), (0, 0)] {
        let (a, b) = (pixel(&image, row, column), reference.pixel(row, column));
        assert!(
            a.iter().zip(b).all(|(x, y)| x.abs_diff(y) <= 1),
            "({row}, {column}): {a:?} {b:?}"
        );
    }
}

#[test]
fn a_directional_light_casts_parallel_shadows_of_near_and_far_objects() {
    let scene = scene_from_toml(&plane_scene(
        r#"
[[lights]]
kind = "directional"
direction = [1, -1, 0]
ambient = [0, 0, 0]
specular = [0, 0, 0]
"#,
        // A ball above the origin, whose shadow falls at x = 1, and one far
        // up the light's way (behind the camera), whose shadow falls at
        // (1, 0, 2.5): beyond any finite light position in that direction
        // that a point light would need.
        r#"
[[spheres]]
center = [0, 1, 0]
radius = 0.5
material = "white"

[[spheres]]
center = [-30, 31, 2.5]
radius = 0.5
material = "white"
"#,
        "",
    ));
    let image = render(&scene, Accel::Kdtree);
    let lit = quantize([std::f64::consts::FRAC_1_SQRT_2; 3]);
    let at = |x: f64, z: f64| {
        let half = EYE_HEIGHT * (VFOV / 2.0).to_radians().tan();
        let index = |c: f64| ((c / half + 1.0) / 2.0 * f64::from(SIZE)).floor() as u32;
        pixel(&image, index(z), index(x))
    };
    assert_eq!(at(1.0, 0.0), [0, 0, 0], "the near ball's shadow");
    assert_eq!(at(1.0, 2.5), [0, 0, 0], "the far ball's shadow");
    for (x, z) in [(-2.0, 0.0), (1.0, -1.5), (2.5, 2.5), (-1.0, 2.5)] {
        let got = at(x, z);
        assert!(
            got.iter().all(|&c| c.abs_diff(lit[0]) <= 1),
            "({x}, {z}): {got:?}, want {lit:?}"
        );
    }
    let reference = ReferenceTracer::new(&scene, true);
    assert_eq!(reference.pixel(32, 42), pixel(&image, 32, 42));
}

/// The sRGB transfer function, as the PNG encodes linear radiance with
/// `tone_map = "clamp"`.
fn srgb_level(x: f64) -> u8 {
    let x = x.clamp(0.0, 1.0);
    let v = if x <= 0.0031308 {
        12.92 * x
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    };
    (255.0 * v + 0.5).floor() as u8
}

#[test]
fn path_traced_delta_lights_give_the_radiance_their_units_predict() {
    let albedo = 0.5;
    let path = "integrator = \"path\"\ntone_map = \"clamp\"\nsamples = 4\nmax_depth = 2";
    // A directional light of irradiance E straight down: a E / pi.
    let irradiance = [1.0, 2.0, 4.0];
    let directional = scene_from_toml(
        &plane_scene(
            &format!(
                "[[lights]]\nkind = \"directional\"\ndirection = [0, -1, 0]\ndiffuse = {irradiance:?}\n"
            ),
            "",
            path,
        )
        .replace("diffuse = [1, 1, 1]", &format!("diffuse = [{albedo}, {albedo}, {albedo}]")),
    );
    let image = render(&directional, Accel::Kdtree);
    let want = irradiance.map(|e| srgb_level(albedo * e / std::f64::consts::PI));
    for (row, column) in [(0, 0), (32, 32), (63, 10)] {
        let got = pixel(&image, row, column);
        assert!(
            got.iter().zip(want).all(|(g, w)| g.abs_diff(w) <= 1),
            "({row}, {column}): {got:?}, want {want:?}"
        );
    }
    // A spot light of intensity I at height h, straight above: a I / (pi h^2)
    // inside its inner cone, nothing outside its outer one.
    let (intensity, h) = (2.0, 1.5);
    let spot = scene_from_toml(
        &plane_scene(
            &format!(
                "[[lights]]\nkind = \"spot\"\nposition = [0, {h}, 0]\ndirection = [0, -1, 0]\ninner_cone = 10\nouter_cone = 20\ndiffuse = [{intensity}, {intensity}, {intensity}]\n"
            ),
            "",
            path,
        )
        .replace("diffuse = [1, 1, 1]", &format!("diffuse = [{albedo}, {albedo}, {albedo}]")),
    );
    let image = render(&spot, Accel::Kdtree);
    // Pixel (31, 31)'s centre is 0.06 off the axis: cos^3 of its angle is 0.998.
    let p = plane_point(31, 31);
    let d2 = p.length_squared() + h * h;
    let cos = h / d2.sqrt();
    let centre = srgb_level(albedo / std::f64::consts::PI * intensity * cos / d2);
    let got = pixel(&image, 31, 31);
    assert!(
        got.iter().all(|&g| g.abs_diff(centre) <= 1),
        "{got:?}, want {centre}"
    );
    assert_eq!(pixel(&image, 31, 50), [0, 0, 0], "outside the outer cone");
}

/// A scene with a spot or a directional light gets a pipeline with the
/// light kinds (`SPOT_OR_DIRECTIONAL_LIGHTS`), one with point lights only a
/// pipeline without them; both render what the general kernel renders, bit
/// for bit.
#[test]
fn the_pipeline_holds_the_light_kinds_only_where_the_scene_has_them() {
    use kdray::gpu::{GpuScene, PreparedScene, Renderer};
    let ctx = gpu();
    let specialised = Renderer::new(ctx).unwrap_or_else(|e| panic!("{e}"));
    let general = Renderer::general(ctx).unwrap_or_else(|e| panic!("{e}"));
    let point = "[[lights]]\nposition = [1, 3, 0]\nambient = [0.1, 0.1, 0.1]\n";
    let spot = "[[lights]]\nkind = \"spot\"\nposition = [0, 2, 0]\ndirection = [0, -1, 0]\ninner_cone = 20\nouter_cone = 30\n";
    let directional = "[[lights]]\nkind = \"directional\"\ndirection = [0.3, -1, 0.2]\n";
    let ball = "[[spheres]]\ncenter = [0.5, 1, 0.5]\nradius = 0.5\nmaterial = \"white\"\n";
    for (lights, kinds) in [
        (point.to_string(), false),
        (format!("{point}{spot}"), true),
        (format!("{directional}{point}"), true),
    ] {
        let scene = scene_from_toml(&plane_scene(&lights, ball, ""));
        let uploaded = GpuScene::upload(ctx, PreparedScene::new(scene.clone(), Accel::Kdtree))
            .unwrap_or_else(|e| panic!("{e}"));
        let buffers = uploaded.buffers();
        let params = uploaded.frame_params();
        let variant = specialised.variant_for(buffers, &params, false);
        assert_eq!(variant.spot_or_directional_lights, kinds, "{lights}");
        let (a, b) = render_pair(&specialised, &general, buffers, params);
        assert!(a.rgb == b.rgb, "{lights}: the specialised image differs");
        assert_eq!(a.rays, b.rays, "{lights}");
    }
}
