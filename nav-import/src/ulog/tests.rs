//! Import tests on ULog files written by [`super::writer`]: both PX4 layouts,
//! increments, several instances, the error cases as one table, and property
//! tests (truncations, bit flips) that must never panic.

use proptest::prelude::*;

use super::writer::{Payload, Writer};
use super::{read, read_unguarded, CsvFile, ImportError, ImportedLog};

/// Which generation of PX4 topics the synthetic flight is written with.
#[derive(Clone, Copy, PartialEq, Debug)]
enum Layout {
    /// Separate magnetometer, air-data and GNSS topics, GNSS in degrees.
    New,
    /// Magnetometer and barometer inside `sensor_combined`, GNSS in 1e-7 deg / mm.
    Old,
    /// `vehicle_imu` increments instead of `sensor_combined`.
    Increments,
}

const LAT_DEG: f64 = 47.4;
const LON_DEG: f64 = 8.5;
const HEIGHT: f64 = 500.0;
const MSL: f64 = 450.0;
const YAW_DEG: f64 = 30.0;
const GYRO: [f32; 3] = [0.01, -0.02, 0.03];
const ACCEL: [f32; 3] = [0.1, 0.2, -9.81];
const MAG: [f32; 3] = [0.2, 0.1, 0.4];
const BARO: f32 = 450.5;
const T0_US: u64 = 1_000_000;
const TICKS: u64 = 200;

