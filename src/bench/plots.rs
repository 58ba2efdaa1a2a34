//! The bench's three log-log plots, drawn with plotters into an RGB buffer
//! and written with [`crate::output::write_png_atomic`]:
//!
//! - `bench-time.png`: GPU time per frame against N, k-d tree and brute force,
//!   with brute force's linear fit (the seed's figures 7 and 9 together);
//! - `bench-speedup.png`: brute / k-d tree against N;
//! - `bench-build.png`: k-d build and upload time against N.
//!
//! Text uses the embedded font of [`crate::output::font`].

use std::path::{Path, PathBuf};

use plotters::element::DashedPathElement;
use plotters::prelude::*;

use super::record::RunStatus;
use super::report::BenchReport;
use crate::error::{Error, Result};
use crate::gpu::Accel;

pub const TIME_PLOT: &str = "bench-time.png";
pub const SPEEDUP_PLOT: &str = "bench-speedup.png";
pub const BUILD_PLOT: &str = "bench-build.png";

const WIDTH: u32 = 960;
const HEIGHT: u32 = 640;
use crate::output::font::{register as register_font, FAMILY};

const KD_COLOUR: RGBColor = RGBColor(31, 96, 196);
const BRUTE_COLOUR: RGBColor = RGBColor(204, 51, 38);
const FIT_COLOUR: RGBColor = RGBColor(120, 120, 120);
const BUILD_COLOUR: RGBColor = RGBColor(40, 140, 70);
const UPLOAD_COLOUR: RGBColor = RGBColor(150, 80, 170);

#[derive(Clone, Copy, PartialEq)]
enum Marker {
    Dot,
    Triangle,
    /// Hollow circle: a value predicted, not measured.
    Hollow,
    Square,
    None,
}

struct Series {
    label: String,
    points: Vec<(f64, f64)>,
    colour: RGBColor,
    dashed: bool,
    marker: Marker,
}

/// 1, 10, 100, 1k, 10k, 100k, 1M, ... for object counts.
fn count_label(v: f64) -> String {
    let (scaled, suffix) = if v >= 1e6 {
        (v / 1e6, "M")
    } else if v >= 1e3 {
        (v / 1e3, "k")
    } else {
        (v, "")
    };
    format!("{}{suffix}", short(scaled))
}

