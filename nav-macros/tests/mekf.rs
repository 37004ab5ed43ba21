//! The multiplicative error-state pattern for attitude (docs/language.md,
//! "Attitude"), as a quaternion AHRS with gyro bias and an accelerometer, run
//! against a simulated truth over seeds: accelerometer NIS and 6-state NEES
//! must be consistent.
//!
//! The filter's state is a 3-element attitude error `attitude_error` about a
//! nominal unit quaternion kept outside the filter (`q_true = q_nominal ⊗
//! exp(attitude_error)`) and the gyro bias. The nominal is propagated with the
//! bias-corrected gyro; after each accelerometer update the error is folded
//! into the nominal and reset to zero.
//!
//! The same declaration is generated twice, in `f64` ([`Mekf`]) and in `f32`
//! ([`MekfSingle`], `scalar f32;`): the single-precision filter must be as
//! consistent, and its estimates must agree with the double-precision ones to
//! a small fraction of their sigma.

use nav_runtime::ekf::Ekf;
use nav_runtime::model::{Model, Record, Sensor};
use nav_runtime::nalgebra::{SMatrix, SVector};
use nav_runtime::Real;

/// The declaration, for a model name and a scalar.
macro_rules! mekf {
    ($name:ident, $scalar:ident) => {
nav_runtime::model! {
    /// Attitude error about a nominal quaternion, and gyro bias.
    pub model $name {
        scalar $scalar;
        states {
            /// attitude error, rad: `q_true = q_nominal ⊗ exp(attitude_error)`
            attitude_error: 3,
            /// gyro bias, rad/s
            gyro_bias: 3,
        }
        inputs {
            /// measured body rate, rad/s
            gyro: 3,
            /// the bias the nominal was propagated with, rad/s
            bias_used: 3,
            /// the nominal attitude `[w, x, y, z]`, body to navigation
            nominal: 4,
        }
        parameters { gravity }
        noise { gyro_noise: 3, bias_noise: 3 }
        continuous {
            d/dt attitude_error = -cross(gyro - gyro_bias, attitude_error) + bias_used - gyro_bias - gyro_noise;
            d/dt gyro_bias = bias_noise;
        }
        /// Specific force at rest (or in pure rotation), body axes; navigation
        /// axes north-east-down.
        sensor Accel: 3 {
            let c_bn = quat_to_dcm(quat_mul(nominal, rotvec_to_quat(attitude_error)));
            h = transpose(c_bn) * [0.0, 0.0, -gravity];
        }
    }
}
    };
}

mekf!(Mekf, f64);
mekf!(MekfSingle, f32);

type Quat = SVector<f64, 4>;
type Vec3 = SVector<f64, 3>;

fn quat_mul(p: &Quat, q: &Quat) -> Quat {
    Quat::new(
        p[0] * q[0] - p[1] * q[1] - p[2] * q[2] - p[3] * q[3],
        p[0] * q[1] + p[1] * q[0] + p[2] * q[3] - p[3] * q[2],
        p[0] * q[2] - p[1] * q[3] + p[2] * q[0] + p[3] * q[1],
        p[0] * q[3] + p[1] * q[2] - p[2] * q[1] + p[3] * q[0],
    )
}

fn exp(v: &Vec3) -> Quat {
    let theta = v.norm();
    let k = if theta < 1e-12 {
        0.5
    } else {
        (0.5 * theta).sin() / theta
    };
    Quat::new((0.5 * theta).cos(), k * v[0], k * v[1], k * v[2])
}

/// The rotation vector of a unit quaternion (shortest rotation).
fn log(q: &Quat) -> Vec3 {
    let q = if q[0] < 0.0 { -q } else { *q };
    let v = Vec3::new(q[1], q[2], q[3]);
    let s = v.norm();
    if s < 1e-12 {
        return 2.0 * v;
    }
    2.0 * s.atan2(q[0]) / s * v
}

fn conj(q: &Quat) -> Quat {
    Quat::new(q[0], -q[1], -q[2], -q[3])
}

fn dcm(q: &Quat) -> SMatrix<f64, 3, 3> {
    let (w, x, y, z) = (q[0], q[1], q[2], q[3]);
    SMatrix::<f64, 3, 3>::new(
        1.0 - 2.0 * (y * y + z * z),
        2.0 * (x * y - w * z),
        2.0 * (x * z + w * y),
        2.0 * (x * y + w * z),
        1.0 - 2.0 * (x * x + z * z),
        2.0 * (y * z - w * x),
        2.0 * (x * z - w * y),
        2.0 * (y * z + w * x),
        1.0 - 2.0 * (x * x + y * y),
    )
}