/// A stationary flight at 100 Hz for 2 s, yaw 30 deg.
fn flight(layout: Layout, mag_instances: u8) -> Writer {
    let mut w = Writer::new();
    match layout {
        Layout::New | Layout::Increments => {
            w.format("sensor_combined:uint64_t timestamp;float[3] gyro_rad;uint32_t gyro_integral_dt;int32_t accelerometer_timestamp_relative;float[3] accelerometer_m_s2;");
            w.format("vehicle_magnetometer:uint64_t timestamp;uint64_t timestamp_sample;uint32_t device_id;float[3] magnetometer_ga;");
            w.format("vehicle_air_data:uint64_t timestamp;uint64_t timestamp_sample;float baro_alt_meter;");
            w.format("vehicle_gps_position:uint64_t timestamp;uint64_t timestamp_sample;double latitude_deg;double longitude_deg;double altitude_msl_m;double altitude_ellipsoid_m;float eph;float epv;float vel_n_m_s;float vel_e_m_s;float vel_d_m_s;float s_variance_m_s;uint8_t fix_type;");
        }
        Layout::Old => {
            w.format("sensor_combined:uint64_t timestamp;float[3] gyro_rad;float[3] accelerometer_m_s2;int32_t accelerometer_timestamp_relative;float[3] magnetometer_ga;int32_t magnetometer_timestamp_relative;float baro_alt_meter;int32_t baro_timestamp_relative;");
            w.format("vehicle_gps_position:uint64_t timestamp;int32_t lat;int32_t lon;int32_t alt;int32_t alt_ellipsoid;float eph;float epv;uint8_t fix_type;");
        }
    }
    w.format("vehicle_imu:uint64_t timestamp;uint64_t timestamp_sample;float[3] delta_angle;float[3] delta_velocity;uint16_t delta_angle_dt;");
    w.format("vehicle_attitude:uint64_t timestamp;uint64_t timestamp_sample;float[4] q;");
    w.format("vehicle_global_position:uint64_t timestamp;uint64_t timestamp_sample;double lat;double lon;float alt;float alt_ellipsoid;");
    w.format("vehicle_local_position:uint64_t timestamp;uint64_t timestamp_sample;float vx;float vy;float vz;");
    w.parameter("EKF2_GYR_NOISE", 0.02);
    w.parameter("EKF2_MAG_NOISE", 0.07);
    let imu_topic = if layout == Layout::Increments {
        "vehicle_imu"
    } else {
        "sensor_combined"
    };
    w.subscribe(0, 0, imu_topic);
    w.subscribe(0, 1, "vehicle_gps_position");
    w.subscribe(0, 2, "vehicle_attitude");
    w.subscribe(0, 3, "vehicle_global_position");
    w.subscribe(0, 4, "vehicle_local_position");
    if layout != Layout::Old {
        w.subscribe(0, 5, "vehicle_air_data");
        for i in 0..mag_instances {
            w.subscribe(i, 10 + u16::from(i), "vehicle_magnetometer");
        }
    }
    let half = (YAW_DEG.to_radians() / 2.0) as f32;
    for k in 0..TICKS {
        let t = T0_US + k * 10_000;
        match layout {
            Layout::New => {
                w.data(
                    0,
                    &Payload::default()
                        .u64(t)
                        .f32s(&GYRO)
                        .u32(10_000)
                        .i32(0)
                        .f32s(&ACCEL),
                );
            }
            Layout::Increments => {
                let da = GYRO.map(|g| g * 0.01);
                let dv = ACCEL.map(|a| a * 0.01);
                w.data(
                    0,
                    &Payload::default()
                        .u64(t)
                        .u64(t)
                        .f32s(&da)
                        .f32s(&dv)
                        .u16(10_000),
                );
            }
            Layout::Old => {
                // Magnetometer and barometer sampled 2 ms before the gyro, every 5th row valid.
                let rel = if k % 5 == 0 { -2_000 } else { i32::MAX };
                w.data(
                    0,
                    &Payload::default()
                        .u64(t)
                        .f32s(&GYRO)
                        .f32s(&ACCEL)
                        .i32(0)
                        .f32s(&MAG)
                        .i32(rel)
                        .f32s(&[BARO])
                        .i32(rel),
                );
            }
        }
        if k % 5 == 0 {
            if layout != Layout::Old {
                for i in 0..mag_instances {
                    w.data(
                        10 + u16::from(i),
                        &Payload::default().u64(t).u64(t).u32(7).f32s(&MAG),
                    );
                }
                w.data(5, &Payload::default().u64(t).u64(t).f32s(&[BARO]));
            }
            w.data(
                2,
                &Payload::default()
                    .u64(t)
                    .u64(t)
                    .f32s(&[half.cos(), 0.0, 0.0, half.sin()]),
            );
        }
        if k % 10 == 0 {
            w.data(
                3,
                &Payload::default()
                    .u64(t)
                    .u64(t)
                    .f64s(&[LAT_DEG, LON_DEG])
                    .f32s(&[MSL as f32, HEIGHT as f32]),
            );
            w.data(4, &Payload::default().u64(t).u64(t).f32s(&[1.0, 0.5, 0.0]));
        }
        if k % 20 == 0 {
            // The first fix has no 3D fix yet.
            let fix = if k == 0 { 2 } else { 3 };
            let p = match layout {
                Layout::Old => Payload::default()
                    .u64(t)
                    .i32((LAT_DEG * 1e7) as i32)
                    .i32((LON_DEG * 1e7) as i32)
                    .i32((MSL * 1e3) as i32)
                    .i32((HEIGHT * 1e3) as i32)
                    .f32s(&[0.8, 1.2])
                    .u8(fix),
                _ => Payload::default()
                    .u64(t)
                    .u64(t)
                    .f64s(&[LAT_DEG, LON_DEG, MSL, HEIGHT])
                    .f32s(&[0.8, 1.2, 1.0, 0.5, 0.0, 0.2])
                    .u8(fix),
            };
            w.data(1, &p);
        }
    }
    w
}

fn import(bytes: &[u8]) -> ImportedLog {
    match read("flight.ulg", bytes) {
        Ok(log) => log,
        Err(e) => panic!("import failed: {e}"),
    }
}

fn close(a: f64, b: f64, tol: f64, what: &str) {
    assert!((a - b).abs() <= tol, "{what}: {a} vs {b}");
}

fn has_warning(log: &ImportedLog, part: &str) {
    assert!(
        log.warnings.iter().any(|w| w.contains(part)),
        "no warning containing `{part}` in {:#?}",
        log.warnings
    );
}

