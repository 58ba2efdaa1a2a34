//! The path tracer (`integrator = "path"`) on the adapter at hand: scenes
//! whose radiance is known exactly (a white furnace, a Lambertian plane
//! under a uniform sky, a plane lit by a sphere of known solid angle),
//! determinism and the seed, the image independent of its tiles, sample
//! ranges (a farm's split by samples), no infinity or NaN in a pixel, and
//! EXR output. That every walk and brute
//! force give the same path-traced image is checked on the shipped Cornell
//! box by tests/gpu/gpu_render.rs's
//! `every_walk_renders_brute_forces_and_the_general_kernels_image_on_every_scene`.

use crate::common;

use common::*;
use glam::DVec3;
use kdray::gpu::{Accel, GpuScene, PreparedScene, Renderer, TilePlan};
use kdray::kdtree::Traversal;
use kdray::scene::Scene;

/// A frame's mean radiance per pixel (r, g, b, row-major) and
/// its dropped samples, through the k-d tree with `traversal`, in
/// dispatches of at most `max_tile_pixels`.
fn radiance(scene: &Scene, traversal: Traversal, max_tile_pixels: u64) -> (Vec<f32>, u64) {
    radiance_with(scene, Accel::Kdtree, traversal, max_tile_pixels, None)
}

/// [`radiance`] with the search `accel` (the walk matters for the k-d tree
/// only), and of samples `first .. first + count` alone when `samples` is
/// `Some((first, count))`.
fn radiance_with(
    scene: &Scene,
    accel: Accel,
    traversal: Traversal,
    max_tile_pixels: u64,
    samples: Option<(u32, u32)>,
) -> (Vec<f32>, u64) {
    let ctx = gpu();
    let prepared = PreparedScene::new(scene.clone(), accel);
    let uploaded = GpuScene::upload(ctx, prepared).unwrap_or_else(|e| panic!("{e}"));
    // Whitted frames' radiance too (path frames always carry theirs).
    let mut renderer = Renderer::new(ctx)
        .unwrap_or_else(|e| panic!("{e}"))
        .with_settings(&scene.render)
        .with_radiance();
    if let Some((first, count)) = samples {
        renderer = renderer.with_sample_range(first, count);
    }
    let params = uploaded.frame_params().with_traversal(traversal);
    let (w, h) = (scene.render.width, scene.render.height);
    let plan = TilePlan::new(
        w,
        h,
        max_tile_pixels,
        kdray::gpu::max_binding_bytes(&ctx.device.limits()),
    );
    let mut out = Vec::new();
    let summary = renderer
        .render_bands_with_cost(ctx, uploaded.buffers(), params, plan, false, &mut |band| {
            out.extend_from_slice(band.radiance.expect("path frames carry radiance"));
            Ok(())
        })
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(out.len(), (w * h * 3) as usize);
    (out, summary.rays.nonfinite)
}

fn default_radiance(scene: &Scene) -> Vec<f32> {
    radiance(
        scene,
        Traversal::default(),
        TilePlan::DEFAULT_MAX_TILE_PIXELS,
    )
    .0
}

fn assert_close(actual: f32, expected: f64, relative: f64, what: &str) {
    let error = (actual as f64 - expected).abs();
    assert!(
        error <= relative * expected.abs().max(1e-3),
        "{what}: {actual} is not within {relative} of {expected}"
    );
}

/// A sphere of albedo a under a uniform sky of radiance L: every path that
/// meets the convex sphere leaves it at the next bounce, so each pixel on
/// it shows a x L exactly (no variance), and the sky L around it. Albedo 1
/// is the white furnace.
#[test]
fn a_sphere_under_a_uniform_sky_shows_its_albedo_times_the_sky() {
    for albedo in [1.0, 0.5] {
        let scene = scene_from_toml(&format!(
            r#"
            [camera]
            position = [0, 0, 4]
            look_at = [0, 0, 0]
            vfov = 40
            [render]
            width = 24
            height = 24
            integrator = "path"
            samples = 5
            max_depth = 4
            [environment]
            color = [0.5, 0.25, 1.0]
            [materials.m]
            diffuse = [{albedo}, {albedo}, {albedo}]
            [[spheres]]
            center = [0, 0, 0]
            radius = 1
            material = "m"
            "#
        ));
        let image = default_radiance(&scene);
        let sky = [0.5, 0.25, 1.0];
        let centre = (12 * 24 + 12) * 3;
        let corner = 0;
        for c in 0..3 {
            assert_close(image[centre + c], albedo * sky[c], 1e-5, "on the sphere");
            assert_close(image[corner + c], sky[c], 0.0, "the sky");
        }
        // Every pixel is the sky or albedo x sky (edge pixels a mix of the two).
        for px in image.chunks_exact(3) {
            let t = px[2] as f64 / sky[2];
            assert!((albedo - 1e-5..=1.0 + 1e-5).contains(&t), "{px:?}");
            for c in 0..3 {
                assert_close(px[c], t * sky[c], 1e-5, "a pixel's colour");
            }
        }
    }
}

