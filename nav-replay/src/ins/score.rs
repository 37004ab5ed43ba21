//! Scoring an SDINS-25 run against truth.csv: horizontal and depth errors, the
//! filter's sigmas and the NEES of the 9 navigation states.

use nav_runtime::earth::{Geodetic, LocalNed};
use nav_runtime::gate::chi_square_quantile;
use nav_runtime::log::TruthRow;
use nav_runtime::nalgebra::{Cholesky, SVector};
use nav_runtime::strapdown::NavState;

use super::reference_point_fit::{FittedPoint, ReferencePointFit};
use super::setup::{c_bn, Estimate};
use crate::output::series::{BoundedTable, TableWriter, PLOT_ROWS};
use crate::RunTable;

/// Navigation states of the NEES.
pub const NEES_DOF: usize = 9;

/// Name of the per-run table.
pub const TABLE: &str = "errors";

/// Columns of the per-run table: errors (estimate minus truth; position N/E/D
/// in m, velocity m/s, attitude deg), the filter's 1-sigma of each, the NEES,
/// the true and estimated horizontal track (m from the first truth point), and
/// the compass-bias estimate error and sigma (deg; NaN without a known bias).
pub const COLUMNS: [&str; 26] = [
    "t",
    "err_n",
    "err_e",
    "err_d",
    "err_vn",
    "err_ve",
    "err_vd",
    "err_roll_deg",
    "err_pitch_deg",
    "err_yaw_deg",
    "sig_n",
    "sig_e",
    "sig_d",
    "sig_vn",
    "sig_ve",
    "sig_vd",
    "sig_roll_deg",
    "sig_pitch_deg",
    "sig_yaw_deg",
    "nees",
    "true_n",
    "true_e",
    "est_n",
    "est_e",
    "compass_bias_err_deg",
    "compass_bias_sig_deg",
];

/// A scored run.
#[derive(Clone, Debug, Default)]
pub struct Scored {
    /// One row per truth time with an estimate, [`COLUMNS`].
    pub table: RunTable,
    /// Horizontal error at the last scored time (m).
    pub horizontal_error_final_m: f64,
    /// RMS horizontal error over the scored times (m).
    pub horizontal_error_rms_m: f64,
    /// RMS depth error (m).
    pub depth_error_rms_m: f64,
    /// Time average of the 9-state NEES.
    pub nees_mean: f64,
    /// Time average of the position error's NEES (3 states: north, east,
    /// down, with their block of the covariance): the filter's claim about
    /// where it is, apart from its velocity and attitude.
    pub nees_position_mean: f64,
    /// Compass-bias estimate error at the end (deg; NaN without a known bias).
    pub compass_bias_error_final_deg: f64,
    /// Filter sigma of the compass bias at the end (deg).
    pub compass_bias_sigma_final_deg: f64,
    /// Time from the first to the last scored truth row (s): the overlap of
    /// truth and estimate.
    pub scored_seconds: f64,
    /// Number of scored truth rows.
    pub scored_rows: usize,
    /// Set when the scored rows cover less than half of the truth's span.
    pub partial: Option<String>,
    /// The point of the vehicle the truth seems to describe, when its
    /// velocity errors in turns say it is not the IMU (beyond a declared
    /// `[files.truth] lever_arm`).
    pub reference_point: Option<FittedPoint>,
}

/// Why a run cannot be scored.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ScoreError {
    /// `truth.csv` has no rows.
    #[error("truth.csv: no rows after the header: nothing to score (remove the file to replay without scoring)")]
    NoTruth,
    /// Fewer than two truth rows have an estimate.
    #[error(
        "truth.csv (t = {truth_start}..{truth_end} s) and the estimate overlap in {rows} row(s) only: \
         nothing to score (the IMU covers t = {imu_start}..{imu_end} s)"
    )]
    NoOverlap {
        /// First truth time, s.
        truth_start: f64,
        /// Last truth time, s.
        truth_end: f64,
        /// First IMU time, s (NaN without IMU rows).
        imu_start: f64,
        /// Last IMU time, s.
        imu_end: f64,
        /// Truth rows with an estimate.
        rows: usize,
    },
    /// An error came out non-finite (a truth value far out of range).
    #[error(
        "truth.csv:{line}: the error against this row is not finite (truth value out of range?)"
    )]
    NotFinite {
        /// 1-based line of the truth row.
        line: u64,
    },
    /// The error table could not be written.
    #[error("writing the error table: {reason}")]
    Write {
        /// Why.
        reason: String,
    },
}

