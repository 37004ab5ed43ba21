//! SDINS-25 end to end: simulate -> log -> replay, late USBL fixes, divergence
//! without aiding, DVL aiding, consistency, sensor subsets and IMU rates.
//!
//! Thresholds come from the physics of the scenario, not from the seeds:
//! - IMU only: a 1 mg accelerometer bias (Table 1, 1-sigma) alone gives
//!   `0.5 b t^2 = 1.2 km` after 500 s (the Schuler period, 84 min, is far
//!   longer), so the median over seeds is hundreds of metres;
//! - DVL-aided: the DVL bias (0.01 m/s) integrates to at most 5 m along the
//!   track and mostly cancels on the lawn-mower legs; the compass bias is
//!   separated because the initial heading is known, so a few metres.

use models::harness::{ReplayModel, ReplayOptions, RunOptions, Scenario};
use models::sdins25::filter::{self, FilterOptions, UsblDelivery};
use models::sdins25::simulation::{self, SimConfig};
use models::sdins25::{run_and_score, scenario, Sdins25Replay};
use nav_runtime::gate::chi_square_quantile;
use nav_runtime::log::{LogDir, Strictness};
use nav_runtime::stats;

fn temp_dir(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("sdins25-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

fn final_error(config: &SimConfig, seed: u64) -> f64 {
    let sim = simulation::simulate(config, seed);
    let (_, s) = run_and_score(&sim.log, &FilterOptions::default(), None).unwrap();
    s.unwrap().horizontal_error_final_m
}

/// `navsim simulate` + `navsim replay` reproduces `navsim scenario`: the log is
/// written to disk, read back and replayed; every metric agrees to 1e-9.
#[test]
fn simulate_write_read_replay_equals_scenario() {
    let sc = scenario("lawnmower-usbl").unwrap();
    let seed = 7;
    let opts = RunOptions::default();
    let direct = sc.run_one(seed, &opts).unwrap();
    let log = sc.simulate_log(seed, &opts).unwrap().unwrap();
    let dir = temp_dir("roundtrip");
    log.write(&dir).unwrap();
    let read = LogDir::read(&dir, Strictness::Strict).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    let out = Sdins25Replay::new()
        .replay(&read, &ReplayOptions::default())
        .unwrap();
    for key in [
        "horizontal_error_final_m",
        "horizontal_error_rms_m",
        "depth_error_rms_m",
        "nees_mean",
    ] {
        let a = direct.metric(key);
        let b = out.metrics[key].as_f64().unwrap();
        assert!(
            a.is_finite() && (a - b).abs() <= 1e-9 * (1.0 + a.abs()),
            "{key}: scenario {a}, replay {b}"
        );
    }
    assert_eq!(out.samples as f64, direct.metric("samples"));
}

/// Posidonia fixes at 6000 m arrive about 4 s late; applied at their
/// measurement time through the scheduler's history, the run equals one where
/// every fix is delivered on time.
#[test]
fn late_usbl_fixes_equal_on_time_delivery() {
    let sim = simulation::simulate(&SimConfig::usbl_deep(), 3);
    let late = FilterOptions::default();
    let on_time = FilterOptions {
        usbl_delivery: UsblDelivery::OnTime,
        ..late
    };
    let (ra, sa) = run_and_score(&sim.log, &late, None).unwrap();
    let (rb, sb) = run_and_score(&sim.log, &on_time, None).unwrap();
    assert!(ra.replays >= 60, "late fixes replayed: {}", ra.replays);
    assert_eq!(rb.replays, 0);
    assert_eq!(ra.health[3].1.accepted, rb.health[3].1.accepted);
    let (sa, sb) = (sa.unwrap(), sb.unwrap());
    for (a, b) in [
        (sa.horizontal_error_final_m, sb.horizontal_error_final_m),
        (sa.horizontal_error_rms_m, sb.horizontal_error_rms_m),
        (sa.depth_error_rms_m, sb.depth_error_rms_m),
        (sa.nees_mean, sb.nees_mean),
    ] {
        assert!((a - b).abs() <= 1e-9 * (1.0 + a.abs()), "{a} vs {b}");
    }
    let (na, nb) = (ra.final_filter.nominal(), rb.final_filter.nominal());
    assert!((na.ins.state.lat - nb.ins.state.lat).abs() < 1e-15);
    assert!((na.ins.state.v_n - nb.ins.state.v_n).norm() < 1e-9);
    assert!(
        (ra.final_filter.covariance() - rb.final_filter.covariance())
            .abs()
            .max()
            < 1e-9
    );
}

/// Without aiding the position diverges (grows without bound: roughly
/// quadratically in time), and DVL aiding beats it by orders of magnitude.
#[test]
fn imu_only_diverges_and_dvl_aiding_bounds_it() {
    let seeds = [1u64, 2, 3, 4];
    let mut imu_only = Vec::new();
    let mut growth = Vec::new();
    for &seed in &seeds {
        let sim = simulation::simulate(&SimConfig::imu_only(), seed);
        let (_, s) = run_and_score(&sim.log, &FilterOptions::default(), None).unwrap();
        let s = s.unwrap();
        let t = s.table.column("t");
        let (n, e) = (s.table.column("err_n"), s.table.column("err_e"));
        let at = |time: f64| {
            let i = t.iter().position(|&x| x >= time).unwrap();
            n[i].hypot(e[i])
        };
        growth.push(at(500.0) / at(250.0));
        imu_only.push(s.horizontal_error_final_m);
    }
    let dvl: Vec<f64> = seeds
        .iter()
        .map(|&s| final_error(&SimConfig::dvl(), s))
        .collect();
    let (mi, md) = (stats::median(&imu_only), stats::median(&dvl));
    assert!(mi > 200.0, "IMU only, median final error {mi} m");
    // Quadratic growth would give 4; a clear acceleration of the error.
    assert!(
        stats::median(&growth) > 2.0,
        "growth 250 -> 500 s: {growth:?}"
    );
    assert!(stats::max(&dvl) < 10.0, "DVL-aided final errors {dvl:?}");
    assert!(mi > 50.0 * md, "IMU only {mi} m vs DVL-aided {md} m");
}

/// The mean NEES of the 9 navigation states over 8 runs lies in the 99.9 %
/// band of chi-square(9 x 8) / 8. (Time samples of one run are correlated, so
/// the runs, not the time steps, are the independent samples.)
#[test]
fn nees_is_consistent_over_seeds() {
    let runs = 8;
    let nees: Vec<f64> = (11..11 + runs as u64)
        .map(|seed| {
            let sim = simulation::simulate(&SimConfig::dvl(), seed);
            let (_, s) = run_and_score(&sim.log, &FilterOptions::default(), None).unwrap();
            s.unwrap().nees_mean
        })
        .collect();
    let m = stats::mean(&nees);
    let lo = chi_square_quantile(0.0005, 9 * runs).unwrap() / runs as f64;
    let hi = chi_square_quantile(0.9995, 9 * runs).unwrap() / runs as f64;
    assert!(
        m > lo && m < hi,
        "mean NEES {m} outside [{lo}, {hi}]: {nees:?}"
    );
}

/// Any subset of aiding sensors replays: depth + USBL only, DVL + USBL only.
#[test]
fn replay_with_a_subset_of_sensors() {
    let full = simulation::simulate(&SimConfig::usbl(), 5).log;
    let mut depth_usbl = full.clone();
    depth_usbl.dvl = None;
    depth_usbl.altitude = None;
    depth_usbl.heading = None;
    let mut dvl_usbl = full.clone();
    dvl_usbl.depth = None;
    dvl_usbl.heading = None;
    for (name, log, bound) in [
        ("depth+usbl", depth_usbl, 100.0),
        ("dvl+usbl", dvl_usbl, 15.0),
    ] {
        let out = Sdins25Replay::new()
            .replay(&log, &ReplayOptions::default())
            .unwrap();
        let e = out.metrics["horizontal_error_final_m"].as_f64().unwrap();
        let d = out.metrics["depth_error_rms_m"].as_f64().unwrap();
        assert!(e.is_finite() && e < bound, "{name}: final error {e} m");
        assert!(d.is_finite(), "{name}");
        let health = &out.metrics["health"];
        assert!(
            health["usbl"]["accepted"].as_f64().unwrap() >= 55.0,
            "{name}: {health}"
        );
    }
}

/// The replay works at any IMU rate: 50 Hz and 200 Hz logs of the DVL case.
#[test]
fn replay_at_50_and_200_hz() {
    for rate in [50.0, 200.0] {
        let config = SimConfig {
            imu_rate: rate,
            ..SimConfig::dvl()
        };
        let sim = simulation::simulate(&config, 2);
        let (run, s) = run_and_score(&sim.log, &FilterOptions::default(), None).unwrap();
        let s = s.unwrap();
        assert_eq!(run.samples, (500.0 * rate) as usize + 1);
        assert!(
            s.horizontal_error_final_m < 10.0,
            "{rate} Hz: {}",
            s.horizontal_error_final_m
        );
        assert!(
            s.nees_mean > 2.0 && s.nees_mean < 30.0,
            "{rate} Hz: NEES {}",
            s.nees_mean
        );
    }
}

/// No DVL update without bottom lock (empty cells) or above 100 m altitude.
#[test]
fn dvl_is_skipped_without_lock_or_out_of_range() {
    let mut log = simulation::simulate(&SimConfig::dvl(), 4).log;
    let dvl = log.dvl.as_mut().unwrap();
    for r in dvl.iter_mut().skip(100).take(50) {
        r.vx = None;
        r.vy = None;
        r.vz = None;
    }
    let alt = log.altitude.as_mut().unwrap();
    for r in alt.iter_mut().skip(400).take(80) {
        r.altitude = 150.0;
    }
    let (run, s) = run_and_score(&log, &FilterOptions::default(), None).unwrap();
    let h = run.health[1].1;
    assert_eq!(h.skipped, 130);
    assert_eq!(h.accepted + h.gated + h.rejected, 1000 - 130);
    assert!(s.unwrap().horizontal_error_final_m < 10.0);
    // The filter module is usable on its own as well.
    assert!(filter::imu_period(&log) > 0.0);
}
