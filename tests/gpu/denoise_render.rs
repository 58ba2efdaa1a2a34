//! The path tracer feeding the denoiser: its feature images (albedo and
//! shading normal of the first hit that is not a perfect mirror or smooth
//! glass) on scenes where they are known exactly (a plane, a textured
//! plane, a mirror), the radiance of the
//! feature variant equal to the plain one's bit for bit, and `kdray render
//! --denoise` (`[render] denoise = true`) end to end: a denoised image far
//! less noisy than the noisy one, the EXR's three companion files, and the
//! Whitted integrator refused in one line.

use crate::common;

use common::*;
use kdray::gpu::{Accel, GpuScene, PreparedScene, Renderer, TilePlan};
use kdray::output::exr::read_exr_rgb;
use kdray::output::read_png_rgb;
use kdray::scene::Scene;

/// A path frame's mean radiance, albedo and normal per pixel (three floats
/// each, row-major), from a renderer asked for the features or not (then
/// the albedo and normal are empty).
struct Frame {
    radiance: Vec<f32>,
    albedo: Vec<f32>,
    normal: Vec<f32>,
}

fn render_frame(scene: &Scene, features: bool) -> Frame {
    let ctx = gpu();
    let uploaded = GpuScene::upload(ctx, PreparedScene::new(scene.clone(), Accel::Kdtree))
        .unwrap_or_else(|e| panic!("{e}"));
    let mut renderer = Renderer::new(ctx)
        .unwrap_or_else(|e| panic!("{e}"))
        .with_settings(&scene.render);
    if features {
        renderer = renderer.with_features();
    }
    let (w, h) = (scene.render.width, scene.render.height);
    let plan = TilePlan::new(
        w,
        h,
        TilePlan::DEFAULT_MAX_TILE_PIXELS,
        kdray::gpu::max_binding_bytes(&ctx.device.limits()),
    );
    let mut frame = Frame {
        radiance: Vec::new(),
        albedo: Vec::new(),
        normal: Vec::new(),
    };
    renderer
        .render_bands(
            ctx,
            uploaded.buffers(),
            uploaded.frame_params(),
            plan,
            &mut |band| {
                frame
                    .radiance
                    .extend_from_slice(band.radiance.expect("path frames carry radiance"));
                assert_eq!(band.features.is_some(), features);
                if let Some(f) = band.features {
                    frame.albedo.extend_from_slice(f.albedo);
                    frame.normal.extend_from_slice(f.normal);
                }
                Ok(())
            },
        )
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(frame.radiance.len(), (w * h * 3) as usize);
    frame
}

fn assert_near(actual: &[f32], expected: [f32; 3], tolerance: f32, what: &str) {
    for c in 0..3 {
        assert!(
            (actual[c] - expected[c]).abs() <= tolerance,
            "{what}: {actual:?}, expected {expected:?}"
        );
    }
}