/// A Lambertian plane of albedo a seen from above, under a uniform sky L:
/// each path's bounce leaves to the sky, so the plane shows a x L exactly
/// in every channel.
#[test]
fn a_lambertian_plane_under_a_uniform_sky_shows_albedo_times_the_sky() {
    let scene = scene_from_toml(
        r#"
        [camera]
        position = [0, 3, 2]
        look_at = [0, 0, 0]
        vfov = 50
        [render]
        width = 16
        height = 16
        integrator = "path"
        samples = 3
        [environment]
        color = [1.0, 2.0, 3.0]
        [materials.m]
        diffuse = [0.2, 0.5, 0.8]
        [[triangles]]
        vertices = [[-1000, 0, -1000], [1000, 0, -1000], [1000, 0, 1000]]
        material = "m"
        [[triangles]]
        vertices = [[-1000, 0, -1000], [1000, 0, 1000], [-1000, 0, 1000]]
        material = "m"
        "#,
    );
    let image = default_radiance(&scene);
    for px in image.chunks_exact(3) {
        assert_close(px[0], 0.2, 1e-5, "red");
        assert_close(px[1], 1.0, 1e-5, "green");
        assert_close(px[2], 2.4, 1e-5, "blue");
    }
}

/// A plane of albedo a lit only by a sphere of radius r and radiance L whose
/// centre stands h above it: at a point at distance D from the centre the
/// sphere subtends sin^2 = r^2 / D^2 and the plane shows
/// a L (r^2 / D^2) (h / D) (direct light only: max_depth 1). Each pixel,
/// its samples' mean, matches the formula at its centre within 2%, and the
/// image's mean within 0.5%: light sampling, BSDF sampling and their
/// weights together are unbiased.
#[test]
fn a_sphere_light_lights_a_plane_by_its_solid_angle() {
    let (h, r, l, a) = (2.0, 0.5, 4.0, 0.5);
    let scene = scene_from_toml(&format!(
        r#"
        [camera]
        position = [0, 3, 4]
        look_at = [0, 0, 0]
        vfov = 10
        [render]
        width = 12
        height = 12
        integrator = "path"
        samples = 400
        max_depth = 1
        [materials.plane]
        diffuse = [{a}, {a}, {a}]
        [materials.light]
        diffuse = [0, 0, 0]
        emission = [{l}, {l}, {l}]
        [[triangles]]
        vertices = [[-100, 0, -100], [100, 0, -100], [100, 0, 100]]
        material = "plane"
        [[triangles]]
        vertices = [[-100, 0, -100], [100, 0, 100], [-100, 0, 100]]
        material = "plane"
        [[spheres]]
        center = [0, {h}, 0]
        radius = {r}
        material = "light"
        "#
    ));
    let image = default_radiance(&scene);
    let basis = scene.camera.basis();
    let (w, hgt) = (scene.render.width, scene.render.height);
    let aspect = w as f64 / hgt as f64;
    let (mut sum, mut expected_sum) = (0.0, 0.0);
    for y in 0..hgt {
        for x in 0..w {
            let u = (x as f64 + 0.5) / w as f64;
            let v = (y as f64 + 0.5) / hgt as f64;
            let dir = (basis.forward
                + (2.0 * u - 1.0) * basis.tan_half_vfov * aspect * basis.right
                + (1.0 - 2.0 * v) * basis.tan_half_vfov * basis.up)
                .normalize();
            let t = -basis.position.y / dir.y;
            let p = basis.position + t * dir;
            let d = (DVec3::new(0.0, h, 0.0) - p).length();
            let expected = a * l * (r * r / (d * d)) * (h / d);
            let got = image[((y * w + x) * 3) as usize];
            assert_close(got, expected, 0.02, &format!("pixel ({x}, {y})"));
            sum += got as f64;
            expected_sum += expected;
        }
    }
    assert_close(sum as f32, expected_sum, 0.005, "the image's sum");
}

