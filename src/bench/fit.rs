//! Least-squares fits of the measured GPU times against the object count
//! ([`Fit`]): the slope on a log-log plot, and the seed study's straight
//! line ms = a + b N, fitted to relative error.

use serde::{Deserialize, Serialize};

use crate::gpu::Accel;

/// Least-squares fits of one acceleration's measured GPU times.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Fit {
    pub accel: Accel,
    /// Sizes used (N >= 100, where fixed costs no longer dominate).
    pub points: usize,
    /// Slope of log(ms) against log(N): 1 is linear, 0 constant.
    pub loglog_slope: Option<f64>,
    /// ms = intercept + per_object * N (the seed's figure 7 fit), all sizes,
    /// fitted to relative error (each point weighted by 1 / ms^2), so that
    /// the small sizes count as much as the large ones on a log-log plot.
    pub linear_intercept_ms: Option<f64>,
    pub linear_per_object_ms: Option<f64>,
    pub linear_r2: Option<f64>,
}

/// The fits of `accel`'s series of (N, GPU ms); None without a point.
pub fn fit(accel: Accel, points: &[(usize, f64)]) -> Option<Fit> {
    if points.is_empty() {
        return None;
    }
    let large: Vec<(f64, f64)> = points
        .iter()
        .filter(|(n, ms)| *n >= 100 && *ms > 0.0)
        .map(|&(n, ms)| ((n as f64).ln(), ms.ln()))
        .collect();
    let loglog_slope = least_squares(&large).map(|(_, b, _)| b);
    let linear: Vec<(f64, f64, f64)> = points
        .iter()
        .filter(|(_, ms)| *ms > 0.0)
        .map(|&(n, ms)| (n as f64, ms, 1.0 / (ms * ms)))
        .collect();
    let lin = weighted_least_squares(&linear);
    Some(Fit {
        accel,
        points: large.len(),
        loglog_slope,
        linear_intercept_ms: lin.map(|l| l.0),
        linear_per_object_ms: lin.map(|l| l.1),
        linear_r2: lin.and_then(|l| l.2),
    })
}

/// y = a + b x by least squares: (a, b, R^2); None under two distinct x.
pub fn least_squares(points: &[(f64, f64)]) -> Option<(f64, f64, Option<f64>)> {
    let weighted: Vec<_> = points.iter().map(|&(x, y)| (x, y, 1.0)).collect();
    weighted_least_squares(&weighted)
}

/// y = a + b x by least squares over (x, y, weight): (a, b, weighted R^2).
pub fn weighted_least_squares(points: &[(f64, f64, f64)]) -> Option<(f64, f64, Option<f64>)> {
    let w: f64 = points.iter().map(|p| p.2).sum();
    if points.len() < 2 || w.is_nan() || w <= 0.0 {
        return None;
    }
    let mx = points.iter().map(|p| p.2 * p.0).sum::<f64>() / w;
    let my = points.iter().map(|p| p.2 * p.1).sum::<f64>() / w;
    let sxx: f64 = points.iter().map(|p| p.2 * (p.0 - mx).powi(2)).sum();
    let sxy: f64 = points.iter().map(|p| p.2 * (p.0 - mx) * (p.1 - my)).sum();
    let syy: f64 = points.iter().map(|p| p.2 * (p.1 - my).powi(2)).sum();
    if sxx <= 0.0 || sxx.is_nan() {
        return None;
    }
    let b = sxy / sxx;
    let a = my - b * mx;
    let r2 = (syy > 0.0).then(|| (sxy * sxy) / (sxx * syy));
    Some((a, b, r2))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn least_squares_recovers_a_line() {
        let pts: Vec<(f64, f64)> = (0..5).map(|i| (i as f64, 2.0 + 3.0 * i as f64)).collect();
        let (a, b, r2) = least_squares(&pts).unwrap();
        assert!((a - 2.0).abs() < 1e-12 && (b - 3.0).abs() < 1e-12);
        assert!((r2.unwrap() - 1.0).abs() < 1e-12);
        assert!(least_squares(&[(1.0, 1.0)]).is_none());
        // Weights pull the fit towards the heavy points.
        let (a, b, _) =
            weighted_least_squares(&[(0.0, 0.0, 1.0), (1.0, 1.0, 1.0), (2.0, 4.0, 1e-9)]).unwrap();
        assert!(a.abs() < 1e-6 && (b - 1.0).abs() < 1e-6, "{a} {b}");
    }
}