#[test]
fn both_layouts_give_the_same_log() {
    for layout in [Layout::New, Layout::Old] {
        let log = import(&flight(layout, 1).bytes());
        let imu = log.file("imu.csv").expect("imu.csv");
        assert_eq!(imu.header, ["t", "gx", "gy", "gz", "ax", "ay", "az"]);
        assert_eq!(imu.rows(), TICKS as usize, "{layout:?}");
        let first = imu.row(0);
        // Seconds after the header's start time (0 in these files).
        close(first[0], 1.0, 1e-12, "t");
        for i in 0..3 {
            close(first[1 + i], f64::from(GYRO[i]), 1e-7, "gyro");
            close(first[4 + i], f64::from(ACCEL[i]), 1e-6, "accel");
        }
        let mag = log.file("mag.csv").expect("mag.csv");
        assert_eq!(mag.header, ["t", "mx", "my", "mz"]);
        assert_eq!(mag.rows(), 40, "{layout:?}");
        let sample_delay = if layout == Layout::Old { 0.002 } else { 0.0 };
        close(mag.row(1)[0], 1.05 - sample_delay, 1e-9, "mag time");
        close(mag.row(0)[3], f64::from(MAG[2]), 1e-7, "mz");
        let baro = log.file("baro.csv").expect("baro.csv");
        assert_eq!(baro.rows(), 40);
        close(baro.row(0)[1], f64::from(BARO), 1e-4, "baro");
        let gnss = log.file("gnss.csv").expect("gnss.csv");
        assert_eq!(&gnss.header[..4], ["t", "lat", "lon", "height"]);
        // 10 fixes, the first without a 3D fix.
        assert_eq!(gnss.rows(), 9, "{layout:?}");
        let fix = gnss.row(0);
        close(fix[1], LAT_DEG.to_radians(), 1e-9, "lat");
        close(fix[2], LON_DEG.to_radians(), 1e-9, "lon");
        close(fix[3], HEIGHT, 1e-6, "ellipsoidal height");
        // The fixed schema: the older layout has no velocity, an empty cell.
        assert_eq!(gnss.header.len(), 10);
        assert_eq!(
            fix[6].is_nan(),
            layout == Layout::Old,
            "{layout:?}: {fix:?}"
        );
        let text = gnss.text();
        let line = text.lines().nth(1).unwrap_or_default();
        assert_eq!(line.ends_with(",,,,"), layout == Layout::Old, "{line}");
        has_warning(&log, "fix_type < 3");
        let reference = log.file("reference.csv").expect("reference.csv");
        assert_eq!(
            reference.header,
            ["t", "lat", "lon", "height", "vn", "ve", "vd", "roll", "pitch", "yaw"]
        );
        // Attitude at 20 Hz; the last one lies after the last position (no extrapolation).
        assert_eq!(reference.rows(), 39);
        let r = reference.row(1);
        close(r[9], YAW_DEG.to_radians(), 1e-6, "yaw");
        close(r[7], 0.0, 1e-9, "roll");
        close(r[4], 1.0, 1e-9, "vn (interpolated between equal values)");
        assert!(log.file("truth.csv").is_none());
        if layout == Layout::Old {
            has_warning(
                &log,
                "sensor_combined multi_id 0 (magnetometer_ga, older layout)",
            );
        } else {
            has_warning(&log, "mag.csv: vehicle_magnetometer multi_id 0");
            has_warning(&log, "baro.csv: vehicle_air_data multi_id 0");
        }
    }
}

#[test]
fn meta_toml_is_read_by_the_log_reader() {
    let log = import(&flight(Layout::New, 1).bytes());
    let meta = match nav_runtime::log::Meta::parse(&log.meta) {
        Ok(m) => m,
        Err(e) => panic!("{e}\n{}", log.meta),
    };
    close(meta.initial.lat, LAT_DEG.to_radians(), 1e-9, "initial lat");
    close(meta.initial.depth, -HEIGHT, 1e-4, "initial depth");
    close(meta.initial.vn, 1.0, 1e-9, "initial vn");
    close(
        meta.initial.yaw.expect("yaw"),
        YAW_DEG.to_radians(),
        1e-6,
        "initial yaw",
    );
    let imu = meta.sensors.imu.expect("[sensors.imu]");
    close(imu.gyro_noise_sigma, 0.02, 1e-8, "EKF2_GYR_NOISE");
    // Not in the log: PX4's default, said in the warnings.
    close(imu.accel_noise_sigma, 0.35, 1e-12, "EKF2_ACC_NOISE default");
    has_warning(&log, "EKF2_ACC_NOISE not in the log");
    let noise: toml::Table = log.noise.parse().expect("noise.toml is TOML");
    let mag = noise["mag"]["noise_sigma"].as_float().expect("mag noise");
    close(mag, 0.07, 1e-8, "EKF2_MAG_NOISE");
}

#[test]
fn increments_and_instances() {
    let log = import(&flight(Layout::Increments, 2).bytes());
    let imu = log.file("imu.csv").expect("imu.csv");
    assert_eq!(
        imu.header,
        ["t", "dtheta_x", "dtheta_y", "dtheta_z", "dv_x", "dv_y", "dv_z"]
    );
    close(imu.row(0)[3], f64::from(GYRO[2] * 0.01), 1e-9, "dtheta_z");
    has_warning(&log, "vehicle_imu multi_id 0 (increments");
    has_warning(
        &log,
        "vehicle_magnetometer: 2 instances (multi_id 0, 1); multi_id 0 used",
    );
}

