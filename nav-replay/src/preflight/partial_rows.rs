//! DVL rows with only some cells empty: the reader takes them (an empty cell
//! is "no value"), but a row that is neither complete nor wholly empty is not
//! "no bottom lock" and is not used as a measurement: an error naming the line
//! and column, a warning with `--lenient`.

use nav_runtime::log::{DvlRow, Row, Warning, WarningKind};

use super::{PreflightOptions, Report};

/// Rows listed before the rest are only counted.
const LISTED: usize = 3;

/// The first [`LISTED`] partly empty DVL rows (line, empty column) and the
/// count of all.
#[derive(Debug, Default)]
pub(super) struct Fold {
    listed: Vec<(Option<u64>, &'static str)>,
    found: usize,
}

/// A DVL row neither complete nor wholly empty (no bottom lock).
pub(super) fn is_partial(r: &DvlRow) -> bool {
    let empty = [r.vx, r.vy, r.vz].iter().filter(|c| c.is_none()).count();
    empty != 0 && empty != 3
}

impl Fold {
    pub(super) fn dvl(&mut self, line: Option<u64>, r: &DvlRow) {
        if !is_partial(r) {
            return;
        }
        let cells = [r.vx, r.vy, r.vz];
        self.found += 1;
        if self.found <= LISTED {
            let column = DvlRow::COLUMNS[1 + cells.iter().position(Option::is_none).unwrap_or(0)];
            self.listed.push((line, column));
        }
    }

    /// Partly empty rows found: rows the replay does not use, counted with
    /// the reader's skipped rows (`skipped_rows` of the JSON) when they are
    /// warnings rather than errors.
    pub(super) fn found(&self) -> usize {
        self.found
    }

    pub(super) fn finish(&self, options: &PreflightOptions, report: &mut Report) {
        for &(line, column) in &self.listed {
            let mut w = Warning::about(
                WarningKind::SkippedRow,
                DvlRow::FILE,
                "empty cell in a row with values: the row is not used (all three cells \
                 empty = no bottom lock; otherwise every cell needs a value)",
            )
            .with_key(column);
            if let Some(line) = line {
                w = w.at_line(line);
            }
            report.error_unless(options.lenient, w);
        }
        if self.found > LISTED {
            report.error_unless(
                options.lenient,
                Warning::about(
                    WarningKind::SkippedRow,
                    DvlRow::FILE,
                    format!("{} more partly empty rows", self.found - LISTED),
                ),
            );
        }
    }
}
