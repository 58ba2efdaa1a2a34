//! The machine a bench ran on, as its report records it ([`Machine`]: the
//! adapter, the CPU, the load), the clock's date in ISO 8601, and the
//! process's peak memory per run. The readings come from Linux's /proc and
//! are absent elsewhere.

use serde::{Deserialize, Serialize};

use crate::gpu::GpuContext;

#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Machine {
    pub adapter: String,
    pub adapter_line: String,
    pub backend: String,
    pub timestamps: bool,
    pub host_cpu: Option<String>,
    pub host_threads: Option<usize>,
    pub os: String,
    /// 1-minute load average when the sweep started and when it last
    /// recorded a run (Linux): a software adapter shares the CPU with
    /// whatever else runs, so a busy machine shows up here.
    pub load_average_start: Option<f64>,
    pub load_average_end: Option<f64>,
}

impl Machine {
    /// The adapter of `ctx` and the host, with the load average now as the
    /// load at the start.
    pub fn of(ctx: &GpuContext) -> Self {
        Machine {
            adapter: ctx.info.name.clone(),
            adapter_line: ctx.adapter_line(),
            backend: format!("{:?}", ctx.info.backend),
            timestamps: ctx.has_timestamps,
            host_cpu: host_cpu(),
            host_threads: std::thread::available_parallelism().ok().map(|n| n.get()),
            os: std::env::consts::OS.to_string(),
            load_average_start: load_average(),
            load_average_end: None,
        }
    }
}

/// The 1-minute load average (Linux /proc/loadavg).
pub fn load_average() -> Option<f64> {
    std::fs::read_to_string("/proc/loadavg")
        .ok()?
        .split_whitespace()
        .next()?
        .parse()
        .ok()
}

fn host_cpu() -> Option<String> {
    let info = std::fs::read_to_string("/proc/cpuinfo").ok()?;
    let line = info.lines().find(|l| l.starts_with("model name"))?;
    Some(line.split_once(':')?.1.trim().to_string())
}

/// The system clock's time as ISO 8601 UTC to the second
/// (`YYYY-MM-DDThh:mm:ssZ`).
pub fn utc_now_iso() -> String {
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    iso_from_unix(secs)
}

/// ISO 8601 UTC of a Unix time in seconds (`jiff`'s RFC 3339 form, which
/// leaves out a zero fraction of a second).
pub fn iso_from_unix(secs: u64) -> String {
    i64::try_from(secs)
        .ok()
        .and_then(|s| jiff::Timestamp::from_second(s).ok())
        .unwrap_or(jiff::Timestamp::MAX)
        .to_string()
}

/// Peak resident memory of this process so far, in MiB (Linux: VmHWM).
pub fn peak_host_mib() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib / 1024.0)
}

/// Resets the peak to the current resident size, so the next reading is
/// this run's own peak (Linux >= 4.0; harmless where unsupported).
pub fn reset_peak_host_memory() {
    let _ = std::fs::write("/proc/self/clear_refs", "5");
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dates_are_iso() {
        let d = utc_now_iso();
        assert_eq!(d.len(), 20, "{d}");
        assert_eq!(iso_from_unix(0), "1970-01-01T00:00:00Z");
        assert_eq!(iso_from_unix(951_782_400), "2000-02-29T00:00:00Z");
        assert_eq!(iso_from_unix(1_700_000_000), "2023-11-14T22:13:20Z");
        assert_eq!(iso_from_unix(4_102_444_799), "2099-12-31T23:59:59Z");
    }
}
