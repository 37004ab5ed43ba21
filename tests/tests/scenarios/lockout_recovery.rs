//! Recovery from a lock-out into divergence (docs/lockout.md, "Recovery"):
//! a burst of wrong IMU samples written into the IMU file of a simulated DVL
//! survey (`lawnmower-dvl`) throws the filter off; the DVL, depth and
//! compass readings that follow are correct and agree with one another, but
//! the filter's error seen through them grows beyond the release's bounds.
//! Without the recovery every later DVL reading is refused and the estimate
//! diverges (tens of km, or out of its physical bounds); with it the filter
//! recovers after the DVL's horizon, says when, and the final error stays
//! bounded.

use models::sdins25::filter::FilterOptions;
use models::sdins25::simulation::simulate;
use models::sdins25::{run_and_score, scenario};
use nav_ins::lockout::LockoutOptions;
use nav_runtime::log::LogDir;
use nav_runtime::stats;

/// Start of every transient (s): mid-survey, on a straight leg.
const START_S: f64 = 150.0;

/// One IMU transient: from [`START_S`] for `duration_s` every IMU row gets
/// `gyro_x` (rad/s, a roll rate) and `accel_x` (m/s^2, forward) added; with
/// the recovery the final horizontal error must stay within `bound_m`.
struct Transient {
    what: &'static str,
    duration_s: f64,
    gyro_x: f64,
    accel_x: f64,
    bound_m: f64,
}

const TRANSIENTS: &[Transient] = &[
    Transient {
        what: "0.5 s of roll 0.2 rad/s and 3 m/s^2 (5.7 deg, 1.5 m/s)",
        duration_s: 0.5,
        gyro_x: 0.2,
        accel_x: 3.0,
        bound_m: 150.0,
    },
    Transient {
        what: "1.8 s of 3 m/s^2 (5.4 m/s)",
        duration_s: 1.8,
        gyro_x: 0.0,
        accel_x: 3.0,
        bound_m: 20.0,
    },
    Transient {
        what: "1.8 s of roll 0.05 rad/s (5.2 deg)",
        duration_s: 1.8,
        gyro_x: 0.05,
        accel_x: 0.0,
        bound_m: 150.0,
    },
    Transient {
        what: "1.8 s of roll 0.2 rad/s and 3 m/s^2 (21 deg, 5.4 m/s)",
        duration_s: 1.8,
        gyro_x: 0.2,
        accel_x: 3.0,
        bound_m: 200.0,
    },
    Transient {
        what: "5 s of roll 0.02 rad/s and 1 m/s^2 (5.7 deg, 5 m/s)",
        duration_s: 5.0,
        gyro_x: 0.02,
        accel_x: 1.0,
        bound_m: 100.0,
    },
];

fn with_transient(log: &LogDir, t: &Transient) -> LogDir {
    let mut log = log.clone();
    let end = START_S + t.duration_s;
    for r in log.imu.iter_mut().filter(|r| r.t >= START_S && r.t < end) {
        r.gx += t.gyro_x;
        r.ax += t.accel_x;
    }
    log
}

/// Final horizontal error without the recovery above which (or an estimate
/// out of its physical bounds) the filter counts as diverged (m): every
/// transient of the table gives 780 m to 42 km, or leaves the bounds.
const DIVERGED_M: f64 = 500.0;

