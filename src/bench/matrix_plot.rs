//! A plot per scene of the matrix (`matrix-<scene>-<N>.svg`): one bar per
//! run (build x walk, brute force) and Embree's when measured, the length
//! the rays per second, on a linear axis from zero so that ratios read as
//! lengths. Written as SVG text by hand (no plotting dependency): the same
//! report gives the same bytes, which `--replot` relies on.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::cases::scene_slug;
use super::record::RunRecord;
use super::report::BenchReport;
use crate::error::Result;
use crate::gpu::Accel;
use crate::kdtree::BuildStrategy;

const WIDTH: f64 = 900.0;
/// Left margin (run names), right margin (values), bar pitch, top and bottom.
const LABEL_W: f64 = 210.0;
const VALUE_W: f64 = 110.0;
const ROW_H: f64 = 26.0;
const TOP: f64 = 62.0;
const BOTTOM: f64 = 58.0;

/// The plots.rs palette: k-d tree blue (SAH; light blue binned) and green
/// (median), brute force red, the peer grey.
fn colour(r: &RunRecord) -> &'static str {
    match (r.accel, r.build) {
        (Accel::Brute, _) => "#cc3326",
        (Accel::Kdtree, Some(BuildStrategy::Median)) => "#288c46",
        (Accel::Kdtree, Some(BuildStrategy::Binned)) => "#7fa8e0",
        (Accel::Kdtree, _) => "#1f60c4",
    }
}
const EMBREE_COLOUR: &str = "#787878";

/// The plot's file name for a scene.
pub fn plot_file(scene: &str, n: usize) -> String {
    format!("matrix-{}.svg", scene_slug(scene, n))
}

/// Text with the five XML specials escaped.
fn xml(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
        .replace('\'', "&apos;")
}

/// A round step for about five grid lines up to `max`.
fn grid_step(max: f64) -> f64 {
    let raw = (max / 5.0).max(1e-12);
    let p = 10f64.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * p)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * p)
}

/// Up to 3 significant digits, for values and grid labels.
fn num(v: f64) -> String {
    if v >= 100.0 {
        format!("{v:.0}")
    } else if v >= 10.0 {
        format!("{v:.1}")
    } else if v >= 1.0 {
        format!("{v:.2}")
    } else {
        format!("{v:.3}")
    }
}

/// One bar: its label, value (None: a note instead) and colour.
struct Bar {
    label: String,
    value: Option<f64>,
    note: String,
    colour: &'static str,
}

/// The SVG text of one scene's plot.
pub fn scene_svg(report: &BenchReport, scene: &str, n: usize) -> String {
    let runs: Vec<&RunRecord> = report.runs_of(scene, n).collect();
    let bars = scene_bars(report, scene, n, &runs);
    let max = bars.iter().filter_map(|b| b.value).fold(0.0f64, f64::max);
    let step = grid_step(max);
    let axis_max = if max > 0.0 {
        (max / step).ceil() * step
    } else {
        1.0
    };
    let plot_w = WIDTH - LABEL_W - VALUE_W;
    let height = TOP + ROW_H * bars.len() as f64 + BOTTOM;
    let x = |v: f64| LABEL_W + plot_w * v / axis_max;
    let first = runs.first();

    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{WIDTH}" height="{height}" viewBox="0 0 {WIDTH} {height}" font-family="DejaVu Sans, Arial, sans-serif">"#
    );
    let _ = writeln!(s, r#"<rect width="100%" height="100%" fill="white"/>"#);
    let _ = writeln!(
        s,
        r#"<text x="{}" y="24" font-size="17" text-anchor="middle">{}</text>"#,
        WIDTH / 2.0,
        xml(&format!(
            "Rays per second: {scene}, N = {}{}",
            super::numbers::count(n as u64),
            first.map_or(String::new(), |r| format!(
                ", {}x{}, max_depth {}",
                r.width, r.height, r.max_depth
            ))
        ))
    );
    let bottom = TOP + ROW_H * bars.len() as f64;
    write_grid(&mut s, step, axis_max, bottom, &x);
    let _ = writeln!(
        s,
        r#"<text x="{:.1}" y="{:.1}" font-size="13" text-anchor="middle">million rays per second (GPU time; Embree: CPU time)</text>"#,
        LABEL_W + plot_w / 2.0,
        bottom + 34.0
    );
    write_bars(&mut s, &bars, &x);
    let _ = writeln!(
        s,
        r##"<line x1="{LABEL_W:.1}" y1="{:.1}" x2="{LABEL_W:.1}" y2="{bottom:.1}" stroke="#505050"/>"##,
        TOP - 6.0
    );
    let _ = writeln!(
        s,
        r##"<text x="10" y="{:.1}" font-size="11" fill="#6e6e6e">{}</text>"##,
        height - 8.0,
        xml(&format!(
            "{}  |  {} UTC",
            report.machine.adapter_line, report.date_utc
        ))
    );
    s.push_str("</svg>\n");
    s
}

