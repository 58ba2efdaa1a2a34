//! The native renderer on a second Vulkan implementation: SwiftShader's,
//! which Debian's chromium package ships
//! (/usr/lib/chromium/vk_swiftshader_icd.json; scripts/test.sh installs it).
//! It allows 10 storage buffers per shader stage where lavapipe allows 32,
//! so each pipeline there binds only what its scene and walk read
//! (gpu/trace_pipelines.rs); its loops and float arithmetic are its own.
//!
//! Every k-d walk equals brute force on every shipped scene, as on lavapipe
//! (tests/gpu/gpu_render.rs), and the CLI picks SwiftShader and renders with
//! it. The loader must see SwiftShader's ICD alone before the process opens
//! its first device, and the rest of this binary runs on lavapipe: so the
//! tests of [`on_swiftshader`] are marked ignored, and
//! `every_swiftshader_test_passes_in_a_process_of_its_own` runs them in a
//! child process of this binary, its environment pointed at SwiftShader.

use std::path::Path;
use std::process::Command;

use crate::common;

const SWIFTSHADER_ICD: &str = "/usr/lib/chromium/vk_swiftshader_icd.json";

/// The loader's and kdray's choice, for the child process and the CLI it
/// runs: only SwiftShader's ICD, and the adapter named after it.
const ENV: [(&str, &str); 2] = [
    ("VK_ICD_FILENAMES", SWIFTSHADER_ICD),
    ("WGPU_ADAPTER_NAME", "SwiftShader"),
];

#[test]
fn every_swiftshader_test_passes_in_a_process_of_its_own() {
    assert!(
        Path::new(SWIFTSHADER_ICD).exists(),
        "these tests need SwiftShader's Vulkan from Debian's chromium package: run scripts/test.sh gpu \
         (or apt-get install chromium)"
    );
    let out = Command::new(std::env::current_exe().unwrap())
        .args(["swiftshader::on_swiftshader::", "--include-ignored"])
        .envs(ENV)
        .output()
        .expect("cannot run the test binary");
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        out.status.success(),
        "the SwiftShader tests failed:\n{stdout}\n{stderr}"
    );
    let ran = stdout
        .lines()
        .filter(|l| l.starts_with("test ") && l.ends_with(" ... ok"))
        .count();
    assert!(ran >= 3, "only {ran} SwiftShader tests ran:\n{stdout}");
    eprintln!("{stdout}");
}

mod on_swiftshader {
    use super::*;

    use common::*;
    use kdray::gpu::{
        Accel, GpuContext, GpuScene, PreparedScene, RenderedImage, Renderer, TilePlan,
    };
    use kdray::kdtree::Traversal;
    use kdray::scene::Scene;

