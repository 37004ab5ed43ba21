//! Tests of the navigator (navigator.rs) with the estimators of this crate.
use models::sdins25::Sdins25;
use models::vehicles::sdins::{Sdins20, Sdins20DvlCal};
use nav_ins::prelude::*;
use nav_runtime::earth::{meridian_radius, normal_gravity, transverse_radius};

fn initial() -> InitialState {
    InitialState {
        t: 0.0,
        position: Geodetic::new(0.7, 2.2, -50.0),
        velocity: Vector3::zeros(),
        attitude: Euler {
            roll: 0.0,
            pitch: 0.0,
            yaw: 0.3,
        },
        sigma: InitialSigma::default(),
    }
}

fn imu() -> ImuSettings {
    ImuSettings {
        period_s: 0.01,
        gyro_bias_sigma: 1e-6,
        gyro_noise_sigma: 1e-6,
        accel_bias_sigma: 1e-3,
        accel_noise_sigma: 1e-3,
    }
}

fn at_rest() -> ImuSample {
    ImuSample {
        gyro: Vector3::zeros(),
        accel: Vector3::new(0.0, 0.0, -normal_gravity(0.7, -50.0)),
    }
}

#[test]
fn readings_are_applied_and_reported_per_sensor() {
    let mut b = Navigator::<Sdins25, 25>::builder(initial(), imu());
    let depth = b.sensor::<DepthReading>(SensorSettings::new(0.05)).unwrap();
    let heading = b
        .sensor::<HeadingReading>(SensorSettings::new(0.01))
        .unwrap();
    let mut nav = b.build(at_rest()).unwrap();
    // A reading more than one IMU period before the start is skipped;
    // one within it is applied at the start.
    nav.push(depth, -0.02, DepthReading(50.0));
    nav.push(heading, -0.005, HeadingReading(0.3));
    let ticket = nav.request_estimate(5.0);
    for k in 1..=1000 {
        let t = k as f64 * 0.01;
        if k % 50 == 0 {
            // Varying readings (identical ones would be frozen values).
            let wiggle = (k as f64).sin();
            nav.push(depth, t, DepthReading(50.0 + 0.02 * wiggle));
            nav.push(heading, t, HeadingReading(0.3 + 0.005 * wiggle));
        }
        nav.push_imu(t, at_rest()).unwrap();
    }
    let d = nav.report(depth);
    assert_eq!(d.health.accepted, 20);
    assert_eq!(d.health.skipped, 1);
    assert_eq!(nav.report(heading).health.accepted, 21);
    assert_eq!(nav.report(heading).health.skipped, 0);
    assert!(d.last_nis.is_some_and(|x| x.is_finite() && x >= 0.0));
    let e = nav.estimate();
    assert!((e.nav.depth() - 50.0).abs() < 0.2, "{}", e.nav.depth());
    let mut got = Vec::new();
    nav.flush_estimates(|t, e| got.push((t, e)));
    assert_eq!(got.len(), 1);
    assert_eq!(got[0].0, ticket);
    assert!(got[0].1.is_some_and(|e| (e.t - 5.0).abs() < 1e-9));
}

#[test]
fn a_sensor_the_vehicle_lacks_is_a_setup_error() {
    let mut b = Navigator::<Sdins20, 20>::builder(initial(), imu());
    let e = b.sensor::<UsblFix>(SensorSettings::new(1.0)).unwrap_err();
    assert!(e.to_string().contains("sdins20 has no usbl sensor"), "{e}");
}

#[test]
fn an_estimate_out_of_bounds_stops_the_navigator() {
    let cases: [(ImuSample, &str); 3] = [
        (
            ImuSample {
                accel: Vector3::new(1e6, 0.0, -9.8),
                ..at_rest()
            },
            "speed",
        ),
        (
            ImuSample {
                gyro: Vector3::new(1e300, 0.0, 0.0),
                ..at_rest()
            },
            "not finite",
        ),
        (
            ImuSample {
                accel: Vector3::new(0.0, 0.0, 1e5),
                ..at_rest()
            },
            "exceeds",
        ),
    ];
    for (sample, expected) in cases {
        let mut nav = Navigator::<Sdins25, 25>::builder(initial(), imu())
            .build(at_rest())
            .unwrap();
        nav.push_imu(0.01, at_rest()).unwrap();
        let e = nav.push_imu(0.02, sample).unwrap_err();
        assert!(
            matches!(e, NavigatorError::OutOfBounds { .. }) && e.to_string().contains(expected),
            "{e}"
        );
    }
}

