//! The preflight on a small simulated log: clean as simulated, and each
//! check firing on the mistake it is for (cases as data).

use nav_runtime::log::{ImuRow, LogDir, LogFiles, Strictness, WarningKind};

use models::sdins25::simulation::{simulate, SimConfig};
use nav_replay::preflight::{check, check_files, PreflightOptions, Severity};

fn log() -> LogDir {
    let config = SimConfig {
        duration: 30.0,
        ..SimConfig::usbl()
    };
    simulate(&config, 3).log
}

/// (name, edit, expected severity, expected kind, text in the message)
type Case = (
    &'static str,
    fn(&mut LogDir),
    Severity,
    WarningKind,
    &'static str,
);

fn cases() -> Vec<Case> {
    use Severity::*;
    use WarningKind::*;
    vec![
        (
            "accelerometer in g",
            |l| {
                l.imu.iter_mut().for_each(|r| {
                    r.ax /= 9.81;
                    r.ay /= 9.81;
                    r.az /= 9.81
                })
            },
            Error,
            Suspicious,
            "g units?",
        ),
        (
            "az sign flipped",
            |l| l.imu.iter_mut().for_each(|r| r.az = -r.az),
            Error,
            Suspicious,
            "FLU",
        ),
        (
            "gyro beyond 2000 deg/s",
            |l| l.imu[50].gx = 40.0,
            Error,
            Suspicious,
            "deg/s?",
        ),
        (
            "heading in degrees",
            |l| {
                l.heading
                    .as_mut()
                    .unwrap()
                    .iter_mut()
                    .for_each(|r| r.heading = r.heading.to_degrees())
            },
            Error,
            Suspicious,
            "degrees?",
        ),
        (
            "depth sign",
            |l| {
                l.depth
                    .as_mut()
                    .unwrap()
                    .iter_mut()
                    .for_each(|r| r.depth = -r.depth)
            },
            Error,
            Suspicious,
            "sign",
        ),
        (
            "depth in feet",
            |l| {
                l.depth
                    .as_mut()
                    .unwrap()
                    .iter_mut()
                    .for_each(|r| r.depth /= 0.3048)
            },
            Error,
            Suspicious,
            "feet?",
        ),
        (
            "initial depth 1e300",
            |l| l.meta.initial.depth = 1e300,
            Error,
            Suspicious,
            "physical depth",
        ),
        (
            "IMU gap",
            |l| {
                l.imu.drain(500..1500);
            },
            Error,
            ImuGap,
            "gap of",
        ),
        (
            "frozen IMU",
            |l| {
                let f = l.imu[100];
                for r in &mut l.imu[100..2700] {
                    (r.gx, r.gy, r.gz) = (f.gx, f.gy, f.gz);
                }
            },
            Error,
            FrozenImu,
            "frozen IMU",
        ),
        (
            "DVL in cm/s",
            |l| {
                l.dvl.as_mut().unwrap().iter_mut().for_each(|r| {
                    r.vx = r.vx.map(|v| v * 100.0 + 300.0);
                })
            },
            Error,
            Suspicious,
            "cm/s?",
        ),
        (
            "truth depth 1e300",
            |l| l.truth.as_mut().unwrap()[5].depth = 1e300,
            Error,
            Suspicious,
            "not a physical value",
        ),
        (
            "truth header only",
            |l| l.truth = Some(Vec::new()),
            Error,
            Suspicious,
            "nothing to score",
        ),
        (
            "missing sensor section",
            |l| l.meta.sensors.dvl = None,
            Warning,
            MissingSensorSection,
            "[sensors.dvl]",
        ),
        (
            "one IMU row",
            |l| l.imu.truncate(1),
            Error,
            ImuGap,
            "at least 2",
        ),
    ]
}

/// The options of an SDINS replay.
fn sdins() -> PreflightOptions {
    PreflightOptions {
        model_files: Some(&[
            "imu.csv",
            "dvl.csv",
            "depth.csv",
            "heading.csv",
            "usbl.csv",
            "altitude.csv",
            "truth.csv",
        ]),
        ..PreflightOptions::default()
    }
}

