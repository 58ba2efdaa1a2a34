//! Textured meshes read: OBJ `vt` with MTL `map_Kd` (v turned to the
//! image's convention, repeat or `-clamp on`, PNG and JPEG) and glTF
//! `TEXCOORD_0` with `baseColorTexture` (sampler filters and wraps, image in
//! a data URI), carried into the scene's textures and triangles.

use super::*;
use crate::textured::{gradient, write_gltf_quad, write_obj_quad, IMAGE_UVS};
use glam::DVec2;
use kdray_core::scene::{TextureFilter, TextureWrap};

fn scene_of(dir: &TempDir, mesh: &Path) -> Scene {
    let text = format!(
        "[camera]\nposition = [0, 0, 3]\nlook_at = [0, 0, 0]\nvfov = 60\n[render]\nwidth = 8\nheight = 8\n\
         [[lights]]\nposition = [0, 0, 5]\nambient = [1, 1, 1]\ndiffuse = [1, 1, 1]\nspecular = [0, 0, 0]\n\
         [[meshes]]\npath = {:?}\n",
        mesh.file_name().unwrap().to_str().unwrap()
    );
    let path = dir.join("scene.toml");
    std::fs::write(&path, text).unwrap();
    load_scene(&path).unwrap()
}

fn image_uvs(scale: f64) -> Vec<DVec2> {
    IMAGE_UVS
        .iter()
        .map(|uv| DVec2::new(uv[0] as f64, uv[1] as f64) * scale)
        .collect()
}

#[test]
fn obj_texture_coordinates_run_up_from_the_bottom_row_and_map_kd_is_bilinear_and_repeats() {
    let dir = TempDir::new("tex-obj");
    let image = gradient(4, 3);
    let obj = write_obj_quad(&dir.path, &image, 0.8, "", 1.0);
    let mesh = load_obj(&obj, true).unwrap();
    assert!(mesh.warnings.is_empty(), "{:?}", mesh.warnings);
    // OBJ's v = 0 is the image's bottom row: v = 1 in the image's convention.
    assert_eq!(mesh.uvs, image_uvs(1.0));
    let texture = mesh.materials[0].texture.as_ref().unwrap();
    assert_eq!((texture.width, texture.height), (4, 3));
    assert_eq!(texture.filter, TextureFilter::Bilinear);
    assert_eq!(texture.wrap, [TextureWrap::Repeat; 2]);
    // Row 0 is the image's top row.
    assert_eq!(
        texture.texels[4 * 2 + 1],
        u32::from_le_bytes(image.get_pixel(1, 2).0)
    );
    assert_eq!(mesh.materials[0].diffuse, DVec3::splat(0.8));

    let scene = scene_of(&dir, &obj);
    assert_eq!(scene.textures.len(), 1);
    assert_eq!(scene.materials[0].texture, Some(0));
    assert_eq!(scene.triangles.len(), 2);
    for t in &scene.triangles {
        let uvs = scene.uvs_of(t).unwrap();
        for (k, v) in t.vertices.iter().enumerate() {
            // Each corner's coordinates follow it: the quad's corner
            // (x, y) has image coordinates ((x + 1) / 2, (1 - y) / 2).
            let want = DVec2::new((v.x + 1.0) / 2.0, (1.0 - v.y) / 2.0);
            assert!((uvs[k] - want).length() < 1e-6, "{uvs:?} at {v}");
        }
    }
}

#[test]
fn map_kd_clamp_on_clamps_and_a_jpeg_decodes() {
    let dir = TempDir::new("tex-clamp");
    let image = gradient(4, 4);
    let obj = write_obj_quad(&dir.path, &image, 1.0, "-clamp on -s 1 1 1", 1.0);
    let mesh = load_obj(&obj, true).unwrap();
    let texture = mesh.materials[0].texture.as_ref().unwrap();
    assert_eq!(texture.wrap, [TextureWrap::ClampToEdge; 2]);

    let rgb = image::DynamicImage::ImageRgba8(image.clone()).to_rgb8();
    rgb.save(dir.path.join("tex.jpg")).unwrap();
    let mtl = std::fs::read_to_string(dir.path.join("quad.mtl")).unwrap();
    std::fs::write(dir.path.join("quad.mtl"), mtl.replace("tex.png", "tex.jpg")).unwrap();
    let mesh = load_obj(&obj, true).unwrap();
    assert!(mesh.warnings.is_empty(), "{:?}", mesh.warnings);
    let texture = mesh.materials[0].texture.as_ref().unwrap();
    assert_eq!((texture.width, texture.height), (4, 4));
}

