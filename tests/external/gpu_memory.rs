//! Out of GPU memory, for real: lavapipe is given a small device memory by
//! tests/common/device_memory_budget.c (an LD_PRELOAD library; see its
//! comment for what it assumes), so that its vkAllocateMemory fails as a
//! real GPU's does when the scene or the image does not fit. kdray must then
//! say so in one line, exit 1, and leave the output file as it was.
//!
//! These tests need lavapipe (they pin the Vulkan llvmpipe adapter) and a C
//! compiler (`cc`, which linking Rust needs anyway).

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

use crate::common;

use common::{repo_path, run_kdray, Run, TempDir};

/// One block of wgpu's device memory under MemoryHints::MemoryUsage: what
/// opening a device and a small render need on lavapipe.
const SMALL_GPU_BYTES: u64 = 4 << 20;

/// The budget library, compiled once per test run.
fn budget_library() -> &'static Path {
    static LIBRARY: OnceLock<PathBuf> = OnceLock::new();
    LIBRARY.get_or_init(|| {
        let source = repo_path("tests/common/device_memory_budget.c");
        let library =
            Path::new(env!("CARGO_TARGET_TMPDIR")).join("libkdray_device_memory_budget.so");
        let status = Command::new("cc")
            .args(["-shared", "-fPIC", "-O2", "-Wall", "-Werror", "-o"])
            .arg(&library)
            .arg(&source)
            .arg("-ldl")
            .status()
            .expect("cannot run cc (a C compiler is needed for the GPU memory tests)");
        assert!(status.success(), "cc failed on {}", source.display());
        library
    })
}

/// Runs `kdray ARGS` in `dir` on lavapipe with `gpu_bytes` of device memory.
fn kdray_with_gpu_memory(dir: &Path, gpu_bytes: u64, args: &[&str]) -> Run {
    let budget = gpu_bytes.to_string();
    run_kdray(
        dir,
        args,
        &[
            ("LD_PRELOAD", budget_library().to_str().unwrap()),
            ("KDRAY_TEST_DEVICE_MEMORY_BYTES", budget.as_str()),
            ("WGPU_BACKEND", "vulkan"),
            ("WGPU_ADAPTER_NAME", "llvmpipe"),
        ],
    )
}

const OLD_OUTPUT: &[u8] = b"the previous render, which a failed run must keep";

/// A folder holding `out.png` with [`OLD_OUTPUT`] in it.
fn folder_with_old_output(tag: &str) -> TempDir {
    let dir = TempDir::new(tag);
    std::fs::write(dir.join("out.png"), OLD_OUTPUT).unwrap();
    dir
}

/// The run failed with one line about GPU memory and exit 1, printed no
/// stats, and left `out.png` and the folder as they were.
fn assert_out_of_gpu_memory(run: &Run, dir: &TempDir, during: &str) -> String {
    assert_eq!(run.code, 1, "{run:#?}");
    let line = run.one_error_line().to_string();
    assert!(line.starts_with("kdray: "), "{line}");
    assert!(line.contains(during), "want {during:?} in: {line}");
    assert!(
        line.to_lowercase().contains("memory"),
        "the line says it is about memory: {line}"
    );
    assert!(run.stdout.is_empty(), "no stats on failure: {run:#?}");
    assert_eq!(std::fs::read(dir.join("out.png")).unwrap(), OLD_OUTPUT);
    assert!(dir.temp_files().is_empty(), "{:?}", dir.temp_files());
    line
}

fn seed_scene() -> String {
    repo_path("scenes/seed.toml").to_str().unwrap().to_string()
}

/// The control: the small budget leaves a small render alone (so the
/// failures below come from what those renders need, not from the library).
#[test]
fn a_small_render_fits_in_a_small_gpu() {
    let dir = TempDir::new("gpu-memory-fits");
    let seed = seed_scene();
    let run = kdray_with_gpu_memory(
        &dir.path,
        SMALL_GPU_BYTES,
        &[
            "render", &seed, "--width", "64", "--height", "36", "-o", "out.png",
        ],
    );
    assert_eq!(run.code, 0, "{run:#?}");
    let (width, height, _) = kdray::output::read_png_rgb(&dir.join("out.png")).unwrap();
    assert_eq!((width, height), (64, 36));
}

#[test]
fn no_memory_for_the_device_is_one_line_and_exit_1() {
    let dir = folder_with_old_output("gpu-memory-none");
    let seed = seed_scene();
    let run = kdray_with_gpu_memory(
        &dir.path,
        0,
        &[
            "render", &seed, "--width", "64", "--height", "36", "-o", "out.png",
        ],
    );
    assert_out_of_gpu_memory(&run, &dir, "cannot open a device");
}

/// A flat grid of `quads` x `quads` squares, two triangles each, as OBJ text.
fn grid_obj(quads: usize) -> String {
    let mut text = String::new();
    for i in 0..=quads {
        for j in 0..=quads {
            text += &format!("v {i} 0 {j}\n");
        }
    }
    let vertex = |i: usize, j: usize| i * (quads + 1) + j + 1;
    for i in 0..quads {
        for j in 0..quads {
            let (a, b) = (vertex(i, j), vertex(i + 1, j));
            let (c, d) = (vertex(i + 1, j + 1), vertex(i, j + 1));
            text += &format!("f {a} {b} {c} {d}\n");
        }
    }
    text
}

#[test]
fn a_scene_too_big_for_the_gpu_is_refused_in_one_line() {
    let dir = folder_with_old_output("gpu-memory-scene");
    // 2 x 200 x 200 = 80,000 triangles at 52 bytes each (48 of vertices, 4 of
    // material index): about 4 MiB of scene, which no longer fits beside
    // what the device itself holds.
    dir.write("grid.obj", &grid_obj(200));
    dir.write(
        "grid.toml",
        "[camera]\nposition = [100, 50, -80]\nlook_at = [100, 0, 100]\n\
         [[lights]]\nposition = [100, 100, 100]\n\
         [materials.grey]\ndiffuse = [0.5, 0.5, 0.5]\n\
         [[meshes]]\npath = \"grid.obj\"\nmaterial = \"grey\"\n",
    );
    let run = kdray_with_gpu_memory(
        &dir.path,
        SMALL_GPU_BYTES,
        &[
            "render",
            "grid.toml",
            "--width",
            "16",
            "--height",
            "16",
            "--accel",
            "brute",
            "-o",
            "out.png",
        ],
    );
    let line = assert_out_of_gpu_memory(&run, &dir, "uploading the scene");
    assert!(line.contains("out of GPU memory"), "{line}");
    // The line says how much the scene needs.
    assert!(line.contains("MiB of GPU memory"), "{line}");
}

#[test]
fn an_image_too_big_for_the_gpu_is_refused_in_one_line() {
    let dir = folder_with_old_output("gpu-memory-image");
    let seed = seed_scene();
    // 1024 x 1024 is one tile: 4 MiB of pixels, twice (output and readback).
    let run = kdray_with_gpu_memory(
        &dir.path,
        SMALL_GPU_BYTES,
        &[
            "render", &seed, "--width", "1024", "--height", "1024", "-o", "out.png",
        ],
    );
    let line = assert_out_of_gpu_memory(&run, &dir, "allocating the output buffers");
    assert!(line.contains("out of GPU memory"), "{line}");
}
