//! `kdray web SCENE -o DIR` without a browser: the folder rules, scene
//! errors as `render`'s, and the bundle and contract it writes.

use crate::common;

use common::*;
use kdray::web::bundle;

#[test]
fn an_existing_folder_that_is_not_a_site_is_refused_untouched() {
    let dir = TempDir::new("web-refuse");
    dir.write("mine/notes.txt", "keep me");
    let seed = repo_path("scenes/seed.toml");
    let run = run_kdray(
        &dir.path,
        &["web", seed.to_str().unwrap(), "-o", "mine"],
        &[],
    );
    assert_eq!(run.code, 2, "{}", run.stderr_text());
    assert!(
        run.one_error_line().contains("is not a kdray site"),
        "{run:?}"
    );
    let names: Vec<_> = std::fs::read_dir(dir.join("mine"))
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names, ["notes.txt"], "nothing written");
    dir.write("file", "x");
    let run = run_kdray(
        &dir.path,
        &["web", seed.to_str().unwrap(), "-o", "file"],
        &[],
    );
    assert_eq!(run.code, 2);
    assert_eq!(std::fs::read_to_string(dir.join("file")).unwrap(), "x");
}

#[test]
fn a_site_is_written_and_written_again() {
    let dir = TempDir::new("web-site");
    let seed = repo_path("scenes/seed.toml");
    for _ in 0..2 {
        let run = run_kdray(
            &dir.path,
            &["web", seed.to_str().unwrap(), "-o", "site"],
            &[],
        );
        assert_eq!(run.code, 0, "{}", run.stderr_text());
    }
    let site = dir.join("site");
    for (name, _) in kdray::web::site::PAGE_FILES {
        assert!(site.join(name).is_file(), "{name}");
    }
    let kernel = std::fs::read_to_string(site.join("kernel.wgsl")).unwrap();
    assert_eq!(
        kernel,
        kdray::gpu::shaders::trace_source(kdray::gpu::bindings::UNSPLIT)
    );
    let leftovers: Vec<_> = std::fs::read_dir(&site)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.contains(".tmp"))
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");
    // The bundle: its sections are the contract's, the arrays as prepared.
    let bytes = std::fs::read(site.join("scene.kdray")).unwrap();
    let sections = bundle::read_sections(&bytes).unwrap();
    let contract: serde_json::Value =
        serde_json::from_slice(&std::fs::read(site.join("contract.json")).unwrap()).unwrap();
    let mut expected = vec!["scene".to_string(), "frame_params".to_string()];
    expected.extend(
        contract["bundle"]["scene_arrays"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_str().unwrap().to_string()),
    );
    let names: Vec<String> = sections.iter().map(|(n, _)| n.clone()).collect();
    assert_eq!(names, expected);
    let scene = kdray::scene::load_scene(&seed).unwrap();
    let prepared = kdray::gpu::PreparedScene::new(scene, Accel::Kdtree);
    for ((name, got), (want_name, want)) in
        sections[2..].iter().zip(prepared.arrays.whole_buffers())
    {
        assert_eq!(name, want_name);
        assert_eq!(*got, want, "{name}");
    }
    assert_eq!(
        sections[1].1.len() as u64,
        contract["frame_params"]["size"].as_u64().unwrap()
    );
}

use kdray::gpu::Accel;

#[test]
fn bad_scenes_exit_2_with_renders_error() {
    let dir = TempDir::new("web-bad");
    dir.write("bad.toml", "[camera]\nposition = [0, 0, 1]\n");
    let web = run_kdray(&dir.path, &["web", "bad.toml", "-o", "site"], &[]);
    let render = run_kdray(&dir.path, &["render", "bad.toml", "-o", "x.png"], &[]);
    assert_eq!(web.code, 2);
    assert_eq!(web.one_error_line(), render.one_error_line());
    assert!(!dir.join("site").exists(), "nothing written");
}
