//! DVL rows with only some cells empty: the reader takes them (an empty cell
//! is "no value"), but a row that is neither complete nor wholly empty is not
//! "no bottom lock" and is not used as a measurement: an error naming the line
//! and column, a warning with `--lenient`.

use nav_runtime::log::{DvlRow, LogDir, Row, Warning, WarningKind};

use super::{line_of, PreflightOptions, Report};

/// Rows listed before the rest are only counted.
const LISTED: usize = 3;

pub(super) fn check(log: &LogDir, options: &PreflightOptions, report: &mut Report) {
    let Some(rows) = &log.dvl else { return };
    let mut found = 0usize;
    for (i, r) in rows.iter().enumerate() {
        let cells = [r.vx, r.vy, r.vz];
        let empty = cells.iter().filter(|c| c.is_none()).count();
        if empty == 0 || empty == 3 {
            continue;
        }
        found += 1;
        if found > LISTED {
            continue;
        }
        let column = DvlRow::COLUMNS[1 + cells.iter().position(Option::is_none).unwrap_or(0)];
        let mut w = Warning::about(
            WarningKind::SkippedRow,
            DvlRow::FILE,
            "empty cell in a row with values: the row is not used (all three cells \
             empty = no bottom lock; otherwise every cell needs a value)",
        )
        .with_key(column);
        if let Some(line) = line_of::<DvlRow>(log, i) {
            w = w.at_line(line);
        }
        report.error_unless(options.lenient, w);
    }
    if found > LISTED {
        report.error_unless(
            options.lenient,
            Warning::about(
                WarningKind::SkippedRow,
                DvlRow::FILE,
                format!("{} more partly empty rows", found - LISTED),
            ),
        );
    }
}
