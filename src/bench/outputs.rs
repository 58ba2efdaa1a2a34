//! The bench's output folder: its files' names, writing every output of a
//! report (the data files of [`BenchReport::write_data`] and the plots of
//! [`plots`] and [`matrix_plot`]), the measured scenes written for peers
//! (`scenes/`), and `--replot`, which rewrites the outputs of a recorded run
//! without measuring.

use std::path::{Path, PathBuf};

use super::csv::{csv_text, CSV_FILE};
use super::report::{BenchReport, EMBREE_FILE, JSON_FILE};
use super::summary::{markdown_summary, SUMMARY_FILE};
use super::{cases, matrix_plot, plots, random_scene};
use crate::error::{Error, Result};
use crate::output::write_file_atomic;
use crate::scene::Scene;

/// Folder (in the output folder) of the scenes written for peers.
pub const SCENES_DIR: &str = "scenes";

/// What `kdray bench` measured, and where it wrote it.
#[derive(Debug, Clone)]
pub struct BenchOutcome {
    pub report: BenchReport,
    pub files: Vec<PathBuf>,
}

/// The output folder's standard file names.
pub fn output_files(out: &Path) -> [PathBuf; 6] {
    [
        out.join(CSV_FILE),
        out.join(JSON_FILE),
        out.join(SUMMARY_FILE),
        out.join(plots::TIME_PLOT),
        out.join(plots::SPEEDUP_PLOT),
        out.join(plots::BUILD_PLOT),
    ]
}

impl BenchReport {
    /// Writes bench.csv, bench.json and summary.md; returns their paths.
    pub fn write_data(&self, out: &Path) -> Result<Vec<PathBuf>> {
        let csv = out.join(CSV_FILE);
        write_file_atomic(&csv, csv_text(&self.runs).as_bytes())?;
        let json = out.join(JSON_FILE);
        let text = serde_json::to_string_pretty(self)?;
        write_file_atomic(&json, (text + "\n").as_bytes())?;
        let md = out.join(SUMMARY_FILE);
        write_file_atomic(&md, markdown_summary(self).as_bytes())?;
        Ok(vec![csv, json, md])
    }
}

/// Writes the data files and every plot of `report` into `out`; returns
/// their paths.
pub fn write_outputs(report: &BenchReport, out: &Path) -> Result<Vec<PathBuf>> {
    let mut files = report.write_data(out)?;
    files.extend(plots::write_plots(report, out)?);
    files.extend(matrix_plot::write_matrix_plots(report, out)?);
    Ok(files)
}

/// Rewrites the summary, fits and plots of the run recorded in
/// `dir/bench.json`, in `dir`, taking in the Embree results of
/// `dir/embree.json` when there are (scripts/peers/bench_embree.py).
pub fn replot(dir: &Path) -> Result<BenchOutcome> {
    let report = BenchReport::read(dir)?;
    let files = write_outputs(&report, dir)?;
    Ok(BenchOutcome { report, files })
}

/// Creates the output folder of a new sweep, and removes a peer's results
/// left in it: they belong to the run they were measured beside.
pub(super) fn prepare_output_folder(out: &Path) -> Result<()> {
    create_folder(out)?;
    let stale = out.join(EMBREE_FILE);
    if stale.is_file() {
        eprintln!(
            "kdray: removing {} of an earlier run (scripts/peers/bench_embree.py measures it again)",
            stale.display()
        );
        let _ = std::fs::remove_file(&stale);
    }
    Ok(())
}

/// Writes `scene` as JSON into `out/scenes/`; returns its path relative to `out`.
pub(super) fn write_scene(out: &Path, label: &str, scene: &Scene) -> Result<String> {
    let dir = out.join(SCENES_DIR);
    create_folder(&dir)?;
    let name = format!("{}.json", cases::scene_slug(label, scene.object_count()));
    let text = random_scene::scene_file_text(scene, crate::scene::SceneFormat::Json, "")
        .map_err(|e| Error::Output(format!("{label}: cannot write the scene: {e}")))?;
    crate::output::write_file_atomic(&dir.join(&name), text.as_bytes())?;
    Ok(format!("{SCENES_DIR}/{name}"))
}

fn create_folder(dir: &Path) -> Result<()> {
    std::fs::create_dir_all(dir).map_err(|source| Error::File {
        path: dir.to_path_buf(),
        what: "cannot create the folder",
        source,
    })
}
