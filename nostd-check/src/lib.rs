//! A `no_std` library that declares a model with the generator and runs the EKF
//! core on it. `tests/tests/no_std.rs` builds this crate alone, so `nav-runtime`
//! is compiled without its `std` feature (libm for the scalar functions).
#![no_std]

use nav_runtime::ekf::{Ekf, FilterError};
use nav_runtime::nalgebra::{Matrix2, SMatrix, SVector, Vector2, Vector3, Vector6};

nav_runtime::model! {
    /// LEVELING-6, as in `models`.
    pub model Leveling {
        states { velocity: 3, a: 3 }
        inputs { gyro: 3, specific_force: 3, earth_rate_body: 3 }
        parameters { gravity }
        noise { accel_noise: 3, gyro_noise: 3 }
        continuous {
            let w_star = gyro + earth_rate_body;
            let w = gyro - earth_rate_body;
            d/dt velocity = -cross(w_star, velocity) + gravity * a + specific_force + accel_noise;
            d/dt a = -cross(w + gyro_noise, a);
        }
        sensor Moving: 2 {
            h = [velocity[0], norm_squared(a)];
        }
    }
}

/// The second round of the language without std: a model-level `let`, a
/// quaternion and an angle state (renormalized and wrapped by the filter),
/// rotations and non-smooth functions; declared in `f64` ([`Attitude`]) and
/// in `f32` ([`AttitudeSingle`]).
macro_rules! attitude {
    ($name:ident, $scalar:ident) => {
nav_runtime::model! {
    /// A quaternion attitude with an angle state (see the macro above).
    pub model $name {
        scalar $scalar;
        states { q: quaternion, heading: angle, attitude_error: 3 }
        inputs { gyro: 3 }
        parameters { gravity, limit }
        noise { gyro_noise: 3 }
        let c_bn = quat_to_dcm(quat_mul(q, rotvec_to_quat(attitude_error)));
        continuous {
            let w = gyro + gyro_noise;
            d/dt q = 0.5 * quat_mul(q, [0.0, w[0], w[1], w[2]]);
            d/dt heading = clamp(w[2], -limit, limit) + sign(w[0]) * min(abs(w[1]), max(w[0], 0.0));
        }
        sensor Accel: 3 {
            h = transpose(c_bn) * [0.0, 0.0, -gravity];
        }
        sensor Euler: 3 {
            angles = [0, 2];
            h = dcm_to_euler(c_bn);
        }
        // `heading` exercises the `angle` state and the non-smooth builtins;
        // no sensor reads it.
        allow_unused { heading }
    }
}
    };
}

attitude!(Attitude, f64);
attitude!(AttitudeSingle, f32);

/// One predict and one update of [`Attitude`]; returns the quaternion norm
/// after them (1 to rounding).
pub fn attitude_step() -> Result<f64, FilterError> {
    let x0 = SVector::<f64, 8>::from_column_slice(&[1.0, 0.0, 0.0, 0.0, 3.0, 0.0, 0.0, 0.0]);
    let mut ekf = Ekf::<Attitude, 8>::new(
        x0,
        SMatrix::<f64, 8, 8>::identity() * 1e-2,
        AttitudeParams {
            gravity: 9.8,
            limit: 1.0,
        },
        AttitudeNoise {
            gyro_noise: Vector3::repeat(1e-6),
        },
    )?;
    ekf.predict(
        0.1,
        &AttitudeInput {
            gyro: Vector3::new(0.1, 0.2, 0.3),
        },
    )?;
    ekf.update::<AttitudeAccel, 3>(
        &Vector3::new(0.1, 0.0, -9.8),
        &SMatrix::<f64, 3, 3>::identity(),
        &(),
    )?;
    Ok(ekf.state().fixed_rows::<4>(0).norm())
}

/// [`attitude_step`] in single precision, with a sequential update as
/// well; returns the quaternion norm (1 to `f32` rounding).
pub fn attitude_step_single() -> Result<f32, FilterError> {
    let x0 = SVector::<f32, 8>::from_column_slice(&[1.0, 0.0, 0.0, 0.0, 3.0, 0.0, 0.0, 0.0]);
    let mut ekf = Ekf::<AttitudeSingle, 8, f32>::new(
        x0,
        SMatrix::<f32, 8, 8>::identity() * 1e-2,
        AttitudeSingleParams {
            gravity: 9.8,
            limit: 1.0,
        },
        AttitudeSingleNoise {
            gyro_noise: Vector3::repeat(1e-6),
        },
    )?;
    ekf.predict(
        0.1,
        &AttitudeSingleInput {
            gyro: Vector3::new(0.1, 0.2, 0.3),
        },
    )?;
    ekf.update::<AttitudeSingleAccel, 3>(
        &Vector3::new(0.1, 0.0, -9.8),
        &SMatrix::<f32, 3, 3>::identity(),
        &(),
    )?;
    ekf.update_sequential::<AttitudeSingleEuler, 3>(
        &Vector3::new(0.0, 0.0, 0.05),
        &Vector3::repeat(1e-2),
        &(),
    )?;
    Ok(ekf.state().fixed_rows::<4>(0).norm())
}

/// One predict and one update at rest; returns the NIS.
pub fn step() -> Result<f64, FilterError> {
    let mut ekf = Ekf::<Leveling, 6>::new(
        Vector6::new(0.0, 0.0, 0.0, 0.0, 0.0, 1.0),
        SMatrix::<f64, 6, 6>::identity(),
        LevelingParams { gravity: 9.8 },
        LevelingNoise {
            accel_noise: Vector3::repeat(1e-4),
            gyro_noise: Vector3::repeat(1e-8),
        },
    )?;
    let input = LevelingInput {
        gyro: Vector3::zeros(),
        specific_force: Vector3::new(0.0, 0.0, -9.8),
        earth_rate_body: Vector3::zeros(),
    };
    ekf.predict(0.01, &input)?;
    let report =
        ekf.update::<LevelingMoving, 2>(&Vector2::new(0.0, 1.0), &Matrix2::identity(), &())?;
    Ok(report.nis)
}

#[cfg(test)]
mod tests {
    /// The steps run (here with the workspace's std build of the runtime;
    /// `tests/tests/no_std.rs` builds them without std) and keep the
    /// quaternion on the unit sphere in both precisions.
    #[test]
    fn steps_run_in_both_precisions() {
        let double = super::attitude_step().expect("f64 step");
        let single = super::attitude_step_single().expect("f32 step");
        assert!((double - 1.0).abs() < 1e-12, "{double}");
        assert!((single - 1.0).abs() < 1e-6, "{single}");
        assert!(super::step().expect("leveling step").is_finite());
    }
}
