//! Is the recording static? The means of the eighths of the record are
//! compared (docs/allan.md, "Recording"): a turn changes a gyro's mean, a
//! tilt changes the direction of gravity, an acceleration its magnitude.
//! Thresholds are physical (1 deg/s, 2 deg, 0.5 m/s^2) and also at least six
//! standard errors of the compared means, so a noisy but static sensor
//! passes.

use super::{AllanError, AXES};

/// Parts the record is cut into.
const PARTS: usize = 8;
/// A change of mean rate between parts above this is a turn, rad/s (1 deg/s).
const MAX_RATE_CHANGE: f64 = 1.0 * core::f64::consts::PI / 180.0;
/// A change of gravity direction above this is a tilt, rad (2 deg).
const MAX_TILT: f64 = 2.0 * core::f64::consts::PI / 180.0;
/// A change of the specific force magnitude above this is an acceleration, m/s^2.
const MAX_FORCE_CHANGE: f64 = 0.5;
/// Standard errors a change must also exceed.
const SIGMAS: f64 = 6.0;

/// The standard deviation of the white part of a column, from its first
/// differences (blind to slow motion, which would inflate a plain standard
/// deviation and hide itself).
fn white_sd(samples: &[[f64; 6]], j: usize) -> f64 {
    let n = samples.len().saturating_sub(1).max(1) as f64;
    let ss: f64 = samples
        .windows(2)
        .map(|w| (w[1][j] - w[0][j]).powi(2))
        .sum();
    (ss / n / 2.0).sqrt()
}

/// `Err(NotStatic)` naming what moved and by how much.
pub(super) fn check(samples: &[[f64; 6]]) -> Result<(), AllanError> {
    let len = samples.len() / PARTS;
    if len < 2 {
        return Ok(());
    }
    let means: Vec<[f64; 6]> = samples
        .chunks_exact(len)
        .take(PARTS)
        .map(|part| {
            let mut m = [0.0; 6];
            for row in part {
                for (a, v) in m.iter_mut().zip(row) {
                    *a += v / len as f64;
                }
            }
            m
        })
        .collect();
    let standard_error = |j: usize| white_sd(samples, j) / (len as f64).sqrt();
    for (j, (name, _)) in AXES.iter().enumerate().take(3) {
        let (lo, hi) = means
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), m| {
                (lo.min(m[j]), hi.max(m[j]))
            });
        if hi - lo > MAX_RATE_CHANGE.max(SIGMAS * standard_error(j)) {
            return Err(AllanError::NotStatic {
                reason: format!(
                    "the mean of {name} changes by {:.4} rad/s ({:.2} deg/s) between eighths of the record: the sensor turned",
                    hi - lo,
                    (hi - lo).to_degrees()
                ),
            });
        }
    }
    let force = |m: &[f64; 6]| (m[3] * m[3] + m[4] * m[4] + m[5] * m[5]).sqrt();
    let se = (3..6).map(standard_error).fold(0.0, f64::max);
    let (lo, hi) = means
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), m| {
            (lo.min(force(m)), hi.max(force(m)))
        });
    if hi - lo > MAX_FORCE_CHANGE.max(SIGMAS * se) {
        return Err(AllanError::NotStatic {
            reason: format!(
                "the specific force magnitude changes by {:.3} m/s^2 between eighths of the record: the sensor accelerated",
                hi - lo
            ),
        });
    }
    let g = force(&means[0]);
    if g > 0.0 {
        for m in &means[1..] {
            let (a, b) = (&means[0], m);
            let dot = a[3] * b[3] + a[4] * b[4] + a[5] * b[5];
            let angle = (dot / (force(a) * force(b))).clamp(-1.0, 1.0).acos();
            if angle > MAX_TILT.max(SIGMAS * se / g) {
                return Err(AllanError::NotStatic {
                    reason: format!(
                        "the direction of gravity changes by {:.2} deg between eighths of the record: the sensor was tilted or moved",
                        angle.to_degrees()
                    ),
                });
            }
        }
    }
    Ok(())
}
