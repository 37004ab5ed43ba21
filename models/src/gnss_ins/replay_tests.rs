//! The streamed `gnss-ins` replay on the committed PX4 fixture
//! (`tests/data/ulog/sample_px4_events.ulg`, imported here, with PX4's
//! estimate copied into `truth.csv` so that every score is exercised): the
//! same result from the files as from the log in memory and as the scores
//! of the whole series it replaces, every row written under `--out`, and
//! broken copies of the log refused or warned about, never a panic.

use std::path::{Path, PathBuf};

use nav_runtime::log::{LogDir, LogFiles, Strictness, Warning, WarningKind};
use serde_json::{Map, Value};

use super::*;
use crate::harness::RunTable;
use crate::harness::TempDir;
use crate::sdins25::score;
use crate::ulog::replay::{attitude_errors, reference_metrics, rpy_json};

/// The streamed scores sum the same terms in the same order as the
/// whole-series functions; they are expected to agree to the last bit, and
/// are held to this relative tolerance.
const SAME_SUMS_TOLERANCE: f64 = 1e-12;

/// The fixture imported into `tmp`, with `reference.csv` copied as
/// `truth.csv` (height turned into depth).
fn flight(tmp: &TempDir) -> PathBuf {
    let ulg = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/ulog/sample_px4_events.ulg");
    let dir = tmp.0.join("flight");
    nav_import::ulog::import(&ulg, &dir).expect("the fixture imports");
    crate::ulog::reference::write_reference_as_truth(&dir).expect("truth.csv written");
    dir
}

/// A copy of `dir` named `name` beside it.
fn copy(dir: &Path, name: &str) -> PathBuf {
    let to = dir.with_file_name(name);
    std::fs::create_dir_all(&to).unwrap();
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        std::fs::copy(&path, to.join(path.file_name().unwrap())).unwrap();
    }
    to
}

/// Rewrites `file` of `dir` line by line (`None` drops the line).
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

fn streamed(dir: &Path, strictness: Strictness) -> Result<ReplayOutput, RunError> {
    streamed_with(dir, strictness, &ReplayOptions::default())
}

fn streamed_with(
    dir: &Path,
    strictness: Strictness,
    options: &ReplayOptions,
) -> Result<ReplayOutput, RunError> {
    let files = LogFiles::open(dir, strictness)?;
    GnssInsReplay.replay_files(&files, options, None)
}

/// The scores of the whole series, as the replay computed them before it
/// streamed: every estimate at the IMU samples and at the truth rows kept,
/// then compared with the files read whole. Returns the score keys, the
/// scoring warnings and the tables (truth errors, attitude errors,
/// reference differences).
fn whole_series(log: &LogDir) -> (Map<String, Value>, Vec<Warning>, Vec<RunTable>) {
    enum At {
        Sample,
        Truth(usize),
    }
    let truth = log.truth.as_deref().unwrap_or_default();
    let mut points = Vec::new();
    let mut at_truth = vec![None; truth.len()];
    let requests = EachSample::new(
        Listed::new(
            truth
                .iter()
                .enumerate()
                .map(|(k, r)| Ok((r.t, At::Truth(k)))),
        ),
        |_| At::Sample,
    );
    replay_vehicle::<GnssIns, N, _, _>(
        &LogSource::Memory(log),
        &FilterOptions::default(),
        requests,
        |at, e| {
            match (at, e) {
                (At::Truth(k), e) => at_truth[k] = e.copied(),
                (At::Sample, Some(e)) => {
                    let a = e.nav.euler();
                    points.push(EstimatePoint {
                        t: e.t,
                        attitude: [a.roll, a.pitch, a.yaw],
                        position: Some([e.nav.lat, e.nav.lon, e.nav.h]),
                    });
                }
                (At::Sample, None) => {}
            }
            Ok(())
        },
        |_, _| Ok(()),
    )
    .expect("replays");
    let (mut metrics, mut warnings, mut tables) = (Map::new(), Vec::new(), Vec::new());
    let difference = reference_metrics(log, &points, &mut metrics, &mut warnings);
    let s = score::score(&at_truth, truth, None, log.imu_time_span()).expect("scored");
    for (k, v) in [
        ("horizontal_error_final_m", s.horizontal_error_final_m),
        ("horizontal_error_rms_m", s.horizontal_error_rms_m),
        ("depth_error_rms_m", s.depth_error_rms_m),
        ("nees_mean", s.nees_mean),
        ("nees_position_mean", s.nees_position_mean),
        ("scored_seconds", s.scored_seconds),
    ] {
        metrics.insert(k.into(), Value::from(v));
    }
    warnings.extend(
        s.partial
            .map(|p| Warning::about(WarningKind::PartialScoring, "truth.csv", p)),
    );
    tables.push(s.table);
    let (rms, _, table) = attitude_errors(truth, &points).expect("attitude scored");
    metrics.insert("attitude_error_rms_deg".into(), rpy_json(rms));
    tables.push(table);
    tables.extend(difference);
    (metrics, warnings, tables)
}

