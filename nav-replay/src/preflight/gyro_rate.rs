//! Gyro rates against a physical limit and against the heading reference:
//! a gyro file in deg/s, or a z axis of the wrong sign.

use nav_runtime::log::{ImuRow, LogDir, Row, Warning, WarningKind};

use super::Report;

/// Largest rate a common gyro measures (2000 deg/s), rad/s.
pub(super) const MAX_RATE: f64 = 35.0;

/// Smallest heading change (rad) over which the gyro is compared with it.
const MIN_TURN: f64 = 0.5;

/// The largest gyro rate beyond [`MAX_RATE`] and its line.
#[derive(Debug, Default)]
pub(super) struct Fold {
    worst: Option<(Option<u64>, f64)>,
}

impl Fold {
    pub(super) fn imu(&mut self, line: Option<u64>, r: &ImuRow) {
        let w = (r.gx * r.gx + r.gy * r.gy + r.gz * r.gz).sqrt();
        if w > MAX_RATE && self.worst.is_none_or(|(_, m)| w > m) {
            self.worst = Some((line, w));
        }
    }

    /// A rate above [`MAX_RATE`] anywhere is an error (deg/s?). Otherwise,
    /// over the head of the log: when `heading.csv` (or the truth yaw) turns
    /// by at least [`MIN_TURN`], the integrated `gz` over the same interval
    /// must agree with it: a ratio near 57.3 is a deg/s file, a negative
    /// ratio a z axis pointing up (both errors); other ratios off by more
    /// than 50 % are warnings. `beyond` tells, for the heading and the truth
    /// yaw, whether the whole file has values beyond 2 pi (then the
    /// comparison is not made: the angle range check reports them).
    pub(super) fn finish(&self, head: &LogDir, beyond: (bool, bool), report: &mut Report) {
        if let Some((line, w)) = self.worst {
            let mut warning = Warning::about(
                WarningKind::Suspicious,
                <ImuRow as Row>::FILE,
                if w > 1e4 {
                    format!("|omega| = {w:e} rad/s: not a physical rate")
                } else {
                    format!(
                        "|omega| = {w:.1} rad/s, beyond {MAX_RATE} rad/s (2000 deg/s, the range \
                         of common gyros): deg/s? the format is rad/s"
                    )
                },
            )
            .with_key("gx,gy,gz");
            if let Some(line) = line {
                warning = warning.at_line(line);
            }
            report.error(warning);
            return;
        }
        turn(head, beyond, report);
    }
}

fn turn(log: &LogDir, beyond: (bool, bool), report: &mut Report) {
    let (reference, file, beyond): (Vec<(f64, f64)>, &str, bool) = match (&log.heading, &log.truth)
    {
        (Some(h), _) if h.len() >= 2 => (
            h.iter().map(|r| (r.t, r.heading)).collect(),
            "heading.csv",
            beyond.0,
        ),
        (_, Some(t)) if t.len() >= 2 => (
            t.iter().map(|r| (r.t, r.yaw)).collect(),
            "truth.csv",
            beyond.1,
        ),
        _ => return,
    };
    if beyond {
        return; // angle_range reports it.
    }
    // The reference sample of largest unwrapped change from the first.
    let mut unwrapped = 0.0;
    let mut best = (0usize, 0.0f64);
    for k in 1..reference.len() {
        let d = reference[k].1 - reference[k - 1].1;
        unwrapped += (d + core::f64::consts::PI).rem_euclid(2.0 * core::f64::consts::PI)
            - core::f64::consts::PI;
        if unwrapped.abs() > best.1.abs() {
            best = (k, unwrapped);
        }
    }
    if best.1.abs() < MIN_TURN {
        return;
    }
    let (t0, t1) = (reference[0].0, reference[best.0].0);
    let mut integral = 0.0;
    for w in log.imu.windows(2) {
        let (a, b) = (w[0].t.max(t0), w[1].t.min(t1));
        if b > a {
            integral += w[1].gz * (b - a);
        }
    }
    let (imu_t0, imu_t1) = log.imu_time_span().unwrap_or((0.0, 0.0));
    if imu_t0 > t0 || imu_t1 < t1 {
        return; // the IMU does not cover the turn
    }
    let ratio = integral / best.1;
    let turn = best.1.to_degrees();
    let msg = |cause: &str| {
        Warning::about(
            WarningKind::Suspicious,
            <ImuRow as Row>::FILE,
            format!(
                "integrated gz over t = {t0:.1}..{t1:.1} s is {ratio:.2} times the {turn:.0} deg \
                 turn of {file}: {cause}"
            ),
        )
        .with_key("gz")
    };
    if (40.0..=80.0).contains(&ratio) {
        report.error(msg("deg/s? the format is rad/s"));
    } else if (1.0 / 80.0..=1.0 / 40.0).contains(&ratio) {
        report.error(msg("the reference in degrees? the format is radians"));
    } else if (-1.5..=-0.5).contains(&ratio) {
        report.error(msg("FLU axes (z up)? the format is FRD (z down)"));
    } else if !(0.5..=1.5).contains(&ratio) {
        report.warn(msg("check the gyro scale and axes"));
    }
}
