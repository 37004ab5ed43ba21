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

/// The rows of a CSV file with a header, as numbers.
fn rows(path: &std::path::Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).expect("file written");
    let mut lines = text.lines();
    let header = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    (header, rows)
}

/// A log without truth (the usual real log): `--smooth` writes the
/// smoothed trajectory beside the forward one, row for row, and leaves the
/// forward one as it was.
#[test]
fn replay_smooth_writes_the_smoothed_trajectory_of_a_log_without_truth() {
    let dir = TempDir::new("smooth-no-truth");
    let log = dir.path().join("log");
    common::simulate("lawnmower-usbl-10s", 5, &log);
    std::fs::remove_file(log.join("truth.csv")).unwrap();
    let log = log.to_str().unwrap();
    let run = |out: &std::path::Path, smooth: bool| {
        let mut args = vec!["replay", log, "--model", "sdins25", "--json"];
        args.extend(["--out", out.to_str().unwrap()]);
        if smooth {
            args.push("--smooth");
        }
        json(&navsim(&args))
    };
    let (plain, smoothed) = (dir.path().join("plain"), dir.path().join("smoothed"));
    let forward = run(&plain, false);
    let both = run(&smoothed, true);
    assert!(forward.get("smoothed").is_none());
    let (header, estimates) = rows(&smoothed.join("estimates.csv"));
    assert_eq!(
        (header.clone(), estimates.clone()),
        rows(&plain.join("estimates.csv")),
        "the forward trajectory is the same with --smooth"
    );
    let (smoothed_header, smoothed_rows) = rows(&smoothed.join("smoothed.csv"));
    assert_eq!(smoothed_header, header);
    assert_eq!(smoothed_rows.len(), estimates.len());
    assert!(estimates.len() > 50, "{} rows", estimates.len());
    assert_eq!(
        both["smoothed"]["estimates"].as_u64(),
        Some(estimates.len() as u64)
    );
    let column = |name: &str| header.iter().position(|h| h == name).unwrap();
    // The smoothed estimate is at the same time, its sigmas are no larger,
    // and at the end it is the forward estimate (nothing comes after it).
    let mut tighter = 0;
    for (f, s) in estimates.iter().zip(&smoothed_rows) {
        assert_eq!(f[0], s[0], "same time");
        for name in ["sig_n", "sig_e", "sig_d", "sig_vn", "sig_yaw_deg"] {
            let k = column(name);
            assert!(
                s[k] <= f[k] * (1.0 + 1e-9) + 1e-12,
                "{name} at t = {}",
                f[0]
            );
        }
        tighter += usize::from(s[column("sig_n")] < 0.9 * f[column("sig_n")]);
    }
    assert!(tighter > estimates.len() / 2, "{tighter} rows tighter");
    let (f, s) = (estimates.last().unwrap(), smoothed_rows.last().unwrap());
    for k in 1..f.len() {
        assert!(
            (f[k] - s[k]).abs() <= 1e-9 * f[k].abs().max(1.0),
            "{}",
            header[k]
        );
    }
    let notes = both["warnings"].to_string();
    assert!(notes.contains("smoothed run is not scored"), "{notes}");
    // Without truth, the plots of what the run estimated, forward and smoothed.
    for plot in ["replay-estimated-track.svg", "replay-horizontal-sigma.svg"] {
        let svg = std::fs::read_to_string(smoothed.join(plot)).expect(plot);
        assert!(
            svg.contains("forward") && svg.contains("smoothed"),
            "{plot}"
        );
        assert!(plain.join(plot).is_file(), "{plot} without --smooth");
    }
}
