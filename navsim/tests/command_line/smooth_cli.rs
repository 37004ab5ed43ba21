//! `--smooth` through the binary: the `smoothed` JSON object beside the
//! unchanged forward keys, the smoothed outputs under `--out`, and a clear
//! refusal where a model cannot be smoothed.

use crate::common;

use common::{navsim, stderr, stdout, TempDir};
use serde_json::Value;

fn json(o: &std::process::Output) -> Value {
    assert!(o.status.success(), "{}", stderr(o));
    serde_json::from_str(&stdout(o)).expect("one JSON object")
}

const KEYS: [&str; 4] = [
    "horizontal_error_final_m",
    "horizontal_error_rms_m",
    "depth_error_rms_m",
    "nees_mean",
];

#[test]
fn scenario_smooth_adds_the_smoothed_statistics() {
    let args = [
        "scenario",
        "lawnmower-usbl-10s",
        "--runs",
        "2",
        "--seed",
        "1",
        "--json",
    ];
    let forward = json(&navsim(&args));
    let mut with = args.to_vec();
    with.push("--smooth");
    let both = json(&navsim(&with));
    for key in KEYS {
        assert_eq!(both[key], forward[key], "forward {key} unchanged");
        assert!(!both["smoothed"][key].is_null(), "smoothed {key}");
    }
    let rms = |v: &Value| v["horizontal_error_rms_m"]["median"].as_f64().unwrap();
    assert!(rms(&both["smoothed"]) < rms(&forward));
    assert!(
        both["smoothed"]["horizontal_rms_ratio"]["median"]
            .as_f64()
            .unwrap()
            < 1.0
    );
    assert!(forward.get("smoothed").is_none());
}

#[test]
fn scenario_smooth_is_refused_where_not_supported() {
    let o = navsim(&["scenario", "leveling-moving", "--runs", "1", "--smooth"]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("cannot be smoothed"), "{}", stderr(&o));
}

#[test]
fn replay_smooth_reports_and_writes_the_smoothed_run() {
    let dir = TempDir::new("smooth");
    let log = dir.path().join("log");
    let out = dir.path().join("out");
    common::simulate("lawnmower-usbl-10s", 4, &log);
    let log = log.to_str().unwrap();
    let forward = json(&navsim(&["replay", log, "--model", "sdins25", "--json"]));
    let both = json(&navsim(&[
        "replay",
        log,
        "--model",
        "sdins25",
        "--json",
        "--smooth",
        "--out",
        out.to_str().unwrap(),
    ]));
    for key in KEYS {
        assert_eq!(both[key], forward[key], "forward {key} unchanged");
        assert!(both["smoothed"][key].as_f64().unwrap().is_finite(), "{key}");
    }
    assert!(
        both["smoothed"]["horizontal_error_rms_m"].as_f64().unwrap()
            < forward["horizontal_error_rms_m"].as_f64().unwrap()
    );
    for f in [
        "errors.csv",
        "smoothed_errors.csv",
        "replay-smoothed-horizontal.svg",
    ] {
        assert!(out.join(f).is_file(), "{f} written");
    }
}