/// The truth row as a navigation state.
pub fn truth_state(r: &TruthRow) -> NavState {
    NavState {
        lat: r.lat,
        lon: r.lon,
        h: -r.depth,
        v_n: SVector::<f64, 3>::new(r.vn, r.ve, r.vd),
        c_bn: c_bn(r.roll, r.pitch, r.yaw),
    }
}

/// Scores `estimates` (one per truth row, `None` where missing) against `truth`,
/// only where both exist (truth rows outside the estimate's span are not
/// scored; `scored_seconds` says how much is). `compass_bias` is the true
/// compass bias (rad) when known; `imu_span` the IMU's first and last time, for
/// the messages. The whole table is kept ([`Scorer`] scores a run as it goes).
///
/// # Errors
/// No truth rows, fewer than two scored rows, or a non-finite error.
pub fn score(
    estimates: &[Option<Estimate>],
    truth: &[TruthRow],
    compass_bias: Option<f64>,
    imu_span: Option<(f64, f64)>,
) -> Result<Scored, ScoreError> {
    let mut scorer = Scorer::new(compass_bias, Keep::All);
    for (i, (est, row)) in estimates.iter().zip(truth).enumerate() {
        scorer.push(Some(i as u64 + 2), row, est.as_ref())?;
    }
    // Truth rows beyond the estimates are counted, not scored.
    for (i, row) in truth.iter().enumerate().skip(estimates.len()) {
        scorer.push(Some(i as u64 + 2), row, None)?;
    }
    scorer.finish(imu_span)
}

/// Which rows of the error table a [`Scorer`] keeps in [`Scored::table`].
#[derive(Debug)]
pub enum Keep {
    /// Every row.
    All,
    /// A bounded, evenly thinned copy (for plots), every row also written to
    /// the file of the writer when there is one.
    Bounded(Option<TableWriter>),
    /// None.
    Nothing,
}

impl Keep {
    /// What a replay keeps of error table `name`: with an output directory,
    /// `<name>.csv` written there and a bounded copy for the plots; else
    /// every row when `keep_series`, or none.
    ///
    /// # Errors
    /// The file cannot be created.
    pub fn for_replay(
        name: &str,
        out: Option<&std::path::Path>,
        keep_series: bool,
    ) -> Result<Self, crate::RunError> {
        Ok(match out {
            Some(dir) => Keep::Bounded(Some(TableWriter::create(
                &dir.join(format!("{name}.csv")),
                &COLUMNS,
            )?)),
            None if keep_series => Keep::All,
            None => Keep::Nothing,
        })
    }
}

/// Scores a run against truth as the estimates come, one truth row at a
/// time, in memory that does not grow with the log (with [`Keep::Bounded`]
/// or [`Keep::Nothing`]).
#[derive(Debug)]
pub struct Scorer {
    compass_bias: Option<f64>,
    keep: Keep,
    kept: Option<BoundedTable>,
    table: RunTable,
    frame: Option<LocalNed>,
    truth_first: Option<f64>,
    truth_last: f64,
    truth_rows: usize,
    t_first: f64,
    t_last: f64,
    h2: f64,
    d2: f64,
    nees_sum: f64,
    nees_position_sum: f64,
    n: usize,
    reference_point: ReferencePointFit,
    out: Scored,
}

impl Scorer {
    /// A scorer; `compass_bias` is the true compass bias (rad) when known.
    pub fn new(compass_bias: Option<f64>, keep: Keep) -> Self {
        let kept =
            matches!(keep, Keep::Bounded(_)).then(|| BoundedTable::new(TABLE, &COLUMNS, PLOT_ROWS));
        Scorer {
            compass_bias,
            keep,
            kept,
            table: RunTable::new(TABLE, &COLUMNS),
            frame: None,
            truth_first: None,
            truth_last: f64::NAN,
            truth_rows: 0,
            t_first: f64::NAN,
            t_last: f64::NAN,
            h2: 0.0,
            d2: 0.0,
            nees_sum: 0.0,
            nees_position_sum: 0.0,
            n: 0,
            reference_point: ReferencePointFit::default(),
            out: Scored::default(),
        }
    }

