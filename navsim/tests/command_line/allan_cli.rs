//! `navsim allan`: the Allan analysis of a log's `imu.csv` through the
//! binary, on static recordings the test writes with known white noise,
//! and the recordings it must refuse.

use crate::common;

use common::{navsim, stderr, stdout, TempDir};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use serde_json::Value;

const PERIOD_S: f64 = 0.01;
/// Per-sample white noise of the gyros (rad/s) and accelerometers (m/s^2).
const GYRO_SIGMA: f64 = 2e-4;
const ACCEL_SIGMA: f64 = 5e-3;

/// A static log of `samples` rows at 100 Hz: white noise about the Earth
/// rate and gravity; `turn` (rad/s) is added to gz over the second half
/// (the vehicle turned: not static).
fn write_log(dir: &std::path::Path, samples: usize, seed: u64, turn: f64) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (g, a) = (
        Normal::new(0.0, GYRO_SIGMA).unwrap(),
        Normal::new(0.0, ACCEL_SIGMA).unwrap(),
    );
    let mut text = String::from("t,gx,gy,gz,ax,ay,az\n");
    for k in 0..samples {
        let extra = if k > samples / 2 { turn } else { 0.0 };
        text.push_str(&format!(
            "{},{},{},{},{},{},{}\n",
            (k + 1) as f64 * PERIOD_S,
            5.6e-5 + g.sample(&mut rng),
            g.sample(&mut rng),
            -5.3e-5 + extra + g.sample(&mut rng),
            a.sample(&mut rng),
            a.sample(&mut rng),
            -9.81 + a.sample(&mut rng),
        ));
    }
    std::fs::write(dir.join("imu.csv"), text).unwrap();
    std::fs::write(
        dir.join("meta.toml"),
        "[initial]\nlat = 0.7\nlon = 2.2\ndepth = 0.0\n",
    )
    .unwrap();
}

/// White noise of per-sample sigma `s` at period `T` reads `N = s sqrt(T)`
/// at 1 s; the value is held to four of its own reported relative errors.
#[test]
fn the_white_noise_of_a_static_log_is_found_with_its_confidence() {
    let dir = TempDir::new("allan-static");
    write_log(dir.path(), 60_000, 7, 0.0);
    let section = dir.path().join("imu-section.toml");
    let o = navsim(&[
        "allan",
        dir.path().to_str().unwrap(),
        "--json",
        "--write",
        section.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: Value = serde_json::from_str(stdout(&o).trim()).expect("one JSON object");
    assert_eq!(v["samples"], 60_000);
    for (axis, key, sigma) in [
        ("gx", "angle_random_walk", GYRO_SIGMA),
        ("gz", "angle_random_walk", GYRO_SIGMA),
        ("ay", "velocity_random_walk", ACCEL_SIGMA),
    ] {
        let r = &v["axes"][axis][key];
        let (value, rel) = (
            r["value"].as_f64().expect("found"),
            r["relative_error"].as_f64().expect("confidence"),
        );
        let truth = sigma * PERIOD_S.sqrt();
        assert!(
            ((value - truth) / truth).abs() < 4.0 * rel,
            "{axis}: {value} against {truth} (+-{rel})"
        );
    }
    let written = std::fs::read_to_string(&section).expect("--write");
    assert!(written.contains("[sensors.imu]"), "{written}");
    assert_eq!(v["imu_section"].as_str(), Some(written.as_str()));
}

/// (name, samples, turn rad/s, text the error must contain)
const REFUSED: &[(&str, usize, f64, &str)] = &[
    ("too short", 50, 0.0, "at least 100"),
    ("turning", 20_000, 0.05, "not a static recording"),
];

#[test]
fn recordings_that_cannot_be_analysed_are_refused_with_the_reason() {
    for &(name, samples, turn, said) in REFUSED {
        let dir = TempDir::new("allan-refused");
        write_log(dir.path(), samples, 3, turn);
        let o = navsim(&["allan", dir.path().to_str().unwrap(), "--json"]);
        assert!(!o.status.success(), "{name}: accepted");
        let err = stderr(&o);
        assert!(
            err.starts_with("error: imu.csv: ") && err.contains(said),
            "{name}: {err}"
        );
        assert!(stdout(&o).is_empty(), "{name}: {}", stdout(&o));
    }
}

/// `--out` the log directory (or inside it) is refused before anything is
/// written: its `allan-*.csv` would be unknown log files there, and every
/// later read of the log an error.
#[test]
fn an_output_inside_the_log_is_refused_and_the_log_left_as_it_was() {
    let dir = TempDir::new("allan-out-in-log");
    write_log(dir.path(), 2_000, 4, 0.0);
    let log = dir.path().to_str().unwrap();
    let listing = || {
        let mut names: Vec<_> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        names.sort();
        names
    };
    let before = listing();
    for (out, said) in [
        (log.to_string(), "is the log directory"),
        (format!("{log}/allan"), "lies inside the log directory"),
    ] {
        let o = navsim(&["allan", log, "--out", &out]);
        assert_eq!(o.status.code(), Some(1), "{out}: {}", stderr(&o));
        assert!(stderr(&o).contains(said), "{out}: {}", stderr(&o));
        assert_eq!(listing(), before, "{out}");
    }
    let o = navsim(&["allan", log, "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
}

/// The stretch's bounds: not a number is refused (it meant "no bound"), a
/// negative time parses as a time (it was an unexpected argument).
#[test]
fn stretch_bounds_are_times() {
    let dir = TempDir::new("allan-stretch");
    write_log(dir.path(), 2_000, 5, 0.0);
    let log = dir.path().to_str().unwrap();
    // (arguments, what the error says)
    let cases: [(&[&str], &str); 3] = [
        (&["--from", "nan"], "--from NaN: expected a finite time"),
        (&["--to", "inf"], "--to inf: expected a finite time"),
        (&["--to", "-5"], "no row in the stretch"),
    ];
    for (args, said) in cases {
        let mut all = vec!["allan", log];
        all.extend_from_slice(args);
        let o = navsim(&all);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {}", stderr(&o));
        assert!(stderr(&o).contains(said), "{args:?}: {}", stderr(&o));
    }
}
