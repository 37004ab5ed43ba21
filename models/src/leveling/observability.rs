//! Which combinations of the [`Leveling8`] states the measurements determine
//! along a motion (docs/results/leveling6.md, "Observability"): the filter is
//! linearized along the noise-free truth, `Phi` is propagated at the IMU rate,
//! and the rows `H Phi(t_k, 0)` of every measurement epoch are stacked into the
//! observability matrix of the initial state. Columns are scaled to a typical
//! error (0.1 m/s, 1 mrad of `a`, 1 mg) and rows by the measurement sigma, so
//! the singular values compare information about comparable errors; a
//! singular value many orders below the largest is a combination the data
//! cannot determine, and its right singular vector says which one.

use super::filter::Tuning;
use super::model::{
    Leveling8, Leveling8Input, Leveling8Moving, Leveling8Params, Leveling8Stationary,
};
use super::simulation::{self, Motion, DURATION, IMU_RATE, SPEED_RATE};
use nav_runtime::attitude::Euler;
use nav_runtime::earth;
use nav_runtime::imu::{self, MG};
use nav_runtime::model::{Model, Sensor};
use nav_runtime::nalgebra::{DMatrix, SMatrix, SVector};
use nav_runtime::trajectory::TruthSource;

/// The singular values of the scaled observability matrix, largest first, and
/// the right singular vectors (columns, in state order) belonging to them.
#[derive(Clone, Debug)]
pub struct Observability {
    /// Singular values, descending.
    pub singular_values: Vec<f64>,
    /// Right singular vectors in scaled state coordinates, one per singular value.
    pub directions: Vec<SVector<f64, 8>>,
}

impl Observability {
    /// Number of singular values above `ratio` times the largest.
    pub fn rank(&self, ratio: f64) -> usize {
        let top = self.singular_values.first().copied().unwrap_or(0.0);
        self.singular_values
            .iter()
            .filter(|&&s| s > ratio * top)
            .count()
    }
}

/// Typical error of each state, the column scaling.
fn scale() -> SVector<f64, 8> {
    SVector::<f64, 8>::from_column_slice(&[0.1, 0.1, 0.1, 1e-3, 1e-3, 1e-3, MG, MG])
}

/// The observability of [`Leveling8`] over `seconds` of `motion`'s truth with
/// its measurement model (moving: speed log and unit norm; stationary: zero
/// velocity and unit norm).
pub fn analyse(motion: Motion, seconds: f64) -> Observability {
    let truth = simulation::trajectory(motion);
    let start = truth.spec().start;
    let params = Leveling8Params {
        gravity: earth::normal_gravity(start.lat, start.h),
    };
    let tuning = Tuning::default();
    let w_ie_n = earth::earth_rate_n(start.lat);
    let d = SMatrix::<f64, 8, 8>::from_diagonal(&scale());
    let mut phi = SMatrix::<f64, 8, 8>::identity();
    let mut rows: Vec<f64> = Vec::new();
    let mut n_rows = 0usize;
    let every = (IMU_RATE / SPEED_RATE).round() as usize;
    let dt = 1.0 / IMU_RATE;
    for (k, r) in imu::rates(&truth, IMU_RATE, seconds.min(DURATION)).enumerate() {
        let s = truth.truth(r.t);
        let e = Euler::new(s.euler.roll, s.euler.pitch, s.euler.yaw);
        let a = super::filter::gravity_direction(e.roll, e.pitch);
        let v = s.v_body();
        let x = SVector::<f64, 8>::from_column_slice(&[v.x, v.y, v.z, a.x, a.y, a.z, 0.0, 0.0]);
        let u = Leveling8Input {
            gyro: r.w_ib_b,
            specific_force: r.f_b,
            earth_rate_body: e.c_nb() * w_ie_n,
        };
        if k > 0 && k % every == 0 {
            // One row `H_i Phi D / sigma_i` per measured component.
            let mut push = |h: [f64; 8], sigma: f64| {
                let row = (SVector::<f64, 8>::from(h).transpose() * phi * d) / sigma;
                rows.extend(row.iter());
                n_rows += 1;
            };
            if motion.is_stationary() {
                let h = Leveling8Stationary::jacobian(&x, &u, &params, &());
                for i in 0..3 {
                    push(row_of(&h, i), tuning.zero_velocity_sigma);
                }
                push(row_of(&h, 3), tuning.norm_sigma);
            } else {
                let h = Leveling8Moving::jacobian(&x, &u, &params, &());
                push(row_of(&h, 0), tuning.speed_sigma);
                push(row_of(&h, 1), tuning.norm_sigma);
            }
        }
        let f = Leveling8::jacobian(&x, &u, &params, dt);
        phi = (SMatrix::<f64, 8, 8>::identity() + f * dt) * phi;
    }
    let o = DMatrix::from_row_slice(n_rows, 8, &rows);
    let svd = o.svd(false, true);
    let v_t = svd.v_t.expect("requested");
    let mut pairs: Vec<(f64, SVector<f64, 8>)> = svd
        .singular_values
        .iter()
        .enumerate()
        .map(|(i, &s)| {
            (
                s,
                SVector::<f64, 8>::from_iterator(v_t.row(i).iter().copied()),
            )
        })
        .collect();
    pairs.sort_by(|a, b| b.0.total_cmp(&a.0));
    Observability {
        singular_values: pairs.iter().map(|p| p.0).collect(),
        directions: pairs.into_iter().map(|p| p.1).collect(),
    }
}

