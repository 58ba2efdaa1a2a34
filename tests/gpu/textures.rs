//! Base-colour textures on the GPU: a textured quad facing the camera,
//! rendered with and without its texture; the ratio of the two images is
//! the texture sampled at each pixel's hit, for OBJ's `map_Kd` (bilinear,
//! v up from the bottom row) and glTF (NEAREST, v down from the top row),
//! and for each wrap mode. The k-d walk equals brute force with textures,
//! and the GPU equals the CPU reference. Far away, a checker's mip levels
//! turn it the mean grey where its base level aliases; glTF's minFilter
//! chooses how the levels are read.

use crate::common;
use crate::common::textured;

use std::path::Path;

use common::{gpu, pixel, render, TempDir};
use glam::{Vec2, Vec3};
use kdray::gpu::{Accel, ArrayBindings, RenderedImage};
use kdray::scene::{load_scene, MinFilter, MipMode, Scene, TextureFilter};
use kdray_core::reference::ReferenceTracer;
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
    // The texels of every mip level (64 x 32 halving down to 1 x 1), the
    // 5-word prefix and the header, the level table (7 levels of 3 words),
    // and two triangles' coordinates.
    let texels = 64 * 32 + 32 * 16 + 16 * 8 + 8 * 4 + 4 * 2 + 2 + 1;
    let texture_bytes = texels * 4 + (5 + 7) * 4 + 7 * 3 * 4 + 2 * 6 * 4;
    assert_eq!(
        textured.arrays.byte_size(),
        plain.arrays.byte_size() + texture_bytes
    );
    let limits = wgpu::Limits {
        max_storage_buffer_binding_size: 4096,
        ..wgpu::Limits::default()
    };
    let message = textured.arrays.check_fits(&limits).unwrap_err().to_string();
    for words in ["textures buffer", "10.8 KiB", "4.0 KiB"] {
        assert!(message.contains(words), "{message} lacks {words}");
    }
    assert!(plain.arrays.check_fits(&limits).is_ok());
}

/// A 64 x 64 checker of one-texel squares (black and white): every mip
/// level below the base is grey 128.
fn fine_checker() -> image::RgbaImage {
    image::RgbaImage::from_fn(64, 64, |x, y| {
        let v = if (x + y) % 2 == 0 { 0 } else { 255 };
        image::Rgba([v, v, v, 255])
    })
}

/// The quad file `mesh` seen head-on from 40 away through a narrow view
/// (3.5 degrees), lit from beside the camera.
fn far_quad_scene(dir: &TempDir, mesh: &Path) -> Scene {
    let text = format!(
        "[camera]\nposition = [0, 0, 40]\nlook_at = [0, 0, 0]\nvfov = 3.5\n\
         [render]\nwidth = {SIDE}\nheight = {SIDE}\nbackground = [0, 0, 0]\n\
         [[lights]]\nposition = [0, 0, 41]\nambient = [0.3, 0.3, 0.3]\ndiffuse = [0.7, 0.7, 0.7]\nspecular = [0, 0, 0]\n\
         [[meshes]]\npath = {:?}\n",
        mesh.file_name().unwrap().to_str().unwrap()
    );
    let path = dir.join("scene.toml");
    std::fs::write(&path, text).unwrap();
    load_scene(&path).unwrap_or_else(|e| panic!("{e}"))
}

/// Per pixel that sees the quad (away from its edges), textured / plain:
/// the texture's value there.
fn texture_ratios(scene: &Scene) -> Vec<f32> {
    let textured = render(scene, Accel::Kdtree);
    let plain = render(&untextured(scene), Accel::Kdtree);
    let mut ratios = Vec::new();
    for row in 0..SIDE {
        for column in 0..SIDE {
            if hit_uv(scene, row, column, 1.0).is_some() {
                let p = pixel(&plain, row, column)[1] as f32;
                ratios.push(pixel(&textured, row, column)[1] as f32 / p);
            }
        }
    }
    assert!(ratios.len() > SIDE as usize * SIDE as usize / 3);
    ratios
}

