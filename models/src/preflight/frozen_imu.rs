//! A frozen IMU: the gyro triple repeating one value for longer than noise
//! and resolution explain (the rule of `nav_runtime::stuck`).

use nav_runtime::log::{ImuRow, LogDir, Row, Warning, WarningKind};
use nav_runtime::stuck::StuckDetector;

use super::{line_of, PreflightOptions, Report};

/// Gyro noise sigma assumed when `[sensors.imu]` is absent, rad/s.
const DEFAULT_GYRO_SIGMA: f64 = 1e-6;

/// False-alarm probability per sample of the frozen-IMU test.
const FALSE_ALARM: f64 = 1e-9;

/// The gyro's output resolution: the smallest nonzero step between
/// consecutive samples of one axis (0 when every value repeats).
fn resolution(rows: &[ImuRow]) -> f64 {
    let mut q = f64::INFINITY;
    for w in rows.windows(2) {
        for d in [w[1].gx - w[0].gx, w[1].gy - w[0].gy, w[1].gz - w[0].gz] {
            if d != 0.0 && d.abs() < q {
                q = d.abs();
            }
        }
    }
    if q.is_finite() {
        q
    } else {
        0.0
    }
}

/// A run of identical gyro triples that is both longer than
/// [`StuckDetector::required_repeats`] samples (for the logged gyro noise and
/// the observed resolution) and longer than `frozen_seconds` is an error
/// naming its first and last lines (a warning with `--lenient`, and when
/// `[sensors.imu]` is absent: a noise-free synthetic IMU repeats legitimately).
pub(super) fn check(log: &LogDir, options: &PreflightOptions, report: &mut Report) {
    let rows = &log.imu;
    if rows.len() < 2 {
        return;
    }
    let declared = log.meta.sensors.imu.is_some();
    let sigma = log
        .meta
        .sensors
        .imu
        .map_or(DEFAULT_GYRO_SIGMA, |n| n.gyro_noise_sigma);
    let required = StuckDetector::required_repeats(sigma, resolution(rows), FALSE_ALARM) as usize;
    let mut start = 0usize;
    let mut flagged = 0usize;
    for i in 1..=rows.len() {
        let same = i < rows.len() && {
            let (a, b) = (&rows[i], &rows[start]);
            a.gx == b.gx && a.gy == b.gy && a.gz == b.gz
        };
        if same {
            continue;
        }
        let (first, last) = (start, i - 1);
        let count = last - first + 1;
        let span = rows[last].t - rows[first].t;
        if count >= required && span >= options.frozen_seconds {
            flagged += 1;
            if flagged <= 3 {
                let lines = match (line_of::<ImuRow>(log, first), line_of::<ImuRow>(log, last)) {
                    (Some(a), Some(b)) => format!("lines {a}-{b}"),
                    _ => "rows".to_string(),
                };
                let mut w = Warning::about(
                    WarningKind::FrozenImu,
                    ImuRow::FILE,
                    format!(
                        "gyro triple constant for {span:.1} s ({lines}, t = {:.3}..{:.3} s, \
                         {count} samples; noise of {sigma:e} rad/s repeats at most {} times): \
                         frozen IMU",
                        rows[first].t,
                        rows[last].t,
                        required.saturating_sub(1)
                    ),
                )
                .with_key("gx,gy,gz");
                if let Some(line) = line_of::<ImuRow>(log, first) {
                    w = w.at_line(line);
                }
                if declared {
                    report.error_unless(options.lenient, w);
                } else {
                    w.message.push_str(
                        " (a warning: without [sensors.imu] the log does not say the gyro is noisy)",
                    );
                    report.warn(w);
                }
            }
        }
        start = i;
    }
}