/// splitmix64 and Box-Muller: standard normal samples from a seed.
struct Normal(u64);

impl Normal {
    fn uniform(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
    fn sample(&mut self) -> f64 {
        let (u, v) = (self.uniform().max(1e-300), self.uniform());
        (-2.0 * u.ln()).sqrt() * (2.0 * std::f64::consts::PI * v).cos()
    }
    fn vec3(&mut self, sigma: f64) -> Vec3 {
        Vec3::new(self.sample(), self.sample(), self.sample()) * sigma
    }
}

const GRAVITY: f64 = 9.81;
const DT: f64 = 0.01;
const STEPS: usize = 6000;
const UPDATE_EVERY: usize = 10;
/// Gyro noise density, rad/s/sqrt(Hz); bias random walk, rad/s^2/sqrt(Hz).
const GYRO_DENSITY: f64 = 2e-3;
const BIAS_DENSITY: f64 = 1e-5;
const ACCEL_SIGMA: f64 = 0.05;
const ATTITUDE_SIGMA0: f64 = 0.05;
const BIAS_SIGMA0: f64 = 0.01;

/// The state after the last update and its sigma (f64).
type Final = (SVector<f64, 6>, SVector<f64, 6>);
/// One run: NIS and NEES per update, and the final state.
type Run = (Vec<f64>, Vec<f64>, Final);

/// One run of the filter `M` (sensor `A`) in the scalar `T`: per
/// accelerometer update, the NIS and the 6-state NEES after the update
/// (before the reset), and the state after the last update. The truth, the
/// sensor samples and the nominal quaternion are `f64`, so two scalars see
/// the same data.
fn run<M, A, T>(seed: u64) -> Run
where
    M: Model<6, T>,
    A: Sensor<6, 3, T, Model = M, Aux = ()>,
    T: Real,
{
    let mut rng = Normal(seed);
    let mut q_true = exp(&rng.vec3(1.0));
    let mut bias_true = rng.vec3(BIAS_SIGMA0);
    let mut nominal = quat_mul(&q_true, &exp(&rng.vec3(ATTITUDE_SIGMA0)));
    let phase = rng.uniform() * 6.0;
    let p0 = SMatrix::<T, 6, 6>::from_diagonal(&SVector::<T, 6>::from_fn(|i, _| {
        T::of(if i < 3 {
            ATTITUDE_SIGMA0 * ATTITUDE_SIGMA0
        } else {
            BIAS_SIGMA0 * BIAS_SIGMA0
        })
    }));
    // Records are built by position (declaration order) from f64 values.
    let noise = M::Noise::from_fn(|i| {
        if i < 3 {
            GYRO_DENSITY * GYRO_DENSITY
        } else {
            BIAS_DENSITY * BIAS_DENSITY
        }
    });
    let mut ekf = Ekf::<M, 6, T>::new(SVector::zeros(), p0, M::Params::from_fn(|_| GRAVITY), noise)
        .expect("valid setup");
    ekf.set_default_gate(None);
    let r = SMatrix::<T, 3, 3>::identity() * T::of(ACCEL_SIGMA * ACCEL_SIGMA);
    let (mut nis, mut nees) = (Vec::new(), Vec::new());
    let mut last = (SVector::zeros(), SVector::zeros());
    for k in 0..STEPS {
        let t = k as f64 * DT;
        let rate = Vec3::new(0.4 * (0.5 * t + phase).sin(), 0.3 * (0.3 * t).cos(), 0.2);
        let gyro = rate + bias_true + rng.vec3(GYRO_DENSITY / DT.sqrt());
        q_true = quat_mul(&q_true, &exp(&(rate * DT)));
        bias_true += rng.vec3(BIAS_DENSITY * DT.sqrt());
        let bias_used = ekf.state().fixed_rows::<3>(3).map(T::to_f64);
        nominal = quat_mul(&nominal, &exp(&((gyro - bias_used) * DT))).normalize();
        let input: [f64; 10] = core::array::from_fn(|i| match i {
            0..=2 => gyro[i],
            3..=5 => bias_used[i - 3],
            _ => nominal[i - 6],
        });
        ekf.predict(T::of(DT), &M::Input::from_fn(|i| input[i]))
            .expect("predict");
        if (k + 1) % UPDATE_EVERY != 0 {
            continue;
        }
        let z = dcm(&q_true).transpose() * Vec3::new(0.0, 0.0, -GRAVITY) + rng.vec3(ACCEL_SIGMA);
        let report = ekf.update::<A, 3>(&z.map(T::of), &r, &()).expect("update");
        nis.push(report.nis);
        let x = ekf.state().map(T::to_f64);
        let attitude_error = log(&quat_mul(&conj(&nominal), &q_true));
        let mut e = SVector::<f64, 6>::zeros();
        e.fixed_rows_mut::<3>(0)
            .copy_from(&(attitude_error - x.fixed_rows::<3>(0)));
        e.fixed_rows_mut::<3>(3)
            .copy_from(&(bias_true - x.fixed_rows::<3>(3)));
        let p = ekf.covariance().map(T::to_f64);
        last = (x, p.diagonal().map(f64::sqrt));
        nees.push(e.dot(&(p.cholesky().expect("P positive definite").solve(&e))));
        // Reset: fold the error into the nominal.
        nominal = quat_mul(&nominal, &exp(&x.fixed_rows::<3>(0).into_owned())).normalize();
        let mut reset = *ekf.state();
        reset.fixed_rows_mut::<3>(0).fill(T::zero());
        ekf.set_state(reset).expect("finite state");
    }
    (nis, nees, last)
}

/// Checks the Monte Carlo consistency of 20 runs (seeds `7919 k`): the
/// run-averaged NIS (3 dof) and NEES (6 dof) of each update time must lie in
/// their two-sided 95 % chi-square bands for 20 runs (NIS: chi2(60)/20 in
/// [2.02, 4.17]; NEES: chi2(120)/20 in [4.77, 7.38]) at least 90 % of the
/// time, and their grand means within 10 % of 3 and 6. Returns the final
/// states.
fn assert_consistent(what: &str, runs: Vec<Run>) -> Vec<Final> {
    let n = runs[0].0.len();
    let averaged = |pick: &dyn Fn(&Run) -> &Vec<f64>| -> Vec<f64> {
        (0..n)
            .map(|i| runs.iter().map(|r| pick(r)[i]).sum::<f64>() / runs.len() as f64)
            .collect()
    };
    let nis = averaged(&|r| &r.0);
    let nees = averaged(&|r| &r.1);
    let inside = |v: &[f64], lo: f64, hi: f64| {
        v.iter().filter(|&&x| x >= lo && x <= hi).count() as f64 / v.len() as f64
    };
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    let (nis_in, nees_in) = (inside(&nis, 2.02, 4.17), inside(&nees, 4.77, 7.38));
    let (nis_mean, nees_mean) = (mean(&nis), mean(&nees));
    eprintln!(
        "{what}, 20 seeds x {n} updates: mean NIS {nis_mean:.3} (3), in band {:.1} %; \
         mean NEES {nees_mean:.3} (6), in band {:.1} %",
        100.0 * nis_in,
        100.0 * nees_in
    );
    assert!((nis_mean - 3.0).abs() < 0.3, "{what}: mean NIS {nis_mean}");
    assert!(
        (nees_mean - 6.0).abs() < 0.6,
        "{what}: mean NEES {nees_mean}"
    );
    assert!(nis_in >= 0.9, "{what}: NIS in band {nis_in}");
    assert!(nees_in >= 0.9, "{what}: NEES in band {nees_in}");
    runs.into_iter().map(|r| r.2).collect()
}

/// Monte Carlo over 20 seeds of 60 s (600 accelerometer updates each), in
/// `f64` and in `f32`: both consistent, and the `f32` final estimates within
/// 1 % of the final sigma of the `f64` ones (the rounding of 6,000
/// single-precision steps stays far below the statistical spread).
#[test]
fn multiplicative_ahrs_is_consistent_over_seeds_in_both_precisions() {
    let seeds: Vec<u64> = (1..=20u64).map(|s| s * 7919).collect();
    let double = assert_consistent(
        "MEKF AHRS (f64)",
        seeds
            .iter()
            .map(|&s| run::<Mekf, MekfAccel, f64>(s))
            .collect(),
    );
    let single = assert_consistent(
        "MEKF AHRS (f32)",
        seeds
            .iter()
            .map(|&s| run::<MekfSingle, MekfSingleAccel, f32>(s))
            .collect(),
    );
    let mut worst: f64 = 0.0;
    for ((a, sigma), (b, _)) in double.iter().zip(&single) {
        for i in 0..6 {
            worst = worst.max((a[i] - b[i]).abs() / sigma[i]);
        }
    }
    eprintln!("f32 against f64: largest final difference {worst:.2e} sigma");
    assert!(worst < 0.01, "f32 differs from f64 by {worst} sigma");
}
