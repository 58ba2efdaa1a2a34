//! GPU renders on the adapter at hand (lavapipe in CI): the k-d tree equals
//! brute force on every shipped scene, tiling changes nothing, and analytic
//! scenes give the values the spec predicts.

use crate::common;

use common::*;
use kdray::gpu::{
    Accel, CostTotals, GpuScene, KernelVariant, PreparedScene, RenderedImage, Renderer, TilePlan,
};
use kdray::kdtree::traverse::WalkCost;
use kdray::kdtree::Traversal;
use kdray::scene::Scene;

/// `scene` through the k-d tree with the walk `traversal`, in dispatches of
/// at most `max_tile_pixels`.
fn render_walk(scene: &Scene, traversal: Traversal, max_tile_pixels: u64) -> RenderedImage {
    let ctx = gpu();
    let prepared = PreparedScene::new(scene.clone(), Accel::Kdtree);
    let uploaded = GpuScene::upload(ctx, prepared).unwrap_or_else(|e| panic!("{e}"));
    let renderer = Renderer::new(ctx).unwrap_or_else(|e| panic!("{e}"));
    let params = uploaded.frame_params().with_traversal(traversal);
    let (w, h) = (scene.render.width, scene.render.height);
    let plan = TilePlan::new(
        w,
        h,
        max_tile_pixels,
        kdray::gpu::max_binding_bytes(&ctx.device.limits()),
    );
    renderer
        .render(ctx, uploaded.buffers(), params, plan)
        .unwrap_or_else(|e| panic!("{e}"))
}

/// Small tiles give the same image, bit for bit, and the same ray counts as
/// one dispatch, with every walk.
#[test]
fn tiled_render_equals_untiled() {
    let scene = small_scene(&repo_path("scenes/seed.toml"));
    for walk in Traversal::ALL {
        let whole = render_walk(&scene, walk, u64::MAX);
        let tiled = render_walk(&scene, walk, 37 * 3); // odd-sized tiles, partial last tile
        assert_eq!(whole.rgb, tiled.rgb, "{walk}");
        // The shader's ray counters are per tile and summed: tiling changes nothing.
        assert_eq!(whole.rays, tiled.rays, "{walk}");
        assert_eq!(
            whole.rays.primary,
            (scene.render.width * scene.render.height) as u64
        );
    }
}

const HEAD_ON: &str = r#"
[camera]
position = [0.0, 0.0, 5.0]
look_at = [0.0, 0.0, 0.0]
vfov = 30.0
[render]
width = 33
height = 33
[[lights]]
position = [0.0, 0.0, 5.0]
ambient = [0.5, 0.5, 0.5]
diffuse = [0.8, 0.7, 0.6]
specular = [0.9, 0.9, 0.9]
[materials.m]
ambient = [0.1, 0.2, 0.05]
diffuse = [0.5, 0.3, 0.2]
specular = [0.3, 0.2, 0.1]
shininess = 40.0
[[spheres]]
center = [0.0, 0.0, 0.0]
radius = 1.0
material = "m"
"#;

/// Blinn-Phong of one sphere lit by one light, in f64, for the pixel's ray.
fn single_sphere_expected(scene: &kdray::scene::Scene, row: u32, column: u32) -> Option<[f64; 3]> {
    let cam = &scene.camera;
    let (w, h) = (scene.render.width as f64, scene.render.height as f64);
    let forward = (cam.look_at - cam.position).normalize();
    let right = forward.cross(cam.up).normalize();
    let up = right.cross(forward);
    let t = (cam.vfov_degrees.to_radians() / 2.0).tan();
    let (u, v) = ((column as f64 + 0.5) / w, (row as f64 + 0.5) / h);
    let dir =
        (forward + (2.0 * u - 1.0) * t * (w / h) * right + (1.0 - 2.0 * v) * t * up).normalize();
    let s = &scene.spheres[0];
    let f = cam.position - s.center;
    let b = f.dot(dir);
    let disc = b * b - (f.dot(f) - s.radius * s.radius);
    if disc < 0.0 {
        return None;
    }
    let p = cam.position + (-b - disc.sqrt()) * dir;
    let n = (p - s.center).normalize();
    let m = &scene.materials[0];
    let l = &scene.lights[0];
    let to_light = (l.position - p).normalize();
    let mut c = m.ambient * l.ambient;
    let l_dot_n = to_light.dot(n);
    if l_dot_n > 0.0 {
        let half = (to_light - dir).normalize();
        c += m.diffuse * l.diffuse * l_dot_n
            + m.specular * l.specular * n.dot(half).max(0.0).powf(m.shininess / 4.0);
    }
    Some(c.to_array())
}

