//! The nominal solution of the `ahrs` filter: the attitude integrated from
//! the gyro and the running gyro bias correction, advanced by the IMU
//! samples themselves ([`Mechanization`]) so that the multi-rate scheduler
//! can re-propagate it after a late measurement.

use nav_runtime::attitude::{correct_c_bn, euler_from_c_bn, rotation_from_rotvec};
use nav_runtime::error_state::{ErrorStateFilter, Mechanization, NominalState};
use nav_runtime::nalgebra::{Matrix3, SVector, Vector3};

use super::model::{Ahrs, AhrsInput};
use nav_ins::ImuSample;

/// The error-state filter of the `ahrs` model.
pub type AhrsFilter = ErrorStateFilter<Ahrs, AhrsNominal, 6>;

/// The nominal attitude and the running gyro bias correction.
#[derive(Clone, Debug, PartialEq)]
pub struct AhrsNominal {
    /// Body to NED.
    pub c_bn: Matrix3<f64>,
    /// Gyro bias correction, subtracted from the samples, rad/s.
    pub gyro_bias: Vector3<f64>,
}

impl NominalState<6> for AhrsNominal {
    fn inject(&mut self, e: &SVector<f64, 6>) {
        self.c_bn = correct_c_bn(&self.c_bn, &Vector3::new(e[0], e[1], e[2]));
        self.gyro_bias += Vector3::new(e[3], e[4], e[5]);
    }
}

/// The attitude is integrated from the bias-corrected gyro alone (Earth
/// rate left out, as in eq. A1 of `docs/ulog.md`); the accelerometer half of
/// the sample is read by the gravity measurement, not here.
impl Mechanization<Ahrs, 6> for AhrsNominal {
    type Imu = ImuSample;
    fn mechanize(&mut self, dt: f64, imu: &ImuSample) -> AhrsInput {
        // The error model's input is the attitude at the start of the interval.
        let input = AhrsInput { c_bn: self.c_bn };
        let w = imu.gyro - self.gyro_bias;
        self.c_bn *= rotation_from_rotvec(&(w * dt));
        input
    }
}

impl AhrsNominal {
    /// Roll, pitch, yaw, rad.
    pub fn euler(&self) -> [f64; 3] {
        let e = euler_from_c_bn(&self.c_bn);
        [e.roll, e.pitch, e.yaw]
    }
}
