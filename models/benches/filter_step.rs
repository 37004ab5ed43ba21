//! One full SDINS-25 filter step at 100 Hz against one dense covariance
//! propagation alone, in the same run.
//!
//! A step is: the error model's input from the nominal solution, the strapdown
//! mechanization (`Strapdown::update_rates`), `ErrorStateFilter::predict`
//! (generated propagation, Euler transition, checks), and the aiding updates
//! amortized: DVL (3 rows), compass (1 row) and depth (1 row) at 2 Hz, each
//! followed by the feedback into the nominal solution. One benchmark
//! iteration of `full_step_x50` is 50 steps (0.5 s of data, one aiding cycle);
//! the per-step cost is its time / 50.
//!
//! Group `step/sdins25`: `full_step_x50`, `dense_propagation` (`Phi P Phi^T +
//! Qd`, `Phi` and `Qd` precomputed), and the parts: `strapdown`, `predict`,
//! `aiding_burst` (the three updates with feedback).
//!
//! Run: `cargo bench -p models --bench filter_step` (ratios: `scripts/bench.sh`).

mod common;

use common::*;
use criterion::{criterion_group, criterion_main, Criterion};
use models::sdins25::model::{Sdins25, Sdins25Compass, Sdins25Depth, Sdins25Dvl, Sdins25Input};
use nav_runtime::attitude::Euler;
use nav_runtime::earth::Geodetic;
use nav_runtime::ekf::Ekf;
use nav_runtime::error_state::{ErrorStateFilter, NominalState};
use nav_runtime::model::Model;
use nav_runtime::nalgebra::{SMatrix, SVector, Vector3};
use nav_runtime::strapdown::{NavError, NavState, Strapdown};
use std::hint::black_box;

/// Steps per aiding cycle (100 Hz IMU, 2 Hz aiding).
const STEPS: usize = 50;

/// The nominal solution: the strapdown INS (sensor-error corrections, a few
/// vector additions in the real filter, are left out).
#[derive(Clone, Debug)]
struct Nominal {
    ins: Strapdown,
}

impl NominalState<25> for Nominal {
    fn inject(&mut self, e: &SVector<f64, 25>) {
        self.ins.inject(&NavError::from_slice(&e.as_slice()[..9]));
    }
}

type Filter = ErrorStateFilter<Sdins25, Nominal, 25>;

/// A filter cruising at the bench operating point, gating off (every update applied).
fn filter() -> Filter {
    let (x, u, par, q) = sdins25_point();
    let state = NavState::new(
        Geodetic::from_degrees(37.0, 127.0, u.height),
        u.velocity,
        &Euler::from_degrees(2.0, -3.0, 40.0),
    );
    let ekf = Ekf::<Sdins25, 25>::new(x, sdins25_covariance(), par, q)
        .unwrap()
        .with_default_gate(None);
    Filter::new(
        ekf,
        Nominal {
            ins: Strapdown::new(state),
        },
    )
}

/// The IMU sample of step `k`: a gentle oscillation on top of the level
/// specific force.
fn imu(k: usize) -> (Vector3<f64>, Vector3<f64>) {
    let s = (k as f64 * 0.05).sin();
    (
        Vector3::new(1e-3 * s, -5e-4 * s, 2e-3),
        Vector3::new(0.02 * s, -0.01, -9.80),
    )
}

/// The error model's input from the nominal solution and the sample, as
/// the SDINS-25 filter builds it, then the mechanization.
fn mechanize(f: &mut Filter, w: &Vector3<f64>, fb: &Vector3<f64>) -> Sdins25Input {
    let ins = &mut f.nominal_mut().ins;
    let s = &ins.state;
    let input = Sdins25Input {
        latitude: s.lat,
        height: s.h,
        velocity: s.v_n,
        c_bn: s.c_bn,
        specific_force: *fb,
    };
    ins.update_rates(w, fb, DT_SDINS);
    input
}

/// DVL, compass and depth residuals with their noise, applied with feedback.
fn aiding(f: &mut Filter) {
    let dvl_r = SMatrix::<f64, 3, 3>::from_diagonal_element(0.01f64.powi(2));
    f.update::<Sdins25Dvl, 3>(&Vector3::new(0.002, -0.001, 0.0005), &dvl_r, &())
        .unwrap();
    let r1 = SMatrix::<f64, 1, 1>::new(0.5f64.to_radians().powi(2));
    f.update::<Sdins25Compass, 1>(&SVector::<f64, 1>::new(1e-3), &r1, &())
        .unwrap();
    let rd = SMatrix::<f64, 1, 1>::new(0.01);
    f.update::<Sdins25Depth, 1>(&SVector::<f64, 1>::new(0.02), &rd, &())
        .unwrap();
}

/// 50 steps: mechanization + prediction each, the aiding burst at the last.
fn cycle(f: &mut Filter) {
    for k in 0..STEPS {
        let (w, fb) = imu(k);
        let input = mechanize(f, &w, &fb);
        f.predict(DT_SDINS, &input).unwrap();
    }
    aiding(f);
}

fn filter_step(c: &mut Criterion) {
    let f0 = filter();
    let mut probe = f0.clone();
    for _ in 0..100 {
        cycle(&mut probe);
    }
    assert!(probe.covariance().iter().all(|v| v.is_finite()));

    let (x, u, par, q) = sdins25_point();
    let phi = dense_phi::<Sdins25, 25>(&x, &u, &par, DT_SDINS);
    let qd = Sdins25::process_noise(&x, &u, &par, &q, DT_SDINS);
    let p0 = sdins25_covariance();

    let mut g = c.benchmark_group("step/sdins25");
    // Restored every 20 cycles (10 s), amortized.
    g.bench_function("full_step_x50", |b| {
        b.iter_custom(|iters| time_in_place(iters, &f0, 20, cycle))
    });
    g.bench_function("dense_propagation", |b| {
        b.iter_custom(|iters| {
            time_in_place(iters, &p0, 1000, |p| {
                dense_propagate(p, black_box(&phi), black_box(&qd))
            })
        })
    });
    g.bench_function("strapdown", |b| {
        let (w, fb) = imu(3);
        b.iter_custom(|iters| {
            time_in_place(iters, &f0, 1000, |f| {
                black_box(mechanize(f, black_box(&w), black_box(&fb)));
            })
        })
    });
    g.bench_function("predict", |b| {
        b.iter_custom(|iters| {
            time_in_place(iters, &f0, 1000, |f| {
                f.predict(DT_SDINS, black_box(&u)).unwrap()
            })
        })
    });
    // From a filter whose last input (used by the sensors' h) is set.
    let mut f1 = f0.clone();
    cycle(&mut f1);
    g.bench_function("aiding_burst", |b| {
        b.iter_custom(|iters| time_in_place(iters, &f1, 20, aiding))
    });
    g.finish();
}

criterion_group!(benches, filter_step);
criterion_main!(benches);
