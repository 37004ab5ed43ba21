//! Truth values: a truth file with no rows, or a value beyond physical
//! bounds, would give a score that means nothing.

use nav_runtime::log::{Row, TruthRow, Warning, WarningKind};

use super::depth_consistency::MAX_DEPTH;
use super::Report;

/// Largest plausible truth speed, m/s.
const MAX_SPEED: f64 = 1000.0;

/// The first truth row with a value beyond physical bounds.
#[derive(Debug, Default)]
pub(super) struct Fold {
    bad: Option<(Option<u64>, &'static str, String)>,
}

impl Fold {
    pub(super) fn row(&mut self, line: Option<u64>, r: &TruthRow) {
        if self.bad.is_some() {
            return;
        }
        let speed = (r.vn * r.vn + r.ve * r.ve + r.vd * r.vd).sqrt();
        if r.depth.abs() > MAX_DEPTH {
            self.bad = Some((
                line,
                "depth",
                format!("depth {} m is beyond {MAX_DEPTH} m", r.depth),
            ));
        } else if speed > MAX_SPEED {
            self.bad = Some((
                line,
                "vn,ve,vd",
                format!("speed {speed} m/s is beyond {MAX_SPEED} m/s"),
            ));
        }
    }

    /// A header-only `truth.csv` (`empty`) is an error (nothing to score); so
    /// is the first row with `|depth|` beyond 100 km or a speed beyond
    /// 1000 m/s.
    pub(super) fn finish(&self, empty: bool, report: &mut Report) {
        if empty {
            report.error(Warning::about(
                WarningKind::Suspicious,
                TruthRow::FILE,
                "no rows after the header: nothing to score (remove the file to replay without \
                 scoring)",
            ));
            return;
        }
        if let Some((line, column, msg)) = &self.bad {
            let mut w = Warning::about(
                WarningKind::Suspicious,
                TruthRow::FILE,
                format!("{msg}: not a physical value, the score would mean nothing"),
            )
            .with_key(column);
            if let Some(line) = line {
                w = w.at_line(*line);
            }
            report.error(w);
        }
    }
}
