//! The set-up of the `ahrs` filter from a log's `meta.toml`: initial
//! attitude and sigmas, sensor noises (PX4's defaults where the log says
//! nothing, with a warning), the local gravity and the magnetic
//! declination.

use nav_runtime::attitude::Euler;
use nav_runtime::earth::normal_gravity;
use nav_runtime::ekf::Ekf;
use nav_runtime::log::{Meta, Warning};
use nav_runtime::nalgebra::{SMatrix, SVector, Vector3};

use super::model::{Ahrs, AhrsInput, AhrsNoise, AhrsParams};
use super::nominal::{AhrsFilter, AhrsNominal};
use crate::harness::RunError;

/// Gyro bias random walk, rad/s^1.5 (PX4 EKF2's default `EKF2_GYR_B_NOISE`).
pub const GYRO_BIAS_WALK: f64 = 1e-3;
/// Magnetometer noise when `meta.toml` has no `[sensors.mag]`, gauss
/// (PX4's default `EKF2_MAG_NOISE`).
pub const MAG_NOISE_DEFAULT: f64 = 0.05;
/// Initial roll and pitch sigma without `[initial_sigma] level`, rad.
pub const LEVEL_SIGMA_DEFAULT: f64 = 0.05;
/// Initial heading sigma without `[initial_sigma] heading`, rad.
pub const HEADING_SIGMA_DEFAULT: f64 = 0.1;
/// Initial gyro bias sigma without `[sensors.imu] gyro_bias_sigma`, rad/s.
pub const GYRO_BIAS_SIGMA_DEFAULT: f64 = 0.01;
/// Gyro noise sigma per sample without `[sensors.imu]`, rad/s.
pub const GYRO_SIGMA_DEFAULT: f64 = 1.5e-2;
/// Accelerometer noise sigma per sample without `[sensors.imu]`, m/s^2.
pub const ACCEL_SIGMA_DEFAULT: f64 = 0.35;
/// Standard gravity, m/s^2: the gravity of a log without a position.
const STANDARD_GRAVITY: f64 = 9.806_65;

/// What the filter is built from.
#[derive(Debug, Clone, PartialEq)]
pub struct AhrsSettings {
    /// Initial roll, pitch, yaw, rad.
    pub attitude: [f64; 3],
    /// Initial roll and pitch sigma, rad.
    pub level_sigma: f64,
    /// Initial heading sigma, rad.
    pub heading_sigma: f64,
    /// Initial gyro bias sigma, rad/s.
    pub gyro_bias_sigma: f64,
    /// Gyro noise per sample, rad/s.
    pub gyro_sigma: f64,
    /// Accelerometer noise per sample, m/s^2.
    pub accel_sigma: f64,
    /// The IMU sampling interval the gyro noise is discretized with, s.
    pub imu_period: f64,
    /// Local gravity, m/s^2.
    pub gravity: f64,
    /// Magnetometer noise per axis, gauss.
    pub mag_sigma: f64,
    /// Magnetic declination, rad (east positive).
    pub declination: f64,
}

impl AhrsSettings {
    /// The settings of a log with `meta.toml` `meta` and IMU interval
    /// `imu_period` (s), declination zero; the defaults taken are said in
    /// `warnings`.
    ///
    /// # Errors
    /// No initial attitude in `meta.toml`.
    pub fn of(meta: &Meta, imu_period: f64, warnings: &mut Vec<Warning>) -> Result<Self, RunError> {
        let init = &meta.initial;
        let attitude = init.attitude()?;
        let imu = meta.sensors.imu;
        let mag_sigma = match meta.sensors.mag {
            Some(n) => n.noise_sigma,
            None => {
                warnings.push(nav_replay::missing_section(
                    "mag",
                    format!(
                        "meta.toml has no [sensors.mag]: magnetometer noise {MAG_NOISE_DEFAULT} gauss (PX4's default)"
                    ),
                ));
                MAG_NOISE_DEFAULT
            }
        };
        let sigma = meta.initial_sigma.unwrap_or_default();
        // An attitude-only meta.toml (a log without any position): the
        // standard gravity, 0.03 % from the normal gravity at 45 deg.
        let gravity = if init.has_position() {
            normal_gravity(init.lat, -init.depth)
        } else {
            warnings.push(nav_replay::meta_note(
                "initial.lat",
                "meta.toml has no initial position: gravity 9.80665 m/s^2 (standard gravity)",
            ));
            STANDARD_GRAVITY
        };
        Ok(AhrsSettings {
            attitude,
            level_sigma: sigma.level.unwrap_or(LEVEL_SIGMA_DEFAULT),
            heading_sigma: sigma.heading.unwrap_or(HEADING_SIGMA_DEFAULT),
            gyro_bias_sigma: imu
                .map(|n| n.gyro_bias_sigma)
                .filter(|s| *s > 0.0)
                .unwrap_or(GYRO_BIAS_SIGMA_DEFAULT),
            gyro_sigma: imu.map_or(GYRO_SIGMA_DEFAULT, |n| n.gyro_noise_sigma),
            accel_sigma: imu.map_or(ACCEL_SIGMA_DEFAULT, |n| n.accel_noise_sigma),
            imu_period,
            gravity,
            mag_sigma,
            declination: 0.0,
        })
    }

    /// The initial filter: zero error, the initial sigmas, the nominal at
    /// the initial attitude with no bias correction.
    ///
    /// # Errors
    /// A filter set-up error (a sigma or noise not finite).
    pub fn filter(&self) -> Result<AhrsFilter, RunError> {
        let (level, heading, bias) = (self.level_sigma, self.heading_sigma, self.gyro_bias_sigma);
        let p0 = SMatrix::<f64, 6, 6>::from_diagonal(&SVector::from([
            level * level,
            level * level,
            heading * heading,
            bias * bias,
            bias * bias,
            bias * bias,
        ]));
        let noise = AhrsNoise {
            gyro_noise: Vector3::repeat(self.gyro_sigma * self.gyro_sigma * self.imu_period),
            gyro_bias_noise: Vector3::repeat(GYRO_BIAS_WALK * GYRO_BIAS_WALK),
        };
        let params = AhrsParams {
            gravity: self.gravity,
        };
        let ekf = Ekf::<Ahrs, 6>::new(SVector::zeros(), p0, params, noise)
            .map_err(|e| RunError::Invalid(format!("ahrs: {e}")))?;
        let [roll, pitch, yaw] = self.attitude;
        let nominal = AhrsNominal {
            c_bn: Euler::new(roll, pitch, yaw).c_bn(),
            gyro_bias: Vector3::zeros(),
        };
        // Gravity and the magnetometer often share an epoch: the second is
        // linearized about the attitude the first corrected.
        Ok(AhrsFilter::new(ekf, nominal).with_sensor_input(|n| AhrsInput { c_bn: n.c_bn }))
    }
}