/// `a` and `b` equal, numbers to [`SAME_SUMS_TOLERANCE`] relative.
fn close(a: &Value, b: &Value) -> bool {
    match (a, b) {
        (Value::Number(x), Value::Number(y)) => {
            let (x, y) = (x.as_f64().unwrap(), y.as_f64().unwrap());
            x == y || (x - y).abs() <= SAME_SUMS_TOLERANCE * x.abs().max(y.abs())
        }
        (Value::Object(x), Value::Object(y)) => {
            x.len() == y.len() && x.iter().all(|(k, v)| y.get(k).is_some_and(|w| close(v, w)))
        }
        _ => a == b,
    }
}

fn same_rows(a: &RunTable, b: &RunTable) {
    assert_eq!(a.name, b.name);
    assert_eq!(a.columns, b.columns, "{}", a.name);
    assert_eq!(a.rows.len(), b.rows.len(), "{}", a.name);
    for (x, y) in a.rows.iter().zip(&b.rows) {
        for (u, v) in x.iter().zip(y) {
            let same = u == v
                || (u.is_nan() && v.is_nan())
                || (u - v).abs() <= SAME_SUMS_TOLERANCE * u.abs().max(v.abs());
            assert!(same, "{}: {x:?} vs {y:?}", a.name);
        }
    }
}

#[test]
fn the_streamed_replay_equals_the_whole_series_scores() {
    let tmp = TempDir::new("figures");
    let dir = flight(&tmp);
    let options = ReplayOptions {
        keep_series: true,
        ..ReplayOptions::default()
    };
    let files = streamed_with(&dir, Strictness::Strict, &options).expect("replays");
    let log = LogDir::read(&dir, Strictness::Strict).expect("reads");
    let memory = GnssInsReplay.replay(&log, &options).expect("replays");
    // From the files and from memory: the same rows, the same result.
    assert_eq!(files.metrics, memory.metrics);
    assert_eq!(files.samples, memory.samples);
    assert_eq!(files.warnings, memory.warnings);
    assert_eq!(files.tables.len(), memory.tables.len());
    for (a, b) in files.tables.iter().zip(&memory.tables) {
        same_rows(a, b);
    }

    let (whole, whole_warnings, whole_tables) = whole_series(&log);
    for (k, v) in &whole {
        let got = files
            .metrics
            .get(k)
            .unwrap_or_else(|| panic!("{k} missing"));
        assert!(close(got, v), "{k}: {got} streamed, {v} whole");
    }
    // The filter's own words (its sensors' NIS) are not the scores'.
    let scoring: Vec<&Warning> = files
        .warnings
        .iter()
        .filter(|w| w.kind != WarningKind::NoiseSigma)
        .collect();
    assert_eq!(scoring, whole_warnings.iter().collect::<Vec<_>>());
    let names: Vec<&str> = files.tables.iter().map(|t| t.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "errors",
            "attitude_errors",
            "estimates",
            "reference_difference"
        ]
    );
    same_rows(&files.tables[0], &whole_tables[0]);
    same_rows(&files.tables[1], &whole_tables[1]);
    same_rows(&files.tables[3], &whole_tables[2]);
    // Every 10th of the 5350 IMU samples (the first one starts the filter).
    assert_eq!(files.tables[2].rows.len(), 535);
    assert_eq!(files.metrics["reference_samples"], 428);
    assert!((files.metrics["replayed_seconds"].as_f64().unwrap() - 21.396).abs() < 1e-9);
}