/// A plane of albedo a seen straight down through a narrow view, lit from
/// height h above by a point light of `diffuse` D: the path tracer shows
/// a D / (pi h^2) there, and with `reference_distance = h` the Whitted
/// integrator's a D (its lights do not fall off), which the Whitted
/// integrator shows too.
#[test]
fn a_point_light_with_a_reference_distance_matches_the_whitted_integrator_there() {
    let (a, d, h) = (0.5, 0.6, 3.0);
    let scene = |integrator: &str, reference: &str| {
        scene_from_toml(&format!(
            r#"
            [camera]
            position = [0, 10, 0]
            look_at = [0, 0, 0]
            up = [0, 0, -1]
            vfov = 1
            [render]
            width = 4
            height = 4
            integrator = "{integrator}"
            samples = 16
            max_depth = 1
            [materials.plane]
            diffuse = [{a}, {a}, {a}]
            ambient = [0, 0, 0]
            specular = [0, 0, 0]
            [[lights]]
            position = [0, {h}, 0]
            ambient = [0, 0, 0]
            diffuse = [{d}, {d}, {d}]
            specular = [0, 0, 0]
            {reference}
            [[triangles]]
            vertices = [[-1000, 0, -1000], [1000, 0, 1000], [1000, 0, -1000]]
            material = "plane"
            [[triangles]]
            vertices = [[-1000, 0, -1000], [-1000, 0, 1000], [1000, 0, 1000]]
            material = "plane"
            "#
        ))
    };
    let mean = |scene: &Scene| {
        let image = default_radiance(scene);
        image.iter().map(|&x| x as f64).sum::<f64>() / image.len() as f64
    };
    let pi = std::f64::consts::PI;
    let tolerance = 0.002;
    let plain = mean(&scene("path", ""));
    assert_close(
        plain as f32,
        a * d / (pi * h * h),
        tolerance,
        "path, no reference distance",
    );
    let reference = format!("reference_distance = {h}");
    let matched = mean(&scene("path", &reference));
    assert_close(
        matched as f32,
        a * d,
        tolerance,
        "path, reference distance h",
    );
    let whitted = mean(&scene("whitted", &reference));
    assert_close(whitted as f32, a * d, tolerance, "Whitted");
}

/// The Cornell box at test size, with a few samples.
fn small_cornell_box(samples: u32) -> Scene {
    let mut scene = small_scene(&repo_path("scenes/cornell_box.toml"));
    scene.render.width = 40;
    scene.render.height = 40;
    scene.render.samples = samples;
    scene
}

/// The same scene and seed give the same image bit for bit, whatever the
/// tiles (a sample's random numbers depend on its pixel and index only) and
/// with more samples than one dispatch takes; another seed gives another.
#[test]
fn path_images_depend_on_the_seed_alone() {
    let scene = small_cornell_box(2 * kdray::gpu::SAMPLES_PER_DISPATCH + 3);
    let (first, dropped) = radiance(&scene, Traversal::default(), u64::MAX);
    assert_eq!(dropped, 0);
    let (again, _) = radiance(&scene, Traversal::default(), u64::MAX);
    let (tiled, _) = radiance(&scene, Traversal::default(), 13 * 7);
    let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&first), bits(&again));
    assert_eq!(bits(&first), bits(&tiled));
    let mut reseeded = scene.clone();
    reseeded.render.seed = 7;
    let (other, _) = radiance(&reseeded, Traversal::default(), u64::MAX);
    let differing = first.iter().zip(&other).filter(|(a, b)| a != b).count();
    assert!(
        differing > first.len() / 2,
        "{differing} of {}",
        first.len()
    );
}

