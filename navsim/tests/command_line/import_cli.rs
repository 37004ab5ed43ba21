//! `navsim import`: the command line of the importers (ULog and MCAP).

/// `navsim import ulog FILE --out DIR` writes the directory; a missing file
/// is a one-line error naming it.
#[test]
fn the_command_line_writes_the_log_directory() {
    let fixture = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../models/tests/data/ulog/sample_px4_events.ulg");
    let out = std::env::temp_dir().join(format!("ulog-cli-{}", std::process::id()));
    let code = navsim::cli::main_with_args([
        "navsim".to_string(),
        "import".to_string(),
        "ulog".to_string(),
        fixture.display().to_string(),
        "--out".to_string(),
        out.display().to_string(),
        "--json".to_string(),
    ]);
    assert_eq!(
        format!("{code:?}"),
        format!("{:?}", std::process::ExitCode::SUCCESS)
    );
    for name in [
        "imu.csv",
        "mag.csv",
        "baro.csv",
        "gnss.csv",
        "reference.csv",
        "meta.toml",
        "noise.toml",
    ] {
        assert!(out.join(name).is_file(), "{name} not written");
    }
    let meta = std::fs::read_to_string(out.join("meta.toml")).expect("meta.toml");
    assert!(nav_runtime::log::Meta::parse(&meta).is_ok(), "{meta}");
    let _ = std::fs::remove_dir_all(&out);
    let code = navsim::cli::main_with_args([
        "navsim",
        "import",
        "ulog",
        "/nonexistent/x.ulg",
        "--out",
        "/tmp/never-written",
    ]);
    assert_eq!(
        format!("{code:?}"),
        format!("{:?}", std::process::ExitCode::FAILURE)
    );
    assert!(!std::path::Path::new("/tmp/never-written").exists());
}

