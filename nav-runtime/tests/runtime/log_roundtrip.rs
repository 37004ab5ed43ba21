//! Writing a log and reading it back gives the same values; the writer never leaves
//! partial output; the merged event stream is time-ordered.

use crate::common;

use common::*;
use nav_runtime::log::*;

#[test]
fn write_then_read_is_identity() {
    let log = sample_log();
    let dir = TempDir::new("rt");
    let target = dir.path().join("log");
    log.write(&target).unwrap();
    let back = LogDir::read(&target, Strictness::Strict).unwrap();
    assert_eq!(back, log);
    // Bit-exact floats (PartialEq would accept -0.0 == 0.0).
    for (a, b) in back.imu.iter().zip(&log.imu) {
        assert_eq!(a.gx.to_bits(), b.gx.to_bits());
        assert_eq!(a.ay.to_bits(), b.ay.to_bits());
    }
    // No staging directories left next to the target.
    let names: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, vec!["log".to_string()]);
}

#[test]
fn meta_text_round_trip() {
    let meta = sample_log().meta;
    let text = meta.to_toml();
    assert_eq!(Meta::parse(&text).unwrap(), meta);
}

#[test]
fn float_format_round_trips() {
    for v in [
        0.1 + 0.2,
        1e-300,
        -2.5e-7,
        1e16,
        123456789.125,
        -0.0,
        5e-324,
        f64::MAX,
        1.0 / 3.0,
    ] {
        let s = format_f64(v);
        assert_eq!(
            s.parse::<f64>().unwrap().to_bits(),
            v.to_bits(),
            "{v} -> {s}"
        );
    }
}

#[test]
fn rewriting_removes_stale_sensor_files_only() {
    let dir = TempDir::new("stale");
    let target = dir.path().join("log");
    sample_log().write(&target).unwrap();
    std::fs::write(target.join("notes.txt"), "keep me").unwrap();
    let mut smaller = sample_log();
    smaller.dvl = None;
    smaller.truth = None;
    smaller.write(&target).unwrap();
    assert!(!target.join("dvl.csv").exists());
    assert!(!target.join("truth.csv").exists());
    assert_eq!(
        std::fs::read_to_string(target.join("notes.txt")).unwrap(),
        "keep me"
    );
    assert_eq!(LogDir::read(&target, Strictness::Strict).unwrap(), smaller);
}

#[test]
fn writing_over_a_file_fails_without_leftovers() {
    let dir = TempDir::new("file");
    let target = dir.path().join("log");
    std::fs::write(&target, "not a dir").unwrap();
    let err = sample_log().write(&target).unwrap_err();
    assert!(matches!(err, LogError::Write { .. }), "{err:?}");
    let count = std::fs::read_dir(dir.path()).unwrap().count();
    assert_eq!(count, 1);
}

/// A sensor's mounting or `estimate` lives in its `meta.toml` section, which
/// needs the sensor's noise: a log that has them without it is refused
/// (naming the sensor) rather than written without them. With the noise,
/// they come back as written.
#[test]
fn a_mounting_without_its_sensor_section_is_refused_not_dropped() {
    let dir = TempDir::new("mounting");
    // (case, edit of a log without a DVL section)
    type Edit = fn(&mut LogDir);
    let cases: [(&str, Edit); 2] = [
        ("a lever arm", |l| {
            l.meta.sensors.mountings[0] = Some(Mounting {
                lever_arm: [1.0, 0.2, 0.0],
                misalignment: [0.0; 3],
            })
        }),
        ("an estimate", |l| {
            l.meta.sensors.dvl_calibration.time_offset = Some(0.5)
        }),
    ];
    for (i, (what, edit)) in cases.into_iter().enumerate() {
        let target = dir.path().join(format!("log{i}"));
        let mut log = sample_log();
        log.meta.sensors.dvl = None;
        edit(&mut log);
        let err = log.write(&target).unwrap_err();
        assert!(
            matches!(&err, LogError::Write { reason, .. } if reason.contains("sensor `dvl`")),
            "{what}: {err:?}"
        );
        assert!(!target.exists(), "{what}: nothing written");
        log.meta.sensors.dvl = Some(SensorNoise {
            bias_sigma: 0.0,
            noise_sigma: 0.02,
        });
        log.write(&target).unwrap();
        let back = LogDir::read(&target, Strictness::Strict).unwrap();
        assert_eq!(back.meta.sensors, log.meta.sensors, "{what}");
    }
}

#[test]
fn events_are_merged_in_time_order_imu_first_on_ties() {
    let log = sample_log();
    let events: Vec<Event> = log.events().collect();
    let aiding: usize = [
        log.dvl.as_ref().map_or(0, Vec::len),
        log.depth.as_ref().map_or(0, Vec::len),
        log.heading.as_ref().map_or(0, Vec::len),
        log.usbl.as_ref().map_or(0, Vec::len),
        log.speed.as_ref().map_or(0, Vec::len),
        log.rpm.as_ref().map_or(0, Vec::len),
        log.altitude.as_ref().map_or(0, Vec::len),
    ]
    .iter()
    .sum();
    assert_eq!(events.len(), log.imu.len() + aiding);
    for w in events.windows(2) {
        assert!(w[0].t() <= w[1].t());
    }
    // depth at t = 0.1 and the IMU sample at t = 0.1: IMU first.
    let i = events
        .iter()
        .position(|e| matches!(e, Event::Depth(d) if d.t == 0.1))
        .unwrap();
    assert!(matches!(events[i - 1], Event::Imu(r) if r.t == 0.1));
    // speed at t = 0 comes after the IMU sample at t = 0.
    assert!(matches!(events[0], Event::Imu(_)));
    assert!(matches!(events[1], Event::Speed(_)));
}
