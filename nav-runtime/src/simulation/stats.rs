//! Ensemble statistics over Monte Carlo runs.
//!
//! Conventions (stable; scripts compare numbers across versions):
//! - [`percentile`] uses **linear interpolation between closest ranks** (the
//!   "type 7" definition, the default of NumPy and R): for sorted values
//!   `x[0..n]` and `p` in `[0, 100]`, `h = (n - 1) p / 100`, and the result is
//!   `x[floor h] + (h - floor h) (x[floor h + 1] - x[floor h])`. So `p = 50` is the
//!   usual median, `p = 100` the maximum, and one value gives itself for every `p`.
//! - [`std_dev`] is the **sample** standard deviation (divides by `n - 1`); it is 0
//!   for a single value.
//! - Empty input gives NaN everywhere (serialized to JSON as `null`).
//! - NaN inputs sort after every number (IEEE total order), so they show up in
//!   [`max`] and high percentiles instead of being silently dropped.
//!
//! Chi-square quantiles live with the filter's gating code; the band of a
//! Monte Carlo's mean squared normalized error is [`NormalizedErrors`].

use serde::{Deserialize, Serialize};

fn sorted(xs: &[f64]) -> Vec<f64> {
    let mut v = xs.to_vec();
    v.sort_by(|a, b| a.total_cmp(b));
    v
}

fn percentile_of_sorted(v: &[f64], p: f64) -> f64 {
    if v.is_empty() || p.is_nan() {
        return f64::NAN;
    }
    let p = p.clamp(0.0, 100.0);
    let h = (v.len() - 1) as f64 * p / 100.0;
    let lo = h.floor() as usize;
    let hi = (lo + 1).min(v.len() - 1);
    let frac = h - lo as f64;
    if frac == 0.0 || lo == hi {
        v[lo]
    } else {
        v[lo] + frac * (v[hi] - v[lo])
    }
}

/// The `p`-th percentile (`p` in `[0, 100]`, clamped), linear interpolation between
/// closest ranks (see the module documentation). NaN for empty input.
pub fn percentile(xs: &[f64], p: f64) -> f64 {
    percentile_of_sorted(&sorted(xs), p)
}

/// The median (50th percentile; mean of the two middle values for an even count).
pub fn median(xs: &[f64]) -> f64 {
    percentile(xs, 50.0)
}

/// The 95th percentile.
pub fn p95(xs: &[f64]) -> f64 {
    percentile(xs, 95.0)
}

/// The largest value (NaN if any value is NaN, or for empty input).
pub fn max(xs: &[f64]) -> f64 {
    sorted(xs).last().copied().unwrap_or(f64::NAN)
}

/// The smallest value (NaN for empty input).
pub fn min(xs: &[f64]) -> f64 {
    sorted(xs).first().copied().unwrap_or(f64::NAN)
}

/// The arithmetic mean (NaN for empty input).
pub fn mean(xs: &[f64]) -> f64 {
    if xs.is_empty() {
        return f64::NAN;
    }
    xs.iter().sum::<f64>() / xs.len() as f64
}

/// The sample standard deviation (`n - 1` in the denominator; 0 for one value, NaN
/// for none).
pub fn std_dev(xs: &[f64]) -> f64 {
    match xs.len() {
        0 => f64::NAN,
        1 => 0.0,
        n => {
            let m = mean(xs);
            let ss: f64 = xs.iter().map(|x| (x - m) * (x - m)).sum();
            (ss / (n - 1) as f64).sqrt()
        }
    }
}

/// Root mean square (NaN for empty input).
pub fn rms(xs: &[f64]) -> f64 {
    if xs.is_empty() {
        return f64::NAN;
    }
    (xs.iter().map(|x| x * x).sum::<f64>() / xs.len() as f64).sqrt()
}

/// The `{"median", "p95", "max"}` object reported for each statistic over runs.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    /// Median over runs.
    pub median: f64,
    /// 95th percentile over runs (linear interpolation).
    pub p95: f64,
    /// Maximum over runs.
    pub max: f64,
}

impl Summary {
    /// Summarizes values (NaN fields for empty input).
    pub fn of(xs: &[f64]) -> Summary {
        let v = sorted(xs);
        Summary {
            median: percentile_of_sorted(&v, 50.0),
            p95: percentile_of_sorted(&v, 95.0),
            max: v.last().copied().unwrap_or(f64::NAN),
        }
    }
}

