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

/// Scores `estimates` (one per truth row, `None` where missing) against `truth`.
/// `compass_bias` is the true compass bias (rad) when known.
pub fn score(
    estimates: &[Option<Estimate>],
    truth: &[TruthRow],
    compass_bias: Option<f64>,
) -> Scored {
    let mut table = RunTable::new(TABLE, &COLUMNS);
    let Some(first) = truth.first() else {
        return Scored {
            table,
            ..Scored::default()
        };
    };
    let frame = LocalNed::new(Geodetic::new(first.lat, first.lon, -first.depth));
    let (mut h2, mut d2, mut nees_sum, mut n) = (0.0, 0.0, 0.0, 0usize);
    let mut out = Scored::default();
    for (est, row) in estimates.iter().zip(truth) {
        let Some(e) = est else { continue };
        let tr = truth_state(row);
        let err = e.nav.error_from(&tr);
        let p = err.position_ned(tr.lat, tr.h);
        let x = SVector::<f64, 9>::from([
            p.x, p.y, p.z, err.dv_n.x, err.dv_n.y, err.dv_n.z, err.phi.x, err.phi.y, err.phi.z,
        ]);
        let nees = Cholesky::new(e.cov).map_or(f64::NAN, |c| x.dot(&c.solve(&x)));
        let horizontal = p.x.hypot(p.y);
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
    if n > 0 {
        let k = n as f64;
        out.horizontal_error_rms_m = (h2 / k).sqrt();
        out.depth_error_rms_m = (d2 / k).sqrt();
        out.nees_mean = nees_sum / k;
    } else {
        out.horizontal_error_final_m = f64::NAN;
        out.horizontal_error_rms_m = f64::NAN;
        out.depth_error_rms_m = f64::NAN;
        out.nees_mean = f64::NAN;
    }
    out.table = table;
    out
}

/// Two-sided 95 % band of the NEES of `dof` states averaged over `runs`
/// independent runs: `chi2(dof runs)` quantiles divided by `runs`.
pub fn nees_band_95(dof: usize, runs: usize) -> (f64, f64) {
    let k = dof * runs.max(1);
    let r = runs.max(1) as f64;
    let q = |p: f64| chi_square_quantile(p, k).unwrap_or(f64::NAN) / r;
    (q(0.025), q(0.975))
}
