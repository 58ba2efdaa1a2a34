//! `kdray inspect` end to end: one JSON document on stdout in the format
//! docs/inspect.md gives, from the kernel (either integrator) or the CPU
//! mirror, and bad input (pixel, scene, frame, walk source) refused with
//! exit code 2 and one line naming the problem.

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
    let walks = ["restart", "ropes", "short-stack"];
    let sources = [
        (None, "kernel"),
        (Some("cpu"), "cpu"),
        (Some("kernel"), "kernel"),
    ];
    for (traversal, (flag, source)) in walks.into_iter().flat_map(|w| sources.map(|s| (w, s))) {
        let mut args = vec!["--pixel", "32,18", "--traversal", traversal];
        if let Some(flag) = flag {
            args.extend(["--walk-source", flag]);
        }
        let doc = parse(&inspect(&dir, &mirrors, &args));
        assert_eq!(doc["version"], 1, "{doc}");
        assert_eq!(doc["pixel"], serde_json::json!([32, 18]), "{doc}");
        assert_eq!(doc["traversal"], traversal, "{doc}");
        assert_eq!(doc["integrator"], "whitted", "{doc}");
        assert_eq!(doc["walk_source"], source, "{doc}");
        assert_eq!(doc.get("sample").is_some(), source == "kernel", "{doc}");
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
        // The mirrors scene's one light: every shadow ray names it, with
        // probability 1 (Whitted lights every light) and no density.
        for r in rays {
            let light = serde_json::json!({
                "source": "light", "index": 0, "kind": "point", "pick": 1.0, "pdf": null
            });
            match r["kind"] == "shadow" {
                true => assert_eq!(r["light"], light, "{r}"),
                false => assert!(r.get("light").is_none(), "{r}"),
            }
        }
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
    let cpu_path = [
        "--pixel",
        "1,1",
        "--integrator",
        "path",
        "--walk-source",
        "cpu",
    ];
    let run = inspect(&dir, &seed, &cpu_path);
    assert_eq!(run.code, 2, "{run:#?}");
    assert!(run.one_error_line().contains("Whitted"), "{run:#?}");
    let run = inspect(&dir, &seed, &["--pixel", "1,1", "--walk-source", "gpu"]);
    assert_eq!(run.code, 2, "{run:#?}");
    assert!(run.one_error_line().contains("--walk-source"), "{run:#?}");
}

/// The kernel inspects a path-traced pixel: the camera ray, then bounces
/// and shadow rays of next-event estimation, with the sample's radiance.
/// The Cornell box's light is two emissive triangles of equal power after
/// two spheres: each shadow ray aims at one of them (object 2 or 3,
/// triangle 0 or 1) picked with probability 1/2, and its direction has a
/// density.
#[test]
fn inspect_follows_a_path_traced_pixels_bounces() {
    let dir = TempDir::new("inspect-path");
    let cornell = scene_path("cornell_box.toml");
    let doc = parse(&inspect(
        &dir,
        &cornell,
        &["--pixel", "32,20", "--seed", "3"],
    ));
    assert_eq!(doc["integrator"], "path", "{doc}");
    assert_eq!(doc["walk_source"], "kernel", "{doc}");
    let kinds: Vec<&str> = doc["rays"]
        .as_array()
        .expect("rays is an array")
        .iter()
        .filter_map(|r| r["kind"].as_str())
        .collect();
    assert_eq!(kinds.first(), Some(&"primary"), "{doc}");
    assert!(kinds.contains(&"bounce"), "{kinds:?}");
    assert!(kinds.contains(&"shadow"), "{kinds:?}");
    assert!(
        kinds
            .iter()
            .all(|k| ["primary", "bounce", "shadow"].contains(k)),
        "{kinds:?}"
    );
    let sample = doc["sample"].as_array().expect("the sample's radiance");
    assert_eq!(sample.len(), 3, "{doc}");
    for r in doc["rays"].as_array().expect("rays").iter() {
        if r["kind"] != "shadow" {
            assert!(r.get("light").is_none(), "{r}");
            continue;
        }
        let light = &r["light"];
        assert_eq!(
            (&light["source"], &light["kind"], &light["pick"]),
            (
                &serde_json::json!("emitter"),
                &serde_json::json!("triangle"),
                &serde_json::json!(0.5)
            ),
            "{r}"
        );
        let object = light["object"].as_u64().expect("the emitter's object");
        assert!(object == 2 || object == 3, "{r}");
        assert_eq!(light["triangle"].as_u64(), Some(object - 2), "{r}");
        assert!(light["pdf"].as_f64().is_some_and(|p| p > 0.0), "{r}");
    }
}