/// Row `i` of a Jacobian.
fn row_of<const M: usize>(h: &SMatrix<f64, M, 8>, i: usize) -> [f64; 8] {
    std::array::from_fn(|j| h[(i, j)])
}

/// Which scaled state a direction weighs most, and its weight on each state.
pub fn describe(direction: &SVector<f64, 8>) -> String {
    const NAMES: [&str; 8] = ["v_x", "v_y", "v_z", "a1", "a2", "a3", "b_x", "b_y"];
    let mut parts: Vec<String> = Vec::new();
    for (i, name) in NAMES.iter().enumerate() {
        if direction[i].abs() > 0.1 {
            parts.push(format!("{:+.2} {name}", direction[i]));
        }
    }
    parts.join(" ")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Scaled-state indices.
    const A1: usize = 3;
    const A2: usize = 4;
    const VZ: usize = 2;
    const BX: usize = 6;
    const BY: usize = 7;

    /// Two scaled-state indices.
    type Pair = (usize, usize);

    /// Singular value (relative to the largest) of the direction that weighs
    /// states `i` and `j` most together, i.e. the best-aligned right singular vector.
    fn strength_of(o: &Observability, i: usize, j: usize, sign: f64) -> f64 {
        let mut want = SVector::<f64, 8>::zeros();
        want[i] = 1.0;
        want[j] = sign;
        let want = want.normalize();
        let (k, _) = o
            .directions
            .iter()
            .enumerate()
            .map(|(k, d)| (k, d.dot(&want).abs()))
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .expect("eight directions");
        o.singular_values[k] / o.singular_values[0]
    }

    /// Measured over the 30 s of each motion (printed with `--nocapture`):
    ///
    /// | motion | rank (1e-6) | tilt + bias separations |
    /// |---|---|---|
    /// | stationary | 6 | `a1 + b_x`, `a2 + b_y`: 1e-14 (none) |
    /// | straight | 4 | `a1 + b_x`: 2e-9 (none); roll and `b_y`: 1e-4 and below |
    /// | S-type | 7 (only `v_z` missing) | `a1 + b_x`: 2.4e-3, `a2 + b_y`: 1.9e-2 |
    ///
    /// (`a1 + b_x` in scaled units is `g da1 = db_x`: a bias and the tilt it causes.)
    #[test]
    fn which_tilt_and_bias_combinations_are_observable() {
        // (motion, rank at 1e-6, separations that must be absent (< 1e-8),
        //  separations that must be present (> 1e-3)).
        let cases: [(Motion, usize, &[Pair], &[Pair]); 3] = [
            (Motion::Stationary, 6, &[(A1, BX), (A2, BY)], &[]),
            (Motion::Straight, 4, &[(A1, BX)], &[]),
            (Motion::SType, 7, &[], &[(A1, BX), (A2, BY)]),
        ];
        for (motion, rank, absent, present) in cases {
            let o = analyse(motion, DURATION);
            let top = o.singular_values[0];
            eprintln!("{motion:?}: rank(1e-6) {}", o.rank(1e-6));
            for (s, d) in o.singular_values.iter().zip(&o.directions) {
                eprintln!("  {:.3e}  {}", s / top, describe(d));
            }
            assert_eq!(o.rank(1e-6), rank, "{motion:?}");
            for &(i, j) in absent {
                let s = strength_of(&o, i, j, 1.0);
                assert!(s < 1e-8, "{motion:?}: ({i}, {j}) separated at {s:e}");
            }
            for &(i, j) in present {
                let s = strength_of(&o, i, j, 1.0);
                assert!(s > 1e-3, "{motion:?}: ({i}, {j}) only at {s:e}");
            }
        }
        // On the straight track roll and the y bias are not determined either
        // (only the Earth rate couples them into the speed log).
        let straight = analyse(Motion::Straight, DURATION);
        assert!(strength_of(&straight, A2, BY, -1.0) < 1e-3);
        // The weave separates the y bias (first order in the heading swing)
        // better than the x bias (second order): the x bias is the weak one.
        let weave = analyse(Motion::SType, DURATION);
        assert!(strength_of(&weave, A1, BX, 1.0) < 0.5 * strength_of(&weave, A2, BY, 1.0));
        // The vertical body velocity is unobservable in every moving case (no
        // pitch rate couples it into the forward speed); it does not touch the tilt.
        assert!(strength_of(&weave, VZ, VZ, 1.0) < 1e-6);
    }

    /// The replay's observability report (recorded along the filter's own
    /// estimate, docs/observability.md) on the S-track, against the answer
    /// above: the forward accelerometer bias is learned least of the two,
    /// and a weakest direction is the forward bias against the tilt it
    /// causes; the vertical velocity is not learned at all.
    #[test]
    fn the_run_report_finds_the_forward_bias_against_the_tilt_on_the_s_track() {
        use super::super::filter::{observability_of_run, LevelingOptions};
        use super::super::simulation::{simulate, Biases};
        let log = simulate(Motion::SType, Biases::OneSigma, 11);
        let truth = simulation::trajectory(Motion::SType).truth(0.0);
        let options = LevelingOptions {
            stationary: false,
            initial_attitude: Some((truth.euler.roll, truth.euler.pitch)),
            tuning: Tuning {
                bias_states: true,
                ..Tuning::default()
            },
        };
        let o = observability_of_run(&log, &options, 4).unwrap();
        eprintln!("learned {:?}", o.learned);
        for d in &o.weakest {
            eprintln!("  {:.3e}  {:?}", d.learned, d.coefficients);
        }
        // Measured (seed 11): b_x 0.005, b_y 0.21, v_z 1e-8, tilt 0.97-0.999.
        assert!(o.learned[BX] < 0.05, "{:?}", o.learned);
        assert!(o.learned[BY] > 4.0 * o.learned[BX], "{:?}", o.learned);
        assert!(o.learned[VZ] < 1e-6, "{:?}", o.learned);
        assert!(
            o.learned[A1] > 0.9 && o.learned[A2] > 0.9,
            "{:?}",
            o.learned
        );
        // The weakest direction after v_z: the forward bias with the tilt
        // that hides it, `g da1 = db_x`, which in prior-sigma units is a
        // coefficient of sigma_b / (g sigma_a) on a1 (sigma_a = 1: the tilt
        // is known far better than the bias, relative to their priors).
        let bias = o
            .weakest
            .iter()
            .find(|d| d.coefficients[BX] == 1.0)
            .unwrap_or_else(|| panic!("no direction led by b_x: {:?}", o.weakest));
        assert!(bias.learned < 0.01, "{}", bias.learned);
        let expected = options.tuning.accel_bias_sigma / 9.81;
        let a1 = bias.coefficients[A1].abs();
        assert!((0.5..1.5).contains(&(a1 / expected)), "{a1} vs {expected}");
        assert!(
            bias.coefficients[BY].abs() < 0.01,
            "{:?}",
            bias.coefficients
        );
        // One sensor (the speed log with the unit norm): all of it.
        assert_eq!(o.by_sensor.len(), 1);
        for (i, l) in o.by_sensor[0].1.iter().enumerate() {
            assert!((l - o.learned[i]).abs() < 1e-6, "{i}");
        }
    }
}