/// A sample range traces those sample indices with the whole frame's
/// random numbers: the range of every sample is the whole frame bit for
/// bit, two ranges of one size differ, and ranges that cover the samples
/// (13, 13 and 9 of 35: unequal, and starting inside a dispatch of 16)
/// average, weighted by their counts, to the whole frame within f32
/// rounding (radiance is never negative: relative error about the count
/// times 2^-24).
#[test]
fn sample_ranges_average_to_the_whole_frame() {
    let scene = small_cornell_box(35);
    let of = |range| {
        radiance_with(
            &scene,
            Accel::Kdtree,
            Traversal::default(),
            u64::MAX,
            Some(range),
        )
        .0
    };
    let whole = default_radiance(&scene);
    let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&of((0, 35))), bits(&whole));
    let ranges = [(0, 13), (13, 13), (26, 9)];
    let shares: Vec<Vec<f32>> = ranges.iter().map(|&r| of(r)).collect();
    assert_ne!(shares[0], shares[1], "other samples, other random numbers");
    let mut worst: f64 = 0.0;
    for (i, &expected) in whole.iter().enumerate() {
        let sum: f64 = ranges
            .iter()
            .zip(&shares)
            .map(|(&(_, count), share)| share[i] as f64 * count as f64)
            .sum();
        let error = (sum / 35.0 - expected as f64).abs();
        worst = worst.max(error / (1e-5 * (expected as f64).abs() + 1e-7));
    }
    assert!(worst <= 1.0, "differs by {worst} tolerances");
}

/// Every walk meets the same hits with the same random numbers as brute
/// force: the radiance is equal bit for bit.
#[test]
fn every_walk_gives_brute_force_radiance() {
    let scene = small_cornell_box(4);
    let (brute, _) = radiance_with(&scene, Accel::Brute, Traversal::default(), u64::MAX, None);
    for walk in Traversal::ALL {
        let (kd, _) = radiance(&scene, walk, TilePlan::DEFAULT_MAX_TILE_PIXELS);
        let differing = kd.iter().zip(&brute).filter(|(a, b)| a != b).count();
        assert_eq!(differing, 0, "{walk}");
    }
}

/// Radiance too large for f32 sums: the samples that would overflow are
/// dropped and counted, and every pixel stays finite.
#[test]
fn no_infinity_reaches_a_pixel() {
    let scene = scene_from_toml(
        r#"
        [camera]
        position = [0, 0, 4]
        look_at = [0, 0, 0]
        [render]
        width = 8
        height = 8
        integrator = "path"
        samples = 6
        [materials.sun]
        diffuse = [0, 0, 0]
        emission = [3e38, 3e38, 3e38]
        [materials.wall]
        diffuse = [1, 1, 1]
        [[spheres]]
        center = [0, 0, 0]
        radius = 1
        material = "sun"
        [[triangles]]
        vertices = [[-10, -10, -2], [10, -10, -2], [10, 10, -2]]
        material = "wall"
        "#,
    );
    let (image, dropped) = radiance(&scene, Traversal::default(), u64::MAX);
    assert!(dropped > 0);
    assert!(image.iter().all(|x| x.is_finite()), "{image:?}");
}

/// `-o image.exr` writes the mean radiance; the PNG of the same command is
/// that radiance tone-mapped (ACES, sRGB), pixel for pixel; `--stats`
/// counts the samples.
#[test]
fn exr_output_holds_the_radiance_the_png_tone_maps() {
    let dir = TempDir::new("path-exr");
    let scene = repo_path("scenes/cornell_box.toml");
    let args = |out: &str| {
        vec![
            "render".to_string(),
            scene.to_str().unwrap().to_string(),
            "--samples".into(),
            "3".into(),
            "--width".into(),
            "24".into(),
            "--height".into(),
            "24".into(),
            "--stats".into(),
            "-o".into(),
            out.to_string(),
        ]
    };
    for out in ["box.exr", "box.png"] {
        let a = args(out);
        let a: Vec<&str> = a.iter().map(String::as_str).collect();
        let run = run_kdray(dir.join("").as_path(), &a, &[]);
        assert_eq!(run.code, 0, "{}", run.stderr_text());
        let stats: serde_json::Value = serde_json::from_str(&run.stdout).unwrap();
        assert_eq!(stats["integrator"], "path");
        assert_eq!(stats["primary_rays"], 24 * 24 * 3);
        assert_eq!(stats["nonfinite_samples"], 0);
    }
    let (w, h, exr) = kdray::output::exr::read_exr_rgb(&dir.join("box.exr")).unwrap();
    let (pw, ph, png) = kdray::output::read_png_rgb(&dir.join("box.png")).unwrap();
    assert_eq!((w, h, pw, ph), (24, 24, 24, 24));
    assert!(
        exr.iter().any(|&x| x > 1.0),
        "a light seen directly is brighter than 1"
    );
    for (e, p) in exr.iter().zip(&png) {
        assert_eq!(kdray::scene::ToneMap::Aces.to_srgb8(*e, 1.0), *p);
    }
}

