//! GPU faults become one clear error (exit code 1), never a panic or a hang;
//! renders are deterministic; the Vulkan and GL backends agree.

use crate::common;

use common::*;
use kdray::gpu::{Accel, GpuContext, TilePlan};
use kdray::Error;

fn assert_one_line_gpu_error(result: Result<impl Sized, Error>, what: &str) {
    match result {
        Err(e @ Error::Gpu(_)) => {
            let message = e.to_string();
            assert_eq!(message.lines().count(), 1, "{what}: {message}");
            assert_eq!(e.exit_code(), 1);
        }
        Err(other) => panic!("{what}: expected a GPU error, got {other:?}"),
        Ok(_) => panic!("{what}: expected a GPU error"),
    }
}

#[test]
fn a_validation_error_becomes_one_error_line() {
    let ctx = gpu();
    // MAP_READ may not be combined with STORAGE: a validation error.
    let result = ctx.checked("creating a bad buffer", |device| {
        device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("bad"),
            size: 64,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::STORAGE,
            mapped_at_creation: false,
        })
    });
    assert_one_line_gpu_error(result, "bad buffer usage");
    // The shared device is still usable afterwards.
    let scene = small_scene(&repo_path("scenes/seed.toml"));
    render(&scene, Accel::Kdtree);
}

#[test]
fn a_lost_device_becomes_one_error_line() {
    let ctx = GpuContext::new().expect("adapter");
    let scene = small_scene(&repo_path("scenes/mixed.toml"));
    ctx.device.destroy();
    let result = kdray::render::render_scene(
        &ctx,
        &scene,
        Accel::Kdtree,
        TilePlan::DEFAULT_MAX_TILE_PIXELS,
    );
    assert_one_line_gpu_error(result, "render on a destroyed device");
}

#[test]
fn the_same_render_twice_is_identical() {
    let scene = small_scene(&repo_path("scenes/lights.json"));
    let a = render(&scene, Accel::Kdtree);
    let b = render(&scene, Accel::Kdtree);
    assert_eq!(a.rgb, b.rgb);
    assert_eq!(a.rays, b.rays);
}

/// The same command twice gives byte-identical PNG files.
#[test]
fn the_same_command_twice_writes_identical_files() {
    let dir = std::env::temp_dir().join(format!("kdray-determinism-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let run = |name: &str| {
        let out = dir.join(name);
        let status = std::process::Command::new(env!("CARGO_BIN_EXE_kdray"))
            .args(["render", "--width", "96", "--height", "54", "-o"])
            .arg(&out)
            .arg(repo_path("scenes/seed.toml"))
            .status()
            .unwrap();
        assert!(status.success());
        std::fs::read(out).unwrap()
    };
    let (a, b) = (run("a.png"), run("b.png"));
    std::fs::remove_dir_all(&dir).unwrap();
    assert!(a == b, "two runs of the same command wrote different files");
}

/// Vulkan (lavapipe) and GL (llvmpipe over EGL) agree within the golden
/// budget. CI installs both; elsewhere a missing backend fails the test with
/// the reason.
#[test]
fn vulkan_and_gl_agree() {
    let dir = std::env::temp_dir().join(format!("kdray-backends-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let render_with = |backend: &str| {
        let out = dir.join(format!("{backend}.png"));
        let result = std::process::Command::new(env!("CARGO_BIN_EXE_kdray"))
            .env("WGPU_BACKEND", backend)
            .args(["render", "--width", "120", "--height", "90", "-o"])
            .arg(&out)
            .arg(repo_path("scenes/mixed.toml"))
            .output()
            .unwrap();
        assert!(
            result.status.success(),
            "{backend}: {}",
            String::from_utf8_lossy(&result.stderr)
        );
        kdray::output::read_png_rgb(&out).unwrap()
    };
    let (w, h, vulkan) = render_with("vulkan");
    let (_, _, gl) = render_with("gl");
    std::fs::remove_dir_all(&dir).unwrap();
    let d = compare(&vulkan, &gl, w, h, 2);
    assert!(
        d.mean_flip <= 0.01 && d.pixels_over <= (w * h) as usize / 1000,
        "Vulkan and GL differ: {d:?}"
    );
}
