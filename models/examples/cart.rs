//! Declare a model with `nav_runtime::model!` and run its EKF: a cart with a
//! measured acceleration and a position fix (the model of
//! `docs/guide/declaring-a-model.md`).
//!
//! `cargo run --release -p models --example cart`

use nav_runtime::ekf::{Ekf, FilterError};
use nav_runtime::nalgebra::{Matrix1, Matrix2, Vector1, Vector2};

nav_runtime::model! {
    /// Position and velocity driven by a measured acceleration.
    pub model Cart {
        states {
            /// Position, m.
            position,
            /// Velocity, m/s.
            velocity,
        }
        inputs {
            /// Measured acceleration, m/s^2.
            acceleration,
        }
        noise {
            /// Accelerometer white noise, (m/s^2)^2/Hz.
            accel_noise,
        }
        continuous {
            d/dt position = velocity;
            d/dt velocity = acceleration + accel_noise;
        }
        /// A position fix, m.
        sensor Fix: 1 {
            h = [position];
        }
    }
}

fn main() -> Result<(), FilterError> {
    // The truth: starts at 0 m with 1 m/s and accelerates at 0.2 m/s^2 for 10 s.
    // The filter starts with a wrong velocity (0.5 m/s) and a broad covariance.
    let dt = 0.01;
    let acceleration = 0.2;
    let (mut position, mut velocity) = (0.0_f64, 1.0_f64);
    let mut filter = Ekf::<Cart, 2>::new(
        Vector2::new(0.0, 0.5),
        Matrix2::from_diagonal(&Vector2::new(1.0, 1.0)),
        CartParams::default(),
        CartNoise { accel_noise: 0.01 },
    )?;
    // A fixed sequence of fix errors (m), so the run is reproducible without a
    // random number generator.
    let fix_errors = [
        0.05, -0.08, 0.02, 0.11, -0.04, -0.09, 0.07, 0.0, -0.03, 0.06,
    ];
    println!("    t   position  estimate  sigma    velocity  estimate  sigma    NIS");
    for step in 1..=1000 {
        position += velocity * dt + 0.5 * acceleration * dt * dt;
        velocity += acceleration * dt;
        filter.predict(dt, &CartInput { acceleration })?;
        if step % 100 == 0 {
            let k = step / 100 - 1;
            let z = Vector1::new(position + fix_errors[k]);
            let report = filter.update::<CartFix, 1>(&z, &Matrix1::new(0.1 * 0.1), &())?;
            let x = filter.state();
            let p = filter.covariance();
            println!(
                "{:5.1}  {:8.3}  {:8.3}  {:6.3}  {:8.3}  {:8.3}  {:6.3}  {:5.2}{}",
                step as f64 * dt,
                position,
                x[0],
                p[(0, 0)].sqrt(),
                velocity,
                x[1],
                p[(1, 1)].sqrt(),
                report.nis,
                if report.accepted { "" } else { "  gated" }
            );
        }
    }
    println!(
        "generated covariance propagation: {} ops (Jacobian {} ops)",
        Cart::OPS_PROPAGATE_COVARIANCE,
        Cart::OPS_JACOBIAN
    );
    Ok(())
}