#[test]
fn an_undecodable_map_kd_is_a_warning_and_the_flat_colour() {
    let dir = TempDir::new("tex-bad");
    let obj = write_obj_quad(&dir.path, &gradient(2, 2), 0.5, "", 1.0);
    std::fs::write(dir.path.join("tex.png"), b"not an image").unwrap();
    let mesh = load_obj(&obj, true).unwrap();
    assert_eq!(mesh.warnings.len(), 1, "{:?}", mesh.warnings);
    assert!(
        mesh.warnings[0].message.contains("tex.png"),
        "{}",
        mesh.warnings[0]
    );
    assert!(mesh.materials[0].texture.is_none());
    let scene = scene_of(&dir, &obj);
    assert!(scene.textures.is_empty());
    assert!(scene.triangles.iter().all(|t| scene.uvs_of(t).is_none()));
}

#[test]
fn gltf_texture_coordinates_run_down_from_the_top_row_with_the_sampler_and_factor() {
    let dir = TempDir::new("tex-gltf");
    let image = gradient(3, 2);
    let gltf = write_gltf_quad(
        &dir.path,
        &image,
        [0.5, 0.25, 1.0, 1.0],
        9728,
        [33648, 33071],
        2.0,
    );
    let mesh = kdray_core::scene::gltf::load_gltf(&gltf, true, &mut |_| {}).unwrap();
    assert!(mesh.warnings.is_empty(), "{:?}", mesh.warnings);
    assert_eq!(mesh.uvs, image_uvs(2.0));
    let m = &mesh.materials[0];
    assert_eq!(m.diffuse, DVec3::new(0.5, 0.25, 1.0));
    let texture = m.texture.as_ref().unwrap();
    assert_eq!(texture.filter, TextureFilter::Nearest);
    assert_eq!(
        texture.wrap,
        [TextureWrap::MirroredRepeat, TextureWrap::ClampToEdge]
    );
    assert_eq!(
        texture.texels[3 + 2],
        u32::from_le_bytes(image.get_pixel(2, 1).0)
    );

    // LINEAR and REPEAT.
    let gltf = write_gltf_quad(&dir.path, &image, [1.0; 4], 9729, [10497, 10497], 1.0);
    let scene = scene_of(&dir, &gltf);
    assert_eq!(scene.textures[0].filter, TextureFilter::Bilinear);
    assert_eq!(scene.textures[0].wrap, [TextureWrap::Repeat; 2]);
    assert!(scene.triangles.iter().all(|t| scene.uvs_of(t).is_some()));
    // A scene material instead: no texture, no coordinates.
    let text = std::fs::read_to_string(dir.join("scene.toml")).unwrap()
        + "material = \"m\"\n[materials.m]\nambient = [0.1, 0.1, 0.1]\ndiffuse = [1, 1, 1]\nspecular = [0, 0, 0]\nshininess = 1\nreflection = 0\n";
    std::fs::write(dir.join("scene.toml"), text).unwrap();
    let scene = load_scene(&dir.join("scene.toml")).unwrap();
    assert!(scene.textures.is_empty() && scene.triangle_uvs.is_empty());
}

/// A glTF material's metallic-roughness, emissive, normal and occlusion
/// textures load as its maps (with the normal map's scale and the
/// occlusion's strength), each image once, without a warning.
#[test]
fn gltf_material_maps_load_with_their_scale_and_strength() {
    let dir = TempDir::new("tex-maps");
    let texel = |r, g, b| image::RgbaImage::from_pixel(1, 1, image::Rgba([r, g, b, 255]));
    let material = r#"{"pbrMetallicRoughness":{"baseColorTexture":{"index":0},
        "metallicRoughnessTexture":{"index":1}},"emissiveFactor":[1,1,1],
        "emissiveTexture":{"index":2},"normalTexture":{"index":3,"scale":0.5},
        "occlusionTexture":{"index":1,"strength":0.25}}"#;
    let images = [
        texel(200, 100, 50),
        texel(0, 60, 220),
        texel(10, 20, 30),
        texel(128, 128, 255),
    ];
    let gltf =
        crate::textured::write_gltf_quad_material(&dir.path, "maps.gltf", material, &images, None);
    let mesh = kdray_core::scene::gltf::load_gltf(&gltf, true, &mut |_| {}).unwrap();
    let warnings: Vec<String> = mesh.warnings.iter().map(|w| w.to_string()).collect();
    assert!(warnings.is_empty(), "{warnings:?}");
    let m = &mesh.materials[0];
    let texel_of = |t: &Option<std::sync::Arc<kdray_core::scene::Texture>>| {
        t.as_ref().expect("a map").texels[0].to_le_bytes()
    };
    assert_eq!(texel_of(&m.texture), images[0].get_pixel(0, 0).0);
    assert_eq!(texel_of(&m.maps.metal_rough), images[1].get_pixel(0, 0).0);
    assert_eq!(texel_of(&m.maps.emissive), images[2].get_pixel(0, 0).0);
    assert_eq!(texel_of(&m.maps.normal), images[3].get_pixel(0, 0).0);
    assert_eq!(m.maps.normal_scale, 0.5);
    assert_eq!(texel_of(&m.maps.occlusion), images[1].get_pixel(0, 0).0);
    assert_eq!(m.maps.occlusion_strength, 0.25);
    // In a scene: the four images, each a texture of the scene, and every
    // triangle textured.
    let scene = scene_of(&dir, &gltf);
    assert_eq!(scene.textures.len(), 4);
    let sm = &scene.materials[0];
    assert!(sm.texture.is_some() && sm.maps.metal_rough.is_some());
    assert!(sm.maps.emissive.is_some() && sm.maps.normal.is_some());
    assert!(scene.triangles.iter().all(|t| scene.uvs_of(t).is_some()));
}

