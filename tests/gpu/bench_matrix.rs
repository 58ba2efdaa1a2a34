//! `kdray bench`'s matrix end to end through the binary, at tiny sizes:
//! `--build` and `--traversal` over every build and walk measure each cell
//! once (each k-d cell's image brute force's), `--replot` rewrites the
//! summary and plots byte for byte, the defaults measure the default cell
//! only, and bad values exit 2 naming the valid ones.

use std::path::Path;

use kdray::bench::report::JSON_FILE;
use kdray::bench::summary::SUMMARY_FILE;

use crate::bench::{kdray, read_json};
use crate::common;

use common::TempDir;

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
