//! End-to-end tests of the `navsim` binary (the plumbing, with the demo scenario).

use crate::common;

use common::{navsim, navsim_env, stderr, stdout, TempDir};
use std::process::Output;

use serde_json::Value;

const DEMO: &str = "demo-constant-velocity";
const DEMO_MODEL: &str = "demo-depth-kf";

/// The command failed with exactly one `error: ...` line on stderr; returns it.
fn one_line_error(o: &Output) -> String {
    assert!(
        !o.status.success(),
        "expected failure, stdout: {}",
        stdout(o)
    );
    let err = stderr(o);
    let lines: Vec<&str> = err.lines().collect();
    assert_eq!(lines.len(), 1, "stderr: {err:?}");
    assert!(lines[0].starts_with("error: "), "stderr: {err:?}");
    assert!(o.stdout.is_empty(), "stdout on error: {}", stdout(o));
    lines[0].to_string()
}

/// The command succeeded and printed exactly one JSON object on stdout.
fn json(o: &Output) -> Value {
    assert!(o.status.success(), "stderr: {}", stderr(o));
    let out = stdout(o);
    assert_eq!(out.lines().count(), 1, "stdout: {out:?}");
    let v: Value = serde_json::from_str(out.trim()).expect("valid JSON");
    assert!(v.is_object(), "{v}");
    v
}

#[test]
fn unknown_scenario_is_a_one_line_error_naming_valid_ones() {
    let line = one_line_error(&navsim(&["scenario", "no-such-thing"]));
    assert!(line.contains("no-such-thing"), "{line}");
    assert!(line.contains(DEMO), "{line}");
}

#[test]
fn bad_values_are_one_line_errors() {
    let line = one_line_error(&navsim(&["scenario", DEMO, "--seed", "abc"]));
    assert!(line.contains("--seed"), "{line}");
    let line = one_line_error(&navsim(&["scenario", DEMO, "--runs", "0"]));
    assert!(line.contains("--runs"), "{line}");
    // Seeds past u64's end wrapped to 0 with no word.
    let last = u64::MAX.to_string();
    let line = one_line_error(&navsim(&["scenario", DEMO, "--seed", &last, "--runs", "2"]));
    assert!(
        line.contains("--seed") && line.contains("--runs 2"),
        "{line}"
    );
    let v = json(&navsim(&[
        "scenario", DEMO, "--seed", &last, "--runs", "1", "--json",
    ]));
    assert_eq!(v["runs"], 1, "{v}");
    let line = one_line_error(&navsim(&["scenario", DEMO, "--shard", "5/4", "--out", "x"]));
    assert!(line.contains("5/4"), "{line}");
    let line = one_line_error(&navsim(&["scenario", DEMO, "--faults", "gremlins"]));
    assert!(
        line.contains("gremlins") && line.contains("depth-dropout"),
        "{line}"
    );
    let line = one_line_error(&navsim(&["replay", "somewhere"]));
    assert!(line.contains("--model"), "{line}");
    let line = one_line_error(&navsim(&["replay", "somewhere", "--model", "nope"]));
    assert!(line.contains("nope") && line.contains(DEMO_MODEL), "{line}");
    let line = one_line_error(&navsim(&["frobnicate"]));
    assert!(line.contains("frobnicate"), "{line}");
}

/// `--draw-biases` where it would change nothing is refused, naming the
/// scenarios it changes (it was accepted and ignored); where it changes
/// something it is taken. (command line, accepted)
#[test]
fn draw_biases_is_refused_where_it_would_change_nothing() {
    let dir = TempDir::new("draw-biases");
    let log = dir.path().join("log");
    let log = log.to_str().unwrap();
    let cases: [(&[&str], bool); 6] = [
        (&["scenario", "lawnmower-dvl", "--runs", "1"], false),
        (&["scenario", "vkf", "--runs", "1"], false),
        (&["scenario", "marker-path", "--runs", "1"], false),
        (
            &["simulate", "lawnmower-usbl", "--seed", "1", "--out", log],
            false,
        ),
        (&["simulate", "vkf", "--seed", "1", "--out", log], true),
        (&["scenario", DEMO, "--runs", "2", "--json"], true),
    ];
    for (args, accepted) in cases {
        let mut args = args.to_vec();
        args.push("--draw-biases");
        let o = navsim(&args);
        if accepted {
            assert!(o.status.success(), "{args:?}: {}", stderr(&o));
            continue;
        }
        let line = one_line_error(&o);
        assert!(
            line.contains("--draw-biases") && line.contains(args[1]) && line.contains(DEMO),
            "{args:?}: {line}"
        );
    }
}

