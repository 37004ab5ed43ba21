//! A `no_std` library that declares a model with the generator and runs the EKF
//! core on it. `tests/tests/no_std.rs` builds this crate alone, so `nav-runtime`
//! is compiled without its `std` feature (libm for the scalar functions).
#![no_std]

use nav_runtime::ekf::{Ekf, FilterError};
use nav_runtime::nalgebra::{Matrix2, SMatrix, Vector2, Vector3, Vector6};

nav_runtime::model! {
    /// LEVELING-6 (docs/models/leveling6.md), as in `models`.
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