/// A square of diffuse colour (0.2, 0.5, 0.8), 2 on a side, facing the
/// camera under a sky of (0.3, 1.5, 0.1): every sample of a pixel wholly
/// on it has the square's colour as albedo and its normal (0, 0, 1); every
/// sample of a pixel wholly off it sees the sky, whose albedo is its
/// colour clamped to [0, 1], (0.3, 1, 0.1), and whose normal is 0. The
/// feature variant's radiance is the plain variant's, bit for bit: the
/// features draw no random number and change nothing of the path.
#[test]
fn a_plane_facing_the_camera_shows_its_colour_and_normal() {
    let scene = scene_from_toml(
        r#"
        [camera]
        position = [0, 0, 3]
        look_at = [0, 0, 0]
        vfov = 60
        [render]
        width = 32
        height = 32
        integrator = "path"
        samples = 4
        max_depth = 3
        [environment]
        color = [0.3, 1.5, 0.1]
        [materials.m]
        diffuse = [0.2, 0.5, 0.8]
        [[triangles]]
        vertices = [[-1, -1, 0], [1, -1, 0], [1, 1, 0]]
        material = "m"
        [[triangles]]
        vertices = [[-1, -1, 0], [1, 1, 0], [-1, 1, 0]]
        material = "m"
        "#,
    );
    let plain = render_frame(&scene, false);
    let frame = render_frame(&scene, true);
    let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert!(
        bits(&plain.radiance) == bits(&frame.radiance),
        "the feature variant changed the radiance"
    );

    // The square's edges at z = 0 are at +-1 of a half-width of
    // 3 tan 30 degrees: columns and rows whose whole pixel lies inside, or
    // wholly outside.
    let half = 3.0 * (30f64.to_radians()).tan();
    let side = 32;
    let edge = |i: usize| (2.0 * i as f64 / side as f64 - 1.0) * half;
    let inside = |i: usize| edge(i).abs() < 1.0 && edge(i + 1).abs() < 1.0;
    let outside = |i: usize| edge(i + 1) < -1.0 || edge(i) > 1.0;
    let (mut on, mut off) = (0, 0);
    for y in 0..side {
        for x in 0..side {
            let at = (y * side + x) * 3;
            let (albedo, normal) = (&frame.albedo[at..at + 3], &frame.normal[at..at + 3]);
            if inside(x) && inside(y) {
                on += 1;
                assert_near(albedo, [0.2, 0.5, 0.8], 1e-6, "the square's albedo");
                assert_near(normal, [0.0, 0.0, 1.0], 1e-6, "the square's normal");
            } else if outside(x) || outside(y) {
                off += 1;
                assert_near(albedo, [0.3, 1.0, 0.1], 1e-6, "the sky's albedo");
                assert_near(normal, [0.0; 3], 0.0, "the sky's normal");
            }
        }
    }
    assert!(on >= 100 && off >= 100, "{on} pixels on, {off} off");
}

/// The same square from an OBJ whose MTL paints it with a one-texel
/// texture of (255, 0, 255) over `Kd` (0.4, 0.6, 0.8): the albedo is the
/// texel times the colour, (0.4, 0, 0.8), where the square fills a pixel.
#[test]
fn a_textured_surface_shows_its_texel_times_its_colour() {
    let dir = TempDir::new("denoise-texture");
    image::RgbImage::from_pixel(1, 1, image::Rgb([255, 0, 255]))
        .save(dir.path.join("texel.png"))
        .unwrap();
    std::fs::write(
        dir.path.join("quad.mtl"),
        "newmtl tex\nKd 0.4 0.6 0.8\nmap_Kd texel.png\n",
    )
    .unwrap();
    std::fs::write(
        dir.path.join("quad.obj"),
        "mtllib quad.mtl\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n\
         vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl tex\nf 1/1 2/2 3/3\nf 1/1 3/3 4/4\n",
    )
    .unwrap();
    let toml = dir.path.join("scene.toml");
    std::fs::write(
        &toml,
        "[camera]\nposition = [0, 0, 3]\nlook_at = [0, 0, 0]\nvfov = 60\n\
         [render]\nwidth = 16\nheight = 16\nintegrator = \"path\"\nsamples = 2\nmax_depth = 2\n\
         [environment]\ncolor = [0.5, 0.5, 0.5]\n\
         [[meshes]]\npath = \"quad.obj\"\n",
    )
    .unwrap();
    let scene = kdray::scene::load_scene(&toml).unwrap_or_else(|e| panic!("{e}"));
    let frame = render_frame(&scene, true);
    let half = 3.0 * (30f64.to_radians()).tan();
    let edge = |i: usize| (2.0 * i as f64 / 16.0 - 1.0) * half;
    let inside = |i: usize| edge(i).abs() < 1.0 && edge(i + 1).abs() < 1.0;
    let mut on = 0;
    for y in (0..16).filter(|&y| inside(y)) {
        for x in (0..16).filter(|&x| inside(x)) {
            let at = (y * 16 + x) * 3;
            assert_near(
                &frame.albedo[at..at + 3],
                [0.4, 0.0, 0.8],
                1e-6,
                "the texel",
            );
            on += 1;
        }
    }
    assert!(on >= 25, "{on} pixels on the square");
}