/// A number with at most 3 significant digits, no trailing zeros.
fn short(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    if v.abs() >= 1e4 || v.abs() < 1e-3 {
        return format!("{v:.0e}");
    }
    let digits = (2 - v.abs().log10().floor() as i32).max(0) as usize;
    let s = format!("{v:.digits$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// A log axis range covering `values`, out to the enclosing powers of ten
/// and a little beyond, so markers on the edge stay whole.
fn log_range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
    for v in values.filter(|v| *v > 0.0 && v.is_finite()) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if lo > hi {
        return (0.1, 10.0);
    }
    let lo = 10f64.powf(lo.log10().floor());
    let mut hi = 10f64.powf(hi.log10().ceil());
    if hi <= lo {
        hi = lo * 10.0;
    }
    (lo * 0.7, hi * 1.4)
}

fn plot_error(path: &Path, e: impl std::fmt::Debug) -> Error {
    Error::Output(format!("{}: cannot draw the plot: {e:?}", path.display()))
}

/// Draws one log-log chart of `series` and writes it as a PNG.
fn loglog_chart(
    path: &Path,
    title: &str,
    footer: &str,
    x_desc: &str,
    y_desc: &str,
    series: &[Series],
) -> Result<()> {
    register_font()?;
    let xs = log_range(series.iter().flat_map(|s| s.points.iter().map(|p| p.0)));
    let ys = log_range(series.iter().flat_map(|s| s.points.iter().map(|p| p.1)));
    let mut buf = vec![255u8; (WIDTH * HEIGHT * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (WIDTH, HEIGHT)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| plot_error(path, e))?;
        let mut chart = ChartBuilder::on(&root)
            .caption(title, (FAMILY, 24))
            .margin(20)
            .margin_bottom(30)
            .x_label_area_size(55)
            .y_label_area_size(80)
            .build_cartesian_2d((xs.0..xs.1).log_scale(), (ys.0..ys.1).log_scale())
            .map_err(|e| plot_error(path, e))?;
        chart
            .configure_mesh()
            .x_desc(x_desc)
            .y_desc(y_desc)
            .x_label_formatter(&|v| count_label(*v))
            .y_label_formatter(&|v| short(*v))
            .label_style((FAMILY, 16))
            .axis_desc_style((FAMILY, 18))
            .light_line_style(RGBColor(235, 235, 235))
            .bold_line_style(RGBColor(200, 200, 200))
            .draw()
            .map_err(|e| plot_error(path, e))?;

        for s in series {
            draw_series(&mut chart, s, path)?;
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperLeft)
            .label_font((FAMILY, 16))
            .background_style(WHITE.mix(0.9))
            .border_style(RGBColor(160, 160, 160))
            .draw()
            .map_err(|e| plot_error(path, e))?;
        root.draw(&Text::new(
            footer.to_string(),
            (10, HEIGHT as i32 - 18),
            (FAMILY, 13).into_font().color(&RGBColor(110, 110, 110)),
        ))
        .map_err(|e| plot_error(path, e))?;
        root.present().map_err(|e| plot_error(path, e))?;
    }
    crate::output::write_png_atomic(path, WIDTH, HEIGHT, &buf)
}

/// Draws one series on `chart`: its line (dashed or not; none between
/// predicted points), its markers and its legend entry.
fn draw_series<'a>(
    chart: &mut ChartContext<'a, BitMapBackend<'a>, Cartesian2d<LogCoord<f64>, LogCoord<f64>>>,
    s: &Series,
    path: &Path,
) -> Result<()> {
    let colour = s.colour;
    let line_style = colour.stroke_width(2);
    // Predicted points are separate estimates: no line between them.
    if s.points.len() > 1 && s.marker != Marker::Hollow {
        if s.dashed {
            chart
                .draw_series(DashedLineSeries::new(
                    s.points.iter().copied(),
                    8,
                    6,
                    line_style,
                ))
                .map_err(|e| plot_error(path, e))?;
        } else {
            chart
                .draw_series(LineSeries::new(s.points.iter().copied(), line_style))
                .map_err(|e| plot_error(path, e))?;
        }
    }
    let points = s.points.iter().copied();
    let anno =
        match s.marker {
            Marker::Dot => chart
                .draw_series(points.map(|p| Circle::new(p, 5, colour.filled())))
                .map_err(|e| plot_error(path, e))?,
            Marker::Hollow => chart
                .draw_series(points.map(|p| Circle::new(p, 6, colour.stroke_width(2))))
                .map_err(|e| plot_error(path, e))?,
            Marker::Triangle => chart
                .draw_series(points.map(|p| TriangleMarker::new(p, 7, colour.filled())))
                .map_err(|e| plot_error(path, e))?,
            Marker::Square => chart
                .draw_series(points.map(|p| {
                    EmptyElement::at(p) + Rectangle::new([(-4, -4), (4, 4)], colour.filled())
                }))
                .map_err(|e| plot_error(path, e))?,
            Marker::None => chart
                .draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())
                .map_err(|e| plot_error(path, e))?,
        };
    let marker = s.marker;
    let dashed = s.dashed;
    let anno = anno.label(s.label.as_str());
    let style = colour.stroke_width(2);
    let line = move |(x, y): (i32, i32)| {
        EmptyElement::at((x, y)) + PathElement::new(vec![(0, 0), (24, 0)], style)
    };
    match (dashed, marker) {
        (true, _) => anno
            .legend(move |(x, y)| DashedPathElement::new(vec![(x, y), (x + 24, y)], 5, 4, style)),
        (false, Marker::Dot) => {
            anno.legend(move |p| line(p) + Circle::new((12, 0), 4, colour.filled()))
        }
        (false, Marker::Hollow) => anno.legend(move |p| line(p) + Circle::new((12, 0), 5, style)),
        (false, Marker::Triangle) => {
            anno.legend(move |p| line(p) + TriangleMarker::new((12, 0), 6, colour.filled()))
        }
        (false, Marker::Square) => {
            anno.legend(move |p| line(p) + Rectangle::new([(8, -4), (16, 4)], colour.filled()))
        }
        (false, Marker::None) => anno.legend(line),
    };
    Ok(())
}

