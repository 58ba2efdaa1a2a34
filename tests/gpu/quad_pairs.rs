//! A one-quad glTF scene and the assertions its tests of material
//! features share (`material_maps`, `vertex_attributes`): two ways of
//! stating a surface must render alike, and unlike the plain surface.

use crate::common;
use crate::common::textured;

use common::{compare, gpu, render, TempDir};
use kdray::gpu::Accel;
use kdray::scene::{load_scene, Scene};
use kdray_core::reference::ReferenceTracer;
use textured::write_gltf_quad_attributes;

/// The images' side, in pixels.
pub const SIDE: u32 = 32;

/// The quad of `material` (textures `images`, vertex attributes
/// `attributes`), seen head-on by `integrator`, lit by a point light off to
/// the side (with an ambient part) over a black sky.
pub fn quad_scene(
    dir: &TempDir,
    integrator: &str,
    material: &str,
    images: &[image::RgbaImage],
    attributes: &[(&str, Vec<Vec<f32>>)],
) -> Scene {
    let gltf = write_gltf_quad_attributes(&dir.path, "quad.gltf", material, images, attributes);
    // The Whitted integrator's samples are a square grid, and its point
    // light does not fall off with distance.
    let (samples, power) = if integrator == "path" {
        (8, 3.0)
    } else {
        (4, 0.5)
    };
    let text = format!(
        "[camera]\nposition = [0, 0, 2.2]\nlook_at = [0, 0, 0]\nvfov = 60\n\
         [render]\nwidth = {SIDE}\nheight = {SIDE}\nintegrator = \"{integrator}\"\nsamples = {samples}\nmax_depth = 3\n\
         background = [0, 0, 0]\n\
         [[lights]]\nposition = [1.5, 0.8, 1.2]\nambient = [0.6, 0.6, 0.6]\ndiffuse = [{power}, {power}, {power}]\nspecular = [0, 0, 0]\n\
         [[meshes]]\npath = {:?}\n",
        gltf.file_name().unwrap().to_str().unwrap()
    );
    let path = dir.join("scene.toml");
    std::fs::write(&path, text).unwrap();
    load_scene(&path).unwrap_or_else(|e| panic!("{e}"))
}

pub fn texel(r: u8, g: u8, b: u8) -> image::RgbaImage {
    image::RgbaImage::from_pixel(1, 1, image::Rgba([r, g, b, 255]))
}

/// The same values at the quad's four corners.
pub fn at_corners(v: &[f32]) -> Vec<Vec<f32>> {
    vec![v.to_vec(); 4]
}

/// Asserts that `a` and `b` render alike (pixels at most `levels` apart),
/// and returns how many pixels of `a` differ from `plain`'s.
pub fn assert_alike(what: &str, a: &Scene, b: &Scene, levels: u8, plain: &Scene) -> usize {
    let _ = gpu();
    let (ia, ib, ip) = (
        render(a, Accel::Kdtree),
        render(b, Accel::Kdtree),
        render(plain, Accel::Kdtree),
    );
    let d = compare(&ia.rgb, &ib.rgb, SIDE, SIDE, levels);
    assert_eq!(d.pixels_over, 0, "{what}: {d:?}");
    compare(&ia.rgb, &ip.rgb, SIDE, SIDE, 2).pixels_over
}

/// The Whitted image of `scene` equals the CPU reference's within a level.
pub fn assert_matches_the_reference(what: &str, scene: &Scene) {
    let gpu_image = render(scene, Accel::Kdtree);
    let reference = ReferenceTracer::new(scene, true).image();
    let d = compare(&gpu_image.rgb, &reference, SIDE, SIDE, 1);
    assert_eq!(
        d.pixels_over, 0,
        "{what}: GPU against the CPU reference: {d:?}"
    );
}

/// Most of the picture (the quad fills it) changed.
pub fn assert_most_changed(what: &str, changed: usize) {
    assert!(
        changed > (SIDE * SIDE / 4) as usize,
        "{what} changed {changed} pixels"
    );
}