/// The plot's bars: each run of `scene` at size `n` (its walk's Mrays/s,
/// or why it has none), then Embree's figure where the report has one.
fn scene_bars(report: &BenchReport, scene: &str, n: usize, runs: &[&RunRecord]) -> Vec<Bar> {
    let mut bars: Vec<Bar> = runs
        .iter()
        .map(|r| {
            let label = match (r.build, r.traversal) {
                (Some(b), Some(t)) => {
                    format!("{} / {}", b.name(), t.name())
                }
                _ => "brute force".into(),
            };
            Bar {
                label,
                value: r.mrays_per_s.filter(|_| r.is_ok()),
                note: if r.is_ok() {
                    String::new()
                } else {
                    r.status.name().to_string()
                },
                colour: colour(r),
            }
        })
        .collect();
    if let Some(e) = report.embree_for(scene, n) {
        bars.push(Bar {
            label: "Embree 4, one thread".into(),
            value: e.mrays_per_s_median,
            note: if e.unsupported.is_some() {
                "n/a (no sphere geometry in embreex)".into()
            } else {
                "no figure".into()
            },
            colour: EMBREE_COLOUR,
        });
    }
    bars
}

/// The vertical grid lines at multiples of `step` up to `axis_max`, and
/// their labels under `bottom`; `x` maps a value to its position.
fn write_grid(s: &mut String, step: f64, axis_max: f64, bottom: f64, x: &impl Fn(f64) -> f64) {
    let mut k = 0u32;
    loop {
        let v = step * k as f64;
        if v > axis_max * (1.0 + 1e-9) {
            break;
        }
        let gx = x(v);
        let _ = writeln!(
            s,
            r##"<line x1="{gx:.1}" y1="{:.1}" x2="{gx:.1}" y2="{bottom:.1}" stroke="#dcdcdc"/>"##,
            TOP - 6.0
        );
        let _ = writeln!(
            s,
            r#"<text x="{gx:.1}" y="{:.1}" font-size="12" text-anchor="middle">{}</text>"#,
            bottom + 16.0,
            // Multiples of a round step: the shortest decimal once rounded.
            (v * 1e6).round() / 1e6
        );
        k += 1;
    }
}

/// One row per bar: its label, and its bar and value or its note.
fn write_bars(s: &mut String, bars: &[Bar], x: &impl Fn(f64) -> f64) {
    for (i, b) in bars.iter().enumerate() {
        let y = TOP + ROW_H * i as f64;
        let mid = y + ROW_H / 2.0 + 4.0;
        let _ = writeln!(
            s,
            r#"<text x="{:.1}" y="{mid:.1}" font-size="13" text-anchor="end">{}</text>"#,
            LABEL_W - 8.0,
            xml(&b.label)
        );
        match b.value {
            Some(v) => {
                let w = (x(v) - LABEL_W).max(1.0);
                let _ = writeln!(
                    s,
                    r#"<rect x="{LABEL_W:.1}" y="{:.1}" width="{w:.1}" height="{:.1}" fill="{}"/>"#,
                    y + 4.0,
                    ROW_H - 8.0,
                    b.colour
                );
                let _ = writeln!(
                    s,
                    r#"<text x="{:.1}" y="{mid:.1}" font-size="12">{}</text>"#,
                    LABEL_W + w + 5.0,
                    num(v)
                );
            }
            None => {
                let _ = writeln!(
                    s,
                    r##"<text x="{:.1}" y="{mid:.1}" font-size="12" fill="#666666">{}</text>"##,
                    LABEL_W + 5.0,
                    xml(&b.note)
                );
            }
        }
    }
}

/// Writes one plot per scene into `out`; returns their paths.
pub fn write_matrix_plots(report: &BenchReport, out: &Path) -> Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    for (scene, n) in report.scenes() {
        let path = out.join(plot_file(&scene, n));
        crate::output::write_file_atomic(&path, scene_svg(report, &scene, n).as_bytes())?;
        files.push(path);
    }
    Ok(files)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_steps_are_round() {
        for (max, step) in [
            (10.0, 2.0),
            (0.41, 0.1),
            (7.0, 2.0),
            (100.0, 20.0),
            (3.0, 1.0),
        ] {
            let got = grid_step(max);
            assert!((got - step).abs() < 1e-12 * step, "{max}: {got}");
        }
    }

    #[test]
    fn text_is_escaped() {
        assert_eq!(xml("a<b & \"c\""), "a&lt;b &amp; &quot;c&quot;");
    }
}
