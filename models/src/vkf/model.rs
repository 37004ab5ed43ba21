//! VKF (docs/models/vkf.md; velocity-filter paper, eqs. 6-18): the 3-state
//! velocity Kalman filter that learns the propeller-RPM-to-speed map from the
//! DVL, and the 9-state integrated navigation filter driven by the nav-frame
//! acceleration and aided by the switching box's 3-axis velocity.

nav_runtime::model! {
    /// Velocity Kalman filter, `X = [V, sf, b]` (paper eqs. 6-10): the forward
    /// speed is the RPM map `V_{k+1} = sf_k rpm_k + b_k`; the scale factor and the
    /// bias are random walks; the DVL forward speed measures `V`.
    /// Discrete, one step per RPM sample; noise intensities are per-step variances.
    pub model VelocityFilter {
        states {
            /// Forward (body x) speed over ground `V`, m/s.
            speed,
            /// RPM-to-speed scale factor `sf`, (m/s)/rpm.
            scale_factor,
            /// RPM-to-speed bias `b`, m/s.
            bias,
        }
        inputs {
            /// Measured propeller revolutions per minute.
            rpm,
        }
        noise {
            /// Departure of the speed from the map in one step (map curvature,
            /// RPM noise, sea state), m/s.
            speed_noise,
            /// Scale-factor random-walk step, (m/s)/rpm.
            scale_factor_walk,
            /// Bias random-walk step, m/s.
            bias_walk,
        }
        discrete {
            // eq. 7: V_{k+1} = sf_k rpm_k + b_k + w_V
            speed = scale_factor * rpm + bias + speed_noise;
            scale_factor = scale_factor + scale_factor_walk;
            bias = bias + bias_walk;
        }
        /// DVL forward speed, eq. 9: `z = V + v` (the DVL velocity rotated to the
        /// body forward axis with the Euler angles, eq. 5).
        sensor Dvl: 1 {
            h = speed;
        }
    }

    /// 9-state integrated navigation filter (paper eqs. 13-18): local-level NED
    /// position and velocity relative to the start point and the accelerometer
    /// bias. The input is the nav-frame acceleration after the coordinate
    /// transform, Coriolis and gravity compensation,
    /// `a^n = C_b^n f^b - (2 w_ie^n + w_en^n) x v^n + g^n`; the bias is carried in
    /// body axes and rotated with `C_b^n`, so a turn does not invalidate it (it
    /// also absorbs the slowly growing tilt error, which this filter does not
    /// estimate).
    pub model Nav9 {
        states {
            /// Position north, east, down of the start point, m.
            position: 3,
            /// NED velocity over ground, m/s.
            velocity: 3,
            /// Accelerometer bias in body axes, m/s^2.
            accel_bias: 3,
        }
        inputs {
            /// Compensated nav-frame acceleration `a^n`, m/s^2.
            accel_n: 3,
            /// Attitude `C_b^n` of the strapdown attitude computer.
            c_bn: 3x3,
        }
        noise {
            /// Acceleration white noise (accelerometer noise, unmodelled tilt), (m/s^2)^2/Hz.
            accel_noise: 3,
            /// Bias random walk, (m/s^2)^2/s.
            bias_walk: 3,
        }
        continuous {
            d/dt position = velocity;
            d/dt velocity = accel_n - c_bn * accel_bias + accel_noise;
            d/dt accel_bias = bias_walk;
        }
        /// The DVL's NED velocity (valid below the DVL's range), eq. 12 upper branch.
        sensor Dvl: 3 {
            h = velocity;
        }
        /// The RPM-derived NED velocity `C_b^n [sf rpm + b, 0, 0]`, eqs. 11-12.
        sensor Rpm: 3 {
            h = velocity;
        }
        // Both sensors measure velocity: the position is dead-reckoned, which
        // the generator's structural observability check requires saying.
        allow_unused { position }
    }
}

