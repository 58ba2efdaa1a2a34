//! What a glTF primitive carries beside positions and normals, on the GPU,
//! each against the same surface stated another way: `COLOR_0` and the same
//! colour as `baseColorFactor` (both integrators); a normal map in the
//! frame of the file's `TANGENT`, and in MikkTSpace's frame of a mirrored
//! texture mapping (read through `TEXCOORD_1`), and that normal given at the
//! vertices; an occlusion map and the ambient colour it leaves (Whitted),
//! and no change at all in the path tracer. The Whitted images also equal
//! the CPU reference's. Each also differs from the
//! plain surface, so an attribute the kernel ignored would fail.

use crate::common;
use crate::common::textured;
use crate::quad_pairs::*;

use common::{compare, gpu, render, TempDir};
use glam::Vec3;
use kdray::gpu::Accel;
use kdray::scene::{load_scene, Scene};

#[test]
fn vertex_colours_equal_the_same_colour_as_base_colour_factor() {
    let colour = [0.9f32, 0.4, 0.2];
    for integrator in ["whitted", "path"] {
        let dir = TempDir::new(&format!("colour-0-{integrator}"));
        let material = |factor: [f32; 3]| {
            format!(
                r#"{{"pbrMetallicRoughness":{{"baseColorFactor":[{},{},{},1],"metallicFactor":0,
                "roughnessFactor":1,"baseColorTexture":{{"index":0}}}}}}"#,
                factor[0], factor[1], factor[2]
            )
        };
        let white = [texel(255, 255, 255)];
        let coloured = quad_scene(
            &dir,
            integrator,
            &material([1.0; 3]),
            &white,
            &[(
                "COLOR_0",
                at_corners(&[colour[0], colour[1], colour[2], 1.0]),
            )],
        );
        assert!(!coloured.triangle_colours.is_empty());
        let factor = quad_scene(&dir, integrator, &material(colour), &white, &[]);
        let plain = quad_scene(&dir, integrator, &material([1.0; 3]), &white, &[]);
        let changed = assert_alike(
            &format!("COLOR_0 ({integrator})"),
            &coloured,
            &factor,
            1,
            &plain,
        );
        assert_most_changed("COLOR_0", changed);
    }
}

/// A quad without textures whose only attribute is `COLOR_0` gets a record
/// too: its colour shows.
#[test]
fn vertex_colours_show_on_an_untextured_surface() {
    let dir = TempDir::new("colour-0-untextured");
    let material = |g: f32| {
        format!(
            r#"{{"pbrMetallicRoughness":{{"baseColorFactor":[1,{g},1,1],"metallicFactor":0,"roughnessFactor":1}}}}"#
        )
    };
    let coloured = quad_scene(
        &dir,
        "whitted",
        &material(1.0),
        &[],
        &[("COLOR_0", at_corners(&[1.0, 0.25, 1.0]))],
    );
    let factor = quad_scene(&dir, "whitted", &material(0.25), &[], &[]);
    let plain = quad_scene(&dir, "whitted", &material(1.0), &[], &[]);
    let changed = assert_alike("COLOR_0 without textures", &coloured, &factor, 1, &plain);
    assert_most_changed("COLOR_0", changed);
    assert_matches_the_reference("COLOR_0", &coloured);
}

/// The scene `mapped` with its normal map replaced by the normal `n` at
/// every vertex.
fn with_vertex_normal(mapped: &Scene, n: Vec3) -> Scene {
    let mut given = mapped.clone();
    given.materials[0].maps.normal = None;
    given.triangle_normals.push([n.as_dvec3(); 3]);
    let index = given.triangle_normals.len() as u32 - 1;
    for t in &mut given.triangles {
        t.normals = index;
    }
    given
}

const NORMAL_MAPPED: &str = r#"{"pbrMetallicRoughness":{"baseColorFactor":[0.8,0.8,0.8,1],"metallicFactor":0,
    "roughnessFactor":1},"normalTexture":{"index":0,"scale":0.9}}"#;
const NORMAL_TEXEL: [u8; 3] = [224, 96, 200];

/// The normal NORMAL_TEXEL gives at scale 0.9 in the frame (t, b, +z).
fn bent(t: Vec3, b: Vec3) -> Vec3 {
    let c = NORMAL_TEXEL.map(|v| v as f32 / 255.0 * 2.0 - 1.0);
    (t * (c[0] * 0.9) + b * (c[1] * 0.9) + Vec3::Z * c[2]).normalize()
}

