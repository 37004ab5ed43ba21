//! Bad log directories: every error names file, line and column (or meta key).

#[path = "log_common.rs"]
mod common;

use common::*;
use nav_runtime::log::*;

/// What a case expects.
#[derive(Debug)]
enum Expect {
    /// A CSV error at file:line in column, with a problem matching the predicate.
    Csv(&'static str, u64, &'static str, fn(&CsvProblem) -> bool),
    /// A meta.toml error on key (and line, if given).
    Meta(&'static str, Option<u64>),
    Empty(&'static str),
    Missing(&'static str),
}

/// (name, file to overwrite, content or None = delete, expectation, also fatal when lenient)
type Case = (
    &'static str,
    &'static str,
    Option<&'static str>,
    Expect,
    bool,
);

fn cases() -> Vec<Case> {
    use CsvProblem as P;
    use Expect::*;
    vec![
        ("too few columns", "imu.csv", Some("t,gx,gy,gz,ax,ay,az\n0,0,0,0,0,0,0\n0.01,0,0,0,0,0\n"),
            Csv("imu.csv", 3, "az", |p| matches!(p, P::ColumnCount { expected: 7, found: 6 })), false),
        ("too many columns", "depth.csv", Some("t,depth\n0.1,1,2\n"),
            Csv("depth.csv", 2, "<column 3>", |p| matches!(p, P::ColumnCount { expected: 2, found: 3 })), false),
        ("text in a number", "dvl.csv", Some("t,vx,vy,vz\n0.1,1,2,3\n0.2,abc,2,3\n"),
            Csv("dvl.csv", 3, "vx", |p| matches!(p, P::NotANumber { text } if text == "abc")), false),
        ("text in time", "heading.csv", Some("t,heading\nnoon,0.1\n"),
            Csv("heading.csv", 2, "t", |p| matches!(p, P::NotANumber { .. })), false),
        ("empty cell in required column", "depth.csv", Some("t,depth\n0.1,\n"),
            Csv("depth.csv", 2, "depth", |p| matches!(p, P::EmptyCell)), false),
        ("empty time cell in dvl", "dvl.csv", Some("t,vx,vy,vz\n,1,2,3\n"),
            Csv("dvl.csv", 2, "t", |p| matches!(p, P::EmptyCell)), false),
        ("NaN", "usbl.csv", Some("t,lat,lon,depth\n0.1,0.7,0.2,3\n0.2,NaN,0.2,3\n"),
            Csv("usbl.csv", 3, "lat", |p| matches!(p, P::NonFinite { .. })), false),
        ("infinity", "speed.csv", Some("t,speed\n0.1,inf\n"),
            Csv("speed.csv", 2, "speed", |p| matches!(p, P::NonFinite { .. })), false),
        ("time backwards", "rpm.csv", Some("t,rpm\n0.1,100\n0.3,100\n0.2,100\n"),
            Csv("rpm.csv", 4, "t", |p| matches!(p, P::TimeBackwards { .. })), false),
        ("duplicate timestamp", "altitude.csv", Some("t,altitude\n0.1,5\n0.1,5\n"),
            Csv("altitude.csv", 3, "t", |p| matches!(p, P::DuplicateTime { .. })), false),
        ("latitude out of range", "usbl.csv", Some("t,lat,lon,depth\n0.1,1.6,0.2,3\n"),
            Csv("usbl.csv", 2, "lat", |p| matches!(p, P::OutOfRange { .. })), false),
        ("longitude out of range", "truth.csv", Some("t,lat,lon,depth,vn,ve,vd,roll,pitch,yaw\n0,0.1,7,0,0,0,0,0,0,0\n"),
            Csv("truth.csv", 2, "lon", |p| matches!(p, P::OutOfRange { .. })), false),
        ("negative altitude", "altitude.csv", Some("t,altitude\n0.1,-1\n"),
            Csv("altitude.csv", 2, "altitude", |p| matches!(p, P::OutOfRange { .. })), false),
        ("blank lines keep line numbers", "depth.csv", Some("t,depth\n\n0.1,1\n\n0.2,x\n"),
            Csv("depth.csv", 5, "depth", |p| matches!(p, P::NotANumber { .. })), false),
        ("CRLF line ends", "depth.csv", Some("t,depth\r\n0.1,1\r\n0.2,1e\r\n"),
            Csv("depth.csv", 3, "depth", |p| matches!(p, P::NotANumber { .. })), false),
        ("wrong header", "heading.csv", Some("t,hdg\n0.1,0.5\n"),
            Csv("heading.csv", 1, "heading", |p| matches!(p, P::WrongHeader { found, .. } if found == "hdg")), true),
        ("missing header", "imu.csv", Some("0,0,0,0,0,0,0\n"),
            Csv("imu.csv", 1, "t", |p| matches!(p, P::WrongHeader { .. })), true),
        ("header with extra column", "depth.csv", Some("t,depth,quality\n"),
            Csv("depth.csv", 1, "<column 3>", |p| matches!(p, P::WrongHeader { .. })), true),
        ("header too short", "usbl.csv", Some("t,lat,lon\n"),
            Csv("usbl.csv", 1, "depth", |p| matches!(p, P::WrongHeader { .. })), true),
        ("empty file", "speed.csv", Some(""), Empty("speed.csv"), true),
        ("whitespace-only file", "imu.csv", Some("\n\n"), Empty("imu.csv"), true),
        ("missing imu.csv", "imu.csv", None, Missing("imu.csv"), true),
        ("missing meta.toml", "meta.toml", None, Missing("meta.toml"), true),
        ("malformed meta", "meta.toml", Some("[initial]\nlat = 0.1\nlon = = 2\n"), Meta("", Some(3)), true),
        ("meta missing [initial]", "meta.toml", Some("[initial_sigma]\nposition = 1.0\n"), Meta("initial", None), true),
        ("meta missing key", "meta.toml", Some("[initial]\nlat = 0.1\ndepth = 3\n"), Meta("initial.lon", Some(1)), true),
        ("meta unknown key", "meta.toml", Some("[initial]\nlat = 0.1\nlon = 0.2\ndepth = 3\nheight = 4\n"),
            Meta("initial.height", Some(5)), true),
        ("meta zero noise sigma", "meta.toml",
            Some("[initial]\nlat = 0.1\nlon = 0.2\ndepth = 3\n[sensors.dvl]\nnoise_sigma = 0\n"),
            Meta("sensors.dvl.noise_sigma", Some(6)), true),
        ("meta zero imu noise sigma", "meta.toml",
            Some("[initial]\nlat = 0.1\nlon = 0.2\ndepth = 3\n[sensors.imu]\ngyro_noise_sigma = 0.0\naccel_noise_sigma = 0.01\n"),
            Meta("sensors.imu.gyro_noise_sigma", Some(6)), true),
        ("meta yaw in degrees", "meta.toml", Some("[initial]\nlat = 0.1\nlon = 0.2\ndepth = 3\nyaw = 90\n"),
            Meta("initial.yaw", Some(5)), true),
        ("meta misalignment sigma negative", "meta.toml",
            Some("[initial]\nlat = 0.1\nlon = 0.2\ndepth = 3\n[sensors.usbl]\nnoise_sigma = 1\nmisalignment_sigma = -1\n"),
            Meta("sensors.usbl.misalignment_sigma", Some(7)), true),
        ("meta initial t not a number", "meta.toml", Some("[initial]\nt = \"start\"\nlat = 0.1\nlon = 0.2\ndepth = 3\n"),
            Meta("initial.t", Some(2)), true),
        ("meta unknown sensor", "meta.toml",
            Some("[initial]\nlat = 0.1\nlon = 0.2\ndepth = 3\n[sensors.sonar]\nnoise_sigma = 1.0\n"),
            Meta("sensors.sonar", Some(5)), true),
        ("meta unknown sensor key", "meta.toml",
            Some("[initial]\nlat = 0.1\nlon = 0.2\ndepth = 3\n[sensors.dvl]\nnoise_sigma = 1.0\nscale = 2\n"),
            Meta("sensors.dvl.scale", Some(7)), true),
        ("meta negative sigma", "meta.toml",
            Some("[initial]\nlat = 0.1\nlon = 0.2\ndepth = 3\n[sensors.dvl]\nnoise_sigma = -1.0\n"),
            Meta("sensors.dvl.noise_sigma", Some(6)), true),
        ("meta sensor without noise", "meta.toml",
            Some("[initial]\nlat = 0.1\nlon = 0.2\ndepth = 3\n[sensors.depth]\nbias_sigma = 1.0\n"),
            Meta("sensors.depth.noise_sigma", Some(5)), true),
        ("meta latitude out of range", "meta.toml", Some("[initial]\nlat = 2.0\nlon = 0.2\ndepth = 3\n"),
            Meta("initial.lat", Some(2)), true),
        ("meta roll out of range", "meta.toml", Some("[initial]\nlat = 0.1\nlon = 0.2\ndepth = 3\nroll = 4.0\n"),
            Meta("initial.roll", Some(5)), true),
        ("meta text value", "meta.toml", Some("[initial]\nlat = \"north\"\nlon = 0.2\ndepth = 3\n"),
            Meta("initial.lat", Some(2)), true),
        ("meta nan value", "meta.toml", Some("[initial]\nlat = nan\nlon = 0.2\ndepth = 3\n"),
            Meta("initial.lat", Some(2)), true),
        ("meta section is a value", "meta.toml", Some("initial = 3\n"), Meta("initial", Some(1)), true),
        ("meta usbl incomplete", "meta.toml", Some("[initial]\nlat = 0.1\nlon = 0.2\ndepth = 3\n[usbl]\nlat = 0.1\n"),
            Meta("usbl.lon", Some(5)), true),
    ]
}

fn apply(dir: &std::path::Path, file: &str, content: Option<&str>) {
    let p = dir.join(file);
    match content {
        Some(c) => std::fs::write(p, c).unwrap(),
        None => std::fs::remove_file(p).unwrap(),
    }
}

fn check(name: &str, err: &LogError, expect: &Expect) {
    let msg = err.to_string();
    assert!(!msg.contains('\n'), "{name}: multi-line message {msg:?}");
    match expect {
        Expect::Csv(file, line, column, pred) => {
            assert!(matches!(err, LogError::Csv { .. }), "{name}: {err:?}");
            assert_eq!(err.file(), Some(*file), "{name}: {msg}");
            assert_eq!(err.line(), Some(*line), "{name}: {msg}");
            assert_eq!(err.column(), Some(*column), "{name}: {msg}");
            assert!(pred(err.csv_problem().unwrap()), "{name}: {err:?}");
            assert!(
                msg.starts_with(&format!("{file}:{line}: column `{column}`")),
                "{name}: {msg}"
            );
        }
        Expect::Meta(key, line) => {
            assert!(matches!(err, LogError::Meta { .. }), "{name}: {err:?}");
            assert_eq!(err.column(), Some(*key), "{name}: {msg}");
            assert_eq!(err.line(), *line, "{name}: {msg}");
            assert!(msg.starts_with("meta.toml"), "{name}: {msg}");
        }
        Expect::Empty(file) => {
            assert!(matches!(err, LogError::EmptyFile { .. }), "{name}: {err:?}");
            assert_eq!(err.file(), Some(*file));
        }
        Expect::Missing(file) => {
            assert!(
                matches!(err, LogError::MissingFile { .. }),
                "{name}: {err:?}"
            );
            assert_eq!(err.file(), Some(*file));
            assert!(msg.contains(file), "{name}: {msg}");
        }
    }
}

#[test]
fn strict_reader_reports_file_line_and_column() {
    for (name, file, content, expect, _) in cases() {
        let dir = sample_dir("strict");
        apply(dir.path(), file, content);
        match LogDir::read(dir.path(), Strictness::Strict) {
            Ok(_) => panic!("{name}: accepted a bad log"),
            Err(err) => check(name, &err, &expect),
        }
    }
}

#[test]
fn lenient_reader_skips_and_counts_bad_rows() {
    for (name, file, content, expect, fatal) in cases() {
        let dir = sample_dir("lenient");
        apply(dir.path(), file, content);
        let res = LogDir::read(dir.path(), Strictness::Lenient);
        if fatal {
            match res {
                Ok(_) => panic!("{name}: lenient reader accepted a fatal problem"),
                Err(err) => check(name, &err, &expect),
            }
            continue;
        }
        let log = res.unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(
            log.skipped_rows.get(file),
            Some(&1),
            "{name}: {:?}",
            log.skipped_rows
        );
        assert_eq!(log.total_skipped_rows(), 1, "{name}");
        let reason = &log.skip_reasons[0];
        if let Expect::Csv(f, line, column, pred) = expect {
            assert_eq!(
                (reason.file.as_str(), reason.line, reason.column.as_str()),
                (f, line, column),
                "{name}"
            );
            assert!(pred(&reason.problem), "{name}");
        }
    }
}

#[test]
fn lenient_keeps_good_rows_around_bad_ones() {
    let dir = sample_dir("keep");
    apply(
        dir.path(),
        "depth.csv",
        Some("t,depth\n0.1,1\n0.3,3\n0.2,2\nx,4\n0.3,5\n0.4,4,4\n0.5,5\n"),
    );
    let log = LogDir::read(dir.path(), Strictness::Lenient).unwrap();
    let depth = log.depth.unwrap();
    assert_eq!(
        depth,
        vec![
            DepthRow::new(0.1, 1.0),
            DepthRow::new(0.3, 3.0),
            DepthRow::new(0.5, 5.0)
        ]
    );
    assert_eq!(log.skipped_rows["depth.csv"], 4);
    let lines: Vec<u64> = log.skip_reasons.iter().map(|r| r.line).collect();
    assert_eq!(lines, vec![4, 5, 6, 7]);
}

#[test]
fn absent_aiding_files_are_absent_sensors() {
    let dir = sample_dir("absent");
    for f in [
        "dvl.csv",
        "depth.csv",
        "heading.csv",
        "usbl.csv",
        "speed.csv",
        "rpm.csv",
        "altitude.csv",
        "truth.csv",
    ] {
        std::fs::remove_file(dir.path().join(f)).unwrap();
    }
    let log = LogDir::read(dir.path(), Strictness::Strict).unwrap();
    assert!(log.dvl.is_none() && log.depth.is_none() && log.truth.is_none() && log.rpm.is_none());
    assert_eq!(log.imu.len(), 40);
    assert_eq!(log.events().count(), 40);
}

#[test]
fn dvl_empty_cells_are_no_lock() {
    let dir = sample_dir("dvl");
    apply(
        dir.path(),
        "dvl.csv",
        Some("t,vx,vy,vz\n0.1,,,\n0.2,1, ,3\n"),
    );
    let log = LogDir::read(dir.path(), Strictness::Strict).unwrap();
    let dvl = log.dvl.unwrap();
    assert_eq!(dvl[0], DvlRow::new(0.1, None, None, None));
    assert_eq!(dvl[0].velocity(), None);
    assert_eq!(dvl[1], DvlRow::new(0.2, Some(1.0), None, Some(3.0)));
}

#[test]
fn header_tolerates_spaces_and_byte_order_mark() {
    let dir = sample_dir("bom");
    apply(
        dir.path(),
        "depth.csv",
        Some("\u{feff}t, depth\n 0.1 , 2 \n"),
    );
    let log = LogDir::read(dir.path(), Strictness::Strict).unwrap();
    assert_eq!(log.depth.unwrap(), vec![DepthRow::new(0.1, 2.0)]);
}

#[test]
fn not_a_directory_is_an_io_error() {
    let dir = TempDir::new("nodir");
    let missing = dir.path().join("nope");
    let err = LogDir::read(&missing, Strictness::Strict).unwrap_err();
    assert!(matches!(err, LogError::Io { .. }));
    assert!(err.to_string().contains("nope"));
}

/// Meta problems whose message must say more than the key: the likely cause
/// or the closest valid name.
#[test]
fn meta_messages_name_the_likely_cause() {
    for (text, needle) in [
        (
            "[initial]\nlat = 0.1\nlon = 0.2\ndepth = 3\nyaw = 179.9\n",
            "degrees?",
        ),
        (
            "[initial]\nlat = 0.1\nlon = 0.2\ndepth = 3\nlatt = 1\n",
            "did you mean `lat`?",
        ),
        (
            "[initial]\nlat = 0.1\nlon = 0.2\ndepth = 3\n[sensors.dvl]\nnoise_sgima = 1\n",
            "did you mean `noise_sigma`?",
        ),
        (
            "[initial]\nlat = 0.1\nlon = 0.2\ndepth = 3\n[sensors.dvll]\nnoise_sigma = 1\n",
            "did you mean `dvl`?",
        ),
        (
            "[initial]\nlat = 0.1\nlon = 0.2\ndepth = 3\n[sensors.dvl]\nnoise_sigma = 0\n",
            "must be > 0",
        ),
        (
            "[initial]\nlat = 0.1\nlon = 0.2\ndepth = 3\n[initial_sigma]\nposition = 1e200\n",
            "its square finite",
        ),
        (
            "[initial]\nlat = 0.1\nlon = 0.2\ndepth = 3\n[initial_sigma]\nlevel = 5\n",
            "degrees?",
        ),
        (
            "[initial]\nlat = 0.1\nlon = 0.2\ndepth = 3\n[sensors.heading]\nnoise_sigma = 10\n",
            "degrees?",
        ),
    ] {
        let msg = Meta::parse(text).unwrap_err().to_string();
        assert!(msg.contains(needle), "{text:?}: {msg}");
    }
}

/// Another tool's top-level sections are accepted and listed as warnings
/// naming the section and its line; the new `[initial] t` and USBL
/// misalignment keys are read and round-trip.
#[test]
fn meta_unknown_sections_are_warnings_and_new_keys_are_read() {
    let text = "[vehicle]\nname = \"x\"\n[initial]\nt = 2.5\nlat = 0.1\nlon = 0.2\ndepth = 3\n\
                [sensors.usbl]\nnoise_sigma = 1\nbias_sigma = 0.5\nmisalignment_sigma = 0.001\n\
                [generator.settings]\nseed = 4\n";
    let (meta, warnings) = Meta::parse_with_warnings(text).unwrap();
    assert_eq!(meta.initial.t, Some(2.5));
    assert_eq!(meta.sensors.usbl_misalignment_sigma, Some(0.001));
    let names: Vec<_> = warnings
        .iter()
        .map(|w| (w.key.clone().unwrap(), w.line))
        .collect();
    assert_eq!(
        names,
        [
            ("generator".to_string(), Some(12)),
            ("vehicle".to_string(), Some(1))
        ]
    );
    assert!(warnings
        .iter()
        .all(|w| w.kind == WarningKind::UnknownSection));
    assert_eq!(Meta::parse(&meta.to_toml()).unwrap(), meta);
    let bare = Meta::parse("[initial]\nlat = 0\nlon = 1\ndepth = 5\n").unwrap();
    assert_eq!(
        (bare.initial.t, bare.sensors.usbl_misalignment_sigma),
        (None, None)
    );
    // The reader carries them into the log's warnings.
    let dir = sample_dir("unknown-section");
    let meta_path = dir.path().join("meta.toml");
    let old = std::fs::read_to_string(&meta_path).unwrap();
    std::fs::write(
        &meta_path,
        format!("{old}\n[generator]\nname = \"other\"\n"),
    )
    .unwrap();
    let log = LogDir::read(dir.path(), Strictness::Strict).unwrap();
    assert_eq!(log.warnings.len(), 1, "{:?}", log.warnings);
    assert!(log.warnings[0].to_string().starts_with("meta.toml:"));
}

/// A symbolic link whose target is gone is an error naming the link, not
/// an absent sensor.
#[cfg(unix)]
#[test]
fn dangling_symlink_is_an_error() {
    let dir = sample_dir("dangling");
    std::fs::remove_file(dir.path().join("dvl.csv")).unwrap();
    std::os::unix::fs::symlink(dir.path().join("gone.csv"), dir.path().join("dvl.csv")).unwrap();
    let err = LogDir::read(dir.path(), Strictness::Lenient).unwrap_err();
    let msg = err.to_string();
    assert!(
        msg.contains("dvl.csv") && msg.contains("does not exist"),
        "{msg}"
    );
}

#[test]
fn meta_accepts_minimal_and_integers() {
    let m = Meta::parse("[initial]\nlat = 0\nlon = 1\ndepth = 5\n").unwrap();
    assert_eq!(m.initial.lon, 1.0);
    assert_eq!(m.initial.roll, None);
    assert!(m.initial.attitude().is_err());
    assert_eq!(
        m.initial.attitude().unwrap_err().column(),
        Some("initial.roll")
    );
    assert!(m.sensors.imu.is_none() && m.usbl.is_none() && m.initial_sigma.is_none());
}

/// A `.csv` file the format does not define (a misnamed or unsupported
/// sensor) is refused by the strict reader with a typed error naming it; the
/// lenient reader reads the log and lists it. Other extensions are not looked
/// at, and a directory named like a CSV file is not a file.
#[test]
fn unknown_csv_files_are_refused_strictly_and_listed_leniently() {
    let dir = sample_dir("unknown");
    std::fs::write(dir.path().join("sonar.csv"), "t,range\n0.1,3\n").unwrap();
    std::fs::write(dir.path().join("IMU.CSV"), "").unwrap();
    std::fs::write(dir.path().join("notes.txt"), "not a log file").unwrap();
    std::fs::create_dir(dir.path().join("plots.csv")).unwrap();
    let err = LogDir::read(dir.path(), Strictness::Strict).unwrap_err();
    // Sorted by name: `IMU.CSV` before `sonar.csv`.
    match &err {
        LogError::UnknownFile { file, dir: d } => {
            assert_eq!((file.as_str(), d.as_path()), ("IMU.CSV", dir.path()));
        }
        other => panic!("{other:?}"),
    }
    assert_eq!(err.file(), Some("IMU.CSV"));
    let text = err.to_string();
    assert!(
        text.starts_with("IMU.CSV: unknown log file") && !text.contains('\n'),
        "{text}"
    );
    let log = LogDir::read(dir.path(), Strictness::Lenient).unwrap();
    assert_eq!(log.unknown_files, vec!["IMU.CSV", "sonar.csv"]);
    assert_eq!(log.total_skipped_rows(), 0);
    assert_eq!(log.imu.len(), 40);
    // Without them the strict reader accepts the log and lists nothing.
    std::fs::remove_file(dir.path().join("sonar.csv")).unwrap();
    std::fs::remove_file(dir.path().join("IMU.CSV")).unwrap();
    let log = LogDir::read(dir.path(), Strictness::Strict).unwrap();
    assert!(log.unknown_files.is_empty());
}