fn points(report: &BenchReport, accel: Accel) -> Vec<(f64, f64)> {
    report
        .series(accel)
        .into_iter()
        .filter(|p| p.1 > 0.0)
        .map(|(n, ms)| (n as f64, ms))
        .collect()
}

/// The scene kind or file names, for titles.
fn what(report: &BenchReport) -> String {
    match report.config.kind {
        Some(kind) if report.config.scenes.is_empty() => format!("random {}", kind.name()),
        _ => "scene files".into(),
    }
}

fn image_size(report: &BenchReport) -> String {
    match report.runs.first() {
        Some(r) => format!("{}x{}", r.width, r.height),
        None => String::new(),
    }
}

/// Writes the three plots into `out`; returns their paths.
pub fn write_plots(report: &BenchReport, out: &Path) -> Result<Vec<PathBuf>> {
    let footer = format!(
        "{}  |  {} UTC",
        report.machine.adapter_line, report.date_utc
    );
    let kd = points(report, Accel::Kdtree);
    let brute = points(report, Accel::Brute);

    let series = time_series(report, &kd, &brute);
    let time_path = out.join(TIME_PLOT);
    loglog_chart(
        &time_path,
        &format!(
            "GPU time per frame vs objects: {}, {}",
            what(report),
            image_size(report)
        ),
        &footer,
        "objects N (log)",
        "GPU time per frame, ms (log)",
        &series,
    )?;

    let series = speedup_series(&kd, &brute);
    let speedup_path = out.join(SPEEDUP_PLOT);
    loglog_chart(
        &speedup_path,
        &format!(
            "Speed-up of the k-d tree over brute force: {}",
            what(report)
        ),
        &footer,
        "objects N (log)",
        "speed-up, x (log)",
        &series,
    )?;

    let series = build_series(report);
    let build_path = out.join(BUILD_PLOT);
    loglog_chart(
        &build_path,
        &format!(
            "k-d tree build and upload time vs objects: {}",
            what(report)
        ),
        &footer,
        "objects N (log)",
        "time, ms (log)",
        &series,
    )?;
    Ok(vec![time_path, speedup_path, build_path])
}

/// The time plot's series (seed figures 7 and 9): the k-d tree's and brute
/// force's GPU time against N, brute force's linear fit, and its
/// prediction for the sizes it skipped (over the budget or past the
/// adapter's loop limit).
fn time_series(report: &BenchReport, kd: &[(f64, f64)], brute: &[(f64, f64)]) -> Vec<Series> {
    let mut series = vec![Series {
        label: "k-d tree".into(),
        points: kd.to_vec(),
        colour: KD_COLOUR,
        dashed: false,
        marker: Marker::Dot,
    }];
    if !brute.is_empty() {
        series.push(Series {
            label: "brute force (the seed's loop)".into(),
            points: brute.to_vec(),
            colour: BRUTE_COLOUR,
            dashed: false,
            marker: Marker::Triangle,
        });
    }
    let fit = report.fits.iter().find(|f| f.accel == Accel::Brute);
    let skipped: Vec<_> = report
        .runs
        .iter()
        .filter(|r| r.accel == Accel::Brute && r.status == RunStatus::Skipped)
        .map(|r| r.n as f64)
        .collect();
    if let Some((a, b)) = fit.and_then(|f| Some((f.linear_intercept_ms?, f.linear_per_object_ms?)))
    {
        if brute.len() >= 2 && b > 0.0 {
            let lo = brute.iter().map(|p| p.0).fold(f64::INFINITY, f64::min);
            let hi = brute
                .iter()
                .map(|p| p.0)
                .chain(skipped.iter().copied())
                .fold(0.0, f64::max);
            let steps = 60;
            let line: Vec<(f64, f64)> = (0..=steps)
                .map(|i| {
                    let n = lo * (hi / lo).powf(i as f64 / steps as f64);
                    (n, a + b * n)
                })
                .filter(|p| p.1 > 0.0)
                .collect();
            series.push(Series {
                label: format!(
                    "brute-force linear fit: {} ms + {} ms x N",
                    short(a),
                    short(b)
                ),
                points: line,
                colour: FIT_COLOUR,
                dashed: true,
                marker: Marker::None,
            });
            let predicted: Vec<(f64, f64)> = skipped.iter().map(|&n| (n, a + b * n)).collect();
            if !predicted.is_empty() {
                series.push(Series {
                    label: "brute force skipped: fit's prediction".into(),
                    points: predicted,
                    colour: BRUTE_COLOUR,
                    dashed: false,
                    marker: Marker::Hollow,
                });
            }
        }
    }
    series
}