#[test]
fn a_truncated_file_is_read_up_to_its_last_whole_message() {
    let bytes = flight(Layout::New, 1).bytes();
    // The last message is the last IMU sample: cut inside it, it is lost, nothing else.
    let log = import(&bytes[..bytes.len() - 5]);
    has_warning(&log, "truncated log");
    assert_eq!(
        log.file("imu.csv").map(|f| f.rows()),
        Some(TICKS as usize - 1)
    );
    assert_eq!(log.file("mag.csv").map(|f| f.rows()), Some(40));
}

/// A flight's definitions followed by `extra` messages.
fn with(extra: impl Fn(&mut Writer)) -> Vec<u8> {
    let mut w = Writer::new();
    w.format("sensor_combined:uint64_t timestamp;float[3] gyro_rad;float[3] accelerometer_m_s2;");
    extra(&mut w);
    w.bytes()
}

#[test]
fn malformed_files_are_errors_naming_what_is_wrong() {
    let imu = |w: &mut Writer| {
        w.subscribe(0, 0, "sensor_combined");
        w.data(0, &Payload::default().u64(1).f32s(&GYRO).f32s(&ACCEL));
    };
    let cases: Vec<(&str, Vec<u8>, &str)> = vec![
        ("empty file", vec![], "file header: 0 bytes"),
        (
            "not ULog",
            b"PK\x03\x04 this is a zip file".to_vec(),
            "not a ULog file",
        ),
        (
            "short subscription",
            with(|w| {
                w.message(b'A', &[0]);
            }),
            "subscription (add logged) message `A`: payload of 1 bytes, at least 3 expected",
        ),
        (
            "parameter key past its payload",
            with(|w| {
                w.message(b'P', &[200, b'x', b' ']);
            }),
            "parameter message `P`: key length 200 runs past the 3-byte payload",
        ),
        (
            "nested arrays expanding to 9e8 fields",
            with(|w| {
                w.format("a:b[30000] x;")
                    .format("b:c[30000] y;")
                    .format("c:uint8_t z;");
            }),
            "more than 262144 fields",
        ),
        (
            "a type defined in terms of itself",
            with(|w| {
                w.format("a:a[2] x;");
            }),
            "nested more than 16 deep",
        ),
        (
            "subscription id far beyond any log",
            with(|w| {
                w.subscribe(0, 60_000, "sensor_combined");
            }),
            "field `msg_id`: 60000, at most 4095",
        ),
        (
            "data of the wrong size",
            with(|w| {
                w.subscribe(0, 0, "sensor_combined");
                w.data(0, &Payload::default().u64(1));
            }),
            "data message `D`: data message had wrong size 10",
        ),
        (
            "data of an unsubscribed id",
            with(|w| {
                imu(w);
                w.data(7, &Payload::default().u64(1));
            }),
            "unregistered msg_id: 7",
        ),
        ("definitions only", with(|_| {}), "no data messages"),
        (
            "no IMU topic",
            {
                let mut w = Writer::new();
                w.format("vehicle_attitude:uint64_t timestamp;float[4] q;");
                w.subscribe(0, 0, "vehicle_attitude");
                w.data(0, &Payload::default().u64(1).f32s(&[1.0, 0.0, 0.0, 0.0]));
                w.bytes()
            },
            "no IMU data",
        ),
        (
            "unknown sensor_combined layout",
            {
                let mut w = Writer::new();
                w.format(
                    "sensor_combined:uint64_t timestamp;float[3] gyro;float[3] accelerometer_m_s2;",
                );
                imu(&mut w);
                w.bytes()
            },
            "topic `sensor_combined`: field `gyro_rad[0]`: missing (unknown topic layout)",
        ),
    ];
    for (name, bytes, expected) in cases {
        match read_unguarded("case.ulg", &bytes) {
            Ok(_) => panic!("{name}: imported"),
            Err(e) => {
                let text = e.to_string();
                assert!(text.starts_with("case.ulg: "), "{name}: {text}");
                assert!(
                    text.contains(expected),
                    "{name}: `{text}` lacks `{expected}`"
                );
                assert!(!matches!(e, ImportError::Io { .. }), "{name}");
            }
        }
    }
}

