//! `navsim replay` of a log on disk, two ways, in the same run: the replay
//! pipeline as the binary runs it (the log streamed file by file, the
//! preflight beside the replay, taking the IMU rows the replay reads:
//! [`check_alongside`]) against the
//! way the built-in SDINS-25 replay ran before the pipeline streamed (the
//! whole log read into memory, the preflight run over it, then the replay).
//!
//! The log is the simulated `lawnmower-dvl` run of seed 3 (500 s, 100 Hz IMU,
//! 2 Hz DVL, depth, compass and altimeter, 10 Hz truth) written to a
//! temporary directory; the model is `sdins25` with the default options.
//!
//! Group `replay/pipeline`: `loaded_then_checked` (the baseline) and
//! `streamed_alongside`. Their ratio is the pipeline's cost in time.
//!
//! Groups `replay/leveling6-moving` and `replay/leveling6-stationary`: the
//! same two ways for `leveling6` on the simulated `leveling-moving` and
//! `leveling-stationary` logs of seed 3 (30 s, 100 Hz IMU, 10 Hz speed log
//! and truth). The streamed replay reads the speed log (and at rest the
//! IMU file) once before the run to tell rest from motion.
//!
//! Run: `cargo bench -p models --bench replay_pipeline`.

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use models::harness::{ReplayModel, ReplayOptions, RunOptions};
use models::registry::{find_replay_model, find_scenario};
use nav_replay::preflight::{self, check_alongside, PreflightOptions};
use nav_runtime::log::{LogDir, LogFiles, Strictness};

/// The baseline: read whole, check, replay.
fn loaded_then_checked(model: &dyn ReplayModel, dir: &std::path::Path) -> usize {
    let log = LogDir::read(dir, Strictness::Strict).expect("reads the log");
    let report = preflight::check(&log, &PreflightOptions::default());
    assert!(preflight::refusal(&report).is_none(), "the log passes");
    model
        .replay(&log, &ReplayOptions::default())
        .expect("replays")
        .samples
}

/// The pipeline: streamed, the preflight beside the replay.
fn streamed_alongside(model: &dyn ReplayModel, dir: &std::path::Path) -> usize {
    let files = LogFiles::open(dir, Strictness::Strict).expect("opens the log");
    let options = PreflightOptions::default();
    let (output, _, _) = check_alongside(&files, &options, model.shares_imu(), || {
        model.replay_files(&files, &ReplayOptions::default(), None)
    })
    .expect("replays");
    output.samples
}

/// Group `group`: the log of run 3 of `scenario`, written to a temporary
/// directory, replayed by `model` both ways.
fn compare(c: &mut Criterion, group: &str, scenario: &str, model: &str) {
    let dir = std::env::temp_dir().join(format!(
        "replay-pipeline-bench-{scenario}-{}",
        std::process::id()
    ));
    find_scenario(scenario)
        .expect("scenario")
        .simulate_log(3, &RunOptions::default())
        .expect("simulates")
        .expect("valid log")
        .write(&dir)
        .expect("writes the log");
    let model = find_replay_model(model).expect("model");
    let model = model.as_ref();
    // Both give the same run.
    assert_eq!(
        loaded_then_checked(model, &dir),
        streamed_alongside(model, &dir)
    );
    let mut g = c.benchmark_group(group);
    g.sample_size(20);
    g.bench_function("loaded_then_checked", |b| {
        b.iter(|| black_box(loaded_then_checked(model, black_box(&dir))))
    });
    g.bench_function("streamed_alongside", |b| {
        b.iter(|| black_box(streamed_alongside(model, black_box(&dir))))
    });
    g.finish();
    let _ = std::fs::remove_dir_all(&dir);
}

fn bench(c: &mut Criterion) {
    compare(c, "replay/pipeline", "lawnmower-dvl", "sdins25");
    for motion in ["moving", "stationary"] {
        let scenario = format!("leveling-{motion}");
        compare(
            c,
            &format!("replay/leveling6-{motion}"),
            &scenario,
            "leveling6",
        );
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