/// `navsim import mcap BAG --out DIR --json` writes the log directory of a
/// bag another tool wrote; `--mapping` with `ulog` is refused.
#[test]
fn the_command_line_imports_a_ros_bag() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let bag = root.join("nav-import/tests/fixtures/mcap/small_survey.mcap");
    let out = std::env::temp_dir().join(format!("mcap-cli-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let code = navsim::cli::main_with_args([
        "navsim",
        "import",
        "mcap",
        bag.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--json",
    ]);
    assert_eq!(
        format!("{code:?}"),
        format!("{:?}", std::process::ExitCode::SUCCESS)
    );
    for name in ["imu.csv", "mag.csv", "meta.toml"] {
        assert!(out.join(name).is_file(), "{name} not written");
    }
    let _ = std::fs::remove_dir_all(&out);
    let code = navsim::cli::main_with_args([
        "navsim",
        "import",
        "ulog",
        bag.to_str().unwrap(),
        "--mapping",
        "m.toml",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(
        format!("{code:?}"),
        format!("{:?}", std::process::ExitCode::FAILURE)
    );
    assert!(!out.exists());
}

use crate::common;

use common::{navsim, replay_json, stderr, stdout, TempDir};
use nalgebra::{Matrix3, Rotation3, UnitQuaternion};
use nav_import::mcap::writer;
use nav_runtime::log::{LogDir, Meta, SensorNoise, Sensors, Strictness};

/// Scenario simulated and model replayed in the bag / CSV round trip.
const SURVEY: &str = "lawnmower-dvl";
const SURVEY_MODEL: &str = "sdins25";
/// Bag epoch, ns: 2023-11-14.
const EPOCH_NS: i64 = 1_700_000_000_000_000_000;
const RHO: f64 = 1025.0;
const G0: f64 = 9.806_65;
const P0: f64 = 101_325.0;

/// `t` (s of the log) as a bag stamp, ns.
fn stamp(t: f64) -> i64 {
    EPOCH_NS + (t * 1e9).round() as i64
}

/// The rotation ENU / FLU of the attitude `rpy` (NED / FRD, rad), as a
/// quaternion x, y, z, w: `C_enu_flu = A C_ned_frd B`.
fn enu_flu(rpy: [f64; 3]) -> [f64; 4] {
    let c = Rotation3::from_euler_angles(rpy[0], rpy[1], rpy[2]).into_inner();
    let a = Matrix3::new(0.0, 1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, -1.0);
    let b = Matrix3::from_diagonal(&nalgebra::Vector3::new(1.0, -1.0, -1.0));
    let q = UnitQuaternion::from_matrix(&(a * c * b));
    [q.i, q.j, q.k, q.w]
}

/// The survey of `log` written as a bag: IMU, magnetometer, pressure, DVL
/// (FLU), truth as odometry on the local tangent plane of `origin` (lat,
/// lon rad, height m), every stamp `EPOCH_NS + t`.
fn survey_bag(log: &LogDir, origin: [f64; 3]) -> Vec<u8> {
    let s = &log.meta.sensors;
    let var = |n: Option<SensorNoise>| n.map_or(0.0, |n| n.noise_sigma * n.noise_sigma);
    let imu_noise = s.imu.expect("imu noise");
    let q0 = enu_flu([
        log.meta.initial.roll.expect("roll"),
        log.meta.initial.pitch.expect("pitch"),
        log.meta.initial.yaw.expect("yaw"),
    ]);
    let mut topics: Vec<writer::Topic> = Vec::new();
    let mut push = |topic: &str, ty: &str, msgs: Vec<(i64, Vec<u8>)>| {
        topics.push((
            topic.into(),
            ty.into(),
            msgs.into_iter().map(|(ns, m)| (ns as u64, m)).collect(),
        ));
    };
    push(
        "/imu/data",
        "sensor_msgs/msg/Imu",
        log.imu
            .iter()
            .enumerate()
            .map(|(i, r)| {
                let ns = stamp(r.t);
                let q = (i == 0).then_some(q0);
                let m = writer::imu(
                    ns,
                    "imu_link",
                    q,
                    [r.gx, -r.gy, -r.gz],
                    [r.ax, -r.ay, -r.az],
                    imu_noise.gyro_noise_sigma.powi(2),
                    imu_noise.accel_noise_sigma.powi(2),
                );
                (ns, m)
            })
            .collect(),
    );
    if let Some(rows) = &log.mag {
        let v = var(s.mag) * 1e-8;
        push(
            "/imu/mag",
            "sensor_msgs/msg/MagneticField",
            rows.iter()
                .map(|r| {
                    let tesla = [r.mx * 1e-4, -r.my * 1e-4, -r.mz * 1e-4];
                    (stamp(r.t), writer::mag(stamp(r.t), "imu_link", tesla, v))
                })
                .collect(),
        );
    }
    if let Some(rows) = &log.depth {
        let v = var(s.depth) * (RHO * G0).powi(2);
        push(
            "/pressure",
            "sensor_msgs/msg/FluidPressure",
            rows.iter()
                .map(|r| {
                    let pa = P0 + r.depth * RHO * G0;
                    (stamp(r.t), writer::pressure(stamp(r.t), "ps", pa, v))
                })
                .collect(),
        );
    }
    if let Some(rows) = &log.dvl {
        push(
            "/dvl/twist",
            "geometry_msgs/msg/TwistWithCovarianceStamped",
            rows.iter()
                .filter_map(|r| {
                    let v = [r.vx?, -r.vy?, -r.vz?];
                    Some((
                        stamp(r.t),
                        writer::twist(stamp(r.t), "dvl_link", v, var(s.dvl)),
                    ))
                })
                .collect(),
        );
    }
    if let Some(rows) = &log.truth {
        let [lat0, lon0, h0] = origin;
        let rn = nav_runtime::earth::meridian_radius(lat0) + h0;
        let re = (nav_runtime::earth::transverse_radius(lat0) + h0) * lat0.cos();
        push(
            "/odometry",
            "nav_msgs/msg/Odometry",
            rows.iter()
                .map(|r| {
                    let (n, e, d) = ((r.lat - lat0) * rn, (r.lon - lon0) * re, r.depth + h0);
                    let c = Rotation3::from_euler_angles(r.roll, r.pitch, r.yaw).into_inner();
                    let v = c.transpose() * nalgebra::Vector3::new(r.vn, r.ve, r.vd);
                    let m = writer::odometry(
                        stamp(r.t),
                        "map",
                        [e, n, -d],
                        enu_flu([r.roll, r.pitch, r.yaw]),
                        [v[0], -v[1], -v[2]],
                    );
                    (stamp(r.t), m)
                })
                .collect(),
        );
    }
    writer::bag(&topics)
}

/// A simulated survey written as CSV (what a bag carries of it: IMU,
/// magnetometer, depth, DVL, truth; `[initial]` position and attitude;
/// noise sigmas) and as a bag gives, once imported, the same replay: the
/// JSON keys identical, every number within 1e-6 (m, m/s, rad: the
/// conversions are exact but for rounding, ~1e-9 m at the survey's
/// latitude through radians, degrees and the tangent plane).
#[test]
fn a_survey_as_a_bag_and_as_csv_replays_the_same() {
    let dir = TempDir::new("bag-csv");
    let sim = dir.path().join("sim");
    common::simulate(SURVEY, 5, &sim);
    let full = LogDir::read(&sim, Strictness::Strict).expect("simulated log");
    // The CSV directory: what a bag carries, times from the first row.
    let t0 = full.imu[0].t;
    let mut log = full.clone();
    let shift = |t: &mut f64| *t -= t0;
    log.imu.iter_mut().for_each(|r| shift(&mut r.t));
    if let Some(rows) = &mut log.mag {
        rows.iter_mut().for_each(|r| shift(&mut r.t));
    }
    if let Some(rows) = &mut log.depth {
        rows.iter_mut().for_each(|r| shift(&mut r.t));
    }
    if let Some(rows) = &mut log.dvl {
        rows.retain(|r| r.vx.is_some() && r.vy.is_some() && r.vz.is_some());
        rows.iter_mut().for_each(|r| shift(&mut r.t));
    }
    if let Some(rows) = &mut log.truth {
        rows.iter_mut().for_each(|r| shift(&mut r.t));
    }
    for rows in [
        &log.depth.as_ref().map(|r| r[0].t),
        &log.mag.as_ref().map(|r| r[0].t),
    ] {
        assert!(
            !matches!(rows, Some(t) if *t < 0.0),
            "a sensor before the first IMU row"
        );
    }
    (log.heading, log.usbl, log.speed, log.rpm, log.altitude) = (None, None, None, None, None);
    (log.baro, log.gnss, log.reference) = (None, None, None);
    let i = full.meta.initial;
    let noise = |n: Option<SensorNoise>| {
        n.map(|n| SensorNoise {
            bias_sigma: 0.0,
            ..n
        })
    };
    let mut imu = full.meta.sensors.imu.expect("[sensors.imu]");
    (imu.gyro_bias_sigma, imu.accel_bias_sigma) = (0.0, 0.0);
    log.meta = Meta {
        sensors: Sensors {
            imu: Some(imu),
            dvl: noise(full.meta.sensors.dvl).filter(|_| log.dvl.is_some()),
            depth: noise(full.meta.sensors.depth).filter(|_| log.depth.is_some()),
            mag: noise(full.meta.sensors.mag).filter(|_| log.mag.is_some()),
            ..Sensors::default()
        },
        ..Meta::at(i.lat, i.lon, i.depth)
    };
    log.meta.initial.t = Some(0.0);
    (
        log.meta.initial.roll,
        log.meta.initial.pitch,
        log.meta.initial.yaw,
    ) = (i.roll, i.pitch, i.yaw);
    let csv = dir.path().join("csv");
    log.write(&csv).expect("CSV directory");
    // The same survey as a bag, imported.
    let bag = dir.path().join("survey.mcap");
    std::fs::write(&bag, survey_bag(&log, [i.lat, i.lon, -i.depth])).expect("bag");
    let mapping = dir.path().join("map.toml");
    std::fs::write(
        &mapping,
        format!(
            "origin = {{ lat = {:?}, lon = {:?}, height = {:?} }}\n",
            i.lat.to_degrees(),
            i.lon.to_degrees(),
            -i.depth
        ),
    )
    .expect("mapping");
    let imported = dir.path().join("imported");
    nav_import::mcap::import(&bag, Some(&mapping), &imported).expect("import");
    // IMU and DVL rows and their times are the same numbers (the stamps'
    // nanoseconds give back the seconds); depth to a few units in the last
    // place of its pascals.
    let back = LogDir::read(&imported, Strictness::Strict).expect("imported log");
    assert_eq!(back.imu, log.imu, "imu.csv");
    assert_eq!(back.dvl, log.dvl, "dvl.csv");
    let (da, db) = (
        log.depth.as_ref().expect("depth"),
        back.depth.as_ref().expect("depth"),
    );
    assert_eq!(da.len(), db.len());
    for (x, y) in da.iter().zip(db) {
        assert!(
            x.t == y.t && (x.depth - y.depth).abs() < 1e-13,
            "depth {x:?} {y:?}"
        );
    }
    let replay = |d: &std::path::Path| replay_json(d, SURVEY_MODEL, &[]);
    let (mut a, mut b) = (replay(&csv), replay(&imported));
    for v in [&mut a, &mut b] {
        v.as_object_mut().expect("object").remove("runtime_s");
    }
    let mut compared = 0;
    same("", &a, &b, &mut compared);
    assert!(compared >= 10, "{a}");
}

/// Earth radius for a latitude or longitude difference in metres.
const EARTH_RADIUS_M: f64 = 6.4e6;

/// `a` and `b` have the same keys, strings and counts; their numbers agree
/// within 1e-6 (latitude and longitude converted to metres; relative above
/// 1): the inputs differ by at most two units in the last place (the
/// initial position through degrees, the attitude through a quaternion,
/// depth through pascals), which 500 s of filtering carry to ~4e-8 m.
fn same(path: &str, a: &serde_json::Value, b: &serde_json::Value, compared: &mut usize) {
    use serde_json::Value;
    match (a, b) {
        (Value::Object(x), Value::Object(y)) => {
            let keys = |o: &serde_json::Map<String, Value>| o.keys().cloned().collect::<Vec<_>>();
            assert_eq!(keys(x), keys(y), "{path}: keys");
            for (k, v) in x {
                same(&format!("{path}.{k}"), v, &y[k], compared);
            }
        }
        (Value::Array(x), Value::Array(y)) => {
            assert_eq!(x.len(), y.len(), "{path}: length");
            for (i, (u, v)) in x.iter().zip(y).enumerate() {
                same(&format!("{path}[{i}]"), u, v, compared);
            }
        }
        (Value::Number(x), Value::Number(y)) => {
            let (x, y) = (
                x.as_f64().unwrap_or(f64::NAN),
                y.as_f64().unwrap_or(f64::NAN),
            );
            let scale = if path.ends_with(".lat") || path.ends_with(".lon") {
                EARTH_RADIUS_M
            } else {
                1.0
            };
            let d = (x - y).abs() * scale;
            assert!(d <= 1e-6 * x.abs().max(1.0), "{path}: CSV {x}, bag {y}");
            *compared += 1;
        }
        _ => assert_eq!(a, b, "{path}"),
    }
}

/// An attitude-only log (the committed bag imported without its fix): each
/// built-in replay model that needs a position refuses it with an error
/// naming the model and the missing `[initial]` position; `ahrs` replays it
/// and the preflight (`navsim check`) finds nothing (standard gravity).
#[test]
fn an_attitude_only_log_is_refused_by_the_models_that_need_a_position() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let bag = root.join("nav-import/tests/fixtures/mcap/small_survey.mcap");
    let dir = TempDir::new("attitude-only");
    let mapping = dir.path().join("map.toml");
    std::fs::write(&mapping, "[topics.\"/fix\"]\nsensor = \"ignore\"\n").expect("mapping");
    let log = dir.path().join("log");
    nav_import::mcap::import(&bag, Some(&mapping), &log).expect("import");
    let meta = LogDir::read(&log, Strictness::Strict).expect("log").meta;
    assert!(!meta.initial.has_position(), "attitude only");
    let log = log.to_str().unwrap();
    let needs = "needs an initial position: meta.toml [initial] has none (attitude-only log";
    // gnss-ins is refused first for the missing gnss.csv (the import had
    // no fix): also a statement of what the log lacks for that model.
    let gnss = "gnss.csv: missing: model gnss-ins needs GNSS fixes";
    let cases: [(&str, bool, Option<&str>); 8] = [
        ("demo-depth-kf", false, None),
        ("leveling6", false, None),
        ("sdins25", false, None),
        ("sdins25-composed", false, None),
        ("sdins20", false, None),
        ("pressure-auv", false, None),
        ("gnss-ins", false, Some(gnss)),
        ("ahrs", true, None),
    ];
    for (model, replays, cause) in cases {
        let o = navsim(&["replay", log, "--model", model, "--json"]);
        if replays {
            assert!(o.status.success(), "{model}: {}", stderr(&o));
            let v: serde_json::Value = serde_json::from_str(stdout(&o).trim()).expect("JSON");
            assert_eq!(v["model"], model);
        } else {
            assert!(
                !o.status.success(),
                "{model}: replayed an attitude-only log"
            );
            let e = stderr(&o);
            let expected = cause.map_or(
                format!("`initial.lat`: model {model} {needs}"),
                String::from,
            );
            assert!(e.contains(&expected), "{model}: {e}");
        }
    }
    let o = navsim(&["check", log, "--json"]);
    assert!(o.status.success(), "{}", stdout(&o));
    let v: serde_json::Value = serde_json::from_str(stdout(&o).trim()).expect("JSON");
    assert_eq!(v["errors"], serde_json::json!([]), "{v}");
    assert_eq!(v["warnings"], serde_json::json!([]), "{v}");
    // Depth and USBL rows: no comparison with the absent initial depth or
    // position (no finding speaks of NaN).
    let dir_path = std::path::Path::new(log);
    std::fs::write(dir_path.join("depth.csv"), "t,depth\n0.1,5\n0.5,5.1\n").expect("depth");
    std::fs::write(
        dir_path.join("usbl.csv"),
        "t,lat,lon,depth\n0.2,0.8,0.15,5\n",
    )
    .expect("usbl");
    let o = navsim(&["check", log, "--json"]);
    let text = stdout(&o);
    assert!(text.contains("\"imu_rows\":50"), "{text}");
    assert!(!text.contains("NaN"), "{text}");
}
