//! A glTF material's maps in the path tracer, each against the same surface
//! stated without it: a one-texel normal map and that normal given at the
//! vertices (in the Whitted integrator too); a one-texel metallic-roughness map and its values as factors;
//! a one-texel emissive map and its linear colour as the emission; a
//! one-texel base-colour texture and its colour decoded from sRGB. Each map
//! also changes the picture against the plain surface, so a map the kernel
//! ignored would fail.

use crate::common;
use crate::quad_pairs::{
    assert_alike, assert_matches_the_reference, assert_most_changed, quad_scene, texel,
};

use common::TempDir;
use glam::{DVec3, Vec3};
use kdray::scene::{MetalRough, Scene};

/// The quad in `material` (textures `images`), seen head-on, path traced,
/// lit by a point light off to the side over a black sky.
fn path_traced_quad(dir: &TempDir, material: &str, images: &[image::RgbaImage]) -> Scene {
    quad_scene(dir, "path", material, images, &[])
}

/// The sRGB transfer function's inverse, as the kernel decodes texels.
fn srgb_to_linear(byte: u8) -> f64 {
    let c = byte as f64 / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// The normal map's quad against the same quad with the map's one normal
/// given at its vertices, seen by `integrator`.
fn assert_one_texel_normal_map_equals_that_normal(integrator: &str) {
    let dir = TempDir::new(&format!("maps-normal-{integrator}"));
    let bytes = [224u8, 96, 200];
    let material = r#"{"pbrMetallicRoughness":{"baseColorFactor":[0.8,0.8,0.8,1],"metallicFactor":0,
        "roughnessFactor":1},"normalTexture":{"index":0,"scale":0.9}}"#;
    let mapped = quad_scene(
        &dir,
        integrator,
        material,
        &[texel(bytes[0], bytes[1], bytes[2])],
        &[],
    );
    // The tangent frame: T = dp/du = +x (u grows with x), n = +z, B = n x T = +y.
    let c = bytes.map(|b| b as f32 / 255.0 * 2.0 - 1.0);
    let n = (Vec3::X * (c[0] * 0.9) + Vec3::Y * (c[1] * 0.9) + Vec3::Z * c[2]).normalize();
    let mut given = mapped.clone();
    given.materials[0].maps.normal = None;
    given.triangle_normals.push([n.as_dvec3(); 3]);
    let index = given.triangle_normals.len() as u32 - 1;
    for t in &mut given.triangles {
        t.normals = index;
    }
    let mut plain = mapped.clone();
    plain.materials[0].maps.normal = None;
    let changed = assert_alike(
        &format!("normal map, {integrator}"),
        &mapped,
        &given,
        2,
        &plain,
    );
    assert_most_changed("the map", changed);
}

#[test]
fn a_one_texel_normal_map_equals_that_normal_given_at_the_vertices() {
    assert_one_texel_normal_map_equals_that_normal("path");
}

/// The Whitted integrator bends its shading normal by the map as the path
/// tracer does, and as the CPU reference does.
#[test]
fn the_whitted_integrator_reads_the_normal_map_as_the_path_tracer_does() {
    assert_one_texel_normal_map_equals_that_normal("whitted");
    let dir = TempDir::new("maps-normal-reference");
    let material = r#"{"pbrMetallicRoughness":{"baseColorFactor":[0.8,0.8,0.8,1],"metallicFactor":0,
        "roughnessFactor":1},"normalTexture":{"index":0,"scale":0.9}}"#;
    let mapped = quad_scene(&dir, "whitted", material, &[texel(224, 96, 200)], &[]);
    assert_matches_the_reference("normal map", &mapped);
}

#[test]
fn a_one_texel_metallic_roughness_map_equals_its_values_as_factors() {
    let dir = TempDir::new("maps-metal-rough");
    let (g, b) = (70u8, 230u8);
    let material = r#"{"pbrMetallicRoughness":{"baseColorFactor":[0.9,0.6,0.3,1],"metallicFactor":1,
        "roughnessFactor":1,"metallicRoughnessTexture":{"index":0}}}"#;
    let mapped = path_traced_quad(&dir, material, &[texel(0, g, b)]);
    let mut given = mapped.clone();
    given.materials[0].maps.metal_rough = None;
    given.materials[0].physical.metal_rough = Some(MetalRough {
        metallic: (b as f32 / 255.0) as f64,
        roughness: (g as f32 / 255.0) as f64,
    });
    let mut plain = mapped.clone();
    plain.materials[0].maps.metal_rough = None;
    let changed = assert_alike("metallic-roughness map", &mapped, &given, 1, &plain);
    assert_most_changed("the map", changed);
}

#[test]
fn a_one_texel_emissive_map_equals_its_linear_colour_as_emission() {
    let dir = TempDir::new("maps-emissive");
    let bytes = [200u8, 120, 40];
    let material = r#"{"pbrMetallicRoughness":{"baseColorFactor":[0.2,0.2,0.2,1],"metallicFactor":0,
        "roughnessFactor":1},"emissiveFactor":[1,0.5,1],"emissiveTexture":{"index":0}}"#;
    let mut mapped = path_traced_quad(&dir, material, &[texel(bytes[0], bytes[1], bytes[2])]);
    // Lit by its own emission alone: next-event estimation picks lights by
    // power, which counts an emitter's factor and not its texture, so
    // beside the point light the map and its colour as the factor would be
    // picked at other rates (the same mean, other noise).
    mapped.lights.clear();
    let mut given = mapped.clone();
    given.materials[0].maps.emissive = None;
    given.materials[0].physical.emission = DVec3::new(
        srgb_to_linear(bytes[0]),
        0.5 * srgb_to_linear(bytes[1]),
        srgb_to_linear(bytes[2]),
    );
    let mut plain = mapped.clone();
    plain.materials[0].maps.emissive = None;
    let changed = assert_alike("emissive map", &mapped, &given, 2, &plain);
    assert_most_changed("the map", changed);
}

#[test]
fn a_base_colour_texture_is_decoded_from_srgb_in_path_mode() {
    let dir = TempDir::new("maps-base");
    let bytes = [180u8, 120, 60];
    let material = r#"{"pbrMetallicRoughness":{"baseColorFactor":[1,1,1,1],"metallicFactor":0,
        "roughnessFactor":1,"baseColorTexture":{"index":0}}}"#;
    let mapped = path_traced_quad(&dir, material, &[texel(bytes[0], bytes[1], bytes[2])]);
    let mut given = mapped.clone();
    given.materials[0].texture = None;
    given.materials[0].diffuse = DVec3::from_array(bytes.map(srgb_to_linear));
    // As stored (byte / 255, the Whitted integrator's reading), the picture
    // is brighter.
    let mut stored = mapped.clone();
    stored.materials[0].texture = None;
    stored.materials[0].diffuse = DVec3::from_array(bytes.map(|b| b as f64 / 255.0));
    let changed = assert_alike("base colour", &mapped, &given, 2, &stored);
    assert_most_changed("decoding", changed);
}
