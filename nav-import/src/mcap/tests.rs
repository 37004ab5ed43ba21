//! Bag import tests on bags written here with the `mcap` crate's writer and
//! a small CDR encoder: a survey's files, frames and units; the error cases
//! as one table; property tests (truncations, bit flips) that never panic.

use proptest::prelude::*;

use super::{read, ImportError, ImportedBag, Mapping};

use super::writer::{self, tf_message, Enc};

/// ENU quaternion (x, y, z, w) of a level body at ENU yaw `yaw` (rad).
fn yaw_q(yaw: f64) -> [f64; 4] {
    [0.0, 0.0, (yaw / 2.0).sin(), (yaw / 2.0).cos()]
}

fn imu(ns: i64, q: Option<[f64; 4]>, rate: [f64; 3], accel: [f64; 3]) -> Vec<u8> {
    writer::imu(ns, "imu_link", q, rate, accel, 1e-6, 1e-4)
}

fn mag(ns: i64, tesla: [f64; 3]) -> Vec<u8> {
    writer::mag(ns, "mag", tesla, 1e-14)
}

fn pressure(ns: i64, pa: f64) -> Vec<u8> {
    writer::pressure(ns, "ps", pa, 100.0)
}

fn fix(ns: i64, lat: f64, lon: f64, alt: f64, status: i8) -> Vec<u8> {
    writer::fix(ns, "gps", [lat, lon, alt], status, 4.0)
}

fn twist(ns: i64, v: [f64; 3]) -> Vec<u8> {
    writer::twist(ns, "dvl_link", v, 0.01)
}
fn range(ns: i64, r: f32) -> Vec<u8> {
    Enc::new()
        .header(ns, "alt")
        .u8(1)
        .f32(0.1)
        .f32(0.5)
        .f32(100.0)
        .f32(r)
        .0
}

fn tf_static(frame: &str, t: [f64; 3]) -> Vec<u8> {
    tf_message(&[("base_link", frame, t, [0.0, 0.0, 0.0, 1.0])])
}

/// One static transform: parent, child, translation (m), rotation x y z w.
type Tf = (&'static str, &'static str, [f64; 3], [f64; 4]);

/// A bag of `topics`: (topic, ROS type, messages as (log time ns, CDR bytes)).
/// One topic of a test bag: name, ROS type, messages as (log time ns, CDR bytes).
type Topic = (&'static str, &'static str, Vec<(u64, Vec<u8>)>);

fn bag(topics: &[Topic]) -> Vec<u8> {
    let topics: Vec<writer::Topic> = topics
        .iter()
        .map(|(t, ty, m)| (t.to_string(), ty.to_string(), m.clone()))
        .collect();
    writer::bag(&topics)
}

const T0: i64 = 1_700_000_000_000_000_000;
const MS: i64 = 1_000_000;
/// ENU yaw of the survey: 60 deg from east = 30 deg from north.
const YAW_ENU: f64 = std::f64::consts::FRAC_PI_3;
const LAT: f64 = 47.4;
const LON: f64 = 8.5;
/// 10 m of sea water at the default density.
const PA: f64 = 101_325.0 + 1025.0 * 9.806_65 * 10.0;

/// A 2-s survey: IMU 100 Hz, magnetometer 20 Hz, pressure 10 Hz, fix 1 Hz,
/// DVL and altimeter 5 Hz; the static transform of the DVL.
fn survey() -> Vec<Topic> {
    let at = |k: i64| (T0 + k * 10 * MS) as u64 + 1_000;
    let every = |n: i64, f: &dyn Fn(i64) -> Vec<u8>| -> Vec<(u64, Vec<u8>)> {
        (0..200)
            .filter(|k| k % n == 0)
            .map(|k| (at(k), f(T0 + k * 10 * MS)))
            .collect()
    };
    vec![
        (
            "/imu/data",
            "sensor_msgs/msg/Imu",
            every(1, &|ns| {
                imu(
                    ns,
                    Some(yaw_q(YAW_ENU)),
                    [0.01, 0.02, 0.03],
                    [0.1, 0.2, 9.81],
                )
            }),
        ),
        (
            "/imu/mag",
            "sensor_msgs/msg/MagneticField",
            every(5, &|ns| mag(ns, [2e-5, -1e-5, -4e-5])),
        ),
        (
            "/pressure",
            "sensor_msgs/msg/FluidPressure",
            every(10, &|ns| pressure(ns, PA)),
        ),
        (
            "/fix",
            "sensor_msgs/NavSatFix",
            every(100, &|ns| fix(ns, LAT, LON, 3.0, 0)),
        ),
        (
            "/dvl/twist",
            "geometry_msgs/msg/TwistWithCovarianceStamped",
            every(20, &|ns| twist(ns, [1.0, 0.2, -0.1])),
        ),
        (
            "/altimeter",
            "sensor_msgs/msg/Range",
            every(20, &|ns| range(ns, 12.5)),
        ),
        (
            "/tf_static",
            "tf2_msgs/msg/TFMessage",
            vec![(T0 as u64, tf_static("dvl_link", [0.5, 0.1, -0.2]))],
        ),
    ]
}

