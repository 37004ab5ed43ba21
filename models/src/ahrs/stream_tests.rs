//! The streamed `ahrs` filter: late magnetometer rows, gaps, bad samples.

use nav_runtime::attitude::{rotation_from_rotvec, Euler};
use nav_runtime::error_state::Mechanization;
use nav_runtime::log::MagRow;
use nav_runtime::nalgebra::{Matrix3, Vector3};

use super::*;
use crate::ahrs::nominal::AhrsNominal;
use nav_ins::ImuSample;

const RATE_HZ: f64 = 100.0;
/// Earth field (NED, gauss) of the synthetic rows: no declination.
const FIELD_N: [f64; 3] = [0.21, 0.0, 0.42];
const GYRO_BIAS: [f64; 3] = [0.002, -0.001, 0.003];

fn settings() -> AhrsSettings {
    AhrsSettings {
        attitude: [0.01, -0.02, 0.3],
        level_sigma: 0.05,
        heading_sigma: 0.1,
        gyro_bias_sigma: 0.01,
        gyro_sigma: 0.01,
        accel_sigma: 0.3,
        imu_period: 1.0 / RATE_HZ,
        gravity: 9.80665,
        mag_sigma: 0.05,
        declination: 0.0,
    }
}

/// The true attitude at `t`: a slow yaw swing.
fn yaw(t: f64) -> f64 {
    0.3 + 0.4 * (0.5 * t).sin()
}

fn c_bn(t: f64) -> Matrix3<f64> {
    Euler::new(0.01, -0.02, yaw(t)).c_bn()
}

/// The IMU sample ending at `t` (the yaw rate of the middle of the
/// interval, plus the gyro bias; gravity as specific force).
fn imu(t: f64) -> ImuSample {
    let rate = 0.4 * 0.5 * (0.5 * (t - 0.5 / RATE_HZ)).cos();
    let body_rate = c_bn(t).transpose() * Vector3::new(0.0, 0.0, rate);
    let f = c_bn(t).transpose() * Vector3::new(0.0, 0.0, -9.80665);
    ImuSample {
        gyro: body_rate + Vector3::from(GYRO_BIAS),
        accel: f,
    }
}

fn mag(t: f64) -> MagRow {
    let m = c_bn(t).transpose() * Vector3::from(FIELD_N);
    MagRow {
        t,
        mx: m.x,
        my: m.y,
        mz: m.z,
    }
}

fn imu_times(from: f64, to: f64) -> impl Iterator<Item = f64> {
    let first = (from * RATE_HZ).round() as i64;
    let last = (to * RATE_HZ).round() as i64;
    (first..=last).map(|k| k as f64 / RATE_HZ)
}

/// Magnetometer rows at 10 Hz, between IMU samples.
fn mag_times(from: f64, to: f64) -> Vec<f64> {
    let mut t = from + 0.0037;
    let mut out = Vec::new();
    while t < to {
        out.push(t);
        t += 0.1;
    }
    out
}

/// Runs the stream over IMU samples from 0 to `end` s, each magnetometer
/// row pushed once the IMU is `delay` s past it (0: in time order).
fn run(end: f64, delay: f64) -> AhrsStream {
    let mut stream = AhrsStream::new(settings()).expect("stream");
    let mags = mag_times(0.0, end);
    let mut next = 0;
    for t in imu_times(0.0, end) {
        while next < mags.len() && mags[next] + delay < t {
            stream.push_mag(mag(mags[next])).expect("mag");
            next += 1;
        }
        stream.push_imu(t, imu(t)).expect("imu");
    }
    // The rows the IMU passed by less than `delay` at its end.
    for &t in &mags[next..] {
        stream.push_mag(mag(t)).expect("mag");
    }
    stream
}

fn assert_same(a: &AhrsStream, b: &AhrsStream, tolerance: f64) {
    let (fa, fb) = (a.filter(), b.filter());
    let dc = (fa.nominal().c_bn - fb.nominal().c_bn).abs().max();
    let db = (fa.nominal().gyro_bias - fb.nominal().gyro_bias)
        .abs()
        .max();
    let dp = (fa.covariance() - fb.covariance()).abs().max();
    assert!(
        dc < tolerance && db < tolerance && dp < tolerance,
        "{dc} {db} {dp}"
    );
}

#[test]
fn the_mechanization_turns_the_attitude_by_the_corrected_gyro() {
    let c0 = Euler::new(0.1, 0.2, 0.3).c_bn();
    let mut n = AhrsNominal {
        c_bn: c0,
        gyro_bias: Vector3::new(0.01, 0.0, 0.0),
    };
    let sample = ImuSample {
        gyro: Vector3::new(0.01, 0.0, 0.5),
        accel: Vector3::zeros(),
    };
    let input = n.mechanize(0.02, &sample);
    assert_eq!(input.c_bn, c0, "the input is the attitude at the start");
    let expected = c0 * rotation_from_rotvec(&Vector3::new(0.0, 0.0, 0.01));
    assert!((n.c_bn - expected).abs().max() < 1e-15);
}