#[test]
fn sphere_lit_head_on_has_the_exact_blinn_phong_value() {
    let scene = scene_from_toml(HEAD_ON);
    let image = render(&scene, Accel::Kdtree);
    // Centre pixel: N = L = V = H, so colour = ka*la + kd*ld + ks*ls exactly.
    let expected = quantize(single_sphere_expected(&scene, 16, 16).unwrap());
    assert_eq!(
        expected,
        quantize([
            0.1 * 0.5 + 0.5 * 0.8 + 0.3 * 0.9,
            0.2 * 0.5 + 0.3 * 0.7 + 0.2 * 0.9,
            0.05 * 0.5 + 0.2 * 0.6 + 0.1 * 0.9
        ])
    );
    assert_eq!(pixel(&image, 16, 16), expected);
    // Off-centre pixels, where L.N < 1 and the specular falls off: within a
    // level of the f64 reference; misses are black.
    for (row, column) in [(10, 16), (16, 22), (12, 19), (20, 13), (8, 16), (0, 0)] {
        let expected = single_sphere_expected(&scene, row, column).map_or([0, 0, 0], quantize);
        let got = pixel(&image, row, column);
        for c in 0..3 {
            assert!(
                got[c].abs_diff(expected[c]) <= 1,
                "pixel ({row}, {column}): got {got:?}, expected {expected:?}"
            );
        }
    }
}

/// A floor point under a sphere that hides the light: black in seed mode,
/// exactly its ambient term in ambient mode; a lit point stays lit.
#[test]
fn shadowed_point_is_black_in_seed_mode_and_ambient_in_ambient_mode() {
    let scene_text = |mode: &str| {
        format!(
            r#"
[camera]
position = [0.0, 4.0, 0.001]
look_at = [0.0, 0.0, 0.0]
vfov = 40.0
[render]
width = 41
height = 41
shadow_mode = "{mode}"
[[lights]]
position = [0.0, 10.0, 0.0]
ambient = [0.5, 0.4, 1.0]
[materials.floor]
ambient = [0.2, 0.3, 0.1]
diffuse = [0.6, 0.6, 0.6]
[materials.blocker]
ambient = [0.0, 0.0, 0.0]
diffuse = [0.0, 0.0, 1.0]
[[triangles]]
vertices = [[-50.0, 0.0, -50.0], [50.0, 0.0, 50.0], [50.0, 0.0, -50.0]]
material = "floor"
[[triangles]]
vertices = [[-50.0, 0.0, -50.0], [-50.0, 0.0, 50.0], [50.0, 0.0, 50.0]]
material = "floor"
[[spheres]]
center = [0.0, 6.0, 0.0]
radius = 0.5
material = "blocker"
"#
        )
    };
    // The blocker sits between the light and the floor's centre, above the
    // camera's view (the camera looks down from y = 4 < 5.5).
    let seed = render(&scene_from_toml(&scene_text("seed")), Accel::Kdtree);
    assert_eq!(
        pixel(&seed, 20, 20),
        [0, 0, 0],
        "shadowed floor in seed mode"
    );
    let ambient = render(&scene_from_toml(&scene_text("ambient")), Accel::Kdtree);
    assert_eq!(
        pixel(&ambient, 20, 20),
        quantize([0.2 * 0.5, 0.3 * 0.4, 0.1 * 1.0]),
        "shadowed floor in ambient mode"
    );
    // A corner of the view is outside the shadow: ambient + diffuse.
    let lit = pixel(&ambient, 0, 0);
    assert!(
        lit[0] > quantize([0.1, 0.0, 0.0])[0] + 50,
        "lit floor {lit:?}"
    );
    assert_eq!(
        pixel(&seed, 0, 0),
        lit,
        "lit points are the same in both modes"
    );
}

