//! Base-colour textures on the GPU: a textured quad facing the camera,
//! rendered with and without its texture; the ratio of the two images is
//! the texture sampled at each pixel's hit, for OBJ's `map_Kd` (bilinear,
//! v up from the bottom row) and glTF (NEAREST, v down from the top row),
//! and for each wrap mode. The k-d walk equals brute force with textures,
//! and the GPU equals the CPU reference.

mod common;
#[path = "common/textured.rs"]
mod textured;

use std::path::Path;

use common::{gpu, pixel, render, TempDir};
use glam::{Vec2, Vec3};
use kdray::gpu::{Accel, RenderedImage};
use kdray::reference::ReferenceTracer;
use kdray::scene::{load_scene, Scene};
use textured::{gradient, write_gltf_quad, write_obj_quad};

const SIDE: u32 = 24;

/// A scene of the quad file `mesh` seen head-on, lit from the camera
/// (ambient and diffuse, no specular).
fn quad_scene(dir: &TempDir, mesh: &Path) -> Scene {
    let text = format!(
        "[camera]\nposition = [0, 0, 2.2]\nlook_at = [0, 0, 0]\nvfov = 60\n\
         [render]\nwidth = {SIDE}\nheight = {SIDE}\nbackground = [0, 0, 0]\n\
         [[lights]]\nposition = [0, 0, 3]\nambient = [0.3, 0.3, 0.3]\ndiffuse = [0.7, 0.7, 0.7]\nspecular = [0, 0, 0]\n\
         [[meshes]]\npath = {:?}\n",
        mesh.file_name().unwrap().to_str().unwrap()
    );
    let path = dir.join("scene.toml");
    std::fs::write(&path, text).unwrap();
    let scene = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene.textures.len(), 1);
    scene
}

/// The scene with its materials' textures taken away.
fn untextured(scene: &Scene) -> Scene {
    let mut plain = scene.clone();
    for m in &mut plain.materials {
        m.texture = None;
    }
    plain
}

/// Where the centre of pixel (row, column) sees the quad, in the image's
/// texture coordinates times `uv_scale`; None off the quad or near its
/// edges.
fn hit_uv(scene: &Scene, row: u32, column: u32, uv_scale: f32) -> Option<Vec2> {
    let tracer = ReferenceTracer::new(scene, false);
    let u = (column as f32 + 0.5) / SIDE as f32;
    let v = (row as f32 + 0.5) / SIDE as f32;
    let ray = tracer.camera_ray(u, v);
    let t = -ray.origin.z / ray.dir.z;
    let p = ray.origin + t * ray.dir;
    if p.x.abs() > 0.95 || p.y.abs() > 0.95 {
        return None;
    }
    Some(Vec2::new((p.x + 1.0) / 2.0, (1.0 - p.y) / 2.0) * uv_scale)
}

/// Checks textured = plain x texel at every pixel that sees the quad
/// (within one level: each image is rounded to 8 bits on its own), skipping
/// for point sampling the pixels within 1/1000 of a texel edge. Returns how
/// many pixels it checked.
fn assert_ratio_is_the_texture(scene: &Scene, uv_scale: f32) -> usize {
    let textured = render(scene, Accel::Kdtree);
    let plain = render(&untextured(scene), Accel::Kdtree);
    let texture = &scene.textures[0];
    let size = Vec2::new(texture.width as f32, texture.height as f32);
    let nearest = texture.filter == kdray::scene::TextureFilter::Nearest;
    let mut checked = 0;
    for row in 0..SIDE {
        for column in 0..SIDE {
            let Some(uv) = hit_uv(scene, row, column, uv_scale) else {
                continue;
            };
            let edge = (uv * size - (uv * size).round()).abs().min_element();
            if nearest && edge < 1e-3 {
                continue;
            }
            let t = texture.sample(uv);
            let p = pixel(&plain, row, column);
            let got = pixel(&textured, row, column);
            let want = Vec3::new(p[0] as f32, p[1] as f32, p[2] as f32) * t;
            for k in 0..3 {
                assert!(
                    (got[k] as f32 - want[k]).abs() <= 1.01,
                    "pixel ({row}, {column}) at uv {uv}: textured {got:?}, plain {p:?} x texel {t} = {want}"
                );
            }
            checked += 1;
        }
    }
    assert!(
        checked > SIDE as usize * SIDE as usize / 3,
        "{checked} pixels checked"
    );
    checked
}

/// The k-d walk and brute force give the same image, and the GPU the CPU
/// reference's (within one level).
fn assert_walks_and_reference_agree(scene: &Scene) {
    let kd = render(scene, Accel::Kdtree);
    let brute = render(scene, Accel::Brute);
    assert!(kd.rgb == brute.rgb, "the k-d walk and brute force differ");
    let reference = ReferenceTracer::new(scene, true).image();
    let most = max_difference(&kd, &reference);
    assert!(
        most <= 1,
        "the GPU and the CPU reference differ by {most} levels"
    );
}

