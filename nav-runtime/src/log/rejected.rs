//! Rejected readings: a non-physical value (`1e300`, `inf`, `nan`, a
//! latitude beyond the pole, a negative altitude) in a non-time column of an
//! aiding sensor's file is a sensor glitch, not a broken file
//! (docs/log-format.md, "Rejected readings"). Its row is skipped, never fed
//! to a filter, and counted; the count and the first such row are a
//! [`Warning`] of kind [`WarningKind::RejectedReading`].
//!
//! Many of them are not glitches but a mistake in the file or its mapping (a
//! unit, a column): a strict reader refuses a file once more than
//! [`REJECTED_FLOOR`] rows and more than one row in [`REJECTED_ONE_IN`] are
//! rejected, or when every row is. Times stay errors: a non-finite time or
//! one going backwards says nothing about where the row belongs.

use std::collections::BTreeMap;
use std::sync::{Arc, Mutex};

use super::error::SkippedRow;
use super::mapping::{quantity, Quantity};
use super::warning::{Warning, WarningKind};

/// How a reader treats a non-physical value in a non-time column of an
/// aiding sensor's file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum NonPhysical {
    /// As any bad row (the default, the behaviour of earlier versions): a
    /// non-finite value is an error (strict) or a skipped row (lenient); a
    /// finite value of any magnitude is read.
    #[default]
    BadRow,
    /// A rejected reading: the row is skipped with a
    /// [`WarningKind::RejectedReading`] warning, in strict reading too
    /// (unless there are too many); a magnitude beyond
    /// [`plausible_limit`] is non-physical too.
    Rejected,
}

/// Rejected rows a strict reader always accepts as glitches.
pub const REJECTED_FLOOR: usize = 10;
/// Beyond [`REJECTED_FLOOR`], a strict reader refuses a file in which more
/// than one row in this many is rejected.
pub const REJECTED_ONE_IN: usize = 100;

/// Largest magnitude a reading of `column` may have, with the bound in
/// words: far beyond any vehicle's, so that only glitches pass it.
pub fn plausible_limit(column: &str) -> (f64, &'static str) {
    match quantity(column) {
        Some(Quantity::Speed) => (1e4, "|value| <= 1e4 m/s"),
        Some(Quantity::Length) => (1e5, "|value| <= 1e5 m"),
        Some(Quantity::Angle) => (1e6, "|value| <= 1e6 rad"),
        Some(Quantity::Rpm) => (1e6, "|value| <= 1e6 rpm"),
        Some(Quantity::MagneticField) => (1e3, "|value| <= 1e3 gauss"),
        Some(Quantity::SpecificForce) => (1e4, "|value| <= 1e4 m/s^2"),
        Some(Quantity::Rate) => (1e4, "|value| <= 1e4 rad/s"),
        Some(Quantity::Time) | None => (1e9, "|value| <= 1e9"),
    }
}

/// What one file's reader rejected so far.
#[derive(Debug, Clone, PartialEq)]
pub struct Rejected {
    /// Rows rejected.
    pub count: usize,
    /// The first of them, with its reason.
    pub first: SkippedRow,
}

impl Rejected {
    /// The warning: file, the first row's line and column, the count.
    pub fn warning(&self) -> Warning {
        let rows = if self.count == 1 { "row" } else { "rows" };
        Warning::about(
            WarningKind::RejectedReading,
            &self.first.file,
            format!(
                "{} {rows} skipped as non-physical readings (first: {})",
                self.count, self.first.problem
            ),
        )
        .at_line(self.first.line)
        .with_key(&self.first.column)
    }
}

/// The rejected readings of every file read through one log, shared by the
/// readers that log opens (and by its clones), so that a replay that holds
/// its readers inside an event stream still learns them at the end. Two
/// readers of one file (a replay and a check beside it) reject the same
/// rows: the tally keeps the larger count, not the sum.
#[derive(Debug, Clone, Default)]
pub struct RejectedTally(Arc<Mutex<BTreeMap<String, Rejected>>>);

impl RejectedTally {
    /// Records that the reader of `r.first.file` has rejected `r.count` rows.
    pub fn record(&self, r: &Rejected) {
        if let Ok(mut map) = self.0.lock() {
            match map.get_mut(&r.first.file) {
                Some(known) if known.count >= r.count => {}
                Some(known) => known.count = r.count,
                None => {
                    map.insert(r.first.file.clone(), r.clone());
                }
            }
        }
    }

    /// One warning per file with rejected rows, in file-name order.
    pub fn warnings(&self) -> Vec<Warning> {
        self.0
            .lock()
            .map(|m| m.values().map(Rejected::warning).collect())
            .unwrap_or_default()
    }
}
