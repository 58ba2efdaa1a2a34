//! How much of a denoise in progress a frame runs: units of work
//! ([`crate::denoise::WorkUnit`]) until their predicted time reaches
//! [`DENOISE_BUDGET_MS`], the time per unit of cost learned from the
//! frames before. Free of winit and wgpu.
//!
//! Measured on lavapipe (2 busy cores): the 480x360 denoise's largest
//! convolutions cost about 0.9 G multiply-adds a dispatch, several
//! seconds, so they are cut into units of at most [`MAX_UNIT_COST`]
//! (tens of ms there); a frame runs as many as fit its budget.

/// GPU time a frame gives the denoise in progress, ms (on top of its
/// sample pass, [`super::refinement::STILL_BUDGET_MS`]).
pub const DENOISE_BUDGET_MS: f64 = 120.0;
/// The most multiply-adds of one unit of the window's denoise.
pub const MAX_UNIT_COST: u64 = 16 << 20;

/// The learned time per unit of cost.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct DenoiseBudget {
    /// Seconds per unit of cost, once a frame has run units.
    seconds_per_cost: Option<f64>,
}

impl DenoiseBudget {
    /// How many of the units ahead (their costs `next`, in order) a frame
    /// runs: those whose predicted time fits the budget, at least one
    /// (only one before anything is learned).
    pub fn units(&self, next: impl IntoIterator<Item = u64>) -> usize {
        let Some(rate) = self.seconds_per_cost else {
            return 1;
        };
        let budget = DENOISE_BUDGET_MS * 1e-3;
        let mut predicted = 0.0;
        let mut count = 0;
        for cost in next {
            predicted += cost as f64 * rate;
            if count > 0 && predicted > budget {
                break;
            }
            count += 1;
        }
        count.max(1)
    }

    /// Units of total `cost` took `seconds`: the rate is their mean with
    /// the rate before (a frame's units differ in kind, so one frame's
    /// rate alone is noisy).
    pub fn learn(&mut self, cost: u64, seconds: f64) {
        if cost == 0 {
            return;
        }
        let rate = seconds / cost as f64;
        self.seconds_per_cost = Some(match self.seconds_per_cost {
            Some(before) => 0.5 * (before + rate),
            None => rate,
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_first_frame_runs_one_unit_to_learn_the_rate() {
        let budget = DenoiseBudget::default();
        assert_eq!(budget.units([1, 1, 1]), 1);
        assert_eq!(budget.units([]), 1);
    }

    #[test]
    fn a_frame_runs_the_units_that_fit_its_budget() {
        let mut budget = DenoiseBudget::default();
        // 10 M cost in 40 ms: 4 ns per unit of cost.
        budget.learn(10_000_000, 0.040);
        let per_ms = (1e-3 / 4e-9) as u64;
        // 50 ms units: two fit 120 ms, a third would not.
        assert_eq!(budget.units([50 * per_ms; 5]), 2);
        // 7 ms units: 17 fit (119 ms), an 18th would not.
        assert_eq!(budget.units([7 * per_ms; 200]), 17);
        // Fewer units than fit: all of them.
        assert_eq!(budget.units([7 * per_ms; 3]), 3);
        // One unit over the whole budget still runs.
        assert_eq!(budget.units([500 * per_ms, 1]), 1);
    }

    #[test]
    fn the_rate_follows_the_measurements() {
        let mut budget = DenoiseBudget::default();
        budget.learn(1000, 1.0);
        assert_eq!(budget.seconds_per_cost, Some(1e-3));
        budget.learn(1000, 3.0);
        assert_eq!(budget.seconds_per_cost, Some(2e-3));
        budget.learn(0, 5.0);
        assert_eq!(budget.seconds_per_cost, Some(2e-3), "nothing ran");
    }
}
