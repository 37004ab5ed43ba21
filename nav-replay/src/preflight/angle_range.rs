//! Angle columns against their range: a heading or truth attitude in degrees.
//!
//! A heading (or truth yaw) beyond 2 pi is either in degrees or unwrapped
//! (a logger adding the turns made, perhaps since before the log started):
//! continuity tells them apart. An unwrapped heading never steps by pi or
//! more between rows (that is what unwrapping means); a heading in degrees
//! wraps at 360 (a step of 360), and its turns and noise, 57 times larger in
//! number, step by more than pi (3 deg) whenever the vehicle turns faster
//! than a few degrees per row or the compass noise is a degree. A heading in
//! degrees that still never steps by pi (a vehicle holding its heading with
//! a quiet compass) is left to the gyro's turn (`gyro_rate`: a heading
//! change 57 times the integrated rate) and to the compass noise
//! (`heading_units`: changes many times `noise_sigma`), and, first, to the
//! initial yaw: an unwrapped column starts, modulo 2 pi, within
//! [`AGREEMENT`] of `[initial] yaw` (when given), where a heading of 90 deg
//! read as 90 rad is 2 rad away.

use core::f64::consts::PI;

use nav_runtime::log::{HeadingRow, Meta, Row, TruthRow, Warning, WarningKind};
use nav_runtime::math::wrap_angle;

use super::Report;

/// Largest difference, modulo 2 pi, of an unwrapped column's first value
/// from `[initial] yaw`, rad: a compass bias of 10 deg and the initial
/// uncertainty several times over.
const AGREEMENT: f64 = 0.5;

/// The value of largest `|value|` beyond 2 pi of one column, its line, and
/// whether the column is continuous (module docs).
#[derive(Debug, Default, Clone, Copy)]
struct Beyond {
    worst: Option<(Option<u64>, f64)>,
    /// Whether the column may be unwrapped (heading, yaw).
    may_unwrap: bool,
    first: Option<f64>,
    previous: Option<f64>,
    /// A step of pi or more between consecutive rows.
    jump: bool,
}

impl Beyond {
    fn unwrapping() -> Self {
        Beyond {
            may_unwrap: true,
            ..Beyond::default()
        }
    }

    fn row(&mut self, line: Option<u64>, v: f64) {
        if v.abs() > 2.0 * PI && self.worst.is_none_or(|(_, w)| v.abs() > w.abs()) {
            self.worst = Some((line, v));
        }
        self.first.get_or_insert(v);
        if let Some(p) = self.previous {
            self.jump |= (v - p).abs() >= PI;
        }
        self.previous = Some(v);
    }

    /// Whether the column is an unwrapped angle: it may be, never steps by
    /// pi or more, and starts within [`AGREEMENT`] of `initial_yaw` modulo
    /// 2 pi (when known).
    fn unwrapped(&self, initial_yaw: Option<f64>) -> bool {
        let agrees = match (self.first, initial_yaw) {
            (Some(f), Some(y)) if y.is_finite() => wrap_angle(f - y).abs() <= AGREEMENT,
            _ => true,
        };
        self.may_unwrap && !self.jump && agrees
    }

    /// A value beyond 2 pi that unwrapping does not explain.
    fn in_degrees(&self, initial_yaw: Option<f64>) -> bool {
        self.worst.is_some() && !self.unwrapped(initial_yaw)
    }

    fn finish(&self, file: &str, column: &str, initial_yaw: Option<f64>, report: &mut Report) {
        let Some((line, v)) = self.worst else {
            return;
        };
        if self.unwrapped(initial_yaw) {
            return;
        }
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
#[derive(Debug)]
pub(super) struct Fold {
    /// `[initial] yaw`, rad.
    initial_yaw: Option<f64>,
    heading: Beyond,
    roll: Beyond,
    pitch: Beyond,
    yaw: Beyond,
}

impl Fold {
    pub(super) fn new(meta: &Meta) -> Self {
        Fold {
            initial_yaw: meta.initial.yaw,
            heading: Beyond::unwrapping(),
            roll: Beyond::default(),
            pitch: Beyond::default(),
            yaw: Beyond::unwrapping(),
        }
    }

    pub(super) fn heading(&mut self, line: Option<u64>, r: &HeadingRow) {
        self.heading.row(line, r.heading);
    }

    pub(super) fn truth(&mut self, line: Option<u64>, r: &TruthRow) {
        self.roll.row(line, r.roll);
        self.pitch.row(line, r.pitch);
        self.yaw.row(line, r.yaw);
    }

    /// Whether the heading, and the truth yaw, have a value beyond 2 pi that
    /// unwrapping does not explain.
    pub(super) fn reference_beyond(&self) -> (bool, bool) {
        (
            self.heading.in_degrees(self.initial_yaw),
            self.yaw.in_degrees(self.initial_yaw),
        )
    }

    /// `heading.csv` and the truth's roll, pitch and yaw beyond 2 pi are
    /// errors (degrees?), unless the heading or yaw is unwrapped.
    pub(super) fn finish(&self, report: &mut Report) {
        let y = self.initial_yaw;
        self.heading.finish(HeadingRow::FILE, "heading", y, report);
        self.roll.finish(TruthRow::FILE, "roll", y, report);
        self.pitch.finish(TruthRow::FILE, "pitch", y, report);
        self.yaw.finish(TruthRow::FILE, "yaw", y, report);
    }
}
