//! `kdray bench` and `kdray generate`, end to end through the binary, at
//! tiny sizes: the files are produced and sane (not the timings).

use std::path::Path;

use kdray::bench::csv::{CSV_COLUMNS, CSV_FILE};
use kdray::bench::report::JSON_FILE;
use kdray::bench::summary::SUMMARY_FILE;
use kdray::bench::{output_files, random_scene, RandomSceneSpec, SceneKind, DEFAULT_SEED};
use kdray::output::read_png_rgb;

use crate::common;

use common::{run_kdray, Run, TempDir};

fn kdray(args: &[&str]) -> Run {
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

fn read_json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// The summary and every per-scene plot, by file name.
fn summary_and_plots(out: &Path) -> Vec<(String, Vec<u8>)> {
    let mut files: Vec<(String, Vec<u8>)> = std::fs::read_dir(out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n == SUMMARY_FILE || n.ends_with(".svg"))
        .map(|n| {
            let bytes = std::fs::read(out.join(&n)).unwrap();
            (n, bytes)
        })
        .collect();
    files.sort();
    files
}

/// `--build all --traversal all` on two sizes: every (size, build, walk)
/// cell is measured once, with its tree and walk costs, and renders brute
/// force's image exactly; the summary has a table and a plot per scene,
/// `--replot` rewrites them byte for byte, and an `embree.json` beside the
/// run adds kdray's ratio to Embree.
#[test]
fn bench_matrix_measures_every_build_and_walk() {
    use kdray::choice::Choice;
    use kdray::kdtree::{BuildStrategy, Traversal};

    let dir = TempDir::new("matrix");
    let out = dir.join("out");
    let out_s = out.to_str().unwrap();
    let sizes = [10usize, 60];
    let run = kdray(&[
        "bench",
        "--sizes",
        "10,60",
        "--kind",
        "mixed",
        "--width",
        "24",
        "--height",
        "16",
        "--repeat",
        "1",
        "--build",
        "all",
        "--traversal",
        "all",
        "--out",
        out_s,
    ]);
    assert_eq!(run.code, 0, "{}", run.stderr_text());

    let json = read_json(&out.join(JSON_FILE));
    let runs = json["runs"].as_array().unwrap();
    let cells = BuildStrategy::ALL.len() * Traversal::ALL.len();
    assert_eq!(
        runs.len(),
        sizes.len() * (cells + 1),
        "cells and brute force per size"
    );
    for &n in &sizes {
        let of_n: Vec<&serde_json::Value> = runs.iter().filter(|r| r["n"] == n).collect();
        for build in BuildStrategy::ALL {
            for walk in Traversal::ALL {
                let found: Vec<_> = of_n
                    .iter()
                    .filter(|r| {
                        r["accel"] == "kdtree"
                            && r["build"] == Choice::name(build)
                            && r["traversal"] == walk.name()
                    })
                    .collect();
                assert_eq!(found.len(), 1, "N={n} {build:?} {walk:?}");
                let r = found[0];
                assert_eq!(r["status"], "ok", "{r}");
                assert!(r["gpu_ms"].as_f64().unwrap() > 0.0, "{r}");
                assert!(r["mrays_per_s"].as_f64().unwrap() > 0.0, "{r}");
                assert!(r["kd_nodes"].as_u64().unwrap() >= 1, "{r}");
                assert!(r["kd_refs_per_leaf"].as_f64().unwrap() > 0.0, "{r}");
                // Every ray enters the root: at least one node per ray.
                assert!(r["nodes_visited_per_ray"].as_f64().unwrap() >= 1.0, "{r}");
                assert!(r["leaves_visited_per_ray"].as_f64().unwrap() >= 0.0, "{r}");
                assert!(r["objects_tested_per_ray"].as_f64().unwrap() > 0.0, "{r}");
                assert_eq!(
                    r["pixels_differing_from_brute"], 0,
                    "N={n} {build:?} {walk:?}: {r}"
                );
            }
        }
        // One build per (size, build): its figures are the same for every walk.
        for build in BuildStrategy::ALL {
            let nodes: Vec<_> = of_n
                .iter()
                .filter(|r| r["build"] == Choice::name(build))
                .map(|r| (r["kd_nodes"].clone(), r["build_ms"].clone()))
                .collect();
            assert!(nodes.windows(2).all(|w| w[0] == w[1]), "{nodes:?}");
        }
        let brute: Vec<_> = of_n.iter().filter(|r| r["accel"] == "brute").collect();
        assert_eq!(brute.len(), 1);
        assert_eq!(brute[0]["status"], "ok");
        assert_eq!(brute[0]["pixels_differing_from_kdtree"], 0);
        assert!(brute[0]["build"].is_null() && brute[0]["traversal"].is_null());
        // Brute force tests every object for every ray.
        assert!(brute[0]["objects_tested_per_ray"].as_f64().unwrap() >= n as f64 * 0.99);
    }

    let summary = std::fs::read_to_string(out.join(SUMMARY_FILE)).unwrap();
    for &n in &sizes {
        let plot = kdray::bench::matrix_plot::plot_file("mixed", n);
        assert!(
            summary.contains(&format!("### mixed, N = {n} ")),
            "{summary}"
        );
        assert!(summary.contains(&format!("({plot})")) || summary.contains(&format!("(./{plot})")));
        let svg = std::fs::read_to_string(out.join(&plot)).unwrap();
        assert!(
            svg.starts_with("<svg ") && svg.trim_end().ends_with("</svg>"),
            "{plot}"
        );
        // A bar per run (the background is the one other rect).
        assert_eq!(svg.matches("<rect ").count(), 1 + cells + 1, "{plot}");
        for build in BuildStrategy::ALL {
            for walk in Traversal::ALL {
                let row = format!("| kdtree | {} | {} |", Choice::name(build), walk.name());
                assert_eq!(summary.matches(&row).count(), sizes.len(), "{row}");
                assert!(svg.contains(&format!("{} / {}", Choice::name(build), walk.name())));
            }
        }
    }

    // --replot: the same summary and plots, byte for byte.
    let before = summary_and_plots(&out);
    for (name, _) in &before {
        std::fs::remove_file(out.join(name)).unwrap();
    }
    let replot = kdray(&["bench", "--replot", out_s]);
    assert_eq!(replot.code, 0, "{}", replot.stderr_text());
    let after = summary_and_plots(&out);
    assert_eq!(before.len(), 1 + sizes.len());
    assert_eq!(
        before.iter().map(|f| &f.0).collect::<Vec<_>>(),
        after.iter().map(|f| &f.0).collect::<Vec<_>>()
    );
    for (b, a) in before.iter().zip(&after) {
        assert!(b.1 == a.1, "{} differs after --replot", b.0);
    }

    // Embree's figure (as scripts/peers/bench_embree.py writes it) is
    // merged on --replot: kdray's rays/s over Embree's, per cell.
    let embree_mrays = 2.5;
    let embree = serde_json::json!({
        "date_utc": "1970-01-01T00:00:00Z",
        "scenes": [
            {"scene": "mixed", "n": 60, "primary_rays": 384, "shadow_rays": 100,
             "repeat": 3, "seconds_median": 0.001, "mrays_per_s_median": embree_mrays},
            {"scene": "mixed", "n": 10, "unsupported": "5 spheres: embreex exposes no sphere geometry"}
        ]
    });
    std::fs::write(out.join("embree.json"), embree.to_string()).unwrap();
    let replot = kdray(&["bench", "--replot", out_s]);
    assert_eq!(replot.code, 0, "{}", replot.stderr_text());
    let summary = std::fs::read_to_string(out.join(SUMMARY_FILE)).unwrap();
    let json = read_json(&out.join(JSON_FILE));
    assert_eq!(
        json["embree"]["scenes"][0]["mrays_per_s_median"],
        embree_mrays
    );
    for r in json["runs"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|r| r["n"] == 60)
    {
        let ratio = format!(
            "| {} |",
            kdray::bench::numbers::ratio_text(r["mrays_per_s"].as_f64().unwrap() / embree_mrays)
        );
        let line = summary
            .lines()
            .find(|l| {
                l.starts_with(&format!(
                    "| {} | {} | {} |",
                    r["accel"].as_str().unwrap(),
                    r["build"].as_str().unwrap_or(""),
                    r["traversal"].as_str().unwrap_or("")
                )) && l.contains(&format!("| {:.3} |", r["mrays_per_s"].as_f64().unwrap()))
            })
            .unwrap_or_else(|| panic!("no row for {r}"));
        assert!(line.trim_end().ends_with(&ratio), "{line} vs {ratio}");
    }
    assert!(
        summary.contains("Embree (one thread): n/a (5 spheres"),
        "{summary}"
    );
    let svg = std::fs::read_to_string(out.join(kdray::bench::matrix_plot::plot_file("mixed", 60)))
        .unwrap();
    assert!(svg.contains("Embree 4, one thread"));
}

/// Without --build and --traversal the bench measures the default cell
/// only, as before the matrix.
#[test]
fn bench_defaults_to_the_default_build_and_walk() {
    use kdray::choice::Choice;

    let dir = TempDir::new("default-cell");
    let out = dir.join("out");
    let run = kdray(&[
        "bench",
        "--sizes",
        "5",
        "--width",
        "16",
        "--height",
        "12",
        "--repeat",
        "1",
        "--accel",
        "kdtree",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(run.code, 0, "{}", run.stderr_text());
    let json = read_json(&out.join(JSON_FILE));
    let runs = json["runs"].as_array().unwrap();
    assert_eq!(runs.len(), 1);
    assert_eq!(
        runs[0]["build"],
        Choice::name(kdray::kdtree::BuildStrategy::default())
    );
    assert_eq!(
        runs[0]["traversal"],
        kdray::kdtree::Traversal::default().name()
    );
}

/// Unknown builds and walks exit 2 naming the valid ones; --suite takes no
/// scene files.
#[test]
fn bad_matrix_values_exit_2_naming_the_valid_ones() {
    use kdray::choice::Choice;

    let dir = TempDir::new("matrix-usage");
    let out = dir.join("out");
    let out = out.to_str().unwrap();
    let names = |all: Vec<&'static str>| all;
    for (flag, valid) in [
        (
            "--traversal",
            names(
                kdray::kdtree::Traversal::ALL
                    .iter()
                    .map(|t| t.name())
                    .collect(),
            ),
        ),
        (
            "--build",
            names(
                kdray::kdtree::BuildStrategy::ALL
                    .iter()
                    .map(|b| Choice::name(*b))
                    .collect(),
            ),
        ),
    ] {
        for bad in ["nope", "all,nope"] {
            let run = kdray(&["bench", flag, bad, "--out", out]);
            assert_eq!(run.code, 2, "{flag} {bad}: {}", run.stderr_text());
            let err = run.stderr_text();
            assert!(err.contains("nope"), "{err}");
            for name in valid.iter().chain(&["all"]) {
                assert!(err.contains(name), "{flag}: {name} not named in {err}");
            }
        }
    }
    let seed = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/seed.toml");
    let run = kdray(&[
        "bench",
        "--suite",
        "--scene",
        seed.to_str().unwrap(),
        "--out",
        out,
    ]);
    assert_eq!(run.code, 2, "{}", run.stderr_text());
    assert!(!Path::new(out).join(JSON_FILE).exists(), "nothing measured");
}