/// A half mirror facing the camera reflects a sphere behind the camera:
/// colour = (1 - r) * mirror_local + r * sphere_local (sphere opaque).
#[test]
fn mirror_gives_the_weighted_sum_of_the_spec() {
    let scene = scene_from_toml(
        r#"
[camera]
position = [0.0, 0.0, 5.0]
look_at = [0.0, 0.0, 0.0]
vfov = 20.0
[render]
width = 21
height = 21
[[lights]]
position = [0.0, 0.0, 7.0]
ambient = [0.5, 0.5, 0.5]
diffuse = [0.6, 0.6, 0.6]
specular = [0.4, 0.4, 0.4]
[materials.mirror]
ambient = [0.05, 0.1, 0.0]
diffuse = [0.1, 0.0, 0.2]
specular = [0.05, 0.05, 0.05]
shininess = 8.0
reflection = 0.5
[materials.ball]
ambient = [0.2, 0.1, 0.3]
diffuse = [0.7, 0.2, 0.1]
specular = [0.3, 0.3, 0.3]
shininess = 50.0
[[triangles]]
vertices = [[-10.0, -10.0, 0.0], [10.0, -10.0, 0.0], [10.0, 10.0, 0.0]]
material = "mirror"
[[triangles]]
vertices = [[-10.0, -10.0, 0.0], [10.0, 10.0, 0.0], [-10.0, 10.0, 0.0]]
material = "mirror"
[[spheres]]
center = [0.0, 0.0, 10.0]
radius = 1.0
material = "ball"
"#,
    );
    let image = render(&scene, Accel::Kdtree);
    // Centre ray: hits the mirror at the origin head-on (N = L = V = H), then
    // the sphere's near pole at z = 9 head-on as well.
    let local = |m: usize| {
        let (m, l) = (&scene.materials[m], &scene.lights[0]);
        m.ambient * l.ambient + m.diffuse * l.diffuse + m.specular * l.specular
    };
    let (ball, mirror) = (
        scene
            .materials
            .iter()
            .position(|m| m.name == "ball")
            .unwrap(),
        scene
            .materials
            .iter()
            .position(|m| m.name == "mirror")
            .unwrap(),
    );
    let expected = 0.5 * local(mirror) + 0.5 * local(ball);
    assert_eq!(pixel(&image, 10, 10), quantize(expected.to_array()));
    // Brute force agrees exactly on this pixel.
    assert_eq!(
        pixel(&render(&scene, Accel::Brute), 10, 10),
        pixel(&image, 10, 10)
    );
}

/// The GPU kernel against its CPU mirror (crates/kdray-core/src/reference/:
/// the same path loop, shading and f32 arithmetic over the CPU traversal) on
/// every scene of the Whitted integrator, which it mirrors: pixels may
/// differ only where float rounding (e.g. fused multiply-adds on the GPU)
/// flips a tie. (The path tracer is held to exact radiance in the
/// `path_tracing` module.)
#[test]
fn gpu_matches_the_cpu_reference_on_every_scene() {
    for path in shipped_scenes() {
        let mut scene = small_scene(&path);
        if scene.render.integrator == kdray::scene::Integrator::Path {
            continue;
        }
        scene.render.width = 64;
        scene.render.height = (scene.render.height * 64).div_ceil(160);
        let gpu = render(&scene, Accel::Kdtree);
        let cpu = kdray_core::reference::ReferenceTracer::new(&scene, true).image();
        let d = compare(&gpu.rgb, &cpu, gpu.width, gpu.height, 2);
        let budget = (gpu.width * gpu.height) as usize / 1000;
        assert!(
            d.pixels_over <= budget,
            "{}: GPU and CPU reference differ on {} pixels (budget {budget}): {d:?}",
            path.display(),
            d.pixels_over
        );
    }
}

/// The tier's tests share one device, and llvmpipe compiles a pipeline on
/// its device's queue thread at the first dispatch, so the test binary used
/// one core of two while two tests ran (measured with top). The test below
/// compiles the most pipelines of any (every shipped scene's, every walk's),
/// so it runs in a child process of this binary, on a device of its own,
/// while the rest run here.
#[test]
fn every_walk_renders_brute_forces_and_the_general_kernels_image_in_a_process_of_its_own() {
    const TEST: &str =
        "gpu_render::every_walk_renders_brute_forces_and_the_general_kernels_image_on_every_scene";
    let out = std::process::Command::new(std::env::current_exe().unwrap())
        .args([TEST, "--exact", "--include-ignored"])
        .output()
        .expect("cannot run the test binary");
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{TEST} failed:\n{stdout}\n{stderr}");
    assert!(
        stdout.contains(&format!("test {TEST} ... ok")),
        "{TEST} did not run:\n{stdout}"
    );
}

/// One frame's images and counted work: the specialised pipeline's plain
/// render, its counting render where the frame checks counting, and the
/// general kernel's (which counts).
struct FrameRenders {
    plain: RenderedImage,
    counted: Option<(Vec<u8>, Vec<WalkCost>, CostTotals)>,
    general: RenderedImage,
    general_counted: (Vec<WalkCost>, CostTotals),
}

