//! `summary.md`, the report as Markdown: the command and the machine, a
//! table per scene (rows build x walk, and brute force, with ratios to
//! brute force and to Embree when measured) and its plot, then the
//! speed-ups and fits along the sizes of a random-scene sweep.

use std::fmt::Write as _;

use super::matrix_plot;
use super::numbers::{count, ms, opt, opt_f, ratio_text};
use super::options::BenchMode;
use super::record::RunRecord;
use super::report::{BenchReport, EmbreeScene};
use crate::choice::Choice;
use crate::gpu::Accel;
use crate::kdtree::{BuildStrategy, Traversal};

pub const SUMMARY_FILE: &str = "summary.md";

/// One scene's section of the summary: what was rendered, Embree's figure,
/// a row per run (build x walk, then brute force) and the scene's plot.
fn scene_table(s: &mut String, report: &BenchReport, scene: &str, n: usize) {
    let runs: Vec<&RunRecord> = report.runs_of(scene, n).collect();
    let Some(first) = runs.first() else {
        return;
    };
    scene_heading(s, scene, n, &runs, first);
    let embree = report.embree_for(scene, n);
    let embree_mrays = embree.and_then(|e| e.mrays_per_s_median);
    if report.embree.is_some() {
        let _ = writeln!(s, "Embree (one thread): {}.  ", embree_line(embree));
    }
    let brute_ms = runs
        .iter()
        .find(|r| r.accel == Accel::Brute && r.is_ok())
        .and_then(|r| r.gpu_ms);
    let _ = writeln!(
        s,
        "\n| accel | build | walk | build ms | nodes | depth | refs/leaf | GPU ms median (min-max) | Mrays/s | nodes/ray | leaves/ray | objects/ray | peak MiB | px differing from brute | vs brute | vs Embree |"
    );
    let _ = writeln!(
        s,
        "|---|---|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|"
    );
    for r in runs {
        let _ = writeln!(s, "{}", run_row(r, brute_ms, embree_mrays));
    }
    let _ = writeln!(
        s,
        "\n![rays per second, {scene}](./{})",
        matrix_plot::plot_file(scene, n)
    );
}

/// The section's heading (scene, N, objects) and what a frame is: image
/// size, samples, depth and the rays of the first run that counted them.
fn scene_heading(s: &mut String, scene: &str, n: usize, runs: &[&RunRecord], first: &RunRecord) {
    let _ = writeln!(
        s,
        "\n### {scene}, N = {} ({} spheres, {} triangles)\n",
        count(n as u64),
        count(first.spheres as u64),
        count(first.triangles as u64)
    );
    let rays = runs.iter().find(|r| r.total_rays.is_some());
    let _ = writeln!(
        s,
        "{}x{}, {} sample(s), max_depth {}{}; rays per frame: {}.  ",
        first.width,
        first.height,
        first.samples,
        first.max_depth,
        if first.max_depth == 1 {
            " (primary + shadow)"
        } else {
            ""
        },
        rays.map_or("-".into(), |r| format!(
            "{} primary, {} shadow, {} reflection",
            count(r.primary_rays.unwrap_or(0)),
            count(r.shadow_rays.unwrap_or(0)),
            count(r.reflection_rays.unwrap_or(0))
        ))
    );
}

/// Embree's figure for the scene: its rate and how it was measured, why
/// it has none, or that it was not measured.
fn embree_line(embree: Option<&EmbreeScene>) -> String {
    match embree {
        None => "not measured".to_string(),
        Some(e) => match (e.mrays_per_s_median, &e.unsupported) {
            (Some(m), _) => format!(
                "{m:.2} M rays/s ({} primary + {} shadow rays, median of {} runs {} ms; BVH build {} ms)",
                count(e.primary_rays.unwrap_or(0)),
                count(e.shadow_rays.unwrap_or(0)),
                opt(e.repeat),
                ms(e.seconds_median.map(|v| v * 1e3)),
                ms(e.build_s.map(|v| v * 1e3))
            ),
            (None, Some(why)) => format!("n/a ({why})"),
            (None, None) => "no figure".into(),
        },
    }
}