/// The barometer port's lever arm carries the INS height to the port:
/// a port 1.5 m below the IMU of a level vehicle reads 1.5 m low. With
/// the lever arm declared the height estimate stays at the truth; with
/// none it is pulled to the port's height.
#[test]
fn baro_lever_arm_carries_the_height_to_the_port() {
    use models::gnss_ins::GnssIns;
    // (port lever arm down, m; expected height error, m)
    for (arm_down, expected) in [(1.5, 0.0), (0.0, -1.5)] {
        let mut start = initial();
        start.sigma.position = 5.0;
        let p = start.position;
        let mut b = Navigator::<GnssIns, 16>::builder(start, imu());
        let mut settings = SensorSettings::new(0.5)
            .bias(0.01)
            .lever_arm(Vector3::new(0.0, 0.0, arm_down));
        settings.initial_bias = 3.0;
        let baro = b.sensor::<BaroReading>(settings).unwrap();
        let mut nav = b.build(at_rest()).unwrap();
        for k in 1..=500 {
            let t = k as f64 * 0.01;
            if k % 20 == 0 {
                let w = 1e-3 * (k as f64).sin();
                nav.push(baro, t, BaroReading(p.h - 1.5 + 3.0 + w));
            }
            nav.push_imu(t, at_rest()).unwrap();
        }
        assert_eq!(nav.report(baro).health.accepted, 25);
        let dh = nav.estimate().nav.h - p.h;
        assert!(
            (dh - expected).abs() < 0.15,
            "port {arm_down} m down: height error {dh} m"
        );
    }
}

/// The GNSS, barometer and magnetometer slots of `gnss-ins`: fixes of an
/// antenna 2 m forward of the IMU (heading north) at 2 m north of the
/// true IMU position, a barometer reading 3 m high with that bias known,
/// and the field of a level vehicle heading north keep the estimate where
/// it is; a fix with a NaN latitude is refused and counted, not applied.
#[test]
fn gnss_baro_and_mag_slots_apply_their_readings() {
    use models::gnss_ins::GnssIns;
    let mut start = initial();
    start.attitude.yaw = 0.0;
    start.sigma.position = 5.0;
    let p = start.position;
    let mut b = Navigator::<GnssIns, 16>::builder(start, imu());
    let arm = Vector3::new(2.0, 0.0, 0.0);
    let gnss = b
        .sensor::<GnssFix>(SensorSettings::new(0.1).lever_arm(arm))
        .unwrap();
    let mut baro_settings = SensorSettings::new(0.5).bias(0.1);
    baro_settings.initial_bias = 3.0;
    let baro = b.sensor::<BaroReading>(baro_settings).unwrap();
    let mag = b.sensor::<MagReading>(SensorSettings::new(0.01)).unwrap();
    let mut nav = b.build(at_rest()).unwrap();
    let north = 2.0 / (meridian_radius(p.lat) + p.h);
    for k in 1..=500 {
        let t = k as f64 * 0.01;
        if k % 20 == 0 {
            // Varying readings (identical ones would be frozen values).
            let w = 1e-3 * (k as f64).sin();
            let fix = GnssFix {
                lat: p.lat + north,
                lon: p.lon,
                height: p.h + w,
                eph: None,
                epv: None,
            };
            nav.push(gnss, t, fix);
            nav.push(baro, t, BaroReading(p.h + 3.0 + w));
            nav.push(mag, t, MagReading(Vector3::new(0.2, w, 0.4)));
        }
        nav.push_imu(t, at_rest()).unwrap();
    }
    let bad = GnssFix {
        lat: f64::NAN,
        ..GnssFix {
            lat: p.lat,
            lon: p.lon,
            height: p.h,
            eph: None,
            epv: None,
        }
    };
    nav.push(gnss, 5.005, bad);
    nav.push_imu(5.01, at_rest()).unwrap();
    for (name, r) in [
        ("gnss", nav.report(gnss)),
        ("baro", nav.report(baro)),
        ("mag", nav.report(mag)),
    ] {
        assert_eq!(r.health.accepted, 25, "{name}: {r:?}");
    }
    assert_eq!(nav.report(gnss).health.rejected, 1);
    let e = nav.estimate();
    let dn = (e.nav.lat - p.lat) * (meridian_radius(p.lat) + p.h);
    assert!(dn.abs() < 0.05, "north error {dn} m (the lever arm is 2 m)");
    assert!((e.nav.h - p.h).abs() < 0.05, "height {}", e.nav.h - p.h);
    assert!((e.baro_bias.0 - 3.0).abs() < 0.05, "{:?}", e.baro_bias);
    assert!(e.nav.euler().yaw.abs() < 3e-3, "{}", e.nav.euler().yaw);
}