#[test]
fn simulated_log_is_clean() {
    // The SDINS models read every file the simulator writes (the echo
    // sounder gates the DVL, and needs no [sensors.altitude] noise).
    let report = check(&log(), &sdins());
    assert!(report.findings.is_empty(), "{:?}", report.findings);
    // A model that does not read the echo sounder lists it as unused.
    let without_altitude = PreflightOptions {
        model_files: Some(&[
            "imu.csv",
            "dvl.csv",
            "depth.csv",
            "heading.csv",
            "usbl.csv",
            "truth.csv",
        ]),
        ..PreflightOptions::default()
    };
    let partial = check(&log(), &without_altitude);
    let unused: Vec<_> = partial
        .findings
        .iter()
        .map(|f| (f.severity, f.what.kind, f.what.file.as_deref()))
        .collect();
    assert_eq!(
        unused,
        [(
            Severity::Warning,
            WarningKind::UnusedFile,
            Some("altitude.csv")
        )]
    );
    // Without a model's file list nothing is unused.
    let all = check(&log(), &PreflightOptions::default());
    assert!(
        all.findings
            .iter()
            .all(|f| f.what.kind == WarningKind::MissingSensorSection),
        "{:?}",
        all.findings
    );
}

#[test]
fn each_check_fires_on_its_mistake() {
    let base = log();
    for (name, edit, severity, kind, text) in cases() {
        let mut l = base.clone();
        edit(&mut l);
        let report = check(&l, &sdins());
        let hit = report
            .findings
            .iter()
            .find(|f| f.what.kind == kind && f.what.to_string().contains(text));
        let Some(hit) = hit else {
            panic!("{name}: {:?}", report.findings)
        };
        assert_eq!(hit.severity, severity, "{name}: {}", hit.what);
        assert!(hit.what.file.is_some(), "{name}: no file in {}", hit.what);
    }
}

#[test]
fn lenient_turns_gaps_and_frozen_imu_into_warnings() {
    let mut l = log();
    l.imu.drain(500..1500);
    let lenient = PreflightOptions {
        lenient: true,
        ..PreflightOptions::default()
    };
    let report = check(&l, &lenient);
    assert!(!report.has_errors(), "{:?}", report.findings);
    assert!(report.has(WarningKind::ImuGap));
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(48))]
    /// Any finite values the reader can accept: the preflight never panics
    /// and every finding names a file.
    #[test]
    fn never_panics_on_finite_values(
        row in 0usize..3000,
        column in 0usize..7,
        exponent in -300i32..300,
        sign in proptest::bool::ANY,
        keep in 1usize..3000,
    ) {
        let mut l = log();
        let v = if sign { 1.0 } else { -1.0 } * 10f64.powi(exponent);
        if let Some(r) = l.imu.get_mut(row) {
            match column {
                0 => r.gx = v, 1 => r.gy = v, 2 => r.gz = v,
                3 => r.ax = v, 4 => r.ay = v, 5 => r.az = v,
                _ => {}
            }
        }
        if let Some(d) = l.dvl.as_mut().and_then(|d| d.get_mut(row % 60)) {
            d.vy = if column == 6 { None } else { Some(v) };
        }
        if let Some(h) = l.heading.as_mut().and_then(|h| h.get_mut(row % 60)) {
            h.heading = v.clamp(-1e6, 1e6);
        }
        l.imu.truncate(keep);
        let report = check(&l, &sdins());
        for f in &report.findings {
            proptest::prop_assert!(f.what.file.is_some() || f.what.key.is_some(), "{}", f.what);
        }
    }
}

/// A directory under the system's temporary directory, removed on drop.
struct Scratch(std::path::PathBuf);

