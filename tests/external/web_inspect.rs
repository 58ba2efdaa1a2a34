//! The page's `window.kdray.inspect(x, y)` in headless Chromium (WebGPU on
//! SwiftShader) against `kdray inspect` on lavapipe: for pixels of a
//! Whitted scene with each walk, a glass scene and a path-traced one, the
//! page's document is the command line's (the same rays, steps, ids and
//! hits; floats within the GPU's rounding), the scene's file name aside;
//! a pixel outside the image is refused with a sentence.

use crate::common;
use crate::web::{drive, export, title, Server};

use common::*;

/// (scene, the page's URL parameters and `kdray inspect`'s flags, pixels)
const CASES: [(&str, &str, &[(u32, u32)]); 4] = [
    ("seed", "traversal=restart", &[(32, 18), (5, 30)]),
    ("mirrors", "traversal=ropes", &[(32, 18), (50, 9)]),
    ("glass", "traversal=short-stack", &[(32, 18)]),
    (
        "cornell_box",
        "traversal=short-stack&integrator=path&samples=4",
        &[(32, 20), (10, 30)],
    ),
];
const WIDTH: u32 = 64;
const HEIGHT: u32 = 36;

/// `kdray inspect`'s flags for the page's URL parameters.
fn flags(params: &str) -> Vec<String> {
    let mut out = vec![
        "--width".into(),
        WIDTH.to_string(),
        "--height".into(),
        HEIGHT.to_string(),
    ];
    for pair in params.split('&') {
        let (key, value) = pair.split_once('=').expect("key=value");
        out.extend([format!("--{key}"), value.to_string()]);
    }
    out
}

#[test]
fn the_pages_inspect_returns_the_command_lines_document() {
    let out = repo_path("target/web-test-inspect");
    let _ = std::fs::remove_dir_all(&out);
    std::fs::create_dir_all(&out).unwrap();
    for (name, ..) in CASES {
        export(&out, &format!("scenes/{name}.toml"), name);
    }
    let server = Server::start(&out);
    let jobs: Vec<serde_json::Value> = CASES
        .iter()
        .map(|(name, params, pixels)| {
            serde_json::json!({
                "url": format!(
                    "http://127.0.0.1:{}/{name}/index.html?width={WIDTH}&height={HEIGHT}&{params}",
                    server.port
                ),
                "inspect": pixels.iter().map(|&(x, y)| [x, y]).collect::<Vec<_>>(),
            })
        })
        .collect();
    let results = drive(&serde_json::Value::Array(jobs), &out);
    drop(server);
    let mut rays = 0;
    for ((name, params, pixels), r) in CASES.iter().zip(&results) {
        assert!(
            title(r).starts_with("kdray: done") && r["failure"].is_null(),
            "{name}: {r}"
        );
        let outside = r["inspect_outside"].as_str().unwrap_or("");
        assert!(outside.contains("outside"), "{name}: {outside:?}");
        let scene = repo_path(&format!("scenes/{name}.toml"));
        for (&(x, y), page) in pixels
            .iter()
            .zip(r["inspections"].as_array().expect("inspections"))
        {
            let what = format!("{name} pixel {x},{y}");
            let mut args = vec![
                "inspect".to_string(),
                scene.to_string_lossy().into_owned(),
                "--pixel".into(),
                format!("{x},{y}"),
            ];
            args.extend(flags(params));
            let args: Vec<&str> = args.iter().map(String::as_str).collect();
            let run = run_kdray(&out, &args, &[]);
            assert_eq!(run.code, 0, "{what}: {}", run.stderr_text());
            let mut cli: serde_json::Value =
                serde_json::from_str(run.stdout.trim_end()).expect("the command line prints JSON");
            assert_eq!(page["scene"], format!("{name}.toml"), "{what}");
            cli["scene"] = page["scene"].clone();
            if let Some(d) = json_disagreement(page, &cli, &what) {
                panic!("the page's inspect and the command line's differ: {d}");
            }
            rays += cli["rays"].as_array().map_or(0, Vec::len);
        }
    }
    assert!(rays >= 14, "only {rays} rays compared");
}
