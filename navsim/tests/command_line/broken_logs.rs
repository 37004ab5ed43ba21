//! The broken-log suite: realistic defects of a recorded log, each run through
//! the `navsim` binary and classified. A case is one row of [`cases`]:
//!
//! - `Correct`: exit 0, a JSON result whose error figures are finite numbers;
//! - `Error`: exit 1, nothing on stdout, exactly one `error:` line on stderr
//!   containing every given text (the file and line, column or key, and the
//!   likely cause);
//! - `Warn`: exit 0 and a JSON `warnings` entry of the given kind whose text
//!   (file, key and message) contains the given text.
//!
//! Each case starts from a fresh copy of one small simulated survey log.
//! Cases marked `Needs::Pipeline` depend on the in-loop work of the replay
//! pipeline (bounded time steps, physical bounds on the estimate); they are
//! run by `pipeline_cases`, ignored until that work is merged.

use crate::common;

use std::path::Path;
use std::sync::OnceLock;

use common::{navsim, stderr, stdout, SharedDir, TempDir};
use models::sdins25::simulation::{simulate, SimConfig};
use serde_json::Value;

/// What a case expects.
#[derive(Debug, Clone, Copy)]
enum Expect {
    Correct,
    Error(&'static [&'static str]),
    Warn(&'static str, &'static str),
}

/// Whose work makes the case pass.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Needs {
    /// Passes on this branch.
    Here,
    /// Needs the replay pipeline's in-loop checks.
    Pipeline,
}

/// (name, class, edit of the log directory, extra arguments, expectation, needs)
type Case = (
    &'static str,
    &'static str,
    fn(&Path),
    &'static [&'static str],
    Expect,
    Needs,
);

/// The base log: 60 s of the USBL survey (IMU 100 Hz, DVL, depth, compass,
/// USBL fixes, truth), written once and copied per case.
fn base() -> &'static Path {
    static DIR: OnceLock<SharedDir> = OnceLock::new();
    DIR.get_or_init(|| {
        let d = SharedDir::new("broken-base");
        let config = SimConfig {
            duration: 60.0,
            ..SimConfig::usbl()
        };
        simulate(&config, 4)
            .log
            .write(d.path().join("log"))
            .unwrap();
        d
    })
    .path()
}

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        std::fs::copy(e.path(), to.join(e.file_name())).unwrap();
    }
}

// ---- edits ---------------------------------------------------------------

/// Rewrites every data row of `file` (row index from 0, cells as text).
fn rows(dir: &Path, file: &str, f: impl Fn(usize, &mut Vec<String>)) {
    let path = dir.join(file);
    let text = std::fs::read_to_string(&path).unwrap();
    let mut lines = text.lines();
    let mut out = format!("{}\n", lines.next().unwrap());
    for (i, line) in lines.enumerate() {
        let mut cells: Vec<String> = line.split(',').map(String::from).collect();
        f(i, &mut cells);
        if !cells.is_empty() {
            out.push_str(&cells.join(","));
            out.push('\n');
        }
    }
    std::fs::write(path, out).unwrap();
}

/// Multiplies columns `cols` of every row by `k` (empty cells stay empty).
fn scale(dir: &Path, file: &str, cols: &[usize], k: f64) {
    rows(dir, file, |_, c| {
        for &j in cols {
            if let Ok(v) = c[j].parse::<f64>() {
                c[j] = format!("{}", v * k);
            }
        }
    });
}

/// Adds `k` to column `col` of every row.
fn add_to(dir: &Path, file: &str, col: usize, k: f64) {
    rows(dir, file, |_, c| {
        c[col] = format!("{}", c[col].parse::<f64>().unwrap() + k);
    });
}

/// Sets column `col` of data row `row` to `value`.
fn cell(dir: &Path, file: &str, row: usize, col: usize, value: &str) {
    rows(dir, file, |i, c| {
        if i == row {
            c[col] = value.to_string();
        }
    });
}

/// Drops data rows in `from..to`.
fn drop_rows(dir: &Path, file: &str, from: usize, to: usize) {
    rows(dir, file, |i, c| {
        if (from..to).contains(&i) {
            c.clear();
        }
    });
}

/// Adds `dt` to the time of data rows from `from` on.
fn shift_from(dir: &Path, file: &str, from: usize, dt: f64) {
    rows(dir, file, |i, c| {
        if i >= from {
            c[0] = format!("{}", c[0].parse::<f64>().unwrap() + dt);
        }
    });
}

/// Adds `dt` to the time of every row of every sensor and truth file.
fn shift_all(dir: &Path, dt: f64) {
    for f in [
        "imu.csv",
        "dvl.csv",
        "depth.csv",
        "heading.csv",
        "usbl.csv",
        "altitude.csv",
        "truth.csv",
    ] {
        shift_from(dir, f, 0, dt)
    }
}

/// Replaces the `key = ...` line of `[section]` of meta.toml by `line` (or
/// appends it to the section when the key is absent).
/// An accelerometer noise sigma whose square is finite but no sensor's.
fn accel_noise_1e50(dir: &Path) {
    meta_key(
        dir,
        "sensors.imu",
        "accel_noise_sigma",
        "accel_noise_sigma = 1e50",
    );
}