impl Scratch {
    fn new(name: &str) -> Self {
        let d = std::env::temp_dir().join(format!(
            "preflight-{name}-{}-{:?}",
            std::process::id(),
            std::thread::current().id()
        ));
        let _ = std::fs::remove_dir_all(&d);
        Scratch(d)
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// Writes `log`, checks it as a stream and returns the findings and summary.
fn stream(
    log: &LogDir,
    strictness: Strictness,
    options: &PreflightOptions,
    name: &str,
) -> (
    nav_replay::preflight::Report,
    nav_replay::preflight::LogSummary,
    LogDir,
) {
    let dir = Scratch::new(name);
    log.write(&dir.0).unwrap();
    let files = LogFiles::open(&dir.0, strictness).unwrap();
    let (report, summary) = check_files(&files, options).unwrap();
    let read = LogDir::read(&dir.0, strictness).unwrap();
    (report, summary, read)
}

/// Freezes the gyro triple over `rows`.
fn freeze(l: &mut LogDir, rows: std::ops::Range<usize>) {
    let f = l.imu[rows.start];
    for r in &mut l.imu[rows] {
        (r.gx, r.gy, r.gz) = (f.gx, f.gy, f.gz);
    }
}

#[test]
fn streaming_gives_the_findings_of_the_log_in_memory() {
    // (name, edit, options): every case of `cases`, then variants that
    // exercise the folds' bookkeeping (several gaps, several frozen runs,
    // rows outside the IMU span, a short head).
    let short_head = PreflightOptions {
        head_seconds: 12.0,
        ..sdins()
    };
    let lenient = PreflightOptions {
        lenient: true,
        ..sdins()
    };
    type Variant = (&'static str, fn(&mut LogDir), PreflightOptions);
    let mut variants: Vec<Variant> = cases()
        .into_iter()
        .map(|(name, edit, ..)| (name, edit, sdins()))
        .collect();
    variants.extend::<[Variant; 9]>([
        ("unchanged", |_| {}, sdins()),
        ("unchanged, short head", |_| {}, short_head),
        (
            "five gaps",
            |l| {
                for k in 0..5 {
                    l.imu.drain(200 + 300 * k..300 + 300 * k);
                }
            },
            sdins(),
        ),
        (
            "frozen runs, lenient",
            |l| {
                freeze(l, 10..2100);
                freeze(l, 2100..2600);
                freeze(l, 2600..2999);
            },
            lenient,
        ),
        (
            "DVL rows partly empty",
            |l| {
                for r in l.dvl.as_mut().unwrap().iter_mut().take(6) {
                    r.vy = None;
                }
            },
            sdins(),
        ),
        (
            "aiding rows outside the IMU span",
            |l| {
                let t1 = l.imu.last().unwrap().t;
                let d = l.depth.as_mut().unwrap();
                let last = *d.last().unwrap();
                d.push(nav_runtime::log::DepthRow::new(t1 + 5.0, last.depth));
                d.push(nav_runtime::log::DepthRow::new(t1 + 7200.0, last.depth));
            },
            sdins(),
        ),
        (
            "heading in degrees, short head",
            |l| {
                l.heading
                    .as_mut()
                    .unwrap()
                    .iter_mut()
                    .for_each(|r| r.heading = r.heading.to_degrees())
            },
            short_head,
        ),
        (
            "gyro z up",
            |l| l.imu.iter_mut().for_each(|r| r.gz = -r.gz),
            sdins(),
        ),
        (
            "no aiding files",
            |l| {
                (l.dvl, l.depth, l.heading, l.usbl) = (None, None, None, None);
                l.truth = Some(Vec::new());
            },
            PreflightOptions::default(),
        ),
    ]);
    let base = log();
    for (name, edit, options) in variants {
        let mut l = base.clone();
        edit(&mut l);
        let (streamed, summary, read) = stream(&l, Strictness::Strict, &options, "same");
        assert_eq!(read, l, "{name}: the log does not round-trip");
        let in_memory = check(&l, &options);
        assert_eq!(streamed, in_memory, "{name}");
        // The summary agrees with the log read whole.
        assert_eq!(summary.warnings, read.warnings, "{name}");
        assert_eq!(summary.imu_rows(), l.imu.len(), "{name}");
        assert_eq!(summary.imu_time_span(), l.imu_time_span(), "{name}");
        assert_eq!(
            summary.imu.map(|i| i.first),
            l.imu.first().copied(),
            "{name}"
        );
        let dvl = summary.file("dvl.csv");
        assert_eq!(dvl.map(|f| f.rows), l.dvl.as_ref().map(Vec::len), "{name}");
        assert_eq!(
            summary,
            nav_replay::preflight::LogSummary::of(&read),
            "{name}"
        );
    }
}

#[test]
fn streaming_finds_the_gyro_resolution_of_the_whole_file() {
    // A 27-s frozen run early, while the gyro's steps seen so far are coarse
    // (the run is too short for them), and a much finer step late in the
    // file that makes the run frozen: the choice is made with the final
    // resolution, as over the whole file.
    use nav_runtime::stuck::StuckDetector;
    let base = log();
    let sigma = base.meta.sensors.imu.unwrap().gyro_noise_sigma;
    let required = |q: f64| StuckDetector::required_repeats(sigma, q, 1e-9) as usize;
    let q = (0..60)
        .map(|k| sigma * 1.25f64.powi(k))
        .find(|&q| (3100..1_000_000).contains(&required(q)))
        .expect("a coarse resolution");
    let fine = sigma / 100.0;
    assert!(required(fine) < 2600, "{}", required(fine));
    let quantized = |step: bool| {
        let mut l = base.clone();
        for (i, r) in l.imu.iter_mut().enumerate() {
            r.gx = (r.gx / q).round() * q + if step && i == 2990 { fine } else { 0.0 };
            // Steps of the coarse resolution before and after the run.
            let offset = match i {
                0..100 => 2.0 * q,
                2800.. => q,
                _ => 0.0,
            };
            r.gy = (r.gy / q).round() * q + offset;
            r.gz = (r.gz / q).round() * q;
        }
        freeze(&mut l, 100..2800);
        l
    };
    for (step, frozen) in [(true, true), (false, false)] {
        let l = quantized(step);
        let (streamed, _, _) = stream(&l, Strictness::Strict, &sdins(), "resolution");
        assert_eq!(streamed, check(&l, &sdins()));
        assert_eq!(
            streamed.has(WarningKind::FrozenImu),
            frozen,
            "step {step}: {:?}",
            streamed.findings
        );
    }
}

#[test]
fn lenient_streaming_names_the_lines() {
    // A gap and a frozen run after a row the lenient reader skips: the
    // stream names the file's lines; the log in memory cannot (it no longer
    // knows which line a row came from).
    let mut l = log();
    l.imu.drain(500..520);
    let n = l.imu.len();
    freeze(&mut l, 700..n);
    let dir = Scratch::new("lines");
    l.write(&dir.0).unwrap();
    let path = dir.0.join(<ImuRow as nav_runtime::log::Row>::FILE);
    let text = std::fs::read_to_string(&path).unwrap();
    let mut lines: Vec<&str> = text.lines().collect();
    lines[10] = "not,a,row"; // line 11
    std::fs::write(&path, lines.join("\n") + "\n").unwrap();
    let options = PreflightOptions {
        lenient: true,
        ..sdins()
    };
    let files = LogFiles::open(&dir.0, Strictness::Lenient).unwrap();
    let (report, summary) = check_files(&files, &options).unwrap();
    assert_eq!(summary.total_skipped_rows(), 1);
    assert_eq!(summary.file("imu.csv").unwrap().skip_reasons[0].line, 11);
    // Row 499 of `l` is on line 501, the row after the gap on line 502.
    let gap = report
        .findings
        .iter()
        .find(|f| f.what.kind == WarningKind::ImuGap)
        .expect("a gap");
    assert_eq!(gap.what.line, Some(501), "{}", gap.what);
    assert!(
        gap.what.message.contains("lines 501 and 502"),
        "{}",
        gap.what
    );
    let frozen = report
        .findings
        .iter()
        .find(|f| f.what.kind == WarningKind::FrozenImu)
        .expect("a frozen IMU");
    assert_eq!(frozen.what.line, Some(702), "{}", frozen.what);
    let last = l.imu.len() + 1;
    assert!(
        frozen.what.message.contains(&format!("lines 702-{last}")),
        "{}",
        frozen.what
    );
    // The same rows in memory: the same findings without the lines.
    let read = LogDir::read(&dir.0, Strictness::Lenient).unwrap();
    assert_eq!(summary.warnings, read.warnings);
    assert_eq!(summary, nav_replay::preflight::LogSummary::of(&read));
    let in_memory = check(&read, &options);
    let strip = |r: &nav_replay::preflight::Report| -> Vec<_> {
        r.findings
            .iter()
            .map(|f| (f.severity, f.what.kind, f.what.file.clone()))
            .collect()
    };
    assert_eq!(strip(&report), strip(&in_memory));
    assert!(in_memory
        .findings
        .iter()
        .any(|f| f.what.message.contains("between two rows")));
}

#[test]
fn streaming_reports_the_read_error_of_the_whole_log() {
    // A bad row in depth.csv and one in truth.csv: the first in read order
    // is the error, as `LogDir::read` gives it.
    let dir = Scratch::new("error");
    log().write(&dir.0).unwrap();
    for file in ["depth.csv", "truth.csv"] {
        let path = dir.0.join(file);
        let text = std::fs::read_to_string(&path).unwrap();
        std::fs::write(&path, text + "1e9,x\n").unwrap();
    }
    let files = LogFiles::open(&dir.0, Strictness::Strict).unwrap();
    let streamed = check_files(&files, &sdins()).unwrap_err();
    let whole = LogDir::read(&dir.0, Strictness::Strict).unwrap_err();
    assert_eq!(streamed.to_string(), whole.to_string());
    assert!(streamed.to_string().contains("depth.csv"), "{streamed}");
}

#[test]
fn alongside_the_preflight_refuses_first_and_stops_the_work() {
    use nav_replay::RunError;
    use std::time::{Duration, Instant};
    let dir = Scratch::new("alongside");
    let mut bad = log();
    bad.imu.iter_mut().for_each(|r| r.az = -r.az);
    bad.write(&dir.0).unwrap();
    let files = LogFiles::open(&dir.0, Strictness::Strict).unwrap();
    // The work waits until the refusal stops the log (bounded, so a missing
    // stop fails the test instead of hanging it), then fails on its own.
    let started = Instant::now();
    let result = nav_replay::preflight::check_alongside(&files, &sdins(), false, || {
        while !files.stopped() && started.elapsed() < Duration::from_secs(20) {
            std::thread::sleep(Duration::from_millis(1));
        }
        assert!(files.stopped(), "the refusal stops the log's streams");
        Err::<(), _>(RunError::Invalid("the work's own error".into()))
    });
    let err = result.expect_err("refused").to_string();
    assert!(
        err.contains("FLU"),
        "the preflight's error comes first: {err}"
    );
    // An accepted log gives the work's result, its error included.
    let good = Scratch::new("alongside-good");
    log().write(&good.0).unwrap();
    let files = LogFiles::open(&good.0, Strictness::Strict).unwrap();
    let (n, report, summary) =
        nav_replay::preflight::check_alongside(&files, &sdins(), false, || Ok(7))
            .expect("accepted");
    assert_eq!(n, 7);
    assert_eq!(report.errors().count(), 0);
    assert!(summary.imu_rows() > 0);
    assert!(!files.stopped());
    let err = nav_replay::preflight::check_alongside(&files, &sdins(), false, || {
        Err::<(), _>(RunError::Invalid("the work's own error".into()))
    })
    .expect_err("the work's error");
    assert!(err.to_string().contains("own error"), "{err}");
}

/// With the IMU shared, the preflight's findings and summary are those of
/// reading the log itself, however much of `imu.csv` the work read: all of
/// it, part of it (a work that stops early), or none (a work that never
/// opens it); strict and lenient, with a bad IMU row.
#[test]
fn a_shared_imu_gives_the_findings_of_reading_it() {
    use nav_runtime::log::{LogSource, RowSource};
    let dir = Scratch::new("shared-imu");
    let mut l = log();
    l.imu.iter_mut().skip(40).take(30).for_each(|r| r.gx = 0.2);
    l.write(&dir.0).unwrap();
    let path = dir.0.join("imu.csv");
    let text = std::fs::read_to_string(&path).unwrap();
    let mut lines: Vec<&str> = text.lines().collect();
    lines.insert(1500, "12.3,x,0,0,0,0,-9.8");
    std::fs::write(&path, lines.join("\n") + "\n").unwrap();
    for strictness in [Strictness::Strict, Strictness::Lenient] {
        let files = LogFiles::open(&dir.0, strictness).unwrap();
        let mut options = sdins();
        options.lenient = strictness == Strictness::Lenient;
        let alone = check_files(&files, &options).map(|(r, s)| (format!("{r:?}"), s));
        assert_eq!(
            alone.is_err(),
            strictness == Strictness::Strict,
            "the bad row"
        );
        // How many IMU rows the work reads before it stops (None: to the end).
        for read in [None, Some(0), Some(700), Some(5000)] {
            let shared = nav_replay::preflight::check_alongside(&files, &options, true, || {
                let source = LogSource::Files(&files);
                let mut imu = source.imu_rows().unwrap();
                let mut n = 0usize;
                while read.is_none_or(|k| n < k) {
                    match imu.next_row() {
                        Ok(Some(_)) => n += 1,
                        _ => break,
                    }
                }
                Ok(n)
            });
            match (&alone, shared) {
                (Ok((report, summary)), Ok((_, r, s))) => {
                    assert_eq!(&format!("{r:?}"), report, "{strictness:?} {read:?}");
                    assert_eq!(&s, summary, "{strictness:?} {read:?}");
                }
                (Err(a), Err(b)) => {
                    assert_eq!(a.to_string(), b.to_string(), "{strictness:?} {read:?}")
                }
                (a, b) => panic!("{strictness:?} {read:?}: alone {a:?}, shared {b:?}"),
            }
        }
    }
}