    /// Scores the estimate at truth row `row` (line `line` of `truth.csv`);
    /// `None`: no estimate there (the row is counted, not scored).
    ///
    /// # Errors
    /// A non-finite error against the row; the table file cannot be written.
    pub fn push(
        &mut self,
        line: Option<u64>,
        row: &TruthRow,
        estimate: Option<&Estimate>,
    ) -> Result<(), ScoreError> {
        self.truth_rows += 1;
        self.truth_first.get_or_insert(row.t);
        self.truth_last = row.t;
        let frame = *self
            .frame
            .get_or_insert_with(|| LocalNed::new(Geodetic::new(row.lat, row.lon, -row.depth)));
        let Some(e) = estimate else {
            self.reference_point.push(row, None);
            return Ok(());
        };
        let tr = truth_state(row);
        let err = e.nav.error_from(&tr);
        self.reference_point.push(row, Some(err.dv_n));
        let p = err.position_ned(tr.lat, tr.h);
        let x = SVector::<f64, 9>::from([
            p.x, p.y, p.z, err.dv_n.x, err.dv_n.y, err.dv_n.z, err.phi.x, err.phi.y, err.phi.z,
        ]);
        let nees = Cholesky::new(e.cov).map_or(f64::NAN, |c| x.dot(&c.solve(&x)));
        let position = x.fixed_rows::<3>(0).into_owned();
        let nees_position = Cholesky::new(e.cov.fixed_view::<3, 3>(0, 0).into_owned())
            .map_or(f64::NAN, |c| position.dot(&c.solve(&position)));
        let horizontal = p.x.hypot(p.y);
        if !(horizontal.is_finite() && p.z.is_finite()) {
            return Err(ScoreError::NotFinite {
                line: line.unwrap_or(self.truth_rows as u64 + 1),
            });
        }
        if self.n == 0 {
            self.t_first = row.t;
        }
        self.t_last = row.t;
        self.h2 += horizontal * horizontal;
        self.d2 += p.z * p.z;
        self.nees_sum += nees;
        self.nees_position_sum += nees_position;
        self.n += 1;
        self.out.horizontal_error_final_m = horizontal;
        let sig: [f64; 9] = std::array::from_fn(|i| e.cov[(i, i)].sqrt());
        let tn = frame.geodetic_to_ned(&tr.position());
        let en = frame.geodetic_to_ned(&e.nav.position());
        let (cb_err, cb_sig) = (
            self.compass_bias
                .map_or(f64::NAN, |b| (e.compass_bias.0 - b).to_degrees()),
            e.compass_bias.1.to_degrees(),
        );
        self.out.compass_bias_error_final_deg = cb_err;
        self.out.compass_bias_sigma_final_deg = cb_sig;
        let deg = f64::to_degrees;
        let values = [
            row.t,
            x[0],
            x[1],
            x[2],
            x[3],
            x[4],
            x[5],
            deg(x[6]),
            deg(x[7]),
            deg(x[8]),
            sig[0],
            sig[1],
            sig[2],
            sig[3],
            sig[4],
            sig[5],
            deg(sig[6]),
            deg(sig[7]),
            deg(sig[8]),
            nees,
            tn.x,
            tn.y,
            en.x,
            en.y,
            cb_err,
            cb_sig,
        ];
        match &mut self.keep {
            Keep::All => self.table.push(&values),
            Keep::Bounded(writer) => {
                if let Some(w) = writer {
                    w.push(&values).map_err(|e| ScoreError::Write {
                        reason: e.to_string(),
                    })?;
                }
                if let Some(k) = &mut self.kept {
                    k.push(&values);
                }
            }
            Keep::Nothing => {}
        }
        Ok(())
    }