/// Each transient of the table on seeds 1-3: with the recovery the final
/// horizontal error stays within the row's bound (the bounds were set with
/// the 5-s horizon and no eq. R3; seeds 1-3 now give 8.1-41.5 m, against
/// 0.8-4.9 m without any transient), at least one DVL recovery is reported,
/// the first after the transient started and after the DVL's horizon of
/// refusals, each also as a `lockout_recovery` warning naming `dvl.csv` and
/// its time; without it the same log diverges.
#[test]
fn imu_transients_recover_instead_of_diverging() {
    let cfg = scenario("lawnmower-dvl").unwrap().config;
    let with = FilterOptions::default();
    let without = FilterOptions {
        lockout_release: Some(LockoutOptions {
            recovery: None,
            ..LockoutOptions::default()
        }),
        ..FilterOptions::default()
    };
    let dvl_horizon = nav_ins::lockout::RecoveryRules::default().dvl.horizon_s;
    for seed in [1u64, 2, 3] {
        let sim = simulate(&cfg, seed);
        let bias = Some(sim.errors.compass_bias);
        for t in TRANSIENTS {
            let log = with_transient(&sim.log, t);
            let (run, scored) = run_and_score(&log, &with, bias)
                .unwrap_or_else(|e| panic!("{} seed {seed}: {e}", t.what));
            let final_m = scored.unwrap().horizontal_error_final_m;
            assert!(
                final_m < t.bound_m,
                "{} seed {seed}: final error {final_m} m with the recovery",
                t.what
            );
            let first = run
                .recoveries
                .first()
                .unwrap_or_else(|| panic!("{} seed {seed}: no recovery", t.what));
            assert_eq!(first.sensor, "dvl", "{} seed {seed}", t.what);
            assert!(
                first.t_s > START_S && first.refused_for_s >= dvl_horizon,
                "{} seed {seed}: {first:?}",
                t.what
            );
            assert_eq!(
                run.final_filter.ekf().counters().recoveries,
                run.recoveries.len() as u64,
                "{} seed {seed}",
                t.what
            );
            let warned = run
                .warnings
                .iter()
                .filter(|w| w.kind == nav_runtime::log::WarningKind::LockoutRecovery)
                .collect::<Vec<_>>();
            assert_eq!(warned.len(), run.recoveries.len(), "{} seed {seed}", t.what);
            assert_eq!(warned[0].file.as_deref(), Some("dvl.csv"));
            assert!(
                warned[0]
                    .message
                    .contains(&format!("t = {:.3} s", first.t_s)),
                "{}",
                warned[0].message
            );
            match run_and_score(&log, &without, bias) {
                Ok((run, scored)) => {
                    let final_m = scored.unwrap().horizontal_error_final_m;
                    assert!(
                        final_m > DIVERGED_M && run.recoveries.is_empty(),
                        "{} seed {seed}: without the recovery {final_m} m",
                        t.what
                    );
                }
                // Out of the physical bounds: diverged too.
                Err(e) => assert!(
                    e.to_string().contains("out of physical bounds"),
                    "{} seed {seed}: {e}",
                    t.what
                ),
            }
        }
    }
}

/// Seeds of the Monte Carlo below (not used while building the recovery).
const MONTE_CARLO_SEEDS: std::ops::Range<u64> = 4200..4300;

/// The final horizontal error after each transient of the table over
/// [`MONTE_CARLO_SEEDS`]: median, 95th percentile and maximum (m), and the
/// runs that ended out of the physical bounds (docs/lockout.md, "Recovery").
/// `cargo test --release -p tests --test scenarios lockout_recovery:: -- --ignored
/// --nocapture`.
#[test]
#[ignore = "Monte Carlo over 100 seeds; prints the figures of docs/lockout.md"]
fn transient_monte_carlo() {
    let cfg = scenario("lawnmower-dvl").unwrap().config;
    let options = FilterOptions::default();
    let mut finals: Vec<Vec<f64>> = vec![Vec::new(); TRANSIENTS.len()];
    let mut out_of_bounds = vec![0usize; TRANSIENTS.len()];
    for seed in MONTE_CARLO_SEEDS {
        let sim = simulate(&cfg, seed);
        let bias = Some(sim.errors.compass_bias);
        for (k, t) in TRANSIENTS.iter().enumerate() {
            match run_and_score(&with_transient(&sim.log, t), &options, bias) {
                Ok((_, scored)) => finals[k].push(scored.unwrap().horizontal_error_final_m),
                Err(_) => out_of_bounds[k] += 1,
            }
        }
    }
    for (k, t) in TRANSIENTS.iter().enumerate() {
        let f = &finals[k];
        let median = stats::median(f);
        println!(
            "{}: final error median {median:.1} m, p95 {:.1} m, max {:.1} m; out of bounds {}",
            t.what,
            stats::p95(f),
            stats::max(f),
            out_of_bounds[k]
        );
    }
    // What docs/lockout.md and the README claim: every run recovers within
    // its bounds, with a median final error under 20 m.
    for (k, t) in TRANSIENTS.iter().enumerate() {
        let median = stats::median(&finals[k]);
        assert_eq!(out_of_bounds[k], 0, "{}", t.what);
        assert!(median < 20.0, "{}: median {median} m", t.what);
    }
}
