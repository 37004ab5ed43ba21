//! Angle columns against their range: a heading or truth attitude in degrees.

use core::f64::consts::PI;

use nav_runtime::log::{HeadingRow, Row, TruthRow, Warning, WarningKind};

use super::Report;

/// The value of largest `|value|` beyond 2 pi of one column, and its line.
#[derive(Debug, Default, Clone, Copy)]
struct Beyond {
    worst: Option<(Option<u64>, f64)>,
}

impl Beyond {
    fn row(&mut self, line: Option<u64>, v: f64) {
        if v.abs() > 2.0 * PI && self.worst.is_none_or(|(_, w)| v.abs() > w.abs()) {
            self.worst = Some((line, v));
        }
    }

    fn finish(&self, file: &str, column: &str, report: &mut Report) {
        let Some((line, v)) = self.worst else {
            return;
        };
        let mut w = Warning::about(
            WarningKind::Suspicious,
            file,
            format!("{column} values reach {v}: degrees? the format is radians (|value| <= 2 pi)"),
        )
        .with_key(column);
        if let Some(line) = line {
            w = w.at_line(line);
        }
        report.error(w);
    }
}

/// The largest heading and truth roll, pitch and yaw beyond 2 pi.
#[derive(Debug, Default)]
pub(super) struct Fold {
    heading: Beyond,
    roll: Beyond,
    pitch: Beyond,
    yaw: Beyond,
}

impl Fold {
    pub(super) fn heading(&mut self, line: Option<u64>, r: &HeadingRow) {
        self.heading.row(line, r.heading);
    }

    pub(super) fn truth(&mut self, line: Option<u64>, r: &TruthRow) {
        self.roll.row(line, r.roll);
        self.pitch.row(line, r.pitch);
        self.yaw.row(line, r.yaw);
    }

    /// Whether the heading, and the truth yaw, have a value beyond 2 pi.
    pub(super) fn reference_beyond(&self) -> (bool, bool) {
        (self.heading.worst.is_some(), self.yaw.worst.is_some())
    }

    /// `heading.csv` and the truth's roll, pitch and yaw beyond 2 pi are
    /// errors (degrees?).
    pub(super) fn finish(&self, report: &mut Report) {
        self.heading.finish(HeadingRow::FILE, "heading", report);
        self.roll.finish(TruthRow::FILE, "roll", report);
        self.pitch.finish(TruthRow::FILE, "pitch", report);
        self.yaw.finish(TruthRow::FILE, "yaw", report);
    }
}
