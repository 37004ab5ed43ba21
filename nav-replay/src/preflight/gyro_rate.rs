//! Gyro rates against a physical limit and against the heading reference:
//! a gyro file in deg/s, or a z axis of the wrong sign.

use nav_runtime::log::{ImuRow, LogDir, LogMapping, Row, Warning, WarningKind};

use super::{declared, Report};

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
    pub(super) fn finish(
        &self,
        head: &LogDir,
        beyond: (bool, bool),
        mapping: &LogMapping,
        report: &mut Report,
    ) {
        if let Some((line, w)) = self.worst {
            let mut warning = Warning::about(
                WarningKind::Suspicious,
                <ImuRow as Row>::FILE,
                if w > 1e4 {
                    format!("|omega| = {w:e} rad/s: not a physical rate")
                } else {
                    format!(
                        "|omega| = {w:.1} rad/s, beyond {MAX_RATE} rad/s (2000 deg/s, the range \
                         of common gyros): {}",
                        declared::scale_cause(mapping, "imu", "gx", "rad/s", "deg/s", true)
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
        let bias = head.meta.sensors.imu.map(|s| s.gyro_bias_sigma);
        turn(head, beyond, mapping, bias, report);
    }
}

/// Ratio bands (gyro turn over reference turn) of a degree/radian mix-up.
const DEGREE_BAND: (f64, f64) = (40.0, 80.0);

/// Gyro bias assumed without `[sensors.imu] gyro_bias_sigma`, rad/s (a
/// consumer MEMS gyro): the integrated `gz` of a still vehicle drifts by
/// this much per second.
const DEFAULT_GYRO_BIAS: f64 = 1e-3;

fn turn(
    log: &LogDir,
    beyond: (bool, bool),
    mapping: &LogMapping,
    bias: Option<f64>,
    report: &mut Report,
) {
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
    let Some((imu_t0, imu_t1)) = log.imu_time_span() else {
        return;
    };
    // The reference samples the IMU covers.
    let reference: Vec<(f64, f64)> = reference
        .into_iter()
        .filter(|(t, _)| *t >= imu_t0 && *t <= imu_t1)
        .collect();
    if reference.len() < 2 {
        return;
    }
    let t0 = reference[0].0;
    // The unwrapped reference change and the integrated gz from the first
    // reference sample to each sample.
    let mut unwrapped = 0.0;
    let mut integral = 0.0;
    let mut imu = log.imu.windows(2).peekable();
    let mut changes = Vec::with_capacity(reference.len());
    changes.push((t0, 0.0, 0.0));
    for k in 1..reference.len() {
        let d = reference[k].1 - reference[k - 1].1;
        unwrapped += (d + core::f64::consts::PI).rem_euclid(2.0 * core::f64::consts::PI)
            - core::f64::consts::PI;
        let (a_end, b_end) = (reference[k - 1].0, reference[k].0);
        while let Some(w) = imu.peek() {
            let (a, b) = (w[0].t.max(a_end), w[1].t.min(b_end));
            if b > a {
                integral += w[1].gz * (b - a);
            }
            if w[1].t > b_end {
                break;
            }
            imu.next();
        }
        changes.push((b_end, unwrapped, integral));
    }
    let bias = bias.unwrap_or(DEFAULT_GYRO_BIAS);
    // The gyro's turn beyond what its bias could integrate to.
    let gyro_turn = |t: f64, g: f64| (g.abs() - 3.0 * bias * (t - t0)).max(0.0);
    let Some(&(t1, heading_turn, gyro)) = changes.iter().max_by(|a, b| {
        a.1.abs()
            .max(gyro_turn(a.0, a.2))
            .total_cmp(&b.1.abs().max(gyro_turn(b.0, b.2)))
    }) else {
        return;
    };
    if heading_turn.abs() >= MIN_TURN {
        gyro_against(file, (t0, t1), heading_turn, gyro, mapping, report);
    } else if gyro_turn(t1, gyro) >= MIN_TURN {
        reference_against(file, (t0, t1), heading_turn, gyro, mapping, report);
    }
}

/// The gyro's turn against a reference turn of at least [`MIN_TURN`].
fn gyro_against(
    file: &str,
    (t0, t1): (f64, f64),
    reference: f64,
    integral: f64,
    mapping: &LogMapping,
    report: &mut Report,
) {
    let ratio = integral / reference;
    let turn = reference.to_degrees();
    let msg = |cause: &str| {
        Warning::about(
            WarningKind::Suspicious,
            <ImuRow as Row>::FILE,
            format!(
                "integrated gz over t = {t0:.1}..{t1:.1} s is {ratio:.3} times the {turn:.0} deg \
                 turn of {file}: {cause}"
            ),
        )
        .with_key("gz")
    };
    let degrees =
        |too_large| declared::scale_cause(mapping, "imu", "gz", "rad/s", "deg/s", too_large);
    if (DEGREE_BAND.0..=DEGREE_BAND.1).contains(&ratio) {
        report.error(msg(&degrees(true)));
    } else if (1.0 / DEGREE_BAND.1..=1.0 / DEGREE_BAND.0).contains(&ratio) {
        report.error(msg(&degrees(false)));
    } else if (-1.5..=-0.5).contains(&ratio) {
        report.error(msg("FLU axes (z up)? the format is FRD (z down)"));
    } else if !(0.5..=1.5).contains(&ratio) {
        report.warn(msg("check the gyro scale and axes"));
    }
}

/// A reference (heading or truth yaw) that turns by less than [`MIN_TURN`]
/// while the gyro turns by more than its bias explains: a heading in
/// radians read as degrees turns 57.3 times too little.
fn reference_against(
    file: &str,
    (t0, t1): (f64, f64),
    reference: f64,
    integral: f64,
    mapping: &LogMapping,
    report: &mut Report,
) {
    let ratio = reference / integral;
    let (sensor, column) = if file == "heading.csv" {
        ("heading", "heading")
    } else {
        ("truth", "yaw")
    };
    let msg = |cause: &str| {
        Warning::about(
            WarningKind::Suspicious,
            file,
            format!(
                "{column} turns by {:.2} deg over t = {t0:.1}..{t1:.1} s while the gyro turns by \
                 {:.0} deg ({ratio:.3} times): {cause}",
                reference.to_degrees(),
                integral.to_degrees()
            ),
        )
        .with_key(column)
    };
    if (1.0 / DEGREE_BAND.1..=1.0 / DEGREE_BAND.0).contains(&ratio.abs()) {
        report.error(msg(&declared::scale_cause(
            mapping, sensor, column, "radians", "degrees", false,
        )));
    } else if ratio.abs() < 0.5 {
        report.warn(msg("the reference does not follow the gyro's turn"));
    }
}
