//! SDINS-25: INS error-state filter aided by DVL, compass, depth meter and USBL
//! (docs/models/sdins25.md; Lee, Lee, Seong). Indirect feedback: the states are the
//! errors of the strapdown solution (error = INS value minus true value); after
//! every update they are fed back and reset to zero.
//!
//! The position, velocity and attitude rows are not typed in: the declaration
//! writes the true quantities as functions of nominal value and error
//! (`L = L^ - dL`, `V = V^ - dV`, `C = (I + [phi x]) C^`, `f = f~ - nabla`) and the
//! generator differentiates `nominal rate - true rate` at zero error, which yields
//! eq. 16's F11..F35 (checked against the paper's blocks in tests). Unlike the
//! paper, gravity's height derivative (about `-2g/R`) is included in F.

nav_runtime::model! {
    /// 25-state indirect-feedback INS error model, docs/models/sdins25.md, eqs. 4-17.
    pub model Sdins25 {
        states {
            /// `[dL, dl, dh]`: latitude, longitude errors (rad) and height error (m).
            position_error: 3,
            /// `[dV_N, dV_E, dV_D]`, m/s.
            velocity_error: 3,
            /// `phi = [phi_N, phi_E, phi_D]` with `C^_b^n = (I - [phi x]) C_b^n`, rad.
            attitude_error: 3,
            /// Accelerometer biases `nabla` (body), m/s^2.
            accel_bias: 3,
            /// Gyro biases `eps` (body), rad/s.
            gyro_bias: 3,
            /// USBL horizontal position bias (N, E), m.
            usbl_bias: 2,
            /// Depth-meter bias, m.
            depth_bias,
            /// DVL body-frame velocity error `a_v`, m/s.
            dvl_bias: 3,
            /// Magnetic compass bias, rad.
            compass_bias,
            /// USBL array misalignment (small angles), rad.
            usbl_misalignment: 3,
        }
        inputs {
            /// Nominal (INS) latitude `L^`, rad.
            latitude,
            /// Nominal (INS) height `h^` (positive up), m.
            height,
            /// Nominal (INS) NED velocity `V^n`, m/s.
            velocity: 3,
            /// Nominal (INS) attitude `C^_b^n`.
            c_bn: 3x3,
            /// Measured specific force `f~^b` (after the current bias correction), m/s^2.
            specific_force: 3,
        }
        noise {
            /// Accelerometer white noise, (m/s^2)^2/Hz.
            accel_noise: 3,
            /// Gyro white noise, (rad/s)^2/Hz.
            gyro_noise: 3,
        }
        continuous {
            // WGS-84 (docs/models/conventions.md, item 4), exact radii.
            let a = 6378137.0;
            let e2 = 0.0066943799901413165;
            let omega = 7.292115e-5;
            // True quantities from nominal value and error.
            let lat = latitude - position_error[0];
            let hgt = height - position_error[2];
            let vel = velocity - velocity_error;
            let c_true = c_bn + skew(attitude_error) * c_bn;
            let f_true = specific_force - accel_bias - accel_noise;

            // Nominal rates (eqs. 1-3, 5), evaluated at the INS solution.
            let s0 = sin(latitude);
            let k0 = 1.0 - e2 * s0 * s0;
            let rm0 = a * (1.0 - e2) / (k0 * sqrt(k0));
            let rn0 = a / sqrt(k0);
            let wie0 = [omega * cos(latitude), 0.0, -omega * s0];
            let wen0 = [velocity[1] / (rn0 + height), -velocity[0] / (rm0 + height),
                        -velocity[1] * tan(latitude) / (rn0 + height)];
            let g0 = 9.7803253359 * (1.0 + 0.00193185265241 * s0 * s0) / sqrt(k0)
                     * (1.0 - 2.0 * height / a * (1.0 + 0.00335281066475 + 0.00344978600308
                        - 2.0 * 0.00335281066475 * s0 * s0) + 3.0 * height * height / (a * a));

            // The same rates at the true state.
            let s1 = sin(lat);
            let k1 = 1.0 - e2 * s1 * s1;
            let rm1 = a * (1.0 - e2) / (k1 * sqrt(k1));
            let rn1 = a / sqrt(k1);
            let wie1 = [omega * cos(lat), 0.0, -omega * s1];
            let wen1 = [vel[1] / (rn1 + hgt), -vel[0] / (rm1 + hgt), -vel[1] * tan(lat) / (rn1 + hgt)];
            let g1 = 9.7803253359 * (1.0 + 0.00193185265241 * s1 * s1) / sqrt(k1)
                     * (1.0 - 2.0 * hgt / a * (1.0 + 0.00335281066475 + 0.00344978600308
                        - 2.0 * 0.00335281066475 * s1 * s1) + 3.0 * hgt * hgt / (a * a));

            // eq. 1 (and its error, eq. 4)
            d/dt position_error = [
                velocity[0] / (rm0 + height) - vel[0] / (rm1 + hgt),
                velocity[1] / ((rn0 + height) * cos(latitude)) - vel[1] / ((rn1 + hgt) * cos(lat)),
                -velocity[2] + vel[2]
            ];
            // eq. 2 (and its error, eq. 5)
            d/dt velocity_error = (c_bn * specific_force - cross(2.0 * wie0 + wen0, velocity) + [0.0, 0.0, g0])
                                - (c_true * f_true - cross(2.0 * wie1 + wen1, vel) + [0.0, 0.0, g1]);
            // eq. 6: phidot = -w_in x phi - C eps + dw_in
            d/dt attitude_error = -cross(wie0 + wen0, attitude_error) - c_bn * (gyro_bias + gyro_noise)
                                + (wie0 + wen0) - (wie1 + wen1);
        }
        /// Depth meter, height convention: `h^ - h_meas = dh - b_depth` (eq. 10).
        sensor Depth: 1 {
            h = [position_error[2] - depth_bias];
        }
        /// DVL, body 3-axis: `V^n - C^_b^n v_meas = dV - V^n x phi - C_b^n b_dvl` (eq. 11),
        /// derived from the true velocity and attitude.
        sensor Dvl: 3 {
            let c_true = c_bn + skew(attitude_error) * c_bn;
            h = velocity - c_bn * (transpose(c_true) * (velocity - velocity_error) + dvl_bias);
        }
        /// Magnetic compass, the paper's small-angle form `-phi_D - b_psi` (eq. 12).
        sensor CompassSmallAngle: 1 {
            angles = [0];
            h = [-attitude_error[2] - compass_bias];
        }
        /// Magnetic compass, exact yaw of the perturbed attitude: `psi(C^) - psi(C) - b_psi`.
        /// Equals the small-angle form when level; differs when the vehicle pitches.
        sensor Compass: 1 {
            angles = [0];
            let c_true = c_bn + skew(attitude_error) * c_bn;
            h = [atan2(c_bn[(1, 0)], c_bn[(0, 0)]) - atan2(c_true[(1, 0)], c_true[(0, 0)]) - compass_bias];
        }
        /// USBL horizontal fix, INS minus fix in metres N/E (eq. 17):
        /// `[(R_m+h) dL, (R_n+h) cos L dl] - b_usbl - ([theta x] r)_NE`.
        sensor Usbl: 2 {
            inputs {
                /// Vector from the USBL transducer to the vehicle, NED, m.
                relative_position: 3,
            }
            let rm0 = meridian_radius(latitude);
            let rn0 = transverse_radius(latitude);
            let tilt = cross(usbl_misalignment, relative_position);
            h = [
                (rm0 + height) * position_error[0] - usbl_bias[0] - tilt[0],
                (rn0 + height) * cos(latitude) * position_error[1] - usbl_bias[1] - tilt[1]
            ];
        }
    }
}
