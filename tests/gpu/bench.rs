//! `kdray bench` and `kdray generate`, end to end through the binary, at
//! tiny sizes: the files are produced and sane (not the timings). The
//! matrix of builds and walks is bench_matrix.rs's.

use std::path::Path;

use kdray::bench::csv::{CSV_COLUMNS, CSV_FILE};
use kdray::bench::report::JSON_FILE;
use kdray::bench::summary::SUMMARY_FILE;
use kdray::bench::{output_files, random_scene, RandomSceneSpec, SceneKind, DEFAULT_SEED};
use kdray::output::read_png_rgb;

use crate::common;

use common::{run_kdray, Run, TempDir};

pub(crate) fn kdray(args: &[&str]) -> Run {
    run_kdray(&std::env::temp_dir(), args, &[])
}

fn csv_rows(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header = lines
        .next()
        .unwrap()
        .split(',')
        .map(str::to_string)
        .collect();
    // No field of these runs needs quoting but the note, which is last-but-
    // not-least: split naively and check the count only on rows without one.
    let rows = lines
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect();
    (header, rows)
}

fn column(header: &[String], name: &str) -> usize {
    header
        .iter()
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("no column {name}"))
}

/// Every plot decodes, has the plot size, and is not blank.
fn check_plots(out: &Path) {
    for name in [
        kdray::bench::plots::TIME_PLOT,
        kdray::bench::plots::SPEEDUP_PLOT,
        kdray::bench::plots::BUILD_PLOT,
    ] {
        let (w, h, rgb) = read_png_rgb(&out.join(name)).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(w >= 400 && h >= 300, "{name}: {w}x{h}");
        let non_white = rgb
            .chunks_exact(3)
            .filter(|p| p != &[255, 255, 255])
            .count();
        assert!(
            non_white > (w * h) as usize / 100,
            "{name}: only {non_white} drawn pixels"
        );
        let coloured = rgb
            .chunks_exact(3)
            .filter(|p| p.iter().max().unwrap() - p.iter().min().unwrap() > 80)
            .count();
        assert!(coloured > 100, "{name}: no coloured series drawn");
    }
}

#[test]
fn bench_writes_csv_json_summary_and_plots() {
    let dir = TempDir::new("sweep");
    let out = dir.join("out");
    let out_s = out.to_str().unwrap();
    let run = kdray(&[
        "bench", "--sizes", "1,10,100", "--width", "32", "--height", "24", "--repeat", "1",
        "--out", out_s,
    ]);
    assert_eq!(run.code, 0, "{}", run.stderr_text());
    for f in output_files(&out) {
        assert!(f.is_file(), "missing {}", f.display());
    }
    assert!(
        run.stdout.contains("### spheres, N = 100 "),
        "{}",
        run.stdout
    );

    let (header, rows) = csv_rows(&out.join(CSV_FILE));
    assert_eq!(header, CSV_COLUMNS.map(str::to_string).to_vec());
    assert_eq!(rows.len(), 6, "3 sizes x 2 accelerations");
    let (n, accel, status) = (
        column(&header, "n"),
        column(&header, "accel"),
        column(&header, "status"),
    );
    let (gpu_ms, total_rays, primary) = (
        column(&header, "gpu_ms"),
        column(&header, "total_rays"),
        column(&header, "primary_rays"),
    );
    let (nodes, differ, differ_kd) = (
        column(&header, "kd_nodes"),
        column(&header, "pixels_differing_from_kdtree"),
        column(&header, "pixels_differing_from_brute"),
    );
    for (i, row) in rows.iter().enumerate() {
        assert_eq!(row.len(), header.len(), "row {i}: {row:?}");
        assert_eq!(row[n], ["1", "10", "100"][i / 2]);
        assert_eq!(row[accel], ["kdtree", "brute"][i % 2]);
        assert_eq!(row[status], "ok", "{row:?}");
        let ms: f64 = row[gpu_ms].parse().unwrap();
        assert!(ms > 0.0 && ms.is_finite(), "{row:?}");
        assert_eq!(row[primary], "768", "32 x 24 x 1 sample");
        assert!(row[total_rays].parse::<u64>().unwrap() >= 768);
        if i % 2 == 0 {
            assert!(row[nodes].parse::<u64>().unwrap() >= 1);
            assert_eq!(row[differ_kd], "0", "{row:?}");
        } else {
            // Brute force and the k-d tree render the same image.
            assert_eq!(row[differ], "0", "{row:?}");
        }
    }

    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join(JSON_FILE)).unwrap()).unwrap();
    assert!(json["machine"]["adapter_line"]
        .as_str()
        .is_some_and(|s| !s.is_empty()));
    assert!(json["date_utc"].as_str().is_some_and(|s| s.ends_with('Z')));
    assert!(json["command"].as_str().unwrap().starts_with("kdray bench"));
    let runs = json["runs"].as_array().unwrap();
    assert_eq!(runs.len(), 6);
    for r in runs {
        for key in [
            "n",
            "accel",
            "status",
            "build_ms",
            "kd_nodes",
            "kd_leaves",
            "kd_max_depth",
            "kd_refs_per_leaf",
            "upload_ms",
            "gpu_ms",
            "gpu_ms_samples",
            "primary_rays",
            "shadow_rays",
            "reflection_rays",
            "mrays_per_s",
            "peak_host_mib",
            "loop_limited_pixels",
        ] {
            assert!(r.get(key).is_some(), "run lacks {key}: {r}");
        }
        assert!(r["gpu_ms"].as_f64().unwrap() > 0.0);
        assert_eq!(r["gpu_ms_samples"].as_array().unwrap().len(), 1);
        // Null off llvmpipe; on llvmpipe these tiny scenes stay far below its loop limit.
        assert!(r["loop_limited_pixels"].is_null() || r["loop_limited_pixels"] == 0);
        if cfg!(target_os = "linux") {
            assert!(r["peak_host_mib"].as_f64().unwrap() > 1.0);
        }
    }
    assert_eq!(json["fits"].as_array().unwrap().len(), 2);
    assert!(json["fits"][1]["loglog_slope"].is_f64() || json["fits"][1]["loglog_slope"].is_null());
    assert!(std::fs::read_to_string(out.join(SUMMARY_FILE))
        .unwrap()
        .contains("speed-up"));
    check_plots(&out);
    // Atomic writes leave no temporary files behind.
    let leftovers = common::temp_files_in(&out);
    assert!(leftovers.is_empty(), "{leftovers:?}");
}