/// The committed PX4 log (see `models/tests/data/ulog/README.md`).
#[test]
fn the_committed_px4_log_imports() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../models/tests/data/ulog/sample_px4_events.ulg");
    let bytes = std::fs::read(&path).expect("fixture");
    let log = import(&bytes);
    for name in [
        "imu.csv",
        "mag.csv",
        "baro.csv",
        "gnss.csv",
        "reference.csv",
    ] {
        assert!(
            log.file(name).is_some_and(|f| f.rows() > 10),
            "{name}: {:#?}",
            log.warnings
        );
    }
    let imu = log.file("imu.csv").expect("imu");
    let span = imu.row(imu.rows() - 1)[0] - imu.row(0)[0];
    let rate = (imu.rows() - 1) as f64 / span;
    assert!(
        (200.0..300.0).contains(&rate),
        "IMU rate {rate} Hz (sensor_combined is 250 Hz)"
    );
    // Specific force at rest before take-off: about -g on the z axis.
    close(imu.row(0)[6], -9.8, 0.5, "az at rest");
    let meta = nav_runtime::log::Meta::parse(&log.meta).expect("meta.toml");
    let fix = log.file("gnss.csv").expect("gnss").row(0);
    close(
        fix[1],
        meta.initial.lat,
        1e-5,
        "first fix vs PX4's initial latitude",
    );
    has_warning(&log, "imu.csv: sensor_combined multi_id 0");
    has_warning(&log, "gnss.csv: vehicle_gps_position multi_id 0");
}

fn fixture() -> Vec<u8> {
    flight(Layout::New, 1).bytes()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    /// Any prefix of a valid file imports or is refused; never a panic.
    #[test]
    fn truncations_never_panic(cut in 0usize..30_000) {
        let bytes = fixture();
        let cut = cut.min(bytes.len());
        if let Err(e) = read_unguarded("cut.ulg", &bytes[..cut]) {
            prop_assert!(e.to_string().starts_with("cut.ulg: "));
        }
    }

    /// Flipping bits anywhere imports or is refused; never a panic.
    #[test]
    fn bit_flips_never_panic(flips in proptest::collection::vec((0usize..30_000, 0u8..8), 1..8)) {
        let mut bytes = fixture();
        for (at, bit) in flips {
            let n = bytes.len();
            bytes[at % n] ^= 1 << bit;
        }
        if let Err(e) = read_unguarded("flip.ulg", &bytes) {
            prop_assert!(e.to_string().starts_with("flip.ulg: "));
        }
    }
}

/// The written directory is read strictly by the project's log reader:
/// every file in its format (the fixed `gnss.csv` and `reference.csv`
/// schemas), the aiding noise in `meta.toml`.
#[test]
fn the_log_reader_reads_the_written_directory() {
    let log = import(&flight(Layout::New, 1).bytes());
    let dir = std::env::temp_dir().join(format!("ulog-logdir-{}", std::process::id()));
    log.write(&dir).expect("written");
    let read = nav_runtime::log::LogDir::read(&dir, nav_runtime::log::Strictness::Strict);
    let _ = std::fs::remove_dir_all(&dir);
    let read = read.expect("read by LogDir");
    assert_eq!(read.imu.len(), TICKS as usize);
    assert!(read.unknown_files.is_empty(), "{:?}", read.unknown_files);
    assert_eq!(read.mag.as_ref().map(Vec::len), Some(40));
    assert_eq!(read.baro.as_ref().map(Vec::len), Some(40));
    let gnss = read.gnss.as_ref().expect("gnss.csv");
    assert_eq!(gnss.len(), 9);
    close(gnss[0].lat, LAT_DEG.to_radians(), 1e-9, "lat");
    let reference = read.reference.as_ref().expect("reference.csv");
    assert_eq!(reference.len(), 39);
    assert!(reference.iter().all(|r| r.attitude().is_some()));
    let s = &read.meta.sensors;
    assert!(
        s.mag.is_some() && s.baro.is_some() && s.gnss.is_some(),
        "{s:?}"
    );
}