#[test]
fn a_far_checker_is_its_mean_grey_with_mip_levels_and_aliases_at_its_base_level() {
    let _ = gpu();
    let dir = TempDir::new("gpu-tex-far");
    // Eight repeats across the quad: 512 texels over about 22 pixels.
    let obj = write_obj_quad(&dir.path, &fine_checker(), 1.0, "", 8.0);
    let mipmapped = far_quad_scene(&dir, &obj);
    assert_eq!(mipmapped.textures[0].min_filter, MinFilter::TRILINEAR);
    let mut base_only = mipmapped.clone();
    base_only.textures[0].min_filter.mip = MipMode::None;
    let mean = 128.0 / 255.0;
    let deviation =
        |ratios: &[f32]| ratios.iter().map(|r| (r - mean).abs()).sum::<f32>() / ratios.len() as f32;
    let with_levels = texture_ratios(&mipmapped);
    let worst = with_levels
        .iter()
        .map(|r| (r - mean).abs())
        .fold(0.0, f32::max);
    assert!(
        worst < 0.01,
        "mipmapped: a pixel {worst} from the mean grey"
    );
    let at_base = texture_ratios(&base_only);
    let aliased = deviation(&at_base);
    assert!(
        aliased > 0.1 && aliased > 10.0 * deviation(&with_levels),
        "base level: mean deviation {aliased} from the mean grey"
    );
    assert_walks_and_reference_agree(&mipmapped);
    assert_walks_and_reference_agree(&base_only);
    // The nearest level, point sampled within it: the same grey.
    let mut nearest_level = mipmapped.clone();
    nearest_level.textures[0].min_filter = MinFilter {
        filter: TextureFilter::Nearest,
        mip: MipMode::Nearest,
    };
    let worst = texture_ratios(&nearest_level)
        .iter()
        .map(|r| (r - mean).abs())
        .fold(0.0, f32::max);
    assert!(
        worst < 0.01,
        "nearest level: a pixel {worst} from the mean grey"
    );
    assert_walks_and_reference_agree(&nearest_level);
}

/// scenes/textured.toml at the golden images' size: the floor is minified
/// (trilinear) towards the horizon and seen again in the mirror ball (its
/// cone's width the whole path's length); the GPU equals the CPU reference
/// within one level.
#[test]
fn the_textured_scene_matches_the_cpu_reference_with_its_mip_levels() {
    let scene = common::small_scene(&common::repo_path("scenes/textured.toml"));
    let gpu = render(&scene, Accel::Kdtree);
    let cpu = ReferenceTracer::new(&scene, true).image();
    let most = max_difference(&gpu, &cpu);
    assert!(
        most <= 1,
        "the GPU and the CPU reference differ by {most} levels"
    );
    // The mip levels are in use: sampling the base level only changes it.
    let mut base_only = scene.clone();
    base_only.textures[0].min_filter.mip = MipMode::None;
    let base = ReferenceTracer::new(&base_only, true).image();
    let changed = max_difference(&gpu, &base);
    assert!(
        changed > 16,
        "base-level sampling differs by only {changed} levels"
    );
}

#[test]
fn gltf_min_filter_chooses_the_filter_within_a_level_and_the_mip_mode() {
    use TextureFilter::{Bilinear, Nearest};
    let cases = [
        (Some(9728), Nearest, MipMode::None),
        (Some(9729), Bilinear, MipMode::None),
        (Some(9984), Nearest, MipMode::Nearest),
        (Some(9985), Bilinear, MipMode::Nearest),
        (Some(9986), Nearest, MipMode::Linear),
        (Some(9987), Bilinear, MipMode::Linear),
        (None, Bilinear, MipMode::Linear),
    ];
    for (min_filter, filter, mip) in cases {
        let dir = TempDir::new("gltf-min-filter");
        let path = write_gltf_quad(&dir.path, &gradient(4, 4), [1.0; 4], 9728, [10497; 2], 1.0);
        let text = std::fs::read_to_string(&path).unwrap();
        let replaced = match min_filter {
            Some(f) => format!("\"minFilter\":{f},"),
            None => String::new(),
        };
        let text = text.replace("\"minFilter\":9728,", &replaced);
        std::fs::write(&path, text).unwrap();
        let scene = quad_scene(&dir, &path);
        let t = &scene.textures[0];
        assert_eq!(t.min_filter, MinFilter { filter, mip }, "{min_filter:?}");
        // The magnification filter is read on its own.
        assert_eq!(t.filter, Nearest);
        // The chain is built whatever the filter: 4 x 4, 2 x 2, 1 x 1.
        assert_eq!(t.level_count(), 3);
    }
}
