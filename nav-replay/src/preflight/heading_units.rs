//! A compass file in degrees whose values stay inside the radian range (a
//! heading near north): its sample-to-sample changes, after the turn the gyro
//! measured, are about 57 times the noise `[sensors.heading]` declares.

use nav_runtime::log::{HeadingRow, LogDir, LogMapping, Row, Warning, WarningKind};

use super::{declared, Report};

/// Residual scale (against the declared noise) beyond which the file is
/// suspect.
const FACTOR: f64 = 15.0;

/// The median of `|wrap(h_k - h_(k-1)) - integral of gz|` over consecutive
/// heading samples, against the `0.954 sqrt(2) sigma` a heading noise of
/// `sigma` gives (median of the absolute difference of two normal draws):
/// beyond [`FACTOR`] times and consistent with degrees (within a factor 5 once
/// converted) an error, otherwise beyond [`FACTOR`] a warning; below it by
/// [`FACTOR`], see [`too_small`].
/// Runs on the head of the log (see [`super::PreflightOptions::head_seconds`]).
pub(super) fn check(log: &LogDir, mapping: &LogMapping, report: &mut Report) {
    let (Some(rows), Some(noise)) = (&log.heading, log.meta.sensors.heading) else {
        return;
    };
    if rows.len() < 5 || log.imu.len() < 2 {
        return;
    }
    let imu = &log.imu;
    let (t0, t1) = (imu[0].t, imu[imu.len() - 1].t);
    // Integral of gz from the first IMU time to each IMU time.
    let mut cumulative = Vec::with_capacity(imu.len());
    let mut acc = 0.0;
    cumulative.push(0.0);
    for w in imu.windows(2) {
        acc += w[1].gz * (w[1].t - w[0].t);
        cumulative.push(acc);
    }
    let integral_to = |t: f64| {
        let i = imu.partition_point(|r| r.t <= t).max(1) - 1;
        cumulative[i]
    };
    use core::f64::consts::PI;
    let mut residuals: Vec<f64> = rows
        .windows(2)
        .filter(|w| w[0].t >= t0 && w[1].t <= t1)
        .map(|w| {
            let dh = (w[1].heading - w[0].heading + PI).rem_euclid(2.0 * PI) - PI;
            (dh - (integral_to(w[1].t) - integral_to(w[0].t))).abs()
        })
        .collect();
    if residuals.len() < 4 {
        return;
    }
    residuals.sort_by(f64::total_cmp);
    let median = residuals[residuals.len() / 2];
    let expected = 0.954 * core::f64::consts::SQRT_2 * noise.noise_sigma;
    if median * FACTOR < expected {
        too_small(median, expected, noise.noise_sigma, mapping, report);
        return;
    }
    if median <= FACTOR * expected {
        return;
    }
    let ratio = median / expected;
    let in_radians = median.to_radians() / expected;
    let degrees = (0.2..=5.0).contains(&in_radians);
    let w = Warning::about(
        WarningKind::Suspicious,
        HeadingRow::FILE,
        format!(
            "sample-to-sample changes (after the gyro's turn) are {ratio:.0} times what \
             [sensors.heading] noise_sigma = {} rad gives{}",
            noise.noise_sigma,
            if degrees {
                ": degrees? the format is radians"
            } else {
                ": check the heading noise or the file"
            }
        ),
    )
    .with_key("heading");
    if degrees {
        report.error(w);
    } else {
        report.warn(w);
    }
}

/// Changes [`FACTOR`] times smaller than the declared noise: with a unit
/// declared by `[files.heading] units` that converted radians as degrees
/// (the changes then are 57.3 times too small, within a factor 5), an error
/// naming the declaration. Without a declaration nothing is said (the
/// noise may simply be stated generously).
fn too_small(median: f64, expected: f64, sigma: f64, mapping: &LogMapping, report: &mut Report) {
    let Some((_, unit)) = declared::unit(mapping, "heading", "heading") else {
        return;
    };
    if unit == "rad" || !(0.2..=5.0).contains(&(median.to_degrees() / expected)) {
        return;
    }
    report.error(
        Warning::about(
            WarningKind::Suspicious,
            HeadingRow::FILE,
            format!(
                "sample-to-sample changes (after the gyro's turn) are {:.3} times what \
                 [sensors.heading] noise_sigma = {sigma} rad gives: {}",
                median / expected,
                declared::scale_cause(mapping, "heading", "heading", "radians", "degrees", false)
            ),
        )
        .with_key("heading"),
    );
}
