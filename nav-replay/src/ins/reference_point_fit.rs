//! Whether `truth.csv` describes a point of the vehicle other than the IMU:
//! the truth's velocity at a point `r` (body axes from the IMU) is the
//! IMU's plus `C_b^n (omega x r)`, so in turns the velocity errors of an
//! aided filter against such a truth follow `-C_b^n [omega x] r`. A least
//! squares fit of `r` over the scored rows (docs/log-format.md,
//! "truth.csv") tells an undeclared reference point, or a declared
//! `[files.truth] lever_arm` that is off, from a filter that is wrong.

use nav_runtime::attitude::rotvec_from_rotation;
use nav_runtime::log::TruthRow;
use nav_runtime::nalgebra::{Matrix3, Vector3};

use super::setup::c_bn;

/// Rows two truth rows further apart than this are not differenced for the
/// body rate, s.
const MAX_ROW_GAP_S: f64 = 5.0;

/// The fitted arm is reported when its length is at least this, m.
pub const MIN_REPORTED_ARM_M: f64 = 0.5;

/// ... a horizontal component is at least this many of its standard errors
/// ...
pub const MIN_REPORTED_SIGMAS: f64 = 5.0;

/// ... and it explains at least this share of the velocity errors' sum of
/// squares. The filter's own errors in turns (while its heading and
/// velocity converge) also follow the turns: on a 200-s simulated survey
/// with the truth at the IMU they fit an arm of 0.40 m at 30 standard
/// errors, explaining 15-19 % of them; a reference point 1.8 m off
/// explains most of a tuned filter's velocity errors.
pub const MIN_EXPLAINED_SHARE: f64 = 1.0 / 3.0;

/// A point the truth seems to describe, fitted over a run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FittedPoint {
    /// The arm, body axes (FRD) from the IMU, m (beyond the declared one).
    pub arm: [f64; 3],
    /// Its standard errors, m.
    pub sigma: [f64; 3],
    /// The share of the velocity errors' sum of squares the arm explains.
    pub explained: f64,
    /// The truth rows fitted.
    pub rows: usize,
}

/// The normal equations of the fit, accumulated row by row.
#[derive(Clone, Debug, Default)]
pub struct ReferencePointFit {
    previous: Option<TruthRow>,
    normal: Matrix3<f64>,
    right: Vector3<f64>,
    squares: f64,
    rows: usize,
}

impl ReferencePointFit {
    /// One truth row (in time order) with the velocity error of the
    /// estimate there (estimate minus truth, north-east-down, m/s; `None`
    /// when the row has no estimate).
    pub fn push(&mut self, row: &TruthRow, velocity_error: Option<Vector3<f64>>) {
        let previous = self.previous.replace(*row);
        let (Some(before), Some(error)) = (previous, velocity_error) else {
            return;
        };
        let dt = row.t - before.t;
        if !(dt > 0.0 && dt <= MAX_ROW_GAP_S && error.iter().all(|v| v.is_finite())) {
            return;
        }
        let c = c_bn(row.roll, row.pitch, row.yaw);
        let c_before = c_bn(before.roll, before.pitch, before.yaw);
        let omega = rotvec_from_rotation(&(c_before.transpose() * c)) / dt;
        // error = -C (omega x r) = -C [omega x] r
        let a = -c * omega.cross_matrix();
        if !a.iter().all(|v| v.is_finite()) {
            return;
        }
        self.normal += a.transpose() * a;
        self.right += a.transpose() * error;
        self.squares += error.norm_squared();
        self.rows += 1;
    }