#[test]
fn written_series_are_every_row_and_the_plots() {
    let tmp = TempDir::new("out");
    let dir = flight(&tmp);
    let out = tmp.0.join("out");
    std::fs::create_dir_all(&out).unwrap();
    let options = ReplayOptions {
        keep_series: true,
        ..ReplayOptions::default()
    };
    let files = LogFiles::open(&dir, Strictness::Strict).unwrap();
    let written = GnssInsReplay
        .replay_files(&files, &options, Some(&out))
        .expect("replays");
    assert!(written.tables.is_empty(), "the series went to the files");
    let kept = streamed_with(&dir, Strictness::Strict, &options).expect("replays");
    assert_eq!(written.metrics, kept.metrics);
    for table in &kept.tables {
        // Written as it grew, and as the whole table writes itself.
        let text = std::fs::read_to_string(out.join(format!("{}.csv", table.name))).unwrap();
        let whole = tmp.0.join("whole.csv");
        table.write_csv(&whole).expect("writes");
        let expected = std::fs::read_to_string(&whole).unwrap();
        assert!(text == expected, "{}", table.name);
    }
    for f in [
        "attitude_difference.svg",
        "horizontal_difference.svg",
        "attitude_errors.svg",
    ] {
        assert!(out.join(f).is_file(), "{f}");
    }
}

