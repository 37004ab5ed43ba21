//! The sampling period of a record from its time stamps (docs/allan.md,
//! "Recording"): the Allan deviation assumes contiguous, evenly spaced
//! samples, so time going backwards or a gap is refused, naming the row.

use super::AllanError;

/// A step longer than this many periods is a gap (samples dropped).
pub const MAX_STEP: f64 = 1.5;

/// The median time step of `times` (s), after checking that every step is
/// positive and at most [`MAX_STEP`] periods.
///
/// # Errors
/// [`AllanError::TooShort`] for fewer than two stamps,
/// [`AllanError::NonFinite`] for a non-finite stamp, [`AllanError::Timing`]
/// for time not increasing or a gap (the row is 1-based, as counted in
/// the samples).
pub fn sampling_period(times: &[f64]) -> Result<f64, AllanError> {
    if times.len() < 2 {
        return Err(AllanError::TooShort {
            samples: times.len(),
            needed: super::MIN_SAMPLES,
        });
    }
    if let Some(k) = times.iter().position(|t| !t.is_finite()) {
        return Err(AllanError::NonFinite {
            sample: k + 1,
            axis: "t",
            value: times[k],
        });
    }
    let steps: Vec<f64> = times.windows(2).map(|w| w[1] - w[0]).collect();
    if let Some(k) = steps.iter().position(|d| *d <= 0.0) {
        return Err(AllanError::Timing {
            sample: k + 2,
            reason: format!(
                "time does not increase ({} s after {} s)",
                times[k + 1],
                times[k]
            ),
        });
    }
    let mut sorted = steps.clone();
    sorted.sort_by(f64::total_cmp);
    let period = sorted[sorted.len() / 2];
    if let Some(k) = steps.iter().position(|d| *d > MAX_STEP * period) {
        return Err(AllanError::Timing {
            sample: k + 2,
            reason: format!(
                "a gap of {:.6} s where the period is {period:.6} s (samples dropped: analyse a contiguous stretch)",
                steps[k]
            ),
        });
    }
    Ok(period)
}
