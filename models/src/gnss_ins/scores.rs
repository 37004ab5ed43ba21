//! The scores of a `gnss-ins` replay, kept as its estimates come so that
//! neither the estimates nor `reference.csv` and `truth.csv` are held:
//!
//! - the difference to PX4's estimate (`reference.csv`) and the attitude
//!   error against `truth.csv`, from the estimate at every IMU sample
//!   interpolated to each row's time ([`crate::ulog::running_score`]);
//! - the INS errors against `truth.csv` (position, depth, NEES), from the
//!   estimate the replay loop gives at each truth row ([`Scorer`]).
//!
//! Only the tables they are told to keep grow: every row when the series
//! stay in memory, a bounded copy when they are written to files.

use std::path::Path;

use nav_runtime::log::{LogSource, ReferenceRow, TruthRow, Warning, WarningKind};
use serde_json::{Map, Value};

use crate::harness::{RunError, RunTable};
use crate::sdins25::score::{Keep, ScoreError, Scorer, TABLE as ERRORS_TABLE};
use crate::ulog::reference::EstimatePoint;
use crate::ulog::replay::rpy_json;
use crate::ulog::running_score::{ReferenceScore, TruthScore, REFERENCE_COLUMNS, TRUTH_COLUMNS};
use nav_ins::Estimate;
use nav_replay::output::series::SeriesSink;

/// A truth height this far from the initial height is on another datum, m.
pub const TRUTH_DATUM_GAP_M: f64 = 100.0;

/// Name of the table of reference differences.
pub const REFERENCE_TABLE: &str = "reference_difference";
/// Name of the table of attitude errors against truth.
pub const ATTITUDE_TABLE: &str = "attitude_errors";

/// The INS errors against `truth.csv`: the scorer, or why it stopped (an
/// error against one row is not finite), said at the end as the reason the
/// run is not scored.
enum Errors {
    /// Boxed: the scorer is far larger than the error.
    Scoring(Box<Scorer>),
    Stopped(ScoreError),
}

/// The running scores of one replay (see the module docs).
pub struct RunningScores<'a> {
    reference: Option<ReferenceScore<'a>>,
    attitude: Option<TruthScore<'a>>,
    errors: Option<Errors>,
    keep_errors_table: bool,
    initial_height: f64,
    /// The warning about the first truth row's height, once it is seen.
    datum: Option<String>,
    truth_seen: bool,
}

/// What the scores leave for the output besides the metrics and warnings:
/// the tables asked for, in the order the replay has always listed them.
pub struct ScoreTables {
    /// `errors` and `attitude_errors`, when there is truth.
    pub truth: Vec<RunTable>,
    /// `reference_difference`, when there is a reference.
    pub reference: Option<RunTable>,
}

impl<'a> RunningScores<'a> {
    /// The scores against the reference and truth files of `source` (each
    /// only when the file exists), their tables written into `out` (when
    /// given) or else kept in memory when `keep_series`; `initial_height`
    /// (m) is the height the truth's datum is checked against.
    ///
    /// # Errors
    /// A file cannot be opened or its first row read, or a table's file
    /// cannot be created.
    pub fn new(
        source: &LogSource<'a>,
        out: Option<&Path>,
        keep_series: bool,
        initial_height: f64,
    ) -> Result<Self, RunError> {
        let sink = |name: &str, columns: &[&str]| SeriesSink::new(name, columns, out, keep_series);
        let reference = match source.rows::<ReferenceRow>()? {
            Some(rows) => Some(ReferenceScore::new(
                rows,
                sink(REFERENCE_TABLE, &REFERENCE_COLUMNS)?,
            )?),
            None => None,
        };
        let (attitude, errors, keep_errors_table) = match source.rows::<TruthRow>()? {
            Some(rows) => {
                let attitude = TruthScore::new(rows, sink(ATTITUDE_TABLE, &TRUTH_COLUMNS)?)?;
                let keep = Keep::for_replay(ERRORS_TABLE, out, keep_series)?;
                let kept = !matches!(keep, Keep::Nothing);
                (
                    Some(attitude),
                    Some(Errors::Scoring(Box::new(Scorer::new(None, keep)))),
                    kept,
                )
            }
            None => (None, None, false),
        };
        Ok(RunningScores {
            reference,
            attitude,
            errors,
            keep_errors_table,
            initial_height,
            datum: None,
            truth_seen: false,
        })
    }