/// A perfect mirror turned 45 degrees fills the view and sends every
/// camera ray sideways onto a diffuse wall of colour (0.9, 0.3, 0.1): the
/// features follow the mirror, so every pixel shows the wall's albedo and
/// its normal, facing the reflected rays, (-1, 0, 0), not the mirror's.
#[test]
fn a_mirror_shows_the_albedo_and_normal_of_what_it_reflects() {
    let scene = scene_from_toml(
        r#"
        [camera]
        position = [0, 0, 3]
        look_at = [0, 0, 0]
        vfov = 30
        [render]
        width = 16
        height = 16
        integrator = "path"
        samples = 2
        max_depth = 3
        [environment]
        color = [0.5, 0.5, 0.5]
        [materials.mirror]
        diffuse = [0.05, 0.05, 0.05]
        reflection = 1
        [materials.wall]
        diffuse = [0.9, 0.3, 0.1]
        # The mirror: the plane z = -x, its normal (1, 0, 1) / sqrt 2.
        [[triangles]]
        vertices = [[-20, -20, 20], [20, -20, -20], [20, 20, -20]]
        material = "mirror"
        [[triangles]]
        vertices = [[-20, -20, 20], [20, 20, -20], [-20, 20, 20]]
        material = "mirror"
        # The wall: the plane x = 3, beside the camera's view.
        [[triangles]]
        vertices = [[3, -50, -50], [3, 50, -50], [3, 50, 50]]
        material = "wall"
        [[triangles]]
        vertices = [[3, -50, -50], [3, 50, 50], [3, -50, 50]]
        material = "wall"
        "#,
    );
    let frame = render_frame(&scene, true);
    for (albedo, normal) in frame.albedo.chunks(3).zip(frame.normal.chunks(3)) {
        assert_near(albedo, [0.9, 0.3, 0.1], 1e-6, "the wall's albedo");
        assert_near(normal, [-1.0, 0.0, 0.0], 1e-6, "the wall's normal");
    }
}

/// The mean squared difference between horizontally neighbouring pixels'
/// luminance: noise, mostly, on a wall whose light varies slowly.
fn roughness(rgb: &[f32], width: usize) -> f64 {
    let luminance: Vec<f64> = rgb
        .chunks(3)
        .map(|p| 0.2126 * p[0] as f64 + 0.7152 * p[1] as f64 + 0.0722 * p[2] as f64)
        .collect();
    let mut sum = 0.0;
    let mut count = 0;
    for row in luminance.chunks(width) {
        for pair in row.windows(2) {
            sum += (pair[1] - pair[0]).powi(2);
            count += 1;
        }
    }
    sum / count as f64
}

