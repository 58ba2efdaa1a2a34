//! Shared helpers of kdray's test binaries (tests/gpu/, tests/external/):
//! one device for the whole test binary, rendering scene text or files at a
//! small size, image comparison, running the binary; and, from kdray-core's
//! tests (crates/kdray-core/tests/common/), the repository's paths,
//! temporary folders, the property tests' random scenes ([`strategies`]) and
//! the textured models ([`textured`]). Each binary's main.rs declares it
//! once; its modules `use crate::common;`.
#![allow(dead_code)]

#[path = "../../crates/kdray-core/tests/common/mod.rs"]
mod core_common;

// Each binary uses some of these.
#[allow(unused_imports)]
pub use core_common::{
    masked, proptest_config, repo_path, repo_root, strategies, temp_files_in, textured, TempDir,
};

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

use kdray::gpu::{Accel, GpuContext, RenderedImage, TilePlan};
use kdray::scene::{parse_scene, Scene, SceneFormat};

pub fn gpu() -> &'static GpuContext {
    static CTX: OnceLock<GpuContext> = OnceLock::new();
    CTX.get_or_init(|| {
        GpuContext::new()
            .unwrap_or_else(|e| panic!("GPU tests need an adapter (lavapipe in CI): {e}"))
    })
}

pub fn scene_from_toml(text: &str) -> Scene {
    parse_scene(text, Path::new("inline.toml"), SceneFormat::Toml).unwrap_or_else(|e| panic!("{e}"))
}

pub fn render(scene: &Scene, accel: Accel) -> RenderedImage {
    render_tiled(scene, accel, TilePlan::DEFAULT_MAX_TILE_PIXELS)
}

pub fn render_tiled(scene: &Scene, accel: Accel, max_tile_pixels: u64) -> RenderedImage {
    kdray::render::render_scene(gpu(), scene, accel, max_tile_pixels)
        .unwrap_or_else(|e| panic!("{e}"))
        .0
}

/// One frame of an uploaded scene rendered by two renderers (a specialised
/// one and the general kernel, say), whole, in the default tiles.
pub fn render_pair(
    first: &kdray::gpu::Renderer,
    second: &kdray::gpu::Renderer,
    buffers: &kdray::gpu::SceneBuffers,
    params: kdray::gpu::FrameParams,
) -> (RenderedImage, RenderedImage) {
    let ctx = gpu();
    let plan = TilePlan::new(
        params.width,
        params.height,
        TilePlan::DEFAULT_MAX_TILE_PIXELS,
        kdray::gpu::max_binding_bytes(&ctx.device.limits()),
    );
    let render = |renderer: &kdray::gpu::Renderer| {
        renderer
            .render(ctx, buffers, params, plan)
            .unwrap_or_else(|e| panic!("{e}"))
    };
    (render(first), render(second))
}

pub fn pixel(image: &RenderedImage, row: u32, column: u32) -> [u8; 3] {
    let i = (row as usize * image.width as usize + column as usize) * 3;
    [image.rgb[i], image.rgb[i + 1], image.rgb[i + 2]]
}

/// The spec's 8-bit quantisation of a linear colour.
pub fn quantize(c: [f64; 3]) -> [u8; 3] {
    c.map(|x| (255.0 * x.clamp(0.0, 1.0) + 0.5).floor() as u8)
}

/// A model file opened two ways, each `side` x `side` pixels: as a scene
/// (the file's own camera and lights, where it has them) and as kdray's
/// default view of it (its framing camera and light rig), for a test that
/// states by hand what the file gives.
pub fn model_and_default_view(path: &Path, side: u32) -> (Scene, Scene) {
    let sized = |mut scene: Scene| {
        scene.render.width = side;
        scene.render.height = side;
        scene
    };
    let from_file = kdray::scene::load_scene(path).unwrap_or_else(|e| panic!("{e}"));
    let default_view = kdray::scene::model_scene_viewed(
        path,
        kdray::scene::ModelCamera::Default,
        &mut |_| {},
        &mut |_| {},
    )
    .unwrap_or_else(|e| panic!("{e}"));
    (sized(from_file), sized(default_view))
}

