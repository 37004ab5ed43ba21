//! Angle columns against their range: a heading or truth attitude in degrees.

use core::f64::consts::PI;

use nav_runtime::log::{HeadingRow, LogDir, Row, TruthRow, Warning, WarningKind};

use super::{line_of, Report};

/// The row of largest `|value|` beyond 2 pi, if any.
fn beyond<R: Row>(rows: &[R], value: impl Fn(&R) -> f64) -> Option<(usize, f64)> {
    let mut worst: Option<(usize, f64)> = None;
    for (i, r) in rows.iter().enumerate() {
        let v = value(r);
        if v.abs() > 2.0 * PI && worst.is_none_or(|(_, w)| v.abs() > w.abs()) {
            worst = Some((i, v));
        }
    }
    worst
}

fn report_beyond<R: Row>(
    log: &LogDir,
    rows: &[R],
    column: &str,
    value: impl Fn(&R) -> f64,
    report: &mut Report,
) {
    let Some((i, v)) = beyond(rows, value) else {
        return;
    };
    let mut w = Warning::about(
        WarningKind::Suspicious,
        R::FILE,
        format!("{column} values reach {v}: degrees? the format is radians (|value| <= 2 pi)"),
    )
    .with_key(column);
    if let Some(line) = line_of::<R>(log, i) {
        w = w.at_line(line);
    }
    report.error(w);
}

/// `heading.csv` and the truth's roll, pitch and yaw beyond 2 pi are errors
/// (degrees?).
pub(super) fn check(log: &LogDir, report: &mut Report) {
    if let Some(h) = &log.heading {
        report_beyond::<HeadingRow>(log, h, "heading", |r| r.heading, report);
    }
    if let Some(t) = &log.truth {
        report_beyond::<TruthRow>(log, t, "roll", |r| r.roll, report);
        report_beyond::<TruthRow>(log, t, "pitch", |r| r.pitch, report);
        report_beyond::<TruthRow>(log, t, "yaw", |r| r.yaw, report);
    }
}
