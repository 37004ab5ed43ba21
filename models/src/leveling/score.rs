//! The roll and pitch errors of a leveling run against `truth.csv`, taken
//! as the estimates come: each truth row is compared with the estimate in
//! force at its time (the latest at or before it), read from the truth file
//! as the run goes, so that neither the estimates nor the truth are held in
//! memory (docs/results/leveling6.md, "Replay").

use nav_replay::output::series::SeriesSink;
use nav_runtime::log::{RowSource, TruthRow};
use nav_runtime::math::wrap_angle;
use nav_runtime::smoother::{SmootherError, SpillFile};

use super::filter::AttitudeEstimate;
use crate::harness::{RunError, RunTable};

/// Columns of an error table: the truth row's time (s), the roll and pitch
/// errors and the sigmas of the estimate in force there (deg).
pub const COLUMNS: [&str; 5] = [
    "t",
    "roll_error_deg",
    "pitch_error_deg",
    "roll_sigma_deg",
    "pitch_sigma_deg",
];

/// One scored truth row: its time (s), the roll and pitch errors (rad).
pub type LevelError = (f64, f64, f64);

/// A truth row more than this many mean periods of the estimates after the
/// estimate before it has none (it lies past the last IMU sample, or in a
/// gap).
pub const STALE_PERIODS: f64 = 1.5;

/// Scalars of a truth row waiting for the run's end: its time, the roll
/// and pitch errors (rad), the sigmas of the estimate in force (rad), and
/// how long before the row that estimate was (s).
const RECORD: usize = 6;

/// The truth scored against estimates handed over in time order. Each row
/// is compared with the estimate in force as the run goes; whether that
/// estimate is too old for it depends on the estimates' mean period, known
/// at the end, so the compared rows wait in a temporary file until then.
pub struct TruthErrors<'a> {
    truth: Box<dyn RowSource<TruthRow> + 'a>,
    next: Option<TruthRow>,
    in_force: Option<AttitudeEstimate>,
    compared: SpillFile,
    table: SeriesSink,
    score: LevelScore,
}

/// What the truth said of a run.
#[derive(Debug, Default)]
pub struct LevelScore {
    /// Truth rows read.
    pub truth_rows: usize,
    /// Times of the first and the last truth row, s.
    pub truth_span: Option<(f64, f64)>,
    /// Truth rows with an estimate in force.
    pub scored: usize,
    /// Of those, the rows after the first estimate (the initial guess).
    pub scored_after: usize,
    /// The last scored row.
    pub last: Option<LevelError>,
    /// Sums of the squared roll and pitch errors of the rows after the first
    /// estimate, rad^2.
    squares: (f64, f64),
    /// The error table (every row, or a bounded copy of a written one), when
    /// asked for.
    pub table: Option<RunTable>,
}

impl LevelScore {
    /// RMS roll and pitch errors (deg) of the rows after the first estimate
    /// (NaN without any).
    pub fn rms_deg(&self) -> (f64, f64) {
        let n = self.scored_after as f64;
        (
            (self.squares.0 / n).sqrt().to_degrees(),
            (self.squares.1 / n).sqrt().to_degrees(),
        )
    }
}

fn spill_error(e: SmootherError) -> RunError {
    RunError::Invalid(format!("leveling6: scoring: {e}"))
}

impl<'a> TruthErrors<'a> {
    /// Scores `truth`; each scored row goes to `table`.
    ///
    /// # Errors
    /// The first truth row cannot be read, or the temporary file made.
    pub fn new(
        mut truth: Box<dyn RowSource<TruthRow> + 'a>,
        table: SeriesSink,
    ) -> Result<Self, RunError> {
        let mut score = LevelScore::default();
        let next = read(&mut truth, &mut score)?;
        Ok(TruthErrors {
            truth,
            next,
            in_force: None,
            compared: SpillFile::create(None, RECORD).map_err(spill_error)?,
            table,
            score,
        })
    }

    /// The next estimate in time order: the truth rows it comes after are
    /// compared with the one before it.
    ///
    /// # Errors
    /// A truth row cannot be read or kept.
    pub fn push(&mut self, estimate: &AttitudeEstimate) -> Result<(), RunError> {
        while let Some(row) = self.next.filter(|r| estimate.t > r.t + 1e-9) {
            self.compare(&row)?;
            self.next = read(&mut self.truth, &mut self.score)?;
        }
        self.in_force = Some(*estimate);
        Ok(())
    }

