//! The pipeline cache kept between processes (src/gpu/pipeline_cache.rs):
//! `kdray render` on a Vulkan adapter saves it to its file, a second run
//! reads it and renders the same image, a damaged file is replaced and
//! changes nothing, and `KDRAY_PIPELINE_CACHE=off` keeps no file.

use std::path::Path;

use crate::common;

use common::{run_kdray, TempDir};

fn render(dir: &Path, out: &str, env: &[(&str, &str)]) -> Vec<u8> {
    let scene = format!("{}/scenes/seed.toml", env!("CARGO_MANIFEST_DIR"));
    let run = run_kdray(
        dir,
        &[
            "render", &scene, "--width", "16", "--height", "9", "-o", out,
        ],
        env,
    );
    assert_eq!(run.code, 0, "{run:#?}");
    std::fs::read(dir.join(out)).expect("the PNG")
}

/// The files of `folder` (none if it does not exist).
fn files(folder: &Path) -> Vec<std::path::PathBuf> {
    match std::fs::read_dir(folder) {
        Ok(entries) => entries.map(|e| e.unwrap().path()).collect(),
        Err(_) => Vec::new(),
    }
}

#[test]
fn a_vulkan_adapter_keeps_its_pipeline_cache_in_one_file_that_changes_no_pixel() {
    let ctx = common::gpu();
    assert_eq!(
        ctx.info.backend,
        wgpu::Backend::Vulkan,
        "the GPU tier runs on a Vulkan adapter (lavapipe)"
    );
    let dir = TempDir::new("pipeline-cache");
    let folder = dir.path.join("cache");
    let folder_text = folder.to_str().unwrap();
    let env = [("KDRAY_PIPELINE_CACHE", folder_text)];

    let first = render(&dir.path, "first.png", &env);
    let kept = files(&folder);
    assert_eq!(kept.len(), 1, "one cache file: {kept:?}");
    let name = kept[0].file_name().unwrap().to_string_lossy().into_owned();
    assert!(name.starts_with("wgpu_pipeline_cache_vulkan_"), "{name}");
    let saved = std::fs::read(&kept[0]).unwrap();
    assert!(!saved.is_empty());

    // Read back: the same image, the same one file.
    assert_eq!(render(&dir.path, "second.png", &env), first);
    assert_eq!(files(&folder), kept);

    // A damaged file is no cache: the render is the same and the file is
    // written whole again.
    std::fs::write(&kept[0], b"not a pipeline cache").unwrap();
    assert_eq!(render(&dir.path, "third.png", &env), first);
    assert_eq!(std::fs::read(&kept[0]).unwrap(), saved);
}

#[test]
fn pipeline_cache_off_writes_no_file() {
    let dir = TempDir::new("pipeline-cache-off");
    let xdg = dir.path.join("xdg");
    let xdg_text = xdg.to_str().unwrap();
    render(
        &dir.path,
        "off.png",
        &[
            ("KDRAY_PIPELINE_CACHE", "off"),
            ("XDG_CACHE_HOME", xdg_text),
        ],
    );
    // (Mesa keeps its own shader cache there too.)
    assert!(!xdg.join("kdray").exists(), "{:?}", files(&xdg));
    // Without the variable the cache goes under XDG_CACHE_HOME.
    render(
        &dir.path,
        "on.png",
        &[("KDRAY_PIPELINE_CACHE", ""), ("XDG_CACHE_HOME", xdg_text)],
    );
    assert_eq!(files(&xdg.join("kdray")).len(), 1);
}
