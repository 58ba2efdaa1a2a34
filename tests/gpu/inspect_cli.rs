//! `kdray inspect` end to end: one JSON document on stdout in the format
//! docs/inspect.md gives, and bad input (pixel, scene, frame, integrator)
//! refused with exit code 2 and one line naming the problem.

use crate::common;

use common::{run_kdray, Run, TempDir};

fn scene_path(name: &str) -> String {
    format!("{}/scenes/{name}", env!("CARGO_MANIFEST_DIR"))
}

fn inspect(dir: &TempDir, scene: &str, extra: &[&str]) -> Run {
    let mut args = vec!["inspect", scene, "--width", "64", "--height", "36"];
    args.extend(extra);
    run_kdray(&dir.path, &args, &[])
}

fn parse(run: &Run) -> serde_json::Value {
    assert_eq!(run.code, 0, "{run:#?}");
    assert_eq!(run.stdout.lines().count(), 1, "stdout: {:?}", run.stdout);
    serde_json::from_str(run.stdout.trim_end()).expect("stdout is not JSON")
}

#[test]
fn inspect_prints_one_json_document_of_the_pixels_rays_and_walks() {
    let dir = TempDir::new("inspect");
    let mirrors = scene_path("mirrors.toml");
    for traversal in ["restart", "ropes", "short-stack"] {
        let run = inspect(
            &dir,
            &mirrors,
            &["--pixel", "32,18", "--traversal", traversal],
        );
        let doc = parse(&run);
        assert_eq!(doc["version"], 1, "{doc}");
        assert_eq!(doc["pixel"], serde_json::json!([32, 18]), "{doc}");
        assert_eq!(doc["traversal"], traversal, "{doc}");
        assert_eq!(doc["walk_source"], "cpu mirror", "{doc}");
        let rays = doc["rays"].as_array().expect("rays is an array");
        assert_eq!(rays[0]["kind"], "primary", "{doc}");
        let primary = &rays[0];
        for key in ["origin", "direction", "t_interval", "walk", "hit", "counts"] {
            assert!(primary.get(key).is_some(), "no {key} in {primary}");
        }
        // The centre of the mirrors scene hits something, and its walk
        // starts at the root.
        assert!(primary["hit"]["object"].is_u64(), "{primary}");
        assert_eq!(primary["walk"][0]["node"], 0, "{primary}");
        let leaves = primary["walk"]
            .as_array()
            .expect("walk is an array")
            .iter()
            .filter(|s| s.get("leaf").is_some())
            .count() as u64;
        assert_eq!(
            Some(leaves),
            primary["counts"]["leaves"].as_u64(),
            "{primary}"
        );
        assert!(
            rays.iter().any(|r| r["kind"] == "shadow"),
            "a lit hit sends shadow rays: {doc}"
        );
    }
}

#[test]
fn inspect_refuses_bad_input_with_exit_2_and_one_line() {
    let dir = TempDir::new("inspect-bad");
    let seed = scene_path("seed.toml");
    let missing = scene_path("no_such_scene.toml");
    let broken = dir.path.join("broken.toml");
    std::fs::write(&broken, "[camera]\nposition = [0.0, 0.0\n").expect("write the scene");
    let broken = broken.to_string_lossy().into_owned();
    let cases: [(&str, &[&str], &str); 7] = [
        (&seed, &["--pixel", "64,0"], "--pixel"),
        (&seed, &["--pixel", "0,36"], "--pixel"),
        (&seed, &["--pixel", "3;4"], "--pixel"),
        (&seed, &["--pixel", "-1,2"], "--pixel"),
        (&missing, &["--pixel", "1,1"], "no_such_scene.toml"),
        (&broken, &["--pixel", "1,1"], "broken.toml"),
        (&seed, &["--pixel", "1,1", "--frame", "1"], "--frame"),
    ];
    for (scene, extra, named) in cases {
        let run = inspect(&dir, scene, extra);
        assert_eq!(run.code, 2, "{extra:?}: {run:#?}");
        let line = run.one_error_line();
        assert!(line.contains(named), "{extra:?}: {line}");
        assert!(run.stdout.is_empty(), "{extra:?}: {run:#?}");
    }
    let run = inspect(&dir, &seed, &["--pixel", "1,1", "--integrator", "path"]);
    assert_eq!(run.code, 2, "{run:#?}");
    assert!(run.one_error_line().contains("Whitted"), "{run:#?}");
}