#[test]
fn a_normal_map_bends_the_normal_in_the_frame_of_the_file_s_tangents() {
    let dir = TempDir::new("tangent-file");
    let [r, g, b] = NORMAL_TEXEL;
    // TANGENT +y with w = 1: the bitangent is n x t = z x y = -x.
    let mapped = quad_scene(
        &dir,
        "path",
        NORMAL_MAPPED,
        &[texel(r, g, b)],
        &[
            ("NORMAL", at_corners(&[0.0, 0.0, 1.0])),
            ("TANGENT", at_corners(&[0.0, 1.0, 0.0, 1.0])),
        ],
    );
    let given = with_vertex_normal(&mapped, bent(Vec3::Y, -Vec3::X));
    // The frame MikkTSpace would build (u along +x) gives another normal.
    let other = with_vertex_normal(&mapped, bent(Vec3::X, Vec3::Y));
    let changed = assert_alike("file tangents", &mapped, &given, 2, &other);
    assert!(changed > 0, "the two frames rendered alike");
}

#[test]
fn a_mirrored_texture_mapping_keeps_the_normal_map_s_green_up_the_image() {
    let dir = TempDir::new("tangent-mirrored");
    let [r, g, b] = NORMAL_TEXEL;
    // The normal map reads TEXCOORD_1: u mirrored (it grows along -x), v
    // as the image's. MikkTSpace's tangent is then -x, and the bitangent
    // still points up the image (+y).
    let mirrored: Vec<Vec<f32>> = textured::IMAGE_UVS
        .iter()
        .map(|uv| vec![1.0 - uv[0], uv[1]])
        .collect();
    let material =
        NORMAL_MAPPED.replace(r#""index":0,"scale""#, r#""index":0,"texCoord":1,"scale""#);
    let mapped = quad_scene(
        &dir,
        "path",
        &material,
        &[texel(r, g, b)],
        &[("TEXCOORD_1", mirrored)],
    );
    let given = with_vertex_normal(&mapped, bent(-Vec3::X, Vec3::Y));
    let unmirrored = with_vertex_normal(&mapped, bent(Vec3::X, Vec3::Y));
    let changed = assert_alike("mirrored mapping", &mapped, &given, 2, &unmirrored);
    assert!(changed > 0, "mirroring changed nothing");
}

#[test]
fn an_occlusion_map_darkens_the_whitted_ambient_term_by_its_strength() {
    let red = 90u8;
    let strength = 0.6;
    let material = format!(
        r#"{{"pbrMetallicRoughness":{{"baseColorFactor":[0.9,0.9,0.9,1],"metallicFactor":0,
        "roughnessFactor":1}},"occlusionTexture":{{"index":0,"strength":{strength}}}}}"#
    );
    let occlusion = [texel(red, 255, 255)];
    let dir = TempDir::new("occlusion-whitted");
    let mapped = quad_scene(&dir, "whitted", &material, &occlusion, &[]);
    let mut given = mapped.clone();
    given.materials[0].maps.occlusion = None;
    let scale = 1.0 + strength * (red as f64 / 255.0 - 1.0);
    given.materials[0].ambient *= scale;
    let mut plain = mapped.clone();
    plain.materials[0].maps.occlusion = None;
    let changed = assert_alike("occlusion (Whitted)", &mapped, &given, 1, &plain);
    assert_most_changed("the occlusion map", changed);
    assert_matches_the_reference("occlusion", &mapped);

    // The path tracer has no ambient term: the map changes nothing.
    let dir = TempDir::new("occlusion-path");
    let mapped = quad_scene(&dir, "path", &material, &occlusion, &[]);
    let mut plain = mapped.clone();
    plain.materials[0].maps.occlusion = None;
    let changed = assert_alike("occlusion (path)", &mapped, &plain, 0, &plain);
    assert_eq!(changed, 0);
}

