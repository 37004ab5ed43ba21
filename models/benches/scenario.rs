//! Whole scenario runs: one 500-s SDINS-25 lawn-mower run (`lawnmower-dvl`:
//! IMU at 100 Hz, DVL, depth and compass) and a Monte Carlo of 100 runs through
//! the `navsim` driver (`montecarlo::run_seeds`) on rayon pools of 1 and 2
//! threads.
//!
//! Group `scenario/lawnmower-dvl`:
//! - `run_one`: simulate + filter + score (`Scenario::run_one`, what the Monte
//!   Carlo repeats); real-time factor = 500 s / its time;
//! - `filter_only`: the filter over an already simulated log
//!   (`sdins25::filter::run`), the estimator's own real-time factor;
//! - `reference`: the truth trajectory, its error-free IMU samples and truth
//!   rows (`simulation::Reference::new`), shared by all runs of a process:
//!   the first run pays it on top of `run_one`.
//!
//! Group `montecarlo/lawnmower-dvl`: `threads_1/<runs>`, `threads_2/<runs>`;
//! the speed-up is their ratio. `BENCH_MC_RUNS` overrides the 100 runs (e.g. for a quick
//! look). These are long: 10 samples each.
//!
//! Run: `cargo bench -p models --bench scenario` (ratios: `scripts/bench.sh`).

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use models::harness::{run_seeds, ProgressBar, RunOptions, Scenario};
use models::sdins25::filter::{run, FilterOptions};
use models::sdins25::simulation::{simulate, Reference, DURATION};
use std::hint::black_box;
use std::time::Duration;

const SCENARIO: &str = "lawnmower-dvl";

fn scenario(c: &mut Criterion) {
    let lawn = models::sdins25::scenario(SCENARIO).expect("the lawnmower-dvl scenario");
    let options = RunOptions::default();
    assert!(
        (DURATION - 500.0).abs() < 1e-9,
        "the scenario is no longer 500 s long"
    );

    let mut g = c.benchmark_group(format!("scenario/{SCENARIO}"));
    g.sample_size(10).measurement_time(Duration::from_secs(10));
    g.bench_function("run_one", |b| {
        b.iter(|| lawn.run_one(black_box(7), &options).unwrap())
    });
    let log = simulate(&lawn.config, 7).log;
    g.bench_function("filter_only", |b| {
        b.iter(|| run(black_box(&log), &FilterOptions::default(), &[]).unwrap())
    });
    g.bench_function("reference", |b| {
        b.iter(|| Reference::new(black_box(&lawn.config)))
    });
    g.finish();

    let runs: usize = std::env::var("BENCH_MC_RUNS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(100);
    let seeds: Vec<u64> = (1..=runs as u64).collect();
    let mut g = c.benchmark_group(format!("montecarlo/{SCENARIO}"));
    g.sample_size(10)
        .warm_up_time(Duration::from_millis(1))
        .measurement_time(Duration::from_secs(1));
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        g.bench_function(BenchmarkId::new(format!("threads_{threads}"), runs), |b| {
            b.iter(|| {
                pool.install(|| {
                    run_seeds(&lawn, black_box(&seeds), &options, &ProgressBar::hidden()).unwrap()
                })
            })
        });
    }
    g.finish();
}

criterion_group!(benches, scenario);
criterion_main!(benches);