    /// The fitted point, when it is large, certain and explanatory enough
    /// to report ([`MIN_REPORTED_ARM_M`], [`MIN_REPORTED_SIGMAS`] for a
    /// horizontal component, [`MIN_EXPLAINED_SHARE`]). A direction the run's motion does not show (the
    /// vertical component when the vehicle only turns about the vertical:
    /// `omega x r` then has no share of it) is left out of the fit: its
    /// component is 0 with an infinite sigma.
    pub fn finish(&self) -> Option<FittedPoint> {
        if self.rows < 10 {
            return None;
        }
        let eigen = self.normal.symmetric_eigen();
        let largest = eigen.eigenvalues.max();
        if largest.is_nan() || largest <= 0.0 {
            return None;
        }
        // Solution and (unscaled) covariance over the directions shown.
        let (mut arm, mut covariance) = (Vector3::zeros(), Matrix3::zeros());
        let mut shown = [false; 3];
        for (k, &value) in eigen.eigenvalues.iter().enumerate() {
            if value > 1e-6 * largest {
                let v = eigen.eigenvectors.column(k);
                arm += v * (v.dot(&self.right) / value);
                covariance += v * v.transpose() / value;
                for (i, s) in shown.iter_mut().enumerate() {
                    *s |= v[i].abs() > 1e-3;
                }
            }
        }
        let dof = (3 * self.rows - 3) as f64;
        let variance = ((self.squares - arm.dot(&self.right)) / dof).max(0.0);
        let sigma: [f64; 3] = std::array::from_fn(|i| {
            if shown[i] {
                (variance * covariance[(i, i)]).max(0.0).sqrt()
            } else {
                f64::INFINITY
            }
        });
        let explained = arm.dot(&self.right) / self.squares;
        let certain = (0..2).any(|i| arm[i].abs() > MIN_REPORTED_SIGMAS * sigma[i]);
        let reported = arm.norm() >= MIN_REPORTED_ARM_M
            && certain
            && explained >= MIN_EXPLAINED_SHARE
            && arm.iter().all(|v| v.is_finite());
        reported.then(|| FittedPoint {
            arm: [arm.x, arm.y, arm.z],
            sigma,
            explained,
            rows: self.rows,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nav_runtime::earth::Geodetic;
    use nav_runtime::trajectory::{Trajectory, TrajectorySpec, TruthSource};

    /// Truth rows at 1 Hz of a vehicle making three turns, with the
    /// velocity errors a truth at `arm` gives (`-C (omega x r)`, omega from
    /// the trajectory itself) plus white noise of 2 cm/s.
    fn fitted(arm: [f64; 3]) -> (Option<FittedPoint>, ReferencePointFit) {
        let mut spec = TrajectorySpec::new(Geodetic::new(0.6, 2.2, -40.0), 0.3, 1.5);
        let mut t = 20.0;
        for delta in [1.6, -2.1, 3.0] {
            t = spec.turn(t, delta) + 15.0;
        }
        let traj = Trajectory::new(spec, 120.0, 0.1);
        let mut fit = ReferencePointFit::default();
        let mut noise = 0x9E37_79B9_7F4A_7C15u64;
        let mut uniform = || {
            noise ^= noise << 13;
            noise ^= noise >> 7;
            noise ^= noise << 17;
            (noise >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        for k in 0..120 {
            let s = traj.truth(k as f64);
            let row = TruthRow::from(&s);
            let e = -(s.c_bn * s.w_nb_b.cross(&Vector3::from(arm)));
            // Uniform on [-0.5, 0.5] times 0.07: 2 cm/s sigma.
            let e = e + Vector3::new(uniform(), uniform(), uniform()) * 0.07;
            fit.push(&row, Some(e));
        }
        (fit.finish(), fit)
    }

    #[test]
    fn a_reference_point_is_found_from_the_velocity_errors() {
        let arm = [1.8, -0.4, 0.3];
        let (found, _) = fitted(arm);
        let found = found.expect("reported");
        for (k, truth) in arm.iter().enumerate().take(2) {
            assert!(
                (found.arm[k] - truth).abs() < 4.0 * found.sigma[k],
                "{found:?}"
            );
            assert!(found.sigma[k] < 0.1, "{found:?}");
        }
        // Turns about the vertical alone do not show the vertical arm.
        assert_eq!(
            (found.arm[2], found.sigma[2]),
            (0.0, f64::INFINITY),
            "{found:?}"
        );
        assert_eq!(found.rows, 119);
    }

    #[test]
    fn the_imu_itself_is_not_reported() {
        let (found, fit) = fitted([0.0; 3]);
        assert_eq!(found, None);
        // The fit ran (the run turned): it is the test that refused.
        assert!(fit.rows > 100 && fit.normal.norm() > 0.0);
    }
}
