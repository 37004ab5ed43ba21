//! Cost of the fixed-interval smoother against the forward filter, on one
//! simulated 500-s `lawnmower-usbl-10s` survey (IMU 100 Hz, DVL, depth,
//! compass at 2 Hz, USBL every 10 s with acoustic delay), estimates at the
//! 10 Hz truth times as a replay writes them:
//!
//! - `forward`: the filter alone (`sdins25::filter::run`);
//! - `forward_and_smoothed`: the same with `FilterOptions::smooth`, i.e. the
//!   forward pass recording its epochs into the temporary file, the backward
//!   pass, and the smoothed estimates.
//!
//! The smoother's cost is `forward_and_smoothed / forward - 1` (goal: the
//! whole at most 2 x the forward pass). Run:
//! `cargo bench -p models --bench smoother`.
//!
//! `SMOOTHER_ONLY=forward` (or `=smoothed`) runs that case once and exits,
//! for exact instruction counts:
//! `valgrind --tool=callgrind --toggle-collect='*run_vehicle*' BENCH_BINARY`.

use criterion::{criterion_group, criterion_main, Criterion};
use models::sdins25::filter::{run, FilterOptions};
use models::sdins25::simulation::{simulate, SimConfig};
use std::hint::black_box;
use std::time::Duration;

fn smoother(c: &mut Criterion) {
    let log = simulate(&SimConfig::usbl_10s(), 7).log;
    let times: Vec<f64> = log
        .truth
        .as_ref()
        .map(|t| t.iter().map(|r| r.t).collect())
        .unwrap_or_default();
    let smooth = FilterOptions {
        smooth: true,
        ..FilterOptions::default()
    };
    if let Some(case) = std::env::var_os("SMOOTHER_ONLY") {
        let options = if case == "smoothed" {
            &smooth
        } else {
            &FilterOptions::default()
        };
        let run = run(black_box(&log), options, &times).unwrap();
        eprintln!(
            "{} estimates, {} smoothed",
            run.estimates.iter().flatten().count(),
            run.smoothed.iter().flatten().flatten().count()
        );
        return;
    }
    let mut g = c.benchmark_group("smoother/lawnmower-usbl-10s");
    g.sample_size(10).measurement_time(Duration::from_secs(8));
    g.bench_function("forward", |b| {
        b.iter(|| run(black_box(&log), &FilterOptions::default(), &times).unwrap())
    });
    g.bench_function("forward_and_smoothed", |b| {
        b.iter(|| run(black_box(&log), &smooth, &times).unwrap())
    });
    g.finish();
}

criterion_group!(benches, smoother);
criterion_main!(benches);