    /// The process's device, on SwiftShader's Vulkan (checked by name): in the
    /// child process that the environment [`ENV`] points at it.
    fn swiftshader() -> &'static GpuContext {
        let ctx = gpu();
        assert!(
            ctx.info.name.contains("SwiftShader") && ctx.info.backend == wgpu::Backend::Vulkan,
            "not SwiftShader's Vulkan but {}: these tests run in the process that \
         every_swiftshader_test_passes_in_a_process_of_its_own starts",
            ctx.adapter_line()
        );
        ctx
    }

    /// `scene` with `accel` and the walk `traversal`, on SwiftShader.
    fn render_walk(scene: &Scene, accel: Accel, traversal: Traversal) -> RenderedImage {
        try_render_walk(scene, accel, traversal).unwrap_or_else(|e| panic!("{e}"))
    }

    /// [`render_walk`], or the renderer's refusal.
    fn try_render_walk(
        scene: &Scene,
        accel: Accel,
        traversal: Traversal,
    ) -> Result<RenderedImage, String> {
        let ctx = swiftshader();
        let prepared = PreparedScene::new(scene.clone(), accel);
        let uploaded = GpuScene::upload(ctx, prepared).unwrap_or_else(|e| panic!("{e}"));
        let renderer = Renderer::new(ctx).unwrap_or_else(|e| panic!("{e}"));
        let params = uploaded.frame_params().with_traversal(traversal);
        let (w, h) = (scene.render.width, scene.render.height);
        let plan = TilePlan::new(
            w,
            h,
            TilePlan::DEFAULT_MAX_TILE_PIXELS,
            kdray::gpu::max_binding_bytes(&ctx.device.limits()),
        );
        renderer
            .render(ctx, uploaded.buffers(), params, plan)
            .map_err(|e| e.to_string())
    }

    /// The device has fewer storage buffers per stage than a kernel with every
    /// binding, so what is tested here is the slim pipelines' path.
    #[test]
    #[ignore = "on SwiftShader: run by every_swiftshader_test_passes_in_a_process_of_its_own"]
    fn swiftshader_has_fewer_storage_buffers_than_the_full_kernel() {
        let ctx = swiftshader();
        let limit = ctx.device.limits().max_storage_buffers_per_shader_stage;
        let full = kdray::gpu::bindings::entry_point_bindings(
            kdray::gpu::bindings::UNSPLIT,
            &kdray::gpu::bindings::RENDER_OUTPUTS,
        )
        .iter()
        .filter(|b| b.access != kdray::gpu::bindings::Access::Uniform)
        .count();
        assert!((limit as usize) < full, "{limit} per stage, {full} bound");
        let pipelines = kdray::gpu::TracePipelines::new(ctx, kdray::gpu::bindings::RENDER_TILE)
            .unwrap_or_else(|e| panic!("{e}"));
        assert!(pipelines.binds_only_what_is_read());
    }

    /// Every k-d walk gives brute force's image on every shipped scene, bit for
    /// bit, on SwiftShader as on lavapipe. Scenes of more objects than
    /// tests/gpu/gpu_render.rs sends to brute force are compared walk against walk.
    /// The one kernel that needs more than SwiftShader's 10 storage buffers a
    /// stage (the rope walk's two rope arrays in a scene with spheres,
    /// triangles and textures: 11) is refused in one line naming the limit.
    /// `scene` at 80 pixels wide, its aspect kept: SwiftShader runs every
    /// frame on the CPU, and what this module checks (each variant's
    /// bindings, each walk against brute force) needs every pipeline, not
    /// many pixels; the image tests on lavapipe render 160.
    fn swiftshader_size(mut scene: Scene) -> Scene {
        let aspect = scene.render.height as f64 / scene.render.width as f64;
        scene.render.width = 80;
        scene.render.height = ((80.0 * aspect).round() as u32).max(1);
        scene
    }

    #[test]
    #[ignore = "on SwiftShader: run by every_swiftshader_test_passes_in_a_process_of_its_own"]
    fn kdtree_equals_brute_force_on_every_scene_on_swiftshader() {
        const BRUTE_FORCE_MAX_OBJECTS: usize = 10_000;
        for path in shipped_scenes() {
            let scene = swiftshader_size(small_pair_scene(&path));
            let reference = if scene.object_count() <= BRUTE_FORCE_MAX_OBJECTS {
                render_walk(&scene, Accel::Brute, Traversal::default())
            } else {
                render_walk(&scene, Accel::Kdtree, Traversal::Restart)
            };
            for walk in Traversal::ALL {
                let kd = match try_render_walk(&scene, Accel::Kdtree, walk) {
                    Ok(kd) => kd,
                    Err(e) => {
                        // The rope walk's two rope arrays beside spheres,
                        // triangles and textures (or a sky image, which lives
                        // in the textures buffer), or beside triangles with
                        // vertex normals and a sky image: 11.
                        let textures = !scene.textures.is_empty() || scene.environment.is_some();
                        let too_many = walk == Traversal::Ropes
                            && textures
                            && !scene.triangles.is_empty()
                            && (!scene.spheres.is_empty() || !scene.triangle_normals.is_empty());
                        assert!(
                            too_many && e.contains("max_storage_buffers_per_shader_stage"),
                            "{} ({walk}): {e}",
                            path.display()
                        );
                        continue;
                    }
                };
                let d = compare(&kd.rgb, &reference.rgb, kd.width, kd.height, 0);
                let allowed = common::path_pixels_allowed(&scene);
                assert!(
                    d.pixels_over <= allowed,
                    "{} ({walk}): {d:?}",
                    path.display()
                );
            }
        }
    }

    /// The CLI, pointed at SwiftShader's ICD, lists it as the adapter it uses
    /// and renders the seed with it.
    #[test]
    #[ignore = "on SwiftShader: run by every_swiftshader_test_passes_in_a_process_of_its_own"]
    fn the_cli_renders_on_swiftshader() {
        swiftshader();
        let kdray = env!("CARGO_BIN_EXE_kdray");
        let info = Command::new(kdray)
            .arg("info")
            .envs(ENV)
            .output()
            .expect("kdray runs");
        let listed = String::from_utf8_lossy(&info.stdout);
        assert!(info.status.success(), "{listed}");
        let picked = listed
            .lines()
            .find(|l| l.starts_with('*'))
            .unwrap_or_else(|| panic!("no adapter picked: {listed}"));
        assert!(
            picked.contains("SwiftShader") && picked.contains("Vulkan"),
            "{picked}"
        );
        let out =
            std::env::temp_dir().join(format!("kdray-swiftshader-{}.png", std::process::id()));
        let render = Command::new(kdray)
            .arg("render")
            .arg(repo_path("scenes/seed.toml"))
            .arg("-o")
            .arg(&out)
            .args(["--width", "64", "--height", "36"])
            .envs(ENV)
            .output()
            .expect("kdray runs");
        let _ = std::fs::remove_file(&out);
        assert!(
            render.status.success(),
            "{}",
            String::from_utf8_lossy(&render.stderr)
        );
    }
}
