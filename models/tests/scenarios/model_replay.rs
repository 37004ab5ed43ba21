//! The replay of a declared model that is not an INS: a wheeled rover with
//! a position fix and a range-bearing sensor to a beacon, on logs the tests
//! write (with the truth), in several units and column orders, and broken
//! in the ways users break them.

use models::vehicles::rover::{rover_replay as rover, write_log, LogStyle, Rover, DRIVE_STEPS};
use nav_replay::model_replay::{
    angle_states, quaternion_blocks, ModelReplay, ModelReplayError, ModelRun, RunOptions,
};
use nav_replay::temp_dir::TempDir;
use std::path::Path;

const SI: LogStyle = LogStyle {
    other_units: false,
    shuffled: false,
};

#[test]
fn the_heading_is_the_rovers_only_angle_state() {
    assert_eq!(angle_states::<Rover, 3>(), [false, false, true]);
}

/// Monte Carlo over 10 seeds: the errors are small against the sensors'
/// sigmas and the NEES and every sensor's NIS are in their band.
#[test]
fn a_rover_replays_consistently_over_seeds() {
    let dir = TempDir::new("seeds");
    let mut nis_lm = Vec::new();
    let (mut nees, mut nis_fix, mut nis_rb, mut rms) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for seed in 0..10 {
        let log = dir.0.join(format!("seed{seed}"));
        write_log(&log, seed, SI, DRIVE_STEPS);
        let run = rover()
            .replay(&log, None, &RunOptions::default(), None)
            .unwrap_or_else(|e| panic!("seed {seed}: {e}"));
        assert_eq!(run.samples, 2000);
        let truth = run.truth.as_ref().expect("truth scored");
        assert_eq!(truth.scored, 2001, "every sample has its truth row");
        assert_eq!(truth.nees_dof, 3);
        nees.push(truth.nees_mean);
        let [fix, rb, lm] = [&run.sensors[0], &run.sensors[1], &run.sensors[2]];
        assert_eq!((fix.rows, rb.rows, lm.rows), (200, 400, 100), "seed {seed}");
        assert!(
            fix.accepted >= 198 && rb.accepted >= 396 && lm.accepted >= 99,
            "seed {seed}: {fix:?} {rb:?} {lm:?}"
        );
        nis_fix.push(fix.nis_mean.unwrap());
        nis_rb.push(rb.nis_mean.unwrap());
        nis_lm.push(lm.nis_mean.unwrap());
        let horizontal = truth.rms[0].1.hypot(truth.rms[1].1);
        rms.push(horizontal);
        assert!(run.warnings.is_empty(), "seed {seed}: {:?}", run.warnings);
    }
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    // 10 runs x 2001 epochs, 3 states: the mean NEES of a consistent filter
    // is 3 (time-correlated epochs: a wide band); each NIS mean 2.
    assert!((2.0..4.0).contains(&mean(&nees)), "NEES {nees:?}");
    assert!((1.6..2.4).contains(&mean(&nis_fix)), "fix NIS {nis_fix:?}");
    assert!(
        (0.7..1.3).contains(&mean(&nis_lm)),
        "landmark NIS {nis_lm:?}"
    );
    assert!(
        (1.6..2.4).contains(&mean(&nis_rb)),
        "range-bearing NIS {nis_rb:?}"
    );
    // The fixes alone (0.5 m each axis) would give 0.71 m horizontal; with
    // the range-bearing and the dead reckoning between them, well below
    // (measured: 0.145 m).
    assert!(mean(&rms) < 0.25, "horizontal RMS {rms:?}");
}

/// The same log in deg/s and ft with its columns shuffled gives the same
/// estimate to rounding.
#[test]
fn units_and_column_order_do_not_change_the_result() {
    let dir = TempDir::new("units");
    let mut finals = Vec::new();
    for (k, style) in [
        SI,
        LogStyle {
            other_units: true,
            shuffled: false,
        },
        LogStyle {
            other_units: true,
            shuffled: true,
        },
        LogStyle {
            other_units: false,
            shuffled: true,
        },
    ]
    .into_iter()
    .enumerate()
    {
        let log = dir.0.join(format!("style{k}"));
        write_log(&log, 7, style, DRIVE_STEPS);
        let run = rover()
            .replay(&log, None, &RunOptions::default(), None)
            .unwrap_or_else(|e| panic!("style {k}: {e}"));
        finals.push(run.final_state);
    }
    for f in &finals[1..] {
        for ((name, a, sa), (_, b, sb)) in finals[0].iter().zip(f) {
            assert!(
                (a - b).abs() < 1e-9 && (sa - sb).abs() < 1e-9,
                "{name}: {a} vs {b}"
            );
        }
    }
}

/// The time column's own unit, and `--out`: `estimates.csv` holds a row per
/// output time with every state and sigma.
#[test]
fn estimates_are_written_at_the_output_period() {
    let dir = TempDir::new("out");
    let log = dir.0.join("log");
    write_log(&log, 1, SI, DRIVE_STEPS);
    let out = dir.0.join("out");
    std::fs::create_dir_all(&out).unwrap();
    let options = RunOptions {
        output_period: 1.0,
        ..RunOptions::default()
    };
    let run = rover().replay(&log, None, &options, Some(&out)).unwrap();
    let text = std::fs::read_to_string(out.join("estimates.csv")).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("t,position[0],position[1],heading,sigma_position[0],sigma_position[1],sigma_heading")
    );
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|c| c.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 201, "t = 0, 1, ..., 200 s");
    let last = rows.last().unwrap();
    assert!((last[0] - 200.0).abs() < 1e-9);
    for (i, (_, v, s)) in run.final_state.iter().enumerate() {
        assert_eq!((last[1 + i], last[4 + i]), (*v, *s));
    }
}

