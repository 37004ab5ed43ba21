//! The barometer and the magnetic heading as blocks for the INS core
//! (`docs/ulog.md`, eqs. G1-G2).

nav_runtime::model! {
    /// Barometric altitude with a drifting bias (eq. G1).
    pub block Barometer {
        states {
            /// Barometer bias: barometric altitude minus true height, m.
            baro_bias,
        }
        needs { position_error: 3 }
        noise {
            /// Bias random walk, m^2/s.
            baro_bias_noise,
        }
        continuous {
            d/dt baro_bias = baro_bias_noise;
        }
        /// INS height minus barometric altitude: `h^ - h_baro = dh - b_baro`, m.
        sensor Barometer: 1 {
            h = [position_error[2] - baro_bias];
        }
    }

    /// Heading from a tilt-compensated magnetometer, no bias state (eq. G2).
    pub block MagneticHeading {
        needs { attitude_error: 3, c_bn: 3x3 }
        /// `psi(C^) - psi(C)`, rad.
        sensor MagneticHeading: 1 {
            angles = [0];
            let c_true = c_bn + skew(attitude_error) * c_bn;
            h = [atan2(c_bn[(1, 0)], c_bn[(0, 0)]) - atan2(c_true[(1, 0)], c_true[(0, 0)])];
        }
    }
}