/// One run's row of the scene's table: a failed run's status and note in
/// place of its figures; ratios to brute force's GPU time (`brute_ms`)
/// and to Embree's rate (`embree_mrays`) where both are known.
fn run_row(r: &RunRecord, brute_ms: Option<f64>, embree_mrays: Option<f64>) -> String {
    let head = format!(
        "| {} | {} | {} |",
        r.accel.name(),
        r.build.map_or("", BuildStrategy::name),
        r.traversal.map_or("", Traversal::name)
    );
    if !r.is_ok() {
        return format!(
            "{head} {} | {} | {} | {} | **{}**: {} | | | | | | | | |",
            ms(r.build_ms),
            r.kd_nodes.map_or(String::new(), |v| count(v as u64)),
            opt(r.kd_max_depth),
            opt_f(r.kd_refs_per_leaf, 2),
            r.status.name(),
            r.note.as_deref().unwrap_or("")
        );
    }
    let ratio = |num: Option<f64>, den: Option<f64>| match (num, den) {
        (Some(a), Some(b)) if b > 0.0 => ratio_text(a / b),
        _ => "-".into(),
    };
    format!(
        "{head} {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
        ms(r.build_ms),
        r.kd_nodes.map_or("-".into(), |v| count(v as u64)),
        opt(r.kd_max_depth),
        opt_f(r.kd_refs_per_leaf, 2),
        if r.gpu_ms_samples.len() > 1 {
            format!(
                "{} ({}-{})",
                ms(r.gpu_ms),
                ms(r.gpu_ms_min),
                ms(r.gpu_ms_max)
            )
        } else {
            ms(r.gpu_ms)
        },
        opt_f(r.mrays_per_s, 3),
        opt_f(r.nodes_visited_per_ray, 1),
        opt_f(r.leaves_visited_per_ray, 2),
        opt_f(r.objects_tested_per_ray, 1),
        opt_f(r.peak_host_mib, 0),
        match r.accel {
            Accel::Brute => "(reference)".into(),
            Accel::Kdtree => opt(r.pixels_differing_from_brute),
        },
        match r.accel {
            Accel::Brute => "1x".into(),
            Accel::Kdtree => ratio(brute_ms, r.gpu_ms),
        },
        ratio(r.mrays_per_s, embree_mrays),
    )
}

/// The report as Markdown: machine, a table per scene, speed-ups (of the
/// primary cell) and fits.
pub fn markdown_summary(report: &BenchReport) -> String {
    let mut s = String::new();
    let m = &report.machine;
    let _ = writeln!(s, "Command: `{}`  ", report.command);
    let _ = writeln!(s, "Adapter: `{}`  ", m.adapter_line);
    let _ = writeln!(
        s,
        "Host: {} ({} threads), {}, load average {} at start, {} at end; GPU time from {}; date {} (UTC); sweep {:.0} s\n",
        m.host_cpu.as_deref().unwrap_or("unknown CPU"),
        m.host_threads.map_or("?".into(), |t| t.to_string()),
        m.os,
        opt_f(m.load_average_start, 2),
        opt_f(m.load_average_end, 2),
        if m.timestamps { "timestamp queries" } else { "wall clock" },
        report.date_utc,
        report.elapsed_s
    );
    for note in &report.notes {
        let _ = writeln!(s, "{note}  ");
    }
    if let Some(e) = &report.embree {
        let _ = writeln!(
            s,
            "Embree: Embree 4 through embreex{}, one thread (`taskset -c 0`), primary + shadow rays of the same scene files, measured {}{}; uptime before: `{}`, after: `{}`  ",
            e.embreex_version.as_deref().map_or(String::new(), |v| format!(" {v}")),
            e.date_utc.as_deref().unwrap_or("?"),
            e.command.as_deref().map_or(String::new(), |c| format!(" by `{c}`")),
            e.uptime_before.as_deref().unwrap_or("?"),
            e.uptime_after.as_deref().unwrap_or("?"),
        );
    }
    for (scene, n) in report.scenes() {
        scene_table(&mut s, report, &scene, n);
    }
    // Speed-ups where both ran.
    let kd = report.series(Accel::Kdtree);
    let brute = report.series(Accel::Brute);
    let pairs: Vec<_> = kd
        .iter()
        .filter_map(|&(n, k)| brute.iter().find(|b| b.0 == n).map(|&(_, b)| (n, k, b)))
        .collect();
    // Across the suite's scenes (of different kinds and images) a series
    // in N means nothing: each scene's table has its own ratios.
    let series_make_sense = report.config.mode != BenchMode::Suite;
    if series_make_sense && !pairs.is_empty() {
        let cell = match report.primary_cell() {
            (Some(b), Some(t)) => format!(" ({}/{})", b.name(), t.name()),
            _ => String::new(),
        };
        let _ = writeln!(s, "\n| N | k-d tree{cell} ms | brute ms | speed-up |");
        let _ = writeln!(s, "|--:|--:|--:|--:|");
        for (n, k, b) in pairs {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {:.1}x |",
                count(n as u64),
                ms(Some(k)),
                ms(Some(b)),
                b / k
            );
        }
    }
    if series_make_sense && !report.fits.is_empty() {
        let _ = writeln!(
            s,
            "\n| accel | log-log slope (N >= 100) | linear fit: ms = a + b N (relative error) | R^2 |"
        );
        let _ = writeln!(s, "|---|--:|---|--:|");
        for f in &report.fits {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} |",
                f.accel.name(),
                opt_f(f.loglog_slope, 2),
                match (f.linear_intercept_ms, f.linear_per_object_ms) {
                    (Some(a), Some(b)) => format!("{a:.3} + {b:.3e} N"),
                    _ => "-".into(),
                },
                opt_f(f.linear_r2, 4)
            );
        }
    }
    s
}