/// Broken mappings and logs: each is an error naming the file and the key
/// (or line and column), never a panic and never a number.
#[test]
fn broken_mappings_and_logs_are_errors_naming_the_key() {
    // (what to change: (file, from, to), expected parts of the message)
    let cases: &[(&str, &str, &str, &[&str])] = &[
        (
            "replay.toml",
            "[sensors.Fix]",
            "[sensors.Fixx]",
            &["sensors.Fixx", "did you mean `Fix`"],
        ),
        // A file's clock offset: seconds, finite, of a sane size, and a
        // unit only with the column it is the unit of.
        (
            "replay.toml",
            "file = \"gnss.csv\"",
            "file = \"gnss.csv\"\ntime = { offset_s = \"0.3\" }",
            &[
                "sensors.Fix.time.offset_s",
                "expected seconds (a number), found string",
            ],
        ),
        (
            "replay.toml",
            "file = \"gnss.csv\"",
            "file = \"gnss.csv\"\ntime = { offset_s = 1e12 }",
            &["sensors.Fix.time.offset_s", "is not an offset in seconds"],
        ),
        (
            "replay.toml",
            "file = \"gnss.csv\"",
            "file = \"gnss.csv\"\ntime = { offset_s = nan }",
            &[
                "sensors.Fix.time.offset_s",
                "NaN is not an offset in seconds",
            ],
        ),
        (
            "replay.toml",
            "file = \"gnss.csv\"",
            "file = \"gnss.csv\"\ntime = { unit = \"ms\", offset_s = 0.1 }",
            &["sensors.Fix.time", "`unit` or `scale` without `column`"],
        ),
        (
            "replay.toml",
            "file = \"gnss.csv\"",
            "file = \"gnss.csv\"\ntime = { column = \"t\", offset = 0.1 }",
            &["sensors.Fix.time", "unknown key"],
        ),
        // One suggestion rule for every name (case, one edit, a swap).
        (
            "replay.toml",
            "[sensors.Fix]",
            "[sensors.fix]",
            &["sensors.fix", "did you mean `Fix`"],
        ),
        (
            "replay.toml",
            "[sensors.Fix]",
            "[sensors.Fxi]",
            &["sensors.Fxi", "did you mean `Fix`"],
        ),
        (
            "replay.toml",
            "z = [\"north\", \"east\"]",
            "z = [\"North\", \"east\"]",
            &["gnss.csv has no column `North`", "did you mean `north`"],
        ),
        (
            "replay.toml",
            "[inputs]",
            "[INPUTS]",
            &["`INPUTS`", "did you mean `inputs`"],
        ),
        (
            "replay.toml",
            "speed_noise =",
            "speed_noies =",
            &["noise.speed_noies", "did you mean `speed_noise`"],
        ),
        (
            "replay.toml",
            "z = [\"north\", \"east\"]",
            "z = [\"north\", \"eats\"]",
            &[
                "sensors.Fix.z[1]",
                "gnss.csv has no column `eats`",
                "did you mean `east`",
            ],
        ),
        (
            "replay.toml",
            "z = [\"north\", \"east\"]",
            "z = [\"north\"]",
            &["sensors.Fix.z", "expected 2 columns, found 1"],
        ),
        (
            "replay.toml",
            "unit = \"deg\"",
            "unit = \"degree\"",
            &["initial.state.heading.unit", "unknown unit `degree`"],
        ),
        (
            "replay.toml",
            "file = \"gnss.csv\"",
            "file = \"gps.csv\"",
            &[
                "gps.csv: required file is missing",
                "named by `replay.toml: sensors.Fix.file`",
            ],
        ),
        (
            "replay.toml",
            "file = \"gnss.csv\"",
            "file = \"../gnss.csv\"",
            &["sensors.Fix.file", "would leave the log directory"],
        ),
        (
            "replay.toml",
            "file = \"gnss.csv\"",
            "file = \"/etc/passwd\"",
            &["sensors.Fix.file", "absolute path"],
        ),
        (
            "replay.toml",
            "beacon = [40, -25]",
            "",
            &["parameters", "`beacon[0]`, `beacon[1]`"],
        ),
        (
            "replay.toml",
            "speed_noise =",
            "speed_nosie =",
            &["noise.speed_nosie", "did you mean `speed_noise`"],
        ),
        (
            "replay.toml",
            "heading = 0.05",
            "heading = -0.05",
            &["initial.sigma", "is not a sigma"],
        ),
        (
            "replay.toml",
            "sigma = 0.5",
            "sigma = 0.5\ngate = 1.5",
            &["sensors.Fix.gate", "not a probability"],
        ),
        (
            "replay.toml",
            "[inputs]",
            "[input]",
            &["`input`", "did you mean `inputs`"],
        ),
        (
            "replay.toml",
            "sigma = 0.5",
            "sigma = 1e-300",
            &["sensors.Fix.sigma", "its square finite and above 0"],
        ),
        (
            "replay.toml",
            "sigma = 0.5",
            "sigma = \"half\"",
            &["sensors.Fix.sigma", "expected a number, found string"],
        ),
        ("replay.toml", "[initial]", "[initial\n", &["replay.toml:"]),
        (
            "gnss.csv",
            "t,north,east",
            "t,north",
            &["sensors.Fix.z[1]", "no column `east`"],
        ),
        (
            "gnss.csv",
            "t,north,east",
            "t,north,north",
            &["gnss.csv:1", "the header names column `north` twice"],
        ),
        (
            "wheels.csv",
            "\n0.5,",
            "\n0.5x,",
            &["wheels.csv:7: column `t`", "`0.5x` is not a number"],
        ),
        (
            "wheels.csv",
            "\n0.5,",
            "\n0.2,",
            &["wheels.csv:7: column `t`", "time goes backwards"],
        ),
        (
            "beacon.csv",
            "\n1,",
            "\n1,NaN",
            &["beacon.csv:3: column `range`"],
        ),
        // A decimal comma: one cell more than the header, not shifted values.
        (
            "gnss.csv",
            "\n1.5,",
            "\n1.5,0,",
            &["gnss.csv:3", "expected 3 columns, found 4"],
        ),
        // A finite cell that overflows once converted.
        (
            "replay.toml",
            "file = \"gnss.csv\"",
            "file = \"gnss.csv\"\ntime = { column = \"t\", scale = 1e308 }",
            &["gnss.csv:4: column `t`", "finite once converted"],
        ),
        (
            "replay.toml",
            "position = 0.0",
            "position = 0.0\n\"position[0]\" = 5.0",
            &["initial.state.position[0]", "given twice"],
        ),
        (
            "replay.toml",
            "speed_noise = ",
            "speed_noise = -",
            &["noise.speed_noise", "negative"],
        ),
        (
            "replay.toml",
            "position = 1.0",
            "position = 1e200",
            &["initial.sigma", "its square finite"],
        ),
        // The first interval is a gap like any other.
        (
            "replay.toml",
            "t = 0.0",
            "t = -30.0",
            &["wheels.csv:2", "gap of 30 s"],
        ),
        // One input row at the epoch: nothing to propagate.
        (
            "replay.toml",
            "t = 0.0",
            "t = 200.0",
            &["wheels.csv:2002", "nothing to propagate"],
        ),
    ];
    let dir = TempDir::new("broken");
    for (k, (file, from, to, expected)) in cases.iter().enumerate() {
        let log = dir.0.join(format!("case{k}"));
        write_log(&log, 3, SI, DRIVE_STEPS);
        let path = log.join(file);
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(text.contains(from), "case {k}: `{from}` not in {file}");
        std::fs::write(&path, text.replacen(from, to, 1)).unwrap();
        let message = match rover().replay(&log, None, &RunOptions::default(), None) {
            Ok(_) => panic!("case {k} ({file}: {from} -> {to}) replayed"),
            Err(e) => e.to_string(),
        };
        for part in *expected {
            assert!(
                message.contains(part),
                "case {k}: `{message}` lacks `{part}`"
            );
        }
        // `check` reads the log as the replay does: it refuses it too.
        let d = log.to_string_lossy().into_owned();
        assert_eq!(
            rover().main_with(["rover", "check", d.as_str()]),
            std::process::ExitCode::FAILURE,
            "case {k}: check passes a log the replay refuses ({message})"
        );
    }
}

/// Files the log points out of its directory are refused without being
/// read (nothing of them is quoted), and a header of a hundred thousand
/// columns is refused after one pass instead of being searched column by
/// column (the cost was quadratic in its width).
#[test]
fn files_outside_the_log_and_absurd_headers_are_refused() {
    let dir = TempDir::new("outside");
    let secret = dir.0.join("secret.csv");
    std::fs::write(&secret, "root:x:0:0:the first line of a private file\n").unwrap();
    // (case, edit of the log, expected parts of the message)
    type Edit = fn(&Path, &Path);
    let cases: &[(&str, Edit, &[&str])] = &[
        (
            "a sensor file linked out of the log",
            |log, secret| {
                std::fs::remove_file(log.join("gnss.csv")).unwrap();
                std::os::unix::fs::symlink(secret, log.join("gnss.csv")).unwrap();
            },
            &["gnss.csv", "outside the log directory", "refused"],
        ),
        (
            "the mapping linked out of the log",
            |log, secret| {
                std::fs::remove_file(log.join("replay.toml")).unwrap();
                std::os::unix::fs::symlink(secret, log.join("replay.toml")).unwrap();
            },
            &["replay.toml", "outside the log directory"],
        ),
        (
            "a header of 100,000 columns",
            |log, _| {
                let text = std::fs::read_to_string(log.join("gnss.csv")).unwrap();
                let (header, rest) = text.split_once('\n').unwrap();
                let wide: String = (0..100_000).map(|k| format!(",extra{k}")).collect();
                std::fs::write(log.join("gnss.csv"), format!("{header}{wide}\n{rest}")).unwrap();
            },
            &["gnss.csv:1", "100", "columns, more than the 4096"],
        ),
    ];
    for (k, (name, edit, expected)) in cases.iter().enumerate() {
        let log = dir.0.join(format!("case{k}"));
        write_log(&log, 3, SI, DRIVE_STEPS);
        edit(&log, &secret);
        let message = match rover().replay(&log, None, &RunOptions::default(), None) {
            Ok(_) => panic!("{name}: replayed"),
            Err(e) => e.to_string(),
        };
        assert!(
            !message.contains("root:x"),
            "{name}: quotes the file: {message}"
        );
        for part in *expected {
            assert!(message.contains(part), "{name}: `{message}` lacks `{part}`");
        }
    }
}