/// A vehicle at rest heading 0.3 rad with its USBL transponder 2 m
/// forward and 1 m to starboard: the fixes are of the transponder. With
/// the lever arm the position estimate stays at the IMU; without it the
/// fixes pull it towards the transponder, 2.2 m away.
#[test]
fn a_usbl_transponder_at_a_lever_arm_is_fixed_where_it_is() {
    let arm = Vector3::new(2.0, 1.0, 0.0);
    let start = initial();
    let p = start.position;
    let c_bn = start.attitude.c_bn();
    let offset = c_bn * arm;
    let error = |lever_arm: Vector3<f64>| {
        let mut b = Navigator::<Sdins25, 25>::builder(start, imu()).options(NavigatorOptions {
            gate_probability: None,
            ..NavigatorOptions::default()
        });
        let usbl = b
            .sensor::<UsblFix>(SensorSettings::new(0.3).lever_arm(lever_arm))
            .unwrap();
        let mut nav = b.build(at_rest()).unwrap();
        let rm = meridian_radius(p.lat) + p.h;
        let rn = transverse_radius(p.lat) + p.h;
        for k in 1..=1000 {
            let t = k as f64 * 0.01;
            if k % 50 == 0 {
                let w = 1e-3 * (k as f64).sin();
                let fix = UsblFix {
                    lat: p.lat + (offset.x + w) / rm,
                    lon: p.lon + offset.y / (rn * p.lat.cos()),
                };
                nav.push(usbl, t, fix);
            }
            nav.push_imu(t, at_rest()).unwrap();
        }
        assert_eq!(nav.report(usbl).health.accepted, 20);
        let e = nav.estimate().nav;
        let dn = (e.lat - p.lat) * rm;
        let de = (e.lon - p.lon) * rn * p.lat.cos();
        dn.hypot(de)
    };
    let with_arm = error(arm);
    assert!(with_arm < 0.2, "{with_arm} m");
    let without = error(Vector3::zeros());
    assert!(without > 1.5, "{without} m");
}

/// A vehicle turning in place at 0.2 rad/s with its DVL 1.5 m forward:
/// the DVL reads `omega x r` = 0.3 m/s to starboard. With the lever arm
/// the velocity estimate stays at rest; without it the reading pulls it
/// towards 0.3 m/s.
#[test]
fn a_dvl_at_a_lever_arm_reads_the_turn_rate_times_the_arm() {
    let omega = 0.2;
    let arm = Vector3::new(1.5, 0.0, 0.0);
    let turning = ImuSample {
        gyro: Vector3::new(0.0, 0.0, omega),
        ..at_rest()
    };
    let speed = |lever_arm: Vector3<f64>| {
        // No gate: the readings without the arm are applied, not refused.
        let mut b = Navigator::<Sdins20, 20>::builder(initial(), imu()).options(NavigatorOptions {
            gate_probability: None,
            ..NavigatorOptions::default()
        });
        let dvl = b
            .sensor::<DvlReading>(SensorSettings::new(0.05).lever_arm(lever_arm))
            .unwrap();
        let mut nav = b.build(turning).unwrap();
        for k in 1..=1000 {
            let t = k as f64 * 0.01;
            if k % 50 == 0 {
                let w = 1e-4 * (k as f64).sin();
                let reading = Vector3::new(w, omega * arm.x, 0.0);
                nav.push(dvl, t, DvlReading(reading));
            }
            nav.push_imu(t, turning).unwrap();
        }
        let r = nav.report(dvl);
        assert_eq!(r.health.accepted, 20, "{r:?}");
        nav.estimate().nav.v_n.norm()
    };
    let with_arm = speed(arm);
    assert!(with_arm < 0.02, "{with_arm} m/s");
    let without = speed(Vector3::zeros());
    assert!(without > 0.1, "{without} m/s");
}