/// Each texture reads its own coordinates: a base colour texture on
/// `TEXCOORD_0` beside an occlusion map on a mirrored `TEXCOORD_1`, or on
/// `TEXCOORD_0` with a `KHR_texture_transform` that mirrors u, renders as the
/// occlusion map's image mirrored on `TEXCOORD_0` does (Whitted, equal to the
/// CPU reference), and unlike the unmirrored image.
#[test]
fn each_texture_reads_its_own_texture_coordinates_and_transform() {
    let two = |a: [u8; 3], b: [u8; 3]| {
        image::RgbaImage::from_fn(2, 1, |x, _| {
            let c = if x == 0 { a } else { b };
            image::Rgba([c[0], c[1], c[2], 255])
        })
    };
    let base = two([200, 60, 60], [60, 200, 60]);
    let occlusion = two([40, 0, 0], [250, 0, 0]);
    let mirrored = two([250, 0, 0], [40, 0, 0]);
    let material = |occlusion_info: &str| {
        format!(
            r#"{{"pbrMetallicRoughness":{{"baseColorFactor":[1,1,1,1],"metallicFactor":0,
            "roughnessFactor":1,"baseColorTexture":{{"index":0}}}},
            "occlusionTexture":{{"index":1{occlusion_info}}}}}"#
        )
    };
    let mirrored_u: Vec<Vec<f32>> = textured::IMAGE_UVS
        .iter()
        .map(|uv| vec![1.0 - uv[0], uv[1]])
        .collect();
    let dir = TempDir::new("uv-channels");
    let on_second = quad_scene(
        &dir,
        "whitted",
        &material(r#","texCoord":1"#),
        &[base.clone(), occlusion.clone()],
        &[("TEXCOORD_1", mirrored_u)],
    );
    assert!(!on_second.triangle_second_uvs.is_empty());
    let transformed = quad_scene(
        &dir,
        "whitted",
        &material(r#","extensions":{"KHR_texture_transform":{"scale":[-1,1],"offset":[1,0]}}"#),
        &[base.clone(), occlusion.clone()],
        &[],
    );
    let given = quad_scene(
        &dir,
        "whitted",
        &material(""),
        &[base.clone(), mirrored],
        &[],
    );
    let plain = quad_scene(&dir, "whitted", &material(""), &[base, occlusion], &[]);
    let changed = assert_alike("TEXCOORD_1", &on_second, &given, 1, &plain);
    assert_most_changed("mirroring the occlusion map", changed);
    let changed = assert_alike("KHR_texture_transform", &transformed, &given, 1, &plain);
    assert_most_changed("mirroring the occlusion map", changed);
    assert_matches_the_reference("two channels", &on_second);
    assert_matches_the_reference("a transformed channel", &transformed);
}

/// A real model: the barrel Blender exported with its own MikkTSpace
/// `TANGENT`s (tests/models/barrel/) renders, path traced, as it does with
/// those tangents dropped and kdray's MikkTSpace tangents in their place:
/// the same frame, bitangent sign included, within the rounding of two
/// programs (at most 0.1% of pixels more than 4 levels apart; on lavapipe
/// none is more than 1 apart, and the opposite bitangent sign puts 70 more
/// than 8 apart). Without its normal map it renders otherwise, so the
/// frames are what is compared.
#[test]
fn a_blender_models_tangents_equal_kdrays_mikktspace_tangents() {
    let _ = gpu();
    let path = common::repo_path("tests/models/barrel/barrel.glb");
    let dir = TempDir::new("barrel-tangents");
    let without = dir.join("barrel_without_tangents.glb");
    std::fs::write(
        &without,
        glb_without_attribute(&std::fs::read(&path).unwrap(), "TANGENT"),
    )
    .unwrap();
    let side = 96;
    let open = |p: &std::path::Path| {
        let mut scene = load_scene(p).unwrap_or_else(|e| panic!("{e}"));
        scene.render.width = side;
        scene.render.height = side;
        scene.render.integrator = kdray::scene::Integrator::Path;
        scene.render.samples = 16;
        scene
    };
    let (given, generated) = (open(&path), open(&without));
    assert!(!given.triangle_tangents.is_empty() && !generated.triangle_tangents.is_empty());
    let mut unmapped = given.clone();
    for m in &mut unmapped.materials {
        m.maps.normal = None;
    }
    let (a, b, plain) = (
        render(&given, Accel::Kdtree),
        render(&generated, Accel::Kdtree),
        render(&unmapped, Accel::Kdtree),
    );
    let d = compare(&a.rgb, &b.rgb, side, side, 4);
    eprintln!("file against kdray's tangents: {d:?}");
    assert!(
        d.pixels_over * 1000 <= (side * side) as usize,
        "file tangents against kdray's: {d:?}"
    );
    let map = compare(&a.rgb, &plain.rgb, side, side, 8);
    eprintln!("with against without the normal map: {map:?}");
    assert!(map.pixels_over > 100, "the normal map changed only {map:?}");
}

/// A GLB file's bytes with the vertex attribute `name` taken out of every
/// primitive (its accessor stays, unused).
fn glb_without_attribute(glb: &[u8], name: &str) -> Vec<u8> {
    let word = |at: usize| u32::from_le_bytes(glb[at..at + 4].try_into().unwrap()) as usize;
    let json_length = word(12);
    let mut json: serde_json::Value = serde_json::from_slice(&glb[20..20 + json_length]).unwrap();
    for mesh in json["meshes"].as_array_mut().unwrap() {
        for primitive in mesh["primitives"].as_array_mut().unwrap() {
            primitive["attributes"]
                .as_object_mut()
                .unwrap()
                .remove(name);
        }
    }
    let mut text = serde_json::to_vec(&json).unwrap();
    while !text.len().is_multiple_of(4) {
        text.push(b' ');
    }
    let rest = &glb[20 + json_length..];
    let total = 12 + 8 + text.len() + rest.len();
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(&glb[0..8]);
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(text.len() as u32).to_le_bytes());
    out.extend_from_slice(&glb[16..20]);
    out.extend_from_slice(&text);
    out.extend_from_slice(rest);
    out
}