/// Lenient reading skips a bad row, counts it and says so; a sensor whose
/// rows are all refused, and a truth the filter's sigmas do not describe,
/// are warnings, not silent numbers.
#[test]
fn lenient_reading_and_refused_sensors_are_in_the_warnings() {
    let dir = TempDir::new("lenient");
    let log = dir.0.join("log");
    write_log(&log, 4, SI, DRIVE_STEPS);
    let path = log.join("gnss.csv");
    let text = std::fs::read_to_string(&path).unwrap();
    std::fs::write(&path, text.replacen("\n1.5,", "\n1.5,oops,", 1)).unwrap();
    // `check` refuses it as the replay does, and passes it with --lenient.
    let d = log.to_string_lossy().into_owned();
    let program = |args: &[&str]| {
        rover().main_with(
            ["rover", "check", d.as_str()]
                .into_iter()
                .chain(args.iter().copied()),
        )
    };
    assert_eq!(program(&[]), std::process::ExitCode::FAILURE);
    assert_eq!(program(&["--lenient"]), std::process::ExitCode::SUCCESS);
    let options = RunOptions {
        lenient: true,
        ..RunOptions::default()
    };
    let run = rover().replay(&log, None, &options, None).unwrap();
    assert_eq!(run.skipped_rows, vec![("gnss.csv".to_string(), 1)]);
    assert_eq!(run.sensors[0].rows, 199);
    assert!(run.skip_reasons[0].to_string().contains("gnss.csv:3"));
    assert!(
        run.warnings
            .iter()
            .any(|w| w.message.contains("skipped gnss.csv:3")
                && w.file.as_deref() == Some("gnss.csv")),
        "{:?}",
        run.warnings
    );

    // (case, what is done to the log, the file and the words of the warning,
    // what else must hold)
    type Edit = fn(&Path);
    type Holds = fn(&ModelRun) -> bool;
    let cases: [(&str, Edit, &str, &[&str], Holds); 5] = [
        (
            // Fixes 100 m off: every one gated.
            "offset",
            |log| edit_rows(&log.join("gnss.csv"), |_, c| c[1] += 100.0),
            "gnss.csv",
            &["sensor Fix: none of its 200 rows was applied"],
            |run| run.sensors[0].accepted == 0,
        ),
        (
            // Every fourth fix 100 m off: most still applied, the gated
            // share far beyond the gate's.
            "some-off",
            |log| {
                edit_rows(&log.join("gnss.csv"), |row, c| {
                    if row % 4 == 1 {
                        c[1] += 100.0;
                    }
                })
            },
            "gnss.csv",
            &["sensor Fix: 50 of its 200 rows were gated (25.0 %)"],
            |run| run.sensors[0].gated == 50,
        ),
        (
            // A truth heading 0.5 rad off (another convention): the RMS
            // errors are not the filter's, and the NEES says so.
            "truth-convention",
            |log| edit_rows(&log.join("truth.csv"), |_, c| c[3] += 0.5),
            "truth.csv",
            &["mean NEES", "for 3 scored states"],
            |_| true,
        ),
        (
            // Fix times read as ms: the fixes crowd the first 0.2 s and
            // most are gated.
            "fix-ms",
            |log| {
                let path = log.join("replay.toml");
                let mapping = std::fs::read_to_string(&path).unwrap().replacen(
                    "file = \"gnss.csv\"",
                    "file = \"gnss.csv\"\ntime = { column = \"t\", unit = \"ms\" }",
                    1,
                );
                std::fs::write(&path, mapping).unwrap();
            },
            "gnss.csv",
            &["sensor Fix: only"],
            |_| true,
        ),
        (
            // A header-only truth file: no score of zeros.
            "truth-header",
            |log| {
                std::fs::write(log.join("truth.csv"), "t,position[0],position[1],heading\n")
                    .unwrap()
            },
            "truth.csv",
            &["nothing is scored"],
            |run| run.truth.is_none(),
        ),
    ];
    for (name, edit, file, said, holds) in cases {
        let log = dir.0.join(name);
        write_log(&log, 4, SI, DRIVE_STEPS);
        edit(&log);
        let run = rover()
            .replay(&log, None, &RunOptions::default(), None)
            .unwrap();
        assert!(holds(&run), "{name}: {:?}", run.sensors);
        assert!(
            run.warnings
                .iter()
                .any(|w| w.file.as_deref() == Some(file)
                    && said.iter().all(|s| w.message.contains(s))),
            "{name}: {:?}",
            run.warnings
        );
    }
}

/// Rewrites the data rows of a CSV file of numbers: `edit(row, values)`,
/// rows counted from 1 (the header is row 0 and kept).
fn edit_rows(path: &Path, edit: impl Fn(usize, &mut [f64])) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut out = String::new();
    for (row, line) in text.lines().enumerate() {
        if row == 0 {
            out.push_str(line);
        } else {
            let mut values: Vec<f64> = line.split(',').map(|c| c.parse().unwrap()).collect();
            edit(row, &mut values);
            let cells: Vec<String> = values.iter().map(f64::to_string).collect();
            out.push_str(&cells.join(","));
        }
        out.push('\n');
    }
    std::fs::write(path, out).unwrap();
}

/// A sensor the mapping does not feed, and sensor rows before the epoch,
/// are in the warnings.
#[test]
fn what_the_log_does_not_feed_is_said() {
    let dir = TempDir::new("unfed");
    let log = dir.0.join("log");
    write_log(&log, 5, SI, DRIVE_STEPS);
    let mapping = std::fs::read_to_string(log.join("replay.toml")).unwrap();
    let cut = mapping.find("[sensors.RangeBearing]").unwrap();
    let truth = mapping.find("[truth.columns]").unwrap();
    let mapping = format!("{}{}", &mapping[..cut], &mapping[truth..]);
    let mapping = mapping.replace("t = 0.0\n", "t = 10.0\n");
    std::fs::write(log.join("replay.toml"), mapping).unwrap();
    let run = rover()
        .replay(&log, None, &RunOptions::default(), None)
        .unwrap();
    let messages: Vec<&str> = run.warnings.iter().map(|w| w.message.as_str()).collect();
    assert!(
        messages
            .iter()
            .any(|m| m.contains("no [sensors.RangeBearing]")),
        "{messages:?}"
    );
    assert!(
        messages
            .iter()
            .any(|m| m.contains("100 row(s) before the initial epoch")),
        "{messages:?}"
    );
    assert!(
        messages
            .iter()
            .any(|m| m.contains("sensor Fix: 10 row(s) more than one input period before")),
        "{messages:?}"
    );
    // The files of the two sensors cut from the mapping feed nothing.
    let unused: Vec<&str> = run
        .warnings
        .iter()
        .filter(|w| w.kind == nav_runtime::log::WarningKind::UnusedFile)
        .filter_map(|w| w.file.as_deref())
        .collect();
    assert_eq!(unused, ["beacon.csv", "landmarks.csv"], "{messages:?}");
    assert_eq!(run.samples, 1900);
}

/// A program that registers a sensor twice, or that does not register a
/// sensor the declaration has and the mapping feeds, is told so: the
/// first was fed once and reported twice, the second as "not fed"; the
/// second was called a sensor the model does not have, with a rename
/// suggested.
#[test]
fn a_sensor_registered_twice_or_not_at_all_is_said() {
    use models::vehicles::rover::{RoverFix, RoverLandmarkRange, RoverRangeBearing};
    let dir = TempDir::new("registered");
    let log = dir.0.join("log");
    write_log(&log, 5, SI, DRIVE_STEPS);
    let twice = ModelReplay::<Rover, 3>::new("rover")
        .sensor::<RoverFix, 2>()
        .sensor::<RoverRangeBearing, 2>()
        .sensor::<RoverFix, 2>()
        .sensor::<RoverLandmarkRange, 1>();
    let missing = ModelReplay::<Rover, 3>::new("rover")
        .sensor::<RoverFix, 2>()
        .sensor::<RoverLandmarkRange, 1>();
    // (program, what the error says)
    let cases = [
        (twice, "sensor Fix of model Rover is registered twice"),
        (
            missing,
            "sensor `RangeBearing` of model Rover is declared but this program does not register it",
        ),
    ];
    for (program, says) in cases {
        let e = program
            .replay(&log, None, &RunOptions::default(), None)
            .unwrap_err();
        assert!(e.to_string().contains(says), "{e}");
    }
}