/// The history a lock-out rollback needs (docs/lockout.md, "Rollback") is
/// kept only while a sensor that has given readings has had none
/// accepted: none before the first reading, the rollback's 10 s while the
/// first readings wait, and none once one is accepted.
#[test]
fn the_rollback_history_is_kept_only_until_a_reading_is_accepted() {
    let mut b = Navigator::<Sdins25, 25>::builder(initial(), imu());
    let depth = b.sensor::<DepthReading>(SensorSettings::new(0.05)).unwrap();
    let mut nav = b.build(at_rest()).unwrap();
    let mut longest = 0;
    for k in 1..=1500 {
        let t = k as f64 * 0.01;
        if k == 300 {
            // Before any reading: the history of a navigator without rollback.
            assert!(
                nav.scheduler().history_len() <= 101,
                "{}",
                nav.scheduler().history_len()
            );
        }
        if k >= 300 && k % 50 == 0 {
            // From 3 s, readings 100 m off, then right from 9 s: refused at
            // first (a run of the depth meter), then accepted.
            let offset = if t < 9.0 { 100.0 } else { 0.0 };
            let wiggle = (k as f64).sin();
            nav.push(depth, t, DepthReading(50.0 + offset + 0.02 * wiggle));
        }
        nav.push_imu(t, at_rest()).unwrap();
        longest = longest.max(nav.scheduler().history_len());
    }
    assert!(nav.report(depth).health.accepted > 0);
    // 6 s of refusals kept (more than the 1-s checkpoint spacing allows
    // without it), then dropped after the first acceptance.
    assert!(longest >= 600, "{longest}");
    assert!(
        nav.scheduler().history_len() <= 101,
        "{}",
        nav.scheduler().history_len()
    );
}

/// Eq. R4 of docs/lockout.md: each refused DVL reading that joins a
/// recovery's run adds its innovation, in NED, times the time since the
/// previous reading; a glitch (a miss) adds nothing; the recovery moves the
/// sum into the horizontal position covariance and clears it. At rest
/// facing yaw 0.3 rad, the DVL reads a forward speed growing by 1 m/s per s
/// from 5 s (refused, agreeing; no release, as the innovation grows), with
/// a 30-m/s glitch at 6.5 s. The sum points along the heading: earlier
/// versions rotated a DVL block's NED residual by the attitude again and
/// pointed it 0.3 rad off (the `Dvl` block's, then the `DvlCalibrated`
/// block's).
#[test]
fn a_recovery_adds_the_position_error_its_refused_readings_built() {
    // Both DVL blocks: each residual (INS velocity less the rotated reading) is in NED.
    refused_run_drift::<Sdins20, 20>("sdins20", &[]);
    // Its mounting states held at their given values (sigma 0).
    let mounting = [
        "dvl_scale",
        "dvl_misalignment",
        "dvl_lever_arm",
        "dvl_time_offset",
    ];
    refused_run_drift::<Sdins20DvlCal, 28>("sdins20-dvl-cal", &mounting);
}

fn refused_run_drift<V: InsVehicle<N>, const N: usize>(what: &str, held: &[&str]) {
    let mut b = Navigator::<V, N>::builder(initial(), imu());
    for state in held {
        b.state_sigma(state, 0.0).unwrap();
    }
    let dvl = b.sensor::<DvlReading>(SensorSettings::new(0.01)).unwrap();
    let mut nav = b.build(at_rest()).unwrap();
    let mut at = std::collections::BTreeMap::new();
    let mut variance = std::collections::BTreeMap::new();
    for k in 1..=800 {
        let t = k as f64 * 0.01;
        if k % 50 == 0 {
            let wiggle = 1e-3 * (k as f64).sin();
            let forward = if k == 650 { 30.0 } else { (t - 4.5).max(0.0) };
            nav.push(
                dvl,
                t,
                DvlReading(Vector3::new(forward + wiggle, wiggle, 0.0)),
            );
        }
        nav.push_imu(t, at_rest()).unwrap();
        at.insert(k, nav.filter().nominal().dvl_refused_drift);
        let e = Estimate::of(t, nav.filter());
        variance.insert(k, e.cov[(0, 0)] + e.cov[(1, 1)]);
    }
    let recoveries = nav.recoveries();
    assert_eq!(recoveries.len(), 1, "{what}: {recoveries:?}");
    assert_eq!(
        (recoveries[0].sensor, recoveries[0].t_s),
        ("dvl", 7.0),
        "{what}"
    );
    assert_eq!(
        at[&499],
        Vector3::zeros(),
        "{what}: accepted readings leave nothing"
    );
    // 0.5, 1 and 1.5 m/s over half a second each: 1.5 m along the heading
    // (either way: the sign of a residual is its block's).
    let run = at[&649];
    let heading = (run.y / run.x).atan();
    assert!((run.xy().norm() - 1.5).abs() < 0.02, "{what}: {run:?}");
    assert!((heading - 0.3).abs() < 0.01, "{what}: {heading} rad");
    assert_eq!(at[&651], run, "{what}: the glitch at 6.5 s adds nothing");
    assert_eq!(
        at[&701],
        Vector3::zeros(),
        "{what}: the recovery clears the sum"
    );
    // The reading at 7 s (2.5 m/s over 0.5 s) joins: 2.75 m in all.
    let gained = variance[&701] - variance[&699];
    assert!(
        gained > 2.7 * 2.7,
        "{what}: horizontal variance gained {gained} m^2"
    );
}