fn meta_key(dir: &Path, section: &str, key: &str, line: &str) {
    let path = dir.join("meta.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let mut out: Vec<String> = Vec::new();
    let mut current = String::new();
    let mut done = false;
    for l in text.lines() {
        if l.starts_with('[') {
            if current == section && !done {
                out.push(line.to_string());
                done = true;
            }
            current = l.trim_matches(|c| c == '[' || c == ']').to_string();
        } else if current == section && l.split('=').next().map(str::trim) == Some(key) {
            out.push(line.to_string());
            done = true;
            continue;
        }
        out.push(l.to_string());
    }
    if !done {
        if current != section {
            out.push(format!("[{section}]"));
        }
        out.push(line.to_string());
    }
    std::fs::write(path, out.join("\n") + "\n").unwrap();
}

/// Removes the `[section]` of meta.toml with its keys.
fn meta_drop_section(dir: &Path, section: &str) {
    let path = dir.join("meta.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let mut out = Vec::new();
    let mut skip = false;
    for l in text.lines() {
        if l.starts_with('[') {
            skip = l.trim_matches(|c| c == '[' || c == ']') == section;
        }
        if !skip {
            out.push(l);
        }
    }
    std::fs::write(path, out.join("\n") + "\n").unwrap();
}

fn append(dir: &Path, file: &str, text: &str) {
    let path = dir.join(file);
    let old = std::fs::read_to_string(&path).unwrap_or_default();
    std::fs::write(path, old + text).unwrap();
}

fn last_time(dir: &Path, file: &str) -> f64 {
    let text = std::fs::read_to_string(dir.join(file)).unwrap();
    text.lines()
        .last()
        .unwrap()
        .split(',')
        .next()
        .unwrap()
        .parse()
        .unwrap()
}

/// Freezes the gyro triple of IMU rows `from..to` at the value of row `from`.
fn freeze(dir: &Path, from: usize, to: usize) {
    freeze_columns(dir, from, to, 1..4);
}

/// Holds columns `columns` of `imu.csv` (1-3 gyro, 4-6 accelerometer) at
/// their values of data row `from` over data rows `from..to`.
fn freeze_columns(dir: &Path, from: usize, to: usize, columns: std::ops::Range<usize>) {
    let text = std::fs::read_to_string(dir.join("imu.csv")).unwrap();
    let frozen: Vec<String> = text
        .lines()
        .nth(from + 1)
        .unwrap()
        .split(',')
        .map(String::from)
        .collect();
    rows(dir, "imu.csv", |i, c| {
        if (from..to).contains(&i) {
            c[columns.clone()].clone_from_slice(&frozen[columns.clone()]);
        }
    });
}

const SDINS: &[&str] = &[];
const LENIENT: &[&str] = &["--lenient"];

fn cases() -> Vec<Case> {
    use Expect::*;
    use Needs::*;
    vec![
        // -- units, signs, frames
        (
            "accelerometer in g",
            "units",
            |d| scale(d, "imu.csv", &[4, 5, 6], 1.0 / 9.80665),
            SDINS,
            Error(&["imu.csv:2", "g units?"]),
            Here,
        ),
        (
            "accelerometer scaled x2",
            "units",
            |d| scale(d, "imu.csv", &[4, 5, 6], 2.0),
            SDINS,
            Error(&["imu.csv:2", "wrong unit or scale"]),
            Here,
        ),
        (
            "az sign flipped (FLU)",
            "frames",
            |d| scale(d, "imu.csv", &[6], -1.0),
            SDINS,
            Error(&["imu.csv:2", "`az`", "FLU"]),
            Here,
        ),
        (
            "y and z axes flipped (FLU)",
            "frames",
            |d| scale(d, "imu.csv", &[2, 3, 5, 6], -1.0),
            SDINS,
            Error(&["imu.csv:2", "FLU"]),
            Here,
        ),
        (
            "one gyro sample beyond 2000 deg/s",
            "units",
            |d| cell(d, "imu.csv", 300, 1, "40"),
            SDINS,
            Error(&["imu.csv:302", "deg/s?"]),
            Here,
        ),
        // Named at its line (the mean of the first seconds blamed line 2;
        // later in the file only the filter's arithmetic failed).
        (
            "accelerometer cell 1e300 in the first seconds",
            "values",
            |d| cell(d, "imu.csv", 99, 4, "1e300"),
            SDINS,
            Error(&["imu.csv:101", "not a physical specific force"]),
            Here,
        ),
        (
            "accelerometer cell 1e300 at 40 s",
            "values",
            |d| cell(d, "imu.csv", 3999, 4, "1e300"),
            SDINS,
            Error(&["imu.csv:4001", "not a physical specific force"]),
            Here,
        ),
        (
            "gyro cell 1e300",
            "values",
            |d| cell(d, "imu.csv", 120, 2, "1e300"),
            SDINS,
            Error(&["imu.csv:122", "not a physical rate"]),
            Here,
        ),
        (
            "heading in degrees",
            "units",
            |d| scale(d, "heading.csv", &[1], 180.0 / std::f64::consts::PI),
            SDINS,
            Error(&["heading.csv", "degrees?"]),
            Here,
        ),
        (
            "gyro in rad/s declared deg/s",
            "units",
            |d| meta_key(d, "files.imu", "units", "units = { rate = \"deg/s\" }"),
            SDINS,
            Error(&["imu.csv:2", "files.imu.units declares deg/s", "rad/s?"]),
            Here,
        ),
        (
            "heading in rad declared deg",
            "units",
            |d| meta_key(d, "files.heading", "units", "units = { angle = \"deg\" }"),
            SDINS,
            Error(&[
                "heading.csv",
                "files.heading.units declares deg",
                "radians?",
            ]),
            Here,
        ),
        (
            "heading in degrees beyond 2 pi",
            "units",
            |d| {
                rows(d, "heading.csv", |_, c| {
                    c[1] = format!("{}", c[1].parse::<f64>().unwrap().to_degrees() + 170.0)
                })
            },
            SDINS,
            Error(&["heading.csv", "values reach", "degrees?"]),
            Here,
        ),
        (
            "heading in 0..2pi convention",
            "correct",
            |d| {
                rows(d, "heading.csv", |_, c| {
                    c[1] = format!(
                        "{}",
                        c[1].parse::<f64>()
                            .unwrap()
                            .rem_euclid(std::f64::consts::TAU)
                    )
                })
            },
            SDINS,
            Correct,
            Here,
        ),
        (
            "heading unwrapped: two turns before the log",
            "valid",
            |d| add_to(d, "heading.csv", 1, 2.0 * std::f64::consts::TAU),
            SDINS,
            Correct,
            Here,
        ),
        (
            "heading unwrapped: one turn before the log",
            "valid",
            |d| add_to(d, "heading.csv", 1, std::f64::consts::TAU),
            SDINS,
            Correct,
            Here,
        ),
        (
            "truth yaw unwrapped: one turn before the log",
            "valid",
            |d| add_to(d, "truth.csv", 9, std::f64::consts::TAU),
            SDINS,
            Correct,
            Here,
        ),
        (
            "heading in degrees, one turn added (wraps at 360)",
            "units",
            |d| {
                rows(d, "heading.csv", |i, c| {
                    let deg = c[1].parse::<f64>().unwrap().to_degrees() + 355.0;
                    // Past 360 the logger wraps to 0.
                    c[1] = format!("{}", if i % 2 == 0 { deg } else { deg - 360.0 });
                })
            },
            SDINS,
            Error(&["heading.csv", "degrees?"]),
            Here,
        ),
        (
            "truth yaw in degrees",
            "units",
            |d| {
                rows(d, "truth.csv", |_, c| {
                    c[9] = format!("{}", c[9].parse::<f64>().unwrap().to_degrees() + 90.0)
                })
            },
            SDINS,
            Error(&["truth.csv", "`yaw`", "degrees?"]),
            Here,
        ),
        (
            "depth sign flipped",
            "signs",
            |d| scale(d, "depth.csv", &[1], -1.0),
            SDINS,
            Error(&["depth.csv:2", "sign"]),
            Here,
        ),
        (
            "depth in feet",
            "units",
            |d| scale(d, "depth.csv", &[1], 1.0 / 0.3048),
            SDINS,
            Error(&["depth.csv:2", "feet?"]),
            Here,
        ),
        (
            "[initial] depth sign flipped",
            "signs",
            |d| {
                let t = std::fs::read_to_string(d.join("meta.toml")).unwrap();
                let v: f64 = t.lines().find(|l| l.starts_with("depth =")).unwrap()[8..]
                    .trim()
                    .parse()
                    .unwrap();
                meta_key(d, "initial", "depth", &format!("depth = {}", -v));
            },
            SDINS,
            Error(&["depth.csv:2", "sign"]),
            Here,
        ),
        (
            "[initial] depth 1e300",
            "values",
            |d| meta_key(d, "initial", "depth", "depth = 1e300"),
            SDINS,
            Error(&["meta.toml", "initial.depth", "physical depth"]),
            Here,
        ),
        (
            "[usbl] transducer depth 1e9",
            "values",
            |d| meta_key(d, "usbl", "depth", "depth = 1e9"),
            SDINS,
            Error(&["meta.toml", "usbl.depth", "physical depth"]),
            Here,
        ),
        (
            "[initial] vn 1e6",
            "values",
            |d| meta_key(d, "initial", "vn", "vn = 1e6"),
            SDINS,
            Error(&["meta.toml", "initial.vn", "10000 m/s"]),
            Here,
        ),
        (
            // Within the key's range but beyond the estimate's bound: the
            // run stopped at its first sample blaming the noise settings.
            // Without a DVL (which the preflight compares first, below).
            "[initial] ve 400 beyond the estimate's bound",
            "values",
            |d| {
                meta_key(d, "initial", "ve", "ve = -400");
                std::fs::remove_file(d.join("dvl.csv")).unwrap();
            },
            SDINS,
            Error(&["meta.toml", "initial.ve", "exceeds the 300 m/s"]),
            Here,
        ),
        (
            // Within every bound but 250 m/s off the DVL: the run went on
            // to a horizontal RMS error of 1.1 km, blaming the DVL's sigma.
            "[initial] vn 250 against a DVL at 1.5 m/s",
            "values",
            |d| meta_key(d, "initial", "vn", "vn = 250.0"),
            SDINS,
            Error(&["meta.toml", "initial.vn", "no vehicle carrying a DVL"]),
            Here,
        ),
        (
            // A DVL mounted backwards, declared: its readings are the
            // vehicle's velocity once the mounting turns them, which the
            // comparison with `[initial]` must do as the filter does.
            "DVL mounted backwards, declared",
            "values",
            |d| {
                scale(d, "dvl.csv", &[1, 2], -1.0);
                meta_key(
                    d,
                    "sensors.dvl",
                    "misalignment",
                    "misalignment = [0.0, 0.0, 3.141592653589793]",
                );
            },
            SDINS,
            Correct,
            Here,
        ),
        (
            // The sign of a velocity component flipped: an RMS error six
            // times a correct run's, and no word without truth.
            "[initial] vn of the wrong sign",
            "values",
            |d| {
                let text = std::fs::read_to_string(d.join("meta.toml")).unwrap();
                let vn = text
                    .lines()
                    .find_map(|l| l.strip_prefix("vn = "))
                    .and_then(|v| v.trim().parse::<f64>().ok())
                    .expect("an [initial] vn");
                assert!(vn.abs() > 1.0, "the base log moves north: vn = {vn}");
                meta_key(d, "initial", "vn", &format!("vn = {}", -vn));
            },
            SDINS,
            Warn("suspicious", "initial.vn"),
            Here,
        ),
        (
            // A zero prior made the covariance singular: the NEES of 5.8e14
            // that followed was blamed on truth.csv.
            "[initial_sigma] position 0",
            "values",
            |d| meta_key(d, "initial_sigma", "position", "position = 0.0"),
            SDINS,
            Error(&["meta.toml", "initial_sigma.position", "must be > 0"]),
            Here,
        ),
        (
            // A negative sigma squared is a variance all the same: it was
            // taken silently (so was a negative heading noise sigma).
            "[initial_sigma] velocity negative",
            "values",
            |d| meta_key(d, "initial_sigma", "velocity", "velocity = -0.1"),
            SDINS,
            Error(&["meta.toml", "initial_sigma.velocity", "must be > 0"]),
            Here,
        ),
        (
            "heading noise sigma negative",
            "sigmas",
            |d| meta_key(d, "sensors.heading", "noise_sigma", "noise_sigma = -0.01"),
            SDINS,
            Error(&["meta.toml", "sensors.heading.noise_sigma", "must be > 0"]),
            Here,
        ),
        (
            "[initial_sigma] heading 0",
            "values",
            |d| meta_key(d, "initial_sigma", "heading", "heading = 0"),
            SDINS,
            Error(&["meta.toml", "initial_sigma.heading", "must be > 0"]),
            Here,
        ),
        (
            "USBL depth cell 1e300",
            "values",
            |d| cell(d, "usbl.csv", 2, 3, "1e300"),
            LENIENT,
            // One glitch is a rejected row, not a broken file.
            Warn("rejected_reading", "usbl.csv:4"),
            Here,
        ),
        (
            "DVL in cm/s",
            "units",
            |d| scale(d, "dvl.csv", &[1, 2, 3], 100.0),
            SDINS,
            Error(&["dvl.csv", "cm/s?"]),
            Here,
        ),
        (
            "DVL in mm/s",
            "units",
            |d| scale(d, "dvl.csv", &[1, 2, 3], 1000.0),
            SDINS,
            Error(&["dvl.csv", "mm/s?"]),
            Here,
        ),
        (
            "compass cell 1e300",
            "values",
            |d| cell(d, "heading.csv", 7, 1, "1e300"),
            SDINS,
            Warn("rejected_reading", "heading.csv:9"),
            Here,
        ),
        (
            "depth cell -1e300",
            "values",
            |d| cell(d, "depth.csv", 12, 1, "-1e300"),
            SDINS,
            Warn("rejected_reading", "depth.csv:14"),
            Here,
        ),
        (
            "DVL cell 1e300",
            "values",
            |d| cell(d, "dvl.csv", 5, 1, "1e300"),
            SDINS,
            // One glitch is a rejected row, not a broken file.
            Warn("rejected_reading", "dvl.csv:7"),
            Here,
        ),
        (
            "DVL 30 m/s for 5 s",
            "outliers",
            |d| {
                rows(d, "dvl.csv", |i, c| {
                    if (40..50).contains(&i) {
                        c[1] = "30".into()
                    }
                })
            },
            SDINS,
            Warn("suspicious", "dvl.csv:42"),
            Here,
        ),
        (
            "USBL lat and lon swapped",
            "frames",
            |d| rows(d, "usbl.csv", |_, c| c.swap(1, 2)),
            SDINS,
            Error(&["usbl.csv:2"]),
            Here,
        ),
        (
            "USBL lat in degrees",
            "units",
            |d| scale(d, "usbl.csv", &[1], 180.0 / std::f64::consts::PI),
            SDINS,
            Error(&["usbl.csv:2: column `lat`"]),
            Here,
        ),
        (
            "USBL fix 20 km off",
            "values",
            |d| {
                rows(d, "usbl.csv", |i, c| {
                    if i == 0 {
                        c[1] = format!("{}", c[1].parse::<f64>().unwrap() + 0.003)
                    }
                })
            },
            SDINS,
            Error(&["usbl.csv:2", "lat,lon"]),
            Here,
        ),
        (
            "USBL fix 200 m off",
            "values",
            |d| {
                rows(d, "usbl.csv", |i, c| {
                    if i == 0 {
                        c[1] = format!("{}", c[1].parse::<f64>().unwrap() + 3e-5)
                    }
                })
            },
            SDINS,
            Warn("suspicious", "usbl.csv:2"),
            Here,
        ),
        (
            "[initial] yaw in degrees",
            "units",
            |d| meta_key(d, "initial", "yaw", "yaw = 90.0"),
            SDINS,
            Error(&["meta.toml", "initial.yaw", "degrees?"]),
            Here,
        ),
        (
            "[initial_sigma] heading in degrees",
            "units",
            |d| meta_key(d, "initial_sigma", "heading", "heading = 5.0"),
            SDINS,
            Error(&["meta.toml", "initial_sigma.heading", "degrees?"]),
            Here,
        ),
        (
            "compass noise sigma in degrees",
            "units",
            |d| meta_key(d, "sensors.heading", "noise_sigma", "noise_sigma = 5"),
            SDINS,
            Error(&["sensors.heading.noise_sigma", "degrees?"]),
            Here,
        ),
        (
            "[initial] lat in degrees",
            "units",
            |d| meta_key(d, "initial", "lat", "lat = 36.4"),
            SDINS,
            Error(&["meta.toml", "initial.lat"]),
            Here,
        ),
        // -- DVL mounting calibration (docs/calibration.md)
        (
            "DVL estimate with a misspelt name",
            "sigmas",
            |d| meta_key(d, "sensors.dvl", "estimate", "estimate = [\"scael\"]"),
            SDINS,
            Error(&["meta.toml", "sensors.dvl.estimate", "did you mean `scale`"]),
            Here,
        ),
        (
            "DVL estimate on a vehicle without calibration states",
            "sigmas",
            |d| meta_key(d, "sensors.dvl", "estimate", "estimate = [\"lever_arm\"]"),
            SDINS,
            Error(&["sensors.dvl.estimate", "vehicle sdins25 cannot estimate"]),
            Here,
        ),
        // -- zero and bad sigmas
        (
            "DVL noise sigma 0",
            "sigmas",
            |d| meta_key(d, "sensors.dvl", "noise_sigma", "noise_sigma = 0"),
            SDINS,
            Error(&["meta.toml", "sensors.dvl.noise_sigma", "> 0"]),
            Here,
        ),
        (
            // Its square underflows to 0: the same zero noise.
            "DVL noise sigma 1e-300",
            "sigmas",
            |d| meta_key(d, "sensors.dvl", "noise_sigma", "noise_sigma = 1e-300"),
            SDINS,
            Error(&[
                "meta.toml",
                "sensors.dvl.noise_sigma",
                "square finite and above 0",
            ]),
            Here,
        ),
        (
            "depth noise sigma 0",
            "sigmas",
            |d| meta_key(d, "sensors.depth", "noise_sigma", "noise_sigma = 0.0"),
            SDINS,
            Error(&["sensors.depth.noise_sigma"]),
            Here,
        ),
        (
            "heading noise sigma 0",
            "sigmas",
            |d| meta_key(d, "sensors.heading", "noise_sigma", "noise_sigma = 0"),
            SDINS,
            Error(&["sensors.heading.noise_sigma"]),
            Here,
        ),
        (
            "USBL noise sigma 0",
            "sigmas",
            |d| meta_key(d, "sensors.usbl", "noise_sigma", "noise_sigma = 0"),
            SDINS,
            Error(&["sensors.usbl.noise_sigma"]),
            Here,
        ),
        (
            "gyro noise sigma 0",
            "sigmas",
            |d| meta_key(d, "sensors.imu", "gyro_noise_sigma", "gyro_noise_sigma = 0"),
            SDINS,
            Error(&["sensors.imu.gyro_noise_sigma"]),
            Here,
        ),
        (
            "accelerometer noise sigma 0",
            "sigmas",
            |d| {
                meta_key(
                    d,
                    "sensors.imu",
                    "accel_noise_sigma",
                    "accel_noise_sigma = 0",
                )
            },
            SDINS,
            Error(&["sensors.imu.accel_noise_sigma"]),
            Here,
        ),
        (
            "negative noise sigma",
            "sigmas",
            |d| meta_key(d, "sensors.dvl", "noise_sigma", "noise_sigma = -0.1"),
            SDINS,
            Error(&["sensors.dvl.noise_sigma"]),
            Here,
        ),
        (
            "NaN noise sigma",
            "sigmas",
            |d| meta_key(d, "sensors.depth", "noise_sigma", "noise_sigma = nan"),
            SDINS,
            Error(&["sensors.depth.noise_sigma", "non-finite"]),
            Here,
        ),
        (
            "initial position sigma 1e200",
            "sigmas",
            |d| meta_key(d, "initial_sigma", "position", "position = 1e200"),
            SDINS,
            Error(&["meta.toml", "initial_sigma.position", "square finite"]),
            Here,
        ),
        (
            "DVL noise sigma 1e200",
            "sigmas",
            |d| meta_key(d, "sensors.dvl", "noise_sigma", "noise_sigma = 1e200"),
            SDINS,
            Error(&["sensors.dvl.noise_sigma", "square finite"]),
            Here,
        ),
        (
            "DVL noise sigma 1e-9",
            "sigmas",
            |d| meta_key(d, "sensors.dvl", "noise_sigma", "noise_sigma = 1e-9"),
            SDINS,
            // The filter gates nearly every DVL row: the run is hardly aided.
            Warn("suspicious", "rows of dvl.csv were applied"),
            Here,
        ),
        (
            // A finite square but no sensor's: the covariance was repaired
            // 1586 times and the NEES was NaN (null in the JSON) beside a
            // 1300 km error, with no warning.
            "accelerometer noise sigma 1e50",
            "sigmas",
            accel_noise_1e50,
            SDINS,
            Warn("model", "repaired its covariance"),
            Here,
        ),
        (
            "accelerometer noise sigma 1e50: the NEES",
            "sigmas",
            accel_noise_1e50,
            SDINS,
            Warn("model", "NEES against truth.csv is not a number"),
            Here,
        ),
        (
            "negative misalignment sigma",
            "sigmas",
            |d| {
                meta_key(
                    d,
                    "sensors.usbl",
                    "misalignment_sigma",
                    "misalignment_sigma = -1",
                )
            },
            SDINS,
            Error(&["sensors.usbl.misalignment_sigma"]),
            Here,
        ),
        // -- meta.toml
        (
            "recorder [vehicle] section",
            "meta",
            |d| append(d, "meta.toml", "\n[vehicle]\nname = \"auv-1\"\n"),
            SDINS,
            Warn("unknown_section", "vehicle"),
            Here,
        ),
        (
            "generator [generator] section",
            "meta",
            |d| append(d, "meta.toml", "\n[generator]\nseed = 4\nversion = \"x\"\n"),
            SDINS,
            Warn("unknown_section", "generator"),
            Here,
        ),
        (
            "typo in [initial] key",
            "meta",
            |d| meta_key(d, "initial_sigma", "position", "posiiton = 1.0"),
            SDINS,
            Error(&["meta.toml", "did you mean `position`"]),
            Here,
        ),
        (
            "typo in sensor name",
            "meta",
            |d| append(d, "meta.toml", "\n[sensors.dvll]\nnoise_sigma = 1\n"),
            SDINS,
            Error(&["sensors.dvll", "did you mean `dvl`"]),
            Here,
        ),
        (
            "typo in sensor key",
            "meta",
            |d| meta_key(d, "sensors.dvl", "noise_sigma", "noise_sgima = 0.1"),
            SDINS,
            Error(&["sensors.dvl.noise_sgima", "did you mean `noise_sigma`"]),
            Here,
        ),
        (
            "[initial] t given",
            "correct",
            |d| meta_key(d, "initial", "t", "t = 0.0"),
            SDINS,
            Correct,
            Here,
        ),
        (
            "[initial] t not a number",
            "meta",
            |d| meta_key(d, "initial", "t", "t = \"start\""),
            SDINS,
            Error(&["meta.toml", "initial.t"]),
            Here,
        ),
        (
            "USBL misalignment sigma given",
            "correct",
            |d| {
                meta_key(
                    d,
                    "sensors.usbl",
                    "misalignment_sigma",
                    "misalignment_sigma = 0.001",
                )
            },
            SDINS,
            Correct,
            Here,
        ),
        (
            "no [sensors.dvl] section",
            "meta",
            |d| meta_drop_section(d, "sensors.dvl"),
            SDINS,
            Warn("missing_sensor_section", "sensors.dvl"),
            Here,
        ),
        (
            "no [sensors.imu] section",
            "meta",
            |d| meta_drop_section(d, "sensors.imu"),
            SDINS,
            Warn("missing_sensor_section", "sensors.imu"),
            Here,
        ),
        // -- gaps and clocks
        (
            "30 s IMU hole",
            "gaps",
            |d| drop_rows(d, "imu.csv", 1000, 4000),
            SDINS,
            Error(&["imu.csv:1001", "lines 1001 and 1002", "gap of"]),
            Here,
        ),
        (
            "30 s IMU hole, lenient",
            "gaps",
            |d| drop_rows(d, "imu.csv", 1000, 4000),
            LENIENT,
            Warn("imu_gap", "imu.csv"),
            Here,
        ),
        (
            "1 s IMU hole, limit 200 periods",
            "gaps",
            |d| drop_rows(d, "imu.csv", 1000, 1100),
            &["--max-gap-periods", "200"],
            Correct,
            Here,
        ),
        (
            "2 s IMU hole",
            "gaps",
            |d| drop_rows(d, "imu.csv", 1000, 1200),
            SDINS,
            Warn("imu_gap", "imu.csv:1001"),
            Here,
        ),
        (
            "0.3 s IMU hole",
            "gaps",
            |d| drop_rows(d, "imu.csv", 2000, 2030),
            SDINS,
            Warn("imu_gap", "propagated"),
            Here,
        ),
        (
            "4.5 s IMU hole",
            "gaps",
            |d| drop_rows(d, "imu.csv", 3000, 3450),
            SDINS,
            Warn("imu_gap", "imu.csv:3001"),
            Here,
        ),
        (
            "five 1 s IMU holes",
            "gaps",
            |d| {
                rows(d, "imu.csv", |i, c| {
                    if (1..=5).any(|k| (k * 900..k * 900 + 100).contains(&i)) {
                        c.clear();
                    }
                })
            },
            SDINS,
            Warn("imu_gap", "propagated"),
            Here,
        ),
        (
            "8 s IMU hole",
            "gaps",
            |d| drop_rows(d, "imu.csv", 1000, 1800),
            SDINS,
            Error(&["imu.csv:1001", "gap of", "more than 5 s"]),
            Here,
        ),
        (
            "four 1 s holes and one of 8 s",
            "gaps",
            |d| {
                rows(d, "imu.csv", |i, c| {
                    if (1..=4).any(|k| (k * 900..k * 900 + 100).contains(&i))
                        || (4000..4800).contains(&i)
                    {
                        c.clear();
                    }
                })
            },
            SDINS,
            Error(&["imu.csv", "gap"]),
            Here,
        ),
        (
            "clock jump of an hour",
            "clocks",
            |d| shift_from(d, "imu.csv", 2000, 3600.0),
            SDINS,
            Error(&["imu.csv:2001", "gap of"]),
            Here,
        ),
        (
            "far-future last IMU row, with truth",
            "clocks",
            |d| {
                let n = std::fs::read_to_string(d.join("imu.csv"))
                    .unwrap()
                    .lines()
                    .count()
                    - 2;
                cell(d, "imu.csv", n, 0, "1e9");
            },
            SDINS,
            Error(&["imu.csv:", "gap of"]),
            Here,
        ),
        (
            "far-future last IMU row, no truth",
            "clocks",
            |d| {
                std::fs::remove_file(d.join("truth.csv")).unwrap();
                let n = std::fs::read_to_string(d.join("imu.csv"))
                    .unwrap()
                    .lines()
                    .count()
                    - 2;
                cell(d, "imu.csv", n, 0, "1e9");
            },
            SDINS,
            Error(&["imu.csv:", "gap of"]),
            Here,
        ),
        (
            "far-future DVL row",
            "clocks",
            |d| append(d, "dvl.csv", "1e9,1,0,0\n"),
            SDINS,
            Error(&["dvl.csv:", "clock jump"]),
            Here,
        ),
        (
            "far-future DVL row, lenient",
            "clocks",
            |d| append(d, "dvl.csv", "1e9,1,0,0\n"),
            LENIENT,
            Warn("outside_imu_span", "dvl.csv"),
            Here,
        ),
        (
            "depth rows after the IMU",
            "clocks",
            |d| {
                let t = last_time(d, "depth.csv");
                append(
                    d,
                    "depth.csv",
                    &format!("{},10\n{},10\n", t + 10.0, t + 11.0),
                );
            },
            SDINS,
            Warn("outside_imu_span", "depth.csv"),
            Here,
        ),
        (
            "epoch time stamps",
            "correct",
            |d| {
                shift_all(d, 1.7e9);
                // The epoch of the initial estimate moves with the data.
                meta_key(d, "initial", "t", "t = 1700000000.0");
            },
            SDINS,
            Correct,
            Here,
        ),
        (
            "epoch time stamps, [initial] t left at 0",
            "clocks",
            |d| shift_all(d, 1.7e9),
            SDINS,
            Error(&["meta.toml", "initial.t", "before the first IMU row"]),
            Here,
        ),
        (
            "[initial] t after the IMU data",
            "clocks",
            |d| meta_key(d, "initial", "t", "t = 1.0e6"),
            SDINS,
            Error(&["meta.toml", "initial.t", "after the last IMU row"]),
            Here,
        ),
        (
            "time backwards",
            "clocks",
            |d| cell(d, "imu.csv", 500, 0, "1.0"),
            SDINS,
            Error(&["imu.csv:502: column `t`"]),
            Here,
        ),
        (
            "duplicate time stamp",
            "clocks",
            |d| cell(d, "depth.csv", 10, 0, "5.0"),
            SDINS,
            Error(&["depth.csv:12: column `t`"]),
            Here,
        ),
        // -- frozen IMU
        (
            "gyro frozen for 25 s",
            "frozen",
            |d| freeze(d, 1000, 3500),
            SDINS,
            Error(&["imu.csv:1002", "frozen IMU"]),
            Here,
        ),
        (
            "gyro frozen for 25 s, lenient",
            "frozen",
            |d| freeze(d, 1000, 3500),
            LENIENT,
            Warn("frozen_imu", "imu.csv:1002"),
            Here,
        ),
        (
            "gyro frozen for 20 s",
            "frozen",
            |d| freeze(d, 1000, 3000),
            SDINS,
            Error(&["imu.csv:1002", "gx,gy,gz", "frozen IMU"]),
            Here,
        ),
        (
            "gyro frozen for 3 s",
            "frozen",
            |d| freeze(d, 2000, 2300),
            SDINS,
            Error(&["imu.csv:2002", "frozen IMU"]),
            Here,
        ),
        (
            "gz alone frozen for 10 s",
            "frozen",
            |d| freeze_columns(d, 1500, 2500, 3..4),
            SDINS,
            Error(&["imu.csv:1502", "gyro gz", "frozen IMU"]),
            Here,
        ),
        (
            "accelerometer frozen for 5 s",
            "frozen",
            |d| freeze_columns(d, 3000, 3500, 4..7),
            SDINS,
            Error(&["imu.csv:3002", "accelerometer ax,ay,az", "frozen IMU"]),
            Here,
        ),
        (
            "gyro frozen for 20 s, lenient",
            "frozen",
            |d| freeze(d, 1000, 3000),
            LENIENT,
            Warn("frozen_imu", "imu.csv:1002"),
            Here,
        ),
        (
            "gyro frozen for 20 s, no [sensors.imu]",
            "frozen",
            |d| {
                meta_drop_section(d, "sensors.imu");
                freeze(d, 1000, 3000);
            },
            SDINS,
            Warn("frozen_imu", "imu.csv:1002"),
            Here,
        ),
        (
            "gyro repeated for 0.3 s (a logger catching up)",
            "frozen",
            |d| freeze(d, 1000, 1030),
            SDINS,
            Correct,
            Here,
        ),
        // -- scoring
        (
            "header-only truth",
            "scoring",
            |d| {
                std::fs::write(
                    d.join("truth.csv"),
                    "t,lat,lon,depth,vn,ve,vd,roll,pitch,yaw\n",
                )
                .unwrap()
            },
            SDINS,
            Error(&["truth.csv", "nothing to score"]),
            Here,
        ),
        (
            "truth depth cell 1e300",
            "scoring",
            |d| cell(d, "truth.csv", 30, 3, "1e300"),
            SDINS,
            Error(&["truth.csv:32", "`depth`"]),
            Here,
        ),
        (
            "truth never overlaps",
            "scoring",
            |d| shift_from(d, "truth.csv", 0, 1000.0),
            SDINS,
            Error(&["truth.csv", "overlap"]),
            Here,
        ),
        (
            "2 IMU rows against 60 s of truth",
            "scoring",
            |d| drop_rows(d, "imu.csv", 2, usize::MAX),
            SDINS,
            Error(&["truth.csv", "overlap"]),
            Here,
        ),
        (
            "1 IMU row",
            "scoring",
            |d| drop_rows(d, "imu.csv", 1, usize::MAX),
            SDINS,
            Error(&["imu.csv", "at least 2"]),
            Here,
        ),
        (
            "truth depth sign flipped",
            "scoring",
            |d| scale(d, "truth.csv", &[3], -1.0),
            SDINS,
            // The depth error is the truth's, not the filter's: said.
            Warn("suspicious", "mean NEES"),
            Here,
        ),
        (
            "truth time stamps 5 s late",
            "clocks",
            |d| shift_from(d, "truth.csv", 0, 5.0),
            SDINS,
            Warn("suspicious", "mean NEES"),
            Here,
        ),
        (
            "truth longer than the IMU",
            "scoring",
            |d| drop_rows(d, "imu.csv", 2000, usize::MAX),
            SDINS,
            Warn("partial_scoring", "truth.csv"),
            Here,
        ),
        (
            // A `period_s` 100 times too small: every row is applied within
            // the first second (exit 0, no warning before).
            "DVL rows packed into the start",
            "clocks",
            |d| {
                rows(d, "dvl.csv", |i, c| {
                    c[0] = format!("{}", 0.005 * (i + 1) as f64)
                })
            },
            SDINS,
            Warn("suspicious", "packs them into the start"),
            Here,
        ),
        // -- output handling
        (
            "--out under a file",
            "output",
            |d| std::fs::write(d.join("../blocker"), "x").unwrap(),
            &["--out", "@/../blocker/out"],
            Error(&[
                "--out",
                "blocker/out",
                "blocker exists and is not a directory",
            ]),
            Here,
        ),
        (
            "--out is a file",
            "output",
            |d| std::fs::write(d.join("../taken"), "x").unwrap(),
            &["--out", "@/../taken"],
            Error(&["taken", "not a directory"]),
            Here,
        ),
        // The replay's files would be unknown log files there.
        (
            "--out is the log directory",
            "output",
            |_| {},
            &["--out", "@"],
            Error(&["--out", "is the log directory"]),
            Here,
        ),
        (
            "--out inside the log directory, by a path through `..`",
            "output",
            |d| std::fs::create_dir(d.join("sub")).unwrap(),
            &["--out", "@/sub/../results"],
            Error(&["--out", "lies inside the log directory"]),
            Here,
        ),
        (
            "--stationary on sdins25",
            "output",
            |_| {},
            &["--stationary"],
            Error(&["--stationary", "no stationary mode"]),
            Here,
        ),
        // -- rows, files, links
        (
            "DVL row with one cell empty",
            "rows",
            |d| cell(d, "dvl.csv", 7, 2, ""),
            SDINS,
            Error(&["dvl.csv:9", "`vy`", "not used"]),
            Here,
        ),
        (
            "DVL row with one cell empty, lenient",
            "rows",
            |d| cell(d, "dvl.csv", 7, 2, ""),
            LENIENT,
            Warn("skipped_row", "dvl.csv:9"),
            Here,
        ),
        (
            "DVL never in bottom lock",
            "rows",
            |d| {
                rows(d, "dvl.csv", |_, c| {
                    c[1].clear();
                    c[2].clear();
                    c[3].clear();
                })
            },
            SDINS,
            Warn("suspicious", "rows of dvl.csv was applied"),
            Here,
        ),
        (
            "DVL without bottom lock",
            "correct",
            |d| {
                rows(d, "dvl.csv", |i, c| {
                    if (10..20).contains(&i) {
                        c[1].clear();
                        c[2].clear();
                        c[3].clear();
                    }
                })
            },
            SDINS,
            Correct,
            Here,
        ),
        (
            "dangling dvl.csv symlink",
            "files",
            |d| {
                std::fs::remove_file(d.join("dvl.csv")).unwrap();
                symlink(&d.join("moved.csv"), &d.join("dvl.csv"));
            },
            SDINS,
            Error(&["dvl.csv", "does not exist"]),
            Here,
        ),
        (
            "dangling symlink, lenient",
            "files",
            |d| {
                std::fs::remove_file(d.join("depth.csv")).unwrap();
                symlink(&d.join("gone.csv"), &d.join("depth.csv"));
            },
            LENIENT,
            Error(&["depth.csv", "does not exist"]),
            Here,
        ),
        (
            "header-only dvl.csv",
            "files",
            |d| std::fs::write(d.join("dvl.csv"), "t,vx,vy,vz\n").unwrap(),
            SDINS,
            Warn("suspicious", "dvl.csv has no rows"),
            Here,
        ),
        (
            "speed.csv for sdins25",
            "files",
            |d| std::fs::write(d.join("speed.csv"), "t,speed\n1,1.5\n2,1.5\n").unwrap(),
            SDINS,
            Warn("unused_file", "speed.csv"),
            Here,
        ),
        (
            "unknown file, lenient",
            "files",
            |d| std::fs::write(d.join("sonar.csv"), "t,range\n1,3\n").unwrap(),
            LENIENT,
            Warn("unknown_file", "sonar.csv"),
            Here,
        ),
        (
            "CRLF line ends",
            "correct",
            |d| {
                for f in ["imu.csv", "dvl.csv", "meta.toml"] {
                    let t = std::fs::read_to_string(d.join(f)).unwrap();
                    std::fs::write(d.join(f), t.replace('\n', "\r\n")).unwrap();
                }
            },
            SDINS,
            Correct,
            Here,
        ),
        (
            "NaN gyro cell",
            "values",
            |d| cell(d, "imu.csv", 10, 1, "NaN"),
            SDINS,
            Error(&["imu.csv:12: column `gx`"]),
            Here,
        ),
        ("unchanged log", "correct", |_| {}, SDINS, Correct, Here),
        // -- in-loop cases (the replay pipeline's work)
        (
            "far-future last IMU row, no truth, lenient",
            "clocks",
            |d| {
                std::fs::remove_file(d.join("truth.csv")).unwrap();
                let n = std::fs::read_to_string(d.join("imu.csv"))
                    .unwrap()
                    .lines()
                    .count()
                    - 2;
                cell(d, "imu.csv", n, 0, "1e9");
            },
            LENIENT,
            // Bounded steps of a 1e9-s gap would be more than a million:
            // refused, naming the two lines.
            Error(&[
                "imu.csv line 6001",
                "imu.csv line 6002",
                "too long to propagate",
            ]),
            Pipeline,
        ),
        (
            "clock jump of an hour, lenient",
            "clocks",
            |d| shift_from(d, "imu.csv", 2000, 3600.0),
            LENIENT,
            // An hour without IMU data, propagated in bounded steps, leaves
            // the estimate's physical bounds: an error naming the gap's lines.
            Error(&[
                "imu.csv line 2001",
                "imu.csv line 2002",
                "out of physical bounds",
            ]),
            Pipeline,
        ),
    ]
}

#[cfg(unix)]
fn symlink(target: &Path, link: &Path) {
    std::os::unix::fs::symlink(target, link).unwrap();
}

#[cfg(not(unix))]
fn symlink(_: &Path, link: &Path) {
    let _ = std::fs::remove_file(link);
}

/// Runs one case; `Err` says how it failed its class.
fn run(case: &Case) -> Result<(), String> {
    let (name, _, edit, extra, expect, _) = case;
    let tmp = TempDir::new("broken");
    let dir = tmp.path().join("log");
    copy_dir(&base().join("log"), &dir);
    edit(&dir);
    let extra: Vec<String> = extra
        .iter()
        .map(|a| a.replace('@', &dir.display().to_string()))
        .collect();
    let mut args = vec![
        "replay",
        dir.to_str().unwrap(),
        "--model",
        "sdins25",
        "--json",
    ];
    args.extend(extra.iter().map(String::as_str));
    let o = navsim(&args);
    let (out, err) = (stdout(&o), stderr(&o));
    let code = o.status.code();
    match expect {
        Expect::Error(needles) => {
            if code != Some(1) {
                return Err(format!("{name}: exit {code:?}, expected 1; stderr {err}"));
            }
            if !out.is_empty() {
                return Err(format!("{name}: stdout not empty: {out}"));
            }
            let lines: Vec<&str> = err.lines().filter(|l| l.starts_with("error:")).collect();
            if lines.len() != 1 {
                return Err(format!("{name}: {} error lines: {err}", lines.len()));
            }
            for n in *needles {
                if !lines[0].contains(n) {
                    return Err(format!("{name}: `{n}` not in {}", lines[0]));
                }
            }
        }
        Expect::Correct | Expect::Warn(..) => {
            if code != Some(0) {
                return Err(format!("{name}: exit {code:?}; stderr {err}"));
            }
            let v: Value = serde_json::from_str(out.trim())
                .map_err(|e| format!("{name}: stdout is not JSON ({e}): {out}"))?;
            for key in [
                "horizontal_error_rms_m",
                "depth_error_rms_m",
                "scored_seconds",
            ] {
                if v.get("horizontal_error_rms_m").is_some()
                    && !v[key].as_f64().is_some_and(f64::is_finite)
                {
                    return Err(format!("{name}: `{key}` = {}", v[key]));
                }
            }
            let warnings = v["warnings"]
                .as_array()
                .ok_or_else(|| format!("{name}: no warnings array"))?;
            let text = |w: &Value| {
                let loc = match (w["file"].as_str(), w["line"].as_u64()) {
                    (Some(f), Some(l)) => format!("{f}:{l}"),
                    (Some(f), None) => f.to_string(),
                    _ => String::new(),
                };
                format!(
                    "{loc} {} {}",
                    w["key"].as_str().unwrap_or(""),
                    w["message"].as_str().unwrap_or("")
                )
            };
            if let Expect::Warn(kind, needle) = expect {
                let hit = warnings
                    .iter()
                    .any(|w| w["kind"] == *kind && text(w).contains(needle));
                if !hit {
                    return Err(format!(
                        "{name}: no `{kind}` warning with `{needle}` in {warnings:?}"
                    ));
                }
            } else if let Some(w) = warnings.iter().find(|w| w["kind"] != "unused_file") {
                return Err(format!("{name}: correct case with a warning: {}", text(w)));
            }
        }
    }
    Ok(())
}

#[test]
fn broken_logs_are_correct_clean_errors_or_warnings() {
    let all = cases();
    let mut names = std::collections::BTreeSet::new();
    for c in &all {
        assert!(names.insert(c.0), "duplicate case name {}", c.0);
    }
    let failures: Vec<String> = all
        .iter()
        .filter(|c| c.5 == Needs::Here)
        .filter_map(|c| run(c).err())
        .collect();
    assert!(
        failures.is_empty(),
        "{} failing cases:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

/// The cases that exercise the replay pipeline's in-loop work (bounded time
/// steps, physical bounds on the estimate).
#[test]
fn pipeline_cases() {
    let failures: Vec<String> = cases()
        .iter()
        .filter(|c| c.5 == Needs::Pipeline)
        .filter_map(|c| run(c).err())
        .collect();
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Prints the number of cases per class and expectation (for the docs).
#[test]
fn case_counts() {
    let mut counts = std::collections::BTreeMap::new();
    for (_, class, _, _, expect, needs) in cases() {
        let kind = match expect {
            Expect::Correct => "correct",
            Expect::Error(_) => "error",
            Expect::Warn(..) => "warning",
        };
        *counts
            .entry((class, kind, needs == Needs::Pipeline))
            .or_insert(0) += 1;
    }
    for ((class, kind, pipeline), n) in &counts {
        eprintln!(
            "{class:10} {kind:8} {n:3}{}",
            if *pipeline { " (pipeline)" } else { "" }
        );
    }
    assert!(cases().len() >= 60);
}

/// SIGINT while `--out` is being written removes the staging directory,
/// of a replay and of a scenario (whose outputs were once written without
/// it, leaving `.out.partial-*` behind): the signal is sent as soon as the
/// `.partial-*` directory appears. An attempt whose run finished before
/// the signal is repeated (at least one must be interrupted for the test
/// to pass).
#[cfg(unix)]
#[test]
fn sigint_while_writing_leaves_no_staging_dir() {
    let log = base().join("log");
    let replay = ["replay", log.to_str().unwrap(), "--model", "sdins25"];
    let scenario = ["scenario", "lawnmower-dvl", "--runs", "2"];
    for command in [replay, scenario] {
        sigint_while_writing(&command);
    }
}

#[cfg(unix)]
fn sigint_while_writing(command: &[&str]) {
    let mut interrupted = 0;
    for attempt in 0..10 {
        let tmp = TempDir::new("sigint");
        let out = tmp.path().join("out");
        let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_navsim"))
            .args(command)
            .arg("--out")
            .arg(&out)
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .spawn()
            .unwrap();
        let partial = |p: &Path| {
            std::fs::read_dir(p)
                .unwrap()
                .filter_map(Result::ok)
                .any(|e| e.file_name().to_string_lossy().contains(".partial-"))
        };
        let mut sent = false;
        while child.try_wait().unwrap().is_none() {
            if partial(tmp.path()) {
                let _ = std::process::Command::new("kill")
                    .args(["-INT", &child.id().to_string()])
                    .status();
                sent = true;
                break;
            }
        }
        let status = child.wait().unwrap();
        assert!(
            !partial(tmp.path()),
            "{command:?} attempt {attempt}: a staging directory is left"
        );
        if sent && !status.success() {
            assert_eq!(status.code(), Some(130), "{command:?} attempt {attempt}");
            assert!(
                !out.exists(),
                "{command:?} attempt {attempt}: a partial output"
            );
            interrupted += 1;
            if interrupted >= 2 {
                break;
            }
        }
    }
    assert!(
        interrupted > 0,
        "{command:?}: no run was interrupted while writing"
    );
}

// ---- check against replay ------------------------------------------------

/// The log a parity case starts from.
#[derive(Debug, Clone, Copy)]
enum Base {
    /// The 60 s survey of [`base`] (SDINS models).
    Survey,
    /// The committed PX4 flight, imported (`ahrs`, `gnss-ins`).
    Flight,
}

/// The imported PX4 fixture, once.
fn flight() -> &'static Path {
    static DIR: OnceLock<SharedDir> = OnceLock::new();
    DIR.get_or_init(|| {
        let d = SharedDir::new("broken-flight");
        let fixture = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../models/tests/data/ulog/sample_px4_events.ulg");
        let o = navsim(&[
            "import",
            "ulog",
            fixture.to_str().unwrap(),
            "--out",
            d.path().join("log").to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        d
    })
    .path()
}

/// Removes the `key = ...` lines of `[initial]` in meta.toml.
fn meta_drop_initial(dir: &Path, keys: &[&str]) {
    let path = dir.join("meta.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let mut current = String::new();
    let mut out = Vec::new();
    for l in text.lines() {
        if l.starts_with('[') {
            current = l.trim_matches(|c| c == '[' || c == ']').to_string();
        }
        let key = l.split('=').next().map(str::trim).unwrap_or("");
        if !(current == "initial" && keys.contains(&key)) {
            out.push(l);
        }
    }
    std::fs::write(path, out.join("\n") + "\n").unwrap();
}

/// (name, base log, model, edit): the log is run through `check --model`
/// and `replay --model`.
type Parity = (&'static str, Base, &'static str, fn(&Path));

fn parity_cases() -> Vec<Parity> {
    use Base::*;
    vec![
        ("as simulated", Survey, "sdins25", |_| {}),
        ("as imported, ahrs", Flight, "ahrs", |_| {}),
        ("as imported, gnss-ins", Flight, "gnss-ins", |_| {}),
        // the initial state
        ("initial epoch after every row", Survey, "sdins25", |d| {
            meta_key(d, "initial", "t", "t = 1e6")
        }),
        ("initial epoch after every row, ahrs", Flight, "ahrs", |d| {
            meta_key(d, "initial", "t", "t = 1e6")
        }),
        ("missing initial yaw", Survey, "sdins25", |d| {
            meta_drop_initial(d, &["yaw"])
        }),
        ("missing initial yaw, sdins20", Survey, "sdins20", |d| {
            meta_drop_initial(d, &["yaw"])
        }),
        (
            "missing initial roll, pressure-auv",
            Survey,
            "pressure-auv",
            |d| meta_drop_initial(d, &["roll"]),
        ),
        ("missing initial attitude", Survey, "sdins25", |d| {
            meta_drop_initial(d, &["roll", "pitch", "yaw"])
        }),
        ("missing initial attitude, ahrs", Flight, "ahrs", |d| {
            meta_drop_initial(d, &["roll", "pitch", "yaw"])
        }),
        (
            "missing initial attitude, gnss-ins",
            Flight,
            "gnss-ins",
            |d| meta_drop_initial(d, &["roll", "pitch", "yaw"]),
        ),
        (
            "missing initial position, gnss-ins",
            Flight,
            "gnss-ins",
            |d| meta_drop_initial(d, &["lat"]),
        ),
        // a cell of every file kind
        ("empty cell in gnss.csv", Flight, "gnss-ins", |d| {
            cell(d, "gnss.csv", 4, 1, "")
        }),
        ("NaN cell in gnss.csv", Flight, "gnss-ins", |d| {
            cell(d, "gnss.csv", 4, 2, "NaN")
        }),
        ("empty cell in mag.csv", Flight, "ahrs", |d| {
            cell(d, "mag.csv", 4, 1, "")
        }),
        ("NaN cell in mag.csv", Flight, "ahrs", |d| {
            cell(d, "mag.csv", 4, 1, "NaN")
        }),
        ("empty cell in baro.csv", Flight, "gnss-ins", |d| {
            cell(d, "baro.csv", 4, 1, "")
        }),
        ("empty cell in reference.csv", Flight, "ahrs", |d| {
            cell(d, "reference.csv", 4, 1, "")
        }),
        ("empty cell in depth.csv", Survey, "sdins25", |d| {
            cell(d, "depth.csv", 4, 1, "")
        }),
        ("empty cell in heading.csv", Survey, "sdins25", |d| {
            cell(d, "heading.csv", 4, 1, "")
        }),
        ("empty cell in usbl.csv", Survey, "sdins25", |d| {
            cell(d, "usbl.csv", 1, 1, "")
        }),
        ("empty cell in altitude.csv", Survey, "sdins25", |d| {
            cell(d, "altitude.csv", 4, 1, "")
        }),
        ("empty cell in truth.csv", Survey, "sdins25", |d| {
            cell(d, "truth.csv", 4, 1, "")
        }),
        // times
        ("time backwards in reference.csv", Flight, "ahrs", |d| {
            cell(d, "reference.csv", 6, 0, "1.5")
        }),
        (
            "time backwards in reference.csv, gnss-ins",
            Flight,
            "gnss-ins",
            |d| cell(d, "reference.csv", 6, 0, "1.5"),
        ),
        ("time backwards in truth.csv", Survey, "sdins25", |d| {
            cell(d, "truth.csv", 6, 0, "0.05")
        }),
        ("time backwards in gnss.csv", Flight, "gnss-ins", |d| {
            cell(d, "gnss.csv", 6, 0, "1.5")
        }),
        ("gap in imu.csv", Survey, "sdins25", |d| {
            drop_rows(d, "imu.csv", 1000, 1500)
        }),
        ("gap in imu.csv, ahrs", Flight, "ahrs", |d| {
            drop_rows(d, "imu.csv", 1000, 1500)
        }),
        // what the model needs
        ("no gnss.csv, gnss-ins", Flight, "gnss-ins", |d| {
            std::fs::remove_file(d.join("gnss.csv")).unwrap()
        }),
        ("no mag.csv, ahrs", Flight, "ahrs", |d| {
            std::fs::remove_file(d.join("mag.csv")).unwrap()
        }),
    ]
}

/// The `error:` line of a failed run, without its prefix and without the
/// count of further problems; `None` when the run succeeded.
fn failure(o: &std::process::Output) -> Option<String> {
    if o.status.success() {
        return None;
    }
    let err = stderr(o);
    let line = err.lines().find(|l| l.starts_with("error: "))?;
    let text = line.trim_start_matches("error: ");
    let text = text.split(" (").next().unwrap_or(text);
    let text = text.split("; first: ").last().unwrap_or(text);
    Some(text.to_string())
}

/// `check --model M` refuses exactly the logs `replay --model M` refuses,
/// with the replay's error; it passes the logs the replay runs.
#[test]
fn check_refuses_what_replay_refuses() {
    let mut failures = Vec::new();
    let mut refused = 0;
    for (name, base_log, model, edit) in parity_cases() {
        let tmp = TempDir::new("parity");
        let dir = tmp.path().join("log");
        let from = match base_log {
            Base::Survey => base().join("log"),
            Base::Flight => flight().join("log"),
        };
        copy_dir(&from, &dir);
        edit(&dir);
        let d = dir.to_str().unwrap();
        let replay = navsim(&["replay", d, "--model", model, "--json"]);
        let check = navsim(&["check", d, "--model", model, "--json"]);
        match (failure(&replay), failure(&check)) {
            (None, None) => {}
            (Some(r), Some(c)) => {
                refused += 1;
                if !c.contains(&r) && !r.contains(&c) {
                    failures.push(format!("{name}: replay `{r}`, check `{c}`"));
                }
            }
            (Some(r), None) => failures.push(format!("{name}: check passes, replay: {r}")),
            (None, Some(c)) => failures.push(format!("{name}: replay runs, check: {c}")),
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    // The table must hold refused logs, or it tests nothing.
    assert!(refused >= 20, "only {refused} refused logs");
}

// ---- errors that name the cause -------------------------------------------

/// `imu.csv` rewritten as increments (rate times the 0.01 s period), with
/// every `drop_every`-th row dropped when given.
fn to_increments(dir: &Path, drop_every: Option<usize>) {
    let path = dir.join("imu.csv");
    let text = std::fs::read_to_string(&path).unwrap();
    let mut out = String::from("t,dtheta_x,dtheta_y,dtheta_z,dv_x,dv_y,dv_z\n");
    for (i, line) in text.lines().skip(1).enumerate() {
        if drop_every.is_some_and(|n| i % n == n / 2) {
            continue;
        }
        let c: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
        let cells: Vec<String> = std::iter::once(c[0])
            .chain(c[1..].iter().map(|x| x * 0.01))
            .map(|x| x.to_string())
            .collect();
        out.push_str(&cells.join(","));
        out.push('\n');
    }
    std::fs::write(path, out).unwrap();
}

/// (name, base log, arguments after the directory, edit, what must name the
/// cause: `Error(texts)` in the one `error:` line, `Warn(kind, text)` in a
/// JSON warning)
type Named = (
    &'static str,
    Base,
    &'static [&'static str],
    fn(&Path),
    Expect,
);

fn named_cases() -> Vec<Named> {
    use Base::*;
    use Expect::*;
    const SDINS: &[&str] = &["--model", "sdins25"];
    vec![
        (
            "gyro in deg/s within the gyro range",
            Survey,
            SDINS,
            |d| scale(d, "imu.csv", &[1, 2, 3], 1f64.to_degrees()),
            // The filter diverges; the error names the doubtful input.
            Error(&["exceeds 300", "likely cause", "imu.csv:2", "deg/s?"]),
        ),
        (
            "times in milliseconds",
            Survey,
            SDINS,
            |d| {
                for f in ["imu.csv", "dvl.csv", "depth.csv", "heading.csv", "usbl.csv"] {
                    scale(d, f, &[0], 1000.0);
                }
            },
            Error(&["imu.csv", "milliseconds?"]),
        ),
        (
            "times in microseconds",
            Survey,
            SDINS,
            |d| scale(d, "imu.csv", &[0], 1e6),
            Error(&["imu.csv", "microseconds?"]),
        ),
        (
            "increments as written",
            Survey,
            SDINS,
            |d| to_increments(d, None),
            Correct,
        ),
        (
            "increment rows dropped",
            Survey,
            SDINS,
            |d| to_increments(d, Some(50)),
            Warn("imu_gap", "increment rows dropped?"),
        ),
        (
            "far-future last IMU row",
            Survey,
            SDINS,
            |d| {
                let text = std::fs::read_to_string(d.join("imu.csv")).unwrap();
                let last = text.lines().last().unwrap().to_string();
                let rest = last.split_once(',').unwrap().1;
                append(d, "imu.csv", &format!("1e9,{rest}\n"));
            },
            // 6001 rows after the header; the appended one is line 6003.
            Error(&["imu.csv:6003", "gap of"]),
        ),
        (
            "a log without GNSS for a model that needs it",
            Flight,
            &["--model", "gnss-ins"],
            |d| std::fs::remove_file(d.join("gnss.csv")).unwrap(),
            Error(&["gnss.csv: missing", "needs GNSS"]),
        ),
        (
            "truth yaw off by 0.3 rad, filter fine",
            Survey,
            SDINS,
            |d| {
                rows(d, "truth.csv", |_, c| {
                    c[9] = format!("{}", c[9].parse::<f64>().unwrap() + 0.3)
                })
            },
            Warn("suspicious", "convention or clock of truth.csv?"),
        ),
        (
            "increment rows dropped, truth right",
            Survey,
            SDINS,
            |d| to_increments(d, Some(10)),
            Warn("suspicious", "a likelier cause than truth.csv: imu.csv:"),
        ),
    ]
}

/// Each error or warning names the input that caused it (the file, line
/// and likely cause), not the estimate that went wrong or an internal path.
#[test]
fn errors_name_the_cause() {
    let mut failures = Vec::new();
    for (name, base_log, args, edit, expect) in named_cases() {
        let tmp = TempDir::new("named");
        let dir = tmp.path().join("log");
        let from = match base_log {
            Base::Survey => base().join("log"),
            Base::Flight => flight().join("log"),
        };
        copy_dir(&from, &dir);
        edit(&dir);
        let mut all = vec!["replay", dir.to_str().unwrap(), "--json"];
        all.extend_from_slice(args);
        let o = navsim(&all);
        let (out, err) = (stdout(&o), stderr(&o));
        let result = match expect {
            Expect::Error(texts) => match err.lines().find(|l| l.starts_with("error:")) {
                Some(line) if !o.status.success() => texts
                    .iter()
                    .find(|t| !line.contains(*t))
                    .map(|t| format!("`{t}` not in {line}")),
                _ => Some(format!("no error: {err}")),
            },
            Expect::Warn(kind, text) => match serde_json::from_str::<Value>(out.trim()) {
                Ok(v) => {
                    let hit = v["warnings"].as_array().into_iter().flatten().any(|w| {
                        let place = format!(
                            "{}: {} {}",
                            w["file"].as_str().unwrap_or(""),
                            w["key"].as_str().unwrap_or(""),
                            w["message"].as_str().unwrap_or("")
                        );
                        w["kind"] == kind && place.contains(text)
                    });
                    (!hit)
                        .then(|| format!("no `{kind}` warning with `{text}` in {}", v["warnings"]))
                }
                Err(_) => Some(format!("failed: {err}")),
            },
            Expect::Correct => (!o.status.success()).then(|| format!("failed: {err}")),
        };
        if let Some(r) = result {
            failures.push(format!("{name}: {r}"));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// A divergence is worded by `check --model` as by `replay`: with what the
/// preflight made of the inputs (`check` dropped that part).
#[test]
fn check_words_a_divergence_as_replay_does() {
    let tmp = TempDir::new("divergence-words");
    let dir = tmp.path().join("log");
    copy_dir(&base().join("log"), &dir);
    meta_key(
        &dir,
        "sensors.imu",
        "gyro_noise_sigma",
        "gyro_noise_sigma = 1e5",
    );
    let d = dir.to_str().unwrap();
    let error_line = |args: &[&str]| {
        let o = navsim(args);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {}", stdout(&o));
        let err = stderr(&o);
        let line = err
            .lines()
            .find(|l| l.starts_with("error: "))
            .map(str::to_string);
        line.unwrap_or_else(|| panic!("{args:?}: {err}"))
    };
    let replay = error_line(&["replay", d, "--model", "sdins25"]);
    let check = error_line(&["check", d, "--model", "sdins25"]);
    assert!(
        replay.contains("check the model's noise settings"),
        "{replay}"
    );
    // `check` counts its problems first ("1 problem(s) found; first: ").
    let message = replay.trim_start_matches("error: ");
    assert!(check.ends_with(message), "check: {check}\nreplay: {replay}");
    // The JSON says where, as every other error of `check` does: the IMU
    // line named in the message (file and line were null).
    let o = navsim(&["check", d, "--model", "sdins25", "--json"]);
    assert_eq!(o.status.code(), Some(1), "{}", stdout(&o));
    let v: Value = serde_json::from_str(stdout(&o).trim()).expect("one JSON line");
    let error = &v["errors"][0];
    assert_eq!(error["file"], "imu.csv", "{v}");
    let line = error["line"]
        .as_u64()
        .unwrap_or_else(|| panic!("no line: {v}"));
    let text = error["message"].as_str().unwrap_or_default();
    assert!(text.contains(&format!("imu.csv line {line} ")), "{v}");
}
