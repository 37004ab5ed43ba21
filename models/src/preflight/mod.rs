//! Preflight: checks of a log's values before any filter runs, for the unit,
//! sign, frame and clock mistakes that the reader cannot see (every value is
//! finite and in its file's format, but the file means something else).
//!
//! Each check is one file; [`check`] runs them all and returns a [`Report`] of
//! [`Finding`]s. A clear mistake is an error naming the file, the line or
//! column and the likely cause; a doubtful one is a warning (listed in the
//! JSON `warnings`). `navsim replay` runs the preflight on every log before the
//! model and stops at its first error; `navsim check DIR` prints every finding.
//! Checks and thresholds are described in `docs/trust.md`.

mod aiding_plausibility;
mod angle_range;
mod depth_consistency;
mod finding;
mod frozen_imu;
mod gyro_rate;
mod heading_units;
mod partial_rows;
mod sensor_sections;
mod specific_force;
mod time_gaps;
mod truth_values;

pub use finding::{Finding, Report, Severity};

use nav_runtime::log::{LogDir, Row};

/// What the preflight checks and how strictly.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PreflightOptions {
    /// `--lenient`: IMU gaps and a frozen IMU are warnings instead of errors.
    pub lenient: bool,
    /// An IMU interval longer than this many median IMU periods is a gap.
    pub max_gap_periods: f64,
    /// A gyro triple repeated for at least this long (s), and for more samples
    /// than noise and resolution explain, is a frozen IMU.
    pub frozen_seconds: f64,
    /// Span of the log's start over which the vehicle is assumed near rest
    /// for the specific-force checks, s.
    pub settle_seconds: f64,
    /// Span over which aiding sensors are compared with the initial state, s.
    pub aiding_seconds: f64,
    /// The files the model reads, when known: sections missing for other
    /// files are not reported (and the files are listed as unused).
    pub model_files: Option<&'static [&'static str]>,
}

impl Default for PreflightOptions {
    fn default() -> Self {
        PreflightOptions {
            lenient: false,
            max_gap_periods: 10.0,
            frozen_seconds: 20.0,
            settle_seconds: 5.0,
            aiding_seconds: 60.0,
            model_files: None,
        }
    }
}

/// Runs every check over `log`.
pub fn check(log: &LogDir, options: &PreflightOptions) -> Report {
    let mut report = Report::default();
    specific_force::check(log, options, &mut report);
    gyro_rate::check(log, options, &mut report);
    frozen_imu::check(log, options, &mut report);
    time_gaps::check(log, options, &mut report);
    partial_rows::check(log, options, &mut report);
    angle_range::check(log, &mut report);
    if !report.has_errors() {
        heading_units::check(log, &mut report);
    }
    depth_consistency::check(log, &mut report);
    aiding_plausibility::check(log, options, &mut report);
    truth_values::check(log, &mut report);
    sensor_sections::check(log, options.model_files, &mut report);
    report
}

/// The 1-based line of row `index` of `R`'s file, when the file was read
/// without skipped rows (with skipped rows the index no longer tells the line).
fn line_of<R: Row>(log: &LogDir, index: usize) -> Option<u64> {
    if log.skipped_rows.contains_key(R::FILE) {
        None
    } else {
        Some(index as u64 + 2)
    }
}

/// Rows of `rows` with `t` before `t_end`.
fn rows_until<R: Row>(rows: &[R], t_end: f64) -> &[R] {
    let n = rows.partition_point(|r| r.t() < t_end);
    &rows[..n]
}

#[cfg(test)]
mod tests;