#[test]
fn brute_force_over_budget_is_skipped_and_reported() {
    let dir = TempDir::new("budget");
    let out = dir.join("out");
    let run = kdray(&[
        "bench",
        "--sizes",
        "1,30",
        "--kind",
        "mixed",
        "--width",
        "16",
        "--height",
        "12",
        "--repeat",
        "1",
        "--budget-s",
        "0.000001",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(run.code, 0, "{}", run.stderr_text());
    let (header, rows) = csv_rows(&out.join(CSV_FILE));
    let (accel, status) = (column(&header, "accel"), column(&header, "status"));
    let statuses: Vec<(&str, &str)> = rows
        .iter()
        .map(|r| (r[accel].as_str(), r[status].as_str()))
        .collect();
    // N = 1 has no earlier brute-force time to predict from, so it runs (and
    // its warm-up frame, over the budget, is its only sample); N = 30 is skipped.
    assert_eq!(
        statuses,
        [
            ("kdtree", "ok"),
            ("brute", "ok"),
            ("kdtree", "ok"),
            ("brute", "skipped")
        ]
    );
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join(JSON_FILE)).unwrap()).unwrap();
    let skipped = &json["runs"][3];
    assert!(skipped["gpu_ms"].is_null());
    let note = skipped["note"].as_str().unwrap();
    assert!(note.contains("budget"), "{note}");
    assert_eq!(
        json["runs"][1]["gpu_ms_samples"].as_array().unwrap().len(),
        1
    );
    assert!(
        run.stderr_text().contains("skipped"),
        "the skip is reported: {}",
        run.stderr_text()
    );
    check_plots(&out);
}

#[test]
fn generated_scenes_load_back_and_render() {
    let dir = TempDir::new("generate");
    for (kind, file) in [("mixed", "mixed.toml"), ("triangles", "tris.json")] {
        let path = dir.join(file);
        let run = kdray(&[
            "generate",
            "--kind",
            kind,
            "--count",
            "40",
            "--seed",
            "7",
            "-o",
            path.to_str().unwrap(),
        ]);
        assert_eq!(run.code, 0, "{}", run.stderr_text());
        let loaded = kdray::scene::load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
        let kind = if kind == "mixed" {
            SceneKind::Mixed
        } else {
            SceneKind::Triangles
        };
        let expected = random_scene(&RandomSceneSpec {
            seed: 7,
            ..RandomSceneSpec::new(kind, 40)
        });
        assert_eq!(loaded, expected, "{file} reads back as the generated scene");

        let png = dir.join(&format!("{file}.png"));
        let run = kdray(&[
            "render",
            path.to_str().unwrap(),
            "--width",
            "40",
            "--height",
            "30",
            "-o",
            png.to_str().unwrap(),
        ]);
        assert_eq!(run.code, 0, "{}", run.stderr_text());
        let (w, h, rgb) = read_png_rgb(&png).unwrap();
        assert_eq!((w, h), (40, 30));
        let background = [rgb[0], rgb[1], rgb[2]];
        assert!(
            rgb.chunks_exact(3).any(|p| p != background),
            "{file}: the objects are in view"
        );
    }
    // The default seed is the bench's.
    let path = dir.join("default.toml");
    assert_eq!(
        kdray(&["generate", "--count", "5", "-o", path.to_str().unwrap()]).code,
        0
    );
    assert_eq!(
        kdray::scene::load_scene(&path).unwrap(),
        random_scene(&RandomSceneSpec::new(SceneKind::Spheres, 5))
    );
    assert_eq!(
        DEFAULT_SEED,
        RandomSceneSpec::new(SceneKind::Spheres, 5).seed
    );
}