#[test]
fn json_output_is_one_object_with_the_common_keys() {
    let v = json(&navsim(&[
        "scenario", DEMO, "--runs", "3", "--seed", "11", "--json",
    ]));
    assert_eq!(v["scenario"], DEMO);
    assert_eq!(v["runs"], 3);
    assert_eq!(v["seed"], 11);
    for key in ["depth_error_rms_m", "depth_error_final_m"] {
        for stat in ["median", "p95", "max"] {
            assert!(v[key][stat].is_f64(), "{key}.{stat} in {v}");
        }
    }
    let nees = v["nees_mean"].as_f64().unwrap();
    assert!(nees > 0.5 && nees < 5.0, "{nees}");
}

#[test]
fn no_command_runs_the_default_scenario() {
    let o = navsim(&[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = stdout(&o);
    assert!(out.contains("scenario"), "{out}");
}

#[test]
fn results_do_not_depend_on_thread_count() {
    let args = ["scenario", DEMO, "--runs", "6", "--seed", "40", "--json"];
    let one = json(&navsim_env(&args, &[("RAYON_NUM_THREADS", "1")]));
    let two = json(&navsim_env(&args, &[("RAYON_NUM_THREADS", "2")]));
    assert_eq!(one, two);
}

#[test]
fn merged_shards_equal_the_single_run() {
    let dir = TempDir::new("shards");
    let base = [
        "scenario",
        DEMO,
        "--runs",
        "10",
        "--seed",
        "5",
        "--faults",
        "depth-dropout",
    ];
    let single = navsim(&[&base[..], &["--json"]].concat());
    let single_json = json(&single);
    let mut outs = Vec::new();
    for k in 1..=4 {
        let out = dir.path().join(format!("machine{k}"));
        let shard = format!("{k}/4");
        let v = json(&navsim(
            &[
                &base[..],
                &["--json", "--shard", &shard, "--out", out.to_str().unwrap()],
            ]
            .concat(),
        ));
        assert_eq!(v["shard"], shard.as_str());
        outs.push(out);
    }
    let mut args = vec!["merge".to_string()];
    args.extend(outs.iter().map(|p| p.display().to_string()));
    args.push("--json".into());
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let merged = navsim(&args);
    assert_eq!(json(&merged), single_json);
    assert_eq!(stdout(&merged), stdout(&single), "byte-identical JSON");
    assert_eq!(single_json["faults"], serde_json::json!(["depth-dropout"]));

    // A missing shard is reported with the missing seeds.
    let line = one_line_error(&navsim(&[
        "merge",
        outs[0].to_str().unwrap(),
        outs[1].to_str().unwrap(),
    ]));
    assert!(line.contains("missing seeds"), "{line}");
    // The same shard twice is a duplicate.
    let line = one_line_error(&navsim(&[
        "merge",
        outs[0].to_str().unwrap(),
        outs[0].to_str().unwrap(),
    ]));
    assert!(line.contains("also in"), "{line}");
    // A result without a metric the others have (an edited shard) is
    // refused, naming the file and the seed: its summary read null.
    let shard = std::fs::read_dir(&outs[1])
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.extension().is_some_and(|x| x == "json"))
        .unwrap();
    let mut v: Value = serde_json::from_str(&std::fs::read_to_string(&shard).unwrap()).unwrap();
    let seed = v["results"][0]["seed"].clone();
    let metrics = v["results"][0]["metrics"].as_object_mut().unwrap();
    assert!(metrics.remove("nees_mean").is_some(), "{metrics:?}");
    std::fs::write(&shard, v.to_string()).unwrap();
    let mut args = vec!["merge".to_string()];
    args.extend(outs.iter().map(|p| p.display().to_string()));
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let line = one_line_error(&navsim(&args));
    let file = shard.file_name().unwrap().to_str().unwrap();
    assert!(
        line.contains(file) && line.contains(&format!("seed {seed} has no metric `nees_mean`")),
        "{line}"
    );
}

#[test]
fn shard_needs_out() {
    let line = one_line_error(&navsim(&["scenario", DEMO, "--shard", "1/2"]));
    assert!(line.contains("--out"), "{line}");
}

#[test]
fn out_dir_gets_csv_plots_and_summary() {
    let dir = TempDir::new("out");
    let out = dir.path().join("results");
    let v = json(&navsim(&[
        "scenario",
        DEMO,
        "--runs",
        "2",
        "--seed",
        "3",
        "--json",
        "--out",
        out.to_str().unwrap(),
    ]));
    assert!(out.join("run-3-depth.csv").is_file());
    assert!(out.join("run-4-depth.csv").is_file());
    assert!(out.join("nees.svg").is_file());
    let summary: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary, v);
}