fn import(bytes: &[u8], mapping: &Mapping) -> ImportedBag {
    match read("survey.mcap", bytes, mapping) {
        Ok(b) => b,
        Err(e) => panic!("{e}"),
    }
}

fn close(a: f64, b: f64, tol: f64, what: &str) {
    assert!((a - b).abs() <= tol, "{what}: {a} vs {b}");
}

#[test]
fn a_survey_bag_gives_the_log_directory() {
    let log = import(&bag(&survey()), &Mapping::default());
    let imu = log.file("imu.csv").expect("imu.csv");
    assert_eq!(imu.rows(), 200);
    let r = imu.row(0);
    close(r[0], 0.0, 1e-12, "t: seconds after the first stamp");
    // FLU -> FRD: y and z negated.
    for (i, v) in [0.01, -0.02, -0.03, 0.1, -0.2, -9.81].iter().enumerate() {
        close(r[1 + i], *v, 1e-12, "imu");
    }
    let m = log.file("mag.csv").expect("mag.csv").row(0);
    close(m[1], 0.2, 1e-12, "mx gauss");
    close(m[2], 0.1, 1e-12, "my");
    close(m[3], 0.4, 1e-12, "mz");
    close(
        log.file("depth.csv").expect("depth").row(0)[1],
        10.0,
        1e-9,
        "depth",
    );
    let g = log.file("gnss.csv").expect("gnss").row(0);
    close(g[1], LAT.to_radians(), 1e-12, "lat");
    close(g[4], 2.0, 1e-12, "eph from the covariance");
    let d = log.file("dvl.csv").expect("dvl").row(0);
    assert_eq!(&d[1..], &[1.0, -0.2, 0.1]);
    close(
        log.file("altitude.csv").expect("alt").row(0)[1],
        12.5,
        1e-6,
        "alt",
    );
    let meta =
        nav_runtime::log::Meta::parse(&log.meta).unwrap_or_else(|e| panic!("{e}\n{}", log.meta));
    close(meta.initial.lat, LAT.to_radians(), 1e-12, "initial lat");
    close(
        meta.initial.yaw.expect("yaw"),
        30f64.to_radians(),
        1e-9,
        "yaw: ENU 60 deg is NED 30 deg",
    );
    close(meta.initial.roll.expect("roll"), 0.0, 1e-12, "roll");
    let imu_noise = meta
        .sensors
        .imu
        .expect("[sensors.imu] from the covariances");
    close(imu_noise.gyro_noise_sigma, 1e-3, 1e-12, "gyro sigma");
    let dvl = meta.sensors.dvl.expect("[sensors.dvl]");
    close(dvl.noise_sigma, 0.1, 1e-12, "dvl sigma");
    assert!(
        log.meta.contains("lever_arm = [5e-1, -1e-1, 2e-1]"),
        "{}",
        log.meta
    );
    // Message counts survive the channel records repeated in the summary.
    assert!(
        log.summary
            .topics
            .iter()
            .any(|t| t.0 == "/imu/data" && t.2 == "imu" && t.3 == 200),
        "{:?}",
        log.summary.topics
    );
    let topics: Vec<&str> = log.summary.topics.iter().map(|t| t.2.as_str()).collect();
    assert!(
        topics.contains(&"dvl") && topics.contains(&"ignore"),
        "{topics:?}"
    );
    // The written directory is read strictly by the project's log reader.
    let dir = std::env::temp_dir().join(format!("mcap-logdir-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    log.write(&dir).expect("written");
    let read = nav_runtime::log::LogDir::read(&dir, nav_runtime::log::Strictness::Strict);
    let _ = std::fs::remove_dir_all(&dir);
    let read = read.expect("read by LogDir");
    assert_eq!(read.imu.len(), 200);
    assert_eq!(read.dvl.as_ref().map(Vec::len), Some(10));
    assert_eq!(read.depth.as_ref().map(Vec::len), Some(20));
}

/// Declarations of the mapping file change what they say, nothing else.
#[test]
fn mapping_cases() {
    type Check = fn(&ImportedBag);
    let cases: [(&str, &str, Check); 5] = [
        (
            "a DVL already in FRD",
            "[topics.\"/dvl/twist\"]\nsensor = \"dvl\"\nbody_frame = \"FRD\"\n",
            |log| {
                let d = log.file("dvl.csv").expect("dvl").row(0);
                assert_eq!(&d[1..], &[1.0, 0.2, -0.1]);
            },
        ),
        ("fresh water", "[water]\ndensity = 1000.0\n", |log| {
            let d = log.file("depth.csv").expect("depth").row(0)[1];
            close(d, 10.25, 1e-9, "depth in fresh water");
        }),
        ("receive time", "time = \"receive\"\n", |log| {
            // Every log time is 1 us after its stamp: the same seconds.
            close(
                log.file("imu.csv").expect("imu").row(1)[0],
                0.01,
                1e-12,
                "t",
            );
            assert!(log
                .summary
                .warnings
                .iter()
                .any(|w| w.contains("receive clock")));
        }),
        (
            "a topic ignored",
            "[topics.\"/altimeter\"]\nsensor = \"ignore\"\n",
            |log| assert!(log.file("altitude.csv").is_none()),
        ),
        (
            // Misspelt: the bag's topic is `/imu/data`. Said, with the
            // topic meant (it was silently not used).
            "a mapped topic the bag lacks",
            "[topics.\"/imu/dada\"]\nsensor = \"imu\"\n",
            |log| {
                let said =
                    "mapping: topic `/imu/dada` is not in the bag (did you mean `/imu/data`?)";
                let w = &log.summary.warnings;
                assert!(w.iter().any(|w| w.starts_with(said)), "{w:?}");
            },
        ),
    ];
    let bytes = bag(&survey());
    for (name, text, check) in cases {
        let mapping = Mapping::parse("map.toml", text).unwrap_or_else(|e| panic!("{name}: {e}"));
        check(&import(&bytes, &mapping));
    }
}

/// ENU / FLU quaternion of a rotation of `angle` (rad) about `axis`.
fn axis_q(axis: [f64; 3], angle: f64) -> [f64; 4] {
    let (sin, cos) = (angle / 2.0).sin_cos();
    [axis[0] * sin, axis[1] * sin, axis[2] * sin, cos]
}

/// Mountings from `/tf_static`, one row each: the transforms (one
/// `TFMessage` per inner list), the mapping, and either the DVL row, the
/// first IMU row, the DVL lever arm from the IMU (FRD) and the initial yaw
/// (deg), with a warning expected; or the error.
#[test]
fn mounting_cases() {
    use std::f64::consts::{FRAC_PI_2, PI};
    let z = [0.0, 0.0, 1.0];
    let x = [1.0, 0.0, 0.0];
    let unit = [0.0, 0.0, 0.0, 1.0];
    let yaw90 = axis_q(z, FRAC_PI_2);
    let scaled = yaw90.map(|v| v * 1.003);
    // The survey's sensors: DVL (FLU) [1, 0.2, -0.1], IMU rate [0.01,
    // 0.02, 0.03] and force [0.1, 0.2, 9.81], IMU attitude ENU yaw 60 deg.
    let imu_frd = [0.01, -0.02, -0.03, 0.1, -0.2, -9.81];
    struct Expect {
        dvl: [f64; 3],
        imu: [f64; 6],
        arm: Option<[f64; 3]>,
        yaw_deg: f64,
        warning: &'static str,
    }
    type Case = (
        &'static str,
        Vec<Vec<Tf>>,
        &'static str,
        Result<Expect, &'static str>,
    );
    let cases: Vec<Case> = vec![
        (
            "DVL yawed 90 deg",
            vec![vec![("base_link", "dvl_link", [0.5, 0.1, -0.2], yaw90)]],
            "",
            Ok(Expect {
                dvl: [-0.2, -1.0, 0.1],
                imu: imu_frd,
                arm: Some([0.5, -0.1, 0.2]),
                yaw_deg: 30.0,
                warning: "body frame `base_link` (base_link, in /tf_static)",
            }),
        ),
        (
            "DVL rolled 180 deg (an FRD-mounted unit)",
            vec![vec![("base_link", "dvl_link", [0.0, 0.0, -1.0], axis_q(x, PI))]],
            "",
            Ok(Expect {
                dvl: [1.0, 0.2, -0.1],
                imu: imu_frd,
                arm: Some([0.0, 0.0, 1.0]),
                yaw_deg: 30.0,
                warning: "vectors rotated into it",
            }),
        ),
        (
            "a two-level chain in two messages",
            vec![
                vec![("base_link", "mast", [1.0, 0.0, 0.0], yaw90)],
                vec![("/mast", "dvl_link", [0.5, 0.0, 0.0], unit)],
            ],
            "",
            Ok(Expect {
                dvl: [-0.2, -1.0, 0.1],
                imu: imu_frd,
                arm: Some([1.0, -0.5, 0.0]),
                yaw_deg: 30.0,
                warning: "lever arms from the IMU",
            }),
        ),
        (
            "an IMU yawed 180 deg on base_link",
            vec![vec![
                ("base_link", "imu_link", [0.2, 0.0, 0.0], axis_q(z, PI)),
                ("base_link", "dvl_link", [0.5, 0.0, 0.0], unit),
            ]],
            "",
            Ok(Expect {
                dvl: [1.0, -0.2, 0.1],
                imu: [-0.01, 0.02, -0.03, -0.1, 0.2, -9.81],
                arm: Some([0.3, 0.0, 0.0]),
                yaw_deg: -150.0,
                warning: "vectors rotated",
            }),
        ),
        (
            "the IMU's frame declared the body frame, the DVL a sibling",
            vec![vec![
                ("base_link", "imu_link", [0.2, 0.0, 0.0], yaw90),
                ("base_link", "dvl_link", [0.2, 1.0, 0.0], unit),
            ]],
            "vehicle_frame = \"imu_link\"\n",
            Ok(Expect {
                dvl: [0.2, 1.0, 0.1],
                imu: imu_frd,
                arm: Some([1.0, 0.0, 0.0]),
                yaw_deg: 30.0,
                warning: "the mapping's vehicle_frame",
            }),
        ),
        (
            "a quaternion of norm 1.003, normalised",
            vec![vec![("base_link", "dvl_link", [0.5, 0.1, -0.2], scaled)]],
            "",
            Ok(Expect {
                dvl: [-0.2, -1.0, 0.1],
                imu: imu_frd,
                arm: Some([0.5, -0.1, 0.2]),
                yaw_deg: 30.0,
                warning: "topic `/tf_static`, message 0: a rotation of norm 1.003000000 normalised",
            }),
        ),
        (
            "a parent missing: not connected",
            vec![vec![
                ("base_link", "imu_link", [0.0; 3], unit),
                ("mast", "dvl_link", [0.5, 0.0, 0.0], yaw90),
            ]],
            "",
            Ok(Expect {
                dvl: [1.0, -0.2, 0.1],
                imu: imu_frd,
                arm: None,
                yaw_deg: 30.0,
                warning: "dvl.csv: frame `dvl_link` is not connected to the body frame `base_link` in /tf_static (its chain ends at `mast`)",
            }),
        ),
        (
            "a cycle",
            vec![
                vec![("base_link", "imu_link", [0.0; 3], unit)],
                vec![("a", "dvl_link", [0.0; 3], unit), ("dvl_link", "a", [0.0; 3], unit)],
            ],
            "",
            Err("topic `/tf_static`, message 1: transform `dvl_link` -> `a` closes a cycle of frames (from `dvl_link`)"),
        ),
        (
            "a quaternion of norm 1.41",
            vec![
                vec![("base_link", "imu_link", [0.0; 3], unit)],
                vec![("base_link", "dvl_link", [0.0; 3], [0.0, 0.0, 1.0, 1.0])],
            ],
            "",
            Err("topic `/tf_static`, message 1: transform `base_link` -> `dvl_link`: rotation (0, 0, 1, 1) has norm 1.414214: a unit quaternion expected"),
        ),
        (
            "a zero quaternion",
            vec![vec![("base_link", "dvl_link", [0.0; 3], [0.0; 4])]],
            "",
            Err("message 0: transform `base_link` -> `dvl_link`: rotation (0, 0, 0, 0) has norm 0.000000"),
        ),
        (
            "a NaN translation",
            vec![vec![("base_link", "dvl_link", [0.0, f64::NAN, 0.0], unit)]],
            "",
            Err("message 0: transform `base_link` -> `dvl_link`: translation component NaN: finite and within 1000 m"),
        ),
        (
            "a DVL 5 km from the body",
            vec![vec![("base_link", "dvl_link", [5000.0, 0.0, 0.0], unit)]],
            "",
            Err("translation component 5000: finite and within 1000 m expected for a mounting"),
        ),
        (
            "two 800 m arms: 1.6 km from the IMU",
            vec![vec![
                ("base_link", "imu_link", [-800.0, 0.0, 0.0], unit),
                ("base_link", "dvl_link", [800.0, 0.0, 0.0], unit),
            ]],
            "",
            Err("dvl.csv: frame `dvl_link` is 1.600e3 m from the IMU in the body frame"),
        ),
    ];
    for (name, messages, mapping, expect) in cases {
        let mut s = survey();
        s.retain(|t| t.0 != "/tf_static");
        let tf: Vec<(u64, Vec<u8>)> = messages
            .iter()
            .enumerate()
            .map(|(i, list)| (T0 as u64 + i as u64, tf_message(list)))
            .collect();
        s.push(("/tf_static", "tf2_msgs/msg/TFMessage", tf));
        let mapping = Mapping::parse("map.toml", mapping).unwrap_or_else(|e| panic!("{name}: {e}"));
        let result = read("case.mcap", bag(&s).as_slice(), &mapping);
        match (result, expect) {
            (Ok(log), Ok(e)) => {
                let d = log.file("dvl.csv").expect("dvl").row(3);
                for i in 0..3 {
                    close(d[1 + i], e.dvl[i], 1e-12, &format!("{name}: dvl[{i}]"));
                }
                let r = log.file("imu.csv").expect("imu").row(7);
                for i in 0..6 {
                    close(r[1 + i], e.imu[i], 1e-12, &format!("{name}: imu[{i}]"));
                }
                let meta = nav_runtime::log::Meta::parse(&log.meta)
                    .unwrap_or_else(|err| panic!("{name}: {err}\n{}", log.meta));
                let arm = meta.sensors.mounting("dvl").map(|m| m.lever_arm);
                match (arm, e.arm) {
                    (Some(a), Some(b)) => {
                        for i in 0..3 {
                            close(a[i], b[i], 1e-12, &format!("{name}: lever arm[{i}]"));
                        }
                    }
                    (a, b) => assert_eq!(a, b, "{name}: lever arm"),
                }
                let yaw = meta.initial.yaw.expect("yaw").to_degrees();
                close(yaw, e.yaw_deg, 1e-9, &format!("{name}: initial yaw"));
                assert!(
                    log.summary.warnings.iter().any(|w| w.contains(e.warning)),
                    "{name}: no warning `{}` in {:?}",
                    e.warning,
                    log.summary.warnings
                );
            }
            (Err(err), Err(part)) => {
                let text = err.to_string();
                assert!(
                    text.starts_with("case.mcap: topic `/tf_static`, message "),
                    "{name}: {text}"
                );
                assert!(text.contains(part), "{name}: `{text}` lacks `{part}`");
            }
            (Ok(_), Err(part)) => panic!("{name}: imported, `{part}` expected"),
            (Err(err), Ok(_)) => panic!("{name}: {err}"),
        }
    }
}

/// Broken bags and mappings, one row each: the error names the topic and
/// message index (or the mapping key).
#[test]
fn error_cases() {
    let survey_bytes = bag(&survey());
    let with = |topic: &'static str, ty: &'static str, msgs: Vec<(u64, Vec<u8>)>| {
        let mut s = survey();
        s.push((topic, ty, msgs));
        bag(&s)
    };
    let t = T0 as u64;
    let cases: Vec<(&str, Vec<u8>, &str, &str)> = vec![
        ("empty file", vec![], "", "truncated bag"),
        (
            "truncated",
            survey_bytes[..survey_bytes.len() / 2].to_vec(),
            "",
            "truncated bag",
        ),
        ("not MCAP", b"PK\x03\x04 zip".to_vec(), "", "MCAP"),
        (
            "an Imu too short for its schema",
            with("/imu2", "sensor_msgs/msg/Imu", vec![(t, Enc::new().header(T0, "").0)]),
            "[topics.\"/imu/data\"]\nsensor = \"ignore\"\n",
            "topic `/imu2`, message 0: sensor_msgs/msg/Imu: field `orientation`: 8 bytes needed",
        ),
        (
            "a wrong schema on a mapped topic",
            with("/imu2", "sensor_msgs/msg/Imu", vec![(t, mag(T0, [0.0; 3]))]),
            "[topics.\"/imu/data\"]\nsensor = \"ignore\"\n",
            "topic `/imu2`, message 0: sensor_msgs/msg/Imu: field `",
        ),
        (
            "a frame id of 4 GB",
            with(
                "/depth2",
                "sensor_msgs/msg/FluidPressure",
                vec![(t, Enc::new().u32(1).u32(0).u32(u32::MAX).0)],
            ),
            "[topics.\"/pressure\"]\nsensor = \"ignore\"\n",
            "topic `/depth2`, message 0: sensor_msgs/msg/FluidPressure: field `header.frame_id`: string of 4294967295 bytes",
        ),
        (
            "a stamp in microseconds",
            with(
                "/alt2",
                "sensor_msgs/msg/Range",
                vec![(t + 1_000_000_000, range(T0 / 1000, 3.0))],
            ),
            "[topics.\"/altimeter\"]\nsensor = \"ignore\"\n",
            "topic `/alt2`, message 0: time -1.698e9 s from the bag's first message",
        ),
        (
            "an unset stamp",
            with("/alt2", "sensor_msgs/msg/Range", vec![(t + 1_000_000_000, range(0, 3.0))]),
            "[topics.\"/altimeter\"]\nsensor = \"ignore\"\n",
            "topic `/alt2`, message 0: header.stamp is zero",
        ),
        (
            "two IMU topics, no mapping",
            with("/imu2", "sensor_msgs/msg/Imu", vec![]),
            "",
            "topics `/imu/data` and `/imu2` would both feed imu.csv: say which in a mapping file",
        ),
        (
            "a pose without an origin",
            with(
                "/usbl",
                "geometry_msgs/msg/PoseWithCovarianceStamped",
                vec![(t, Enc::new().header(T0, "map").f64s(&[0.0; 7]).f64s(&[0.0; 36]).0)],
            ),
            "",
            "topic `/usbl`, message 0: a position in a local frame: declare its `origin",
        ),
        (
            "a mapped topic of a type not read",
            with("/cam", "sensor_msgs/msg/Image", vec![]),
            "[topics.\"/cam\"]\nsensor = \"dvl\"\n",
            "topic `/cam`: type `sensor_msgs/msg/Image` (cdr) is not one the import reads",
        ),
        (
            "a misspelled sensor",
            survey_bytes.clone(),
            "[topics.\"/fix\"]\nsensor = \"gps\"\n",
            "`topics.\"/fix\".sensor`: `gps`, one of imu, mag",
        ),
        (
            "an unknown mapping key",
            survey_bytes.clone(),
            "density = 1000.0\n",
            "unknown field `density`",
        ),
    ];
    for (name, bytes, mapping, part) in cases {
        let result = Mapping::parse("map.toml", mapping)
            .and_then(|m| read("case.mcap", bytes.as_slice(), &m));
        match result {
            Ok(_) => panic!("{name}: imported"),
            Err(e) => {
                let text = e.to_string();
                assert!(
                    text.starts_with("case.mcap: ") || text.starts_with("map.toml: "),
                    "{name}: {text}"
                );
                assert!(text.contains(part), "{name}: `{text}` lacks `{part}`");
                assert!(!matches!(e, ImportError::Io { .. }), "{name}");
            }
        }
    }
}

fn small() -> Vec<u8> {
    let mut s = survey();
    for (_, _, msgs) in &mut s {
        msgs.truncate(3);
    }
    bag(&s)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    /// Any prefix of a bag is imported or refused; never a panic.
    #[test]
    fn truncations_never_panic(cut in 0usize..20_000) {
        let bytes = small();
        let cut = cut.min(bytes.len());
        if let Err(e) = read("cut.mcap", &bytes[..cut], &Mapping::default()) {
            prop_assert!(e.to_string().starts_with("cut.mcap: "));
        }
    }

    /// Bit flips anywhere: imported or refused; never a panic.
    #[test]
    fn bit_flips_never_panic(flips in proptest::collection::vec((0usize..20_000, 0u8..8), 1..8)) {
        let mut bytes = small();
        for (at, bit) in flips {
            let n = bytes.len();
            bytes[at % n] ^= 1 << bit;
        }
        if let Err(e) = read("flip.mcap", bytes.as_slice(), &Mapping::default()) {
            prop_assert!(e.to_string().starts_with("flip.mcap: "));
        }
    }
}
