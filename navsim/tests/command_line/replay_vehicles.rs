//! Vehicles composed from blocks, replayed by the shared SDINS loop
//! (`models::sdins25::filter::run_vehicle`):
//! - `sdins25-composed` (core + USBL + depth + DVL + compass) gives the
//!   estimates and covariance of the monolithic `sdins25`;
//! - `sdins20` (no USBL) on a log without USBL gives sdins25's navigation
//!   solution, and its 20 states carry sdins25's covariance;
//! - `sdins20` on a log with USBL rows counts them as skipped, warns, and
//!   gives the result of the same log without `usbl.csv`;
//! - bad input is still a one-line error through the binary.

use crate::common;

use std::path::Path;

use common::{navsim, stderr, stdout, TempDir};
use models::harness::{ReplayModel, ReplayOptions};
use models::sdins25::filter::{run_vehicle, FilterOptions, InsRun};
use models::sdins25::simulation::{simulate, SimConfig};
use models::sdins25::vehicle::InsVehicle;
use models::sdins25::{InsReplay, Sdins25};
use models::vehicles::sdins::{Sdins20, Sdins25Composed};
use nav_runtime::log::LogDir;
use nav_runtime::model::Model;
use serde_json::Value;

/// `|a - b| <= tol * max(1, |a|, |b|)`.
fn close(what: &str, a: f64, b: f64, tol: f64) {
    let scale = 1f64.max(a.abs()).max(b.abs());
    assert!(
        (a - b).abs() <= tol * scale,
        "{what}: {a} vs {b} (difference {:e})",
        (a - b).abs()
    );
}

/// The run of vehicle `V` with estimates at the truth times.
fn run<V: InsVehicle<N>, const N: usize>(log: &LogDir) -> InsRun<V, N> {
    let times: Vec<f64> = log.truth.as_ref().unwrap().iter().map(|r| r.t).collect();
    run_vehicle::<V, N>(log, &FilterOptions::default(), &times).unwrap()
}

/// Every estimate (navigation solution and 9x9 covariance) of two runs agrees.
fn same_estimates<A: InsVehicle<NA>, B: InsVehicle<NB>, const NA: usize, const NB: usize>(
    a: &InsRun<A, NA>,
    b: &InsRun<B, NB>,
    tol: f64,
) {
    assert_eq!(a.estimates.len(), b.estimates.len());
    let mut compared = 0;
    for (ea, eb) in a.estimates.iter().zip(&b.estimates) {
        let (Some(ea), Some(eb)) = (ea, eb) else {
            assert_eq!(ea.is_some(), eb.is_some());
            continue;
        };
        let (na, nb) = (&ea.nav, &eb.nav);
        // Position in metres (radians of latitude are small).
        close("north", na.lat * 6.4e6, nb.lat * 6.4e6, tol);
        close("east", na.lon * 6.4e6, nb.lon * 6.4e6, tol);
        close("height", na.h, nb.h, tol);
        for i in 0..3 {
            close("velocity", na.v_n[i], nb.v_n[i], tol);
        }
        for (x, y) in na.c_bn.iter().zip(nb.c_bn.iter()) {
            close("attitude", *x, *y, tol);
        }
        for (x, y) in ea.cov.iter().zip(eb.cov.iter()) {
            close("covariance", *x, *y, tol);
        }
        compared += 1;
    }
    assert!(compared > 100, "only {compared} estimates");
    assert_eq!(a.health, b.health);
}

