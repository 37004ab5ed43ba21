//! Covariance propagation `P <- Phi P Phi^T + Qd`: the generated sparse code
//! against dense nalgebra products in the same run (and, for SDINS-25, against a
//! hand-written structure-aware version).
//!
//! Variants per model (group `propagate/<model>`):
//! - `generated`: `Model::propagate_covariance`, which evaluates `F` and `Qd`
//!   itself from `(x, u, p, q, dt)`;
//! - `dense`: `Phi P Phi^T + Qd` with `Phi` and `Qd` precomputed outside the
//!   timing (the product alone; the baseline the ratios are taken against);
//! - `dense_with_model`: the same plus evaluating `jacobian` and `process_noise`
//!   each call (what a dense filter actually pays per step);
//! - `handwritten` (SDINS-25 only): blocks of `F dt` and `Qd` precomputed, only
//!   the 9 changed rows computed.
//!
//! Run: `cargo bench -p models --bench propagation` (ratios: `scripts/bench.sh`).

mod common;

use common::*;
use criterion::{criterion_group, criterion_main, Criterion};
use models::leveling::model::Leveling6;
use models::marker::model::Marker9;
use models::sdins25::model::Sdins25;
use nav_runtime::model::Model;
use nav_runtime::nalgebra::{SMatrix, SVector};
use std::hint::black_box;

/// Covariance steps between restores of the initial `P` (10 s at 100 Hz).
const RESET_EVERY: u64 = 1000;

fn bench_model<Mo: Model<N>, const N: usize>(
    c: &mut Criterion,
    name: &str,
    point: (SVector<f64, N>, Mo::Input, Mo::Params, Mo::Noise),
    p0: SMatrix<f64, N, N>,
    dt: f64,
    extra: impl FnOnce(&mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>),
) {
    let (x, u, par, q) = point;
    let phi = dense_phi::<Mo, N>(&x, &u, &par, dt);
    let qd = Mo::process_noise(&x, &u, &par, &q, dt);

    // The variants agree before anything is timed.
    let mut generated = p0;
    generated_propagate::<Mo, N>(&mut generated, &x, &u, &par, &q, dt);
    let mut dense = p0;
    dense_propagate(&mut dense, &phi, &qd);
    let mut dense_model = p0;
    dense_propagate_with_model::<Mo, N>(&mut dense_model, &x, &u, &par, &q, dt);
    assert!(rel_diff(&generated, &dense) < 1e-12, "{name}: generated != dense");
    assert!(rel_diff(&dense_model, &dense) < 1e-12, "{name}: dense variants differ");

    let mut g = c.benchmark_group(format!("propagate/{name}"));
    g.bench_function("generated", |b| {
        b.iter_custom(|iters| {
            time_in_place(iters, &p0, RESET_EVERY, |p| {
                generated_propagate::<Mo, N>(p, black_box(&x), black_box(&u), black_box(&par), black_box(&q), dt)
            })
        })
    });
    g.bench_function("dense", |b| {
        b.iter_custom(|iters| time_in_place(iters, &p0, RESET_EVERY, |p| dense_propagate(p, black_box(&phi), black_box(&qd))))
    });
    g.bench_function("dense_with_model", |b| {
        b.iter_custom(|iters| {
            time_in_place(iters, &p0, RESET_EVERY, |p| {
                dense_propagate_with_model::<Mo, N>(p, black_box(&x), black_box(&u), black_box(&par), black_box(&q), dt)
            })
        })
    });
    extra(&mut g);
    g.finish();
}

fn propagation(c: &mut Criterion) {
    let (x, u, par, q) = sdins25_point();
    let p0 = sdins25_covariance();
    let f = Sdins25::jacobian(&x, &u, &par, DT_SDINS);
    let qd = Sdins25::process_noise(&x, &u, &par, &q, DT_SDINS);
    let hand = HandWrittenSdins25::new(&f, &qd, DT_SDINS);
    let mut by_hand = p0;
    hand.propagate(&mut by_hand);
    let mut generated = p0;
    Sdins25::propagate_covariance(&mut generated, &x, &u, &par, &q, DT_SDINS);
    assert!(rel_diff(&by_hand, &generated) < 1e-12, "hand-written != generated");

    bench_model::<Sdins25, 25>(c, "sdins25", (x, u, par, q), p0, DT_SDINS, |g| {
        g.bench_function("handwritten", |b| {
            b.iter_custom(|iters| time_in_place(iters, &p0, RESET_EVERY, |p| black_box(&hand).propagate(p)))
        });
    });
    bench_model::<Leveling6, 6>(c, "leveling6", leveling6_point(), leveling6_covariance(), 0.01, |_| {});
    bench_model::<Marker9, 9>(c, "marker9", marker9_point(), marker9_covariance(), 0.02, |_| {});
}

criterion_group!(benches, propagation);
criterion_main!(benches);