    /// The scores; `imu_span` is the IMU's first and last time, for the
    /// messages.
    ///
    /// # Errors
    /// No truth rows, or fewer than two scored rows.
    pub fn finish(mut self, imu_span: Option<(f64, f64)>) -> Result<Scored, ScoreError> {
        let Some(truth_first) = self.truth_first else {
            return Err(ScoreError::NoTruth);
        };
        let n = self.n;
        if n < 2 {
            let (imu_start, imu_end) = imu_span.unwrap_or((f64::NAN, f64::NAN));
            return Err(ScoreError::NoOverlap {
                truth_start: truth_first,
                truth_end: self.truth_last,
                imu_start,
                imu_end,
                rows: n,
            });
        }
        if let Keep::Bounded(Some(w)) = std::mem::replace(&mut self.keep, Keep::Nothing) {
            w.finish().map_err(|e| ScoreError::Write {
                reason: e.to_string(),
            })?;
        }
        let mut out = self.out;
        let k = n as f64;
        out.horizontal_error_rms_m = (self.h2 / k).sqrt();
        out.depth_error_rms_m = (self.d2 / k).sqrt();
        out.nees_mean = self.nees_sum / k;
        out.nees_position_mean = self.nees_position_sum / k;
        out.scored_seconds = self.t_last - self.t_first;
        out.scored_rows = n;
        out.reference_point = self.reference_point.finish();
        let truth_span = self.truth_last - truth_first;
        if out.scored_seconds < 0.5 * truth_span {
            out.partial = Some(format!(
                "truth.csv: only {:.1} s of its {:.1} s (t = {}..{} s, {n} of {} rows) \
                 overlap the estimate and are scored",
                out.scored_seconds, truth_span, self.t_first, self.t_last, self.truth_rows
            ));
        }
        out.table = match self.kept {
            Some(k) => k.into_table(),
            None => self.table,
        };
        Ok(out)
    }
}

/// Two-sided 95 % band of the NEES of `dof` states averaged over `runs`
/// independent runs: `chi2(dof runs)` quantiles divided by `runs`.
pub fn nees_band_95(dof: usize, runs: usize) -> (f64, f64) {
    let k = dof * runs.max(1);
    let r = runs.max(1) as f64;
    let q = |p: f64| chi_square_quantile(p, k).unwrap_or(f64::NAN) / r;
    (q(0.025), q(0.975))
}

#[cfg(test)]
mod tests {
    use super::*;
    use nav_runtime::earth::meridian_radius;
    use nav_runtime::nalgebra::SMatrix;

    /// The position NEES weighs the position error by the position block
    /// of the covariance alone: a velocity error the 9-state NEES counts
    /// does not enter it.
    #[test]
    fn the_position_nees_is_that_of_the_position_block() {
        let (lat, lon, depth) = (0.6, 2.2, 10.0);
        let truth: Vec<TruthRow> = (0..3)
            .map(|k| TruthRow::new(k as f64, lat, lon, depth, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0))
            .collect();
        // 2 m north of the truth with a sigma of 2 m (position NEES 1),
        // 0.5 m/s too fast north with a sigma of 0.1 m/s (25 more).
        let mut cov = SMatrix::<f64, 9, 9>::zeros();
        for (i, sigma) in [2.0, 2.0, 2.0, 0.1, 0.1, 0.1, 1e-2, 1e-2, 1e-2]
            .into_iter()
            .enumerate()
        {
            cov[(i, i)] = sigma * sigma;
        }
        let estimates: Vec<Option<Estimate>> = truth
            .iter()
            .map(|r| {
                let mut nav = truth_state(r);
                nav.lat += 2.0 / (meridian_radius(lat) - depth);
                nav.v_n.x += 0.5;
                Some(Estimate {
                    t: r.t,
                    nav,
                    cov,
                    compass_bias: (0.0, f64::NAN),
                    usbl_bias_n: (0.0, f64::NAN),
                    baro_bias: (0.0, f64::NAN),
                })
            })
            .collect();
        let s = score(&estimates, &truth, None, None).expect("scored");
        approx::assert_relative_eq!(s.nees_position_mean, 1.0, max_relative = 1e-6);
        approx::assert_relative_eq!(s.nees_mean, 26.0, max_relative = 1e-6);
    }
}