    /// The estimate at the next IMU sample (in time order).
    ///
    /// # Errors
    /// A row of `reference.csv` or `truth.csv` cannot be read, or a table
    /// written.
    pub fn push_sample(&mut self, point: EstimatePoint) -> Result<(), RunError> {
        if let Some(r) = self.reference.as_mut() {
            r.push(point)?;
        }
        if let Some(t) = self.attitude.as_mut() {
            t.push(point)?;
        }
        Ok(())
    }

    /// The estimate at the next truth row (line `line` of `truth.csv`, in
    /// file order); `None`: no IMU sample near the row.
    ///
    /// # Errors
    /// The `errors` table cannot be written.
    pub fn push_truth(
        &mut self,
        line: Option<u64>,
        row: &TruthRow,
        estimate: Option<&Estimate>,
    ) -> Result<(), RunError> {
        if !self.truth_seen {
            self.truth_seen = true;
            let h0 = self.initial_height;
            if (-row.depth - h0).abs() > TRUTH_DATUM_GAP_M {
                self.datum = Some(format!(
                    "truth.csv: height {:.1} m at t = {} s, the initial height {h0:.1} m: the truth's \
                     vertical datum differs (depth_error_rms_m, nees_mean and nees_position_mean are not meaningful)",
                    -row.depth, row.t
                ));
            }
        }
        let Some(Errors::Scoring(scorer)) = self.errors.as_mut() else {
            return Ok(());
        };
        match scorer.push(line, row, estimate) {
            Ok(()) => Ok(()),
            Err(ScoreError::Write { reason }) => Err(RunError::Invalid(format!(
                "writing the error table: {reason}"
            ))),
            Err(e) => {
                self.errors = Some(Errors::Stopped(e));
                Ok(())
            }
        }
    }

    /// Reads the rest of the files and adds the keys to `metrics`: the
    /// reference keys, and with truth the INS error keys
    /// (`horizontal_error_final_m`, `horizontal_error_rms_m`,
    /// `depth_error_rms_m`, `nees_mean`, `scored_seconds`) and
    /// `attitude_error_rms_deg`; the warnings in the order the replay has
    /// always given them. `imu_span` (the IMU's first and last time) is for
    /// the message of a run that does not overlap the truth.
    ///
    /// # Errors
    /// A row cannot be read, or a table written.
    pub fn finish(
        self,
        imu_span: Option<(f64, f64)>,
        metrics: &mut Map<String, Value>,
        warnings: &mut Vec<Warning>,
    ) -> Result<ScoreTables, RunError> {
        let reference = match self.reference {
            Some(r) => r.finish(metrics, warnings)?,
            None => None,
        };
        let mut truth = Vec::new();
        warnings.extend(
            self.datum
                .map(|d| Warning::about(WarningKind::Suspicious, "truth.csv", d)),
        );
        let scored = match self.errors {
            Some(Errors::Scoring(scorer)) => Some(scorer.finish(imu_span)),
            Some(Errors::Stopped(e)) => Some(Err(e)),
            None => None,
        };
        match scored {
            Some(Ok(s)) => {
                for (k, v) in [
                    ("horizontal_error_final_m", s.horizontal_error_final_m),
                    ("horizontal_error_rms_m", s.horizontal_error_rms_m),
                    ("depth_error_rms_m", s.depth_error_rms_m),
                    ("nees_mean", s.nees_mean),
                    ("nees_position_mean", s.nees_position_mean),
                    ("scored_seconds", s.scored_seconds),
                ] {
                    metrics.insert(k.into(), Value::from(v));
                }
                warnings.extend(
                    s.partial
                        .map(|p| Warning::about(WarningKind::PartialScoring, "truth.csv", p)),
                );
                if self.keep_errors_table {
                    truth.push(s.table);
                }
            }
            Some(Err(ScoreError::Write { reason })) => {
                return Err(RunError::Invalid(format!(
                    "writing the error table: {reason}"
                )))
            }
            Some(Err(e)) => warnings.push(Warning::about(
                WarningKind::Suspicious,
                "truth.csv",
                format!("not scored against truth: {e}"),
            )),
            None => {}
        }
        if let Some(t) = self.attitude {
            if let Some(score) = t.finish()? {
                metrics.insert("attitude_error_rms_deg".into(), rpy_json(score.rms_deg));
                truth.extend(score.table);
            }
        }
        Ok(ScoreTables { truth, reference })
    }
}