/// A truth column whose name misses its state's by a letter leaves that
/// state unscored: said, naming the column and the state, not silent.
#[test]
fn a_misspelt_truth_column_is_said() {
    let dir = TempDir::new("truth-typo");
    let log = dir.0.join("log");
    write_log(&log, 5, SI, DRIVE_STEPS);
    let truth = std::fs::read_to_string(log.join("truth.csv")).unwrap();
    std::fs::write(
        log.join("truth.csv"),
        truth.replacen("heading", "headng", 1),
    )
    .unwrap();
    let run = rover()
        .replay(&log, None, &RunOptions::default(), None)
        .unwrap();
    let scored: Vec<&str> = run.truth.unwrap().rms.iter().map(|(k, _)| *k).collect();
    assert!(!scored.contains(&"heading"), "{scored:?}");
    let w: Vec<_> = run
        .warnings
        .iter()
        .filter(|w| w.kind == nav_runtime::log::WarningKind::PartialScoring)
        .collect();
    assert_eq!(w.len(), 1, "{:?}", run.warnings);
    assert_eq!(w[0].key.as_deref(), Some("headng"));
    assert!(
        w[0].message.contains("did you mean `heading`?"),
        "{}",
        w[0].message
    );
}

/// `check` says what the replay would not use: a sensor file with only
/// its header, one whose rows all lie outside the inputs' span (times in
/// milliseconds), one with a glitch (a NaN reading). It printed their
/// spans and no warning.
#[test]
fn check_says_what_the_replay_would_not_use() {
    let dir = TempDir::new("check-warns");
    // (the edit of beacon.csv, the warning's kind, what its message says)
    type Edit = fn(&str) -> String;
    let cases: [(Edit, &str, &str); 3] = [
        (
            |text| text.lines().next().unwrap().to_string() + "\n",
            "suspicious",
            "has no rows",
        ),
        (
            |text| {
                let mut lines = text.lines();
                let mut out = lines.next().unwrap().to_string() + "\n";
                for line in lines {
                    let (t, rest) = line.split_once(',').unwrap();
                    let ms = t.parse::<f64>().unwrap() * 1000.0;
                    out.push_str(&format!("{ms},{rest}\n"));
                }
                out
            },
            "outside_imu_span",
            "no row of beacon.csv lies within the inputs' span",
        ),
        (
            |text| {
                let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
                let (t, rest) = lines[5].split_once(',').unwrap();
                let rest = rest
                    .split_once(',')
                    .map_or(String::new(), |(_, r)| format!(",{r}"));
                lines[5] = format!("{t},NaN{rest}");
                lines.join("\n") + "\n"
            },
            "rejected_reading",
            "non-finite value `NaN`",
        ),
    ];
    for (k, (edit, kind, says)) in cases.into_iter().enumerate() {
        let log = dir.0.join(format!("log{k}"));
        write_log(&log, 5, SI, DRIVE_STEPS);
        let text = std::fs::read_to_string(log.join("beacon.csv")).unwrap();
        std::fs::write(log.join("beacon.csv"), edit(&text)).unwrap();
        let v = rover().check(&log, None, false).unwrap();
        let warnings = v["warnings"].as_array().unwrap();
        assert!(
            warnings
                .iter()
                .any(|w| w["kind"] == kind && w["message"].as_str().unwrap().contains(says)),
            "case {k}: {warnings:?}"
        );
    }
}

#[test]
fn a_missing_mapping_says_what_it_is_for() {
    let dir = TempDir::new("nomapping");
    // A log directory that is not there is said as such.
    let e = rover()
        .replay(&dir.0.join("absent"), None, &RunOptions::default(), None)
        .unwrap_err();
    assert!(
        matches!(e, ModelReplayError::Log(_)) && e.to_string().contains("absent"),
        "{e}"
    );
    let e = rover()
        .replay(&dir.0, None, &RunOptions::default(), None)
        .unwrap_err();
    assert!(matches!(e, ModelReplayError::Mapping { .. }));
    assert!(
        e.to_string().contains("which files feed model Rover"),
        "{e}"
    );
}

/// The committed log (`models/tests/fixtures/rover`, other units, shuffled
/// columns) through the library and the program, and its JSON.
#[test]
fn the_committed_rover_log_replays() {
    use std::process::ExitCode;
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/rover");
    let run = rover()
        .replay(&dir, None, &RunOptions::default(), None)
        .unwrap();
    assert_eq!(run.samples, 600);
    assert!(run.warnings.is_empty(), "{:?}", run.warnings);
    let value = nav_replay::model_replay::run_json("rover", "Rover", &run, false);
    let truth = run.truth.as_ref().unwrap();
    let horizontal = truth.rms[0].1.hypot(truth.rms[1].1);
    assert!(horizontal < 0.3, "horizontal RMS {horizontal} m");
    for key in [
        "samples",
        "sensors",
        "final",
        "state_error_rms",
        "nees_mean",
        "health",
        "warnings",
    ] {
        assert!(value.get(key).is_some(), "no `{key}` in {value}");
    }
    assert_eq!(value["sensors"]["Fix"]["rows"], 60);
    assert!(value["sensors"]["RangeBearing"]["nis_mean"].is_f64());
    assert!(value["state_error_rms"]["heading"].is_f64());
    assert_eq!(value["final"]["state"]["heading"], run.final_state[2].1);

    let d = dir.to_string_lossy().into_owned();
    let program =
        |args: &[&str]| rover().main_with(std::iter::once("rover").chain(args.iter().copied()));
    assert_eq!(program(&["check", &d, "--json"]), ExitCode::SUCCESS);
    assert_eq!(program(&["replay", &d, "--json"]), ExitCode::SUCCESS);
    assert_eq!(
        program(&["replay", &d, "--mapping", "/no/such/replay.toml"]),
        ExitCode::FAILURE
    );
    assert_eq!(program(&["replay", &d, "--every=-1"]), ExitCode::FAILURE);
    assert_eq!(program(&["replay"]), ExitCode::from(2), "a usage error");
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig { cases: 48, ..Default::default() })]
    /// A mapping or log with bytes overwritten anywhere replays or fails
    /// with an error; it never panics.
    #[test]
    fn corrupted_mappings_and_logs_never_panic(
        file in 0usize..4,
        edits in proptest::collection::vec((0.0f64..1.0, proptest::prelude::any::<u8>()), 1..6),
    ) {
        let dir = TempDir::new("corrupt");
        let log = dir.0.join("log");
        write_log(&log, 9, SI, 300);
        let name = ["replay.toml", "wheels.csv", "gnss.csv", "beacon.csv"][file];
        let path = log.join(name);
        let mut bytes = std::fs::read(&path).unwrap();
        for (at, b) in edits {
            let i = ((bytes.len() as f64) * at) as usize;
            if let Some(x) = bytes.get_mut(i) {
                *x = b;
            }
        }
        std::fs::write(&path, bytes).unwrap();
        for lenient in [false, true] {
            let options = RunOptions {
                lenient,
                ..RunOptions::default()
            };
            if let Ok(run) = rover().replay(&log, None, &options, None) {
                for (_, v, s) in &run.final_state {
                    proptest::prop_assert!(v.is_finite() && s.is_finite());
                }
            }
        }
    }
}

/// An input gap is an error; with lenient reading it is propagated in steps
/// and said.
#[test]
fn an_input_gap_is_refused_or_stepped_and_said() {
    let dir = TempDir::new("gap");
    let log = dir.0.join("log");
    write_log(&log, 6, SI, 600);
    let path = log.join("wheels.csv");
    // Rows 30.1 .. 39.9 s removed: a 10-s interval ending at 40 s.
    let kept: String = std::fs::read_to_string(&path)
        .unwrap()
        .lines()
        .filter(|l| {
            let t: f64 = l.split(',').next().unwrap().parse().unwrap_or(-1.0);
            !(30.05..39.95).contains(&t)
        })
        .map(|l| format!("{l}\n"))
        .collect();
    std::fs::write(&path, kept).unwrap();
    let e = rover()
        .replay(&log, None, &RunOptions::default(), None)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("wheels.csv:")
            && e.contains("gap of 10 s after t = 30 s")
            && e.contains("input periods of 0.1 s")
            && e.contains("--lenient"),
        "{e}"
    );
    let options = RunOptions {
        lenient: true,
        ..RunOptions::default()
    };
    let run = rover().replay(&log, None, &options, None).unwrap();
    assert!(
        run.warnings
            .iter()
            .any(|w| w.message.contains("1 input gap(s) propagated in steps")),
        "{:?}",
        run.warnings
    );
    let truth = run.truth.unwrap();
    assert!(truth.rms[0].1.hypot(truth.rms[1].1) < 0.5);
}

