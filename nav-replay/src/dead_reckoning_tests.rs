//! Dead reckoning on synthetic logs whose every reading is exact: a straight
//! run and a circle (with and without a declared DVL lever arm), against
//! the truth they were made from; and the logs it refuses.

use nav_runtime::earth::{earth_rate_n, meridian_radius, transport_rate_n, transverse_radius};
use nav_runtime::log::{DvlRow, ImuRow, LogDir, Meta, Mounting, TruthRow};
use nav_runtime::nalgebra::{Rotation3, Vector3};

use super::DeadReckoning;
use crate::{ReplayModel, ReplayOptions, RunError};

const LAT: f64 = 0.6;
const IMU_PERIOD: f64 = 0.01;

/// A vehicle at `speed` (m/s, forward) turning at `rate` (rad/s, about
/// down) for `seconds`, from heading 0.3 rad at (LAT, 0.2, 10 m): the IMU
/// at 100 Hz (gyro with the Earth's and the transport rate, so that the
/// attitude stays level), a DVL at 1 Hz at `arm` from the IMU (its reading
/// carries `omega x arm`), truth every second. The truth's position is the
/// IMU's, integrated finely from the exact velocity.
fn log(speed: f64, rate: f64, seconds: f64, arm: [f64; 3]) -> LogDir {
    let mut meta = Meta::at(LAT, 0.2, 10.0);
    let yaw0 = 0.3_f64;
    meta.initial.t = Some(0.0);
    meta.initial.roll = Some(0.0);
    meta.initial.pitch = Some(0.0);
    meta.initial.yaw = Some(yaw0);
    meta.initial.vn = speed * yaw0.cos();
    meta.initial.ve = speed * yaw0.sin();
    let mut log = LogDir::new(meta);
    let (mut lat, mut lon, h) = (LAT, 0.2, -10.0);
    let mut dvl = Vec::new();
    let mut truth = Vec::new();
    let steps = (seconds / IMU_PERIOD).round() as usize;
    for k in 0..=steps {
        let t = k as f64 * IMU_PERIOD;
        let yaw = yaw0 + rate * t;
        let v = Vector3::new(speed * yaw.cos(), speed * yaw.sin(), 0.0);
        // The yaw of the middle of the interval the sample is held over.
        let mid = yaw0 + rate * (t + IMU_PERIOD / 2.0);
        let c_bn = Rotation3::from_axis_angle(&Vector3::z_axis(), mid);
        let w_in = earth_rate_n(lat) + transport_rate_n(lat, h, &v);
        let gyro = Vector3::new(0.0, 0.0, rate) + c_bn.inverse() * w_in;
        log.imu.push(ImuRow {
            t,
            gx: gyro.x,
            gy: gyro.y,
            gz: gyro.z,
            ax: 0.0,
            ay: 0.0,
            az: -9.8,
        });
        if k % 100 == 0 {
            let body = Vector3::new(speed, 0.0, 0.0)
                + Vector3::new(0.0, 0.0, rate).cross(&Vector3::from(arm));
            dvl.push(DvlRow {
                t,
                vx: Some(body.x),
                vy: Some(body.y),
                vz: Some(body.z),
            });
            truth.push(TruthRow {
                t,
                lat,
                lon,
                depth: -h,
                vn: v.x,
                ve: v.y,
                vd: 0.0,
                roll: 0.0,
                pitch: 0.0,
                yaw,
            });
        }
        // The exact position, integrated in ten substeps.
        for j in 0..10 {
            let ts = t + (j as f64 + 0.5) * IMU_PERIOD / 10.0;
            let y = yaw0 + rate * ts;
            lat += speed * y.cos() * IMU_PERIOD / 10.0 / (meridian_radius(lat) + h);
            lon += speed * y.sin() * IMU_PERIOD / 10.0 / ((transverse_radius(lat) + h) * lat.cos());
        }
    }
    log.dvl = Some(dvl);
    log.truth = Some(truth);
    log
}

fn with_arm(mut log: LogDir, arm: [f64; 3]) -> LogDir {
    log.meta.sensors.mountings[0] = Some(Mounting {
        lever_arm: arm,
        misalignment: [0.0; 3],
    });
    log
}

fn rms(log: &LogDir) -> f64 {
    let options = ReplayOptions::default();
    let out = DeadReckoning.replay(log, &options).expect("dead reckoning");
    out.metrics["horizontal_error_rms_m"]
        .as_f64()
        .expect("scored")
}

/// (case, log, largest RMS horizontal error, smallest): exact readings
/// reproduce the truth to the error of holding the DVL velocity linear
/// between readings (on the circle the chord's `(omega T)^2 / 8` of the
/// speed); an arm the run is not told of is that many times worse.
#[test]
fn exact_readings_give_the_truth_back() {
    let turn = 0.05;
    let cases: [(&str, LogDir, f64, f64); 4] = [
        ("straight, 300 s", log(2.0, 0.0, 300.0, [0.0; 3]), 1e-3, 0.0),
        ("circle, 120 s", log(2.0, turn, 120.0, [0.0; 3]), 0.03, 0.0),
        (
            "circle, DVL 3 m ahead, arm declared",
            with_arm(log(2.0, turn, 120.0, [3.0, 0.0, 0.0]), [3.0, 0.0, 0.0]),
            0.03,
            0.0,
        ),
        (
            "circle, DVL 3 m ahead, arm not declared",
            log(2.0, turn, 120.0, [3.0, 0.0, 0.0]),
            10.0,
            1.0,
        ),
    ];
    for (name, log, most, least) in cases {
        let e = rms(&log);
        assert!(
            e <= most && e >= least,
            "{name}: RMS {e} m, expected {least}..{most}"
        );
    }
}

