//! Bad log directories: every error names file, line and column (or meta key).

use crate::common;

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
        ("latitude out of range", "usbl.csv", Some("t,lat,lon,depth\n0.1,1.6,0.2,3\n"),
            Csv("usbl.csv", 2, "lat", |p| matches!(p, P::OutOfRange { .. })), false),
        ("negative altitude", "altitude.csv", Some("t,altitude\n0.1,-1\n"),
            Csv("altitude.csv", 2, "altitude", |p| matches!(p, P::OutOfRange { .. })), false),
        ("NaN time of an aiding file", "usbl.csv", Some("t,lat,lon,depth\n0.1,0.7,0.2,3\nNaN,0.7,0.2,3\n"),
            Csv("usbl.csv", 3, "t", |p| matches!(p, P::NonFinite { .. })), false),
        ("infinite time", "speed.csv", Some("t,speed\ninf,1\n"),
            Csv("speed.csv", 2, "t", |p| matches!(p, P::NonFinite { .. })), false),
        ("infinity in the IMU", "imu.csv", Some("t,gx,gy,gz,ax,ay,az\n0,0,0,0,0,0,0\n0.01,inf,0,0,0,0,0\n"),
            Csv("imu.csv", 3, "gx", |p| matches!(p, P::NonFinite { .. })), false),
        ("time backwards", "rpm.csv", Some("t,rpm\n0.1,100\n0.3,100\n0.2,100\n"),
            Csv("rpm.csv", 4, "t", |p| matches!(p, P::TimeBackwards { .. })), false),
        ("duplicate timestamp", "altitude.csv", Some("t,altitude\n0.1,5\n0.1,5\n"),
            Csv("altitude.csv", 3, "t", |p| matches!(p, P::DuplicateTime { .. })), false),
        ("longitude out of range", "truth.csv", Some("t,lat,lon,depth,vn,ve,vd,roll,pitch,yaw\n0,0.1,7,0,0,0,0,0,0,0\n"),
            Csv("truth.csv", 2, "lon", |p| matches!(p, P::OutOfRange { .. })), false),
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
        ("meta initial lever arm without attitude", "meta.toml",
            Some("[initial]\nlat = 0.1\nlon = 0.2\ndepth = 3\nroll = 0\npitch = 0\nlever_arm = [1.8, 0, 0]\n"),
            Meta("initial.lever_arm", Some(7)), true),
        ("meta initial lever arm without position", "meta.toml",
            Some("[initial]\nroll = 0\npitch = 0\nyaw = 0\nlever_arm = [1.8, 0, 0]\n"),
            Meta("initial.lever_arm", Some(5)), true),
        ("meta initial lever arm of two numbers", "meta.toml",
            Some("[initial]\nlat = 0.1\nlon = 0.2\ndepth = 3\nlever_arm = [1.8, 0]\n"),
            Meta("initial.lever_arm", Some(5)), true),
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
            // A syntax error names no key (`""` in the table).
            assert_eq!(err.column().unwrap_or(""), *key, "{name}: {msg}");
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
        // An absurd value in scientific notation, not as 201 digits.
        (
            "[initial]\nlat = 0.1\nlon = 0.2\ndepth = 3\n[sensors.dvl]\nnoise_sigma = 1e200\n",
            "value 1e200 out of range",
        ),
        // And a vanishing one, not as 301 digits.
        (
            "[initial]\nlat = 0.1\nlon = 0.2\ndepth = 3\n[sensors.dvl]\nnoise_sigma = 1e-300\n",
            "value 1e-300 out of range",
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

/// A value above the first header is an unknown key at its line, not a
/// section of no line; a syntax error names no empty key (it printed
/// "meta.toml:1: ``: ...").
#[test]
fn meta_top_level_keys_and_syntax_errors_are_worded_for_what_they_are() {
    let (_, warnings) =
        Meta::parse_with_warnings("source = \"x\"\n[initial]\nlat = 0.1\nlon = 0.2\ndepth = 3\n")
            .unwrap();
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert_eq!(warnings[0].line, Some(1), "{warnings:?}");
    assert!(
        warnings[0].message.starts_with("unknown key `source`"),
        "{}",
        warnings[0]
    );
    let e = Meta::parse("[initial\nlat = 1\n").unwrap_err();
    assert_eq!(e.column(), None, "{e:?}");
    let text = e.to_string();
    assert!(
        text.starts_with("meta.toml:1: ") && !text.contains("``"),
        "{text}"
    );
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

/// What reading an aiding file with non-physical readings gives.
#[derive(Debug)]
enum Rejection {
    /// The rows kept (their times), the count rejected, the first one's
    /// line and column.
    Skipped(Vec<f64>, usize, u64, &'static str),
    /// A strict error at this line and column: too many rejected to be
    /// glitches.
    TooMany(u64, &'static str),
}

/// (case, file, content, strict result)
type RejectionCase = (&'static str, &'static str, String, Rejection);

fn rejection_cases() -> Vec<RejectionCase> {
    use Rejection::*;
    let depth_rows = |glitches: &[usize], n: usize| {
        let mut s = String::from("t,depth\n");
        for i in 0..n {
            let v = if glitches.contains(&i) {
                "1e300"
            } else {
                "12.5"
            };
            s.push_str(&format!("{},{v}\n", i as f64 * 0.1));
        }
        s
    };
    let every_tenth: Vec<usize> = (0..200).step_by(10).collect();
    vec![
        (
            "one 1e300 in the DVL",
            "dvl.csv",
            "t,vx,vy,vz\n0.1,1,0,0\n0.2,1e300,0,0\n0.3,1,0,0\n".into(),
            Skipped(vec![0.1, 0.3], 1, 3, "vx"),
        ),
        (
            "inf in the depth",
            "depth.csv",
            "t,depth\n0.1,1\n0.2,inf\n0.3,1\n".into(),
            Skipped(vec![0.1, 0.3], 1, 3, "depth"),
        ),
        (
            "nan in the compass",
            "heading.csv",
            "t,heading\n0.1,nan\n0.2,1\n".into(),
            Skipped(vec![0.2], 1, 2, "heading"),
        ),
        (
            "a latitude beyond the pole in the USBL",
            "usbl.csv",
            "t,lat,lon,depth\n0.1,0.7,0.2,3\n0.2,1.6,0.2,3\n".into(),
            Skipped(vec![0.1], 1, 3, "lat"),
        ),
        (
            "a negative altitude",
            "altitude.csv",
            "t,altitude\n0.1,5\n0.2,-1\n".into(),
            Skipped(vec![0.1], 1, 3, "altitude"),
        ),
        (
            "a speed beyond any vehicle's",
            "speed.csv",
            "t,speed\n0.1,1\n0.2,-2e4\n".into(),
            Skipped(vec![0.1], 1, 3, "speed"),
        ),
        (
            "ten glitches are glitches",
            "depth.csv",
            depth_rows(&[1, 2, 3, 4, 5, 6, 7, 8, 9, 10], 20),
            Skipped(
                (11..20).map(|i| i as f64 * 0.1).chain([0.0]).collect(),
                10,
                3,
                "depth",
            ),
        ),
        (
            "eleven in twenty are a mistake",
            "depth.csv",
            depth_rows(&[1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11], 20),
            TooMany(3, "depth"),
        ),
        (
            "one row in ten over 200 rows is a mistake",
            "depth.csv",
            depth_rows(&every_tenth, 200),
            TooMany(2, "depth"),
        ),
        (
            "every row rejected",
            "rpm.csv",
            "t,rpm\n0.1,inf\n0.2,inf\n".into(),
            TooMany(2, "rpm"),
        ),
    ]
}

/// Read with `NonPhysical::Rejected`, one non-physical reading in an aiding
/// file is a skipped row with a warning (count, first line), not a refused
/// log; too many are an error when strict; a lenient reader skips them all.
#[test]
fn non_physical_readings_of_aiding_files_are_rejected_rows() {
    for (name, file, content, expect) in rejection_cases() {
        for strictness in [Strictness::Strict, Strictness::Lenient] {
            let dir = sample_dir("rejected");
            apply(dir.path(), file, Some(&content));
            let res = LogDir::read_with(dir.path(), strictness, NonPhysical::Rejected);
            let (kept, count, line, column) = match (&expect, strictness) {
                (Rejection::TooMany(line, column), Strictness::Strict) => {
                    let err = res.err().unwrap_or_else(|| panic!("{name}: accepted"));
                    assert_eq!(
                        (err.file(), err.line(), err.column()),
                        (Some(file), Some(*line), Some(*column)),
                        "{name}: {err}"
                    );
                    assert!(
                        matches!(err.csv_problem(), Some(CsvProblem::TooManyRejected { .. })),
                        "{name}: {err}"
                    );
                    // The rule that fired is said: every row, or more than
                    // the floor and the share (the latter was said of both).
                    let every = name == "every row rejected";
                    let said = if every {
                        "all 2 rows rejected"
                    } else {
                        "more than 10 and one in"
                    };
                    assert!(err.to_string().contains(said), "{name}: {err}");
                    continue;
                }
                (Rejection::TooMany(line, column), Strictness::Lenient) => {
                    (None, None, *line, *column)
                }
                (Rejection::Skipped(kept, count, line, column), _) => {
                    (Some(kept.clone()), Some(*count), *line, *column)
                }
            };
            let log = res.unwrap_or_else(|e| panic!("{name} ({strictness:?}): {e}"));
            let times: Vec<f64> = match file {
                "dvl.csv" => log.dvl.iter().flatten().map(|r| r.t).collect(),
                "depth.csv" => log.depth.iter().flatten().map(|r| r.t).collect(),
                "heading.csv" => log.heading.iter().flatten().map(|r| r.t).collect(),
                "usbl.csv" => log.usbl.iter().flatten().map(|r| r.t).collect(),
                "altitude.csv" => log.altitude.iter().flatten().map(|r| r.t).collect(),
                "speed.csv" => log.speed.iter().flatten().map(|r| r.t).collect(),
                _ => log.rpm.iter().flatten().map(|r| r.t).collect(),
            };
            if let Some(mut kept) = kept {
                kept.sort_by(f64::total_cmp);
                assert_eq!(times, kept, "{name} ({strictness:?})");
            }
            // Rejected rows are not skipped rows of a lenient reading.
            assert_eq!(log.total_skipped_rows(), 0, "{name} ({strictness:?})");
            let warnings: Vec<&Warning> = log
                .warnings
                .iter()
                .filter(|w| w.kind == WarningKind::RejectedReading)
                .collect();
            assert_eq!(
                warnings.len(),
                1,
                "{name} ({strictness:?}): {:?}",
                log.warnings
            );
            let w = warnings[0];
            assert_eq!(
                (w.file.as_deref(), w.line, w.key.as_deref()),
                (Some(file), Some(line), Some(column)),
                "{name} ({strictness:?}): {w}"
            );
            if let Some(count) = count {
                assert!(
                    w.message.starts_with(&format!("{count} row")),
                    "{name} ({strictness:?}): {w}"
                );
            }
        }
    }
}

/// The rows a replay streams skip the rejected one (it is never fed), and
/// the log's readers tell what they rejected once read (one warning per file, the larger
/// count when two readers read the same file).
#[test]
fn a_streamed_replay_skips_rejected_rows_and_learns_them() {
    let dir = sample_dir("rejected-stream");
    apply(
        dir.path(),
        "dvl.csv",
        Some("t,vx,vy,vz\n0.05,1,0,0\n0.15,1e300,0,0\n0.25,1,0,inf\n0.3,1,0,0\n"),
    );
    // By default (as before) the non-finite cell refuses the log.
    let err = LogDir::read(dir.path(), Strictness::Strict).unwrap_err();
    assert_eq!((err.line(), err.column()), (Some(4), Some("vz")), "{err}");
    let files = LogFiles::open(dir.path(), Strictness::Strict)
        .unwrap()
        .with_non_physical(NonPhysical::Rejected);
    let mut events = EventStream::open(&files).unwrap();
    let mut dvl = Vec::new();
    while let Some(e) = events.next_event().unwrap() {
        if let Event::Dvl(r) = e.event {
            dvl.push((e.line, r.t));
        }
    }
    assert_eq!(dvl, vec![(Some(2), 0.05), (Some(5), 0.3)]);
    // A second reader of the same file (a check beside the replay).
    let mut again = files.rows::<DvlRow>().unwrap().unwrap();
    while again.next_row().unwrap().is_some() {}
    assert_eq!(again.rejected().map(|r| r.count), Some(2));
    let warnings = files.clone().rejected_warnings();
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    let w = &warnings[0];
    assert_eq!(w.kind.as_str(), "rejected_reading");
    assert_eq!(
        (w.file.as_deref(), w.line, w.key.as_deref()),
        (Some("dvl.csv"), Some(3), Some("vx"))
    );
    assert!(w.message.starts_with("2 rows skipped"), "{w}");
}

/// A header of `n` extra columns after `t,depth`, named `c0`, `c1`, ...
fn wide_header(n: usize) -> String {
    let mut s = String::from("t,depth");
    for i in 0..n {
        s.push_str(&format!(",c{i}"));
    }
    s.push('\n');
    s
}

/// A mapping of `depth.csv` that ignores the columns `c0..c{n}`.
fn ignoring(n: usize) -> FileMapping {
    let meta = format!(
        "[initial]\nlat = 0.1\nlon = 0.2\ndepth = 3\n[files.depth]\nignore = [{}]\n",
        (0..n)
            .map(|i| format!("\"c{i}\""))
            .collect::<Vec<_>>()
            .join(",")
    );
    Meta::parse_log(&meta).unwrap().1.of::<DepthRow>()
}

/// A very wide header costs work linear in its length: beyond
/// `MAX_COLUMNS` it is refused after one pass over its bytes (a million
/// columns took 31.6 s for 60,000 when the lookups were quadratic), and
/// below, the header check's work (cells and name lookups, counted by the
/// reader) grows as the header does. Work is counted, never timed.
#[test]
fn wide_headers_cost_linear_work_or_are_refused() {
    // (extra columns, ignored by the mapping, expected outcome: `Some(n)`
    // refused with n columns found, `None` read)
    let cases: [(usize, bool, Option<usize>); 4] = [
        (1_000_000, false, Some(1_000_002)),
        (MAX_COLUMNS - 1, false, Some(MAX_COLUMNS + 1)),
        (MAX_COLUMNS - 2, true, None),
        ((MAX_COLUMNS - 2) / 2, true, None),
    ];
    let mut work = Vec::new();
    for (n, ignored, refused) in cases {
        let text = format!("{}0.5,1{}\n", wide_header(n), ",0".repeat(n));
        let mapping = if ignored {
            ignoring(n)
        } else {
            FileMapping::standard::<DepthRow>()
        };
        let read =
            RowReader::<DepthRow, _>::with_mapping(text.as_bytes(), Strictness::Strict, &mapping);
        match (read, refused) {
            (Err(err), Some(found)) => {
                assert_eq!(
                    (err.line(), err.file()),
                    (Some(1), Some("depth.csv")),
                    "{err}"
                );
                assert!(
                    matches!(err.csv_problem(), Some(CsvProblem::TooManyColumns { found: f, limit }) if *f == found && *limit == MAX_COLUMNS),
                    "{n}: {err}"
                );
                assert!(err.to_string().len() < 200, "{err}");
            }
            (Ok(mut reader), None) => {
                assert_eq!(
                    reader.next_row().unwrap().map(|(_, r)| r),
                    Some(DepthRow::new(0.5, 1.0))
                );
                work.push((n, reader.header_work()));
            }
            (r, want) => panic!("{n} columns: {:?}, expected refused = {want:?}", r.err()),
        }
    }
    // Linear: the work per column is a small constant, the same for a
    // header twice as wide (a quadratic lookup would double it per column).
    let per_column: Vec<f64> = work
        .iter()
        .map(|(n, w)| *w as f64 / (*n + 2) as f64)
        .collect();
    assert!(per_column.iter().all(|p| *p <= 5.0), "{work:?}");
    assert!(
        (per_column[0] / per_column[1] - 1.0).abs() < 0.05,
        "{work:?}"
    );
}

/// An unknown column in a wide mapped header names the first few, not
/// every one of them.
#[test]
fn many_unknown_columns_are_summed_up() {
    let n = 3000;
    let text = format!("{}0.5,1{}\n", wide_header(n), ",0".repeat(n));
    let err =
        RowReader::<DepthRow, _>::with_mapping(text.as_bytes(), Strictness::Strict, &ignoring(2))
            .expect_err("refused");
    let msg = err.to_string();
    assert!(
        msg.contains("`c2`") && msg.contains("and 2990 more"),
        "{msg}"
    );
    assert!(msg.len() < 400, "{msg}");
}
