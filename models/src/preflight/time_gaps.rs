//! Time stamps: IMU gaps beyond a multiple of the IMU period (a hole or a
//! clock jump), too few IMU rows, and aiding rows far outside the IMU's span.

use nav_runtime::log::{LogDir, Row, Warning, WarningKind};

use super::{line_of, PreflightOptions, Report};

/// Aiding rows further than this outside the IMU span are a clock error, s.
const CLOCK_JUMP: f64 = 3600.0;

/// Rows this close outside the IMU span are not reported, s.
const MARGIN: f64 = 1.0;

/// Findings listed per check before the rest are only counted.
const LISTED: usize = 3;

/// The median IMU interval over the first 10 000 intervals, s.
fn median_period(t: &[f64]) -> Option<f64> {
    let mut dt: Vec<f64> = t.windows(2).take(10_000).map(|w| w[1] - w[0]).collect();
    if dt.is_empty() {
        return None;
    }
    dt.sort_by(f64::total_cmp);
    Some(dt[dt.len() / 2])
}

pub(super) fn check(log: &LogDir, options: &PreflightOptions, report: &mut Report) {
    use nav_runtime::log::ImuRow;
    if log.imu.len() < 2 {
        report.error(Warning::about(
            WarningKind::ImuGap,
            ImuRow::FILE,
            format!(
                "{} IMU row(s): at least 2 are needed to propagate the state",
                log.imu.len()
            ),
        ));
        return;
    }
    let t: Vec<f64> = log.imu.iter().map(|r| r.t).collect();
    let Some(period) = median_period(&t) else {
        return;
    };
    let limit = options.max_gap_periods * period;
    let mut gaps = 0usize;
    for i in 1..t.len() {
        let dt = t[i] - t[i - 1];
        if dt <= limit {
            continue;
        }
        gaps += 1;
        if gaps > LISTED {
            continue;
        }
        let (a, b) = (line_of::<ImuRow>(log, i - 1), line_of::<ImuRow>(log, i));
        let between = match (a, b) {
            (Some(a), Some(b)) => format!("lines {a} and {b}"),
            _ => "two rows".to_string(),
        };
        let mut w = Warning::about(
            WarningKind::ImuGap,
            ImuRow::FILE,
            format!(
                "gap of {dt:.6} s between {between} (t = {} and t = {}; IMU period {period:.6} s, \
                 limit {} periods): missing data or a clock jump",
                t[i - 1],
                t[i],
                options.max_gap_periods
            ),
        )
        .with_key("t");
        if let Some(a) = a {
            w = w.at_line(a);
        }
        report.error_unless(options.lenient, w);
    }
    if gaps > LISTED {
        report.error_unless(
            options.lenient,
            Warning::about(
                WarningKind::ImuGap,
                ImuRow::FILE,
                format!("{} more IMU gaps", gaps - LISTED),
            ),
        );
    }
    let (t0, t1) = (t[0], t[t.len() - 1]);
    outside::<nav_runtime::log::DvlRow>(log, log.dvl.as_deref(), t0, t1, options, report);
    outside::<nav_runtime::log::DepthRow>(log, log.depth.as_deref(), t0, t1, options, report);
    outside::<nav_runtime::log::HeadingRow>(log, log.heading.as_deref(), t0, t1, options, report);
    outside::<nav_runtime::log::UsblRow>(log, log.usbl.as_deref(), t0, t1, options, report);
    outside::<nav_runtime::log::SpeedRow>(log, log.speed.as_deref(), t0, t1, options, report);
    outside::<nav_runtime::log::RpmRow>(log, log.rpm.as_deref(), t0, t1, options, report);
    outside::<nav_runtime::log::AltitudeRow>(log, log.altitude.as_deref(), t0, t1, options, report);
    outside::<nav_runtime::log::TruthRow>(log, log.truth.as_deref(), t0, t1, options, report);
}

/// Rows of `R` before the first or after the last IMU sample: a warning (they
/// are not used), an error when more than [`CLOCK_JUMP`] away (a clock jump;
/// a warning with `--lenient`).
fn outside<R: Row>(
    log: &LogDir,
    rows: Option<&[R]>,
    t0: f64,
    t1: f64,
    options: &PreflightOptions,
    report: &mut Report,
) {
    let Some(rows) = rows.filter(|r| !r.is_empty()) else {
        return;
    };
    let before = rows.partition_point(|r| r.t() < t0 - MARGIN);
    let after = rows.len() - rows.partition_point(|r| r.t() <= t1 + MARGIN);
    let far = |i: usize, d: f64| {
        let mut w = Warning::about(
            WarningKind::OutsideImuSpan,
            R::FILE,
            format!(
                "t = {} is {d:.1} s outside the IMU span {t0}..{t1} s: a clock jump?",
                rows[i].t()
            ),
        )
        .with_key("t");
        if let Some(line) = line_of::<R>(log, i) {
            w = w.at_line(line);
        }
        w
    };
    if before > 0 && t0 - rows[0].t() > CLOCK_JUMP {
        report.error_unless(options.lenient, far(0, t0 - rows[0].t()));
    } else if after > 0 && rows[rows.len() - 1].t() - t1 > CLOCK_JUMP {
        let last = rows.len() - 1;
        report.error_unless(options.lenient, far(last, rows[last].t() - t1));
    } else if before + after > 0 && R::FILE != "truth.csv" {
        report.warn(Warning::about(
            WarningKind::OutsideImuSpan,
            R::FILE,
            format!(
                "{before} row(s) before and {after} row(s) after the IMU span {t0}..{t1} s are not used"
            ),
        ));
    }
}