/// KHR_texture_transform on the base colour's texture: the loaded texture
/// coordinates are the file's transformed by hand (scale, then a rotation
/// counter-clockwise in (u, v), then the offset); a map asking for another
/// transform reads a second channel, and a third choice gets one warning.
#[test]
fn khr_texture_transform_moves_the_texture_coordinates_as_specified() {
    let dir = TempDir::new("tex-transform");
    let texel = image::RgbaImage::from_pixel(2, 2, image::Rgba([200, 100, 50, 255]));
    let (offset, rotation, scale) = ([0.5, 0.25], 0.3_f64, [2.0, 3.0]);
    let transform = format!(
        r#"{{"KHR_texture_transform":{{"offset":[{},{}],"rotation":{rotation},"scale":[{},{}]}}}}"#,
        offset[0], offset[1], scale[0], scale[1]
    );
    let material = format!(
        r#"{{"pbrMetallicRoughness":{{"baseColorTexture":{{"index":0,"extensions":{transform}}}}}}}"#
    );
    let gltf = crate::textured::write_gltf_quad_material(
        &dir.path,
        "t.gltf",
        &material,
        std::slice::from_ref(&texel),
        None,
    );
    let scene = scene_of(&dir, &gltf);
    let (s, c) = rotation.sin_cos();
    let by_hand: Vec<DVec2> = IMAGE_UVS
        .iter()
        .map(|uv| {
            let (u, v) = (uv[0] as f64 * scale[0], uv[1] as f64 * scale[1]);
            DVec2::new(c * u - s * v + offset[0], s * u + c * v + offset[1])
        })
        .collect();
    // The quad's two triangles use corners (0, 1, 2) and (0, 2, 3).
    let loaded: Vec<DVec2> = scene
        .triangles
        .iter()
        .flat_map(|t| scene.uvs_of(t).unwrap())
        .collect();
    let expected = [0, 1, 2, 0, 2, 3].map(|i| by_hand[i]);
    for (got, want) in loaded.iter().zip(&expected) {
        assert!((*got - *want).length() < 1e-6, "{got} != {want}");
    }
    let mesh = kdray_core::scene::gltf::load_gltf(&gltf, true, &mut |_| {}).unwrap();
    assert!(mesh.warnings.is_empty(), "{:?}", mesh.warnings);

    // An emissive map with another transform reads a second channel, the
    // untransformed coordinates, without a warning; a third choice (an
    // occlusion map on TEXCOORD_1) reads the first channel, with one
    // warning naming the rule.
    let material = format!(
        r#"{{"pbrMetallicRoughness":{{"baseColorTexture":{{"index":0,"extensions":{transform}}}}},
            "emissiveFactor":[1,1,1],"emissiveTexture":{{"index":0}}}}"#
    );
    let gltf = crate::textured::write_gltf_quad_material(
        &dir.path,
        "t2.gltf",
        &material,
        std::slice::from_ref(&texel),
        None,
    );
    let mesh = kdray_core::scene::gltf::load_gltf(&gltf, true, &mut |_| {}).unwrap();
    assert!(mesh.warnings.is_empty(), "{:?}", mesh.warnings);
    assert_eq!(
        mesh.materials[0].maps.second_uv,
        kdray_core::layout::UV_SLOT_EMISSIVE
    );
    let scene = scene_of(&dir, &gltf);
    let second: Vec<DVec2> = scene
        .triangle_second_uvs
        .iter()
        .flatten()
        .copied()
        .collect();
    let file =
        [0, 1, 2, 0, 2, 3].map(|i| DVec2::new(IMAGE_UVS[i][0].into(), IMAGE_UVS[i][1].into()));
    assert_eq!(second, file);
    let material = material.replace(
        r#""emissiveTexture":{"index":0}}"#,
        r#""emissiveTexture":{"index":0},"occlusionTexture":{"index":0,"texCoord":1}}"#,
    );
    let second_set = vec![vec![0.5f32, 0.5]; 4];
    let gltf = crate::textured::write_gltf_quad_attributes(
        &dir.path,
        "t3.gltf",
        &material,
        &[texel],
        &[("TEXCOORD_1", second_set)],
    );
    let mesh = kdray_core::scene::gltf::load_gltf(&gltf, true, &mut |_| {}).unwrap();
    let shown: Vec<String> = mesh.warnings.iter().map(|w| w.to_string()).collect();
    assert_eq!(shown.len(), 1, "{shown:?}");
    assert!(
        shown[0].contains("occlusionTexture with its baseColorTexture's"),
        "{shown:?}"
    );
}