nav_runtime::model! {
    /// A discrete constant-velocity tracker with no inputs: the input file
    /// is only its clock.
    pub model Tracker {
        states { position, velocity }
        noise {
            /// Velocity change per step, m/s (a per-step variance).
            velocity_step,
        }
        discrete {
            position = position + velocity * dt;
            velocity = velocity + velocity_step;
        }
        /// A range to the target, m.
        sensor Range: 1 { h = [position]; }
    }
}

/// A discrete model without inputs replays from a clock file, consistently
/// over seeds (NIS and NEES means near their degrees of freedom).
#[test]
fn a_discrete_model_without_inputs_replays_from_a_clock() {
    use rand::SeedableRng;
    use rand_distr::{Distribution, Normal};
    use std::fmt::Write as _;
    let dir = TempDir::new("tracker");
    let (step_sigma, range_sigma) = (0.05, 2.0);
    let (mut nis, mut nees) = (Vec::new(), Vec::new());
    // The same runs smoothed: NEES and the position RMS over the forward's.
    let (mut smoothed_nees, mut ratio) = (Vec::new(), Vec::new());
    for seed in 0..10u64 {
        let log = dir.0.join(format!("seed{seed}"));
        std::fs::create_dir_all(&log).unwrap();
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        let n = Normal::new(0.0, 1.0).unwrap();
        let (mut x, mut v) = (100.0_f64, 3.0_f64);
        let (mut clock, mut ranges, mut truth) = (
            String::from("t\n"),
            String::from("t,range\n"),
            String::from("t,position,velocity\n"),
        );
        for k in 0..=1000 {
            let t = k as f64 * 0.5;
            if k > 0 {
                x += v * 0.5;
                v += step_sigma * n.sample(&mut rng);
            }
            writeln!(clock, "{t}").unwrap();
            writeln!(truth, "{t},{x},{v}").unwrap();
            if k % 4 == 0 && k > 0 {
                writeln!(ranges, "{t},{}", x + range_sigma * n.sample(&mut rng)).unwrap();
            }
        }
        std::fs::write(log.join("clock.csv"), clock).unwrap();
        std::fs::write(log.join("ranges.csv"), ranges).unwrap();
        std::fs::write(log.join("truth.csv"), truth).unwrap();
        std::fs::write(
            log.join("replay.toml"),
            format!(
                "[inputs]\nfile = \"clock.csv\"\n[noise]\nvelocity_step = {}\n\
                 [initial.state]\nposition = 100.0\nvelocity = 3.0\n\
                 [initial.sigma]\nposition = 1.0\nvelocity = 0.1\n\
                 [sensors.Range]\nfile = \"ranges.csv\"\nz = \"range\"\nsigma = {range_sigma}\n",
                step_sigma * step_sigma
            ),
        )
        .unwrap();
        let replay = ModelReplay::<Tracker, 2>::new("tracker").sensor::<TrackerRange, 1>();
        let run = replay
            .replay(&log, None, &RunOptions::default(), None)
            .unwrap_or_else(|e| panic!("seed {seed}: {e}"));
        assert_eq!((run.samples, run.sensors[0].rows), (1000, 250));
        assert!(run.warnings.is_empty(), "{:?}", run.warnings);
        nis.push(run.sensors[0].nis_mean.unwrap());
        let forward = run.truth.unwrap();
        nees.push(forward.nees_mean);
        let smoothing = RunOptions {
            smooth: true,
            ..RunOptions::default()
        };
        let smoothed = replay.replay(&log, None, &smoothing, None).unwrap();
        let s = smoothed.smoothed.unwrap().truth.unwrap();
        smoothed_nees.push(s.nees_mean);
        ratio.push(s.rms[0].1 / forward.rms[0].1);
    }
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    assert!((0.8..1.2).contains(&mean(&nis)), "NIS {nis:?}");
    assert!((1.5..2.6).contains(&mean(&nees)), "NEES {nees:?}");
    // A discrete model smooths as a continuous one does: consistent, and
    // closer to the truth than the filter between the ranges.
    assert!(
        (1.5..2.6).contains(&mean(&smoothed_nees)),
        "NEES {smoothed_nees:?}"
    );
    assert!(
        mean(&ratio) < 0.9,
        "position RMS smoothed / forward {ratio:?}"
    );
}

nav_runtime::model! {
    /// A heading with a gyro bias, aided by a compass.
    pub model Heading {
        states {
            /// Heading, rad.
            heading: angle,
            /// Gyro bias, rad/s.
            gyro_bias,
        }
        inputs {
            /// Gyro rate, rad/s.
            gyro,
        }
        noise { gyro_noise, bias_noise }
        continuous {
            d/dt heading = gyro - gyro_bias + gyro_noise;
            d/dt gyro_bias = bias_noise;
        }
        /// Compass, rad.
        sensor Compass: 1 {
            angles = [0];
            h = heading;
        }
    }
}

/// An update that carries an angle state across +-pi (the prior at 3.10
/// rad, the truth at -3.12) is a step of 0.06 rad, not of 2 pi - 0.06: the
/// recorded correction was once the wrapped state's difference, and the
/// smoothed heading stayed 1.3 rad off with a NEES near 10,000, without a
/// word. Smoothed, the run is as consistent as forward and closer.
#[test]
fn an_update_across_pi_is_smoothed_as_the_small_step_it_is() {
    use rand::SeedableRng;
    use rand_distr::{Distribution, Normal};
    use std::fmt::Write as _;
    assert_eq!(angle_states::<Heading, 2>(), [true, false]);
    let dir = TempDir::new("heading-across-pi");
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
    let n = Normal::new(0.0, 1.0).unwrap();
    let (bias, compass_sigma) = (0.01, 0.05);
    let (mut gyro, mut compass, mut truth) = (
        String::from("t,rate\n"),
        String::from("t,heading\n"),
        String::from("t,heading,gyro_bias\n"),
    );
    for k in 0..=1200 {
        let t = k as f64 * 0.1;
        writeln!(gyro, "{t},{}", bias + 0.003 * n.sample(&mut rng)).unwrap();
        writeln!(truth, "{t},-3.12,{bias}").unwrap();
        if k % 10 == 0 && k > 0 {
            let z = nav_runtime::math::wrap_angle(-3.12 + compass_sigma * n.sample(&mut rng));
            writeln!(compass, "{t},{z}").unwrap();
        }
    }
    std::fs::write(dir.0.join("gyro.csv"), gyro).unwrap();
    std::fs::write(dir.0.join("compass.csv"), compass).unwrap();
    std::fs::write(dir.0.join("truth.csv"), truth).unwrap();
    std::fs::write(
        dir.0.join("replay.toml"),
        "[inputs]\nfile = \"gyro.csv\"\n[inputs.columns]\ngyro = \"rate\"\n\
         [noise]\ngyro_noise = 1e-5\nbias_noise = 1e-9\n\
         [initial.state]\nheading = 3.10\ngyro_bias = 0.0\n\
         [initial.sigma]\nheading = 0.1\ngyro_bias = 0.02\n\
         [sensors.Compass]\nfile = \"compass.csv\"\nz = \"heading\"\nsigma = 0.05\n",
    )
    .unwrap();
    let replay = ModelReplay::<Heading, 2>::new("heading").sensor::<HeadingCompass, 1>();
    let options = RunOptions {
        smooth: true,
        ..RunOptions::default()
    };
    let run = replay.replay(&dir.0, None, &options, None).unwrap();
    let forward = run.truth.unwrap();
    let smoothed = run.smoothed.unwrap().truth.unwrap();
    let heading_rms = |rms: &[(&str, f64)]| rms.iter().find(|(k, _)| *k == "heading").unwrap().1;
    assert!(
        forward.nees_mean < 4.0,
        "forward NEES {}",
        forward.nees_mean
    );
    assert!(
        smoothed.nees_mean < 4.0,
        "smoothed NEES {} (forward {})",
        smoothed.nees_mean,
        forward.nees_mean
    );
    assert!(
        heading_rms(&smoothed.rms) < heading_rms(&forward.rms),
        "heading RMS smoothed {} forward {}",
        heading_rms(&smoothed.rms),
        heading_rms(&forward.rms)
    );
}