/// `--smooth`: the forward run is the same, the rows of the estimates
/// table come back smoothed (same times, no larger sigma, the last one the
/// forward one), the truth rows are scored smoothed, and written under
/// `--out` as they are kept in memory.
#[test]
fn smoothing_adds_the_smoothed_estimates_and_their_scores() {
    let tmp = TempDir::new("smooth");
    let dir = flight(&tmp);
    let forward_options = ReplayOptions {
        keep_series: true,
        ..ReplayOptions::default()
    };
    let options = ReplayOptions {
        smooth: true,
        ..forward_options
    };
    let forward = streamed_with(&dir, Strictness::Strict, &forward_options).expect("replays");
    let both = streamed_with(&dir, Strictness::Strict, &options).expect("replays");
    let mut without = both.metrics.clone();
    let smoothed = without.remove("smoothed").expect("smoothed");
    assert_eq!(without, forward.metrics, "the forward keys are unchanged");
    let table = |out: &ReplayOutput, name: &str| -> RunTable {
        let t = out.tables.iter().find(|t| t.name == name);
        t.unwrap_or_else(|| panic!("{name}")).clone()
    };
    for name in ["errors", "estimates"] {
        same_rows(&table(&both, name), &table(&forward, name));
    }
    let (estimates, smooth) = (table(&forward, "estimates"), table(&both, SMOOTHED_TABLE));
    assert_eq!(smooth.rows.len(), estimates.rows.len());
    let column = |name: &str| ESTIMATES_COLUMNS.iter().position(|c| *c == name).unwrap();
    let mut tighter = 0;
    for (f, s) in estimates.rows.iter().zip(&smooth.rows) {
        assert_eq!(f[0], s[0], "same time");
        for name in ["sig_n", "sig_e", "sig_d"] {
            let k = column(name);
            assert!(s[k] <= f[k] * (1.0 + 1e-9), "{name} at t = {}", f[0]);
        }
        tighter += usize::from(s[column("sig_n")] < 0.9 * f[column("sig_n")]);
    }
    assert!(tighter > estimates.rows.len() / 2, "{tighter} rows tighter");
    let (f, s) = (estimates.rows.last().unwrap(), smooth.rows.last().unwrap());
    for k in 1..f.len() {
        assert!(
            (f[k] - s[k]).abs() <= 1e-9 * f[k].abs().max(1.0),
            "{}",
            ESTIMATES_COLUMNS[k]
        );
    }
    // Scored at as many truth rows as the forward run.
    let errors = table(&both, SMOOTHED_ERRORS_TABLE);
    assert_eq!(errors.rows.len(), table(&forward, "errors").rows.len());
    assert_eq!(
        smoothed["estimates"].as_u64(),
        Some((errors.rows.len() + smooth.rows.len()) as u64)
    );
    for key in nav_replay::ins::ERROR_KEYS {
        assert!(
            smoothed[key].as_f64().is_some_and(f64::is_finite),
            "{key}: {smoothed}"
        );
    }
    // Against PX4's estimate, at the smoothed rows: every reference row
    // inside them is compared.
    let difference = table(&both, SMOOTHED_REFERENCE_TABLE);
    assert!(difference.rows.len() + 2 >= table(&forward, "reference_difference").rows.len());
    assert!(smoothed["horizontal_difference_rms_m"]
        .as_f64()
        .is_some_and(f64::is_finite));
    for axis in ["roll", "pitch", "yaw"] {
        let v = smoothed["attitude_difference_rms_deg"][axis].as_f64();
        assert!(v.is_some_and(f64::is_finite), "{axis}: {smoothed}");
    }

    let out = tmp.0.join("out");
    std::fs::create_dir_all(&out).unwrap();
    let files = LogFiles::open(&dir, Strictness::Strict).unwrap();
    let written = GnssInsReplay
        .replay_files(&files, &options, Some(&out))
        .expect("replays");
    assert_eq!(written.metrics, both.metrics);
    for t in [&smooth, &errors, &difference] {
        let text = std::fs::read_to_string(out.join(format!("{}.csv", t.name))).unwrap();
        let whole = tmp.0.join("whole.csv");
        t.write_csv(&whole).expect("writes");
        assert!(
            text == std::fs::read_to_string(&whole).unwrap(),
            "{}",
            t.name
        );
    }
    assert!(out.join("replay-smoothed-horizontal.svg").is_file());

    // Without truth: the smoothed rows and their differences to PX4's
    // estimate, no smoothed scores and no file of them.
    let no_truth = copy(&dir, "no-truth");
    std::fs::remove_file(no_truth.join("truth.csv")).unwrap();
    let out = tmp.0.join("out-no-truth");
    std::fs::create_dir_all(&out).unwrap();
    let files = LogFiles::open(&no_truth, Strictness::Strict).unwrap();
    let written = GnssInsReplay
        .replay_files(&files, &options, Some(&out))
        .expect("replays");
    let object = written.metrics["smoothed"].as_object().unwrap();
    assert_eq!(
        object.keys().collect::<Vec<_>>(),
        [
            "attitude_difference_rms_deg",
            "estimates",
            "horizontal_difference_rms_m"
        ]
    );
    assert_eq!(object["estimates"].as_u64(), Some(smooth.rows.len() as u64));
    assert!(out.join("smoothed.csv").is_file());
    assert!(!out.join("smoothed_errors.csv").exists());
}

fn has_warning(out: &ReplayOutput, text: &str) -> bool {
    out.warnings.iter().any(|w| w.message.contains(text))
}