/// The errors of one estimated scalar against its truth over Monte Carlo
/// runs, each in the estimate's own sigma: the mean squared normalized
/// error (1 for a consistent estimate; [`NormalizedErrors::consistent`])
/// and the absolute errors.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct NormalizedErrors {
    squared: f64,
    absolute: Vec<f64>,
}

impl NormalizedErrors {
    /// One run's `error` (estimate minus truth) and the estimate's `sigma`.
    pub fn add(&mut self, error: f64, sigma: f64) {
        self.squared += (error / sigma).powi(2);
        self.absolute.push(error.abs());
    }

    /// The mean of the squared errors in sigmas (NaN without runs).
    pub fn mean_squared(&self) -> f64 {
        self.squared / self.absolute.len() as f64
    }

    /// The median absolute error (NaN without runs).
    pub fn median_absolute(&self) -> f64 {
        median(&self.absolute)
    }

    /// Whether [`NormalizedErrors::mean_squared`] lies in the two-sided
    /// 95 % band of the mean of as many chi-square(1) values as runs.
    pub fn consistent(&self) -> bool {
        let n = self.absolute.len();
        let band = |p| crate::gate::chi_square_quantile(p, n).map(|q| q / n as f64);
        match (band(0.025), band(0.975)) {
            (Some(low), Some(high)) => (low..=high).contains(&self.mean_squared()),
            _ => false,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// (errors in sigmas of 100 runs, mean squared, consistent)
    #[test]
    fn normalized_errors_and_their_band() {
        type ErrorOfRun = fn(usize) -> f64;
        let cases: [(ErrorOfRun, f64, bool); 4] = [
            (|_| 1.0, 1.0, true),
            (|k| if k % 2 == 0 { 1.1 } else { -1.1 }, 1.21, true),
            (|_| 2.0, 4.0, false),
            (|_| 0.5, 0.25, false),
        ];
        for (error, mean_squared, consistent) in cases {
            let mut e = NormalizedErrors::default();
            for k in 0..100 {
                e.add(0.1 * error(k), 0.1);
            }
            assert!((e.mean_squared() - mean_squared).abs() < 1e-12);
            assert_eq!(e.consistent(), consistent, "{mean_squared}");
        }
        assert!(!NormalizedErrors::default().consistent());
        assert!(NormalizedErrors::default().median_absolute().is_nan());
    }

    #[test]
    fn percentiles_interpolate_linearly() {
        let xs = [4.0, 1.0, 3.0, 2.0];
        assert_eq!(median(&xs), 2.5);
        assert_eq!(percentile(&xs, 0.0), 1.0);
        assert_eq!(percentile(&xs, 100.0), 4.0);
        // h = 3 * 0.95 = 2.85 -> 3 + 0.85 * (4 - 3)
        assert!((p95(&xs) - 3.85).abs() < 1e-12);
        let xs: Vec<f64> = (1..=20).map(f64::from).collect();
        // h = 19 * 0.95 = 18.05 -> 19.05
        assert!((p95(&xs) - 19.05).abs() < 1e-12);
        assert_eq!(median(&[7.0]), 7.0);
        assert_eq!(p95(&[7.0]), 7.0);
        assert_eq!(percentile(&[1.0, 2.0, 3.0], 50.0), 2.0);
    }

    #[test]
    fn moments() {
        let xs = [2.0, 4.0, 4.0, 4.0, 5.0, 5.0, 7.0, 9.0];
        assert_eq!(mean(&xs), 5.0);
        assert!((std_dev(&xs) - (32.0f64 / 7.0).sqrt()).abs() < 1e-12);
        assert_eq!(std_dev(&[3.0]), 0.0);
        assert!((rms(&[3.0, 4.0]) - 12.5f64.sqrt()).abs() < 1e-12);
        assert_eq!(max(&xs), 9.0);
        assert_eq!(min(&xs), 2.0);
    }

    #[test]
    fn empty_and_nan() {
        assert!(median(&[]).is_nan());
        assert!(mean(&[]).is_nan());
        assert!(std_dev(&[]).is_nan());
        let s = Summary::of(&[]);
        assert!(s.median.is_nan() && s.p95.is_nan() && s.max.is_nan());
        assert!(max(&[1.0, f64::NAN]).is_nan());
        assert_eq!(median(&[1.0, 2.0, f64::NAN]), 2.0);
    }

    #[test]
    fn summary_matches_functions() {
        let xs = [0.3, 0.1, 0.9, 0.5, 0.7];
        let s = Summary::of(&xs);
        assert_eq!(s.median, median(&xs));
        assert_eq!(s.p95, p95(&xs));
        assert_eq!(s.max, max(&xs));
    }
}
