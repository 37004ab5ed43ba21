//! Scoring a replay against `reference.csv` (PX4's estimate) and
//! `truth.csv` as its estimates come, without holding either the estimates
//! or the files: each row is met once the estimate stream has passed its
//! time and compared with the estimate interpolated there, exactly as
//! [`Reference::difference`](super::reference::Reference::difference),
//! [`difference_table`](super::replay::difference_table) and
//! [`attitude_errors`](super::replay::attitude_errors) compare a whole
//! series; the sums are kept, the rows go to a [`SeriesSink`].

use nav_runtime::earth::{geodetic_error_to_ned, meridian_radius, transverse_radius};
use nav_runtime::log::{LogError, ReferenceRow, Row, RowSource, TruthRow, Warning, WarningKind};
use serde_json::{Map, Value};

use super::reference::{EstimatePoint, ReferenceDifference};
use super::replay::{at, wrap};
use crate::harness::{RunError, RunTable};
use nav_replay::output::series::SeriesSink;

/// Columns of the `reference_difference` table.
pub const REFERENCE_COLUMNS: [&str; 12] = [
    "t",
    "roll_deg",
    "pitch_deg",
    "yaw_deg",
    "ref_roll_deg",
    "ref_pitch_deg",
    "ref_yaw_deg",
    "diff_roll_deg",
    "diff_pitch_deg",
    "diff_yaw_deg",
    "diff_n_m",
    "diff_e_m",
];

/// Columns of the `attitude_errors` table.
pub const TRUTH_COLUMNS: [&str; 4] = ["t", "err_roll_deg", "err_pitch_deg", "err_yaw_deg"];

/// The rows of a time-ordered file met by a stream of estimates: a row is
/// handed on with the two estimates around it (the span is closed at both
/// ends, a row at the time of an estimate going with the interval that
/// ends there, the first estimate's time with the first interval). Rows
/// before the first estimate or after the last are passed over.
struct RowsAlong<'a, R> {
    rows: Box<dyn RowSource<R> + 'a>,
    next: Option<R>,
    previous: Option<EstimatePoint>,
}

impl<'a, R: Row> RowsAlong<'a, R> {
    fn new(mut rows: Box<dyn RowSource<R> + 'a>) -> Result<Self, LogError> {
        let next = rows.next_row()?.map(|(_, r)| r);
        Ok(RowsAlong {
            rows,
            next,
            previous: None,
        })
    }

    fn advance(&mut self, passed: &mut impl FnMut(&R)) -> Result<(), LogError> {
        if let Some(r) = &self.next {
            passed(r);
        }
        self.next = self.rows.next_row()?.map(|(_, r)| r);
        Ok(())
    }

    /// Offers the next estimate `b`: each row in the span from the previous
    /// estimate to `b` goes to `inside` with both estimates; every row read
    /// goes to `passed` first.
    fn offer(
        &mut self,
        b: EstimatePoint,
        passed: &mut impl FnMut(&R),
        mut inside: impl FnMut(&R, &EstimatePoint, &EstimatePoint),
    ) -> Result<(), LogError> {
        let Some(a) = self.previous.replace(b) else {
            while self.next.as_ref().is_some_and(|r| r.t() < b.t) {
                self.advance(passed)?;
            }
            return Ok(());
        };
        while let Some(r) = self.next {
            if r.t() > b.t {
                break;
            }
            if r.t() >= a.t {
                inside(&r, &a, &b);
            }
            self.advance(passed)?;
        }
        Ok(())
    }

    /// Reads the rows after the last estimate (each to `passed`).
    fn finish(&mut self, passed: &mut impl FnMut(&R)) -> Result<(), LogError> {
        while self.next.is_some() {
            self.advance(passed)?;
        }
        Ok(())
    }
}

/// The fraction of the way from `a` to `b` at `t`.
fn fraction(a: &EstimatePoint, b: &EstimatePoint, t: f64) -> f64 {
    if b.t > a.t {
        (t - a.t) / (b.t - a.t)
    } else {
        0.0
    }
}

/// Which groups every row of `reference.csv` has: a group is compared
/// only when every row has it (the importer's fixed schema leaves a group
/// the log lacks empty in every row).
#[derive(Debug, Clone, Copy)]
struct Groups {
    rows: usize,
    attitude_everywhere: bool,
    position_everywhere: bool,
}

impl Groups {
    fn see(&mut self, r: &ReferenceRow) {
        self.rows += 1;
        self.attitude_everywhere &= r.attitude().is_some();
        self.position_everywhere &= r.position().is_some();
    }
}