/// Metrics of a filter that a dead reckoning has not: no NEES keys. With
/// the series kept, the track at each DVL reading, the filters' columns
/// without the sigmas.
#[test]
fn no_nees_is_claimed_and_the_track_is_kept() {
    let options = ReplayOptions {
        keep_series: true,
        ..ReplayOptions::default()
    };
    let out = DeadReckoning
        .replay(&log(1.5, 0.02, 30.0, [0.0; 3]), &options)
        .unwrap();
    for key in ["nees_mean", "nees_position_mean"] {
        assert!(!out.metrics.contains_key(key), "{key}");
    }
    assert!(out.metrics["scored_seconds"].as_f64().unwrap() >= 29.0);
    let track = out
        .tables
        .iter()
        .find(|t| t.name == "estimates")
        .expect("estimates table");
    let (t, yaw, depth) = (
        track.column("t"),
        track.column("yaw_deg"),
        track.column("depth"),
    );
    assert_eq!(t.len(), 31, "one row per DVL reading");
    assert!(track.column("sig_n").is_empty(), "no sigma columns");
    // Rotating by the turn and by the Earth's rate one after the other,
    // not together, errs by |w_in x w| dt^2 / 2 per IMU step at most:
    // 7.3e-5 rad/s times 0.02 rad/s over 100 steps a second. Twice that
    // bound (measured at t = 30 s: 3.5e-8 rad of the 2.2e-7 it allows).
    let bound = |t: f64| 2.0 * (t / IMU_PERIOD) * 0.5 * 7.3e-5 * 0.02 * IMU_PERIOD.powi(2);
    for k in [0, 10, 30] {
        let expected = 0.3 + 0.02 * t[k];
        assert!(
            (yaw[k].to_radians() - expected).abs() <= bound(t[k]) + 1e-12,
            "t = {}: yaw {} deg",
            t[k],
            yaw[k]
        );
        // The tilt from the same error, times the speed, would move the
        // depth by 1e-5 m over 30 s at most; it moves by 1e-8 m.
        assert!((depth[k] - 10.0).abs() < 1e-6, "depth {}", depth[k]);
    }
}

/// (case, edit, text the error must contain).
#[test]
fn logs_it_cannot_dead_reckon_are_refused() {
    type Edit = fn(&mut LogDir);
    let cases: [(&str, Edit, &str); 4] = [
        ("no DVL file", |l| l.dvl = None, "dvl.csv: missing"),
        (
            "no bottom lock",
            |l| {
                for r in l.dvl.iter_mut().flatten() {
                    (r.vx, r.vy, r.vz) = (None, None, None);
                }
            },
            "no reading with bottom lock",
        ),
        ("no yaw", |l| l.meta.initial.yaw = None, "initial.yaw"),
        ("no IMU rows", |l| l.imu.clear(), "imu.csv: no rows"),
    ];
    for (name, edit, text) in cases {
        let mut l = log(1.5, 0.0, 20.0, [0.0; 3]);
        edit(&mut l);
        let e: RunError = DeadReckoning
            .replay(&l, &ReplayOptions::default())
            .expect_err(name);
        assert!(e.to_string().contains(text), "{name}: {e}");
    }
}

/// Streamed from its files, the log gives the in-memory replay's figures
/// (the same solution at every truth row), and with an output directory
/// the track and the errors are written as the run goes: one row per DVL
/// reading and per truth row.
#[test]
fn the_streamed_replay_equals_the_one_in_memory_and_writes_its_tables() {
    use nav_runtime::log::{LogFiles, Strictness};
    let mut log = with_arm(log(1.5, 0.03, 60.0, [1.0, 0.2, 0.0]), [1.0, 0.2, 0.0]);
    // `meta.toml` has the arm in the DVL's section, which needs its noise.
    log.meta.sensors.dvl = Some(nav_runtime::log::SensorNoise {
        bias_sigma: 0.0,
        noise_sigma: 0.02,
    });
    let dir = crate::temp_dir::TempDir::new("dead-reckoning-stream");
    log.write(&dir.0).expect("write the log");
    let files = LogFiles::open(&dir.0, Strictness::Strict).expect("open the log");
    let options = ReplayOptions::default();
    let memory = DeadReckoning.replay(&log, &options).expect("in memory");
    let streamed = DeadReckoning
        .replay_files(&files, &options, None)
        .expect("streamed");
    for key in [
        "horizontal_error_rms_m",
        "horizontal_error_final_m",
        "scored_seconds",
    ] {
        let (a, b) = (memory.metrics[key].as_f64(), streamed.metrics[key].as_f64());
        // The files hold the values to 17 significant digits.
        let (a, b) = (a.expect(key), b.expect(key));
        assert!(
            (a - b).abs() <= 1e-9 * a.abs().max(1.0),
            "{key}: {a} vs {b}"
        );
    }
    let out = crate::temp_dir::TempDir::new("dead-reckoning-out");
    DeadReckoning
        .replay_files(&files, &options, Some(&out.0))
        .expect("written");
    let lines = |name: &str| {
        std::fs::read_to_string(out.0.join(name))
            .expect(name)
            .lines()
            .count()
    };
    assert_eq!(
        lines("estimates.csv"),
        1 + 61,
        "header and one row per reading"
    );
    assert_eq!(
        lines("errors.csv"),
        1 + 61,
        "header and one row per truth row"
    );
}
