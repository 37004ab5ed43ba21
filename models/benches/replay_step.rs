//! The SDINS-25 log replay per IMU sample against one generated covariance
//! propagation of the same model, in the same run.
//!
//! The log is the first `REPLAY_SECONDS` of the simulated `lawnmower-dvl` run
//! of seed 1 (100 Hz IMU, 2 Hz DVL, depth and compass, USBL fixes), cut in
//! memory; the replay is [`models::sdins25::filter::run`] with the default
//! options (gates, lock-out release, stuck detector, 10 Hz recording of the
//! estimate is off: no record times), i.e. the scheduler, the strapdown, the
//! error-state filter and the aiding updates.
//!
//! Group `replay/sdins25`: `replay_per_sample` (one whole replay divided by its
//! samples, via `iter_custom`) and `propagate_covariance` (one call). Their
//! ratio is the cost of one replayed IMU sample in propagations.
//!
//! Group `replay/sdins25-rollback`: `without_rollback` (the baseline: the
//! lock-out recovery's rollback off, `rollback_s = 0`) and `with_rollback`
//! (the default, whose 10 s of history the navigator keeps); no recovery
//! happens in the log, so the ratio is the cost of keeping that history.
//!
//! `REPLAY_ONLY=1` runs one replay and exits (for callgrind:
//! `scripts/bench.sh --callgrind` counts the instructions inside `run_vehicle`
//! and divides by the samples printed on stderr);
//! `REPLAY_ONLY=without_rollback` runs the rollback group's baseline.
//!
//! Run: `cargo bench -p models --bench replay_step`.

mod common;

use std::hint::black_box;
use std::time::{Duration, Instant};

use common::*;
use criterion::{criterion_group, criterion_main, Criterion};
use models::harness::RunOptions;
use models::registry::find_scenario;
use models::sdins25::filter::{run, FilterOptions};
use models::sdins25::model::Sdins25;
use nav_ins::lockout::LockoutOptions;
use nav_runtime::log::LogDir;
use nav_runtime::model::Model;

/// Seconds of log replayed.
const REPLAY_SECONDS: f64 = 60.0;

/// The first `REPLAY_SECONDS` of the simulated `lawnmower-dvl` log of seed 1.
fn log() -> LogDir {
    let scenario = find_scenario("lawnmower-dvl").expect("scenario");
    let mut log = scenario
        .simulate_log(1, &RunOptions::default())
        .expect("simulates a log")
        .expect("valid log");
    let end = log.imu.first().map_or(0.0, |r| r.t) + REPLAY_SECONDS;
    log.imu.retain(|r| r.t <= end);
    if let Some(v) = log.dvl.as_mut() {
        v.retain(|r| r.t <= end);
    }
    if let Some(v) = log.depth.as_mut() {
        v.retain(|r| r.t <= end);
    }
    if let Some(v) = log.heading.as_mut() {
        v.retain(|r| r.t <= end);
    }
    if let Some(v) = log.usbl.as_mut() {
        v.retain(|r| r.t <= end);
    }
    if let Some(v) = log.truth.as_mut() {
        v.retain(|r| r.t <= end);
    }
    log
}

/// One replay; returns the IMU samples processed.
fn replay(log: &LogDir) -> usize {
    replay_with(log, &FilterOptions::default())
}

fn replay_with(log: &LogDir, options: &FilterOptions) -> usize {
    run(log, options, &[]).expect("replay succeeds").samples
}

/// The default options without the lock-out recovery's rollback: the
/// navigator keeps no history for it (docs/lockout.md, "Rollback").
fn without_rollback() -> FilterOptions {
    let defaults = FilterOptions::default();
    FilterOptions {
        lockout_release: defaults.lockout_release.map(|o| LockoutOptions {
            rollback_s: 0.0,
            ..o
        }),
        ..defaults
    }
}

fn bench(c: &mut Criterion) {
    let log = log();
    if let Some(which) = std::env::var_os("REPLAY_ONLY") {
        // `REPLAY_ONLY=without_rollback`: the baseline of the rollback group.
        let samples = match which.to_str() {
            Some("without_rollback") => replay_with(black_box(&log), &without_rollback()),
            _ => replay(black_box(&log)),
        };
        eprintln!("samples {samples}");
        return;
    }
    let samples = replay(&log) as u32;
    let (x, u, par, q) = sdins25_point();
    let p = sdins25_covariance();
    let mut g = c.benchmark_group("replay/sdins25");
    g.bench_function("replay_per_sample", |b| {
        b.iter_custom(|iters| {
            let mut total = Duration::ZERO;
            for _ in 0..iters {
                let start = Instant::now();
                black_box(replay(black_box(&log)));
                total += start.elapsed() / samples;
            }
            total
        })
    });
    g.bench_function("propagate_covariance", |b| {
        let mut pm = p;
        b.iter(|| {
            pm = p;
            Sdins25::propagate_covariance(
                black_box(&mut pm),
                black_box(&x),
                black_box(&u),
                black_box(&par),
                black_box(&q),
                DT_SDINS,
            );
            black_box(&pm);
        })
    });
    g.finish();
    // The history the rollback keeps (10 s) against none, on the same log:
    // no recovery happens in it, so both give the same run.
    let plain = without_rollback();
    assert_eq!(replay_with(&log, &plain), samples as usize);
    let mut g = c.benchmark_group("replay/sdins25-rollback");
    g.bench_function("without_rollback", |b| {
        b.iter(|| black_box(replay_with(black_box(&log), &plain)))
    });
    g.bench_function("with_rollback", |b| {
        b.iter(|| black_box(replay(black_box(&log))))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