    /// Compares the rows left with the last estimate, reads the truth to
    /// its end, and scores the rows within [`STALE_PERIODS`] of the
    /// estimates' mean `period` (s) of their estimate; the RMS counts those
    /// after `after` (the first estimate's time, s).
    ///
    /// # Errors
    /// As [`TruthErrors::push`], and the table cannot be written.
    pub fn finish(mut self, period: f64, after: f64) -> Result<LevelScore, RunError> {
        while let Some(row) = self.next {
            self.compare(&row)?;
            self.next = read(&mut self.truth, &mut self.score)?;
        }
        // The file gives the rows back latest first: through a second one
        // they come in time order.
        let mut in_order = SpillFile::create(None, RECORD).map_err(spill_error)?;
        let mut r = [0.0; RECORD];
        while self.compared.pop(&mut r).map_err(spill_error)? {
            in_order.push(&r).map_err(spill_error)?;
        }
        let stale = STALE_PERIODS * period;
        let s = &mut self.score;
        while in_order.pop(&mut r).map_err(spill_error)? {
            let [t, roll, pitch, roll_sigma, pitch_sigma, age] = r;
            if age > stale + 1e-9 {
                continue;
            }
            s.scored += 1;
            s.last = Some((t, roll, pitch));
            if t > after + 1e-9 {
                s.scored_after += 1;
                s.squares.0 += roll * roll;
                s.squares.1 += pitch * pitch;
            }
            if self.table.wanted() {
                self.table.push(&[
                    t,
                    roll.to_degrees(),
                    pitch.to_degrees(),
                    roll_sigma.to_degrees(),
                    pitch_sigma.to_degrees(),
                ])?;
            }
        }
        self.score.table = self.table.finish()?;
        Ok(self.score)
    }

    /// Keeps `row` compared with the estimate in force, if any.
    fn compare(&mut self, row: &TruthRow) -> Result<(), RunError> {
        let Some(e) = self.in_force else {
            return Ok(());
        };
        self.compared
            .push(&[
                row.t,
                wrap_angle(e.roll - row.roll),
                wrap_angle(e.pitch - row.pitch),
                e.roll_sigma,
                e.pitch_sigma,
                row.t - e.t,
            ])
            .map_err(spill_error)
    }
}

/// The next truth row, counted.
fn read(
    truth: &mut Box<dyn RowSource<TruthRow> + '_>,
    score: &mut LevelScore,
) -> Result<Option<TruthRow>, RunError> {
    let row = truth.next_row()?.map(|(_, r)| r);
    if let Some(r) = row {
        score.truth_rows += 1;
        score.truth_span = Some(score.truth_span.map_or((r.t, r.t), |(a, _)| (a, r.t)));
    }
    Ok(row)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nav_runtime::log::LogError;

    /// Truth rows from a list.
    struct Rows(std::vec::IntoIter<TruthRow>);

    impl RowSource<TruthRow> for Rows {
        fn next_row(&mut self) -> Result<Option<(Option<u64>, TruthRow)>, LogError> {
            Ok(self.0.next().map(|r| (None, r)))
        }
    }

    fn estimate(t: f64, roll: f64) -> AttitudeEstimate {
        AttitudeEstimate {
            t,
            roll,
            pitch: 0.0,
            roll_sigma: 0.1,
            pitch_sigma: 0.1,
            roll_pitch_covariance: 0.0,
        }
    }

    fn truth(t: f64) -> TruthRow {
        TruthRow::new(t, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    }

    /// Each case: estimate times (the roll is a tenth of the time), truth
    /// times, and the truth times scored with the time of the estimate in
    /// force there. A truth row takes the latest estimate at or before it,
    /// none before the first, none more than 1.5 periods (here 1 s) after
    /// the last or inside a gap.
    #[test]
    fn each_truth_row_is_scored_by_the_estimate_in_force() {
        /// Estimate times, truth times, (truth time, estimate time) scored.
        type Case<'c> = (&'c [f64], &'c [f64], &'c [(f64, f64)]);
        let cases: [Case; 4] = [
            (
                &[0.0, 1.0, 2.0],
                &[0.0, 0.5, 1.0, 2.0],
                &[(0.0, 0.0), (0.5, 0.0), (1.0, 1.0), (2.0, 2.0)],
            ),
            (&[1.0, 2.0], &[0.5, 1.5], &[(1.5, 1.0)]),
            (&[0.0, 1.0], &[1.4, 2.1, 5.0], &[(1.4, 1.0)]),
            (&[0.0, 1.0, 5.0], &[3.0, 5.0], &[(5.0, 5.0)]),
        ];
        for (estimates, times, expected) in cases {
            let rows = Rows(
                times
                    .iter()
                    .map(|&t| truth(t))
                    .collect::<Vec<_>>()
                    .into_iter(),
            );
            let table = SeriesSink::new("t", &COLUMNS, None, true).unwrap();
            let mut errors = TruthErrors::new(Box::new(rows), table).unwrap();
            for &t in estimates {
                errors.push(&estimate(t, 0.1 * t)).unwrap();
            }
            let score = errors.finish(1.0 / 1.5, 0.0).unwrap();
            let got: Vec<(f64, f64)> = score
                .table
                .unwrap()
                .rows
                .iter()
                .map(|r| (r[0], r[1].to_radians()))
                .collect();
            assert_eq!(
                got.len(),
                expected.len(),
                "{estimates:?} {times:?}: {got:?}"
            );
            for (g, e) in got.iter().zip(expected) {
                assert!(
                    (g.0 - e.0).abs() < 1e-12 && (g.1 - 0.1 * e.1).abs() < 1e-12,
                    "{got:?}"
                );
            }
            assert_eq!(score.truth_rows, times.len());
            assert_eq!(score.scored, expected.len());
        }
    }
}
