//! Brute force's per-frame budget: before a brute-force run, whether it
//! would be wrong (past llvmpipe's loop limit) or take longer than the
//! budget (a line through the frames measured so far), so that it is
//! skipped, and the skip recorded, instead of run.

/// Loop iterations llvmpipe lets one invocation run (`GpuContext::has_loop_limit`).
pub const LLVMPIPE_LOOP_LIMIT: usize = 65_535;

/// Why brute force should not run on a scene of `n` objects and `work`
/// (objects x primary rays), given the brute-force frames measured so far
/// as (work, ms); None when it should.
pub fn brute_skip_reason(
    loop_limited: bool,
    n: usize,
    work: usize,
    measured: &[(usize, f64)],
    budget_s: f64,
) -> Option<String> {
    if loop_limited && n >= LLVMPIPE_LOOP_LIMIT {
        // Every primary ray alone would loop over more objects than
        // llvmpipe lets an invocation run: the image would be wrong.
        return Some(format!(
            "{n} objects: one ray's loop over them passes llvmpipe's limit of \
             {LLVMPIPE_LOOP_LIMIT} iterations per pixel"
        ));
    }
    let (predicted, how) = predict_brute_ms(measured, work)?;
    (predicted > budget_s * 1e3).then(|| {
        format!(
            "predicted {:.1} s per frame ({how}) > budget {} s",
            predicted * 1e-3,
            budget_s
        )
    })
}

/// Predicted brute-force frame time for `work` (objects x primary rays)
/// from the frames measured so far, and how it was obtained. Brute force
/// costs a + b N per frame at a given image size (the seed's linear model),
/// taken here as a + b W in W = N x primary rays so that scenes of other
/// sizes and images can be compared: with two or more measured, a and b
/// come from the two largest; with one, the frame is scaled by W / W0,
/// which overestimates (it scales the fixed cost too) and so errs towards
/// skipping.
pub fn predict_brute_ms(measured: &[(usize, f64)], work: usize) -> Option<(f64, String)> {
    let mut pts: Vec<(usize, f64)> = measured.iter().copied().filter(|p| p.1 > 0.0).collect();
    pts.sort_by_key(|p| p.0);
    pts.dedup_by_key(|p| p.0);
    match pts.as_slice() {
        [] => None,
        [(w0, ms0)] => Some((
            ms0 * work as f64 / (*w0).max(1) as f64,
            format!("{:.3} s at N x rays = {w0} scaled", ms0 * 1e-3),
        )),
        [.., (w0, ms0), (w1, ms1)] => {
            let b = ((ms1 - ms0) / (*w1 as f64 - *w0 as f64)).max(0.0);
            let a = (ms1 - b * *w1 as f64).max(0.0);
            let predicted = if b > 0.0 {
                a + b * work as f64
            } else {
                ms1 * work as f64 / (*w1).max(1) as f64
            };
            Some((
                predicted,
                format!(
                    "line through {:.3} s at N x rays = {w0} and {:.3} s at {w1}",
                    ms0 * 1e-3,
                    ms1 * 1e-3
                ),
            ))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn brute_prediction_uses_a_line_once_it_has_two_sizes() {
        assert!(predict_brute_ms(&[], 10).is_none());
        // One point: proportional (conservative).
        let (ms, how) = predict_brute_ms(&[(10, 50.0)], 1000).unwrap();
        assert!((ms - 5000.0).abs() < 1e-9, "{ms} {how}");
        // Two points on ms = 40 + 1 * N: the fixed cost is not scaled.
        let (ms, how) = predict_brute_ms(&[(10, 50.0), (100, 140.0)], 10_000).unwrap();
        assert!((ms - 10_040.0).abs() < 1e-6, "{ms}");
        assert!(how.contains("= 10 ") && how.contains("at 100"), "{how}");
        // Noise that makes the line fall is not extrapolated downwards.
        let (ms, _) = predict_brute_ms(&[(10, 60.0), (100, 50.0)], 1000).unwrap();
        assert!((ms - 500.0).abs() < 1e-9, "{ms}");
    }

    #[test]
    fn brute_force_past_the_loop_limit_or_the_budget_is_skipped() {
        let measured = [(10, 50.0), (100, 140.0)];
        // Predicted 10.04 s: within a budget of 11 s, over one of 10 s.
        assert_eq!(brute_skip_reason(false, 10, 10_000, &measured, 11.0), None);
        let over = brute_skip_reason(false, 10, 10_000, &measured, 10.0).unwrap();
        assert!(over.contains("budget 10 s"), "{over}");
        // Nothing measured yet: it runs, unless llvmpipe's limit rules it out.
        assert_eq!(brute_skip_reason(true, 65_534, 1, &[], 1.0), None);
        let limited = brute_skip_reason(true, 65_535, 1, &[], 1.0).unwrap();
        assert!(limited.contains("llvmpipe"), "{limited}");
        assert_eq!(brute_skip_reason(false, 65_535, 1, &[], 1.0), None);
    }
}