/// The speed-up plot's series: brute force's time over the k-d tree's at
/// each N both measured, and the break-even line.
fn speedup_series(kd: &[(f64, f64)], brute: &[(f64, f64)]) -> Vec<Series> {
    let speedup: Vec<(f64, f64)> = kd
        .iter()
        .filter_map(|&(n, k)| brute.iter().find(|b| b.0 == n).map(|&(_, b)| (n, b / k)))
        .collect();
    let mut series = vec![Series {
        label: "brute force / k-d tree (GPU time)".into(),
        points: speedup.clone(),
        colour: KD_COLOUR,
        dashed: false,
        marker: Marker::Dot,
    }];
    if let (Some(first), Some(last)) = (speedup.first(), speedup.last()) {
        let (lo, hi) = (first.0.min(last.0), first.0.max(last.0).max(first.0 * 10.0));
        series.push(Series {
            label: "1x (break-even)".into(),
            points: vec![(lo, 1.0), (hi, 1.0)],
            colour: BRUTE_COLOUR,
            dashed: true,
            marker: Marker::None,
        });
    }
    series
}

/// The build plot's series: the k-d tree's build and upload times against
/// N, and c N log2(N)^2 through the largest build.
fn build_series(report: &BenchReport) -> Vec<Series> {
    let build: Vec<(f64, f64)> = report
        .runs
        .iter()
        .filter(|r| report.in_series(r, Accel::Kdtree) && r.is_ok())
        .filter_map(|r| Some((r.n as f64, r.build_ms?)))
        .filter(|p| p.1 > 0.0)
        .collect();
    let upload: Vec<(f64, f64)> = report
        .runs
        .iter()
        .filter(|r| report.in_series(r, Accel::Kdtree) && r.is_ok())
        .filter_map(|r| Some((r.n as f64, r.upload_ms?)))
        .filter(|p| p.1 > 0.0)
        .collect();
    let mut series = vec![
        Series {
            label: "k-d tree build (CPU, SAH)".into(),
            points: build.clone(),
            colour: BUILD_COLOUR,
            dashed: false,
            marker: Marker::Dot,
        },
        Series {
            label: "upload (flatten + storage buffers)".into(),
            points: upload,
            colour: UPLOAD_COLOUR,
            dashed: false,
            marker: Marker::Square,
        },
    ];
    if let Some(&(n_max, ms_max)) = build.iter().max_by(|a, b| a.0.total_cmp(&b.0)) {
        // c N log2(N)^2 through the largest point, from N = 100 up.
        let g = |n: f64| n * n.max(2.0).log2().powi(2);
        let c = ms_max / g(n_max);
        let lo = build
            .iter()
            .map(|p| p.0)
            .fold(f64::INFINITY, f64::min)
            .max(100.0);
        if n_max > lo {
            let steps = 40;
            series.push(Series {
                label: "c N log2(N)^2 through the largest N".into(),
                points: (0..=steps)
                    .map(|i| {
                        let n = lo * (n_max / lo).powf(i as f64 / steps as f64);
                        (n, c * g(n))
                    })
                    .collect(),
                colour: FIT_COLOUR,
                dashed: true,
                marker: Marker::None,
            });
        }
    }
    series
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_are_short() {
        assert_eq!(count_label(1.0), "1");
        assert_eq!(count_label(1000.0), "1k");
        assert_eq!(count_label(100_000.0), "100k");
        assert_eq!(count_label(1_000_000.0), "1M");
        assert_eq!(short(0.5), "0.5");
        assert_eq!(short(12.5), "12.5");
        assert_eq!(short(1234.0), "1234");
        assert_eq!(short(10000.0), "1e4");
        assert_eq!(short(0.000_12), "1e-4");
    }

    #[test]
    fn ranges_reach_powers_of_ten() {
        let (lo, hi) = log_range([3.0, 420.0].into_iter());
        assert!((lo - 0.7).abs() < 1e-9 && (hi - 1400.0).abs() < 1e-6);
    }
}