/// A flight for the cases of [`import_cases`]: 2 s at 100 Hz, level, at yaw
/// `yaw_deg`, with the topics the spec asks for.
#[derive(Clone)]
struct Spec {
    /// `vehicle_imu` instead of `sensor_combined`: (row spacing in 10-ms
    /// ticks, `delta_angle_dt`, `delta_velocity_dt` in us).
    increments: Option<(u64, u16, u16)>,
    /// Per magnetometer instance, the ticks `[from, to)` it has samples in
    /// (every 5th).
    mags: Vec<(u64, u64)>,
    /// PX4's attitude (`vehicle_attitude`).
    attitude: bool,
    /// PX4's position (`vehicle_global_position`).
    position: bool,
    /// `EKF2_MAG_DECL`, deg.
    declination: Option<f32>,
}

const SPEC: Spec = Spec {
    increments: None,
    mags: Vec::new(),
    attitude: true,
    position: true,
    declination: None,
};

/// Earth field, gauss (north, east, down): no declination.
const FIELD: [f64; 2] = [0.2, 0.4];
const LEVEL: [f32; 3] = [0.0, 0.0, -9.81];

fn build(spec: &Spec) -> Writer {
    let mut w = Writer::new();
    w.format("sensor_combined:uint64_t timestamp;float[3] gyro_rad;float[3] accelerometer_m_s2;");
    w.format("vehicle_imu:uint64_t timestamp;uint64_t timestamp_sample;float[3] delta_angle;float[3] delta_velocity;uint16_t delta_angle_dt;uint16_t delta_velocity_dt;");
    w.format("vehicle_magnetometer:uint64_t timestamp;uint64_t timestamp_sample;float[3] magnetometer_ga;");
    w.format("vehicle_attitude:uint64_t timestamp;uint64_t timestamp_sample;float[4] q;");
    w.format("vehicle_global_position:uint64_t timestamp;uint64_t timestamp_sample;double lat;double lon;float alt;float alt_ellipsoid;");
    if let Some(d) = spec.declination {
        w.parameter("EKF2_MAG_DECL", d);
    }
    let imu_topic = if spec.increments.is_some() {
        "vehicle_imu"
    } else {
        "sensor_combined"
    };
    w.subscribe(0, 0, imu_topic);
    w.subscribe(0, 2, "vehicle_attitude");
    w.subscribe(0, 3, "vehicle_global_position");
    for (i, _) in spec.mags.iter().enumerate() {
        let i = u8::try_from(i).expect("few instances");
        w.subscribe(i, 10 + u16::from(i), "vehicle_magnetometer");
    }
    let yaw = YAW_DEG.to_radians();
    // The field seen by a level body at yaw `yaw`.
    let mag = [
        (FIELD[0] * yaw.cos()) as f32,
        (-FIELD[0] * yaw.sin()) as f32,
        FIELD[1] as f32,
    ];
    let half = (yaw / 2.0) as f32;
    for k in 0..TICKS {
        let t = T0_US + k * 10_000;
        match spec.increments {
            None => {
                w.data(0, &Payload::default().u64(t).f32s(&GYRO).f32s(&LEVEL));
            }
            Some((every, da_dt, dv_dt)) => {
                if k % every == 0 {
                    let da = GYRO.map(|g| g * f32::from(da_dt) * 1e-6);
                    let dv = LEVEL.map(|a| a * f32::from(dv_dt) * 1e-6);
                    w.data(
                        0,
                        &Payload::default()
                            .u64(t)
                            .u64(t)
                            .f32s(&da)
                            .f32s(&dv)
                            .u16(da_dt)
                            .u16(dv_dt),
                    );
                }
            }
        }
        if k % 5 == 0 {
            for (i, &(from, to)) in spec.mags.iter().enumerate() {
                if (from..to).contains(&k) {
                    let id = 10 + u16::try_from(i).expect("few");
                    w.data(id, &Payload::default().u64(t).u64(t).f32s(&mag));
                }
            }
            if spec.attitude {
                w.data(
                    2,
                    &Payload::default()
                        .u64(t)
                        .u64(t)
                        .f32s(&[half.cos(), 0.0, 0.0, half.sin()]),
                );
            }
        }
        if k % 10 == 0 && spec.position {
            w.data(
                3,
                &Payload::default()
                    .u64(t)
                    .u64(t)
                    .f64s(&[LAT_DEG, LON_DEG])
                    .f32s(&[MSL as f32, HEIGHT as f32]),
            );
        }
    }
    w
}

