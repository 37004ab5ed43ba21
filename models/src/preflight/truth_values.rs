//! Truth values: a truth file with no rows, or a value beyond physical
//! bounds, would give a score that means nothing.

use nav_runtime::log::{LogDir, Row, TruthRow, Warning, WarningKind};

use super::depth_consistency::MAX_DEPTH;
use super::{line_of, Report};

/// Largest plausible truth speed, m/s.
const MAX_SPEED: f64 = 1000.0;

/// A header-only `truth.csv` is an error (nothing to score); so is the first
/// row with `|depth|` beyond 100 km or a speed beyond 1000 m/s.
pub(super) fn check(log: &LogDir, report: &mut Report) {
    let Some(rows) = &log.truth else { return };
    if rows.is_empty() {
        report.error(Warning::about(
            WarningKind::Suspicious,
            TruthRow::FILE,
            "no rows after the header: nothing to score (remove the file to replay without scoring)",
        ));
        return;
    }
    for (i, r) in rows.iter().enumerate() {
        let speed = (r.vn * r.vn + r.ve * r.ve + r.vd * r.vd).sqrt();
        let bad = if r.depth.abs() > MAX_DEPTH {
            Some((
                "depth",
                format!("depth {} m is beyond {MAX_DEPTH} m", r.depth),
            ))
        } else if speed > MAX_SPEED {
            Some((
                "vn,ve,vd",
                format!("speed {speed} m/s is beyond {MAX_SPEED} m/s"),
            ))
        } else {
            None
        };
        if let Some((column, msg)) = bad {
            let mut w = Warning::about(
                WarningKind::Suspicious,
                TruthRow::FILE,
                format!("{msg}: not a physical value, the score would mean nothing"),
            )
            .with_key(column);
            if let Some(line) = line_of::<TruthRow>(log, i) {
                w = w.at_line(line);
            }
            report.error(w);
            return;
        }
    }
}