#[test]
fn broken_logs_are_refused_or_warned_about() {
    let tmp = TempDir::new("broken");
    let dir = flight(&tmp);
    // A row cut short (a log copied while written).
    let cut = copy(&dir, "cut");
    let text = std::fs::read_to_string(cut.join("imu.csv")).unwrap();
    std::fs::write(cut.join("imu.csv"), &text[..text.len() - 20]).unwrap();
    let e = streamed(&cut, Strictness::Strict)
        .expect_err("strict")
        .to_string();
    assert!(e.contains("imu.csv"), "{e}");
    streamed(&cut, Strictness::Lenient).expect("lenient skips the row");
    // The last truth row cut short.
    let cut_truth = copy(&dir, "cut-truth");
    let text = std::fs::read_to_string(cut_truth.join("truth.csv")).unwrap();
    std::fs::write(cut_truth.join("truth.csv"), &text[..text.len() - 30]).unwrap();
    let e = streamed(&cut_truth, Strictness::Strict)
        .expect_err("strict")
        .to_string();
    assert!(e.contains("truth.csv"), "{e}");
    // A NaN in gnss.csv and in reference.csv.
    for (file, line) in [("gnss.csv", 101), ("reference.csv", 201)] {
        let nan = copy(&dir, &format!("nan-{file}"));
        edit(&nan, file, |i, l| {
            let mut cells: Vec<String> = l.split(',').map(String::from).collect();
            if i + 1 == line {
                cells[1] = "NaN".into();
            }
            Some(cells.join(","))
        });
        let e = streamed(&nan, Strictness::Strict)
            .expect_err("strict")
            .to_string();
        assert!(e.contains(&format!("{file}:{line}")), "{e}");
    }
    // No gnss.csv: an INS aided by the barometer and the heading only
    // diverges (roll 50 deg, 77 m/s east by t = 26 s on this flight) until
    // the solution is not finite, 17 s after the cause. The model needs
    // its GNSS: refused at setup, naming the missing file, on a short log
    // as on the whole flight.
    let no_gnss = copy(&dir, "no-gnss");
    std::fs::remove_file(no_gnss.join("gnss.csv")).unwrap();
    for rows in [usize::MAX, 3000] {
        edit(&no_gnss, "imu.csv", |i, l| (i < rows).then(|| l.into()));
        let e = streamed(&no_gnss, Strictness::Strict)
            .expect_err("no GNSS")
            .to_string();
        assert!(
            e.contains("gnss.csv: missing") && e.contains("needs GNSS"),
            "{e}"
        );
    }
    // One second without IMU rows: a gap, counted; with lenient reading
    // propagated in bounded steps, and said.
    let gap = copy(&dir, "gap");
    edit(&gap, "imu.csv", |i, l| {
        (!(1000..1250).contains(&i)).then(|| l.into())
    });
    let out = streamed(&gap, Strictness::Strict).expect("a gap is not an error");
    assert_eq!(out.metrics["health"]["imu_gaps"], 1);
    let lenient = ReplayOptions {
        lenient: true,
        ..ReplayOptions::default()
    };
    let out = streamed_with(&gap, Strictness::Lenient, &lenient).expect("replays");
    assert_eq!(out.metrics["health"]["imu_gaps"], 1);
    assert!(has_warning(&out, "imu.csv gap of"), "{:?}", out.warnings);
    // Truth after the log: not scored, said; the reference still is.
    let late = copy(&dir, "late-truth");
    edit(&late, "truth.csv", |i, l| {
        if i == 0 {
            return Some(l.into());
        }
        let (t, rest) = l.split_once(',').unwrap();
        Some(format!("{},{rest}", t.parse::<f64>().unwrap() + 100.0))
    });
    let out = streamed(&late, Strictness::Strict).expect("replays");
    assert!(
        has_warning(&out, "not scored against truth"),
        "{:?}",
        out.warnings
    );
    assert!(out.metrics.get("horizontal_error_rms_m").is_none());
    assert!(out.metrics.get("attitude_error_rms_deg").is_none());
    assert!(out.metrics.contains_key("attitude_difference_rms_deg"));
    // A truth file of a header only.
    let empty_truth = copy(&dir, "empty-truth");
    edit(&empty_truth, "truth.csv", |i, l| (i == 0).then(|| l.into()));
    let out = streamed(&empty_truth, Strictness::Strict).expect("replays");
    assert!(
        has_warning(&out, "not scored against truth: truth.csv: no rows"),
        "{:?}",
        out.warnings
    );
    // No IMU rows at all.
    let empty = copy(&dir, "empty");
    edit(&empty, "imu.csv", |i, l| (i == 0).then(|| l.into()));
    let e = streamed(&empty, Strictness::Strict)
        .expect_err("nothing")
        .to_string();
    assert!(e.contains("imu.csv"), "{e}");
}
