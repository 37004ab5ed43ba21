//! Every user-facing name lookup suggests the closest valid name through one
//! rule (`nav_runtime::log::closest_name`: case ignored on both sides, one
//! edit, a swapped pair of letters), seen through the error message a user
//! gets. One row per misspelling: the command, the edit of a valid log, and
//! the text the single `error:` line must contain.

use crate::common;

use std::path::Path;

use common::{navsim, stderr, TempDir};
use models::sdins25::simulation::{simulate, SimConfig};

/// (what is misspelled, edit of `meta.toml` (from, to), extra arguments
/// (`@` is the log directory), the suggestion expected)
type Case = (
    &'static str,
    Option<(&'static str, &'static str)>,
    &'static [&'static str],
    &'static str,
);

const REPLAY: &[&str] = &["replay", "@", "--model", "sdins25", "--json"];

const CASES: &[Case] = &[
    (
        "model name in capitals",
        None,
        &["replay", "@", "--model", "SDINS25"],
        "did you mean `sdins25`?",
    ),
    (
        "model name, swapped pair",
        None,
        &["replay", "@", "--model", "sdisn25"],
        "did you mean `sdins25`?",
    ),
    (
        "short model name, swapped pair",
        None,
        &["replay", "@", "--model", "ahsr"],
        "did you mean `ahrs`?",
    ),
    (
        "model name, one letter missing",
        None,
        &["replay", "@", "--model", "gnssins"],
        "did you mean `gnss-ins`?",
    ),
    (
        "scenario name, swapped pair",
        None,
        &["scenario", "lawnmower-dlv"],
        "did you mean `lawnmower-dvl`?",
    ),
    (
        "fault name, swapped pair",
        None,
        &["scenario", "lawnmower-dvl", "--faults", "dvl-dropuot"],
        "did you mean `dvl-dropout`?",
    ),
    (
        "fault name in capitals",
        None,
        &["scenario", "lawnmower-dvl", "--faults", "STUCK-COMPASS"],
        "did you mean `stuck-compass`?",
    ),
    (
        "sensor name in capitals",
        Some(("[sensors.dvl]", "[sensors.DVL]")),
        REPLAY,
        "did you mean `dvl`?",
    ),
    (
        "sensor name, swapped pair",
        Some(("[sensors.dvl]", "[sensors.dlv]")),
        REPLAY,
        "did you mean `dvl`?",
    ),
    (
        "sensor name, swapped pair in a long name",
        Some(("[sensors.heading]", "[sensors.haeding]")),
        REPLAY,
        "did you mean `heading`?",
    ),
    (
        "sensor name, one letter more",
        Some(("[sensors.usbl]", "[sensors.usbll]")),
        REPLAY,
        "did you mean `usbl`?",
    ),
    (
        "sensor key, swapped pair",
        Some(("noise_sigma = 0.1", "noise_sgima = 0.1")),
        REPLAY,
        "did you mean `noise_sigma`?",
    ),
    (
        "key in capitals",
        Some(("position = ", "Position = ")),
        REPLAY,
        "did you mean `position`?",
    ),
    (
        "section, one letter missing",
        Some(("[initial]", "[intial]")),
        REPLAY,
        "did you mean `initial`?",
    ),
    (
        "section in capitals",
        Some(("[initial_sigma]", "[INITIAL_SIGMA]")),
        REPLAY,
        "did you mean `initial_sigma`?",
    ),
    (
        "mapped sensor, swapped pair",
        Some(("[usbl]", "[files.dlv]\nfile = \"dvl.csv\"\n\n[usbl]")),
        REPLAY,
        "did you mean `dvl`?",
    ),
    (
        "mapping key, one letter missing",
        Some(("[usbl]", "[files.dvl]\nfle = \"dvl.csv\"\n\n[usbl]")),
        REPLAY,
        "did you mean `file`?",
    ),
    (
        "body frame in lower case",
        Some(("[usbl]", "[files.dvl]\nbody_frame = \"frd\"\n\n[usbl]")),
        REPLAY,
        "did you mean `FRD`?",
    ),
];

fn log(dir: &Path) {
    let config = SimConfig {
        duration: 20.0,
        ..SimConfig::usbl()
    };
    simulate(&config, 3).log.write(dir).unwrap();
}

#[test]
fn misspelled_names_get_the_closest_valid_name() {
    let tmp = TempDir::new("suggestions");
    let base = tmp.path().join("base");
    log(&base);
    let mut failures = Vec::new();
    for (k, (what, edit, args, expected)) in CASES.iter().enumerate() {
        let dir = tmp.path().join(format!("case-{k}"));
        std::fs::create_dir_all(&dir).unwrap();
        for e in std::fs::read_dir(&base).unwrap() {
            let e = e.unwrap();
            std::fs::copy(e.path(), dir.join(e.file_name())).unwrap();
        }
        if let Some((from, to)) = edit {
            let path = dir.join("meta.toml");
            let text = std::fs::read_to_string(&path).unwrap();
            assert!(text.contains(from), "{what}: `{from}` not in meta.toml");
            std::fs::write(&path, text.replacen(from, to, 1)).unwrap();
        }
        let args: Vec<String> = args
            .iter()
            .map(|a| a.replace('@', dir.to_str().unwrap()))
            .collect();
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let o = navsim(&args);
        let err = stderr(&o);
        let errors: Vec<&str> = err.lines().filter(|l| l.starts_with("error:")).collect();
        if o.status.code() != Some(1) || errors.len() != 1 || !errors[0].contains(expected) {
            failures.push(format!("{what}: expected `{expected}`, got {err}"));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
