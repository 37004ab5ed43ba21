//! SDINS-25 measurement updates: `Ekf::update` (generated sparse `P H^T`,
//! `H P H^T`, Cholesky of `S`, Joseph form on the upper triangle, checks and
//! repairs included) against a dense nalgebra Joseph update
//! `(I - K H) P (I - K H)^T + K R K^T` with dense `H` from `Sensor::jacobian`,
//! in the same run. Also the innovation terms alone (generated vs dense
//! `P H^T`, `H P H^T`).
//!
//! Groups `update/<sensor>` with `generated` (Ekf::update) and `dense`; groups
//! `innovation_terms/<sensor>` with `generated` and `dense`.
//!
//! Run: `cargo bench -p models --bench update` (ratios: `scripts/bench.sh`).
//! `UPDATE_ONLY=<sensor>/<generated|dense>` skips criterion and calls that
//! variant `UPDATE_CALLS` times (default 1000), for instruction counts under
//! callgrind (`scripts/bench.sh --callgrind`).

mod common;

use common::*;
use criterion::{criterion_group, Criterion};
use models::sdins25::model::{
    Sdins25, Sdins25Compass, Sdins25CompassSmallAngle, Sdins25Depth, Sdins25Dvl, Sdins25Input,
    Sdins25Params, Sdins25Usbl, Sdins25UsblAux,
};
use nav_runtime::ekf::Ekf;
use nav_runtime::model::Sensor;
use nav_runtime::nalgebra::{SMatrix, SVector, Vector3};
use std::hint::black_box;

/// Updates between restores of the prior (the covariance shrinks with each
/// repeated update; 100 keeps it far from singular).
const RESET_EVERY: u64 = 100;

type Filter = Ekf<Sdins25, 25>;

/// A filter at the SDINS-25 operating point, its last input set by one
/// prediction, gating off (every update is applied, as in the dense code).
fn filter() -> (Filter, Sdins25Input, Sdins25Params) {
    let (x, u, par, q) = sdins25_point();
    let mut f = Filter::new(x, sdins25_covariance(), par, q)
        .unwrap()
        .with_default_gate(None);
    f.predict(DT_SDINS, &u).unwrap();
    (f, u, par)
}

/// `Ekf::update` behind a call boundary, so callgrind can collect inside it.
#[inline(never)]
fn generated_update<S, const M: usize>(
    f: &mut Filter,
    z: &SVector<f64, M>,
    r: &SMatrix<f64, M, M>,
    aux: &S::Aux,
) where
    S: Sensor<25, M, Model = Sdins25>,
{
    black_box(f.update::<S, M>(z, r, aux).unwrap());
}

fn bench_sensor<S, const M: usize>(
    c: &mut Criterion,
    name: &str,
    z: SVector<f64, M>,
    r: SMatrix<f64, M, M>,
    aux: S::Aux,
) where
    S: Sensor<25, M, Model = Sdins25>,
{
    let (f0, u, par) = filter();
    let prior = (*f0.state(), *f0.covariance());
    if let Ok(only) = std::env::var("UPDATE_ONLY") {
        let calls: u64 = std::env::var("UPDATE_CALLS")
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or(1000);
        match only.split_once('/') {
            Some((sensor, "generated")) if sensor == name => {
                let mut f = f0.clone();
                for i in 0..calls {
                    if i % RESET_EVERY == 0 {
                        f.clone_from(&f0);
                    }
                    generated_update::<S, M>(&mut f, &z, &r, &aux);
                }
            }
            Some((sensor, "dense")) if sensor == name => {
                let (mut x, mut p) = prior;
                for i in 0..calls {
                    if i % RESET_EVERY == 0 {
                        (x, p) = prior;
                    }
                    dense_joseph_update::<S, 25, M>(&mut x, &mut p, &z, &r, &u, &par, &aux);
                }
            }
            _ => {}
        }
        return;
    }

    // Both updates give the same posterior before anything is timed.
    let mut f = f0.clone();
    f.update::<S, M>(&z, &r, &aux).unwrap();
    let (mut x, mut p) = prior;
    dense_joseph_update::<S, 25, M>(&mut x, &mut p, &z, &r, &u, &par, &aux);
    assert!(
        rel_diff(f.covariance(), &p) < 1e-9,
        "{name}: covariances differ"
    );
    assert!(
        (f.state() - x).amax() <= 1e-9 * x.amax().max(1e-300),
        "{name}: states differ"
    );

    let mut g = c.benchmark_group(format!("update/{name}"));
    g.bench_function("generated", |b| {
        b.iter_custom(|iters| {
            time_in_place(iters, &f0, RESET_EVERY, |f| {
                generated_update::<S, M>(f, black_box(&z), black_box(&r), black_box(&aux))
            })
        })
    });
    g.bench_function("dense", |b| {
        b.iter_custom(|iters| {
            time_in_place(iters, &prior, RESET_EVERY, |(x, p)| {
                dense_joseph_update::<S, 25, M>(
                    x,
                    p,
                    black_box(&z),
                    black_box(&r),
                    black_box(&u),
                    black_box(&par),
                    black_box(&aux),
                )
            })
        })
    });
    g.finish();

    let (x, p) = prior;
    let mut g = c.benchmark_group(format!("innovation_terms/{name}"));
    g.bench_function("generated", |b| {
        b.iter(|| {
            S::innovation_terms(
                black_box(&p),
                black_box(&x),
                black_box(&u),
                black_box(&par),
                black_box(&aux),
            )
        })
    });
    g.bench_function("dense", |b| {
        b.iter(|| {
            let (p, x) = (black_box(&p), black_box(&x));
            let h = S::predict(x, &u, &par, &aux);
            let hm = S::jacobian(x, &u, &par, &aux);
            let pht = p * hm.transpose();
            (h, pht, hm * pht)
        })
    });
    g.finish();
}

fn updates(c: &mut Criterion) {
    bench_sensor::<Sdins25Dvl, 3>(
        c,
        "dvl",
        Vector3::new(0.02, -0.01, 0.005),
        SMatrix::<f64, 3, 3>::from_diagonal_element(0.01f64.powi(2)),
        (),
    );
    bench_sensor::<Sdins25Compass, 1>(
        c,
        "compass",
        SVector::<f64, 1>::new(0.003),
        SMatrix::<f64, 1, 1>::new(0.5f64.to_radians().powi(2)),
        (),
    );
    bench_sensor::<Sdins25CompassSmallAngle, 1>(
        c,
        "compass_small_angle",
        SVector::<f64, 1>::new(0.003),
        SMatrix::<f64, 1, 1>::new(0.5f64.to_radians().powi(2)),
        (),
    );
    bench_sensor::<Sdins25Usbl, 2>(
        c,
        "usbl",
        SVector::<f64, 2>::new(1.5, -0.8),
        SMatrix::<f64, 2, 2>::from_diagonal_element(1.0),
        Sdins25UsblAux {
            relative_position: Vector3::new(120.0, -80.0, 45.0),
        },
    );
    bench_sensor::<Sdins25Depth, 1>(
        c,
        "depth",
        SVector::<f64, 1>::new(0.05),
        SMatrix::<f64, 1, 1>::new(0.1f64.powi(2)),
        (),
    );
}

criterion_group!(benches, updates);

fn main() {
    if std::env::var("UPDATE_ONLY").is_ok() {
        updates(&mut Criterion::default());
        return;
    }
    benches();
    Criterion::default().configure_from_args().final_summary();
}
