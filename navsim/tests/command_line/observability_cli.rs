//! `navsim replay --observability` on logs whose answer is known: a DVL
//! survey without position fixes (absolute horizontal position is not
//! observable), a vehicle at rest without a compass (heading and the
//! vertical gyro bias are not), the leveling filter on its weave, and the
//! refusal for a model without the report.

use crate::common;

use std::path::Path;

use common::{navsim, replay_json, stderr, TempDir};
use nav_runtime::earth::Geodetic;
use nav_runtime::log::{DepthRow, DvlRow, ImuRow, LogDir, Meta};
use nav_runtime::simulation::imu::{rates, ImuModel, ImuSpec};
use nav_runtime::simulation::trajectory::{Trajectory, TrajectorySpec, TruthSource};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;
use serde_json::Value;

/// `learned` of `state` in a replay's JSON.
fn learned(v: &Value, state: &str) -> f64 {
    v["observability"]["states"][state]["learned"]
        .as_f64()
        .unwrap_or_else(|| panic!("no learned for {state}: {}", v["observability"]))
}

fn replay(dir: &Path, model: &str) -> Value {
    replay_json(dir, model, &["--observability"])
}

/// A vehicle at rest for `seconds`: IMU (SDINS-25 class), DVL reading zero
/// and a depth meter, no compass.
fn write_at_rest(dir: &Path, seconds: f64) {
    let start = Geodetic::new(0.6, 2.2, -20.0);
    let traj = Trajectory::new(TrajectorySpec::new(start, 0.7, 0.0), seconds, 0.1);
    let spec = ImuSpec::sdins25();
    let s = traj.truth(0.0);
    let meta = format!(
        "[initial]\nt = 0.0\nlat = {:?}\nlon = {:?}\ndepth = 20.0\nroll = {:?}\npitch = {:?}\nyaw = {:?}\n\n\
         [sensors.imu]\ngyro_bias_sigma = {:?}\ngyro_noise_sigma = {:?}\naccel_bias_sigma = {:?}\naccel_noise_sigma = {:?}\n\n\
         [sensors.dvl]\nnoise_sigma = 0.01\n\n[sensors.depth]\nnoise_sigma = 0.05\n",
        s.lat, s.lon, s.euler.roll, s.euler.pitch, s.euler.yaw,
        spec.gyro_bias, spec.gyro_noise, spec.accel_bias, spec.accel_noise
    );
    let mut log = LogDir::new(Meta::parse(&meta).unwrap());
    let mut imu = ImuModel::new(spec, 5);
    log.imu = rates(&traj, 100.0, seconds)
        .map(|r| ImuRow::from(&imu.corrupt_rate(&r)))
        .collect();
    // Noisy readings, as a sensor gives: exact repeats would be refused as
    // a frozen sensor after a few rows.
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let mut noise = |sigma: f64| sigma * rng.sample::<f64, _>(StandardNormal);
    let (mut dvl, mut depth) = (Vec::new(), Vec::new());
    for k in 1..=(seconds as usize * 2) {
        let t = k as f64 * 0.5;
        dvl.push(DvlRow::new(
            t,
            Some(noise(0.01)),
            Some(noise(0.01)),
            Some(noise(0.01)),
        ));
        depth.push(DepthRow::new(t, 20.0 + noise(0.05)));
    }
    log.dvl = Some(dvl);
    log.depth = Some(depth);
    log.write(dir).unwrap();
}

