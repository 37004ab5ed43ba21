//! The streamed `ahrs` replay on the committed PX4 fixture
//! (`tests/data/ulog/sample_px4_events.ulg`, imported here): the same
//! result from the files as from the log in memory, the figures of the
//! loop over a whole log in memory it replaces, and broken copies of the
//! log refused or warned about, never a panic.

use std::path::{Path, PathBuf};

use nav_runtime::log::{LogDir, LogFiles, Strictness};
use serde_json::Value;

use super::*;
use crate::harness::TempDir;

/// The fixture imported into `tmp`.
fn flight(tmp: &TempDir) -> PathBuf {
    let ulg = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/ulog/sample_px4_events.ulg");
    let dir = tmp.0.join("flight");
    nav_import::ulog::import(&ulg, &dir).expect("the fixture imports");
    dir
}

fn streamed(dir: &Path, strictness: Strictness) -> Result<ReplayOutput, RunError> {
    let files = LogFiles::open(dir, strictness)?;
    AhrsReplay.replay_files(&files, &ReplayOptions::default(), None)
}

fn num(v: &serde_json::Map<String, Value>, path: &[&str]) -> f64 {
    let mut x = &v[path[0]];
    for k in &path[1..] {
        x = &x[*k];
    }
    x.as_f64().unwrap_or_else(|| panic!("{path:?} in {v:?}"))
}

/// Rewrites `file` of `dir` line by line.
fn edit(dir: &Path, file: &str, f: impl Fn(usize, &str) -> Option<String>) {
    let path = dir.join(file);
    let text = std::fs::read_to_string(&path).unwrap();
    let lines: Vec<String> = text
        .lines()
        .enumerate()
        .filter_map(|(i, l)| f(i, l))
        .collect();
    std::fs::write(&path, lines.join("\n") + "\n").unwrap();
}

/// The figures of the loop over the whole log in memory that the streamed
/// replay replaced, on this fixture. The magnetometer rows are now applied
/// at their own times inside the IMU interval (before, at the sample before
/// them), which moves the yaw by a few 1e-4 deg and roll and pitch by about
/// 1e-6 deg; every count is unchanged.
const PREVIOUS_DIFFERENCE_DEG: [f64; 3] =
    [0.05959170528131505, 0.06650047338870645, 0.3330727138854449];
const LEVEL_TOLERANCE_DEG: f64 = 1e-5;
const YAW_TOLERANCE_DEG: f64 = 2e-3;

#[test]
fn the_streamed_replay_keeps_the_figures_of_the_whole_log_replay() {
    let tmp = TempDir::new("figures");
    let dir = flight(&tmp);
    let files = streamed(&dir, Strictness::Strict).expect("replays");
    let log = LogDir::read(&dir, Strictness::Strict).expect("reads");
    let options = ReplayOptions {
        keep_series: true,
        ..ReplayOptions::default()
    };
    let memory = AhrsReplay.replay(&log, &options).expect("replays");
    // From the files and from memory: the same rows, the same result.
    assert_eq!(files.metrics, memory.metrics);
    assert_eq!(files.samples, memory.samples);
    assert_eq!(files.warnings, memory.warnings);
    let m = &files.metrics;
    for (k, axis) in ["roll", "pitch", "yaw"].iter().enumerate() {
        let d = num(m, &["attitude_difference_rms_deg", axis]);
        let tolerance = if k == 2 {
            YAW_TOLERANCE_DEG
        } else {
            LEVEL_TOLERANCE_DEG
        };
        assert!(
            (d - PREVIOUS_DIFFERENCE_DEG[k]).abs() < tolerance,
            "{axis}: {d} deg, was {}",
            PREVIOUS_DIFFERENCE_DEG[k]
        );
    }
    let health = &m["health"];
    for (sensor, counts) in [("gravity", [213, 189, 24]), ("mag", [459, 315, 144])] {
        let h = &health[sensor];
        let got = ["rows", "accepted", "skipped"].map(|k| h[k].as_u64().unwrap());
        assert_eq!(got, counts, "{sensor}: {h}");
        assert_eq!(h["rejected"], 0, "{sensor}: {h}");
    }
    assert_eq!(health["imu_gaps"], 0);
    assert_eq!(files.samples, 5349);
    assert_eq!(num(m, &["reference_samples"]), 428.0);
    assert!((num(m, &["replayed_seconds"]) - 21.396).abs() < 1e-9);
    assert!((num(m, &["magnetic_declination_deg"]) - 3.4753151997696037).abs() < 1e-12);
    // The series of the log in memory: every row.
    let names: Vec<&str> = memory.tables.iter().map(|t| t.name.as_str()).collect();
    assert_eq!(names, ["estimates", "reference_difference"]);
    assert_eq!(memory.tables[1].rows.len(), 428);
    assert_eq!(memory.tables[0].rows.len(), 213);
    assert!(files.tables.is_empty(), "no series asked for");
}

#[test]
fn written_series_are_every_row_and_the_plots() {
    let tmp = TempDir::new("out");
    let dir = flight(&tmp);
    let out = tmp.0.join("out");
    std::fs::create_dir_all(&out).unwrap();
    let files = LogFiles::open(&dir, Strictness::Strict).unwrap();
    let options = ReplayOptions {
        keep_series: true,
        ..ReplayOptions::default()
    };
    AhrsReplay
        .replay_files(&files, &options, Some(&out))
        .expect("replays");
    let lines = |f: &str| {
        std::fs::read_to_string(out.join(f))
            .unwrap()
            .lines()
            .count()
    };
    assert_eq!(lines("reference_difference.csv"), 429);
    assert_eq!(lines("estimates.csv"), 214);
    assert!(out.join("attitude_difference.svg").is_file());
}