/// Writes a `width` x `height` sky of linear RGB (row-major, top row first)
/// as an EXR file in `dir`, and a scene around it; returns the scene.
fn scene_with_sky(dir: &TempDir, texels: &[[f32; 3]], width: u32, scene: &str) -> Scene {
    let height = texels.len() as u32 / width;
    kdray::output::exr::write_exr_atomic(
        &dir.join("sky.exr"),
        width,
        height,
        &texels.iter().flatten().copied().collect::<Vec<f32>>(),
    )
    .unwrap();
    let path = dir.write("scene.toml", scene);
    kdray::scene::load_scene(&path).unwrap_or_else(|e| panic!("{e}"))
}

/// A sky of distinct texels, looked at through a one-pixel camera of 0.5
/// degrees along several directions, turned and not: the kernel reads the
/// texel the documented rule (scene::environment) names.
#[test]
fn the_sky_image_is_read_where_the_documented_rule_says() {
    let dir = TempDir::new("sky-texels");
    let (w, h) = (8u32, 4u32);
    let texels: Vec<[f32; 3]> = (0..w * h)
        .map(|i| [(i % w) as f32 + 1.0, (i / w) as f32 + 1.0, 0.5])
        .collect();
    for rotation in [0.0, 90.0, -30.0] {
        for look in [
            [0.1, 0.1, -1.0],
            [1.0, 0.3, 0.2],
            [-1.0, -0.4, 0.1],
            [0.2, 0.9, 0.3],
            [0.3, -0.2, 1.0],
        ] {
            let scene = scene_with_sky(
                &dir,
                &texels,
                w,
                &format!(
                    r#"
                    [camera]
                    position = [0, 0, 0]
                    look_at = {look:?}
                    vfov = 0.5
                    [render]
                    width = 1
                    height = 1
                    integrator = "path"
                    samples = 4
                    [environment]
                    image = "sky.exr"
                    intensity = 2
                    rotation = {rotation:?}
                    "#
                ),
            );
            let env = scene.environment.as_ref().expect("the sky image");
            let expected = env.radiance(DVec3::from_array(look).normalize());
            let got = default_radiance(&scene);
            for c in 0..3 {
                assert_close(
                    got[c],
                    expected[c],
                    1e-6,
                    &format!("{look:?} turned {rotation}"),
                );
            }
        }
    }
}

/// A plane of albedo a under a sky image with a small bright sun: its
/// radiance is a / pi times the irradiance summed texel by texel over the
/// upper half of the image (direct light only). Sampling the sky by its
/// luminance, sampling the BSDF and their weights together are unbiased.
#[test]
fn a_plane_under_a_sky_image_gets_the_irradiance_of_its_texels() {
    let dir = TempDir::new("sky-plane");
    let (w, h) = (16u32, 8u32);
    let mut texels: Vec<[f32; 3]> = (0..w * h)
        .map(|i| {
            let row = (i / w) as f32;
            [0.2 + 0.1 * row, 0.3, 0.5 - 0.05 * row]
        })
        .collect();
    texels[(w + 5) as usize] = [400.0, 300.0, 200.0]; // the sun, high in the sky
    let a = 0.5;
    let scene = scene_with_sky(
        &dir,
        &texels,
        w,
        &format!(
            r#"
            [camera]
            position = [0, 2, 3]
            look_at = [0, 0, 0]
            vfov = 20
            [render]
            width = 8
            height = 8
            integrator = "path"
            samples = 512
            max_depth = 1
            [environment]
            image = "sky.exr"
            rotation = 40
            [materials.plane]
            diffuse = [{a}, {a}, {a}]
            [[triangles]]
            vertices = [[-1000, 0, -1000], [1000, 0, -1000], [1000, 0, 1000]]
            material = "plane"
            [[triangles]]
            vertices = [[-1000, 0, -1000], [1000, 0, 1000], [-1000, 0, 1000]]
            material = "plane"
            "#
        ),
    );
    // Irradiance on a plane facing +y: each texel of the upper half
    // subtends d(phi) = 2 pi / w and its cosine-weighted polar band
    // (sin^2 theta1 - sin^2 theta0) / 2.
    let mut irradiance = [0.0f64; 3];
    for row in 0..h / 2 {
        let t0 = row as f64 / h as f64 * std::f64::consts::PI;
        let t1 = (row + 1) as f64 / h as f64 * std::f64::consts::PI;
        let band =
            (t1.sin().powi(2) - t0.sin().powi(2)) / 2.0 * (2.0 * std::f64::consts::PI / w as f64);
        for col in 0..w {
            let t = texels[(row * w + col) as usize];
            for c in 0..3 {
                irradiance[c] += t[c] as f64 * band;
            }
        }
    }
    let image = default_radiance(&scene);
    let pixels = (image.len() / 3) as f64;
    for (c, channel_irradiance) in irradiance.iter().enumerate() {
        let mean: f64 = image
            .iter()
            .skip(c)
            .step_by(3)
            .map(|&x| x as f64)
            .sum::<f64>()
            / pixels;
        let expected = a / std::f64::consts::PI * channel_irradiance;
        assert_close(mean as f32, expected, 0.01, &format!("channel {c}"));
    }
}

