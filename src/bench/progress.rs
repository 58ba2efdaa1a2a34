//! What the bench shows on stderr while it runs: a bar of runs done with
//! what it is doing now on a terminal, and one line per finished run
//! ([`run_line`]) either way.

use super::record::{RunRecord, RunStatus};

/// Progress on stderr: a bar on a terminal, one line per finished run otherwise.
pub(super) struct Progress {
    bar: indicatif::ProgressBar,
}

impl Progress {
    pub fn new(total: u64) -> Self {
        let bar = indicatif::ProgressBar::with_draw_target(
            Some(total),
            indicatif::ProgressDrawTarget::stderr(),
        );
        if let Ok(style) = indicatif::ProgressStyle::with_template(
            "{elapsed_precise} [{bar:30.cyan/blue}] {pos}/{len} runs  {msg}",
        ) {
            bar.set_style(style.progress_chars("=> "));
        }
        bar.enable_steady_tick(std::time::Duration::from_millis(250));
        Progress { bar }
    }

    pub fn message(&self, msg: String) {
        self.bar.set_message(msg);
    }

    pub fn line(&self, line: String) {
        if self.bar.is_hidden() {
            eprintln!("{line}");
        } else {
            self.bar.println(line);
        }
    }

    pub fn step(&self) {
        self.bar.inc(1);
    }

    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }
}

/// One line about a finished run, for stderr.
pub(super) fn run_line(r: &RunRecord) -> String {
    let head = format!("{} N={:>8} {:<24}", r.scene, r.n, r.cell_name());
    match r.status {
        RunStatus::Ok => {
            let mut s = format!(
                "{head} gpu {:>10.2} ms (median of {}), {:>7.2} Mrays/s",
                r.gpu_ms.unwrap_or(f64::NAN),
                r.gpu_ms_samples.len(),
                r.mrays_per_s.unwrap_or(f64::NAN)
            );
            if let Some(b) = r.build_ms {
                s.push_str(&format!(", build {b:.1} ms"));
            }
            if let Some(u) = r.upload_ms {
                s.push_str(&format!(", upload {u:.1} ms"));
            }
            if let Some(m) = r.peak_host_mib {
                s.push_str(&format!(", peak {m:.0} MiB"));
            }
            if let Some(d) = r.pixels_differing_from_kdtree {
                s.push_str(&format!(", {d} px differ from kdtree"));
            }
            if let Some(d) = r.pixels_differing_from_brute {
                s.push_str(&format!(", {d} px differ from brute"));
            }
            s
        }
        other => format!(
            "{head} {}: {}",
            other.name(),
            r.note.as_deref().unwrap_or("")
        ),
    }
}
