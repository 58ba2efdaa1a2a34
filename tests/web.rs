//! The web export in a real browser: headless Chromium (WebGPU on
//! SwiftShader) driven by tests/web/drive_page.mjs through npm's
//! playwright-core, the site served by a static server on 127.0.0.1.
//! scripts/test.sh installs Chromium and the npm package (lockfile).
//!
//! Every scene's page image equals the native render within the golden
//! budget; bad, truncated and newer-version bundles show their errors; a
//! drag changes the view and restarts refinement; the overlay names the
//! adapter.

mod common;

use std::net::TcpListener;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};

use common::*;
use kdray::gpu::Accel;
use kdray::output::read_png_rgb;

/// As tests/golden.rs: mean FLIP, and pixels over 2 levels per mille.
const MAX_MEAN_FLIP: f32 = 0.01;
const MAX_PIXELS_OVER_PER_MILLE: usize = 1;

/// A static file server for `root` on a free port, killed (by pid) on drop.
struct Server {
    child: Child,
    port: u16,
}

impl Server {
    fn start(root: &Path) -> Server {
        let port = TcpListener::bind("127.0.0.1:0")
            .unwrap()
            .local_addr()
            .unwrap()
            .port();
        let child = Command::new("python3")
            .args([
                "-m",
                "http.server",
                &port.to_string(),
                "--bind",
                "127.0.0.1",
                "-d",
            ])
            .arg(root)
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("python3 serves the site");
        for _ in 0..100 {
            if std::net::TcpStream::connect(("127.0.0.1", port)).is_ok() {
                return Server { child, port };
            }
            std::thread::sleep(std::time::Duration::from_millis(50));
        }
        panic!("the static server did not start on port {port}");
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn browser_ready() -> PathBuf {
    let driver = repo_path("tests/web");
    assert!(
        Path::new("/usr/bin/chromium").exists() && driver.join("node_modules/playwright-core").exists(),
        "the browser tests need Debian's chromium and tests/web's npm packages: run scripts/test.sh \
         (or apt-get install chromium; npm ci --prefix tests/web)"
    );
    driver
}

/// Runs the driver over `jobs`; its results.
fn drive(jobs: &serde_json::Value, work: &Path) -> Vec<serde_json::Value> {
    let jobs_path = work.join("jobs.json");
    std::fs::write(&jobs_path, jobs.to_string()).unwrap();
    let out = Command::new("node")
        .arg(browser_ready().join("drive_page.mjs"))
        .arg(&jobs_path)
        .output()
        .expect("node runs the driver");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "the driver failed: {}\n{stdout}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_str(stdout.lines().last().unwrap_or("")).unwrap()
}

fn title(r: &serde_json::Value) -> &str {
    r["title"].as_str().unwrap_or("")
}

#[test]
fn pages_trace_every_scene_as_the_native_renderer_does_and_show_their_errors() {
    let out = repo_path("target/web-test");
    let _ = std::fs::remove_dir_all(&out);
    std::fs::create_dir_all(&out).unwrap();
    let mut jobs = Vec::new();
    let mut scenes = Vec::new();
    for path in shipped_scenes() {
        let name = path.file_stem().unwrap().to_string_lossy().into_owned();
        let run = run_kdray(&out, &["web", path.to_str().unwrap(), "-o", &name], &[]);
        assert_eq!(run.code, 0, "{}", run.stderr_text());
        let scene = small_scene(&path);
        let (w, h) = (scene.render.width, scene.render.height);
        jobs.push(serde_json::json!({
            "url": format!("/{name}/index.html?width={w}&height={h}"),
            "png": out.join(format!("{name}.page.png")),
            "drag": if name == "seed" { serde_json::json!(out.join("seed.dragged.png")) } else { serde_json::json!(null) },
            "screenshot": if name == "seed" { serde_json::json!(out.join("page-screenshot.png")) } else { serde_json::json!(null) },
        }));
        scenes.push((name, scene));
    }
    // Broken bundles beside the seed's.
    let good = std::fs::read(out.join("seed/scene.kdray")).unwrap();
    let mut bad_magic = good.clone();
    bad_magic[..4].copy_from_slice(b"JUNK");
    let mut newer = good.clone();
    newer[8..12].copy_from_slice(&(kdray::web::bundle::FORMAT_VERSION + 1).to_le_bytes());
    let broken = [
        ("bad-magic.kdray", bad_magic, "bad magic"),
        (
            "truncated.kdray",
            good[..good.len() - 5].to_vec(),
            "truncated bundle",
        ),
        ("newer.kdray", newer, "is newer than this page reads"),
    ];
    for (file, bytes, _) in &broken {
        std::fs::write(out.join("seed").join(file), bytes).unwrap();
        jobs.push(serde_json::json!({"url": format!("/seed/index.html?bundle={file}"), "png": null, "drag": null, "screenshot": null}));
    }
    let server = Server::start(&out);
    for job in &mut jobs {
        let url = job["url"].as_str().unwrap();
        job["url"] = format!("http://127.0.0.1:{}{url}", server.port).into();
    }
    let results = drive(&serde_json::Value::Array(jobs), &out);
    drop(server);

    let mut failures = Vec::new();
    for ((name, scene), r) in scenes.iter().zip(&results) {
        if !title(r).starts_with("kdray: done") {
            failures.push(format!("{name}: the page ended with {r}"));
            continue;
        }
        let native = render(scene, Accel::Kdtree);
        let (w, h, page) = read_png_rgb(&out.join(format!("{name}.page.png"))).unwrap();
        assert_eq!((w, h), (native.width, native.height), "{name}");
        let d = compare(&native.rgb, &page, w, h, 2);
        let budget = (w * h) as usize * MAX_PIXELS_OVER_PER_MILLE / 1000;
        eprintln!("{name}: page vs native {d:?}");
        if d.mean_flip > MAX_MEAN_FLIP || d.pixels_over > budget {
            failures.push(format!(
                "{name}: page vs native {d:?} (budget FLIP {MAX_MEAN_FLIP}, {budget} pixels)"
            ));
        }
        let overlay = r["overlay"].as_str().unwrap_or("");
        assert!(
            overlay.contains("adapter google swiftshader"),
            "{name}: overlay {overlay}"
        );
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));

    // The drag: the view changed, refinement restarted and finished again.
    let seed = &results[0];
    assert!(scenes[0].0 == "seed" || seed["drag_title"].is_null());
    let seed_index = scenes.iter().position(|(n, _)| n == "seed").unwrap();
    let seed = &results[seed_index];
    let samples = scenes[seed_index].1.render.samples;
    assert!(
        seed["after_drag_sample"].as_u64().unwrap() < samples as u64
            || !seed["after_drag_title"]
                .as_str()
                .unwrap()
                .starts_with("kdray: done"),
        "the drag did not restart refinement: {seed}"
    );
    assert!(
        seed["drag_title"]
            .as_str()
            .unwrap()
            .starts_with("kdray: done"),
        "{seed}"
    );
    let (_, _, before) = read_png_rgb(&out.join("seed.page.png")).unwrap();
    let (_, _, after) = read_png_rgb(&out.join("seed.dragged.png")).unwrap();
    let changed = before
        .chunks(3)
        .zip(after.chunks(3))
        .filter(|(a, b)| a != b)
        .count();
    assert!(
        changed > before.len() / 3 / 10,
        "the drag changed only {changed} pixels"
    );

    // Broken bundles: each shows its own error in the page.
    for ((file, _, expected), r) in broken.iter().zip(&results[scenes.len()..]) {
        assert!(title(r).starts_with("kdray: error"), "{file}: {r}");
        let message = r["message"].as_str().unwrap_or("");
        assert!(message.contains(expected), "{file}: message {message:?}");
    }
}