/// `bytes` with its data continued after a cut: the message that starts at
/// the middle frame is cut after 5 bytes, and everything from that frame on
/// is appended after the cut, its offset in the flag bits message (the ULog
/// format's `appended_offsets[0]`, incompatible flag 0 bit 0).
fn with_appended_data(bytes: &[u8]) -> Vec<u8> {
    let frames = super::guard::frames(bytes).expect("valid").frames;
    let at = frames[frames.len() / 2].offset;
    let mut out = bytes[..at].to_vec();
    out.extend_from_slice(&bytes[at..at + 5]);
    let appended = out.len() as u64;
    out.extend_from_slice(&bytes[at..]);
    // Flag bits: header 16 bytes, frame head 3, compat 8, incompat 8, offsets.
    out[16 + 3 + 8] |= 1;
    out[16 + 3 + 16..16 + 3 + 24].copy_from_slice(&appended.to_le_bytes());
    out
}

fn meta_of(log: &ImportedLog) -> nav_runtime::log::Meta {
    match nav_runtime::log::Meta::parse(&log.meta) {
        Ok(m) => m,
        Err(e) => panic!("{e}\n{}", log.meta),
    }
}

/// Issue cases of the importer, one row each: the file, and what the
/// import must give (a check on the log) or the error it must name.
#[test]
fn import_cases() {
    type Check = fn(&ImportedLog);
    let spec = |f: fn(&mut Spec)| {
        let mut s = SPEC.clone();
        s.mags = vec![(0, TICKS)];
        f(&mut s);
        build(&s).bytes()
    };
    let cases: Vec<(&str, Vec<u8>, Result<Check, &str>)> = vec![
        (
            "vehicle_imu logged every 500 ms, increments over 4 ms: rates over 4 ms",
            spec(|s| s.increments = Some((50, 4_000, 4_000))),
            Ok(|log| {
                let imu = log.file("imu.csv").expect("imu.csv");
                assert_eq!(imu.header, ["t", "gx", "gy", "gz", "ax", "ay", "az"]);
                // The first sample, dated 0.998 s, lies before PX4's first estimate.
                let r = imu.row(0);
                for i in 0..3 {
                    close(r[1 + i], f64::from(GYRO[i]), 1e-5, "rate");
                    close(r[4 + i], f64::from(LEVEL[i]), 1e-4, "specific force");
                }
                // At the middle of the 4-ms period ending at the sample time.
                close(r[0], 1.5 - 0.002, 1e-9, "t");
                has_warning(log, "the increments cover 4.000 ms");
            }),
        ),
        (
            "vehicle_imu with delta_velocity_dt unlike delta_angle_dt: each by its own",
            spec(|s| s.increments = Some((1, 10_000, 5_000))),
            Ok(|log| {
                let imu = log.file("imu.csv").expect("imu.csv");
                assert_eq!(imu.header[1], "gx");
                close(imu.row(3)[6], f64::from(LEVEL[2]), 1e-4, "az");
                close(imu.row(3)[3], f64::from(GYRO[2]), 1e-5, "gz");
            }),
        ),
        (
            "vehicle_imu increments over the row spacing stay increments",
            spec(|s| s.increments = Some((1, 10_000, 10_000))),
            Ok(|log| {
                let imu = log.file("imu.csv").expect("imu.csv");
                assert_eq!(imu.header[1], "dtheta_x");
                close(imu.row(2)[3], f64::from(GYRO[2]) * 0.01, 1e-9, "dtheta_z");
                assert!(!log.warnings.iter().any(|w| w.contains("as rates")));
            }),
        ),
        (
            "magnetometer 0 stops halfway, 1 goes on: continued with 1",
            spec(|s| s.mags = vec![(0, TICKS / 2), (0, TICKS)]),
            Ok(|log| {
                assert_eq!(log.file("mag.csv").map(CsvFile::rows), Some(40));
                has_warning(
                    log,
                    "vehicle_magnetometer: multi_id 0 stops at t = 1.950 s; continued with multi_id 1 from t = 2.000 s (20 rows)",
                );
            }),
        ),
        (
            "the only magnetometer stops halfway: said",
            spec(|s| s.mags = vec![(0, TICKS / 2)]),
            Ok(|log| {
                assert_eq!(log.file("mag.csv").map(CsvFile::rows), Some(20));
                has_warning(
                    log,
                    "vehicle_magnetometer: stops at t = 1.950 s, 1.0 s before the log's last message",
                );
            }),
        ),
        (
            "data appended after a cut message",
            with_appended_data(&spec(|_| {})),
            Ok(|log| {
                assert_eq!(log.file("imu.csv").map(CsvFile::rows), Some(TICKS as usize));
                assert_eq!(log.file("mag.csv").map(CsvFile::rows), Some(40));
                has_warning(log, "cut by data appended at byte");
            }),
        ),
        (
            "an appended offset inside the definitions",
            {
                let mut b = spec(|_| {});
                b[16 + 3 + 16..16 + 3 + 24].copy_from_slice(&20u64.to_le_bytes());
                b
            },
            Err("flag bits message `B`: field `appended_offsets[0]`: 20, before byte 59"),
        ),
        (
            "no position, PX4's attitude: attitude-only meta.toml",
            spec(|s| s.position = false),
            Ok(|log| {
                let meta = meta_of(log);
                assert!(!meta.initial.has_position(), "{}", log.meta);
                close(meta.initial.yaw.expect("yaw"), YAW_DEG.to_radians(), 1e-6, "yaw");
                assert!(log.file("imu.csv").is_some() && log.file("mag.csv").is_some());
                has_warning(log, "meta.toml: attitude only");
                has_warning(
                    log,
                    "model gnss-ins: cannot replay this log: no GNSS fix (gnss.csv) and no initial position",
                );
                assert_eq!(log.models[0], ("ahrs", None));
                let json = log.summary();
                assert_eq!(json["models"]["gnss-ins"]["servable"], false, "{json}");
            }),
        ),
        (
            "no position, no attitude: leveled from accelerometer and magnetometer",
            spec(|s| {
                s.position = false;
                s.attitude = false;
            }),
            Ok(|log| {
                let meta = meta_of(log);
                let i = meta.initial;
                close(i.roll.expect("roll"), 0.0, 1e-6, "roll");
                close(i.pitch.expect("pitch"), 0.0, 1e-6, "pitch");
                close(i.yaw.expect("yaw"), YAW_DEG.to_radians(), 1e-6, "yaw");
                close(i.t.expect("t"), 1.0, 1e-9, "t");
                has_warning(log, "declination 0 (EKF2_MAG_DECL not in the log)");
                has_warning(log, "attitude leveled from the mean specific force");
            }),
        ),
        (
            "leveled, with the declination of EKF2_MAG_DECL",
            spec(|s| {
                s.position = false;
                s.attitude = false;
                s.declination = Some(5.0);
            }),
            Ok(|log| {
                let yaw = meta_of(log).initial.yaw.expect("yaw");
                close(yaw, (YAW_DEG + 5.0).to_radians(), 1e-6, "yaw + declination");
            }),
        ),
        (
            "no position, no attitude, no magnetometer: which model needs what",
            spec(|s| {
                s.position = false;
                s.attitude = false;
                s.mags = Vec::new();
            }),
            Err("no initial attitude: no vehicle_attitude, and no magnetometer and accelerometer samples in the first second to level from (model ahrs needs one"),
        ),
    ];
    for (name, bytes, expected) in cases {
        match (read_unguarded("case.ulg", &bytes), expected) {
            (Ok(log), Ok(check)) => check(&log),
            (Err(e), Err(part)) => {
                let text = e.to_string();
                assert!(text.starts_with("case.ulg: "), "{name}: {text}");
                assert!(text.contains(part), "{name}: `{text}` lacks `{part}`");
            }
            (Ok(log), Err(part)) => {
                panic!("{name}: imported, `{part}` expected: {:#?}", log.warnings)
            }
            (Err(e), Ok(_)) => panic!("{name}: {e}"),
        }
    }
}

/// Importing into the directory of an earlier import replaces it whole: a
/// `mag.csv` of the earlier log does not survive when the new one has none.
#[test]
fn an_earlier_import_is_replaced_whole() {
    let dir = std::env::temp_dir().join(format!("ulog-reimport-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let mut with_mag = SPEC.clone();
    with_mag.mags = vec![(0, TICKS)];
    let first = import(&build(&with_mag).bytes());
    first.write(&dir).expect("first import");
    assert!(dir.join("mag.csv").is_file());
    let second = import(&build(&SPEC).bytes());
    assert!(second.file("mag.csv").is_none());
    second.write(&dir).expect("second import");
    let stale = dir.join("mag.csv").exists();
    let read = nav_runtime::log::LogDir::read(&dir, nav_runtime::log::Strictness::Strict);
    let _ = std::fs::remove_dir_all(&dir);
    assert!(!stale, "mag.csv of the earlier import left");
    assert!(read.expect("read").mag.is_none());
}
