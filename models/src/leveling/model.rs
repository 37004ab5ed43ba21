//! LEVELING-6: roll/pitch alignment EKF (docs/results/leveling6.md; Hong, Park, Han,
//! Lee 2000). Total-state, continuous-time; states `x = [V_x, V_y, V_z, a1, a2, a3]`
//! with `a = C_n^b [0, 0, 1]` (eq. 5), so `theta = asin(-a1)`, `phi = atan2(a2, a3)`
//! (eq. 28).

nav_runtime::model! {
    /// Roll/pitch leveling filter, eqs. 15, 17 and 26 of the leveling paper.
    pub model Leveling6 {
        states {
            /// Body-frame velocity over ground `V^b`, m/s.
            velocity: 3,
            /// Gravity direction in body axes `a = [-sin theta, sin phi cos theta, cos phi cos theta]`.
            gravity_direction: 3,
        }
        inputs {
            /// Gyro output `w_ib^b`, rad/s.
            gyro: 3,
            /// Accelerometer output `f^b`, m/s^2.
            specific_force: 3,
            /// Earth rate in body axes from the current estimate `W^b` (eq. 16), rad/s.
            earth_rate_body: 3,
        }
        parameters {
            /// Local gravity magnitude `g`, m/s^2.
            gravity,
        }
        noise {
            /// Accelerometer white noise, (m/s^2)^2/Hz.
            accel_noise: 3,
            /// Gyro white noise, (rad/s)^2/Hz.
            gyro_noise: 3,
        }
        continuous {
            // eq. 15: w* = w_ib^b + W^b
            let w_star = gyro + earth_rate_body;
            // eq. 17: w = w_ib^b - W^b
            let w = gyro - earth_rate_body + gyro_noise;
            d/dt velocity = -cross(w_star, velocity) + gravity * gravity_direction + specific_force + accel_noise;
            // eq. 7
            d/dt gravity_direction = -cross(w, gravity_direction);
        }
        /// Moving: forward speed log and the unit-norm constraint (eqs. 29-30).
        sensor Moving: 2 {
            h = [velocity[0], norm_squared(gravity_direction)];
        }
        /// Stationary: zero velocity on three axes and the unit norm (eqs. 32-33).
        sensor Stationary: 4 {
            h = [velocity[0], velocity[1], velocity[2], norm_squared(gravity_direction)];
        }
    }
}

nav_runtime::model! {
    /// LEVELING-6 with the horizontal accelerometer bias as states
    /// (docs/results/leveling6.md, "Bias states"): the tilt an uncompensated
    /// bias causes is fixed to the body, while an error of `a` is fixed to the
    /// Earth and turns with the heading in body axes, so heading changes
    /// separate the two. `b_z` is left out: along gravity it only scales `|a|`.
    pub model Leveling8 {
        states {
            /// Body-frame velocity over ground `V^b`, m/s.
            velocity: 3,
            /// Gravity direction in body axes `a = [-sin theta, sin phi cos theta, cos phi cos theta]`.
            gravity_direction: 3,
            /// Accelerometer bias on the body x and y axes, m/s^2.
            accel_bias: 2,
        }
        inputs {
            /// Gyro output `w_ib^b`, rad/s.
            gyro: 3,
            /// Accelerometer output `f^b`, m/s^2.
            specific_force: 3,
            /// Earth rate in body axes from the current estimate `W^b` (eq. 16), rad/s.
            earth_rate_body: 3,
        }
        parameters {
            /// Local gravity magnitude `g`, m/s^2.
            gravity,
        }
        noise {
            /// Accelerometer white noise, (m/s^2)^2/Hz.
            accel_noise: 3,
            /// Gyro white noise, (rad/s)^2/Hz.
            gyro_noise: 3,
            /// Accelerometer-bias random walk, (m/s^2)^2/s.
            bias_walk: 2,
        }
        continuous {
            let w_star = gyro + earth_rate_body;
            let w = gyro - earth_rate_body + gyro_noise;
            d/dt velocity = -cross(w_star, velocity) + gravity * gravity_direction + specific_force
                - [accel_bias[0], accel_bias[1], 0.0] + accel_noise;
            d/dt gravity_direction = -cross(w, gravity_direction);
            d/dt accel_bias = bias_walk;
        }
        /// Moving: forward speed log and the unit-norm constraint.
        sensor Moving: 2 {
            h = [velocity[0], norm_squared(gravity_direction)];
        }
        /// Stationary: zero velocity on three axes and the unit norm.
        sensor Stationary: 4 {
            h = [velocity[0], velocity[1], velocity[2], norm_squared(gravity_direction)];
        }
    }
}