/// From 100,000 objects a TOML scene is slow and big to load: generate
/// says so and names JSON; not for JSON, and not below the threshold.
#[test]
fn generate_suggests_json_for_big_toml_scenes() {
    let dir = TempDir::new("generate-big");
    let note = |name: &str, count: &str| {
        let path = dir.join(name);
        let run = kdray(&["generate", "--count", count, "-o", path.to_str().unwrap()]);
        assert_eq!(run.code, 0, "{}", run.stderr_text());
        run.stderr_text()
            .contains("a name ending in .json writes JSON")
    };
    assert!(note("big.toml", "100000"));
    assert!(!note("big.json", "100000"));
    assert!(!note("small.toml", "99999"));
}

#[test]
fn bench_measures_scene_files() {
    let dir = TempDir::new("scenes");
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/seed.toml");
    let out = dir.join("out");
    let run = kdray(&[
        "bench",
        "--scene",
        scene.to_str().unwrap(),
        "--width",
        "24",
        "--height",
        "16",
        "--max-depth",
        "1",
        "--repeat",
        "2",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(run.code, 0, "{}", run.stderr_text());
    let (header, rows) = csv_rows(&out.join(CSV_FILE));
    assert_eq!(rows.len(), 2);
    let (scene_col, n, depth, refl) = (
        column(&header, "scene"),
        column(&header, "n"),
        column(&header, "max_depth"),
        column(&header, "reflection_rays"),
    );
    for row in &rows {
        assert_eq!(row[scene_col], "seed.toml");
        assert_eq!(row[n], "4");
        assert_eq!(row[depth], "1");
        assert_eq!(row[refl], "0", "max depth 1: no reflection rays");
    }
    check_plots(&out);
}

/// `--wavefront-bound`: every walk's path-traced frame and queue, with
/// their rays counted as made: at max_depth 1 the queue is one camera ray
/// a pixel and a shadow ray per camera ray that hit the box (most, not the
/// ones past its open front), and the frame traces those and more (its
/// BSDF-sampled rays toward the light, for MIS).
#[test]
fn wavefront_bound_measures_the_loop_and_the_queue_with_every_walk() {
    let dir = TempDir::new("wavefront");
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/cornell_box.toml");
    let out = dir.join("out");
    let run = kdray(&[
        "bench",
        "--wavefront-bound",
        "--scene",
        scene.to_str().unwrap(),
        "--width",
        "16",
        "--height",
        "12",
        "--max-depth",
        "1",
        "--repeat",
        "1",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(run.code, 0, "{}", run.stderr_text());
    let report = read_json(&out.join("wavefront-bound.json"));
    let walks = report["scenes"][0]["walks"].as_array().unwrap();
    let names: Vec<&str> = walks
        .iter()
        .map(|w| w["traversal"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["restart", "ropes", "short-stack"]);
    let pixels = 16 * 12;
    for w in walks {
        let n = |key: &str| w[key].as_u64().unwrap();
        let shadow = n("queue_shadow_rays");
        assert!(shadow > pixels / 2 && shadow < pixels, "{w}");
        assert_eq!(n("queue_rays"), pixels + shadow, "{w}");
        assert!(n("megakernel_rays") > pixels + shadow, "{w}");
        for key in ["megakernel_ms", "queue_ms", "ratio"] {
            assert!(w[key].as_f64().unwrap() > 0.0, "{key}: {w}");
        }
    }
    assert!(
        run.stdout.contains("cornell_box.toml | restart"),
        "{}",
        run.stdout
    );
}

#[test]
fn bad_arguments_exit_2() {
    let dir = TempDir::new("usage");
    let out = dir.join("out");
    let out = out.to_str().unwrap();
    for args in [
        &["bench", "--sizes", "0,10", "--out", out][..],
        &["bench", "--repeat", "0", "--out", out],
        &["bench", "--width", "0", "--out", out],
        &["bench", "--budget-s=-1", "--out", out],
        &["bench", "--max-depth", "65", "--out", out],
        &["generate", "--count", "0", "-o", out],
    ] {
        let run = kdray(args);
        assert_eq!(run.code, 2, "{args:?}: {}", run.stderr_text());
        assert!(
            run.stderr_text().starts_with("kdray: "),
            "{args:?}: {}",
            run.stderr_text()
        );
    }
    let run = kdray(&["bench", "--scene", "no/such/scene.toml", "--out", out]);
    assert_eq!(run.code, 2, "{}", run.stderr_text());
    assert!(
        run.stderr_text().contains("no/such/scene.toml"),
        "{}",
        run.stderr_text()
    );
}

pub(crate) fn read_json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}
