//! The preflight judges the values a `[files.<sensor>]` mapping gives
//! exactly like the standard format: a unit or frame declaration that
//! contradicts physics (the Earth's rate, the turn the heading sees, the
//! depth rate) is an error naming the declaration. Cases as data: each
//! edits a simulated log's rows, writes it with a section appended to its
//! `meta.toml` and checks the files on disk.

use std::path::PathBuf;

use nav_runtime::log::{LogDir, LogFiles, Strictness};

use models::sdins25::simulation::{simulate, SimConfig};
use nav_replay::preflight::{check_files, PreflightOptions, Severity};

/// 150 s of the survey: a 5 m dive at 30 s and a 90 deg turn at 100 s.
fn log() -> LogDir {
    let config = SimConfig {
        duration: 150.0,
        ..SimConfig::usbl()
    };
    simulate(&config, 5).log
}

/// The same log flown level through its dive: the body velocity and the
/// specific force rotated by the truth pitch, so that the DVL's vz carries
/// the descent (what a vehicle diving without pitching measures).
fn level_dive(l: &mut LogDir) {
    let truth = l.truth.clone().unwrap();
    let pitch_at = |t: f64| {
        let i = truth.partition_point(|r| r.t < t).min(truth.len() - 1);
        truth[i].pitch
    };
    let level = |p: f64, x: f64, z: f64| (p.cos() * x + p.sin() * z, -p.sin() * x + p.cos() * z);
    for r in l.dvl.as_mut().unwrap() {
        if let (Some(vx), Some(vz)) = (r.vx, r.vz) {
            let (x, z) = level(pitch_at(r.t), vx, vz);
            (r.vx, r.vz) = (Some(x), Some(z));
        }
    }
    for r in &mut l.imu {
        let (x, z) = level(pitch_at(r.t), r.ax, r.az);
        (r.ax, r.az) = (x, z);
    }
}

/// The first 90 s only: straight ahead, no turn for the gyro and the
/// heading to be compared over; only the heading's noise tells.
fn straight(l: &mut LogDir) {
    let t_end = 90.0;
    l.imu.retain(|r| r.t < t_end);
    fn keep<R: nav_runtime::log::Row>(rows: &mut Option<Vec<R>>, t_end: f64) {
        if let Some(rows) = rows {
            rows.retain(|r| r.t() < t_end);
        }
    }
    keep(&mut l.dvl, t_end);
    keep(&mut l.depth, t_end);
    keep(&mut l.heading, t_end);
    keep(&mut l.usbl, t_end);
    keep(&mut l.altitude, t_end);
    keep(&mut l.truth, t_end);
}

fn scale(l: &mut LogDir, k: f64) {
    for r in &mut l.imu {
        r.gx *= k;
        r.gy *= k;
        r.gz *= k;
    }
}

/// (name, edit of the rows, section appended to meta.toml, expected: None
/// for no error, Some(texts) for an error containing every text)
type Case = (
    &'static str,
    fn(&mut LogDir),
    &'static str,
    Option<&'static [&'static str]>,
);

fn cases() -> Vec<Case> {
    vec![
        (
            "rates declared in their own unit",
            |_| {},
            "[files.imu]\nunits = { rate = \"rad/s\" }\n",
            None,
        ),
        (
            "rad/s declared as deg/s",
            |_| {},
            "[files.imu]\nunits = { rate = \"deg/s\" }\n",
            Some(&["imu.csv", "files.imu.units declares deg/s", "rad/s?"]),
        ),
        (
            "deg/s declared as rad/s",
            |l| scale(l, 1f64.to_degrees()),
            "[files.imu]\nunits = { rate = \"rad/s\" }\n",
            Some(&["imu.csv", "gz", "declares rad/s", "deg/s?"]),
        ),
        (
            "gyro in deg/s under the gyro range",
            |l| scale(l, 1f64.to_degrees()),
            "",
            Some(&["imu.csv", "deg/s? the format is rad/s"]),
        ),
        (
            "heading in rad declared as deg",
            |_| {},
            "[files.heading]\nunits = { angle = \"deg\" }\n",
            Some(&[
                "heading.csv",
                "files.heading.units declares deg",
                "radians?",
            ]),
        ),
        (
            "heading in rad declared as deg, no turn",
            straight,
            "[files.heading]\nunits = { angle = \"deg\" }\n",
            Some(&[
                "heading.csv",
                "files.heading.units declares deg",
                "radians?",
            ]),
        ),
        (
            "heading in deg declared as deg",
            |l| {
                for r in l.heading.as_mut().unwrap() {
                    r.heading = r.heading.to_degrees();
                }
            },
            "[files.heading]\nunits = { angle = \"deg\" }\n",
            None,
        ),
        ("level dive as simulated", level_dive, "", None),
        ("straight, as simulated", straight, "", None),
        (
            "DVL in FLU, no frame declared",
            |l| {
                level_dive(l);
                for r in l.dvl.as_mut().unwrap() {
                    (r.vy, r.vz) = (r.vy.map(|v| -v), r.vz.map(|v| -v));
                }
            },
            "",
            Some(&["dvl.csv", "FLU", "body_frame"]),
        ),
        (
            "DVL in FLU, declared",
            |l| {
                level_dive(l);
                for r in l.dvl.as_mut().unwrap() {
                    (r.vy, r.vz) = (r.vy.map(|v| -v), r.vz.map(|v| -v));
                }
            },
            "[files.dvl]\nbody_frame = \"FLU\"\n",
            None,
        ),
        (
            "DVL in FRD declared FLU",
            level_dive,
            "[files.dvl]\nbody_frame = \"FLU\"\n",
            Some(&["dvl.csv", "files.dvl.body_frame = \"FLU\" declared"]),
        ),
    ]
}

struct Scratch(PathBuf);

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

#[test]
fn mapped_values_are_judged_like_the_standard_format() {
    let base = log();
    let mut failures = Vec::new();
    for (k, (name, edit, section, expect)) in cases().into_iter().enumerate() {
        let dir = Scratch(
            std::env::temp_dir().join(format!("preflight-mapped-{}-{k}", std::process::id())),
        );
        let mut l = base.clone();
        edit(&mut l);
        l.write(&dir.0).unwrap();
        let meta = dir.0.join("meta.toml");
        let text = std::fs::read_to_string(&meta).unwrap();
        std::fs::write(&meta, format!("{text}\n{section}")).unwrap();
        let files = LogFiles::open(&dir.0, Strictness::Strict).unwrap();
        let (report, _) = check_files(&files, &PreflightOptions::default()).unwrap();
        let errors: Vec<String> = report
            .findings
            .iter()
            .filter(|f| f.severity == Severity::Error)
            .map(|f| f.what.to_string())
            .collect();
        match expect {
            None if !errors.is_empty() => failures.push(format!("{name}: {errors:?}")),
            Some(texts) if !errors.iter().any(|e| texts.iter().all(|t| e.contains(t))) => {
                failures.push(format!("{name}: no error with {texts:?} in {errors:?}"))
            }
            _ => {}
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