/// The running comparison with `reference.csv`.
pub struct ReferenceScore<'a> {
    rows: RowsAlong<'a, ReferenceRow>,
    groups: Groups,
    attitude: [f64; 3],
    horizontal: f64,
    attitude_rows: usize,
    position_rows: usize,
    first: Option<f64>,
    last: f64,
    /// First and last time of the estimates offered.
    estimates: Option<(f64, f64)>,
    estimate_has_position: bool,
    table: SeriesSink,
}

impl<'a> ReferenceScore<'a> {
    /// Scores against `rows`, the table going to `table`.
    ///
    /// # Errors
    /// The first row cannot be read.
    pub fn new(
        rows: Box<dyn RowSource<ReferenceRow> + 'a>,
        table: SeriesSink,
    ) -> Result<Self, LogError> {
        Ok(ReferenceScore {
            rows: RowsAlong::new(rows)?,
            groups: Groups {
                rows: 0,
                attitude_everywhere: true,
                position_everywhere: true,
            },
            attitude: [0.0; 3],
            horizontal: 0.0,
            attitude_rows: 0,
            position_rows: 0,
            first: None,
            last: 0.0,
            estimates: None,
            estimate_has_position: false,
            table,
        })
    }

    /// Offers the next estimate (in time order).
    ///
    /// # Errors
    /// A row of `reference.csv` cannot be read, or the table written.
    pub fn push(&mut self, point: EstimatePoint) -> Result<(), RunError> {
        self.estimate_has_position |= point.position.is_some();
        self.estimates = Some(
            self.estimates
                .map_or((point.t, point.t), |(a, _)| (a, point.t)),
        );
        let groups = &mut self.groups;
        let (attitude, horizontal) = (&mut self.attitude, &mut self.horizontal);
        let (attitude_rows, position_rows) = (&mut self.attitude_rows, &mut self.position_rows);
        let (first, last, table) = (&mut self.first, &mut self.last, &mut self.table);
        let mut written = Ok(());
        self.rows.offer(point, &mut |r| groups.see(r), |r, a, b| {
            let s = fraction(a, b, r.t);
            first.get_or_insert(r.t);
            *last = r.t;
            let reference_attitude = r.attitude();
            if let Some(reference) = reference_attitude {
                for k in 0..3 {
                    let e = a.attitude[k] + s * wrap(b.attitude[k] - a.attitude[k]);
                    attitude[k] += wrap(e - reference[k]).powi(2);
                }
                *attitude_rows += 1;
            }
            let reference_position = r.position();
            if let (Some([rlat, rlon, rh]), Some(pa), Some(pb)) =
                (reference_position, a.position, b.position)
            {
                let lat = pa[0] + s * (pb[0] - pa[0]);
                let lon = pa[1] + s * (pb[1] - pa[1]);
                let north = (lat - rlat) * (meridian_radius(rlat) + rh);
                let east = (lon - rlon) * (transverse_radius(rlat) + rh) * rlat.cos();
                *horizontal += north * north + east * east;
                *position_rows += 1;
            }
            if table.wanted() && written.is_ok() {
                written = table.push(&difference_row(r, a, b));
            }
        })?;
        written
    }

    /// Reads the rest of `reference.csv` and adds the reference keys to
    /// `metrics` (`attitude_difference_rms_deg`, `horizontal_difference_rms_m`
    /// when both sides have positions, `reference_samples`,
    /// `reference_scored_seconds`) and the warnings of a missing group;
    /// returns the table kept in memory, if any.
    ///
    /// # Errors
    /// A row cannot be read, or the table written.
    pub fn finish(
        mut self,
        metrics: &mut Map<String, Value>,
        warnings: &mut Vec<Warning>,
    ) -> Result<Option<RunTable>, RunError> {
        let groups = &mut self.groups;
        self.rows.finish(&mut |r| groups.see(r))?;
        let has_attitude = self.groups.rows > 0 && self.groups.attitude_everywhere;
        let has_position = self.groups.rows > 0 && self.groups.position_everywhere;
        let attitude_rows = if has_attitude { self.attitude_rows } else { 0 };
        let position_rows = if has_position { self.position_rows } else { 0 };
        let rms = |sum: f64, n: usize| (sum / n as f64).sqrt();
        let difference = ReferenceDifference {
            attitude_rms_deg: (attitude_rows > 0)
                .then(|| self.attitude.map(|s| rms(s, attitude_rows).to_degrees())),
            horizontal_rms_m: (position_rows > 0).then(|| rms(self.horizontal, position_rows)),
            samples: attitude_rows.max(position_rows),
            scored_seconds: self.first.map_or(0.0, |f| self.last - f),
        };
        if let Value::Object(m) = difference.json() {
            metrics.extend(m);
        }
        // A reference that overlaps little of the run gives differences of
        // that part only (a clock offset, a cut file): said.
        if let Some((a, b)) = self.estimates {
            let run = b - a;
            if difference.samples > 0 && difference.scored_seconds < 0.5 * run {
                warnings.push(Warning::about(
                    WarningKind::PartialScoring,
                    "reference.csv",
                    format!(
                        "reference.csv: only {:.1} s of the {run:.1} s run ({} rows) are scored \
                         against it: the differences are of that part only",
                        difference.scored_seconds, difference.samples
                    ),
                ));
            }
        }
        if !has_attitude {
            warnings.push(Warning::about(
                WarningKind::Model,
                "reference.csv",
                "reference.csv has no attitude: no attitude difference",
            ));
        }
        if !has_position && self.estimate_has_position {
            warnings.push(Warning::about(
                WarningKind::Model,
                "reference.csv",
                "reference.csv has no position (the log has no vehicle_global_position): \
                 no horizontal difference",
            ));
        }
        self.table.finish()
    }
}

