//! `[files.truth] lever_arm`: a truth written at a point of the vehicle
//! other than the IMU (here 1.85 m ahead of it and 0.3 m below), as a
//! post-processed reference often is, scores the filter as the IMU's truth
//! does once the arm is declared, and worse without it.

use crate::common;

use common::{navsim, stderr, stdout, TempDir};
use nav_runtime::attitude::Euler;
use nav_runtime::earth::{Geodetic, LocalNed};
use nav_runtime::log::{LogDir, Strictness, TruthRow};
use nav_runtime::nalgebra::Vector3;
use serde_json::Value;

const ARM: [f64; 3] = [1.85, 0.0, 0.3];

fn replay(log: &str) -> Value {
    let o = navsim(&["replay", log, "--model", "sdins25", "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    serde_json::from_str(&stdout(&o)).expect("one JSON object")
}

/// The truth rows moved from the IMU to the point `ARM`: position through
/// the local level frame, velocity with the body rate of the central
/// difference of the attitude (independent of the replay's transport).
fn at_reference(truth: &[TruthRow]) -> Vec<TruthRow> {
    let arm = Vector3::from(ARM);
    let c = |r: &TruthRow| {
        Euler {
            roll: r.roll,
            pitch: r.pitch,
            yaw: r.yaw,
        }
        .c_bn()
    };
    (0..truth.len())
        .map(|i| {
            let r = truth[i];
            let (a, b) = (
                truth[i.saturating_sub(1)],
                truth[(i + 1).min(truth.len() - 1)],
            );
            let turn = c(&a).transpose() * c(&b);
            let omega = nav_runtime::attitude::rotvec_from_rotation(&turn) / (b.t - a.t);
            let c_bn = c(&r);
            let frame = LocalNed::new(Geodetic::new(r.lat, r.lon, -r.depth));
            let at = frame.ned_to_geodetic(&(c_bn * arm));
            let v = Vector3::new(r.vn, r.ve, r.vd) + c_bn * omega.cross(&arm);
            TruthRow {
                lat: at.lat,
                lon: at.lon,
                depth: -at.h,
                vn: v.x,
                ve: v.y,
                vd: v.z,
                ..r
            }
        })
        .collect()
}

/// A simulated `lawnmower-dvl` log (seed 5) in a new temporary directory,
/// and its path.
fn simulated(tag: &str) -> (TempDir, std::path::PathBuf) {
    let dir = TempDir::new(tag);
    let log = dir.path().join("log");
    common::simulate("lawnmower-dvl", 5, &log);
    (dir, log)
}

#[test]
fn a_declared_reference_point_scores_as_the_imu_truth() {
    let (_dir, log) = simulated("reference-point");
    let log_str = log.to_str().unwrap();
    let at_imu = replay(log_str);

    let mut read = LogDir::read(&log, Strictness::Strict).unwrap();
    read.truth = Some(at_reference(read.truth.as_ref().unwrap()));
    read.write(&log).unwrap();
    let undeclared = replay(log_str);
    let meta = std::fs::read_to_string(log.join("meta.toml")).unwrap();
    std::fs::write(
        log.join("meta.toml"),
        format!(
            "{meta}\n[files.truth]\nlever_arm = [{}, {}, {}]\n",
            ARM[0], ARM[1], ARM[2]
        ),
    )
    .unwrap();
    let declared = replay(log_str);

    let rms = |v: &Value| v["horizontal_error_rms_m"].as_f64().unwrap();
    let nees = |v: &Value| v["nees_mean"].as_f64().unwrap();
    assert!(
        (rms(&declared) - rms(&at_imu)).abs() < 0.005,
        "RMS {} declared, {} at the IMU",
        rms(&declared),
        rms(&at_imu)
    );
    assert!(
        (nees(&declared) / nees(&at_imu) - 1.0).abs() < 0.05,
        "NEES {} declared, {} at the IMU",
        nees(&declared),
        nees(&at_imu)
    );
    // Undeclared, the velocity errors in turns name the point; declared
    // (or at the IMU), nothing is said.
    let fitted = |v: &Value| {
        v["warnings"].as_array().is_some_and(|w| {
            w.iter()
                .any(|w| w["key"] == "files.truth.lever_arm" && w["file"] == "truth.csv")
        })
    };
    assert!(fitted(&undeclared), "{undeclared}");
    assert!(
        !fitted(&declared) && !fitted(&at_imu),
        "{declared} {at_imu}"
    );
    // Undeclared, the arm's turning is scored as the filter's error.
    assert!(
        nees(&undeclared) > 2.0 * nees(&at_imu),
        "NEES {} undeclared, {} at the IMU",
        nees(&undeclared),
        nees(&at_imu)
    );
}

/// An initial position copied from the reference row at the epoch (the
/// truth's point, not the IMU) is a warning naming `initial.lever_arm`,
/// and starts the filter off by the arm; with `[initial] lever_arm` it is
/// moved to the IMU and the warning is gone.
#[test]
fn an_initial_position_copied_from_the_reference_is_warned_and_can_be_moved() {
    let (dir, log) = simulated("initial-reference-point");
    let mut read = LogDir::read(&log, Strictness::Strict).unwrap();
    let reference = at_reference(read.truth.as_ref().unwrap());
    let epoch = read.meta.initial.t.unwrap();
    let first = reference
        .iter()
        .find(|r| (r.t - epoch).abs() < 1e-9)
        .expect("a truth row at the epoch");
    read.meta.initial.lat = first.lat;
    read.meta.initial.lon = first.lon;
    read.meta.initial.depth = first.depth;
    read.truth = Some(reference.clone());
    read.write(&log).unwrap();
    let meta = read.meta.to_toml();
    let truth_arm = format!(
        "\n[files.truth]\nlever_arm = [{:?}, {:?}, {:?}]\n",
        ARM[0], ARM[1], ARM[2]
    );
    let initial_arm = format!(
        "[initial]\nlever_arm = [{:?}, {:?}, {:?}]\n",
        ARM[0], ARM[1], ARM[2]
    );
    let moved_meta = meta.replacen("[initial]\n", &initial_arm, 1);
    assert_ne!(moved_meta, meta);
    // The JSON, and the horizontal error at the epoch (m).
    let run = |meta: &str| {
        std::fs::write(log.join("meta.toml"), format!("{meta}{truth_arm}")).unwrap();
        let out = dir.path().join("out");
        let args = [
            "replay",
            log.to_str().unwrap(),
            "--model",
            "sdins25",
            "--json",
        ];
        let o = navsim(&[&args[..], &["--out", out.to_str().unwrap()]].concat());
        assert!(o.status.success(), "{}", stderr(&o));
        let json: Value = serde_json::from_str(&stdout(&o)).expect("one JSON object");
        let errors = std::fs::read_to_string(out.join("errors.csv")).unwrap();
        let first: Vec<f64> = errors
            .lines()
            .nth(1)
            .unwrap()
            .split(',')
            .map(|c| c.parse().unwrap())
            .collect();
        assert_eq!(first[0], epoch);
        (json, first[1].hypot(first[2]))
    };
    let warned = |v: &Value| {
        v["warnings"].as_array().is_some_and(|w| {
            w.iter()
                .any(|w| w["key"] == "initial.lever_arm" && w["kind"] == "suspicious")
        })
    };
    let (copied, copied_error) = run(&meta);
    let (moved, moved_error) = run(&moved_meta);
    assert!(warned(&copied), "{copied}");
    assert!(!warned(&moved), "{moved}");
    // The arm's horizontal part is 1.85 m.
    assert!(copied_error > 1.8, "{copied_error} m copied");
    assert!(moved_error < 0.01, "{moved_error} m moved");
}