/// The quad of a vertical gradient image shows it: the ratio to the plain
/// quad is the texture, the quad's top shows the image's top row (green
/// grows down the image) and its bottom the bottom row, and the walks and
/// the reference agree.
fn assert_the_quad_shows_its_texture_upright(scene: &Scene) {
    assert_ratio_is_the_texture(scene, 1.0);
    let image = render(scene, Accel::Kdtree);
    let plain = render(&untextured(scene), Accel::Kdtree);
    let green = |img: &RenderedImage, row| pixel(img, row, SIDE / 2)[1] as f32;
    let ratio = |row| green(&image, row) / green(&plain, row);
    assert!(
        ratio(SIDE / 4) < ratio(3 * SIDE / 4),
        "{} {}",
        ratio(SIDE / 4),
        ratio(3 * SIDE / 4)
    );
    assert_walks_and_reference_agree(scene);
}

fn max_difference(image: &RenderedImage, other: &[u8]) -> u8 {
    image
        .rgb
        .iter()
        .zip(other)
        .map(|(a, b)| a.abs_diff(*b))
        .max()
        .unwrap()
}

#[test]
fn an_obj_quad_shows_its_map_kd_bilinear_with_v_up_from_the_bottom_row() {
    let _ = gpu();
    let dir = TempDir::new("gpu-tex-obj");
    let obj = write_obj_quad(&dir.path, &gradient(5, 4), 0.9, "", 1.0);
    assert_the_quad_shows_its_texture_upright(&quad_scene(&dir, &obj));
}

#[test]
fn a_gltf_quad_shows_its_texture_nearest_with_v_down_from_the_top_row() {
    let _ = gpu();
    let dir = TempDir::new("gpu-tex-gltf");
    let gltf = write_gltf_quad(
        &dir.path,
        &gradient(4, 3),
        [0.9, 0.8, 1.0, 1.0],
        9728,
        [33071, 33071],
        1.0,
    );
    assert_the_quad_shows_its_texture_upright(&quad_scene(&dir, &gltf));
}

#[test]
fn wrap_modes_repeat_clamp_and_mirror_past_the_image() {
    let _ = gpu();
    // Texture coordinates over [0, 2]: the image twice along each axis.
    for (wrap, filter) in [(10497, 9728), (33071, 9729), (33648, 9728), (33648, 9729)] {
        let dir = TempDir::new("gpu-tex-wrap");
        let gltf = write_gltf_quad(
            &dir.path,
            &gradient(3, 3),
            [1.0; 4],
            filter,
            [wrap, wrap],
            2.0,
        );
        let scene = quad_scene(&dir, &gltf);
        assert_ratio_is_the_texture(&scene, 2.0);
        assert_walks_and_reference_agree(&scene);
    }
}

#[test]
fn clamp_on_in_map_kd_clamps_past_the_image() {
    let _ = gpu();
    let dir = TempDir::new("gpu-tex-clamp");
    let obj = write_obj_quad(&dir.path, &gradient(3, 2), 1.0, "-clamp on", 2.0);
    let scene = quad_scene(&dir, &obj);
    assert_eq!(
        scene.textures[0].wrap,
        [kdray::scene::TextureWrap::ClampToEdge; 2]
    );
    assert_ratio_is_the_texture(&scene, 2.0);
}

#[test]
fn texture_bytes_count_in_the_scene_size_and_a_texture_past_the_limit_is_refused_naming_it() {
    use kdray::gpu::PreparedScene;
    let dir = TempDir::new("gpu-tex-bytes");
    let obj = write_obj_quad(&dir.path, &gradient(64, 32), 1.0, "", 1.0);
    let scene = quad_scene(&dir, &obj);
    let textured = PreparedScene::new(scene.clone(), Accel::Kdtree);
    let plain = PreparedScene::new(untextured(&scene), Accel::Kdtree);
    // The texels, the header and word 0, and two triangles' coordinates.
    let texture_bytes = 64 * 32 * 4 + (1 + 6) * 4 + 2 * 6 * 4;
    assert_eq!(
        textured.arrays.byte_size(),
        plain.arrays.byte_size() + texture_bytes
    );
    let limits = wgpu::Limits {
        max_storage_buffer_binding_size: 4096,
        ..wgpu::Limits::default()
    };
    let message = textured.arrays.check_fits(&limits).unwrap_err().to_string();
    for words in ["textures buffer", "8.1 KiB", "4.0 KiB"] {
        assert!(message.contains(words), "{message} lacks {words}");
    }
    assert!(plain.arrays.check_fits(&limits).is_ok());
}