/// One row of the `reference_difference` table: the estimate between `a`
/// and `b` at the reference row's time, the reference, their wrapped
/// differences (deg) and, with positions on both sides, the north and east
/// differences (m); NaN for what the row lacks.
fn difference_row(r: &ReferenceRow, a: &EstimatePoint, b: &EstimatePoint) -> [f64; 12] {
    let e = at(&[*a, *b], r.t, &mut 0).unwrap_or(*a);
    let mut row = [f64::NAN; 12];
    row[0] = r.t;
    for k in 0..3 {
        row[1 + k] = e.attitude[k].to_degrees();
    }
    if let Some(reference) = r.attitude() {
        for k in 0..3 {
            row[4 + k] = reference[k].to_degrees();
            row[7 + k] = wrap(e.attitude[k] - reference[k]).to_degrees();
        }
    }
    if let (Some(p), Some(rp)) = (e.position, r.position()) {
        let d = geodetic_error_to_ned(rp[0], rp[2], p[0] - rp[0], p[1] - rp[1], 0.0);
        row[10] = d.x;
        row[11] = d.y;
    }
    row
}

/// The running attitude error against `truth.csv`.
pub struct TruthScore<'a> {
    rows: RowsAlong<'a, TruthRow>,
    squares: [f64; 3],
    scored: usize,
    first: Option<f64>,
    last: f64,
    table: SeriesSink,
}

/// The attitude error of a run against `truth.csv`.
#[derive(Debug, Clone, PartialEq)]
pub struct AttitudeError {
    /// RMS of the wrapped roll, pitch and yaw errors, deg.
    pub rms_deg: [f64; 3],
    /// Time between the first and the last truth row scored, s.
    pub scored_seconds: f64,
    /// The `attitude_errors` table kept in memory, if asked for.
    pub table: Option<RunTable>,
}

impl<'a> TruthScore<'a> {
    /// Scores against `rows`, the table going to `table`.
    ///
    /// # Errors
    /// The first row cannot be read.
    pub fn new(
        rows: Box<dyn RowSource<TruthRow> + 'a>,
        table: SeriesSink,
    ) -> Result<Self, LogError> {
        Ok(TruthScore {
            rows: RowsAlong::new(rows)?,
            squares: [0.0; 3],
            scored: 0,
            first: None,
            last: 0.0,
            table,
        })
    }

    /// Offers the next estimate (in time order).
    ///
    /// # Errors
    /// A row of `truth.csv` cannot be read, or the table written.
    pub fn push(&mut self, point: EstimatePoint) -> Result<(), RunError> {
        let (squares, scored, first, last, table) = (
            &mut self.squares,
            &mut self.scored,
            &mut self.first,
            &mut self.last,
            &mut self.table,
        );
        let mut written = Ok(());
        self.rows.offer(point, &mut |_| {}, |r, a, b| {
            let e = at(&[*a, *b], r.t, &mut 0).unwrap_or(*a);
            let err = [
                wrap(e.attitude[0] - r.roll),
                wrap(e.attitude[1] - r.pitch),
                wrap(e.attitude[2] - r.yaw),
            ];
            for k in 0..3 {
                squares[k] += err[k] * err[k];
            }
            first.get_or_insert(r.t);
            *last = r.t;
            *scored += 1;
            if table.wanted() && written.is_ok() {
                written = table.push(&[
                    r.t,
                    err[0].to_degrees(),
                    err[1].to_degrees(),
                    err[2].to_degrees(),
                ]);
            }
        })?;
        written
    }

