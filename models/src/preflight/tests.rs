//! The preflight on a small simulated log: clean as simulated, and each
//! check firing on the mistake it is for (cases as data).

use nav_runtime::log::{LogDir, WarningKind};

use super::{check, PreflightOptions, Severity};
use crate::sdins25::simulation::{simulate, SimConfig};

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
            "truth.csv",
        ]),
        ..PreflightOptions::default()
    }
}

#[test]
fn simulated_log_is_clean() {
    // The simulator writes an echo sounder the SDINS models do not read.
    let report = check(&log(), &sdins());
    let unused: Vec<_> = report
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
    // Without the model's file list the altitude file has no section.
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