/// `params` of `buffers` through `renderer`, whole, keeping every pixel's
/// colour and cost.
fn render_counted(
    renderer: &Renderer,
    buffers: &kdray::gpu::SceneBuffers,
    params: kdray::gpu::FrameParams,
    plan: TilePlan,
) -> (RenderedImage, Vec<WalkCost>, CostTotals) {
    let ctx = gpu();
    let (mut rgb, mut costs) = (Vec::new(), Vec::new());
    let summary = renderer
        .render_bands_with_cost(ctx, buffers, params, plan, true, &mut |band| {
            rgb.extend_from_slice(band.rgb);
            costs.extend_from_slice(band.costs.expect("costs asked for"));
            Ok(())
        })
        .unwrap_or_else(|e| panic!("{e}"));
    let image = RenderedImage {
        width: params.width,
        height: params.height,
        rgb,
        gpu_ms: summary.gpu_ms,
        gpu_time_source: summary.gpu_time_source,
        rays: summary.rays,
    };
    (image, costs, summary.cost.expect("costs asked for"))
}

/// The two guarantees every shipped scene is rendered for, each frame once
/// (llvmpipe compiles each pipeline once per process and renders each
/// frame in seconds, so one pass serves both):
///
/// - Every k-d walk gives brute force's image, bit for bit: each walk finds
///   brute force's nearest hit and its shadow rays' occluders. (A tolerance
///   of 0.1% of pixels once hid a pixel off by 201 levels: a shadow ray
///   through the corner of two split planes.) Scenes of more objects (the
///   bunny's 69,670) are compared walk against walk: brute force over them
///   exceeds llvmpipe's loop limit (design.md).
/// - Each frame runs a pipeline specialised for its scene and walk
///   (`gpu::kernel_variant`): only that walk, only the scene's kinds of
///   object, smooth shading only where a triangle has vertex normals, and
///   the walks' counters only where the frame reports its cost. For every
///   walk and brute force on every scene (spheres only, triangles only,
///   both, smooth), the specialised pipeline renders the general kernel's
///   image bit for bit, with the same ray counts; and it is a specialised
///   one, so the comparison is not the general kernel with itself. Its
///   counting variant renders that image too and counts the general
///   kernel's work pixel for pixel: checked on one frame a scene, the walk
///   turning from scene to scene, so that every walk and brute force count
///   on several kinds of scene.
///
/// Path-traced scenes get [`path_pixels_allowed`] in both.
#[test]
#[ignore = "run by every_walk_renders_brute_forces_and_the_general_kernels_image_in_a_process_of_its_own"]
fn every_walk_renders_brute_forces_and_the_general_kernels_image_on_every_scene() {
    const BRUTE_FORCE_MAX_OBJECTS: usize = 10_000;
    let ctx = gpu();
    let specialised = Renderer::new(ctx).unwrap_or_else(|e| panic!("{e}"));
    let general = Renderer::general(ctx).unwrap_or_else(|e| panic!("{e}"));
    let mut kinds_seen = std::collections::HashSet::new();
    let mut counted_frames = std::collections::HashSet::new();
    for (index, path) in shipped_scenes().into_iter().enumerate() {
        let scene = small_pair_scene(&path);
        let allowed = path_pixels_allowed(&scene);
        let brute_force = scene.object_count() <= BRUTE_FORCE_MAX_OBJECTS;
        let mut frames: Vec<(Accel, Option<Traversal>)> = Traversal::ALL
            .iter()
            .map(|&t| (Accel::Kdtree, Some(t)))
            .collect();
        if brute_force {
            frames.push((Accel::Brute, None));
        }
        let mut images = Vec::new();
        let frame_count = frames.len();
        for (frame_index, (accel, traversal)) in frames.into_iter().enumerate() {
            let prepared = PreparedScene::new(scene.clone(), accel);
            let uploaded = GpuScene::upload(ctx, prepared).unwrap_or_else(|e| panic!("{e}"));
            let buffers = uploaded.buffers();
            let mut params = uploaded.frame_params();
            if let Some(t) = traversal {
                params = params.with_traversal(t);
            }
            let variant = specialised.variant_for(buffers, &params, false);
            assert_ne!(variant, KernelVariant::GENERAL);
            assert!(!variant.count_costs);
            assert!(specialised.variant_for(buffers, &params, true).count_costs);
            assert_eq!(
                general.variant_for(buffers, &params, false),
                KernelVariant::GENERAL
            );
            kinds_seen.insert((variant.spheres, variant.triangles, variant.smooth_triangles));
            let plan = TilePlan::new(
                scene.render.width,
                scene.render.height,
                TilePlan::DEFAULT_MAX_TILE_PIXELS,
                kdray::gpu::max_binding_bytes(&ctx.device.limits()),
            );
            let plain = specialised
                .render(ctx, buffers, params, plan)
                .unwrap_or_else(|e| panic!("{e}"));
            let (general_image, b_costs, b_total) = render_counted(&general, buffers, params, plan);
            // Each counting variant is a pipeline of its own (seconds of
            // llvmpipe compiling), so each scene checks one frame's,
            // the walk turning from scene to scene: every walk and brute
            // force count on several kinds of scene.
            let counted = (index % frame_count == frame_index).then(|| {
                counted_frames.insert(traversal);
                render_counted(&specialised, buffers, params, plan)
            });
            let frame = FrameRenders {
                plain,
                counted: counted.map(|(image, costs, total)| (image.rgb, costs, total)),
                general: general_image,
                general_counted: (b_costs, b_total),
            };
            let what = format!("{} ({accel:?}, {traversal:?}, {variant:?})", path.display());
            check_against_the_general_kernel(&frame, allowed, &what);
            images.push((traversal, frame.plain));
        }
        // Against brute force's image, or restart's where brute force is
        // out of reach.
        let reference = match images.iter().position(|(t, _)| t.is_none()) {
            Some(i) => images.remove(i).1.rgb,
            None => {
                let i = images
                    .iter()
                    .position(|(t, _)| *t == Some(Traversal::Restart))
                    .expect("restart is a walk");
                images[i].1.rgb.clone()
            }
        };
        for (walk, kd) in &images {
            let d = compare(&kd.rgb, &reference, kd.width, kd.height, 0);
            assert!(
                d.pixels_over <= allowed,
                "{} ({walk:?}) against brute force: {d:?}, {allowed} allowed",
                path.display()
            );
        }
    }
    // Spheres only, triangles only, both; and a smooth mesh (scenes/bunny.toml).
    for kinds in [(true, false), (false, true), (true, true)] {
        assert!(
            kinds_seen.iter().any(|k| (k.0, k.1) == kinds),
            "no scene of kinds {kinds:?}"
        );
    }
    assert!(kinds_seen.iter().any(|k| k.2), "no smooth scene");
    let walks = Traversal::ALL.iter().map(|&t| Some(t));
    for frame in walks.chain([None]) {
        assert!(counted_frames.contains(&frame), "{frame:?} never counted");
    }
}

