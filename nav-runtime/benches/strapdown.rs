//! The strapdown mechanization, the nominal-solution half of an error-state
//! filter step (the other half, the covariance, is benchmarked with the models
//! in `models/benches`).
//!
//! Group `strapdown`: `update_rates` (cubic rate model, closed-form coning and
//! sculling, WGS-84 position/velocity/attitude update), `update_increments`
//! (integrating-IMU path), `mechanization_rates` (the continuous right-hand
//! side alone). The 100-Hz step budget these take part in is reported by
//! `scripts/bench.sh`.
//!
//! Run: `cargo bench -p nav-runtime --bench strapdown`.

use criterion::{criterion_group, criterion_main, Criterion};
use nav_runtime::attitude::Euler;
use nav_runtime::earth::Geodetic;
use nav_runtime::nalgebra::Vector3;
use nav_runtime::strapdown::{mechanization_rates, NavState, Strapdown};
use std::hint::black_box;

const DT: f64 = 0.01;

fn state() -> NavState {
    NavState::new(
        Geodetic::from_degrees(37.0, 127.0, -50.0),
        Vector3::new(1.15, 0.96, 0.05),
        &Euler::from_degrees(2.0, -3.0, 40.0),
    )
}

fn strapdown(c: &mut Criterion) {
    let w = Vector3::new(1e-3, -5e-4, 2e-3);
    let f = Vector3::new(0.02, -0.01, -9.80);
    let mut g = c.benchmark_group("strapdown");
    g.bench_function("update_rates", |b| {
        let mut ins = Strapdown::new(state());
        for _ in 0..4 {
            ins.update_rates(&w, &f, DT);
        }
        b.iter(|| black_box(&mut ins).update_rates(black_box(&w), black_box(&f), DT))
    });
    g.bench_function("update_increments", |b| {
        let mut ins = Strapdown::new(state());
        let (dtheta, dv) = (w * DT, f * DT);
        ins.update_increments(&dtheta, &dv, DT);
        b.iter(|| black_box(&mut ins).update_increments(black_box(&dtheta), black_box(&dv), DT))
    });
    g.bench_function("mechanization_rates", |b| {
        let s = state();
        b.iter(|| mechanization_rates(black_box(&s), black_box(&w), black_box(&f)))
    });
    g.finish();
}

criterion_group!(benches, strapdown);
criterion_main!(benches);
