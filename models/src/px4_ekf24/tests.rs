//! The generated PX4 24-state code against the independent evaluation of
//! `reference.rs`, at random operating points.

use super::reference::{self, Step};
use super::{Px4Ekf24, Px4Ekf24Single};
use nav_runtime::model::{Model, Record};
use nav_runtime::nalgebra::{SMatrix, SVector, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

type Input = <Px4Ekf24 as Model<24>>::Input;
type Params = <Px4Ekf24 as Model<24>>::Params;
type Noise = <Px4Ekf24 as Model<24>>::Noise;

/// One random operating point: a unit quaternion, flight-like velocities
/// and positions, biases, fields and wind of their usual sizes, IMU
/// increments of a 400 Hz step (PX4 predicts at about 100 Hz from summed
/// increments; the size does not matter to the comparison).
struct Point {
    x: SVector<f64, 24>,
    step: Step,
    variances: [f64; 6],
    cov: SMatrix<f64, 24, 24>,
}

fn point(seed: u64) -> Point {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut u = |scale: f64| scale * rng.random_range(-1.0..1.0);
    let q = SVector::<f64, 4>::new(u(1.0), u(1.0), u(1.0), u(1.0)).normalize();
    let mut x = SVector::<f64, 24>::zeros();
    x.fixed_rows_mut::<4>(0).copy_from(&q);
    let scales = [
        (4, 3, 10.0),
        (7, 3, 100.0),
        (10, 3, 1e-3),
        (13, 3, 0.1),
        (16, 3, 0.5),
        (19, 3, 0.05),
        (22, 2, 5.0),
    ];
    for (start, len, scale) in scales {
        for i in start..start + len {
            x[i] = u(scale);
        }
    }
    let dt_v = 0.01 * (1.0 + 0.1 * u(1.0));
    let dt_a = 0.01 * (1.0 + 0.1 * u(1.0));
    let step = Step {
        delta_velocity: [u(0.1), u(0.1), -9.8 * dt_v + u(0.05)],
        delta_velocity_dt: dt_v,
        delta_angle: [u(0.02), u(0.02), u(0.02)],
        delta_angle_dt: dt_a,
        gravity: 9.80665,
    };
    let variances = [
        (0.35 * dt_v).powi(2) * (1.0 + 0.2 * u(1.0)),
        (0.35 * dt_v).powi(2) * (1.0 + 0.2 * u(1.0)),
        (0.35 * dt_v).powi(2) * (1.0 + 0.2 * u(1.0)),
        (0.015 * dt_a).powi(2) * (1.0 + 0.2 * u(1.0)),
        (0.015 * dt_a).powi(2) * (1.0 + 0.2 * u(1.0)),
        (0.015 * dt_a).powi(2) * (1.0 + 0.2 * u(1.0)),
    ];
    // A dense, well-conditioned covariance: B B^T + a diagonal.
    let b = SMatrix::<f64, 24, 24>::from_fn(|_, _| u(0.3));
    let cov = b * b.transpose() + SMatrix::<f64, 24, 24>::identity() * 0.1;
    Point {
        x,
        step,
        variances,
        cov,
    }
}

fn inputs(s: &Step) -> (Input, Params) {
    let input = Input {
        delta_velocity: Vector3::from(s.delta_velocity),
        delta_velocity_dt: s.delta_velocity_dt,
        delta_angle: Vector3::from(s.delta_angle),
        delta_angle_dt: s.delta_angle_dt,
    };
    (input, Params { gravity: s.gravity })
}

fn noise(v: &[f64; 6]) -> Noise {
    Noise::from_fn(|i| v[i])
}

fn relative(a: &SMatrix<f64, 24, 24>, b: &SMatrix<f64, 24, 24>) -> f64 {
    (a - b).amax() / b.amax()
}

#[test]
fn generated_code_equals_the_independent_evaluation() {
    let mut worst = [0.0f64; 4];
    for seed in 0..50 {
        let p = point(seed);
        let (u, par) = inputs(&p.step);
        let q = noise(&p.variances);
        // `dt` is unused: the model takes its times from the inputs.
        let dt = f64::NAN;

        let next = Px4Ekf24::transition(&p.x, &u, &par, dt);
        let next_ref = reference::next_state(&p.x, &p.step);
        worst[0] = worst[0].max((next - next_ref).amax() / next_ref.amax());

        let phi = Px4Ekf24::jacobian(&p.x, &u, &par, dt);
        let phi_ref = reference::transition_matrix(&p.x, &p.step);
        worst[1] = worst[1].max(relative(&phi, &phi_ref));

        let qd = Px4Ekf24::process_noise(&p.x, &u, &par, &q, dt);
        let qd_ref = reference::process_noise(&p.x, &p.step, &p.variances);
        worst[2] = worst[2].max(relative(&qd, &qd_ref));

        let mut cov = p.cov;
        Px4Ekf24::propagate_covariance(&mut cov, &p.x, &u, &par, &q, dt);
        let cov_ref = phi_ref * p.cov * phi_ref.transpose() + qd_ref;
        worst[3] = worst[3].max(relative(&cov, &cov_ref));
        assert_eq!(cov, cov.transpose(), "seed {seed}: not exactly symmetric");
    }
    let [next, phi, qd, cov] = worst;
    assert!(next < 1e-15, "transition {next:e}");
    assert!(phi < 1e-15, "Phi {phi:e}");
    assert!(qd < 1e-14, "Qd {qd:e}");
    assert!(cov < 1e-13, "Phi P Phi^T + Qd {cov:e}");
}

/// Every structural zero of the generated sparsity is a zero of the
/// reference `Phi` at generic points, and every entry it keeps is nonzero
/// at some point: the generator found the model's real structure.
#[test]
fn sparsity_is_the_model_structure() {
    let mut seen = [[false; 24]; 24];
    for seed in 0..10 {
        let p = point(seed);
        let phi = reference::transition_matrix(&p.x, &p.step);
        for (i, row) in seen.iter_mut().enumerate() {
            for (j, s) in row.iter_mut().enumerate() {
                *s |= phi[(i, j)] != 0.0;
            }
        }
    }
    assert_eq!(seen, Px4Ekf24::JACOBIAN_SPARSITY);
}

/// The `f32` twin propagates the same covariance to single precision.
#[test]
fn single_precision_agrees() {
    for seed in 0..20 {
        let p = point(seed);
        let (u, par) = inputs(&p.step);
        let q = noise(&p.variances);
        let mut cov = p.cov;
        Px4Ekf24::propagate_covariance(&mut cov, &p.x, &u, &par, &q, 0.0);

        let us = <Px4Ekf24Single as Model<24, f32>>::Input::from_fn(|i| u.get(i));
        let ps = <Px4Ekf24Single as Model<24, f32>>::Params::from_fn(|i| par.get(i));
        let qs = <Px4Ekf24Single as Model<24, f32>>::Noise::from_fn(|i| q.get(i));
        let xs = p.x.map(|v| v as f32);
        let mut covs = p.cov.map(|v| v as f32);
        Px4Ekf24Single::propagate_covariance(&mut covs, &xs, &us, &ps, &qs, 0.0);
        let err = relative(&covs.map(f64::from), &cov);
        assert!(err < 1e-5, "seed {seed}: f32 differs by {err:e}");
    }
}

/// A sequential scalar update of state `i` measured with variance `r`, in
/// Joseph form, in the scalar of the covariance.
fn update_state<T: nav_runtime::nalgebra::RealField + Copy>(
    cov: &mut SMatrix<T, 24, 24>,
    i: usize,
    r: T,
) {
    let k = cov.column(i) / (cov[(i, i)] + r);
    let mut a = SMatrix::<T, 24, 24>::identity();
    for row in 0..24 {
        a[(row, i)] -= k[row];
    }
    *cov = a * *cov * a.transpose() + k * k.transpose() * r;
}

/// The `f32` twin over a minute of flight against the `f64` model: 6,000
/// covariance steps of 10 ms (PX4's prediction rate) with varying IMU
/// increments, position and velocity fixed at 5 Hz. Single precision loses
/// a little of the cross-covariances at every step (docs/language.md,
/// "Scalar type"); the standard deviations must stay within 0.1 % of the
/// `f64` ones (measured: 3.3e-5), and no variance may turn non-positive.
#[test]
fn single_precision_over_a_minute_of_flight() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let p = point(3);
    let mut x = p.x;
    // Level, heading 30 degrees, 5 m/s north.
    let (s, c) = (15f64.to_radians().sin(), 15f64.to_radians().cos());
    x.fixed_rows_mut::<4>(0)
        .copy_from(&SVector::<f64, 4>::new(c, 0.0, 0.0, s));
    x.fixed_rows_mut::<3>(4)
        .copy_from(&SVector::<f64, 3>::new(5.0, 0.0, 0.0));
    let diagonal = [
        [1e-2; 4].as_slice(),
        &[0.25; 3],
        &[1.0; 3],
        &[1e-6; 3],
        &[1e-4; 3],
        &[1e-3; 3],
        &[1e-3; 3],
        &[1.0; 2],
    ]
    .concat();
    let mut cov =
        SMatrix::<f64, 24, 24>::from_diagonal(&SVector::<f64, 24>::from_column_slice(&diagonal));
    let mut covs = cov.map(|v| v as f32);
    let q = noise(&p.variances);
    let qs = <Px4Ekf24Single as Model<24, f32>>::Noise::from_fn(|i| q.get(i));
    let xs = x.map(|v| v as f32);
    let mut worst = 0.0f64;
    for k in 0..6000 {
        let dt = 0.01;
        let mut u = |scale: f64| scale * rng.random_range(-1.0..1.0);
        let step = Step {
            delta_velocity: [u(0.02), u(0.02), -9.80665 * dt + u(0.01)],
            delta_velocity_dt: dt,
            delta_angle: [u(0.002), u(0.002), u(0.002)],
            delta_angle_dt: dt,
            gravity: 9.80665,
        };
        let (input, par) = inputs(&step);
        Px4Ekf24::propagate_covariance(&mut cov, &x, &input, &par, &q, dt);
        let us = <Px4Ekf24Single as Model<24, f32>>::Input::from_fn(|i| input.get(i));
        let ps = <Px4Ekf24Single as Model<24, f32>>::Params::from_fn(|i| par.get(i));
        Px4Ekf24Single::propagate_covariance(&mut covs, &xs, &us, &ps, &qs, dt as f32);
        if k % 20 == 19 {
            for (i, r) in [
                (4, 0.09),
                (5, 0.09),
                (6, 0.09),
                (7, 0.25),
                (8, 0.25),
                (9, 0.25),
            ] {
                update_state(&mut cov, i, r);
                update_state(&mut covs, i, r as f32);
            }
        }
        for i in 0..24 {
            let (d, ds) = (cov[(i, i)], f64::from(covs[(i, i)]));
            assert!(
                ds > 0.0 && ds.is_finite(),
                "step {k}: f32 variance {i} is {ds}"
            );
            worst = worst.max((ds.sqrt() / d.sqrt() - 1.0).abs());
        }
    }
    eprintln!("f32 standard deviations within {worst:.3e} of f64 over 60 s");
    assert!(worst < 1e-3, "f32 standard deviations {worst:e} from f64");
}