/// `--smooth`: the forward keys and rows are unchanged, the rows of the
/// estimates table come back smoothed (same times, no larger sigma, most
/// of them tighter) with their difference to PX4's estimate, and are
/// written under `--out` as they are kept in memory. (The last row is not
/// the forward one here: samples and magnetometer rows follow the last
/// gravity window.)
#[test]
fn smoothing_adds_the_smoothed_rows_and_their_differences() {
    let tmp = TempDir::new("smooth");
    let dir = flight(&tmp);
    let files = LogFiles::open(&dir, Strictness::Strict).unwrap();
    let keep = ReplayOptions {
        keep_series: true,
        ..ReplayOptions::default()
    };
    let smooth = ReplayOptions {
        smooth: true,
        ..keep
    };
    let forward = AhrsReplay
        .replay_files(&files, &keep, None)
        .expect("replays");
    let both = AhrsReplay
        .replay_files(&files, &smooth, None)
        .expect("replays");
    let mut without = both.metrics.clone();
    let smoothed = without.remove("smoothed").expect("smoothed");
    assert_eq!(without, forward.metrics);
    let table = |out: &ReplayOutput, name: &str| {
        let t = out.tables.iter().find(|t| t.name == name);
        t.unwrap_or_else(|| panic!("{name}")).clone()
    };
    let estimates = table(&forward, ESTIMATES_TABLE);
    assert_eq!(table(&both, ESTIMATES_TABLE).rows, estimates.rows);
    let rows = table(&both, SMOOTHED_TABLE);
    assert_eq!(rows.rows.len(), estimates.rows.len());
    assert_eq!(smoothed["estimates"].as_u64(), Some(rows.rows.len() as u64));
    let mut tighter = 0;
    for (f, s) in estimates.rows.iter().zip(&rows.rows) {
        assert_eq!(f[0], s[0]);
        for k in 7..10 {
            assert!(
                s[k] <= f[k] * (1.0 + 1e-9),
                "{} at t = {}",
                ESTIMATES_COLUMNS[k],
                f[0]
            );
        }
        tighter += usize::from(s[9] < 0.99 * f[9]);
    }
    assert!(
        tighter > rows.rows.len() / 2,
        "{tighter} rows tighter in yaw"
    );
    for axis in ["roll", "pitch", "yaw"] {
        let v = smoothed["attitude_difference_rms_deg"][axis].as_f64();
        assert!(
            v.is_some_and(|v| v.is_finite() && v < 1.0),
            "{axis}: {smoothed}"
        );
    }

    let out = tmp.0.join("out");
    std::fs::create_dir_all(&out).unwrap();
    let written = AhrsReplay
        .replay_files(&files, &smooth, Some(&out))
        .expect("replays");
    assert_eq!(written.metrics, both.metrics);
    for name in [SMOOTHED_TABLE, "smoothed_reference_difference"] {
        let text = std::fs::read_to_string(out.join(format!("{name}.csv"))).unwrap();
        let whole = tmp.0.join("whole.csv");
        table(&both, name).write_csv(&whole).expect("writes");
        assert!(text == std::fs::read_to_string(&whole).unwrap(), "{name}");
    }
}

#[test]
fn broken_logs_are_refused_or_warned_about() {
    let tmp = TempDir::new("broken");
    let dir = flight(&tmp);
    let copy = |name: &str| {
        let to = tmp.0.join(name);
        std::fs::create_dir_all(&to).unwrap();
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            std::fs::copy(&path, to.join(path.file_name().unwrap())).unwrap();
        }
        to
    };
    // A row cut short (a log copied while written).
    let cut = copy("cut");
    let text = std::fs::read_to_string(cut.join("imu.csv")).unwrap();
    std::fs::write(cut.join("imu.csv"), &text[..text.len() - 20]).unwrap();
    let e = streamed(&cut, Strictness::Strict)
        .expect_err("strict")
        .to_string();
    assert!(e.contains("imu.csv"), "{e}");
    streamed(&cut, Strictness::Lenient).expect("lenient skips the row");
    // A NaN in mag.csv.
    let nan = copy("nan");
    edit(&nan, "mag.csv", |i, l| {
        let t = l.split(',').next().unwrap_or_default();
        Some(if i == 200 {
            format!("{t},NaN,0.0,0.4")
        } else {
            l.into()
        })
    });
    let e = streamed(&nan, Strictness::Strict)
        .expect_err("strict")
        .to_string();
    assert!(e.contains("mag.csv:201"), "{e}");
    // One second without IMU rows: a gap, counted and not propagated.
    let gap = copy("gap");
    edit(&gap, "imu.csv", |i, l| {
        (!(1000..1250).contains(&i)).then(|| l.into())
    });
    let out = streamed(&gap, Strictness::Strict).expect("a gap is not an error");
    assert_eq!(out.metrics["health"]["imu_gaps"], 1);
    // No magnetometer: said.
    let no_mag = copy("no-mag");
    std::fs::remove_file(no_mag.join("mag.csv")).unwrap();
    let out = streamed(&no_mag, Strictness::Strict).expect("gyro only");
    assert!(
        out.warnings
            .iter()
            .any(|w| w.message.contains("no mag.csv")),
        "{:?}",
        out.warnings
    );
    // No IMU rows at all.
    let empty = copy("empty");
    edit(&empty, "imu.csv", |i, l| (i == 0).then(|| l.into()));
    let e = streamed(&empty, Strictness::Strict)
        .expect_err("nothing")
        .to_string();
    assert!(e.contains("imu.csv"), "{e}");
}
