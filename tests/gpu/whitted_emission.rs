//! Emission in the Whitted integrator: a material's `emission` adds to the
//! colour of every hit on it (docs/scene-format.md, "Shading"), on the GPU
//! as in the CPU reference.

use crate::common;

use common::*;
use kdray::gpu::Accel;
use kdray_core::reference::ReferenceTracer;

/// A unit sphere at the origin seen head-on from z = 5, black but for its
/// emission; a light off to the side that gives no ambient light.
fn emitting_sphere(emission: [f64; 3], shadow_mode: &str) -> String {
    format!(
        r#"
[camera]
position = [0, 0, 5]
look_at = [0, 0, 0]
vfov = 40

[render]
width = 32
height = 32
background = [0.1, 0.1, 0.1]
shadow_mode = "{shadow_mode}"

[[lights]]
position = [0, 0, -10]
ambient = [0, 0, 0]

[materials.glow]
diffuse = [0, 0, 0]
emission = [{}, {}, {}]

[[spheres]]
center = [0, 0, 0]
radius = 1
material = "glow"
"#,
        emission[0], emission[1], emission[2]
    )
}

#[test]
fn a_black_emitting_sphere_shows_its_emission_under_whitted() {
    let emission = [0.2, 0.45, 0.7];
    // The light is behind the sphere: the side seen is unlit, so its colour
    // is its emission alone; "seed" would drop an unlit hit that did not emit.
    for mode in ["ambient", "seed"] {
        let scene = scene_from_toml(&emitting_sphere(emission, mode));
        let image = render(&scene, Accel::Kdtree);
        assert_eq!(pixel(&image, 16, 16), quantize(emission), "{mode}: centre");
        assert_eq!(
            pixel(&image, 13, 18),
            quantize(emission),
            "{mode}: off centre"
        );
        assert_eq!(
            pixel(&image, 0, 0),
            quantize([0.1; 3]),
            "{mode}: background"
        );
        let reference = ReferenceTracer::new(&scene, true);
        assert_eq!(
            reference.pixel(16, 16),
            quantize(emission),
            "{mode}: reference"
        );
    }
}

#[test]
fn whitted_emission_above_one_is_clamped_like_any_colour() {
    let scene = scene_from_toml(&emitting_sphere([4.0, 0.0, 0.5], "ambient"));
    let image = render(&scene, Accel::Kdtree);
    assert_eq!(pixel(&image, 16, 16), quantize([1.0, 0.0, 0.5]));
}