/// `render --denoise -o x.exr`: the denoised radiance and, beside it, the
/// noisy radiance, the albedo and the normal, each 48 x 48; on the Cornell
/// box's back wall at 2 samples a pixel the denoised image's
/// pixel-to-pixel noise is under a tenth of the noisy one's (measured: a
/// 28th; 512 samples leave more than the denoiser), and `kdray denoise` on
/// the three inputs gives the same image. The
/// same render to a PNG is the denoised EXR tone-mapped as the scene says.
#[test]
fn render_denoise_writes_a_less_noisy_image_and_its_inputs() {
    let dir = TempDir::new("denoise-render");
    let scene = repo_path("scenes/cornell_box.toml");
    let scene = scene.to_str().unwrap();
    let size = ["--width", "48", "--height", "48", "--samples", "2"];
    let mut args = vec!["render", scene, "--denoise", "-o", "x.exr"];
    args.extend(size);
    let run = run_kdray(&dir.path, &args, &[]);
    assert_eq!(run.code, 0, "{run:#?}");
    let read = |name: &str| {
        let (w, h, rgb) = read_exr_rgb(&dir.path.join(name)).unwrap();
        assert_eq!((w, h), (48, 48), "{name}");
        rgb
    };
    let (denoised, noisy) = (read("x.exr"), read("x.noisy.exr"));
    let (albedo, normal) = (read("x.albedo.exr"), read("x.normal.exr"));
    assert!(albedo.iter().all(|v| (0.0..=1.0).contains(v)));
    for n in normal.chunks(3) {
        let length = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        assert!(length <= 1.0 + 1e-5, "{n:?}");
    }
    let mut names: Vec<String> = std::fs::read_dir(&dir.path)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(
        names,
        ["x.albedo.exr", "x.exr", "x.noisy.exr", "x.normal.exr"],
        "no temporary file is left"
    );
    // The back wall above the spheres, away from the light and the edges.
    let wall = |rgb: &[f32]| {
        let mut region = Vec::new();
        for y in 8..20 {
            region.extend_from_slice(&rgb[(y * 48 + 12) * 3..(y * 48 + 36) * 3]);
        }
        roughness(&region, 24)
    };
    let (before, after) = (wall(&noisy), wall(&denoised));
    eprintln!("the back wall's neighbour differences: noisy {before:.6}, denoised {after:.6}");
    assert!(after < before / 10.0, "noisy {before}, denoised {after}");

    // `kdray denoise` on the three inputs gives the same image.
    let run = run_kdray(
        &dir.path,
        &[
            "denoise",
            "x.noisy.exr",
            "--albedo",
            "x.albedo.exr",
            "--normal",
            "x.normal.exr",
            "-o",
            "again.exr",
        ],
        &[],
    );
    assert_eq!(run.code, 0, "{run:#?}");
    assert!(
        read("again.exr") == denoised,
        "kdray denoise gave another image"
    );

    let mut args = vec!["render", scene, "--denoise", "-o", "x.png"];
    args.extend(size);
    let run = run_kdray(&dir.path, &args, &[]);
    assert_eq!(run.code, 0, "{run:#?}");
    let (w, h, png) = read_png_rgb(&dir.path.join("x.png")).unwrap();
    assert_eq!((w, h), (48, 48));
    let mapped: Vec<u8> = denoised
        .iter()
        .map(|&v| kdray::scene::ToneMap::Aces.to_srgb8(v, 1.0))
        .collect();
    assert!(png == mapped, "the PNG is not the denoised EXR tone-mapped");
}

/// The denoiser with the Whitted integrator: `--denoise` on a Whitted
/// scene, `--integrator whitted` on a scene asking for the denoiser, and a
/// Whitted scene file with `denoise = true` each exit 2 with one line and
/// write nothing; `--denoise=false` turns the scene's key off.
#[test]
fn the_denoiser_with_the_whitted_integrator_is_refused_in_one_line() {
    let dir = TempDir::new("denoise-whitted");
    let seed = repo_path("scenes/seed.toml");
    let seed = seed.to_str().unwrap();
    let asking = "[camera]\nposition = [0, 0, 3]\nlook_at = [0, 0, 0]\n\
        [render]\nwidth = 8\nheight = 8\nintegrator = \"path\"\ndenoise = true\n\
        [[lights]]\nposition = [0, 2, 2]\n\
        [materials.m]\ndiffuse = [0.5, 0.5, 0.5]\n\
        [[spheres]]\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"m\"\n";
    std::fs::write(dir.path.join("asking.toml"), asking).unwrap();
    std::fs::write(
        dir.path.join("whitted.toml"),
        asking.replace("integrator = \"path\"", "integrator = \"whitted\""),
    )
    .unwrap();
    for (args, names) in [
        (
            vec!["render", seed, "--denoise", "-o", "a.png"],
            "--denoise",
        ),
        (
            vec![
                "render",
                "asking.toml",
                "--integrator",
                "whitted",
                "-o",
                "a.png",
            ],
            "denoise",
        ),
        (
            vec!["render", "whitted.toml", "-o", "a.png"],
            "render.denoise",
        ),
    ] {
        let run = run_kdray(&dir.path, &args, &[]);
        assert_eq!(run.code, 2, "{run:#?}");
        let line = run.one_error_line();
        assert!(line.contains(names), "{line:?} should name {names}");
        assert!(!dir.path.join("a.png").exists());
    }
    let run = run_kdray(
        &dir.path,
        &[
            "render",
            "asking.toml",
            "--integrator",
            "whitted",
            "--denoise=false",
            "-o",
            "a.png",
        ],
        &[],
    );
    assert_eq!(run.code, 0, "{run:#?}");
    assert!(dir.path.join("a.png").exists());
}