nav_runtime::model! {
    /// The integrated filter with the RPM speed map inside (docs/results/vkf.md,
    /// "Speed-map states"): [`Nav9`]'s position, velocity and accelerometer bias
    /// plus the map's correlated errors, so that the covariance keeps what an
    /// error of the RPM-derived speed does to the position during an outage and
    /// the returning DVL can take it back; and the DVL's own scale error and
    /// bias, so that what they integrate to stays in the covariance. The map is
    /// `V_rpm = (1 + speed_scale) sf0 rpm + speed_offset`, and the forward
    /// through-water speed departs from it by a first-order Gauss-Markov
    /// `speed_disturbance` (sea state, loading) with correlation time `tau`.
    pub model NavSpeedMap {
        states {
            /// Position north, east, down of the start point, m.
            position: 3,
            /// NED velocity over ground, m/s.
            velocity: 3,
            /// Accelerometer bias in body axes, m/s^2.
            accel_bias: 3,
            /// Relative error of the design slope `sf0` of the RPM map (dimensionless).
            speed_scale,
            /// Offset of the RPM map, m/s.
            speed_offset,
            /// Forward speed not explained by the map, m/s (Gauss-Markov).
            speed_disturbance,
            /// The DVL's forward scale-factor error (dimensionless, constant
            /// over a run; a consider state, see `CoupledNav`).
            dvl_scale,
            /// The DVL's bias per body axis, m/s (constant over a run).
            dvl_bias: 3,
        }
        inputs {
            /// Compensated nav-frame acceleration `a^n`, m/s^2.
            accel_n: 3,
            /// Attitude `C_b^n` of the strapdown attitude computer.
            c_bn: 3x3,
        }
        parameters {
            /// Design slope of the RPM map `sf0`, (m/s)/rpm.
            design_slope,
            /// Correlation time of the speed disturbance, s.
            tau,
        }
        noise {
            /// Acceleration white noise, (m/s^2)^2/Hz.
            accel_noise: 3,
            /// Bias random walk, (m/s^2)^2/s.
            bias_walk: 3,
            /// Scale random walk, 1/s.
            scale_walk,
            /// Offset random walk, (m/s)^2/s.
            offset_walk,
            /// Drive of the speed disturbance, (m/s)^2/s (`2 sigma^2 / tau`).
            disturbance_drive,
        }
        continuous {
            d/dt position = velocity;
            d/dt velocity = accel_n - c_bn * accel_bias + accel_noise;
            d/dt accel_bias = bias_walk;
            d/dt speed_scale = scale_walk;
            d/dt speed_offset = offset_walk;
            d/dt speed_disturbance = -speed_disturbance / tau + disturbance_drive;
        }
        /// The DVL's velocity rotated to NED (in range): the body velocity
        /// with the DVL's forward scale error and bias,
        /// `C (diag(1 + s, 1, 1) C^T v + b)` (the lateral and vertical body
        /// velocities are about zero, so their scale errors do nothing).
        /// Without them its error would be white to the filter, which then
        /// averages it away and becomes confident to centimetres while the
        /// constant part integrates to metres (docs/results/vkf.md,
        /// "Consistency").
        sensor Dvl: 3 {
            let v_b = transpose(c_bn) * velocity;
            let measured = [
                (1.0 + dvl_scale) * v_b[0] + dvl_bias[0],
                v_b[1] + dvl_bias[1],
                v_b[2] + dvl_bias[2]
            ];
            h = c_bn * measured;
        }
        /// The RPM as a velocity constraint in body axes, `z = [0, 0, 0]`: the
        /// forward body velocity minus the map's speed and the disturbance, and the
        /// lateral and vertical body velocity (no sideslip, no heave).
        sensor Rpm: 3 {
            inputs {
                /// Measured propeller revolutions per minute.
                rpm,
            }
            let v_b = transpose(c_bn) * velocity;
            h = [
                v_b[0] - (1.0 + speed_scale) * design_slope * rpm - speed_offset - speed_disturbance,
                v_b[1],
                v_b[2]
            ];
        }
        // Both sensors measure velocity: the position is dead-reckoned, which
        // the generator's structural observability check requires saying.
        allow_unused { position }
    }
}
