//! The `ahrs` declaration: an error-state attitude filter in the conventions of
//! the INS core (`docs/ulog.md`, eqs. A1-A3). The nominal attitude `C^_b^n` is
//! integrated from the gyro outside the filter; the states are its error
//! `phi` (`C^ = (I - [phi x]) C`, as in the core) and the gyro bias. The
//! Earth rate (15 deg/h) is below what such a filter resolves and is left out.
//!
//! Every measurement is "prediction from the nominal attitude minus sensor",
//! and the declaration writes the true attitude from the nominal one and the
//! error (`C = (I + [phi x]) C^`), so the generator derives `H` itself.

nav_runtime::model! {
    /// Attitude error and gyro bias; accelerometer as a gravity sensor and a
    /// magnetic heading (eqs. A1-A3 of `docs/ulog.md`).
    pub model Ahrs {
        states {
            /// `phi = [phi_N, phi_E, phi_D]` with `C^_b^n = (I - [phi x]) C_b^n`, rad.
            attitude_error: 3,
            /// Gyro biases (body), rad/s.
            gyro_bias: 3,
        }
        inputs {
            /// Nominal attitude `C^_b^n`.
            c_bn: 3x3,
        }
        parameters {
            /// Local gravity magnitude `g`, m/s^2.
            gravity,
        }
        noise {
            /// Gyro white noise, (rad/s)^2/Hz.
            gyro_noise: 3,
            /// Gyro bias random walk, (rad/s^2)^2/Hz.
            gyro_bias_noise: 3,
        }
        continuous {
            // eq. A1: the core's attitude error without Earth and transport rate.
            d/dt attitude_error = -c_bn * (gyro_bias + gyro_noise);
            d/dt gyro_bias = gyro_bias_noise;
        }
        /// Accelerometer as a gravity sensor (eq. A2), valid when the vehicle
        /// does not accelerate: `C^T f_n - C_true^T f_n` with `f_n = [0, 0, -g]`, m/s^2.
        sensor Gravity: 3 {
            let c_true = c_bn + skew(attitude_error) * c_bn;
            let f_n = [0.0, 0.0, -gravity];
            h = transpose(c_bn) * f_n - transpose(c_true) * f_n;
        }
        /// Magnetic heading (eq. A3): `psi(C^) - psi(C)`, rad.
        sensor Heading: 1 {
            angles = [0];
            let c_true = c_bn + skew(attitude_error) * c_bn;
            h = [atan2(c_bn[(1, 0)], c_bn[(0, 0)]) - atan2(c_true[(1, 0)], c_true[(0, 0)])];
        }
    }
}