/// A DVL, depth and compass survey without position fixes: the depth is
/// learned, the absolute horizontal position is not (the weakest direction
/// is in it), and the filter's own velocity and tilt are.
#[test]
fn a_survey_without_position_fixes_does_not_learn_the_position() {
    let tmp = TempDir::new("obs-dvl");
    let dir = tmp.path().join("log");
    common::simulate("lawnmower-dvl", 4, &dir);
    let v = replay(&dir, "sdins20");
    for state in ["position_error[0]", "position_error[1]"] {
        assert!(learned(&v, state) < 0.01, "{state}: {}", v["observability"]);
    }
    for state in [
        "position_error[2]",
        "velocity_error[0]",
        "attitude_error[0]",
    ] {
        assert!(learned(&v, state) > 0.3, "{state}: {}", v["observability"]);
    }
    // The weakest directions: the horizontal position, and the depth
    // against the depth meter's bias (only their difference is measured).
    let weakest = v["observability"]["weakest"].as_array().unwrap();
    let made_of = |prefixes: &[&str]| {
        weakest.iter().any(|d| {
            d["learned"].as_f64().unwrap() < 0.01
                && d["combination"]
                    .as_object()
                    .unwrap()
                    .keys()
                    .all(|k| prefixes.iter().any(|p| k.starts_with(p)))
        })
    };
    assert!(
        made_of(&["position_error[0]", "position_error[1]"]),
        "{weakest:?}"
    );
    assert!(made_of(&["position_error[2]", "depth_bias"]), "{weakest:?}");
    // Per sensor: each state is taught by the sensors that see it, and no
    // sensor alone teaches more than all of them together.
    let by = |state: &str, sensor: &str| {
        v["observability"]["states"][state]["by_sensor"][sensor]
            .as_f64()
            .unwrap_or_else(|| panic!("no by_sensor.{sensor} for {state}"))
    };
    let cases: &[(&str, &str, bool)] = &[
        ("compass_bias", "Compass", true),
        ("compass_bias", "Dvl", false),
        ("compass_bias", "Depth", false),
        ("depth_bias", "Depth", true),
        ("depth_bias", "Dvl", false),
        ("position_error[2]", "Depth", true),
        ("position_error[2]", "Dvl", false),
        ("velocity_error[0]", "Dvl", true),
        ("velocity_error[0]", "Depth", false),
        ("velocity_error[0]", "Compass", false),
        ("dvl_bias[0]", "Dvl", true),
        ("dvl_bias[0]", "Compass", false),
    ];
    for &(state, sensor, teaches) in cases {
        let l = by(state, sensor);
        assert_eq!(l > 0.05, teaches, "{state} by {sensor}: {l}");
        assert!(l <= learned(&v, state) + 0.01, "{state} by {sensor}: {l}");
    }
}

/// At rest without a compass, with noisy zero-velocity DVL and depth
/// readings: heading and the vertical gyro bias are not learned (a rotation
/// about the vertical changes no reading in two minutes); tilt and the
/// horizontal accelerometer bias only together (at rest they give the same
/// specific force: each is learned by about 1 - 1/sqrt(2)); the horizontal
/// gyro biases are (a tilt growing in time is told from a constant one).
#[test]
fn at_rest_without_a_compass_heading_and_vertical_gyro_bias_are_not_learned() {
    let tmp = TempDir::new("obs-rest");
    let dir = tmp.path().join("log");
    std::fs::create_dir_all(&dir).unwrap();
    write_at_rest(&dir, 120.0);
    let v = replay(&dir, "sdins20");
    let o = &v["observability"];
    for state in ["attitude_error[2]", "gyro_bias[2]"] {
        assert!(learned(&v, state) < 0.05, "{state}: {o}");
    }
    for state in [
        "attitude_error[0]",
        "attitude_error[1]",
        "accel_bias[0]",
        "accel_bias[1]",
    ] {
        let l = learned(&v, state);
        assert!((0.1..0.5).contains(&l), "{state}: {l}: {o}");
    }
    for state in [
        "gyro_bias[0]",
        "gyro_bias[1]",
        "velocity_error[0]",
        "accel_bias[2]",
    ] {
        assert!(learned(&v, state) > 0.8, "{state}: {o}");
    }
}

/// A model without the report says so instead of ignoring the flag.
#[test]
fn a_model_without_the_report_refuses_the_flag() {
    let tmp = TempDir::new("obs-refuse");
    let dir = tmp.path().join("log");
    common::simulate("lawnmower-dvl", 2, &dir);
    let o = navsim(&[
        "replay",
        dir.to_str().unwrap(),
        "--model",
        "demo-depth-kf",
        "--observability",
    ]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("--observability"), "{}", stderr(&o));
}

/// The leveling filter (a direct-state model) on the S-type track: the
/// vertical body velocity is not learned (no pitch rate couples it into
/// the forward speed), the gravity direction is, all of it by the speed
/// log with the unit norm.
#[test]
fn the_leveling_filter_reports_what_the_weave_taught() {
    let tmp = TempDir::new("obs-leveling");
    let dir = tmp.path().join("log");
    common::simulate("leveling-moving", 3, &dir);
    let v = replay(&dir, "leveling6");
    assert!(learned(&v, "velocity[2]") < 1e-6, "{}", v["observability"]);
    for state in [
        "gravity_direction[0]",
        "gravity_direction[1]",
        "velocity[0]",
    ] {
        let l = learned(&v, state);
        assert!(l > 0.9, "{state}: {l}");
        let by = v["observability"]["states"][state]["by_sensor"]["Moving"]
            .as_f64()
            .unwrap();
        assert!((by - l).abs() < 1e-6, "{state}: {by} against {l}");
    }
    let weakest = &v["observability"]["weakest"][0]["combination"];
    assert_eq!(weakest.as_object().unwrap().len(), 1, "{weakest}");
    assert_eq!(weakest["velocity[2]"], 1.0, "{weakest}");
}