nav_runtime::model! {
    /// A spinning body: a unit quaternion driven by a gyro, an up sensor.
    pub model Spin {
        states { q: quaternion }
        inputs {
            /// Body rate, rad/s.
            rate: 3,
        }
        noise {
            /// Gyro white noise, (rad/s)^2/Hz.
            rate_noise: 3,
        }
        continuous {
            d/dt q = 0.5 * quat_mul(q, [0.0, rate[0] + rate_noise[0], rate[1] + rate_noise[1], rate[2] + rate_noise[2]]);
        }
        /// The vertical in body axes.
        sensor Up: 3 { h = transpose(quat_to_dcm(q)) * [0.0, 0.0, 1.0]; }
    }
}

/// `q` and `-q` are one attitude: a truth file with the other sign scores
/// as the same small error, not as an error of 2.
#[test]
fn a_quaternion_truth_of_the_other_sign_is_the_same_attitude() {
    use std::fmt::Write as _;
    assert_eq!(quaternion_blocks::<Spin, 4>(), vec![0..4]);
    assert!(quaternion_blocks::<Rover, 3>().is_empty());
    let dir = TempDir::new("spin");
    let w = 0.2; // rad/s about z
    let (mut imu, mut up, mut truth) = (
        String::from("t,wx,wy,wz\n"),
        String::from("t,ux,uy,uz\n"),
        String::from("t,q0,q1,q2,q3\n"),
    );
    for k in 0..=200 {
        let t = k as f64 * 0.1;
        let (s, c) = (0.5 * w * t).sin_cos();
        writeln!(imu, "{t},0,0,{w}").unwrap();
        writeln!(truth, "{t},{},0,0,{}", -c, -s).unwrap();
        if k % 10 == 0 {
            writeln!(up, "{t},0,0,1").unwrap();
        }
    }
    std::fs::write(dir.0.join("imu.csv"), imu).unwrap();
    std::fs::write(dir.0.join("up.csv"), up).unwrap();
    std::fs::write(dir.0.join("truth.csv"), truth).unwrap();
    std::fs::write(
        dir.0.join("replay.toml"),
        "[inputs]\nfile = \"imu.csv\"\n[inputs.columns]\nrate = [\"wx\", \"wy\", \"wz\"]\n\
         [noise]\nrate_noise = 1e-8\n[initial.state]\nq = [1.0, 0.0, 0.0, 0.0]\n\
         [initial.sigma]\nq = 0.01\n[sensors.Up]\nfile = \"up.csv\"\nz = [\"ux\", \"uy\", \"uz\"]\nsigma = 0.01\n\
         [truth.columns]\nq = [\"q0\", \"q1\", \"q2\", \"q3\"]\n",
    )
    .unwrap();
    let run = ModelReplay::<Spin, 4>::new("spin")
        .sensor::<SpinUp, 3>()
        .replay(&dir.0, None, &RunOptions::default(), None)
        .unwrap();
    let truth = run.truth.unwrap();
    assert_eq!(truth.scored, 201);
    for (name, rms) in &truth.rms {
        assert!(
            *rms < 1e-3,
            "{name}: RMS {rms} (the sign of the truth counted as an error?)"
        );
    }
}

