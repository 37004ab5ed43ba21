//! The two measurements of the `ahrs` filter as the scheduler applies them.
//! Both residuals are "prediction from the nominal attitude minus sensor",
//! and the nominal attitude is read when the measurement is applied, not
//! when it is pushed: a late measurement applied during a re-propagation
//! sees the attitude of its own time.

use nav_runtime::ekf::{FilterError, UpdateReport};
use nav_runtime::nalgebra::{SVector, Vector3};
use nav_runtime::scheduler::{FnMeasurement, Measurement, MeasurementOutcome};

use super::heading::{horizontal_field, magnetic_heading};
use super::model::{AhrsGravity, AhrsHeading};
use super::nominal::AhrsFilter;
use crate::ulog::replay::wrap;

/// Smallest sigma of the gravity measurement (the vehicle's unmodelled
/// horizontal accelerations, which averaging does not remove), m/s^2.
pub const GRAVITY_SIGMA_FLOOR: f64 = 0.2;

fn outcome<const M: usize>(
    report: Result<UpdateReport<M>, FilterError>,
) -> Result<MeasurementOutcome, FilterError> {
    report.map(|r| MeasurementOutcome::from(&r))
}

/// The mean specific force `force` (body, m/s^2) of `samples` IMU samples
/// read as gravity `[0, 0, -gravity]` (eq. A2); the per-sample noise
/// `accel_sigma` averages down to [`GRAVITY_SIGMA_FLOOR`] at most.
pub fn gravity_measurement(
    force: Vector3<f64>,
    samples: usize,
    gravity: f64,
    accel_sigma: f64,
) -> Box<dyn Measurement<AhrsFilter>> {
    let variance = (accel_sigma * accel_sigma / samples.max(1) as f64)
        .max(GRAVITY_SIGMA_FLOOR * GRAVITY_SIGMA_FLOOR);
    let f_nav = Vector3::new(0.0, 0.0, -gravity);
    Box::new(FnMeasurement::new(
        &[force.x, force.y, force.z, variance],
        move |f: &mut AhrsFilter| {
            let z = f.nominal().c_bn.transpose() * f_nav - force;
            outcome(f.update_sequential::<AhrsGravity, 3>(&z, &SVector::repeat(variance), &()))
        },
    ))
}

/// A magnetometer sample `field` (body, gauss) read as a magnetic heading
/// (eq. A3): levelled with the nominal roll and pitch, plus `declination`
/// (rad); sigma `atan(field_sigma / |m_horizontal|)`. A sample without a
/// horizontal field at that attitude gives a non-finite residual, which the
/// filter refuses.
pub fn heading_measurement(
    field: [f64; 3],
    field_sigma: f64,
    declination: f64,
) -> Box<dyn Measurement<AhrsFilter>> {
    Box::new(FnMeasurement::new(
        &[field[0], field[1], field[2]],
        move |f: &mut AhrsFilter| {
            let [roll, pitch, yaw] = f.nominal().euler();
            let psi = magnetic_heading(field, roll, pitch, declination).unwrap_or(f64::NAN);
            let s = (field_sigma / horizontal_field(field, roll, pitch)).atan();
            let z = SVector::<f64, 1>::new(wrap(yaw - psi));
            outcome(f.update_sequential::<AhrsHeading, 1>(&z, &SVector::<f64, 1>::new(s * s), &()))
        },
    ))
}