#[test]
fn simulate_then_replay_reproduces_the_scenario() {
    let dir = TempDir::new("sim");
    let log = dir.path().join("log");
    common::simulate(DEMO, 21, &log);
    for f in ["imu.csv", "depth.csv", "truth.csv", "meta.toml"] {
        assert!(log.join(f).is_file(), "{f}");
    }
    let replay = json(&navsim(&[
        "replay",
        log.to_str().unwrap(),
        "--model",
        DEMO_MODEL,
        "--json",
    ]));
    assert_eq!(replay["model"], DEMO_MODEL);
    assert_eq!(replay["samples"], 3000);
    assert!(replay["runtime_s"].as_f64().unwrap() >= 0.0);
    assert!(replay.get("skipped_rows").is_none());
    let scenario = json(&navsim(&[
        "scenario", DEMO, "--runs", "1", "--seed", "21", "--json",
    ]));
    assert_eq!(
        replay["depth_error_rms_m"],
        scenario["depth_error_rms_m"]["median"]
    );
    assert_eq!(
        replay["depth_error_final_m"],
        scenario["depth_error_final_m"]["median"]
    );
}

#[test]
fn replay_of_a_malformed_log_names_file_line_column_and_writes_nothing() {
    let dir = TempDir::new("bad");
    let log = dir.path().join("log");
    common::simulate(DEMO, 2, &log);
    let depth = log.join("depth.csv");
    let mut lines: Vec<String> = std::fs::read_to_string(&depth)
        .unwrap()
        .lines()
        .map(String::from)
        .collect();
    lines[6] = "0.7,12.x".into(); // line 7
    lines[9] = "0.95,nan".into(); // line 10
    std::fs::write(&depth, lines.join("\n") + "\n").unwrap();

    let out = dir.path().join("replay-out");
    let args = [
        "replay",
        log.to_str().unwrap(),
        "--model",
        DEMO_MODEL,
        "--json",
        "--out",
        out.to_str().unwrap(),
    ];
    let line = one_line_error(&navsim(&args));
    assert!(line.contains("depth.csv:7"), "{line}");
    assert!(line.contains("column `depth`"), "{line}");
    assert!(!out.exists(), "no output directory on error");
    let leftovers: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(leftovers.len(), 1, "{leftovers:?}");

    // --lenient skips and counts the bad row, rejects the glitch (NaN) with
    // its own warning, and writes the outputs.
    let v = json(&navsim(&[&args[..], &["--lenient"]].concat()));
    assert_eq!(v["skipped_rows"], 1);
    assert_eq!(v["skipped_rows_by_file"]["depth.csv"], 1);
    assert!(
        v["warnings"]
            .as_array()
            .unwrap()
            .iter()
            .any(|w| w["kind"] == "rejected_reading"
                && w["file"] == "depth.csv"
                && w["line"] == 10),
        "{v}"
    );
    assert!(out.join("summary.json").is_file());
    assert!(stderr(&navsim(&[&args[..], &["--lenient"]].concat())).contains("depth.csv:10"));
}