/// The specialised pipeline's images (plain and counting) are the general
/// kernel's, with its ray counts, and its counted work is the general
/// kernel's pixel for pixel.
fn check_against_the_general_kernel(frame: &FrameRenders, allowed: usize, what: &str) {
    let (a, b) = (&frame.plain, &frame.general);
    let d = compare(&a.rgb, &b.rgb, a.width, a.height, 0);
    assert!(d.pixels_over <= allowed, "{what}: {d:?}, {allowed} allowed");
    if allowed == 0 {
        assert_eq!(a.rays, b.rays, "{what}");
    }
    let Some((rgb, a_costs, a_total)) = &frame.counted else {
        return;
    };
    let d = compare(rgb, &b.rgb, a.width, a.height, 0);
    assert!(
        d.pixels_over <= allowed,
        "{what}, counting: {d:?}, {allowed} allowed"
    );
    let (b_costs, b_total) = &frame.general_counted;
    assert!(
        a_total.nodes_visited + a_total.objects_tested > 0,
        "{what}: nothing counted"
    );
    let differing = a_costs.iter().zip(b_costs).filter(|(a, b)| a != b).count();
    assert!(
        differing <= allowed,
        "{what}: the costs of {differing} pixels differ"
    );
    if allowed == 0 {
        assert_eq!(a_total, b_total, "{what}");
    }
}

/// Every renderer made on one context shares each entry point's pipelines,
/// so that llvmpipe compiles a kernel variant once per process, not once
/// per frame of an animation or band of a farm task.
#[test]
fn renderers_on_one_context_share_their_compiled_pipelines() {
    let ctx = gpu();
    let first = ctx
        .trace_pipelines(kdray::gpu::bindings::RENDER_TILE)
        .unwrap_or_else(|e| panic!("{e}"));
    let again = ctx
        .trace_pipelines(kdray::gpu::bindings::RENDER_TILE)
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(std::sync::Arc::ptr_eq(&first, &again));
    let queries = ctx
        .trace_pipelines(kdray::gpu::bindings::TRACE_RAYS)
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(!std::sync::Arc::ptr_eq(&first, &queries));
}