#[test]
fn composed_sdins25_replays_like_the_monolithic_declaration() {
    // 200 s of the USBL lawn-mower survey: every sensor, late USBL fixes.
    let config = SimConfig {
        duration: 200.0,
        ..SimConfig::usbl()
    };
    let log = simulate(&config, 11).log;
    let mono = run::<Sdins25, 25>(&log);
    let composed = run::<Sdins25Composed, 25>(&log);
    assert!(mono.health[3].1.accepted > 10, "{:?}", mono.health);
    same_estimates(&mono, &composed, 1e-9);
    // Same state order: the whole final covariance and nominal agree.
    assert_eq!(
        <Sdins25 as Model<25>>::STATE_NAMES,
        <Sdins25Composed as Model<25>>::STATE_NAMES
    );
    let (pa, pb) = (
        mono.final_filter.covariance(),
        composed.final_filter.covariance(),
    );
    for (x, y) in pa.iter().zip(pb.iter()) {
        close("final covariance", *x, *y, 1e-9);
    }
    let (na, nb) = (mono.final_filter.nominal(), composed.final_filter.nominal());
    for i in 0..3 {
        close("accel bias", na.accel_bias[i], nb.accel_bias[i], 1e-9);
        close("gyro bias", na.gyro_bias[i], nb.gyro_bias[i], 1e-9);
        close("dvl bias", na.dvl_bias[i], nb.dvl_bias[i], 1e-9);
    }
    close("usbl bias", na.usbl_bias[0], nb.usbl_bias[0], 1e-9);
    close("compass bias", na.compass_bias, nb.compass_bias, 1e-9);

    // The replay models (JSON metrics) agree too.
    let opts = ReplayOptions::default();
    let a = InsReplay::<Sdins25, 25>::new().replay(&log, &opts).unwrap();
    let b = InsReplay::<Sdins25Composed, 25>::new()
        .replay(&log, &opts)
        .unwrap();
    assert_eq!(a.samples, b.samples);
    assert_eq!(
        a.metrics.keys().collect::<Vec<_>>(),
        b.metrics.keys().collect::<Vec<_>>()
    );
    for key in [
        "horizontal_error_final_m",
        "horizontal_error_rms_m",
        "depth_error_rms_m",
        "nees_mean",
    ] {
        close(
            key,
            a.metrics[key].as_f64().unwrap(),
            b.metrics[key].as_f64().unwrap(),
            1e-9,
        );
    }
}

#[test]
fn sdins20_without_usbl_carries_the_sdins25_solution() {
    let config = SimConfig {
        duration: 200.0,
        ..SimConfig::dvl()
    };
    let log = simulate(&config, 12).log;
    assert!(log.usbl.is_none());
    let s25 = run::<Sdins25, 25>(&log);
    let s20 = run::<Sdins20, 20>(&log);
    // Without USBL fixes the USBL states never correlate with the others: the
    // navigation solution is the same.
    same_estimates(&s25, &s20, 1e-9);
    assert!(s20.ignored.is_empty());
    // Each of the 20 states has sdins25's variance and covariances.
    let names25 = <Sdins25 as Model<25>>::STATE_NAMES;
    let names20 = <Sdins20 as Model<20>>::STATE_NAMES;
    let at = |name: &str| names25.iter().position(|n| *n == name).unwrap();
    let (p25, p20) = (s25.final_filter.covariance(), s20.final_filter.covariance());
    for (i, a) in names20.iter().enumerate() {
        for (j, b) in names20.iter().enumerate() {
            close(
                &format!("P[{a}, {b}]"),
                p20[(i, j)],
                p25[(at(a), at(b))],
                1e-9,
            );
        }
    }
}

fn json(o: &std::process::Output) -> Value {
    assert!(o.status.success(), "{}", stderr(o));
    serde_json::from_str(stdout(o).trim()).expect("one JSON object")
}

fn replay(dir: &Path, model: &str) -> (Value, String) {
    let o = navsim(&["replay", dir.to_str().unwrap(), "--model", model, "--json"]);
    (json(&o), stderr(&o))
}

fn number(v: &Value, key: &str) -> f64 {
    v[key]
        .as_f64()
        .unwrap_or_else(|| panic!("{key} missing: {v}"))
}

fn keys(v: &Value) -> Vec<String> {
    v.as_object().unwrap().keys().cloned().collect()
}

