//! Depth against `[initial] depth`: a depth sensor of the wrong sign or in
//! feet, and an initial depth beyond any physical value.

use nav_runtime::log::{DepthRow, Meta, Row, UsblRow, Warning, WarningKind};

use super::Report;

/// Largest plausible `|depth|` (also altitude as negative depth), m.
pub(super) const MAX_DEPTH: f64 = 1e5;

/// Feet per metre.
const FEET: f64 = 1.0 / 0.3048;

/// The first depth row, and the first depth and USBL rows with `|depth|`
/// beyond [`MAX_DEPTH`].
#[derive(Debug, Default)]
pub(super) struct Fold {
    first_depth: Option<(Option<u64>, f64)>,
    depth_beyond: Option<(Option<u64>, f64)>,
    usbl_beyond: Option<(Option<u64>, f64)>,
}

impl Fold {
    pub(super) fn depth(&mut self, line: Option<u64>, r: &DepthRow) {
        self.first_depth.get_or_insert((line, r.depth));
        if self.depth_beyond.is_none() && r.depth.abs() > MAX_DEPTH {
            self.depth_beyond = Some((line, r.depth));
        }
    }

    pub(super) fn usbl(&mut self, line: Option<u64>, r: &UsblRow) {
        if self.usbl_beyond.is_none() && r.depth.abs() > MAX_DEPTH {
            self.usbl_beyond = Some((line, r.depth));
        }
    }

    /// `[initial] depth` or `[usbl] depth` beyond [`MAX_DEPTH`] is an error
    /// naming the key; so is the first depth (then USBL depth) row beyond it. The first depth
    /// sample is compared with `[initial] depth` (USBL depths are only
    /// bounded: a USBL's depth is often that of another reference): equal
    /// within a tolerance is fine; the negative of it is a sign error, 3.28
    /// times it feet (both errors when `|initial depth| >= 2 m`); otherwise a
    /// warning.
    pub(super) fn finish(&self, meta: &Meta, report: &mut Report) {
        let d0 = meta.initial.depth;
        // The USBL transducer's depth enters every fix's geometry.
        let given = [
            ("initial.depth", Some(d0)),
            ("usbl.depth", meta.usbl.map(|u| u.depth)),
        ];
        if let Some((key, d)) = given
            .into_iter()
            .find_map(|(key, d)| Some((key, d?)).filter(|(_, d)| d.abs() > MAX_DEPTH))
        {
            report.error(
                Warning::about(
                    WarningKind::Suspicious,
                    "meta.toml",
                    format!("{d} m is beyond any physical depth (|depth| <= {MAX_DEPTH} m)"),
                )
                .with_key(key),
            );
            return;
        }
        if bound(DepthRow::FILE, self.depth_beyond, report)
            || bound(UsblRow::FILE, self.usbl_beyond, report)
        {
            return;
        }
        let sigma = meta.initial_sigma.and_then(|s| s.position).unwrap_or(0.0);
        // An attitude-only meta.toml has no initial depth to compare with.
        if let (Some((line, d)), true) = (self.first_depth, d0.is_finite()) {
            compare(DepthRow::FILE, line, d, d0, sigma, "depth", report);
        }
    }
}

/// An error naming the first row with `|depth|` beyond [`MAX_DEPTH`]; `true`
/// if there is one.
fn bound(file: &str, beyond: Option<(Option<u64>, f64)>, report: &mut Report) -> bool {
    let Some((line, d)) = beyond else {
        return false;
    };
    let mut w = Warning::about(
        WarningKind::Suspicious,
        file,
        format!("{d} m is beyond any physical depth (|depth| <= {MAX_DEPTH} m)"),
    )
    .with_key("depth");
    if let Some(line) = line {
        w = w.at_line(line);
    }
    report.error(w);
    true
}

fn compare(
    file: &str,
    line: Option<u64>,
    d: f64,
    d0: f64,
    sigma: f64,
    column: &str,
    report: &mut Report,
) {
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
        file,
        format!(
            "first {column} {d} m where [initial] depth is {d0} m{}",
            cause.map(|c| format!(": {c}")).unwrap_or_else(|| {
                ": check the sensor offset or the initial depth".to_string()
            })
        ),
    )
    .with_key(column);
    if let Some(line) = line {
        w = w.at_line(line);
    }
    if cause.is_some() {
        report.error(w);
    } else {
        report.warn(w);
    }
}
