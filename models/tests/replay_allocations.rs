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

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

use models::cli::find_scenario;
use models::harness::RunOptions;
use models::sdins25::filter::{run, FilterOptions};
use nav_runtime::log::LogDir;

struct Counting;

static COUNTING: AtomicBool = AtomicBool::new(false);
static COUNT: AtomicUsize = AtomicUsize::new(0);

fn note() {
    if COUNTING.load(Ordering::Relaxed) {
        COUNT.fetch_add(1, Ordering::Relaxed);
    }
}

// SAFETY: forwards every call unchanged to the system allocator.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        note();
        unsafe { System.alloc(layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        note();
        unsafe { System.alloc_zeroed(layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        note();
        unsafe { System.realloc(ptr, layout, new_size) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

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
    COUNT.store(0, Ordering::Relaxed);
    COUNTING.store(true, Ordering::Relaxed);
    let out = run(log, &FilterOptions::default(), &[]);
    COUNTING.store(false, Ordering::Relaxed);
    let samples = out.expect("the replay succeeds").samples;
    (COUNT.load(Ordering::Relaxed), samples)
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