#[test]
fn a_late_magnetometer_row_gives_the_estimate_of_one_on_time() {
    let on_time = run(20.0, 0.0);
    // Half the latency the scheduler keeps: every row is applied late.
    let late = run(20.0, MAG_LATENCY_S / 2.0);
    assert_same(&on_time, &late, 1e-9);
    let (a, b) = (on_time.counts(), late.counts());
    assert_eq!(a, b);
    assert!(a.mag.accepted > 150, "{:?}", a.mag);
    assert!(a.gravity.accepted > 150, "{:?}", a.gravity);
    // And the filter found the gyro bias and the attitude.
    let n = on_time.filter().nominal();
    let bias_error = (n.gyro_bias - Vector3::from(GYRO_BIAS)).abs().max();
    assert!(bias_error < 5e-4, "{bias_error}");
    let yaw_error = crate::ulog::replay::wrap(n.euler()[2] - yaw(20.0));
    assert!(yaw_error.abs() < 0.01, "{yaw_error}");
}

#[test]
fn a_row_older_than_the_latency_is_refused_and_counted() {
    let mut stream = run(2.0, 0.0);
    let before = stream.counts().mag;
    stream
        .push_mag(mag(2.0 - 2.0 * MAG_LATENCY_S))
        .expect("pushed");
    let after = stream.counts().mag;
    assert_eq!(after.rows, before.rows + 1);
    assert_eq!(after.rejected, before.rejected + 1);
}

#[test]
fn a_gap_is_not_propagated_and_its_rows_are_applied_before_it() {
    let mut stream = AhrsStream::new(settings()).expect("stream");
    for t in imu_times(0.0, 1.0) {
        stream.push_imu(t, imu(t)).expect("imu");
    }
    let before = stream.filter().nominal().clone();
    // One second without IMU: a gap, nothing propagated.
    assert_eq!(stream.push_imu(2.0, imu(2.0)).expect("gap"), ImuStep::Gap);
    assert_eq!(stream.filter().nominal(), &before);
    assert_eq!(stream.counts().imu_gaps, 1);
    // Rows inside the next gap are applied to the estimate before it.
    for t in [2.2, 2.9] {
        stream.push_mag(mag(t)).expect("mag");
    }
    assert_eq!(stream.push_imu(3.0, imu(3.0)).expect("gap"), ImuStep::Gap);
    let c = stream.counts();
    assert_eq!(
        (c.imu_gaps, c.mag.rows, c.mag.accepted + c.mag.gated),
        (2, 2, 2)
    );
    assert_ne!(stream.filter().nominal(), &before);
    // A time that does not increase is a gap too.
    assert_eq!(stream.push_imu(3.0, imu(3.0)).expect("gap"), ImuStep::Gap);
    assert_eq!(
        stream.push_imu(3.01, imu(3.01)).expect("step"),
        ImuStep::Propagated {
            window_closed: false
        }
    );
    assert_eq!(stream.counts().imu_gaps, 3);
}

#[test]
fn rows_before_the_first_sample_are_skipped_and_after_the_last_applied() {
    let mut stream = AhrsStream::new(settings()).expect("stream");
    stream.push_mag(mag(0.0)).expect("mag");
    for t in imu_times(0.01, 1.0) {
        stream.push_imu(t, imu(t)).expect("imu");
    }
    stream.push_mag(mag(1.05)).expect("mag");
    stream.push_mag(mag(3.0)).expect("mag");
    let c = stream.finish().expect("finish");
    assert_eq!((c.mag.rows, c.mag.skipped), (3, 1));
    assert_eq!(c.mag.accepted + c.mag.gated, 2, "{:?}", c.mag);
}

#[test]
fn bad_samples_are_refused_without_a_panic() {
    let mut stream = AhrsStream::new(settings()).expect("stream");
    for t in imu_times(0.0, 0.5) {
        stream.push_imu(t, imu(t)).expect("imu");
    }
    let mut bad = imu(0.51);
    bad.gyro.x = f64::NAN;
    let e = stream
        .push_imu(0.51, bad)
        .expect_err("a NaN sample")
        .to_string();
    assert!(e.contains("imu.csv t = 0.51"), "{e}");
    // A non-finite field, and no horizontal field: no heading, skipped.
    let mut row = mag(0.505);
    row.my = f64::NAN;
    stream.push_mag(row).expect("counted, not an error");
    stream
        .push_mag(MagRow {
            t: 0.507,
            mx: 0.0,
            my: 0.0,
            mz: 0.0,
        })
        .expect("skipped");
    stream
        .push_imu(0.52, imu(0.52))
        .expect("the stream goes on");
    let c = stream.finish().expect("finish");
    assert_eq!((c.mag.rows, c.mag.skipped), (2, 2), "{:?}", c.mag);
    assert!(stream.filter().nominal().c_bn.iter().all(|v| v.is_finite()));
}