#[test]
fn navsim_replays_composed_vehicles() {
    let tmp = TempDir::new("replay-vehicles");
    let dvl = tmp.path().join("dvl");
    common::simulate("lawnmower-dvl", 2, &dvl);

    // (b) A log without USBL: the same keys, the same final error; sdins25
    // says that its declared USBL is fed by no file, sdins20 has none.
    let (a, warn) = replay(&dvl, "sdins25");
    let unfed: Vec<&Value> = a["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|w| w["kind"] == "missing_sensor_section")
        .collect();
    assert_eq!(unfed.len(), 1, "{}", a["warnings"]);
    assert_eq!(unfed[0]["file"], "usbl.csv");
    let message = unfed[0]["message"].as_str().unwrap();
    assert!(
        message.contains("sensor Usbl of vehicle sdins25"),
        "{message}"
    );
    assert!(warn.contains(message), "{warn}");
    let (b, warn) = replay(&dvl, "sdins20");
    assert!(warn.is_empty(), "{warn}");
    assert_eq!(b["model"], "sdins20");
    assert_eq!(keys(&a), keys(&b));
    assert_eq!(keys(&a["health"]), keys(&b["health"]));
    assert_eq!(b["samples"], a["samples"]);
    for key in ["horizontal_error_final_m", "horizontal_error_rms_m"] {
        eprintln!(
            "lawnmower-dvl seed 2 {key}: sdins25 {} sdins20 {}",
            a[key], b[key]
        );
        close(key, number(&a, key), number(&b, key), 1e-9);
    }
    let (c, _) = replay(&dvl, "sdins25-composed");
    assert_eq!(keys(&a), keys(&c));
    close(
        "composed",
        number(&a, "horizontal_error_final_m"),
        number(&c, "horizontal_error_final_m"),
        1e-9,
    );

    // (c) A log with USBL rows: sdins20 counts them as skipped and warns; its
    // result is that of the same log without usbl.csv.
    let usbl = tmp.path().join("usbl");
    common::simulate("lawnmower-usbl", 2, &usbl);
    let rows = std::fs::read_to_string(usbl.join("usbl.csv"))
        .unwrap()
        .lines()
        .count()
        - 1;
    assert!(rows > 10, "{rows} USBL rows");
    let (with, warn) = replay(&usbl, "sdins20");
    let h = &with["health"]["usbl"];
    assert_eq!(h["rows"], rows as f64);
    assert_eq!(h["skipped"], rows as f64);
    assert_eq!(h["accepted"], 0.0);
    let lines: Vec<&str> = warn.lines().collect();
    assert_eq!(lines.len(), 1, "{warn}");
    assert!(
        lines[0].starts_with("warning: model sdins20 has no usbl sensor")
            && lines[0].contains(&format!("{rows} rows of usbl.csv")),
        "{warn}"
    );
    std::fs::remove_file(usbl.join("usbl.csv")).unwrap();
    let (without, warn) = replay(&usbl, "sdins20");
    assert!(warn.is_empty(), "{warn}");
    assert_eq!(without["health"]["usbl"]["rows"], 0.0);
    for key in ["horizontal_error_final_m", "horizontal_error_rms_m"] {
        assert_eq!(with[key], without[key], "{key}");
    }
}

#[test]
fn bad_input_is_one_error_line_for_sdins20() {
    let tmp = TempDir::new("replay-vehicles-bad");
    let dir = tmp.path().join("log");
    let config = SimConfig {
        duration: 10.0,
        ..SimConfig::dvl()
    };
    simulate(&config, 3).log.write(&dir).unwrap();
    let path = dir.join("dvl.csv");
    let text = std::fs::read_to_string(&path).unwrap();
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    // Text is not a reading (a NaN would be a glitch: a rejected row).
    lines[3] = "1.5,0.1,fast,0.0".to_string();
    std::fs::write(&path, lines.join("\n") + "\n").unwrap();
    let o = navsim(&[
        "replay",
        dir.to_str().unwrap(),
        "--model",
        "sdins20",
        "--json",
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert!(o.stdout.is_empty());
    let err = stderr(&o);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.starts_with("error: ") && err.contains("dvl.csv:4: column `vy`"),
        "{err}"
    );
    // With --lenient the row is skipped and counted.
    let o = navsim(&[
        "replay",
        dir.to_str().unwrap(),
        "--model",
        "sdins20",
        "--json",
        "--lenient",
    ]);
    let v = json(&o);
    assert_eq!(v["skipped_rows"], 1);
}

/// `summary.json` of an `--out` directory without its wall times.
fn summary_without_runtime(dir: &Path) -> Value {
    let text = std::fs::read_to_string(dir.join("summary.json")).unwrap();
    let mut v: Value = serde_json::from_str(&text).unwrap();
    v.as_object_mut().unwrap().remove("runtime_s");
    v
}

#[test]
fn a_users_replay_program_gives_the_navsim_replay() {
    use nav_replay::program::replay_main_with;
    let tmp = TempDir::new("replay-main");
    let log = tmp.path().join("log");
    let config = SimConfig {
        duration: 60.0,
        ..SimConfig::dvl()
    };
    simulate(&config, 5).log.write(&log).unwrap();
    let (mine, theirs) = (tmp.path().join("mine"), tmp.path().join("navsim"));
    let code = replay_main_with::<Sdins20, 20, _, _>([
        "my-vehicle",
        "replay",
        log.to_str().unwrap(),
        "--out",
        mine.to_str().unwrap(),
        "--json",
    ]);
    assert_eq!(code, std::process::ExitCode::SUCCESS);
    let o = navsim(&[
        "replay",
        log.to_str().unwrap(),
        "--model",
        "sdins20",
        "--out",
        theirs.to_str().unwrap(),
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        summary_without_runtime(&mine),
        summary_without_runtime(&theirs)
    );
    for file in ["errors.csv", "replay-track.svg", "replay-nees.svg"] {
        assert!(mine.join(file).exists(), "{file}");
    }
    // `check` reads the log; a missing directory is an error.
    let ok = replay_main_with::<Sdins20, 20, _, _>([
        "my-vehicle",
        "check",
        log.to_str().unwrap(),
        "--json",
    ]);
    assert_eq!(ok, std::process::ExitCode::SUCCESS);
    let missing = tmp.path().join("nothing");
    let bad =
        replay_main_with::<Sdins20, 20, _, _>(["my-vehicle", "check", missing.to_str().unwrap()]);
    assert_eq!(bad, std::process::ExitCode::FAILURE);
}

/// A cell of a 30-s USBL survey log changed: `(file, data row, column,
/// value, --lenient)`, and what the replay must say (exit code, text in stderr).
type BrokenCell = (
    &'static str,
    usize,
    usize,
    &'static str,
    bool,
    i32,
    &'static str,
);
const BROKEN_CELLS: &[BrokenCell] = &[
    // Corrupt far-future IMU time on the last row: refused by the preflight
    // as a gap naming both lines (no allocation sized by the time).
    ("imu.csv", usize::MAX, 0, "1e9", false, 1, "imu.csv:3002: `t`: gap of 999999970.010000 s between lines 3001 and 3002"),
    // The same with --lenient: a gap too long to propagate in bounded steps.
    ("imu.csv", usize::MAX, 0, "1e9", true, 1, "imu.csv gap of 999999970.01 s between imu.csv line 3001 to imu.csv line 3002 is too long to propagate"),
    // A 2-s clock jump with --lenient: propagated in steps, with a warning.
    ("imu.csv", usize::MAX, 0, "32", true, 0, "warning: imu.csv gap of 2.0100000000000016 s between imu.csv line 3001 to imu.csv line 3002: propagated in 21 steps"),
    // 1e300 in one gyro cell: refused by the preflight, naming the line.
    ("imu.csv", 1000, 1, "1e300", false, 1, "imu.csv:1002: `gx,gy,gz`: |omega| = inf rad/s: not a physical rate"),
    // 1e300 in one USBL depth cell: a glitch, the row rejected with a
    // warning naming the line and column.
    ("usbl.csv", 1, 3, "1e300", false, 0, "warning: usbl.csv:3: `depth`: 1 row skipped as non-physical"),
];

#[test]
fn broken_cells_are_errors_or_warnings_naming_file_and_line() {
    let tmp = TempDir::new("replay-broken-cells");
    let config = SimConfig {
        duration: 30.0,
        ..SimConfig::usbl()
    };
    let clean = simulate(&config, 4).log;
    for (k, &(file, row, col, value, lenient, code, expected)) in BROKEN_CELLS.iter().enumerate() {
        let dir = tmp.path().join(format!("case{k}"));
        clean.write(&dir).unwrap();
        let path = dir.join(file);
        let text = std::fs::read_to_string(&path).unwrap();
        let mut lines: Vec<String> = text.lines().map(String::from).collect();
        let i = if row == usize::MAX {
            lines.len() - 1
        } else {
            row + 1
        };
        let mut cells: Vec<String> = lines[i].split(',').map(String::from).collect();
        cells[col] = value.to_string();
        lines[i] = cells.join(",");
        std::fs::write(&path, lines.join("\n") + "\n").unwrap();
        let mut args = vec![
            "replay",
            dir.to_str().unwrap(),
            "--model",
            "sdins25",
            "--json",
        ];
        if lenient {
            args.push("--lenient");
        }
        let o = navsim(&args);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(code), "case {k}: {err}");
        assert!(err.contains(expected), "case {k}: {err}");
        if code == 0 {
            // The warning also stands in the JSON.
            let v = json(&o);
            let warning = expected.strip_prefix("warning: ").unwrap();
            // The JSON's message is without the location the line starts with.
            let warning = warning.rsplit(": ").next().unwrap_or(warning);
            assert!(
                v["warnings"].as_array().is_some_and(|w| w
                    .iter()
                    .any(|x| x["message"].as_str().is_some_and(|m| m.contains(warning)))),
                "case {k}: {v}"
            );
        }
    }
}

/// The walk-through's pressure-sensor AUV replays through the same loop: on
/// a log without a lever arm it is sdins20 (same sensors, same residuals);
/// with the pressure sensor 1.2 m aft and 0.3 m below the IMU (the depth
/// rows moved by the true attitude) and the lever arm in `meta.toml`, it
/// takes the lever arm into account while sdins20 warns that it does not.
#[test]
fn the_pressure_sensor_auv_replays_with_its_lever_arm() {
    use models::vehicles::pressure_auv::PressureAuv;
    use nav_runtime::log::{Mounting, AIDING_SENSORS};
    let config = SimConfig {
        duration: 200.0,
        ..SimConfig::dvl()
    };
    let log = simulate(&config, 13).log;
    let s20 = run::<Sdins20, 20>(&log);
    let auv = run::<PressureAuv, 20>(&log);
    same_estimates(&s20, &auv, 1e-9);

    // The sensor at a lever arm: its depth is the IMU's plus (C_b^n r)_D.
    let r = [-1.2, 0.0, 0.3];
    let mut moved = log.clone();
    let truth = log.truth.as_ref().unwrap();
    for row in moved.depth.as_mut().unwrap() {
        let k = truth.partition_point(|t| t.t < row.t - 1e-9);
        let t = &truth[k.min(truth.len() - 1)];
        assert!((t.t - row.t).abs() < 1e-6, "a truth row at each depth row");
        let c = models::sdins25::filter::c_bn(t.roll, t.pitch, t.yaw);
        row.depth += (c * nav_runtime::nalgebra::Vector3::from(r))[2];
    }
    let depth = AIDING_SENSORS.iter().position(|s| *s == "depth").unwrap();
    moved.meta.sensors.mountings[depth] = Some(Mounting {
        lever_arm: r,
        misalignment: [0.0; 3],
    });
    let opts = ReplayOptions::default();
    let at_arm = InsReplay::<PressureAuv, 20>::new()
        .replay(&moved, &opts)
        .unwrap();
    let plain = InsReplay::<PressureAuv, 20>::new()
        .replay(&log, &opts)
        .unwrap();
    let ignored = InsReplay::<Sdins20, 20>::new()
        .replay(&moved, &opts)
        .unwrap();
    let depth_rms =
        |o: &models::harness::ReplayOutput| o.metrics["depth_error_rms_m"].as_f64().unwrap();
    println!(
        "depth error RMS: no lever arm {:.4} m; at 1.2 m aft, 0.3 m down: pressure-auv {:.4} m, sdins20 {:.4} m",
        depth_rms(&plain),
        depth_rms(&at_arm),
        depth_rms(&ignored)
    );
    assert!(
        at_arm
            .warnings
            .iter()
            .all(|w| !w.message.contains("lever_arm")),
        "{:?}",
        at_arm.warnings
    );
    assert!(
        ignored
            .warnings
            .iter()
            .any(|w| w.file.as_deref() == Some("meta.toml")
                && w.key.as_deref() == Some("sensors.depth.lever_arm")),
        "{:?}",
        ignored.warnings
    );
    assert!(
        (depth_rms(&at_arm) - depth_rms(&plain)).abs() < 0.02,
        "{} vs {}",
        depth_rms(&at_arm),
        depth_rms(&plain)
    );
}

/// Without a `[sensors.dvl]` section the filter weighs the DVL with the
/// model's built-in sigma; the innovations report that sigma (and the
/// supported one), as they do with a section. They said `null` and gave
/// only a factor.
#[test]
fn innovations_give_the_built_in_sigma_of_a_sensor_without_a_section() {
    let tmp = TempDir::new("built-in-sigma");
    let log = tmp.path().join("log");
    common::simulate("lawnmower-dvl", 3, &log);
    let meta = log.join("meta.toml");
    let text = std::fs::read_to_string(&meta).unwrap();
    let mut skip = false;
    let kept: Vec<&str> = text
        .lines()
        .filter(|l| {
            if l.starts_with('[') {
                skip = l.trim() == "[sensors.dvl]";
            }
            !skip
        })
        .collect();
    std::fs::write(&meta, kept.join("\n") + "\n").unwrap();
    let (v, _) = replay(&log, "sdins25");
    let dvl = &v["innovations"]["dvl"];
    let built_in = nav_runtime::simulation::sensors::ErrorSpec::sdins25_dvl().noise;
    assert_eq!(dvl["noise_sigma"].as_f64(), Some(built_in), "{dvl}");
    assert!(dvl["supported_sigma"].is_number(), "{dvl}");
    assert!(
        v["warnings"]
            .as_array()
            .unwrap()
            .iter()
            .any(|w| w["kind"] == "missing_sensor_section" && w["key"] == "sensors.dvl"),
        "{}",
        v["warnings"]
    );
}