    /// The score; `None` when no truth row is inside the estimate's span.
    ///
    /// # Errors
    /// The table cannot be written.
    pub fn finish(self) -> Result<Option<AttitudeError>, RunError> {
        let table = self.table.finish()?;
        let Some(first) = self.first else {
            return Ok(None);
        };
        let n = self.scored as f64;
        Ok(Some(AttitudeError {
            rms_deg: self.squares.map(|s| (s / n).sqrt().to_degrees()),
            scored_seconds: self.last - first,
            table,
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ulog::reference::Reference;
    use crate::ulog::replay::{attitude_errors, difference_table, reference};

    /// Rows in memory, in order.
    struct Rows<R>(std::vec::IntoIter<R>);

    impl<R: Row> RowSource<R> for Rows<R> {
        fn next_row(&mut self) -> Result<Option<(Option<u64>, R)>, LogError> {
            Ok(self.0.next().map(|r| (None, r)))
        }
    }

    fn points() -> Vec<EstimatePoint> {
        (0..40)
            .map(|k| {
                let t = 1.0 + 0.07 * k as f64;
                EstimatePoint {
                    t,
                    // The yaw crosses +-180 deg.
                    attitude: [0.01 * t, -0.02 * t, wrap(3.0 + 0.1 * t)],
                    position: Some([0.8 + 1e-7 * t, 0.1 - 1e-7 * t, 10.0]),
                }
            })
            .collect()
    }

    /// From before the first estimate to after the last, one row at the
    /// time of an estimate; times strictly increasing, as the reader gives.
    fn reference_rows(points: &[EstimatePoint]) -> Vec<ReferenceRow> {
        let mut times: Vec<f64> = (0..50).map(|k| 0.5 + 0.06 * k as f64).collect();
        times.push(points[5].t);
        times.sort_by(f64::total_cmp);
        times.dedup();
        times
            .into_iter()
            .map(|t| {
                ReferenceRow::new(
                    t,
                    Some(0.8),
                    Some(0.1),
                    Some(10.0),
                    None,
                    None,
                    None,
                    Some(0.0),
                    Some(0.01),
                    Some(3.1),
                )
            })
            .collect()
    }

    /// The running scores give what the whole-series functions give.
    #[test]
    fn running_scores_equal_the_whole_series_scores() {
        let points = points();
        let rows = reference_rows(&points);
        let whole: Reference = reference(&rows);
        let expected = whole.difference(&points).json();
        let expected_table = difference_table(&whole, &points);
        let mut score = ReferenceScore::new(
            Box::new(Rows(rows.clone().into_iter())),
            SeriesSink::Kept(RunTable::new("reference_difference", &REFERENCE_COLUMNS)),
        )
        .unwrap();
        for p in &points {
            score.push(*p).unwrap();
        }
        let (mut metrics, mut warnings) = (Map::new(), Vec::new());
        let table = score.finish(&mut metrics, &mut warnings).unwrap().unwrap();
        assert_eq!(Value::Object(metrics), expected);
        assert!(warnings.is_empty(), "{warnings:?}");
        assert_eq!(table.rows.len(), expected_table.rows.len());
        for (a, b) in table.rows.iter().zip(&expected_table.rows) {
            for (x, y) in a.iter().zip(b) {
                assert!(x == y || (x - y).abs() < 1e-9, "{a:?} vs {b:?}");
            }
        }

        let truth: Vec<TruthRow> = rows
            .iter()
            .map(|r| TruthRow::new(r.t, 0.8, 0.1, -10.0, 0.0, 0.0, 0.0, 0.0, 0.01, 3.1))
            .collect();
        let (rms, seconds, expected_table) = attitude_errors(&truth, &points).unwrap();
        let mut score = TruthScore::new(
            Box::new(Rows(truth.into_iter())),
            SeriesSink::Kept(RunTable::new("attitude_errors", &TRUTH_COLUMNS)),
        )
        .unwrap();
        for p in &points {
            score.push(*p).unwrap();
        }
        let got = score.finish().unwrap().unwrap();
        assert_eq!(got.rms_deg, rms);
        assert_eq!(got.scored_seconds, seconds);
        assert_eq!(got.table.unwrap().rows, expected_table.rows);
    }
}