/// A sky image that is missing, truncated or not an image: one line naming
/// the file and the key, exit 2.
#[test]
fn a_bad_sky_image_is_refused_in_one_line() {
    let dir = TempDir::new("sky-bad");
    let scene = dir.write(
        "scene.toml",
        "[camera]\nposition = [0, 0, 5]\nlook_at = [0, 0, 0]\n[render]\nintegrator = \"path\"\n[environment]\nimage = \"sky.hdr\"\n",
    );
    let full = {
        let mut bytes = std::io::Cursor::new(Vec::new());
        image::DynamicImage::ImageRgb32F(
            image::Rgb32FImage::from_raw(4, 2, vec![1.0; 24]).unwrap(),
        )
        .write_to(&mut bytes, image::ImageFormat::Hdr)
        .unwrap();
        bytes.into_inner()
    };
    for (what, bytes) in [
        ("missing", None),
        ("truncated", Some(full[..full.len() - 7].to_vec())),
        ("not an image", Some(b"#?RADIANCE\nhello".to_vec())),
    ] {
        let _ = std::fs::remove_file(dir.join("sky.hdr"));
        if let Some(b) = bytes {
            std::fs::write(dir.join("sky.hdr"), b).unwrap();
        }
        let run = run_kdray(
            &dir.path,
            &["render", scene.to_str().unwrap(), "-o", "out.png"],
            &[],
        );
        assert_eq!(run.code, 2, "{what}: {run:?}");
        let line = run.one_error_line();
        assert!(
            line.contains("sky.hdr") && line.contains("environment.image"),
            "{what}: {line}"
        );
        assert!(!dir.join("out.png").exists());
    }
}

/// A glass sphere of ior 1 (nothing bends, nothing reflects) whose inside
/// absorbs: white light that crosses `attenuation_distance` of it turns
/// `attenuation_color`. Under a uniform sky L a path through its centre
/// crosses a diameter 2 inside, so the centre pixel shows
/// L x colour^(2 / distance) (Beer-Lambert), in each channel on its own;
/// the same sphere without the keys shows the sky unchanged.
#[test]
fn a_coloured_medium_absorbs_as_beer_lambert_says() {
    let text = |volume: &str| {
        format!(
            r#"
            [camera]
            position = [0, 0, 4]
            look_at = [0, 0, 0]
            vfov = 40
            [render]
            width = 25
            height = 25
            integrator = "path"
            samples = 8
            max_depth = 6
            [environment]
            color = [0.5, 0.25, 1.0]
            [materials.glass]
            diffuse = [1, 1, 1]
            transmission = 1
            ior = 1
            {volume}
            [[spheres]]
            center = [0, 0, 0]
            radius = 1
            material = "glass"
            "#
        )
    };
    let sky = [0.5, 0.25, 1.0];
    let colour = [0.5, 0.8, 1.0];
    let distance = 2.0;
    let absorbing = default_radiance(&scene_from_toml(&text(&format!(
        "attenuation_color = {colour:?}\nattenuation_distance = {distance}"
    ))));
    let clear = default_radiance(&scene_from_toml(&text("")));
    // Pixel 12 of 25 looks along the axis; its samples spread over the
    // pixel, whose rays cross the sphere within 0.4% of the diameter.
    let centre = (12 * 25 + 12) * 3;
    for c in 0..3 {
        let expected = sky[c] * f64::powf(colour[c], 2.0 / distance);
        assert_close(absorbing[centre + c], expected, 0.005, "through the medium");
        assert_close(clear[centre + c], sky[c], 1e-5, "through clear glass");
    }
}
