//! A simulated flight for the `ahrs` tests: turning at a constant rate about
//! the vertical with a fixed roll and pitch, a gyro with a constant bias,
//! an accelerometer that sees gravity alone and a magnetometer, each with
//! white noise of a known sigma. The random draws are the caller's, in the
//! order of the functions' arguments and results (gyro, then accelerometer,
//! then magnetometer, each x, y, z).
#![allow(dead_code)]

use models::ahrs::settings::AhrsSettings;
use nav_ins::ImuSample;
use nav_runtime::attitude::Euler;
use nav_runtime::nalgebra::{Matrix3, Vector3};

/// IMU sampling interval, s.
pub const PERIOD: f64 = 0.01;
/// Flight length, s.
pub const DURATION: f64 = 60.0;
/// Gravity, m/s^2.
pub const GRAVITY: f64 = 9.80665;
/// Gyro white noise per sample, rad/s.
pub const GYRO_SIGMA: f64 = 2e-3;
/// Accelerometer white noise per sample, m/s^2.
pub const ACCEL_SIGMA: f64 = 0.05;
/// Magnetometer white noise per axis, gauss.
pub const MAG_SIGMA: f64 = 0.004;
/// Gyro bias sigma per axis, rad/s.
pub const BIAS_SIGMA: f64 = 2e-3;
/// Turn rate about the vertical, rad/s.
pub const TURN_RATE: f64 = 0.1;
/// Roll and pitch held through the flight, rad.
pub const ROLL: f64 = 0.3;
pub const PITCH: f64 = -0.2;
/// Heading at t = 0, rad.
pub const YAW: f64 = 1.0;

/// The true body-to-NED rotation at `t` (s).
pub fn c_bn(t: f64) -> Matrix3<f64> {
    Euler::new(ROLL, PITCH, YAW + TURN_RATE * t).c_bn()
}

/// The IMU sample at `t` with gyro bias `bias`, noise from `n`.
pub fn imu(t: f64, bias: &Vector3<f64>, n: &mut impl FnMut() -> f64) -> ImuSample {
    let c = c_bn(t);
    let rate = c.transpose() * Vector3::new(0.0, 0.0, TURN_RATE);
    let gyro = rate + bias + Vector3::new(n(), n(), n()) * GYRO_SIGMA;
    let accel = c.transpose() * Vector3::new(0.0, 0.0, -GRAVITY)
        + Vector3::new(n(), n(), n()) * ACCEL_SIGMA;
    ImuSample { gyro, accel }
}

/// The magnetometer reading at `t` (body, gauss), noise from `n`.
pub fn mag(t: f64, n: &mut impl FnMut() -> f64) -> Vector3<f64> {
    c_bn(t).transpose() * Vector3::new(0.2, 0.0, 0.45) + Vector3::new(n(), n(), n()) * MAG_SIGMA
}

/// Initial roll and pitch sigma of the filter, rad.
pub const LEVEL_SIGMA: f64 = 0.05;
/// Initial heading sigma of the filter, rad.
pub const HEADING_SIGMA: f64 = 0.2;

/// The `ahrs` settings of the flight, the initial attitude drawn from the
/// filter's prior with `n` (roll, pitch, yaw).
pub fn settings(n: &mut impl FnMut() -> f64) -> AhrsSettings {
    AhrsSettings {
        attitude: [
            ROLL + LEVEL_SIGMA * n(),
            PITCH + LEVEL_SIGMA * n(),
            YAW + HEADING_SIGMA * n(),
        ],
        level_sigma: LEVEL_SIGMA,
        heading_sigma: HEADING_SIGMA,
        gyro_bias_sigma: BIAS_SIGMA,
        gyro_sigma: GYRO_SIGMA,
        accel_sigma: ACCEL_SIGMA,
        imu_period: PERIOD,
        gravity: GRAVITY,
        mag_sigma: MAG_SIGMA,
        declination: 0.0,
    }
}