/// One non-physical reading in a sensor file of a model replay (a glitch) is
/// a rejected row with a `rejected_reading` warning naming the file and
/// line, not a broken log and not a value handed to the filter; the replay
/// runs on. One row per file and value.
#[test]
fn a_glitch_in_a_mapped_sensor_file_is_a_rejected_row() {
    let dir = TempDir::new("glitch");
    // (file, column, value)
    let cases: &[(&str, usize, &str)] = &[
        ("gnss.csv", 1, "1e300"),
        ("gnss.csv", 2, "-1e300"),
        ("gnss.csv", 1, "NaN"),
        ("beacon.csv", 1, "inf"),
        ("beacon.csv", 2, "1e300"),
        ("landmarks.csv", 3, "1e300"),
    ];
    let mut failures = Vec::new();
    for (k, &(file, column, value)) in cases.iter().enumerate() {
        let log = dir.0.join(format!("glitch-{k}"));
        write_log(&log, 4, SI, DRIVE_STEPS);
        let path = log.join(file);
        let text = std::fs::read_to_string(&path).unwrap();
        let mut lines: Vec<String> = text.lines().map(String::from).collect();
        // Line 6 of the file (data row 5).
        let mut cells: Vec<String> = lines[5].split(',').map(String::from).collect();
        cells[column] = value.to_string();
        lines[5] = cells.join(",");
        std::fs::write(&path, lines.join("\n") + "\n").unwrap();
        match rover().replay(&log, None, &RunOptions::default(), None) {
            Ok(run) => {
                let hit = run.warnings.iter().any(|w| {
                    w.kind == nav_runtime::log::WarningKind::RejectedReading
                        && w.file.as_deref() == Some(file)
                        && w.line == Some(6)
                });
                if !hit {
                    failures.push(format!("{file} {value}: no warning in {:?}", run.warnings));
                }
            }
            Err(e) => failures.push(format!("{file} {value}: refused: {e}")),
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    // Every fix non-physical: a unit or column mistake, not glitches.
    let log = dir.0.join("all-rejected");
    write_log(&log, 4, SI, DRIVE_STEPS);
    edit_rows(&log.join("gnss.csv"), |_, c| c[1] = 1e300);
    let e = rover()
        .replay(&log, None, &RunOptions::default(), None)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("gnss.csv") && e.contains("rejected as non-physical"),
        "{e}"
    );
}

/// `tune` of a declared model (docs/tuning.md): the rover's sensor sigmas in
/// its `replay.toml` started ten times too large or too small come back
/// within 25 % of the ones the log was drawn with, through the library call
/// and through the program's `tune --write`, whose mapping then reads back
/// with the tuned values (a two-output sigma scaled as one).
#[test]
fn a_declared_models_sigmas_are_tuned_from_its_log() {
    use nav_replay::model_replay::MappingTuning;
    use nav_replay::tune::{tune, with_values, TuneOptions};
    let dir = TempDir::new("tune");
    let log = dir.0.join("log");
    write_log(&log, 41, SI, DRIVE_STEPS);
    let (name, truth) = rover().mapping(&log, None).unwrap();
    let given = |k: usize| truth.sensors[k].as_ref().unwrap().sigma.clone();
    // (key, sensor index, factor on its sigmas)
    let off = [
        ("sensors.Fix.sigma", 0, 10.0),
        ("sensors.RangeBearing.sigma", 1, 0.1),
        ("sensors.LandmarkRange.sigma", 2, 10.0),
    ];
    let mut start = truth.clone();
    for (_, k, f) in off {
        if let Some(s) = start.sensors[k].as_mut() {
            s.sigma.iter_mut().for_each(|v| *v *= f);
        }
    }
    let replay = rover();
    let tunable = MappingTuning::new(&replay, &log, name, start.clone(), RunOptions::default());
    let t = tune(&tunable, &TuneOptions::default(), &|_, _| {}).unwrap();
    assert!(t.replays <= 30, "{}", t.replays);
    for (key, k, _) in off {
        let p = t.parameters.iter().find(|p| p.key == key).unwrap();
        assert!(p.not_identifiable.is_none(), "{p:?}");
        let ratio = p.value / given(k)[0];
        assert!((ratio - 1.0).abs() < 0.25, "{key}: {ratio}");
    }

    // The program: the same from a replay.toml with the wrong sigmas.
    let text = std::fs::read_to_string(log.join("replay.toml")).unwrap();
    let wrong: Vec<(String, String)> = off
        .iter()
        .map(|(key, k, f)| {
            let s: Vec<String> = given(*k).iter().map(|v| format!("{:?}", v * f)).collect();
            let value = if s.len() == 1 {
                s[0].clone()
            } else {
                format!("[{}]", s.join(", "))
            };
            (key.to_string(), value)
        })
        .collect();
    std::fs::write(
        log.join("replay.toml"),
        with_values(&text, "replay.toml", &wrong).unwrap(),
    )
    .unwrap();
    let out = dir.0.join("tuned.toml");
    let code = rover().main_with([
        "rover",
        "tune",
        log.to_str().unwrap(),
        "--json",
        "--write",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, std::process::ExitCode::SUCCESS);
    let (_, tuned) = rover().mapping(&log, Some(&out)).unwrap();
    for (key, k, _) in off {
        let (a, b) = (&tuned.sensors[k].as_ref().unwrap().sigma, given(k));
        for (x, y) in a.iter().zip(&b) {
            assert!((x / y - 1.0).abs() < 0.25, "{key}: {a:?} against {b:?}");
        }
    }
}

/// `--observability` of a declared model: the same estimate as without it,
/// every state learned on the drive, and what each sensor taught (the
/// position fixes the position, and the heading through the motion between
/// them).
#[test]
fn the_observability_report_of_a_declared_model() {
    let dir = TempDir::new("observability");
    let log = dir.0.join("log");
    write_log(&log, 3, SI, DRIVE_STEPS);
    let plain = rover()
        .replay(&log, None, &RunOptions::default(), None)
        .unwrap();
    let options = RunOptions {
        observability: true,
        ..RunOptions::default()
    };
    let run = rover().replay(&log, None, &options, None).unwrap();
    assert_eq!(run.final_state, plain.final_state);
    assert!(plain.observability.is_none());
    let o = run.observability.expect("the report");
    let states = &o["states"];
    for state in ["position[0]", "position[1]", "heading"] {
        assert!(
            states[state]["learned"].as_f64().unwrap() > 0.9,
            "{state}: {o}"
        );
    }
    let by = |state: &str, sensor: &str| states[state]["by_sensor"][sensor].as_f64().unwrap();
    assert!(by("position[0]", "Fix") > 0.9, "{o}");
    assert_eq!(o["weakest"].as_array().unwrap().len(), 3);
}

/// The same rover log with `--smooth` (seed 3): the forward run is
/// unchanged (its estimates and final state to the bit), every forward
/// estimate written or scored has a smoothed counterpart at its time, the smoothed errors
/// are smaller than the forward ones for every state and still covered by
/// their sigmas, and `--out` holds `smoothed.csv` (the rows of
/// `estimates.csv`, `--every` included) and a plot per state.
#[test]
fn a_declared_model_is_smoothed() {
    let dir = TempDir::new("smooth");
    let log = dir.0.join("log");
    write_log(&log, 3, SI, DRIVE_STEPS);
    let out = |name: &str| {
        let out = dir.0.join(name);
        std::fs::create_dir_all(&out).unwrap();
        out
    };
    let options = RunOptions {
        output_period: 0.5,
        ..RunOptions::default()
    };
    let (plain_out, smooth_out) = (out("plain"), out("smoothed"));
    let plain = rover()
        .replay(&log, None, &options, Some(&plain_out))
        .unwrap();
    let smoothing = RunOptions {
        smooth: true,
        ..options
    };
    let run = rover()
        .replay(&log, None, &smoothing, Some(&smooth_out))
        .unwrap();
    assert!(plain.smoothed.is_none());
    assert_eq!(run.final_state, plain.final_state);
    assert_eq!(run.truth, plain.truth);
    let read = |path: &Path| std::fs::read_to_string(path).unwrap();
    let forward = read(&smooth_out.join("estimates.csv"));
    assert_eq!(forward, read(&plain_out.join("estimates.csv")));
    let smoothed_text = read(&smooth_out.join("smoothed.csv"));
    let rows = |text: &str| -> Vec<Vec<f64>> {
        text.lines()
            .skip(1)
            .map(|l| l.split(',').map(|c| c.parse().unwrap()).collect())
            .collect()
    };
    let (f, s) = (rows(&forward), rows(&smoothed_text));
    assert_eq!(f.len(), 401, "t = 0, 0.5, ..., 200 s");
    assert_eq!(
        f.iter().map(|r| r[0]).collect::<Vec<_>>(),
        s.iter().map(|r| r[0]).collect::<Vec<_>>()
    );
    assert_eq!(forward.lines().next(), smoothed_text.lines().next());
    // The last epoch has nothing after it: smoothed = forward.
    let (fl, sl) = (f.last().unwrap(), s.last().unwrap());
    for (a, b) in fl.iter().zip(sl) {
        assert!((a - b).abs() <= 1e-9 * a.abs().max(1.0), "{fl:?} {sl:?}");
    }
    // Earlier, the smoother knows more: no sigma grows, and before the
    // end every position sigma shrinks.
    for (f, s) in f.iter().zip(&s) {
        assert!((4..7).all(|i| s[i] <= f[i] * (1.0 + 1e-9)), "{f:?} {s:?}");
        assert!(f[0] == 200.0 || (s[4] < f[4] && s[5] < f[5]), "{f:?} {s:?}");
    }

    let smoothed = run.smoothed.as_ref().expect("smoothed");
    assert_eq!(
        smoothed.estimates, 2001,
        "one per input sample and the start"
    );
    let (ft, st) = (
        plain.truth.as_ref().unwrap(),
        smoothed.truth.as_ref().unwrap(),
    );
    assert_eq!(st.scored, ft.scored);
    for ((name, forward), (_, smooth)) in ft.rms.iter().zip(&st.rms) {
        assert!(
            smooth < forward,
            "{name}: smoothed {smooth} forward {forward}"
        );
    }
    assert!(
        (1.0..6.0).contains(&st.nees_mean),
        "smoothed NEES {}",
        st.nees_mean
    );
    assert!(run.warnings.is_empty(), "{:?}", run.warnings);
    for name in ["heading", "position[0]", "position[1]"] {
        let plot = read(&smooth_out.join(nav_replay::model_replay::plot_file_name(name)));
        assert!(plot.contains("<svg") && plot.contains("smoothed"), "{name}");
        let plain_plot = read(&plain_out.join(nav_replay::model_replay::plot_file_name(name)));
        assert!(!plain_plot.contains("smoothed"), "{name}");
    }

    // Only the estimates written or scored are epochs: truth once a second
    // and an output every 2 s give the 201 whole seconds, of which the 101
    // even ones are written.
    edit_rows_keeping(&log.join("truth.csv"), |row| {
        (row[0] * 10.0).round() % 10.0 == 0.0
    });
    let sparse_out = out("sparse");
    let options = RunOptions {
        output_period: 2.0,
        smooth: true,
        ..RunOptions::default()
    };
    let run = rover()
        .replay(&log, None, &options, Some(&sparse_out))
        .unwrap();
    let smoothed = run.smoothed.as_ref().unwrap();
    assert_eq!(smoothed.estimates, 201);
    assert_eq!(smoothed.truth.as_ref().unwrap().scored, 201);
    assert_eq!(run.truth.as_ref().unwrap().scored, 201);
    let s = rows(&read(&sparse_out.join("smoothed.csv")));
    assert_eq!(s.len(), 101);
    assert!(s.iter().all(|r| r[0] % 2.0 == 0.0), "{:?}", &s[..3]);
}

/// Keeps the data rows of `path` for which `keep` holds (the header always).
fn edit_rows_keeping(path: &Path, keep: impl Fn(&[f64]) -> bool) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let mut out = format!("{}\n", lines.next().unwrap());
    for line in lines {
        let values: Vec<f64> = line.split(',').map(|c| c.parse().unwrap()).collect();
        if keep(&values) {
            out.push_str(line);
            out.push('\n');
        }
    }
    std::fs::write(path, out).unwrap();
}

/// Monte Carlo of the smoothed rover (seeds 7100-7199, not used while
/// building it): the smoothed horizontal RMS error against the forward
/// one of the same run (median ratio below 0.9), and the smoothed NEES
/// (3 states) within the band its time-correlated epochs allow, as the
/// forward one is (`docs/model-replay.md`, "Smoothing"). Ignored: run by
/// hand, in release.
#[test]
#[ignore = "Monte Carlo, 100 runs: cargo test --release -p models --test scenarios model_replay:: -- --ignored smoothing_monte_carlo"]
fn smoothing_monte_carlo() {
    use nav_runtime::simulation::stats::{median, percentile};
    let dir = TempDir::new("smooth-mc");
    let options = RunOptions {
        smooth: true,
        ..RunOptions::default()
    };
    let (mut ratios, mut forward_nees, mut smoothed_nees) = (Vec::new(), Vec::new(), Vec::new());
    let (mut forward_rms, mut smoothed_rms) = (Vec::new(), Vec::new());
    for seed in 7100..7200u64 {
        let log = dir.0.join(format!("seed{seed}"));
        write_log(&log, seed, SI, DRIVE_STEPS);
        let run = rover().replay(&log, None, &options, None).unwrap();
        let horizontal = |t: &nav_replay::model_replay::TruthScore| t.rms[0].1.hypot(t.rms[1].1);
        let f = run.truth.as_ref().unwrap();
        let s = run.smoothed.as_ref().unwrap().truth.as_ref().unwrap();
        forward_rms.push(horizontal(f));
        smoothed_rms.push(horizontal(s));
        ratios.push(horizontal(s) / horizontal(f));
        forward_nees.push(f.nees_mean);
        smoothed_nees.push(s.nees_mean);
        std::fs::remove_dir_all(&log).unwrap();
    }
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    eprintln!(
        "horizontal RMS median forward {:.4} m, smoothed {:.4} m; ratio median {:.3}, p95 {:.3}, max {:.3}; \
         NEES mean forward {:.3}, smoothed {:.3}",
        median(&forward_rms),
        median(&smoothed_rms),
        median(&ratios),
        percentile(&ratios, 95.0),
        ratios.iter().copied().fold(0.0, f64::max),
        mean(&forward_nees),
        mean(&smoothed_nees)
    );
    // Not every run: a smoother's error is smaller in expectation, and
    // one realization can be a little worse (measured: 1 of 100).
    assert!(median(&ratios) < 0.9, "median ratio {}", median(&ratios));
    // 100 runs x 2001 correlated epochs of 3 states: the forward filter's
    // mean NEES is 3; the smoothed one is held to the same band.
    for (name, nees) in [("forward", &forward_nees), ("smoothed", &smoothed_nees)] {
        assert!(
            (2.5..3.5).contains(&mean(nees)),
            "{name} NEES {}",
            mean(nees)
        );
    }
}

/// A mapped file's clock: the beacon's file written with its clock 0.75 s
/// ahead (a shift exact in binary, so the times come back to the bit).
/// Declared (`time = { offset_s = -0.75 }`) the replay is that of the
/// true clock; not declared, `tune --params` with the sensor's clock finds
/// it from the innovations and `--write` puts it into the mapping.
#[test]
fn a_mapped_files_clock_is_declared_or_found() {
    use nav_replay::model_replay::MappingTuning;
    use nav_replay::tune::{tune, TuneOptions};
    let dir = TempDir::new("clock");
    let (truth_log, log) = (dir.0.join("truth"), dir.0.join("ahead"));
    write_log(&truth_log, 43, SI, DRIVE_STEPS);
    write_log(&log, 43, SI, DRIVE_STEPS);
    edit_rows(&log.join("beacon.csv"), |_, row| row[0] += 0.75);
    let replay = |dir: &Path| {
        rover()
            .replay(dir, None, &RunOptions::default(), None)
            .unwrap()
    };
    let (right, ahead) = (replay(&truth_log), replay(&log));
    let rb = |r: &ModelRun| r.sensors[1].nis_mean.unwrap();
    // The offset shows in the innovations (the precondition of a search).
    assert!(
        rb(&ahead) > 1.5 * rb(&right),
        "{} against {}",
        rb(&ahead),
        rb(&right)
    );

    let mapping = std::fs::read_to_string(log.join("replay.toml")).unwrap();
    let declared = mapping.replace(
        "file = \"beacon.csv\"",
        "file = \"beacon.csv\"\ntime = { offset_s = -0.75 }",
    );
    assert_ne!(declared, mapping);
    std::fs::write(log.join("declared.toml"), &declared).unwrap();
    let run = rover()
        .replay(
            &log,
            Some(&log.join("declared.toml")),
            &RunOptions::default(),
            None,
        )
        .unwrap();
    assert_eq!(run.final_state, right.final_state);
    assert_eq!(run.truth, right.truth);
    assert_eq!(run.sensors[1].accepted, right.sensors[1].accepted);

    // Found from the innovations, from a zero offset.
    let (name, given) = rover().mapping(&log, None).unwrap();
    let replay = rover();
    let tunable = MappingTuning::new(&replay, &log, name, given, RunOptions::default());
    let options = TuneOptions {
        params: vec![
            "sensors.RangeBearing.sigma".into(),
            "sensors.RangeBearing.time.offset_s".into(),
        ],
        ..TuneOptions::default()
    };
    let t = tune(&tunable, &options, &|_, _| {}).unwrap();
    let clock = t
        .parameters
        .iter()
        .find(|p| p.key == "sensors.RangeBearing.time.offset_s")
        .unwrap();
    assert!(clock.not_identifiable.is_none(), "{clock:?}");
    assert!((clock.value + 0.75).abs() < 0.05, "{clock:?}");

    // The program writes it into the section (which had no `time`).
    let out = dir.0.join("tuned.toml");
    let code = rover().main_with([
        "rover",
        "tune",
        log.to_str().unwrap(),
        "--params",
        "sensors.RangeBearing.sigma,sensors.RangeBearing.time.offset_s",
        "--write",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, std::process::ExitCode::SUCCESS);
    let (_, tuned) = rover().mapping(&log, Some(&out)).unwrap();
    let offset = tuned.sensors[1].as_ref().unwrap().source.time_offset_s;
    assert!((offset + 0.75).abs() < 0.05, "{offset}");
    assert_eq!(tuned.sensors[0].as_ref().unwrap().source.time_offset_s, 0.0);
}

/// The checks of the rows as they stream past: an input column that never
/// changes and a sensor silent for 50 s are warnings naming the key, the
/// file and (for the silence) the line after it; the replay still runs.
#[test]
fn a_constant_column_and_a_silent_sensor_are_warned() {
    let dir = TempDir::new("row-checks");
    let log = dir.0.join("log");
    write_log(&log, 5, SI, DRIVE_STEPS);
    // wheels.csv: t, speed, yaw_rate; the speed column held at 1.5 m/s.
    edit_rows(&log.join("wheels.csv"), |_, row| row[1] = 1.5);
    // gnss.csv: one fix a second; none from t = 50 s to t = 100 s.
    let text = std::fs::read_to_string(log.join("gnss.csv")).unwrap();
    let kept: Vec<&str> = text
        .lines()
        .filter(|l| {
            l.split(',')
                .next()
                .and_then(|t| t.parse::<f64>().ok())
                .is_none_or(|t| !(50.0..100.0).contains(&t))
        })
        .collect();
    std::fs::write(log.join("gnss.csv"), kept.join("\n") + "\n").unwrap();
    let run = rover()
        .replay(&log, None, &RunOptions::default(), None)
        .unwrap();
    let constant: Vec<_> = run
        .warnings
        .iter()
        .filter(|w| w.message.contains("never"))
        .collect();
    assert_eq!(constant.len(), 1, "{:?}", run.warnings);
    assert_eq!(constant[0].key.as_deref(), Some("inputs.columns.speed"));
    assert_eq!(constant[0].file.as_deref(), Some("wheels.csv"));
    let silent: Vec<_> = run
        .warnings
        .iter()
        .filter(|w| w.message.contains("silent"))
        .collect();
    assert_eq!(silent.len(), 1, "{:?}", run.warnings);
    assert_eq!(silent[0].file.as_deref(), Some("gnss.csv"));
    assert!(
        silent[0].message.contains("before t = 100.5 s"),
        "{}",
        silent[0].message
    );
    let line = kept.iter().position(|l| l.starts_with("100.5,")).unwrap() as u64 + 1;
    assert_eq!(silent[0].line, Some(line));
    let json = nav_replay::model_replay::run_json("rover", "Rover", &run, false);
    let kinds: Vec<&str> = json["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|w| w["kind"].as_str())
        .collect();
    assert!(
        kinds.iter().filter(|k| **k == "suspicious").count() >= 2,
        "{json}"
    );
}