/// Every scene file shipped in scenes/.
pub fn shipped_scenes() -> Vec<PathBuf> {
    let mut scenes: Vec<PathBuf> = std::fs::read_dir(repo_path("scenes"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| {
            matches!(
                p.extension().and_then(|e| e.to_str()),
                Some("toml" | "json")
            )
        })
        .collect();
    scenes.sort();
    assert!(
        scenes.len() >= 6,
        "scenes/ should hold the seed and at least five more"
    );
    scenes
}

/// A shipped scene at test size: 160 pixels wide, the scene's aspect ratio.
pub fn small_scene(path: &Path) -> Scene {
    let mut scene = kdray::scene::load_scene(path).unwrap_or_else(|e| panic!("{e}"));
    let aspect = scene.render.height as f64 / scene.render.width as f64;
    scene.render.width = 160;
    scene.render.height = ((160.0 * aspect).round() as u32).max(1);
    if scene.render.integrator == kdray::scene::Integrator::Path {
        scene.render.samples = scene.render.samples.min(PATH_TEST_SAMPLES);
    }
    scene
}

/// A shipped scene at test size for the tests that render one frame two
/// ways and compare (two walks, two kernel variants, the page and native):
/// [`small_scene`], path-traced scenes at [`PAIR_TEST_SAMPLES`].
pub fn small_pair_scene(path: &Path) -> Scene {
    let mut scene = small_scene(path);
    if scene.render.integrator == kdray::scene::Integrator::Path {
        scene.render.samples = scene.render.samples.min(PAIR_TEST_SAMPLES);
    }
    scene
}

/// Samples per pixel, at most, of a path-traced shipped scene in a paired
/// test: each pixel's paths meet every surface kind the scene has (160x160
/// pixels of the Cornell box are 102,400 paths a walk), and each sample is
/// a pass on lavapipe.
pub const PAIR_TEST_SAMPLES: u32 = 4;

/// Samples per pixel, at most, of a path-traced shipped scene at test size:
/// its images are compared exactly, or with goldens made from the same
/// samples, so noise does not matter, and each sample is a pass on lavapipe.
pub const PATH_TEST_SAMPLES: u32 = 16;

/// How two 8-bit images differ.
#[derive(Debug)]
pub struct Difference {
    /// Pixels whose largest channel difference exceeds `level_tolerance`.
    pub pixels_over: usize,
    pub largest: u8,
    pub mean_flip: f32,
}

pub fn compare(a: &[u8], b: &[u8], width: u32, height: u32, level_tolerance: u8) -> Difference {
    assert_eq!(a.len(), b.len());
    let mut pixels_over = 0;
    let mut largest = 0;
    for (pa, pb) in a.chunks_exact(3).zip(b.chunks_exact(3)) {
        let d = pa
            .iter()
            .zip(pb)
            .map(|(x, y)| x.abs_diff(*y))
            .max()
            .unwrap();
        largest = largest.max(d);
        if d > level_tolerance {
            pixels_over += 1;
        }
    }
    let flip = nv_flip::flip(
        nv_flip::FlipImageRgb8::with_data(width, height, a),
        nv_flip::FlipImageRgb8::with_data(width, height, b),
        nv_flip::DEFAULT_PIXELS_PER_DEGREE,
    );
    let mean_flip = nv_flip::FlipPool::from_image(&flip).mean();
    Difference {
        pixels_over,
        largest,
        mean_flip,
    }
}

/// A difference image: |a - b| per channel, scaled up to be visible.
pub fn difference_image(a: &[u8], b: &[u8]) -> Vec<u8> {
    a.iter()
        .zip(b)
        .map(|(x, y)| x.abs_diff(*y).saturating_mul(8))
        .collect()
}

/// Where failing image tests leave their actual and difference images.
pub fn failure_dir() -> PathBuf {
    let dir = repo_path("target/test-failures");
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// What one run of the `kdray` binary left behind.
#[derive(Debug)]
pub struct Run {
    pub code: i32,
    pub stdout: String,
    /// Lines of stderr, without Mesa's `XDG_RUNTIME_DIR` noise.
    pub stderr: Vec<String>,
}

impl Run {
    /// The single line of stderr, asserting there is exactly one and that
    /// nothing panicked.
    pub fn one_error_line(&self) -> &str {
        assert!(!self.panicked(), "{self:#?}");
        assert_eq!(self.stderr.len(), 1, "want one stderr line: {self:#?}");
        assert!(!self.stderr[0].trim().is_empty(), "{self:#?}");
        &self.stderr[0]
    }

    pub fn panicked(&self) -> bool {
        self.stderr.iter().any(|l| l.contains("panicked"))
    }

    /// All of stderr, for assertion messages.
    pub fn stderr_text(&self) -> String {
        self.stderr.join("\n")
    }
}

/// Runs the built `kdray ARGS` in `dir` with extra environment variables.
/// A run killed by a signal (a crash) fails the test.
pub fn run_kdray(dir: &Path, args: &[&str], env: &[(&str, &str)]) -> Run {
    let out = Command::new(env!("CARGO_BIN_EXE_kdray"))
        .args(args)
        .current_dir(dir)
        .env("XDG_RUNTIME_DIR", std::env::temp_dir())
        .envs(env.iter().copied())
        .output()
        .expect("cannot run kdray");
    let run = Run {
        code: out.status.code().unwrap_or_else(|| {
            panic!(
                "kdray {} was killed by a signal ({:?}); stderr:\n{}",
                args.join(" "),
                out.status,
                String::from_utf8_lossy(&out.stderr)
            )
        }),
        stdout: String::from_utf8(out.stdout).expect("stdout is not UTF-8"),
        stderr: String::from_utf8_lossy(&out.stderr)
            .lines()
            .filter(|l| !l.contains("XDG_RUNTIME_DIR"))
            .map(str::to_string)
            .collect(),
    };
    eprintln!("kdray {}: exit {}", args.join(" "), run.code);
    run
}

/// Pixels two differently compiled kernels (or two adapters: lavapipe and
/// the browser's SwiftShader) may disagree on in a path-traced scene at
/// test size, where the same walk or the same hits meet the same random
/// numbers: none for the Whitted integrator; for the path tracer 2% of the
/// image. A path's choices compare random numbers
/// with probabilities, so a last-bit difference between two compilations
/// of the same arithmetic (llvmpipe fuses multiply-adds by context) can
/// send a path elsewhere: the bunny under the sky at 160x90 and 16 samples
/// differs on 96 - 167 of 14,400 pixels between its walks, and between the
/// specialised and the general kernel of one walk. The Cornell box agrees
/// exactly, and its radiance equals brute force's bit for bit
/// (tests/gpu/path_tracing.rs). The page on SwiftShader differs from
/// lavapipe on 65 of the Cornell box's 25,600 pixels and 17 of the bunny's.
pub fn path_pixels_allowed(scene: &Scene) -> usize {
    match scene.render.integrator {
        kdray::scene::Integrator::Whitted => 0,
        kdray::scene::Integrator::Path => (scene.render.width * scene.render.height) as usize / 50,
    }
}

/// Whether two JSON documents (`kdray inspect`'s, say) agree: the same keys, arrays of the same length,
/// the same strings and whole numbers (kinds, node and object ids), and
/// floats equal within the GPU's rounding (it may fuse a multiply-add or
/// round a division or square root an ulp differently from the CPU).
/// `None`, or where the first difference lies.
pub fn json_disagreement(a: &serde_json::Value, b: &serde_json::Value, at: &str) -> Option<String> {
    match (a, b) {
        (serde_json::Value::Object(x), serde_json::Value::Object(y)) => {
            if x.len() != y.len() {
                return Some(format!("{at}: keys {:?} against {:?}", x.keys(), y.keys()));
            }
            x.iter().find_map(|(k, v)| match y.get(k) {
                Some(w) => json_disagreement(v, w, &format!("{at}.{k}")),
                None => Some(format!("{at}: no {k}")),
            })
        }
        (serde_json::Value::Array(x), serde_json::Value::Array(y)) => {
            if x.len() != y.len() {
                return Some(format!("{at}: {} against {} entries", x.len(), y.len()));
            }
            (x.iter().zip(y).enumerate())
                .find_map(|(i, (v, w))| json_disagreement(v, w, &format!("{at}[{i}]")))
        }
        (serde_json::Value::Number(x), serde_json::Value::Number(y))
            if x.is_f64() || y.is_f64() =>
        {
            let (x, y) = (x.as_f64()?, y.as_f64()?);
            let close = (x - y).abs() <= 1e-5 * x.abs().max(y.abs()).max(1.0);
            (!close).then(|| format!("{at}: {x} against {y}"))
        }
        _ => (a != b).then(|| format!("{at}: {a} against {b}")),
    }
}
