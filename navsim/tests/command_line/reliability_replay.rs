//! Bad input through the `navsim` binary with the SDINS-25 replay model: every
//! kind of malformed log gives a non-zero exit, exactly one `error:` line naming
//! file, line and column (or meta key), nothing on stdout and no output
//! directory; with `--lenient` the bad rows are skipped and counted in the JSON.
//! Also the `--faults` option of the lawn-mower scenarios end to end.

use crate::common;

use common::{navsim, replay_json, stderr, TempDir};
use std::path::Path;

use models::sdins25::simulation::{simulate, SimConfig};
use serde_json::Value;

/// A 20 s SDINS-25 log with every aiding sensor (USBL fixes at 8 and 16 s).
fn write_log(dir: &Path) {
    let config = SimConfig {
        duration: 20.0,
        ..SimConfig::usbl()
    };
    simulate(&config, 4).log.write(dir).unwrap();
}

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        std::fs::copy(e.path(), to.join(e.file_name())).unwrap();
    }
}

/// How a case corrupts the log.
enum Edit {
    /// Replace line `n` (1-based) of the file with the text.
    Line(usize, &'static str),
    /// Replace line `n` by a copy of line `n - 1`.
    DuplicateOf(usize),
    /// Replace the first `t` cell of line `n` with the text.
    TimeOf(usize, &'static str),
    /// Delete line `n`.
    Delete(usize),
    /// The whole file.
    Content(&'static str),
    /// Remove the file.
    Remove,
    /// Replace the first occurrence of a `key = ...` line after `section`.
    MetaKey(&'static str, &'static str, &'static str),
    /// Append text.
    Append(&'static str),
}

fn edit(dir: &Path, file: &str, e: &Edit) {
    let path = dir.join(file);
    let text = std::fs::read_to_string(&path).unwrap_or_default();
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    let new = match e {
        Edit::Line(n, s) => {
            lines[n - 1] = s.to_string();
            lines.join("\n") + "\n"
        }
        Edit::DuplicateOf(n) => {
            lines[n - 1] = lines[n - 2].clone();
            lines.join("\n") + "\n"
        }
        Edit::TimeOf(n, t) => {
            let rest = lines[n - 1].split_once(',').unwrap().1.to_string();
            lines[n - 1] = format!("{t},{rest}");
            lines.join("\n") + "\n"
        }
        Edit::Delete(n) => {
            lines.remove(n - 1);
            lines.join("\n") + "\n"
        }
        Edit::Content(c) => c.to_string(),
        Edit::Remove => {
            std::fs::remove_file(&path).unwrap();
            return;
        }
        Edit::MetaKey(section, key, value) => {
            let start = lines.iter().position(|l| l.trim() == *section).unwrap();
            let k = start
                + lines[start..]
                    .iter()
                    .position(|l| l.starts_with(&format!("{key} =")))
                    .unwrap();
            lines[k] = format!("{key} = {value}");
            lines.join("\n") + "\n"
        }
        Edit::Append(s) => text + s,
    };
    std::fs::write(&path, new).unwrap();
}

/// (name, file, edit, expected text in the error, rows skipped by --lenient
/// or None when the error is fatal in lenient mode too)
type Case = (&'static str, &'static str, Edit, &'static str, Option<u64>);

fn cases() -> Vec<Case> {
    use Edit::*;
    vec![
        (
            "wrong column count",
            "imu.csv",
            Line(5, "0.03,0,0,0,0,0"),
            "imu.csv:5: column `az`",
            Some(1),
        ),
        (
            "too many columns",
            "depth.csv",
            Line(3, "1,10,11"),
            "depth.csv:3: column `<column 3>`",
            Some(1),
        ),
        (
            "text in a number",
            "dvl.csv",
            Line(4, "1.5,abc,0,0"),
            "dvl.csv:4: column `vx`",
            Some(1),
        ),
        (
            // The reader takes the row; the replay does not use it. With
            // --lenient it was a warning but not counted as skipped.
            "DVL row partly empty",
            "dvl.csv",
            Line(4, "1.5,0.2,,0"),
            "dvl.csv:4",
            Some(1),
        ),
        (
            "time backwards",
            "imu.csv",
            TimeOf(10, "0.005"),
            "imu.csv:10: column `t`",
            Some(1),
        ),
        (
            "duplicate timestamp",
            "depth.csv",
            DuplicateOf(5),
            "depth.csv:5: column `t`",
            Some(1),
        ),
        (
            "empty file",
            "heading.csv",
            Content(""),
            "heading.csv: empty file",
            None,
        ),
        (
            "missing header",
            "depth.csv",
            Delete(1),
            "depth.csv:1: column `t`",
            None,
        ),
        (
            "missing imu.csv",
            "imu.csv",
            Remove,
            "imu.csv: required file is missing",
            None,
        ),
        (
            "missing meta.toml",
            "meta.toml",
            Remove,
            "meta.toml: required file is missing",
            None,
        ),
        (
            "malformed meta.toml",
            "meta.toml",
            Content("[initial]\nlat = = 0.6\n"),
            "meta.toml:2",
            None,
        ),
        (
            "unknown sensor",
            "meta.toml",
            Append("\n[sensors.sonar]\nnoise_sigma = 1.0\n"),
            "`sensors.sonar`",
            None,
        ),
        (
            "negative sigma",
            "meta.toml",
            MetaKey("[sensors.dvl]", "noise_sigma", "-0.1"),
            "`sensors.dvl.noise_sigma`",
            None,
        ),
        (
            "latitude beyond 90 deg in meta",
            "meta.toml",
            MetaKey("[initial]", "lat", "1.7"),
            "`initial.lat`",
            None,
        ),
        (
            "text value in meta",
            "meta.toml",
            MetaKey("[initial]", "depth", "\"deep\""),
            "`initial.depth`",
            None,
        ),
    ]
}

#[test]
fn every_bad_input_kind_fails_cleanly_and_lenient_counts_skips() {
    let tmp = TempDir::new("bad-input");
    let good = tmp.path().join("good");
    write_log(&good);

    // The unmodified log replays.
    replay_json(&good, "sdins25", &[]);

    for (i, (name, file, e, expect, lenient)) in cases().into_iter().enumerate() {
        let dir = tmp.path().join(format!("case-{i}"));
        copy_dir(&good, &dir);
        edit(&dir, file, &e);
        let out = tmp.path().join(format!("out-{i}"));
        let args = [
            "replay",
            dir.to_str().unwrap(),
            "--model",
            "sdins25",
            "--json",
            "--out",
            out.to_str().unwrap(),
        ];
        let o = navsim(&args);
        assert!(!o.status.success(), "{name}: accepted");
        assert_eq!(o.status.code(), Some(1), "{name}");
        assert!(o.stdout.is_empty(), "{name}: stdout on error");
        let err = stderr(&o);
        let lines: Vec<&str> = err.lines().collect();
        assert_eq!(lines.len(), 1, "{name}: {err:?}");
        assert!(lines[0].starts_with("error: "), "{name}: {err:?}");
        assert!(
            lines[0].contains(expect),
            "{name}: {err:?} lacks {expect:?}"
        );
        assert!(!out.exists(), "{name}: output directory written on error");

        let o = navsim(&[&args[..], &["--lenient"]].concat());
        match lenient {
            Some(n) => {
                assert!(o.status.success(), "{name} lenient: {}", stderr(&o));
                let v: Value = serde_json::from_slice(&o.stdout).unwrap();
                assert_eq!(v["skipped_rows"], n, "{name}: {v}");
                assert_eq!(v["skipped_rows_by_file"][file], n, "{name}: {v}");
                assert!(v["health"]["dvl"]["gated"].is_number(), "{name}: {v}");
                assert!(out.join("summary.json").is_file(), "{name}");
                // Each skip stands in the JSON, naming the file.
                let said = v["warnings"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .any(|w| w["kind"] == "skipped_row" && w["file"].as_str() == Some(file));
                assert!(said, "{name}: no skipped_row warning for {file}: {v}");
            }
            None => {
                assert_eq!(o.status.code(), Some(1), "{name} lenient");
                assert!(stderr(&o).contains(expect), "{name} lenient");
                assert!(!out.exists(), "{name} lenient: output written");
            }
        }
        let _ = std::fs::remove_dir_all(&out);
    }
    // No staging directories left behind.
    let left: Vec<String> = std::fs::read_dir(tmp.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| !n.starts_with("case-") && n != "good")
        .collect();
    assert!(left.is_empty(), "{left:?}");
}

#[test]
fn replay_json_reports_health_per_sensor() {
    let tmp = TempDir::new("health");
    write_log(tmp.path());
    let v = replay_json(tmp.path(), "sdins25", &[]);
    for s in ["depth", "dvl", "heading", "usbl"] {
        for k in ["rows", "accepted", "gated", "rejected", "skipped", "stuck"] {
            assert!(v["health"][s][k].is_number(), "{s}.{k}: {v}");
        }
    }
    assert!(v["health"]["covariance_repairs"].is_number());
    assert_eq!(v["health"]["usbl"]["rows"], 2.0);
}

/// An unknown CSV file in the log directory: strict replay fails with one
/// `error:` line naming it, nothing on stdout and no output directory;
/// `--lenient` replays, warns once and lists it in `unknown_files`.
#[test]
fn unknown_csv_file_is_an_error_unless_lenient() {
    let tmp = TempDir::new("unknown-file");
    let log = tmp.path().join("log");
    write_log(&log);
    std::fs::write(log.join("sonar.csv"), "t,range\n0.5,12\n").unwrap();
    let out = tmp.path().join("out");
    let o = navsim(&[
        "replay",
        log.to_str().unwrap(),
        "--model",
        "sdins25",
        "--json",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1));
    let err = stderr(&o);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.starts_with("error: sonar.csv: unknown log file"),
        "{err}"
    );
    assert!(o.stdout.is_empty());
    assert!(!out.exists());

    let o = navsim(&[
        "replay",
        log.to_str().unwrap(),
        "--model",
        "sdins25",
        "--json",
        "--lenient",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let err = stderr(&o);
    assert_eq!(
        err.lines()
            .filter(|l| *l == "warning: ignored unknown file sonar.csv")
            .count(),
        1,
        "{err}"
    );
    let v: Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["unknown_files"], serde_json::json!(["sonar.csv"]));
    assert_eq!(v["skipped_rows"], 0);
}

#[test]
fn faults_option_injects_gates_and_counts() {
    let o = navsim(&[
        "scenario",
        "lawnmower-usbl",
        "--runs",
        "2",
        "--json",
        "--faults",
        "spikes,nan-burst,usbl-multipath,reordered",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["faults"].as_array().unwrap().len(), 4);
    assert!(
        v["faults_injected"]["spikes"].as_f64().unwrap() > 50.0,
        "{v}"
    );
    let h = &v["health"];
    let gated: f64 = ["depth", "dvl", "heading"]
        .iter()
        .map(|s| h[s]["gated"].as_f64().unwrap())
        .sum();
    assert!(gated > 50.0, "{h}");
    // NaN bursts are refused by the scheduler, never applied.
    let rejected: f64 = ["depth", "dvl", "heading", "usbl"]
        .iter()
        .map(|s| h[s]["rejected"].as_f64().unwrap())
        .sum();
    assert!(rejected >= v["faults_injected"]["nan-burst"].as_f64().unwrap());
    assert!(
        v["horizontal_error_final_m"]["max"].as_f64().unwrap() < 30.0,
        "{v}"
    );

    // Unknown fault names are a one-line error listing the valid ones.
    let o = navsim(&["scenario", "lawnmower-dvl", "--faults", "gremlins"]);
    assert_eq!(o.status.code(), Some(1));
    let err = stderr(&o);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.contains("gremlins") && err.contains("dvl-dropout"),
        "{err}"
    );
    // lawnmower-dvl has no USBL: multipath is not one of its faults.
    let o = navsim(&["scenario", "lawnmower-dvl", "--faults", "usbl-multipath"]);
    assert_eq!(o.status.code(), Some(1));
}

/// One non-physical reading in an aiding file (a sensor glitch) is a
/// rejected row with a `rejected_reading` warning naming the file, line and
/// column; the replay runs on the other rows (it refused the whole log
/// before).
#[test]
fn one_glitch_in_an_aiding_file_is_a_rejected_row() {
    let tmp = TempDir::new("glitch");
    let good = tmp.path().join("good");
    write_log(&good);
    // (name, file, edit, the warning's location)
    let cases = [
        (
            "NaN",
            "heading.csv",
            Edit::Line(3, "1,NaN"),
            "heading.csv",
            3,
        ),
        (
            "infinity",
            "depth.csv",
            Edit::Line(6, "2.5,inf"),
            "depth.csv",
            6,
        ),
        (
            "latitude beyond 90 deg",
            "usbl.csv",
            Edit::Line(2, "8,1.7,2.2,3"),
            "usbl.csv",
            2,
        ),
        (
            "negative altitude",
            "altitude.csv",
            Edit::Line(4, "1.5,-3"),
            "altitude.csv",
            4,
        ),
    ];
    for (i, (name, file, e, at, line)) in cases.into_iter().enumerate() {
        let dir = tmp.path().join(format!("glitch-{i}"));
        copy_dir(&good, &dir);
        edit(&dir, file, &e);
        let v = replay_json(&dir, "sdins25", &[]);
        let hit = v["warnings"]
            .as_array()
            .unwrap()
            .iter()
            .any(|w| w["kind"] == "rejected_reading" && w["file"] == at && w["line"] == line);
        assert!(hit, "{name}: {}", v["warnings"]);
    }
}
