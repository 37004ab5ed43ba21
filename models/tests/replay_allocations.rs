//! The replay loop allocates nothing per IMU step: a global allocator (per
//! binary, hence this file of its own) counts the allocations of whole
//! replays of `lawnmower-dvl` (seed 1) of different lengths.
//!
//! With the aiding rows kept to the first second, 30 s and 120 s of IMU make
//! exactly the same number of allocations: every one of them belongs to the
//! setup and to those few rows. With aiding throughout, the count grows with
//! the aiding rows only (about 2.7 per row: the boxed measurement handed to
//! the scheduler, the reports of the step that applies it, the read-ahead of
//! the rows; see docs/performance-replay.md).

use models::harness::RunOptions;
use models::registry::find_scenario;
use models::sdins25::filter::{run, FilterOptions};
use nav_runtime::log::LogDir;

#[path = "../../nav-runtime/tests/support/counting_allocator.rs"]
mod counting_allocator;

/// The first `seconds` of the simulated log, its aiding rows kept up to
/// `aiding_until` seconds from the start.
fn log(seconds: f64, aiding_until: f64) -> LogDir {
    let scenario = find_scenario("lawnmower-dvl").expect("scenario");
    let mut log = scenario
        .simulate_log(1, &RunOptions::default())
        .expect("simulates a log")
        .expect("valid log");
    let t0 = log.imu.first().map_or(0.0, |r| r.t);
    let (end, aiding_end) = (t0 + seconds, t0 + seconds.min(aiding_until));
    log.imu.retain(|r| r.t <= end);
    macro_rules! keep {
        ($($field:ident),*) => {$(
            if let Some(v) = log.$field.as_mut() {
                v.retain(|r| r.t <= aiding_end);
            }
        )*};
    }
    keep!(dvl, depth, heading, usbl, truth);
    log
}

/// Allocations of one replay of `log`, and its IMU samples.
fn allocations(log: &LogDir) -> (usize, usize) {
    let (count, out) = counting_allocator::allocations(|| run(log, &FilterOptions::default(), &[]));
    (count, out.expect("the replay succeeds").samples)
}

#[test]
fn imu_steps_allocate_nothing() {
    let (short, short_samples) = allocations(&log(30.0, 1.0));
    let (long, long_samples) = allocations(&log(120.0, 1.0));
    assert_eq!(long_samples - short_samples, 9_000);
    assert_eq!(
        long,
        short,
        "9,000 more IMU steps made {} more allocations",
        long as i64 - short as i64
    );
    // With aiding throughout, the count does grow (the test can tell).
    let (aided, _) = allocations(&log(120.0, f64::INFINITY));
    assert!(
        aided > long,
        "{aided} allocations with aiding, {long} without"
    );
}
