//! The standard model blocks vehicles are assembled from: an INS error-state
//! core and one block per sensor, usable from any crate:
//!
//! ```text
//! use nav_blocks::{Compass, Depth, Dvl, InsCore};
//! nav_runtime::model! {
//!     pub model MyAuv = InsCore + Depth + Dvl + Compass;
//! }
//! ```
//!
//! Each block declares its own states and measurements and lists in
//! `needs { .. }` what it reads from other blocks (the core's nominal
//! navigation solution and error states). Blocks are `#[macro_export]`
//! macros (a composition expands them one after another), so the crate that
//! uses them names `nav_runtime` as a dependency.
//!
//! Conventions are those of SDINS-25 (docs/models/sdins25.md): indirect
//! feedback, errors are INS value minus true value, every measurement is "INS
//! prediction minus sensor" and the true quantities are written from the
//! nominal ones and the errors (`C = (I + [phi x]) C^`), so the generator
//! derives each `H` from the measurement equation itself. Every block's
//! generated code is compiled and tested in `models` (`BlockCatalog`), from
//! another crate, as users use them.
#![no_std]
#![warn(missing_docs)]

nav_runtime::model! {
    /// The 15-state INS error-state core: position, velocity and attitude errors,
    /// accelerometer and gyro biases (docs/models/sdins25.md, eqs. 4-9). Its inputs are
    /// the nominal navigation solution, visible to every block through `needs`.
    #[macro_export]
    pub block InsCore {
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
    }

    /// USBL horizontal fix with a position bias and an array misalignment (eq. 17).
    #[macro_export]
    pub block Usbl {
        states {
            /// USBL horizontal position bias (N, E), m.
            usbl_bias: 2,
            /// USBL array misalignment (small angles), rad.
            usbl_misalignment: 3,
        }
        needs { position_error: 3, latitude, height }
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

    /// USBL fix of a transponder whose given lever arm may be off: `Usbl`
    /// plus the error of the given transponder position as states
    /// (docs/calibration.md). An alternative to `Usbl` (both declare
    /// `usbl_bias` and `usbl_misalignment`, so a vehicle takes one). The
    /// lever-arm error is a correction to the value the log gives (prior
    /// zero); the navigator keeps it in the filter as a total state.
    #[macro_export]
    pub block UsblCalibrated {
        states {
            /// USBL horizontal position bias (N, E), m.
            usbl_bias: 2,
            /// USBL array misalignment (small angles), rad.
            usbl_misalignment: 3,
            /// Error of the given transponder lever arm: true minus given,
            /// body axes, m.
            usbl_lever_arm: 3,
            /// Lag of the fixes' clock behind the times the log gives them,
            /// s: a fix stamped `t` is where the transponder was at `t - dt`.
            usbl_time_offset,
        }
        needs { position_error: 3, latitude, height, c_bn: 3x3, velocity: 3 }
        /// `Usbl`'s residual (eq. 17) less the share of the lever-arm error,
        /// `(C_b^n dr)_NE`: the transponder is `dr` further than the given
        /// arm says, so the fix is too; plus `dt V_NE`, the way the vehicle
        /// went since the fix was taken (first order in the lag).
        sensor UsblCalibrated: 2 {
            inputs {
                /// Vector from the USBL transducer to the vehicle, NED, m.
                relative_position: 3,
            }
            let rm0 = meridian_radius(latitude);
            let rn0 = transverse_radius(latitude);
            let tilt = cross(usbl_misalignment, relative_position);
            let arm = c_bn * usbl_lever_arm;
            h = [
                (rm0 + height) * position_error[0] - usbl_bias[0] - tilt[0] - arm[0] + usbl_time_offset * velocity[0],
                (rn0 + height) * cos(latitude) * position_error[1] - usbl_bias[1] - tilt[1] - arm[1] + usbl_time_offset * velocity[1]
            ];
        }
    }

    /// Depth meter with a bias, at the IMU.
    #[macro_export]
    pub block Depth {
        states {
            /// Depth-meter bias, m.
            depth_bias,
        }
        needs { position_error: 3 }
        /// Depth meter, height convention: `h^ - h_meas = dh - b_depth` (eq. 10).
        sensor Depth: 1 {
            h = [position_error[2] - depth_bias];
        }
    }

    /// DVL with a body-frame velocity bias (eq. 11).
    #[macro_export]
    pub block Dvl {
        states {
            /// DVL body-frame velocity error `a_v`, m/s.
            dvl_bias: 3,
        }
        needs { velocity: 3, c_bn: 3x3, velocity_error: 3, attitude_error: 3 }
        /// DVL, body 3-axis: `V^n - C^_b^n v_meas = dV - V^n x phi - C_b^n b_dvl` (eq. 11),
        /// derived from the true velocity and attitude.
        sensor Dvl: 3 {
            let c_true = c_bn + skew(attitude_error) * c_bn;
            h = velocity - c_bn * (transpose(c_true) * (velocity - velocity_error) + dvl_bias);
        }
    }

    /// DVL with bias, scale factor, mounting misalignment and a lever arm
    /// whose given value may be off: the mounting calibration states of
    /// docs/calibration.md. An alternative to `Dvl` (both declare
    /// `dvl_bias`, so a vehicle takes one). The scale, misalignment and
    /// lever-arm states are corrections to the values the log gives (prior
    /// zero); the navigator keeps them in the filter as total states.
    #[macro_export]
    pub block DvlCalibrated {
        states {
            /// DVL body-frame velocity bias, m/s.
            dvl_bias: 3,
            /// DVL scale-factor error (dimensionless): the DVL reads `1 + s` times the speed.
            dvl_scale,
            /// DVL mounting misalignment: small rotation of the DVL axes from
            /// the body axes (after the log's given mounting), rad.
            dvl_misalignment: 3,
            /// Error of the given DVL lever arm: true minus given, body axes, m.
            dvl_lever_arm: 3,
            /// Lag of the DVL's clock behind the time the log gives its rows,
            /// s: a row stamped `t` measured the velocity of `t - dt`.
            dvl_time_offset,
        }
        needs { velocity: 3, c_bn: 3x3, velocity_error: 3, attitude_error: 3 }
        /// `z = V^ - C^_b^n v_meas` with
        /// `v_meas = (1 + s)(I - [m x])(C^T V + w x (r + dr) - dt a_b) + b`,
        /// the velocity `dt` earlier to first order in the lag.
        sensor DvlCalibrated: 3 {
            inputs {
                /// Given DVL position in body axes relative to the IMU, m.
                lever_arm: 3,
                /// Body angular rate (bias-corrected gyro), rad/s.
                body_rate: 3,
                /// Rate of change of the body-axes velocity `C^T V`, m/s^2:
                /// `f + C^T g - w x C^T V`.
                body_acceleration: 3,
            }
            let c_true = c_bn + skew(attitude_error) * c_bn;
            let v_body = transpose(c_true) * (velocity - velocity_error) + cross(body_rate, lever_arm + dvl_lever_arm) - dvl_time_offset * body_acceleration;
            h = velocity - c_bn * ((1.0 + dvl_scale) * (v_body - cross(dvl_misalignment, v_body)) + dvl_bias);
        }
    }

    /// Magnetic compass with a bias: the exact yaw and the paper's small-angle form.
    #[macro_export]
    pub block Compass {
        states {
            /// Magnetic compass bias, rad.
            compass_bias,
        }
        needs { attitude_error: 3, c_bn: 3x3 }
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
    }

    /// A GNSS fix at the surface (antenna on a mast): no states of its own.
    #[macro_export]
    pub block GnssFix {
        needs { position_error: 3, attitude_error: 3, latitude, height, c_bn: 3x3 }
        /// INS antenna position minus fix, metres N/E and height:
        /// `[(R_m+h) dL, (R_n+h) cos L dl, dh] + (C^ - C) r` (its down component with
        /// the sign of height).
        sensor GnssFix: 3 {
            inputs {
                /// Antenna position in body axes relative to the IMU, m.
                antenna_lever_arm: 3,
            }
            let rm0 = meridian_radius(latitude);
            let rn0 = transverse_radius(latitude);
            let c_true = c_bn + skew(attitude_error) * c_bn;
            let arm_error = (c_bn - c_true) * antenna_lever_arm;
            h = [
                (rm0 + height) * position_error[0] + arm_error[0],
                (rn0 + height) * cos(latitude) * position_error[1] + arm_error[1],
                position_error[2] - arm_error[2]
            ];
        }
    }

    /// A GNSS fix of an antenna whose given lever arm may be off: `GnssFix`
    /// plus the error of the given antenna position as states
    /// (docs/calibration.md). An alternative to `GnssFix`; the navigator
    /// keeps the states in the filter as total states (prior zero: the given
    /// arm).
    #[macro_export]
    pub block GnssFixCalibrated {
        states {
            /// Error of the given antenna lever arm: true minus given, body
            /// axes, m.
            gnss_lever_arm: 3,
            /// Lag of the fixes' clock behind the times the log gives them,
            /// s: a fix stamped `t` is where the antenna was at `t - dt`.
            gnss_time_offset,
        }
        needs { position_error: 3, attitude_error: 3, latitude, height, c_bn: 3x3, velocity: 3 }
        /// `GnssFix`'s residual less the share of the lever-arm error: the
        /// antenna is `C_b^n dr` further than the given arm says (north,
        /// east; its down component with the sign of height); plus
        /// `dt V`, the way the vehicle went since the fix was taken (first
        /// order in the lag).
        sensor GnssFixCalibrated: 3 {
            inputs {
                /// Antenna position in body axes relative to the IMU, m.
                antenna_lever_arm: 3,
            }
            let rm0 = meridian_radius(latitude);
            let rn0 = transverse_radius(latitude);
            let c_true = c_bn + skew(attitude_error) * c_bn;
            let arm_error = (c_bn - c_true) * antenna_lever_arm;
            let shift = c_bn * gnss_lever_arm - gnss_time_offset * velocity;
            h = [
                (rm0 + height) * position_error[0] + arm_error[0] - shift[0],
                (rn0 + height) * cos(latitude) * position_error[1] + arm_error[1] - shift[1],
                position_error[2] - arm_error[2] + shift[2]
            ];
        }
    }

    /// Speed through water from propeller RPM (`map_speed = k rpm`) with a
    /// scale-factor error, and the horizontal water current as a random walk.
    #[macro_export]
    pub block RpmSpeed {
        states {
            /// Relative error of the RPM speed map (dimensionless).
            rpm_scale,
            /// Water current, N/E, m/s.
            current: 2,
        }
        needs { velocity: 3, c_bn: 3x3, velocity_error: 3, attitude_error: 3 }
        noise {
            /// Water current random walk, (m/s)^2/s.
            current_noise: 2,
        }
        continuous {
            d/dt current = current_noise;
        }
        /// INS forward speed through water minus the map speed:
        /// `z = (C^T V^)_x - map_speed`, `map_speed = (1 + s) (C^T (V - [c_N, c_E, 0]))_x`.
        sensor RpmSpeed: 1 {
            let c_true = c_bn + skew(attitude_error) * c_bn;
            let through_water = transpose(c_true) * (velocity - velocity_error - [current[0], current[1], 0.0]);
            let nominal = transpose(c_bn) * velocity;
            h = [nominal[0] - (1.0 + rpm_scale) * through_water[0]];
        }
    }

    /// Barometric altitude with a drifting bias (docs/ulog.md, eq. G1).
    #[macro_export]
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

    /// Heading from a tilt-compensated magnetometer, no bias state (docs/ulog.md, eq. G2).
    #[macro_export]
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
