//! Depth against `[initial] depth`: a depth sensor of the wrong sign or in
//! feet, and an initial depth beyond any physical value.

use nav_runtime::log::{DepthRow, LogDir, Row, UsblRow, Warning, WarningKind};

use super::{line_of, Report};

/// Largest plausible `|depth|` (also altitude as negative depth), m.
pub(super) const MAX_DEPTH: f64 = 1e5;

/// Feet per metre.
const FEET: f64 = 1.0 / 0.3048;

/// `[initial] depth` beyond [`MAX_DEPTH`] is an error naming the key. The
/// first depth sample is compared with it (USBL depths are only bounded:
/// a USBL's depth is often that of another reference): equal
/// within a tolerance is fine; the negative of it is a sign error, 3.28 times
/// it feet (both errors when `|initial depth| >= 2 m`); otherwise a warning.
pub(super) fn check(log: &LogDir, report: &mut Report) {
    let d0 = log.meta.initial.depth;
    if d0.abs() > MAX_DEPTH {
        report.error(
            Warning::about(
                WarningKind::Suspicious,
                "meta.toml",
                format!("{d0} m is beyond any physical depth (|depth| <= {MAX_DEPTH} m)"),
            )
            .with_key("initial.depth"),
        );
        return;
    }
    if bound::<DepthRow>(log, log.depth.as_deref(), |r| r.depth, report)
        || bound::<UsblRow>(log, log.usbl.as_deref(), |r| r.depth, report)
    {
        return;
    }
    let sigma = log
        .meta
        .initial_sigma
        .and_then(|s| s.position)
        .unwrap_or(0.0);
    if let Some(rows) = &log.depth {
        if let Some(r) = rows.first() {
            compare::<DepthRow>(log, r.depth, d0, sigma, "depth", report);
        }
    }
}

/// An error naming the first row with `|depth|` beyond [`MAX_DEPTH`]; `true`
/// if there is one.
fn bound<R: Row>(
    log: &LogDir,
    rows: Option<&[R]>,
    depth: impl Fn(&R) -> f64,
    report: &mut Report,
) -> bool {
    let Some((i, d)) = rows.and_then(|rows| {
        rows.iter()
            .enumerate()
            .map(|(i, r)| (i, depth(r)))
            .find(|(_, d)| d.abs() > MAX_DEPTH)
    }) else {
        return false;
    };
    let mut w = Warning::about(
        WarningKind::Suspicious,
        R::FILE,
        format!("{d} m is beyond any physical depth (|depth| <= {MAX_DEPTH} m)"),
    )
    .with_key("depth");
    if let Some(line) = line_of::<R>(log, i) {
        w = w.at_line(line);
    }
    report.error(w);
    true
}

fn compare<R: Row>(log: &LogDir, d: f64, d0: f64, sigma: f64, column: &str, report: &mut Report) {
    let tol = 2.0 + 0.1 * d0.abs() + 3.0 * sigma;
    if (d - d0).abs() <= tol {
        return;
    }
    let cause = if d0.abs() >= 2.0 && (d + d0).abs() <= tol {
        Some("wrong sign? depth is positive down")
    } else if d0.abs() >= 2.0 && (d - FEET * d0).abs() <= FEET * tol {
        Some("feet? the format is metres")
    } else {
        None
    };
    let mut w = Warning::about(
        WarningKind::Suspicious,
        R::FILE,
        format!(
            "first {column} {d} m where [initial] depth is {d0} m{}",
            cause.map(|c| format!(": {c}")).unwrap_or_else(|| {
                ": check the sensor offset or the initial depth".to_string()
            })
        ),
    )
    .with_key(column);
    if let Some(line) = line_of::<R>(log, 0) {
        w = w.at_line(line);
    }
    if cause.is_some() {
        report.error(w);
    } else {
        report.warn(w);
    }
}
