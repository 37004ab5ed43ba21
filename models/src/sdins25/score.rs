//! Scoring an SDINS-25 run against truth.csv: horizontal and depth errors, the
//! filter's sigmas and the NEES of the 9 navigation states.

use nav_runtime::earth::{Geodetic, LocalNed};
use nav_runtime::gate::chi_square_quantile;
use nav_runtime::log::TruthRow;
use nav_runtime::nalgebra::{Cholesky, SVector};
use nav_runtime::strapdown::NavState;

use super::filter::{c_bn, Estimate};
use crate::montecarlo::RunTable;

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
}

/// Why a run cannot be scored.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
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
/// the messages.
///
/// # Errors
/// No truth rows, fewer than two scored rows, or a non-finite error.
pub fn score(
    estimates: &[Option<Estimate>],
    truth: &[TruthRow],
    compass_bias: Option<f64>,
    imu_span: Option<(f64, f64)>,
) -> Result<Scored, ScoreError> {
    let mut table = RunTable::new(TABLE, &COLUMNS);
    let Some(first) = truth.first() else {
        return Err(ScoreError::NoTruth);
    };
    let (mut t_first, mut t_last) = (f64::NAN, f64::NAN);
    let frame = LocalNed::new(Geodetic::new(first.lat, first.lon, -first.depth));
    let (mut h2, mut d2, mut nees_sum, mut n) = (0.0, 0.0, 0.0, 0usize);
    let mut out = Scored::default();
    for (i, (est, row)) in estimates.iter().zip(truth).enumerate() {
        let Some(e) = est else { continue };
        let tr = truth_state(row);
        let err = e.nav.error_from(&tr);
        let p = err.position_ned(tr.lat, tr.h);
        let x = SVector::<f64, 9>::from([
            p.x, p.y, p.z, err.dv_n.x, err.dv_n.y, err.dv_n.z, err.phi.x, err.phi.y, err.phi.z,
        ]);
        let nees = Cholesky::new(e.cov).map_or(f64::NAN, |c| x.dot(&c.solve(&x)));
        let horizontal = p.x.hypot(p.y);
        if !(horizontal.is_finite() && p.z.is_finite()) {
            return Err(ScoreError::NotFinite { line: i as u64 + 2 });
        }
        if n == 0 {
            t_first = row.t;
        }
        t_last = row.t;
        h2 += horizontal * horizontal;
        d2 += p.z * p.z;
        nees_sum += nees;
        n += 1;
        out.horizontal_error_final_m = horizontal;
        let sig: Vec<f64> = (0..9).map(|i| e.cov[(i, i)].sqrt()).collect();
        let tn = frame.geodetic_to_ned(&tr.position());
        let en = frame.geodetic_to_ned(&e.nav.position());
        let (cb_err, cb_sig) = (
            compass_bias.map_or(f64::NAN, |b| (e.compass_bias.0 - b).to_degrees()),
            e.compass_bias.1.to_degrees(),
        );
        out.compass_bias_error_final_deg = cb_err;
        out.compass_bias_sigma_final_deg = cb_sig;
        let deg = f64::to_degrees;
        table.push(&[
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
        ]);
    }
    if n < 2 {
        let (imu_start, imu_end) = imu_span.unwrap_or((f64::NAN, f64::NAN));
        return Err(ScoreError::NoOverlap {
            truth_start: first.t,
            truth_end: truth.last().map_or(first.t, |r| r.t),
            imu_start,
            imu_end,
            rows: n,
        });
    }
    let k = n as f64;
    out.horizontal_error_rms_m = (h2 / k).sqrt();
    out.depth_error_rms_m = (d2 / k).sqrt();
    out.nees_mean = nees_sum / k;
    out.scored_seconds = t_last - t_first;
    out.scored_rows = n;
    let truth_span = truth.last().map_or(0.0, |r| r.t) - first.t;
    if out.scored_seconds < 0.5 * truth_span {
        out.partial = Some(format!(
            "truth.csv: only {:.1} s of its {:.1} s (t = {t_first}..{t_last} s, {n} of {} rows) \
             overlap the estimate and are scored",
            out.scored_seconds,
            truth_span,
            truth.len()
        ));
    }
    out.table = table;
    Ok(out)
}

/// Two-sided 95 % band of the NEES of `dof` states averaged over `runs`
/// independent runs: `chi2(dof runs)` quantiles divided by `runs`.
pub fn nees_band_95(dof: usize, runs: usize) -> (f64, f64) {
    let k = dof * runs.max(1);
    let r = runs.max(1) as f64;
    let q = |p: f64| chi_square_quantile(p, k).unwrap_or(f64::NAN) / r;
    (q(0.025), q(0.975))
}