#[test]
fn replay_of_a_missing_directory_fails() {
    let line = one_line_error(&navsim(&[
        "replay",
        "/nonexistent/log/dir",
        "--model",
        DEMO_MODEL,
    ]));
    assert!(line.contains("/nonexistent/log/dir"), "{line}");
}

#[test]
fn list_names_scenarios_and_models() {
    let v = json(&navsim(&["list", "--json"]));
    let names: Vec<&str> = v["scenarios"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["name"].as_str().unwrap())
        .collect();
    assert!(names.contains(&DEMO));
    assert!(v["models"]
        .as_array()
        .unwrap()
        .iter()
        .any(|m| m["name"] == DEMO_MODEL));
}

/// `replay --model leveling6 --out` writes its table and the roll and pitch
/// errors with their sigma bounds as plots, as the other replays do.
#[test]
fn the_leveling_replay_writes_its_plots() {
    let tmp = TempDir::new("leveling-plots");
    let log = tmp.path().join("log");
    let out = tmp.path().join("out");
    common::simulate("leveling-moving", 3, &log);
    let v = json(&navsim(&[
        "replay",
        log.to_str().unwrap(),
        "--model",
        "leveling6",
        "--json",
        "--out",
        out.to_str().unwrap(),
    ]));
    assert!(v["roll_error_final_deg"].is_number(), "{v}");
    for file in ["attitude.csv", "replay-roll.svg", "replay-pitch.svg"] {
        let text =
            std::fs::read_to_string(out.join(file)).unwrap_or_else(|e| panic!("{file}: {e}"));
        assert!(text.len() > 100, "{file}");
    }
    let svg = std::fs::read_to_string(out.join("replay-roll.svg")).unwrap();
    assert!(svg.contains("sigma"), "the bounds are drawn");
}

/// A leveling log whose truth and estimate share fewer than two rows after
/// the initial guess is an error, as for every other model: its final
/// errors read exactly 0 and its RMS errors null before.
#[test]
fn a_leveling_log_with_nothing_to_score_is_an_error() {
    let tmp = TempDir::new("leveling-nothing-to-score");
    let base = tmp.path().join("base");
    common::simulate("leveling-stationary", 1, &base);
    let keep_lines = |file: &str, lines: usize, dir: &std::path::Path| {
        let text = std::fs::read_to_string(base.join(file)).unwrap();
        let kept: Vec<&str> = text.lines().take(lines).collect();
        std::fs::write(dir.join(file), kept.join("\n") + "\n").unwrap();
    };
    // (case, file cut, lines kept with the header)
    let cases = [
        ("three IMU samples", "imu.csv", 4),
        ("one truth row", "truth.csv", 2),
    ];
    for (name, file, lines) in cases {
        let log = tmp.path().join(name.replace(' ', "-"));
        std::fs::create_dir(&log).unwrap();
        for entry in std::fs::read_dir(&base).unwrap() {
            let from = entry.unwrap().path();
            std::fs::copy(&from, log.join(from.file_name().unwrap())).unwrap();
        }
        keep_lines(file, lines, &log);
        let o = navsim(&[
            "replay",
            log.to_str().unwrap(),
            "--model",
            "leveling6",
            "--json",
        ]);
        assert_eq!(o.status.code(), Some(1), "{name}: {}", stdout(&o));
        assert!(stdout(&o).is_empty(), "{name}: {}", stdout(&o));
        let e = one_line_error(&o);
        assert!(
            e.contains("truth.csv") && e.contains("nothing to score"),
            "{name}: {e}"
        );
    }
}

/// The NEES line names the states its scenario counts (`nees_dof`): the
/// demo's two, not the nine of the INS scenarios it once said.
#[test]
fn the_nees_line_counts_the_scenarios_own_states() {
    let o = navsim(&["scenario", DEMO, "--runs", "2"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    assert!(text.contains("NEES of the 2 states, mean"), "{text}");
    let v = json(&navsim(&["scenario", DEMO, "--runs", "2", "--json"]));
    assert_eq!(v["nees_dof"], 2, "{v}");
}
