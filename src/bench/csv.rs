//! `bench.csv`: one row per run, every field of [`RunRecord`] but the
//! timed frames' samples (their count instead), quoted as RFC 4180 says.

use super::numbers::{opt, opt_f};
use super::record::RunRecord;
use crate::choice::Choice;
use crate::kdtree::{BuildStrategy, Traversal};

pub const CSV_FILE: &str = "bench.csv";

/// The CSV's columns, in order (the fields of [`RunRecord`] but the samples).
pub const CSV_COLUMNS: [&str; 39] = [
    "scene",
    "n",
    "spheres",
    "triangles",
    "accel",
    "build",
    "traversal",
    "status",
    "note",
    "width",
    "height",
    "samples",
    "max_depth",
    "scene_ms",
    "build_ms",
    "kd_nodes",
    "kd_leaves",
    "kd_max_depth",
    "kd_refs_per_leaf",
    "upload_ms",
    "gpu_scene_bytes",
    "gpu_ms",
    "gpu_ms_min",
    "gpu_ms_max",
    "repeats",
    "gpu_time_source",
    "frame_wall_ms",
    "primary_rays",
    "shadow_rays",
    "reflection_rays",
    "total_rays",
    "mrays_per_s",
    "peak_host_mib",
    "pixels_differing_from_kdtree",
    "loop_limited_pixels",
    "nodes_visited_per_ray",
    "leaves_visited_per_ray",
    "objects_tested_per_ray",
    "pixels_differing_from_brute",
];

/// A CSV field, quoted when it must be (RFC 4180).
fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// `runs` as CSV: a header of [`CSV_COLUMNS`], then a row per run.
pub fn csv_text(runs: &[RunRecord]) -> String {
    let mut out = CSV_COLUMNS.join(",");
    out.push('\n');
    for r in runs {
        let fields = [
            csv_field(&r.scene),
            r.n.to_string(),
            r.spheres.to_string(),
            r.triangles.to_string(),
            r.accel.name().to_string(),
            r.build.map_or("", BuildStrategy::name).to_string(),
            r.traversal.map_or("", Traversal::name).to_string(),
            r.status.name().to_string(),
            csv_field(r.note.as_deref().unwrap_or("")),
            r.width.to_string(),
            r.height.to_string(),
            r.samples.to_string(),
            r.max_depth.to_string(),
            format!("{:.3}", r.scene_ms),
            opt_f(r.build_ms, 3),
            opt(r.kd_nodes),
            opt(r.kd_leaves),
            opt(r.kd_max_depth),
            opt_f(r.kd_refs_per_leaf, 3),
            opt_f(r.upload_ms, 3),
            opt(r.gpu_scene_bytes),
            opt_f(r.gpu_ms, 3),
            opt_f(r.gpu_ms_min, 3),
            opt_f(r.gpu_ms_max, 3),
            r.gpu_ms_samples.len().to_string(),
            r.gpu_time_source.map_or("", |s| s.name()).to_string(),
            opt_f(r.frame_wall_ms, 3),
            opt(r.primary_rays),
            opt(r.shadow_rays),
            opt(r.reflection_rays),
            opt(r.total_rays),
            opt_f(r.mrays_per_s, 3),
            opt_f(r.peak_host_mib, 1),
            opt(r.pixels_differing_from_kdtree),
            opt(r.loop_limited_pixels),
            opt_f(r.nodes_visited_per_ray, 3),
            opt_f(r.leaves_visited_per_ray, 3),
            opt_f(r.objects_tested_per_ray, 3),
            opt(r.pixels_differing_from_brute),
        ];
        debug_assert_eq!(fields.len(), CSV_COLUMNS.len());
        out.push_str(&fields.join(","));
        out.push('\n');
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_fields_are_quoted_when_needed() {
        assert_eq!(csv_field("plain"), "plain");
        assert_eq!(csv_field("a, b"), "\"a, b\"");
        assert_eq!(csv_field("say \"x\""), "\"say \"\"x\"\"\"");
    }
}
